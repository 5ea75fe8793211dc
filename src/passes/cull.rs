//! The descriptor set shared by `instance_cull` and `cluster_cull`, per phase of the two-pass
//! occlusion culling.

use crate::gpu::{Buffer, Cmd, ComputePipeline, Context, Desc, GpuResult, ShaderStage, vk};
use crate::passes::FrameBuffers;
use crate::scene_gpu::GpuScene;
use crate::shared::SPEC_CULL_STREAMING;

/// Which half of the two-pass occlusion culling runs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Phase {
    /// Test against the previous frame's HZB; defer what it rejects.
    Main,
    /// Test what was deferred against this frame's HZB.
    Post,
}

impl Phase {
    /// The push constant the shaders read.
    pub fn push_constant(self) -> [u8; 4] {
        (self as u32).to_le_bytes()
    }

    /// The debug label suffix.
    pub fn label(self) -> &'static str {
        match self {
            Phase::Main => "",
            Phase::Post => " (post)",
        }
    }

    /// A pass's debug label and timer scope in this phase: `main`, or `post` (`main` plus
    /// [`Phase::label`]), both static so recording allocates nothing.
    pub fn name(self, main: &'static str, post: &'static str) -> &'static str {
        match self {
            Phase::Main => main,
            Phase::Post => post,
        }
    }
}

/// Descriptor types of the shared layout, binding i = entry i.
pub fn layout() -> Vec<vk::DescriptorType> {
    use vk::DescriptorType as D;
    let mut v = vec![D::UNIFORM_BUFFER];
    v.extend([D::STORAGE_BUFFER; 10]);
    v.push(D::UNIFORM_BUFFER);
    v.extend([D::STORAGE_BUFFER; 10]);
    v
}

/// The descriptors of one phase (`hzb`: the HZB the phase tests against).
pub fn descriptors<'a>(
    scene: &'a GpuScene,
    fb: &'a FrameBuffers,
    hzb: &'a Buffer,
    phase: Phase,
) -> [Desc<'a>; 22] {
    let (counters, sw, hw, occ) = match phase {
        Phase::Main => (&fb.counters, &fb.sw_list, &fb.hw_list, &fb.occ_main),
        Phase::Post => (
            &fb.counters_post,
            &fb.sw_list_post,
            &fb.hw_list_post,
            &fb.occ_post,
        ),
    };
    [
        Desc::Uniform(&fb.view),
        Desc::Storage(&scene.meshes),
        Desc::Storage(&scene.instances),
        Desc::Storage(counters),
        Desc::Storage(&fb.queue),
        Desc::Storage(&scene.bvh),
        Desc::Storage(&scene.groups),
        Desc::Storage(&scene.clusters),
        Desc::Storage(&fb.visible),
        Desc::Storage(sw),
        Desc::Storage(hw),
        Desc::Uniform(occ),
        Desc::Storage(hzb),
        Desc::Storage(&fb.counters),
        Desc::Storage(&fb.post_instances),
        Desc::Storage(&fb.post_nodes),
        Desc::Storage(&fb.post_clusters),
        Desc::Storage(&scene.pages),
        Desc::Storage(&scene.page_requests),
        Desc::Storage(&scene.page_usage),
        Desc::Storage(&scene.pool),
        Desc::Storage(&scene.tiny_cuts),
    ]
}

/// A cull pass's pipeline: the shared layout and the phase push constant.
pub fn pipeline(ctx: &Context, name: &str, spirv: &[u8]) -> GpuResult<ComputePipeline> {
    ComputePipeline::new(ctx, ShaderStage { name, spirv }, &layout(), 4)
}

/// A cull pass's shader as two pipelines: `streaming` with the partial-residency code
/// (`CULL_STREAMING` true, [`SPEC_CULL_STREAMING`]), `resident` without it, for frames in which no
/// mesh has [`crate::shared::MESH_STREAM_PARTIAL`]. Both draw the same cut of such a frame (the
/// code they differ by takes no branch there); the resident one is what an all-resident scene
/// runs, so that streaming's code costs it nothing.
pub struct CullPipelines {
    streaming: ComputePipeline,
    resident: ComputePipeline,
}

impl CullPipelines {
    /// Creates both pipelines of `spirv`, named `name`.
    pub fn new(ctx: &Context, name: &str, spirv: &[u8]) -> GpuResult<Self> {
        let make = |on: bool| {
            ComputePipeline::specialized(
                ctx,
                ShaderStage { name, spirv },
                &layout(),
                4,
                &[(SPEC_CULL_STREAMING, on as u32)],
            )
        };
        Ok(Self {
            streaming: make(true)?,
            resident: make(false)?,
        })
    }

    /// The pipeline of a frame: `streaming` when some mesh may be partial.
    pub fn pick(&self, streaming: bool) -> &ComputePipeline {
        if streaming {
            &self.streaming
        } else {
            &self.resident
        }
    }
}

/// Binds a cull pass's pipeline with one phase's descriptors and push constant.
pub fn bind(
    cmd: &mut Cmd,
    pipeline: &ComputePipeline,
    scene: &GpuScene,
    fb: &FrameBuffers,
    hzb: &Buffer,
    phase: Phase,
) {
    cmd.bind_compute(pipeline);
    cmd.push_compute_descriptors(pipeline, &descriptors(scene, fb, hzb, phase));
    cmd.compute_push_constants(pipeline, &phase.push_constant());
}
