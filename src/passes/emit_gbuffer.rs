//! Pass `emit_gbuffer` (shaders_glsl/emit_gbuffer.vert.glsl / .frag.glsl): one draw per material of
//! a grid of 64x64 tile quads at the material's depth. The vertex shader drops the tiles whose
//! `material_classify` range excludes the material; the depth test `EQUAL` against the material
//! depth lets only that material's pixels run the fragment shader, which rebuilds the triangle's
//! attributes from the visibility buffer and writes the GBuffer. With counting on, each fragment
//! adds one to its material's counter (tests compare these with the pixels of each material).

use crate::gpu::{
    Cmd, Context, Desc, GpuResult, GraphicsPipeline, GraphicsPipelineDesc, RenderTarget,
    ShaderStage, Timer, vk,
};
use crate::material::GpuMaterials;
use crate::passes::material_classify::{MATERIAL_DEPTH_FORMAT, MaterialTargets};
use crate::passes::shade::{ALBEDO_FORMAT, NORMAL_FORMAT, PARAMS_FORMAT};
use crate::passes::{FrameBuffers, VisPath, with_geometry};
use crate::scene_gpu::GpuScene;

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "emit_gbuffer";

/// The GBuffer pipeline (made for one material table's texture array and visibility-buffer path).
pub struct EmitGbuffer {
    pipeline: GraphicsPipeline,
}

impl EmitGbuffer {
    /// Creates the pipeline for `path`, with `materials`' texture array as set 1.
    pub fn new(ctx: &Context, path: VisPath, materials: &GpuMaterials) -> GpuResult<Self> {
        use vk::DescriptorType as D;
        let frag = match path {
            VisPath::Buffer => crate::shaders::EMIT_GBUFFER_FRAG,
            VisPath::Image => crate::shaders::EMIT_GBUFFER_FRAG_IMAGE,
        };
        let vis = path.descriptor_type();
        let mut bindings = vec![D::UNIFORM_BUFFER, D::STORAGE_BUFFER, D::UNIFORM_BUFFER];
        bindings.extend([D::STORAGE_BUFFER; 9]);
        bindings.push(vis);
        bindings.push(D::STORAGE_BUFFER);
        let pipeline = GraphicsPipeline::with_textures(
            ctx,
            &GraphicsPipelineDesc {
                name: NAME,
                vertex: ShaderStage {
                    name: "emit_gbuffer.vert",
                    spirv: crate::shaders::EMIT_GBUFFER_VERT,
                },
                fragment: ShaderStage {
                    name: "emit_gbuffer.frag",
                    spirv: frag,
                },
                bindings: &bindings,
                push_constant_size: 4,
                vertex_layout: None,
                color_formats: &[ALBEDO_FORMAT, NORMAL_FORMAT, PARAMS_FORMAT],
                depth_format: Some(MATERIAL_DEPTH_FORMAT),
                depth_compare: vk::CompareOp::EQUAL,
                depth_write: false,
                cull: vk::CullModeFlags::NONE,
            },
            &materials.textures,
        )?;
        Ok(Self { pipeline })
    }

    /// Records the pass: clears the GBuffer, then one draw per material. The material depth must be
    /// written (`material_depth`), the tile ranges visible to vertex shaders.
    pub fn record(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        materials: &GpuMaterials,
        fb: &FrameBuffers,
        t: &MaterialTargets,
    ) {
        timer.begin(cmd, NAME);
        let vis = fb.visbuffer_desc(cmd);
        cmd.begin_rendering(
            &t.gbuffer.attachments(),
            Some(RenderTarget {
                image: &t.material_depth,
                clear: None,
            }),
        );
        cmd.bind_graphics(&self.pipeline);
        cmd.push_graphics_descriptors(
            &self.pipeline,
            &with_geometry(
                &[
                    Desc::Uniform(&t.gbuffer.view),
                    Desc::Storage(&t.tiles),
                    Desc::Uniform(&fb.view),
                    Desc::Storage(&fb.visible),
                ],
                scene,
                &[
                    Desc::Storage(&materials.table),
                    Desc::Storage(&materials.meshes),
                    vis,
                    Desc::Storage(&t.fragment_counts),
                ],
            ),
        );
        cmd.bind_graphics_textures(&self.pipeline, &materials.textures);
        let vertices = 6 * t.tiles_x * t.tiles_y;
        for m in 0..materials.count {
            cmd.graphics_push_constants(&self.pipeline, bytemuck::bytes_of(&m));
            cmd.draw(vertices, 1);
        }
        cmd.end_rendering();
        timer.end(cmd);
    }
}
