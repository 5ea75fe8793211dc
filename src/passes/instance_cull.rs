//! Pass `instance_cull`: a thread per instance tests the mesh's bounding sphere against the frustum
//! and pushes the mesh's BVH root for each visible instance into `cluster_cull`'s work queue.

use crate::gpu::{Buffer, Cmd, ComputePipeline, Context, GpuResult, Timer};
use crate::passes::FrameBuffers;
use crate::passes::cull::{self, Phase};
use crate::scene_gpu::GpuScene;
use crate::shared::INSTANCE_CULL_WORKGROUP_SIZE;

/// The `instance_cull` pipeline.
pub struct InstanceCull {
    pipeline: ComputePipeline,
}

impl InstanceCull {
    /// Creates the pipeline.
    pub fn new(ctx: &Context) -> GpuResult<Self> {
        let pipeline = cull::pipeline(ctx, "instance_cull", crate::shaders::INSTANCE_CULL_COMP)?;
        Ok(Self { pipeline })
    }

    /// Records the pass: one thread per instance in a 2D grid of workgroups.
    pub fn record(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
        hzb: &Buffer,
        phase: Phase,
    ) {
        timer.begin(cmd, phase.name("instance_cull", "instance_cull (post)"));
        cull::bind(cmd, &self.pipeline, scene, fb, hzb, phase);
        let groups = scene.instance_count.div_ceil(INSTANCE_CULL_WORKGROUP_SIZE);
        if groups > 0 {
            let x = groups.min(65535);
            cmd.dispatch(x, groups.div_ceil(x), 1);
        }
        timer.end(cmd);
    }
}
