//! Pass `depth_pyramid`: the hierarchical depth buffer (HZB) from the visibility buffer, stored as
//! one f32 storage buffer with the levels one after another. Each texel holds the farthest depth
//! (reverse-Z minimum) of the pixels below it; empty pixels count as infinitely far. Level `k` is
//! `ceil(w / 2^(k+1)) x ceil(h / 2^(k+1))`. One dispatch whatever the size: each workgroup reduces a
//! tile of level 0 through the first [`HZB_HEAD_LEVELS`](crate::shared::HZB_HEAD_LEVELS) levels in shared memory, and the last
//! workgroup to finish (a counter in `sync`, which it resets) makes the rest; a dispatch per level
//! cost the CPU three commands a level to record and the GPU a drain between levels, and a second
//! dispatch for the rest another drain. The post phase's pyramid is an indirect dispatch
//! ([`DepthPyramid::record_indirect`], `CullCounters::hzb_dispatch`) of no workgroups when that
//! phase drew nothing: the HZB is then the main phase's, unchanged. The `lod` baseline builds the
//! same pyramid from its depth attachment (variant `depth`, [`DepthPyramid::for_depth`]).

use bytemuck::{Pod, Zeroable};

use crate::gpu::{
    Buffer, Cmd, ComputePipeline, Context, Desc, GpuResult, Image, MemoryKind, ShaderStage, Timer,
    vk,
};
use crate::passes::{FrameBuffers, VisPath};
use crate::shared::HZB_GROUP;

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Push {
    width: u32,
    height: u32,
    levels: u32,
    _pad: u32,
}

/// Sizes and offsets (in f32 texels) of the levels of an HZB for a `width` x `height` frame.
pub fn hzb_levels(width: u32, height: u32) -> Vec<(u32, u32, u32)> {
    let mut levels = Vec::new();
    let (mut w, mut h, mut offset) = (width.div_ceil(2).max(1), height.div_ceil(2).max(1), 0u32);
    loop {
        levels.push((w, h, offset));
        offset += w * h;
        if w == 1 && h == 1 {
            break;
        }
        w = w.div_ceil(2);
        h = h.div_ceil(2);
    }
    levels
}

/// The pipeline and the HZB storage for one frame size.
pub struct DepthPyramid {
    pipeline: ComputePipeline,
    /// All levels, one after another (see [`hzb_levels`]).
    pub hzb: Buffer,
    pub levels: Vec<(u32, u32, u32)>,
    /// One u32: the workgroups of the running dispatch that have finished their tile (zero
    /// between dispatches; the last workgroup resets it).
    sync: Buffer,
    width: u32,
    height: u32,
}

impl DepthPyramid {
    /// Creates the pipeline (for the frame buffers' visibility-buffer path) and the HZB buffer.
    pub fn new(ctx: &Context, fb: &FrameBuffers) -> GpuResult<Self> {
        let spirv = match fb.vis_path() {
            VisPath::Buffer => crate::shaders::DEPTH_PYRAMID_COMP,
            VisPath::Image => crate::shaders::DEPTH_PYRAMID_COMP_IMAGE,
        };
        let vis_desc = fb.vis_path().descriptor_type();
        let pipeline = ComputePipeline::new(
            ctx,
            ShaderStage {
                name: "depth_pyramid",
                spirv,
            },
            &[
                vis_desc,
                vk::DescriptorType::STORAGE_BUFFER,
                vk::DescriptorType::STORAGE_BUFFER,
            ],
            size_of::<Push>() as u32,
        )?;
        Self::with_pipeline(ctx, pipeline, fb.width, fb.height)
    }

    /// The pipeline (variant `depth`) and HZB of a `width` x `height` frame whose source is a
    /// depth attachment copied into a buffer of `width * height` f32 (the `lod` baseline,
    /// [`DepthPyramid::record_depth`]).
    pub fn for_depth(ctx: &Context, width: u32, height: u32) -> GpuResult<Self> {
        let pipeline = ComputePipeline::new(
            ctx,
            ShaderStage {
                name: "depth_pyramid",
                spirv: crate::shaders::DEPTH_PYRAMID_COMP_DEPTH,
            },
            &[vk::DescriptorType::STORAGE_BUFFER; 3],
            size_of::<Push>() as u32,
        )?;
        Self::with_pipeline(ctx, pipeline, width, height)
    }

