//! Pass `instance_cull`: a thread per instance tests the mesh's bounding sphere against the frustum
//! and pushes the mesh's BVH root for each visible instance into `cluster_cull`'s work queue.

use crate::gpu::{Cmd, ComputePipeline, Context, Desc, GpuResult, ShaderStage, Timer, vk};
use crate::passes::FrameBuffers;
use crate::scene_gpu::GpuScene;
use crate::shared::INSTANCE_CULL_WORKGROUP_SIZE;

/// The `instance_cull` pipeline.
pub struct InstanceCull {
    pipeline: ComputePipeline,
}

impl InstanceCull {
    /// Creates the pipeline.
    pub fn new(ctx: &Context) -> GpuResult<Self> {
        use vk::DescriptorType as D;
        let pipeline = ComputePipeline::new(
            ctx,
            ShaderStage {
                name: "instance_cull",
                spirv: crate::shaders::INSTANCE_CULL_COMP,
            },
            &[
                D::UNIFORM_BUFFER,
                D::STORAGE_BUFFER,
                D::STORAGE_BUFFER,
                D::STORAGE_BUFFER,
                D::STORAGE_BUFFER,
            ],
            0,
        )?;
        Ok(Self { pipeline })
    }

    /// Records the pass: one thread per instance in a 2D grid of workgroups.
    pub fn record(&self, cmd: &mut Cmd, timer: &mut Timer, scene: &GpuScene, fb: &FrameBuffers) {
        timer.begin(cmd, "instance_cull");
        cmd.bind_compute(&self.pipeline);
        cmd.push_compute_descriptors(
            &self.pipeline,
            &[
                Desc::Uniform(&fb.view),
                Desc::Storage(&scene.meshes),
                Desc::Storage(&scene.instances),
                Desc::Storage(&fb.counters),
                Desc::Storage(&fb.queue),
            ],
        );
        let groups = scene.instance_count.div_ceil(INSTANCE_CULL_WORKGROUP_SIZE);
        if groups > 0 {
            let x = groups.min(65535);
            cmd.dispatch(x, groups.div_ceil(x), 1);
        }
        timer.end(cmd);
    }
}
