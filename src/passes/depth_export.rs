//! Pass `depth_export` (shaders_glsl/depth_export.comp.glsl), embedding only: the visibility
//! buffer's depth after the rasterizers (the nearer of the host's surface, seeded by
//! `depth_import`, and vgeo's; 0 = far where empty) into the float buffer that is then copied into
//! the host's D32 depth image, so the host's later draws are occluded by vgeo's geometry.

use crate::gpu::{Cmd, ComputePipeline, Context, GpuResult, Timer};
use crate::passes::depth_import::{HostDepthBuffer, pipeline, record_pass};
use crate::passes::{FrameBuffers, VisPath};

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "depth_export";

/// The pass's pipeline.
pub struct DepthExport {
    pipeline: ComputePipeline,
}

impl DepthExport {
    /// Creates the pipeline for `path`.
    pub fn new(ctx: &Context, path: VisPath) -> GpuResult<Self> {
        let spirv = match path {
            VisPath::Buffer => crate::shaders::DEPTH_EXPORT_COMP,
            VisPath::Image => crate::shaders::DEPTH_EXPORT_COMP_IMAGE,
        };
        Ok(Self {
            pipeline: pipeline(ctx, NAME, spirv, path)?,
        })
    }

    /// Records the pass (the visibility buffer must be visible to compute shaders; the caller
    /// orders the copy into the host's image after it).
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
