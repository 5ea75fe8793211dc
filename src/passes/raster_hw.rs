//! Pass `raster_hw`: the hardware rasterizer (shaders_glsl/raster_hw.vert.glsl / .frag.glsl).
//!
//! One `vkCmdDrawIndirect` (`CullCounters::hw_draw`: `MAX_CLUSTER_TRIANGLES * 3` vertices, one
//! instance per HW-list entry) with no vertex buffers and no attachments: the vertex shader pulls the
//! cluster's vertices (triangles beyond the cluster's count collapse to a point outside the view
//! volume), the fragment shader does the same `atomicMax` into the visibility buffer as `raster_sw`.
//! Coverage is the hardware's (same fill rule and sub-pixel precision as SW on conformant devices);
//! depth is recomputed from the snapped vertices with `raster_sw`'s exact integer edge functions and
//! float operations, so SW and HW write bit-identical values for the pixels both cover. Triangles
//! with a vertex behind the near plane (which only HW can draw: the hardware clips them) use
//! `gl_FragCoord.z`. With [`VIEW_FLAG_COUNT_OVERDRAW`](crate::shared::VIEW_FLAG_COUNT_OVERDRAW)
//! every fragment also increments a per-pixel counter ([`RasterHw::record_counting`]).

use crate::gpu::{
    Buffer, Cmd, Context, Desc, GpuResult, GraphicsPipeline, GraphicsPipelineDesc, ShaderStage,
    Timer, vk,
};
use crate::passes::cull::Phase;
use crate::passes::{FrameBuffers, VisPath, with_geometry};
use crate::scene_gpu::GpuScene;
use crate::shared::CullCounters;

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "raster_hw";

/// The hardware rasterizer's pipeline for one visibility-buffer path.
pub struct RasterHw {
    pipeline: GraphicsPipeline,
    path: VisPath,
    /// Bound as the overdraw counter when the frame does not count.
    no_overdraw: Buffer,
}

impl RasterHw {
    /// Creates the pipeline for `path` (the image variant needs 64-bit image atomics).
    pub fn new(ctx: &Context, path: VisPath) -> GpuResult<Self> {
        use vk::DescriptorType as D;
        let frag = match path {
            VisPath::Buffer => crate::shaders::RASTER_HW_FRAG,
            VisPath::Image => crate::shaders::RASTER_HW_FRAG_IMAGE,
        };
        let vis = path.descriptor_type();
        let mut bindings = vec![D::UNIFORM_BUFFER];
        bindings.extend([D::STORAGE_BUFFER; 7]);
        bindings.push(vis);
        bindings.push(D::STORAGE_BUFFER);
        let pipeline = GraphicsPipeline::new(
            ctx,
            &GraphicsPipelineDesc {
                name: NAME,
                vertex: ShaderStage {
                    name: "raster_hw.vert",
                    spirv: crate::shaders::RASTER_HW_VERT,
                },
                fragment: ShaderStage {
                    name: "raster_hw.frag",
                    spirv: frag,
                },
                bindings: &bindings,
                push_constant_size: 0,
                vertex_layout: None,
                color_formats: &[],
                depth_format: None,
                depth_compare: vk::CompareOp::ALWAYS,
                depth_write: false,
                cull: vk::CullModeFlags::NONE,
            },
        )?;
        let no_overdraw = crate::passes::raster_sw::overdraw_placeholder(ctx, NAME)?;
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

    /// Records the pass: draws every cluster of `fb.hw_list` (count and draw arguments in
    /// `fb.counters`) into `fb.visbuffer`. Inputs must be visible to the vertex and fragment
    /// shaders and to the indirect-command stage (the frame records those barriers). Counts no
    /// overdraw: the view's flags must not have
    /// [`VIEW_FLAG_COUNT_OVERDRAW`](crate::shared::VIEW_FLAG_COUNT_OVERDRAW).
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

    /// [`RasterHw::record`] with the overdraw counter: `overdraw` (`fb.width * fb.height` u32,
    /// row-major) gets 1 added per fragment when the view's flags have
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
        let (counters, _, hw_list) = fb.phase_lists(phase);
        timer.begin(cmd, phase.name("raster_hw", "raster_hw (post)"));
        let vis = fb.visbuffer_desc(cmd);
        debug_assert_eq!(
            fb.vis_path(),
            self.path,
            "raster_hw: pipeline for another path"
        );
        cmd.begin_rendering_no_attachments(fb.width, fb.height);
        cmd.bind_graphics(&self.pipeline);
        cmd.push_graphics_descriptors(
            &self.pipeline,
            &with_geometry(
                &[
                    Desc::Uniform(&fb.view),
                    Desc::Storage(&fb.visible),
                    Desc::Storage(hw_list),
                ],
                scene,
                &[vis, Desc::Storage(overdraw.unwrap_or(&self.no_overdraw))],
            ),
        );
        cmd.draw_indirect(counters, std::mem::offset_of!(CullCounters, hw_draw) as u64);
        cmd.end_rendering();
        timer.end(cmd);
    }
}
