//! Pass `occluder_select`: in a frame without a previous HZB ([`VIEW_FLAG_COLD_FRAME`]), at most
//! [`OCCLUDER_SELECT_GROUPS`] workgroups sum the projected area of the instances in the frustum by
//! distance ([`CullCounters::cold_area`](crate::shared::CullCounters::cold_area)), so that the main
//! phase's `instance_cull` draws only the nearest and defers the rest to the post phase.
//!
//! [`VIEW_FLAG_COLD_FRAME`]: crate::shared::VIEW_FLAG_COLD_FRAME

use crate::gpu::{Buffer, Cmd, ComputePipeline, Context, GpuResult, Timer};
use crate::passes::FrameBuffers;
use crate::passes::cull::{self, Phase};
use crate::scene_gpu::GpuScene;
use crate::shared::{INSTANCE_CULL_WORKGROUP_SIZE, OCCLUDER_SELECT_GROUPS};

/// The `occluder_select` pipeline.
pub struct OccluderSelect {
    pipeline: ComputePipeline,
}

impl OccluderSelect {
    /// Creates the pipeline (the culling passes' layout).
    pub fn new(ctx: &Context) -> GpuResult<Self> {
        let pipeline =
            cull::pipeline(ctx, "occluder_select", crate::shaders::OCCLUDER_SELECT_COMP)?;
        Ok(Self { pipeline })
    }

    /// Records the pass with the main phase's bindings: at most [`OCCLUDER_SELECT_GROUPS`]
    /// workgroups, each thread taking every so many instances.
    pub fn record(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
        hzb: &Buffer,
    ) {
        timer.begin(cmd, "occluder_select");
        cull::bind(cmd, &self.pipeline, scene, fb, hzb, Phase::Main);
        let groups = scene
            .instance_count
            .div_ceil(INSTANCE_CULL_WORKGROUP_SIZE)
            .min(OCCLUDER_SELECT_GROUPS);
        if groups > 0 {
            cmd.dispatch(groups, 1, 1);
        }
        timer.end(cmd);
    }
}
