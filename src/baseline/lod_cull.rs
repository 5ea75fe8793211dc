//! Pass `lod_cull`: the GPU-driven `lod` baseline's per-instance frustum and HZB culling and
//! level selection (shaders_glsl/lod_cull.comp.glsl). One recording is a culling phase (main or
//! post) followed by the commands phase: the (mesh, level) bucket counters are cleared, the phase
//! fills the buckets and the instance list, then one thread per mesh writes the mesh's
//! `VkDrawIndexedIndirectCommand`s and draw count for `vkCmdDrawIndexedIndirectCount`.

use bytemuck::{Pod, Zeroable};

use crate::gpu::{Buffer, Cmd, ComputePipeline, Context, Desc, GpuResult, ShaderStage, Timer, vk};
use crate::shared::{LOD_CULL_WORKGROUP_SIZE, LOD_PHASE_COMMANDS, LOD_PHASE_MAIN, LOD_PHASE_POST};

/// The pass's name: shader, pipeline, debug label and timer scope of the main phase.
pub const NAME: &str = "lod_cull";
/// Label and timer scope of the post phase.
pub const NAME_POST: &str = "lod_cull (post)";

#[repr(C)]
#[derive(Clone, Copy, Pod, Zeroable)]
struct Push {
    phase: u32,
    frame: u32,
}

/// What one recording of `lod_cull` reads and writes (bindings 0..12 of the shader).
pub(crate) struct LodCullBuffers<'a> {
    /// `LodViewGpu` (uniform).
    pub view: &'a Buffer,
    /// `InstanceGpu` per placement (camera-relative model matrices), in placement order.
    pub instances: &'a Buffer,
    /// Mesh index per placement.
    pub instance_mesh: &'a Buffer,
    /// `LodMeshGpu` per mesh.
    pub meshes: &'a Buffer,
    /// Per mesh, (first, count) of its placements: its buckets' instance-list regions.
    pub mesh_slots: &'a Buffer,
    /// Instances per (mesh, level) bucket (cleared here).
    pub bucket_counts: &'a Buffer,
    /// Placement index per drawn instance, by bucket region (`LOD_LEVELS` per placement).
    pub instance_list: &'a Buffer,
    /// Placements the main phase deferred to the post phase.
    pub post_list: &'a Buffer,
    /// `LodDrawGpu` per bucket (`LOD_LEVELS` per mesh, the non-empty ones first).
    pub commands: &'a Buffer,
    /// Draws per mesh.
    pub draw_counts: &'a Buffer,
    /// `LodStatsGpu` per frame of the submission.
    pub stats: &'a Buffer,
    /// Level per placement (`LOD_LEVEL_CULLED`, `LOD_LEVEL_OCCLUDED` bit).
    pub levels: &'a Buffer,
    /// The HZB (`depth_pyramid`); any buffer when occlusion is off.
    pub hzb: &'a Buffer,
}

/// The `lod_cull` pipeline.
pub(crate) struct LodCull {
    pipeline: ComputePipeline,
}

impl LodCull {
    pub(crate) fn new(ctx: &Context) -> GpuResult<Self> {
        use vk::DescriptorType as D;
        let mut bindings = [D::STORAGE_BUFFER; 13];
        bindings[0] = D::UNIFORM_BUFFER;
        let pipeline = ComputePipeline::new(
            ctx,
            ShaderStage {
                name: NAME,
                spirv: crate::shaders::LOD_CULL_COMP,
            },
            &bindings,
            size_of::<Push>() as u32,
        )?;
        Ok(Self { pipeline })
    }

    /// Records the main (`post` false) or post phase of frame `frame` of the submission over
    /// `instances` placements, then the commands phase over `meshes` meshes. Afterwards the
    /// commands, draw counts and instance list are visible to indirect draws and vertex shaders.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn record(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        b: &LodCullBuffers<'_>,
        post: bool,
        frame: u32,
        instances: u32,
        meshes: u32,
    ) {
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        // Whatever read the buckets, list and commands before (the previous draw) is done.
        cmd.barrier(
            (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
            (S::ALL_TRANSFER, A::TRANSFER_WRITE),
        );
        cmd.fill_buffer(b.bucket_counts, 0);
        cmd.barrier(
            (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            (
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE,
            ),
        );
        timer.begin(cmd, if post { NAME_POST } else { NAME });
        cmd.bind_compute(&self.pipeline);
        cmd.push_compute_descriptors(
            &self.pipeline,
            &[
                Desc::Uniform(b.view),
                Desc::Storage(b.instances),
                Desc::Storage(b.instance_mesh),
                Desc::Storage(b.meshes),
                Desc::Storage(b.mesh_slots),
                Desc::Storage(b.bucket_counts),
                Desc::Storage(b.instance_list),
                Desc::Storage(b.post_list),
                Desc::Storage(b.commands),
                Desc::Storage(b.draw_counts),
                Desc::Storage(b.stats),
                Desc::Storage(b.levels),
                Desc::Storage(b.hzb),
            ],
        );
        let phase = if post { LOD_PHASE_POST } else { LOD_PHASE_MAIN };
        let rw = A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE;
        for (phase, threads) in [(phase, instances), (LOD_PHASE_COMMANDS, meshes)] {
            let push = Push { phase, frame };
            cmd.compute_push_constants(&self.pipeline, bytemuck::bytes_of(&push));
            cmd.dispatch(threads.div_ceil(LOD_CULL_WORKGROUP_SIZE).max(1), 1, 1);
            if phase != LOD_PHASE_COMMANDS {
                cmd.barrier((S::COMPUTE_SHADER, rw), (S::COMPUTE_SHADER, rw));
            }
        }
        cmd.barrier(
            (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
            (
                S::DRAW_INDIRECT | S::VERTEX_SHADER | S::COMPUTE_SHADER | S::ALL_TRANSFER,
                A::INDIRECT_COMMAND_READ | A::SHADER_STORAGE_READ | A::TRANSFER_READ,
            ),
        );
        timer.end(cmd);
    }
}
