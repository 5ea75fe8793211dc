//! Pass `raster_sw`: the compute rasterizer (shaders_glsl/raster_sw.comp.glsl).
//!
//! One workgroup per cluster of the SW list (`CullCounters::sw_dispatch`, grid-stride over
//! `sw_count`; small clusters two to a workgroup, the smallest, at the HW list's end, four),
//! [`RASTER_SW_WORKGROUP_SIZE`](crate::shared::RASTER_SW_WORKGROUP_SIZE) threads: the
//! cluster's vertices are decoded, made camera-relative, projected and snapped to
//! [`SUBPIXEL_BITS`](crate::shared::SUBPIXEL_BITS) fixed point in shared memory, then one thread per
//! triangle tests pixel centres with exact integer edge functions and the top-left rule of
//! [`crate::reference::raster`] (both windings; zero-area triangles skipped), interpolates depth
//! from the snapped positions and does `atomicMax` into the visibility buffer. Small triangles walk
//! their bounding box, larger ones solve each row's covered span from the edge functions. Triangles
//! with a vertex behind the near plane (or beyond a 2^20-pixel guard band) are skipped: the cull
//! sends such clusters to `raster_hw`. With
//! [`VIEW_FLAG_COUNT_OVERDRAW`](crate::shared::VIEW_FLAG_COUNT_OVERDRAW) every covered pixel also
//! increments a per-pixel counter ([`RasterSw::record_counting`]; the overdraw view).

use crate::gpu::{
    Buffer, Cmd, ComputePipeline, Context, Desc, GpuResult, MemoryKind, ShaderStage, Timer, vk,
};
use crate::passes::cull::Phase;
use crate::passes::{FrameBuffers, VisPath, with_geometry};
use crate::scene_gpu::GpuScene;
use crate::shared::CullCounters;

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "raster_sw";

/// The compute rasterizer's pipeline for one visibility-buffer path.
pub struct RasterSw {
    pipeline: ComputePipeline,
    path: VisPath,
    /// Bound as the overdraw counter when the frame does not count.
    no_overdraw: Buffer,
}

impl RasterSw {
    /// Creates the pipeline for `path` (the image variant needs 64-bit image atomics).
    pub fn new(ctx: &Context, path: VisPath) -> GpuResult<Self> {
        use vk::DescriptorType as D;
        let spirv = match path {
            VisPath::Buffer => crate::shaders::RASTER_SW_COMP,
            VisPath::Image => crate::shaders::RASTER_SW_COMP_IMAGE,
        };
        let vis = path.descriptor_type();
        let mut bindings = vec![D::UNIFORM_BUFFER];
        bindings.extend([D::STORAGE_BUFFER; 8]);
        bindings.push(vis);
        // The overdraw counter, then the HW list (its end: the quarter path's clusters).
        bindings.extend([D::STORAGE_BUFFER; 2]);
        let pipeline = ComputePipeline::new(ctx, ShaderStage { name: NAME, spirv }, &bindings, 0)?;
        let no_overdraw = overdraw_placeholder(ctx, NAME)?;
        Ok(Self {
            pipeline,
            path,
            no_overdraw,
        })
    }

    /// The visibility-buffer path the pipeline was made for.
    pub fn path(&self) -> VisPath {
        self.path
    }

    /// Records the pass: rasterizes every cluster of `fb.sw_list` (count and dispatch arguments in
    /// `fb.counters`) into `fb.visbuffer`. Inputs must be visible to compute shaders and to the
    /// indirect-command stage (the frame records those barriers). Counts no overdraw: the view's
    /// flags must not have [`VIEW_FLAG_COUNT_OVERDRAW`](crate::shared::VIEW_FLAG_COUNT_OVERDRAW).
    pub fn record(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
        phase: Phase,
    ) {
        self.record_counting(cmd, timer, scene, fb, phase, None);
    }

    /// [`RasterSw::record`] with the overdraw counter: `overdraw` (`fb.width * fb.height` u32,
    /// row-major) gets 1 added per covered pixel of every triangle when the view's flags have
    /// [`VIEW_FLAG_COUNT_OVERDRAW`](crate::shared::VIEW_FLAG_COUNT_OVERDRAW). `None` binds a
    /// placeholder (counts, if the flag is set anyway, are dropped).
    pub fn record_counting(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
        phase: Phase,
        overdraw: Option<&Buffer>,
    ) {
        let (counters, sw_list, hw_list) = fb.phase_lists(phase);
        timer.begin(cmd, phase.name("raster_sw", "raster_sw (post)"));
        let vis = fb.visbuffer_desc(cmd);
        debug_assert_eq!(
            fb.vis_path(),
            self.path,
            "raster_sw: pipeline for another path"
        );
        cmd.bind_compute(&self.pipeline);
        cmd.push_compute_descriptors(
            &self.pipeline,
            &with_geometry(
                &[
                    Desc::Uniform(&fb.view),
                    Desc::Storage(counters),
                    Desc::Storage(&fb.visible),
                    Desc::Storage(sw_list),
                ],
                scene,
                &[
                    vis,
                    Desc::Storage(overdraw.unwrap_or(&self.no_overdraw)),
                    Desc::Storage(hw_list),
                ],
            ),
        );
        cmd.dispatch_indirect(
            counters,
            std::mem::offset_of!(CullCounters, sw_dispatch) as u64,
        );
        timer.end(cmd);
    }
}

/// A one-word storage buffer bound in place of the overdraw counter when a frame does not count.
pub(crate) fn overdraw_placeholder(ctx: &Context, pass: &str) -> GpuResult<Buffer> {
    Buffer::new(
        ctx,
        &format!("{pass} overdraw placeholder"),
        4,
        vk::BufferUsageFlags::STORAGE_BUFFER,
        MemoryKind::Gpu,
    )
}
