//! Pass `shade` (shaders_glsl/shade.comp.glsl): one directional light plus ambient from the GBuffer
//! into the output image (RGBA8, sRGB-encoded), the background where nothing was drawn; or one of
//! the GBuffer's channels (albedo, normals, materials), by [`MaterialTargets`]' view mode.

use crate::gpu::{Cmd, ComputePipeline, Context, Desc, GpuResult, ShaderStage, Timer, vk};
use crate::passes::material_classify::MaterialTargets;

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "shade";

/// Threads per workgroup side (`local_size_x/y` of the shader).
const WORKGROUP: u32 = 8;

/// The shading pipeline.
pub struct Shade {
    pipeline: ComputePipeline,
}

impl Shade {
    /// Creates the pipeline.
    pub fn new(ctx: &Context) -> GpuResult<Self> {
        use vk::DescriptorType as D;
        let bindings = [
            D::UNIFORM_BUFFER,
            D::STORAGE_IMAGE,
            D::STORAGE_IMAGE,
            D::STORAGE_IMAGE,
            D::STORAGE_IMAGE,
        ];
        Ok(Self {
            pipeline: ComputePipeline::new(
                ctx,
                ShaderStage {
                    name: NAME,
                    spirv: crate::shaders::SHADE_COMP,
                },
                &bindings,
                0,
            )?,
        })
    }

    /// Records the pass (the GBuffer images move to `GENERAL`).
    pub fn record(&self, cmd: &mut Cmd, timer: &mut Timer, t: &MaterialTargets) {
        timer.begin(cmd, NAME);
        for i in [&t.albedo, &t.normal, &t.params, &t.output] {
            cmd.to_general(i);
        }
        cmd.bind_compute(&self.pipeline);
        cmd.push_compute_descriptors(
            &self.pipeline,
            &[
                Desc::Uniform(&t.view),
                Desc::StorageImage(&t.albedo),
                Desc::StorageImage(&t.normal),
                Desc::StorageImage(&t.params),
                Desc::StorageImage(&t.output),
            ],
        );
        cmd.dispatch(t.width.div_ceil(WORKGROUP), t.height.div_ceil(WORKGROUP), 1);
        timer.end(cmd);
    }
}