    fn with_pipeline(
        ctx: &Context,
        pipeline: ComputePipeline,
        width: u32,
        height: u32,
    ) -> GpuResult<Self> {
        let levels = hzb_levels(width, height);
        let texels: u64 = levels.iter().map(|l| (l.0 * l.1) as u64).sum();
        let hzb = Buffer::new(
            ctx,
            "hzb",
            4 * texels,
            vk::BufferUsageFlags::STORAGE_BUFFER
                | vk::BufferUsageFlags::TRANSFER_DST
                | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryKind::Gpu,
        )?;
        let sync = Buffer::with_data(
            ctx,
            "hzb sync",
            &[0u8; 4],
            vk::BufferUsageFlags::STORAGE_BUFFER,
        )?;
        Ok(Self {
            pipeline,
            hzb,
            levels,
            sync,
            width,
            height,
        })
    }

    /// Records the pass (the visibility buffer must be visible to compute shaders).
    pub fn record(&self, cmd: &mut Cmd, timer: &mut Timer, fb: &FrameBuffers) {
        timer.begin(cmd, "depth_pyramid");
        let vis = fb.visbuffer_desc(cmd);
        self.record_from(cmd, vis, None);
        timer.end(cmd);
    }

    /// [`DepthPyramid::record`] as an indirect dispatch whose arguments (x, y, z) are at `offset`
    /// in `args`, written before and visible to the indirect-command stage: the cull's
    /// `CullCounters::hzb_dispatch`, no workgroups when the phase drew nothing (the HZB stays
    /// the pyramid of the unchanged visibility buffer).
    pub fn record_indirect(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        fb: &FrameBuffers,
        args: &Buffer,
        offset: u64,
    ) {
        timer.begin(cmd, "depth_pyramid");
        let vis = fb.visbuffer_desc(cmd);
        self.record_from(cmd, vis, Some((args, offset)));
        timer.end(cmd);
    }

    /// Records the pass of a pyramid made by [`DepthPyramid::for_depth`] from the depth
    /// attachment `depth` (D32, written before), copied first into `copy` (`width * height` f32).
    pub fn record_depth(&self, cmd: &mut Cmd, timer: &mut Timer, depth: &Image, copy: &Buffer) {
        timer.begin(cmd, "depth_pyramid");
        cmd.copy_image_to_buffer(depth, copy);
        cmd.barrier(
            (
                vk::PipelineStageFlags2::ALL_TRANSFER,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (
                vk::PipelineStageFlags2::COMPUTE_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_READ,
            ),
        );
        self.record_from(cmd, Desc::Storage(copy), None);
        timer.end(cmd);
    }

    /// Workgroups of a full dispatch: one per tile of `2 * HZB_GROUP` texels of level 0 (the
    /// cull computes the same for `CullCounters::hzb_dispatch`).
    pub fn groups(&self) -> (u32, u32) {
        let tile = 2 * HZB_GROUP;
        let (w0, h0, _) = self.levels[0];
        (w0.div_ceil(tile), h0.div_ceil(tile))
    }

    fn record_from(&self, cmd: &mut Cmd, source: Desc<'_>, indirect: Option<(&Buffer, u64)>) {
        cmd.bind_compute(&self.pipeline);
        cmd.push_compute_descriptors(
            &self.pipeline,
            &[source, Desc::Storage(&self.hzb), Desc::Storage(&self.sync)],
        );
        let push = Push {
            width: self.width,
            height: self.height,
            levels: self.levels.len() as u32,
            _pad: 0,
        };
        cmd.compute_push_constants(&self.pipeline, bytemuck::bytes_of(&push));
        match indirect {
            Some((args, offset)) => cmd.dispatch_indirect(args, offset),
            None => {
                let (x, y) = self.groups();
                cmd.dispatch(x, y, 1);
            }
        }
        let rw = vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE;
        cmd.barrier(
            (vk::PipelineStageFlags2::COMPUTE_SHADER, rw),
            (vk::PipelineStageFlags2::COMPUTE_SHADER, rw),
        );
    }
}

/// The same pyramid on the CPU from per-pixel depths (0 = empty), for tests.
pub fn hzb_reference(depth: &[f32], width: u32, height: u32) -> Vec<f32> {
    let levels = hzb_levels(width, height);
    let mut out = vec![0f32; levels.iter().map(|l| (l.0 * l.1) as usize).sum()];
    let (mut sw, mut sh, mut so) = (width, height, usize::MAX);
    for (k, &(w, h, offset)) in levels.iter().enumerate() {
        for y in 0..h {
            for x in 0..w {
                let mut d = 1.0f32;
                for (dx, dy) in [(0, 0), (1, 0), (0, 1), (1, 1)] {
                    let (sx, sy) = (2 * x + dx, 2 * y + dy);
                    if sx < sw && sy < sh {
                        let v = if k == 0 {
                            depth[(sy * sw + sx) as usize]
                        } else {
                            out[so + (sy * sw + sx) as usize]
                        };
                        d = d.min(v);
                    }
                }
                out[offset as usize + (y * w + x) as usize] = d;
            }
        }
        (sw, sh, so) = (w, h, offset as usize);
    }
    out
}
