//! Pass `instance_cull`: a thread per instance tests the mesh's bounding sphere against the frustum
//! and pushes the mesh's BVH root for each visible instance into `cluster_cull`'s work queue.

use crate::gpu::{Buffer, Cmd, ComputePipeline, Context, GpuResult, ShaderStage, Timer};
use crate::passes::FrameBuffers;
use crate::passes::cull::{Phase, descriptors};
use crate::scene_gpu::GpuScene;
use crate::shared::INSTANCE_CULL_WORKGROUP_SIZE;

/// The `instance_cull` pipeline.
pub struct InstanceCull {
    pipeline: ComputePipeline,
}

impl InstanceCull {
    /// Creates the pipeline.
    pub fn new(ctx: &Context) -> GpuResult<Self> {
        let pipeline = ComputePipeline::new(
            ctx,
            ShaderStage {
                name: "instance_cull",
                spirv: crate::shaders::INSTANCE_CULL_COMP,
            },
            &crate::passes::cull::layout(),
            4,
        )?;
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
        timer.begin(cmd, &format!("instance_cull{}", phase.label()));
        cmd.bind_compute(&self.pipeline);
        cmd.push_compute_descriptors(&self.pipeline, &descriptors(scene, fb, hzb, phase));
        cmd.compute_push_constants(&self.pipeline, &phase.push_constant());
        let groups = scene.instance_count.div_ceil(INSTANCE_CULL_WORKGROUP_SIZE);
        if groups > 0 {
            let x = groups.min(65535);
            cmd.dispatch(x, groups.div_ceil(x), 1);
        }
        timer.end(cmd);
    }
}
