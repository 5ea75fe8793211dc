//! Pass `depth_import` (shaders_glsl/depth_import.comp.glsl), embedding only: seeds the visibility
//! buffer from the host's depth, copied into a float buffer first (see [`HostDepthBuffer`]). A
//! pixel the host covered becomes `depth << 32 | VISBUFFER_HOST`
//! ([`crate::shared::VISBUFFER_HOST`]), the others empty; it replaces the visibility buffer's
//! clear. vgeo's fragments behind the host's surface then lose the 64-bit `atomicMax`, and
//! `depth_pyramid` builds the HZB over both surfaces (the host's depth occludes vgeo's geometry).

use bytemuck::{Pod, Zeroable};

use crate::gpu::{
    Buffer, Cmd, ComputePipeline, Context, Desc, GpuResult, MemoryKind, ShaderStage, Timer, vk,
};
use crate::passes::{FrameBuffers, VisPath};
use crate::shared::TILE_WORKGROUP_SIZE;

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "depth_import";

/// Push constants of `depth_import` and `depth_export`.
#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
pub(crate) struct Push {
    pub width: u32,
    pub height: u32,
}
const _: () = assert!(size_of::<Push>() == 8);

/// The host's depth as `width * height` f32 (row-major): what a D32 image is copied to and from.
pub struct HostDepthBuffer {
    pub buffer: Buffer,
    pub width: u32,
    pub height: u32,
}

impl HostDepthBuffer {
    /// A device-local buffer for a `width` x `height` depth image.
    pub fn new(ctx: &Context, name: &str, width: u32, height: u32) -> GpuResult<Self> {
        Ok(Self {
            buffer: Buffer::new(
                ctx,
                name,
                4 * width as u64 * height as u64,
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_SRC
                    | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryKind::Gpu,
            )?,
            width,
            height,
        })
    }
}

/// A compute pipeline of a visibility-buffer pass with the host depth buffer at binding 1.
pub(crate) fn pipeline(
    ctx: &Context,
    name: &'static str,
    spirv: &'static [u8],
    path: VisPath,
) -> GpuResult<ComputePipeline> {
    ComputePipeline::new(
        ctx,
        ShaderStage { name, spirv },
        &[path.descriptor_type(), vk::DescriptorType::STORAGE_BUFFER],
        size_of::<Push>() as u32,
    )
}

/// Records one dispatch of `pipeline` over the frame (binding 0 visibility buffer, 1 `depth`).
pub(crate) fn record_pass(
    pipeline: &ComputePipeline,
    name: &'static str,
    cmd: &mut Cmd,
    timer: &mut Timer,
    fb: &FrameBuffers,
    depth: &HostDepthBuffer,
) {
    timer.begin(cmd, name);
    cmd.bind_compute(pipeline);
    let vis = fb.visbuffer_desc(cmd);
    cmd.push_compute_descriptors(pipeline, &[vis, Desc::Storage(&depth.buffer)]);
    let push = Push {
        width: fb.width,
        height: fb.height,
    };
    cmd.compute_push_constants(pipeline, bytemuck::bytes_of(&push));
    cmd.dispatch(
        fb.width.div_ceil(TILE_WORKGROUP_SIZE),
        fb.height.div_ceil(TILE_WORKGROUP_SIZE),
        1,
    );
    timer.end(cmd);
}

/// The pass's pipeline.
pub struct DepthImport {
    pipeline: ComputePipeline,
}

impl DepthImport {
    /// Creates the pipeline for `path`.
    pub fn new(ctx: &Context, path: VisPath) -> GpuResult<Self> {
        let spirv = match path {
            VisPath::Buffer => crate::shaders::DEPTH_IMPORT_COMP,
            VisPath::Image => crate::shaders::DEPTH_IMPORT_COMP_IMAGE,
        };
        Ok(Self {
            pipeline: pipeline(ctx, NAME, spirv, path)?,
        })
    }

    /// Records the pass: `depth` (written by a transfer, made visible to compute by the caller)
    /// into the visibility buffer (the caller orders the rasterizers after it).
    pub fn record(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        fb: &FrameBuffers,
        depth: &HostDepthBuffer,
    ) {
        record_pass(&self.pipeline, NAME, cmd, timer, fb, depth);
    }
}
