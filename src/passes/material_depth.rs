//! Pass `material_depth` (shaders_glsl/material_depth.vert.glsl / .frag.glsl): a full-screen
//! triangle writing every covered pixel's material id as depth (`(id + 1) / 2^24`, exact in
//! `D32_SFLOAT`) from `material_classify`'s per-pixel ids; empty pixels keep the clear value 0, which
//! no material draw matches. `emit_gbuffer` tests against it with `EQUAL`.

use crate::gpu::{
    Cmd, Context, Desc, GeometryStage, GpuResult, GraphicsPipeline, GraphicsPipelineDesc,
    RenderTarget, ShaderStage, Timer, vk,
};
use crate::passes::material_classify::{MATERIAL_DEPTH_FORMAT, MaterialTargets};

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "material_depth";

/// The material-depth pipeline.
pub struct MaterialDepth {
    pipeline: GraphicsPipeline,
}

impl MaterialDepth {
    /// Creates the pipeline.
    pub fn new(ctx: &Context) -> GpuResult<Self> {
        use vk::DescriptorType as D;
        let pipeline = GraphicsPipeline::new(
            ctx,
            &GraphicsPipelineDesc {
                name: NAME,
                geometry: GeometryStage::Vertex(ShaderStage {
                    name: "material_depth.vert",
                    spirv: crate::shaders::MATERIAL_DEPTH_VERT,
                }),
                fragment: ShaderStage {
                    name: "material_depth.frag",
                    spirv: crate::shaders::MATERIAL_DEPTH_FRAG,
                },
                bindings: &[D::UNIFORM_BUFFER, D::STORAGE_BUFFER],
                push_constant_size: 0,
                vertex_layout: None,
                color_formats: &[],
                depth_format: Some(MATERIAL_DEPTH_FORMAT),
                depth_compare: vk::CompareOp::ALWAYS,
                depth_write: true,
                cull: vk::CullModeFlags::NONE,
            },
        )?;
        Ok(Self { pipeline })
    }

    /// Records the pass (clears the material depth to 0 first). `t.pixel_materials` must be
    /// visible to fragment shaders.
    pub fn record(&self, cmd: &mut Cmd, timer: &mut Timer, t: &MaterialTargets) {
        timer.begin(cmd, NAME);
        cmd.begin_rendering(
            &[],
            Some(RenderTarget {
                image: &t.material_depth,
                clear: Some([0.0; 4]),
            }),
        );
        cmd.bind_graphics(&self.pipeline);
        cmd.push_graphics_descriptors(
            &self.pipeline,
            &[
                Desc::Uniform(&t.gbuffer.view),
                Desc::Storage(&t.pixel_materials),
            ],
        );
        cmd.draw(3, 1);
        cmd.end_rendering();
        timer.end(cmd);
    }
}
