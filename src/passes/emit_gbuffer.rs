//! Pass `emit_gbuffer`: per material, the GBuffer of exactly that material's pixels, rebuilt from
//! the visibility buffer (shaders_glsl/common/emit.glsl). Two forms ([`EmitPath`]):
//!
//! - compute (the default, emit_gbuffer.comp.glsl): one dispatch per material over the 64x64
//!   classification tiles; tiles whose `material_classify` range excludes the material leave at
//!   once, the others shade the pixels whose per-pixel material is this one;
//! - raster (DESIGN.md's form, emit_gbuffer.vert/.frag.glsl): one draw per material of a grid of
//!   tile quads at the material's depth; the vertex shader drops the tiles outside the range, the
//!   depth test `EQUAL` against the material depth (`material_depth`) lets only that material's
//!   pixels run the fragment shader.
//!
//! With counting on, each shaded pixel adds one to its material's counter (tests compare these
//! with the pixels of each material).

use crate::gpu::{
    Cmd, ComputePipeline, Context, Desc, DescList, GeometryStage, GpuResult, GraphicsPipeline,
    GraphicsPipelineDesc, Image, RenderTarget, ShaderStage, Timer, vk,
};
use crate::material::GpuMaterials;
use crate::passes::material_classify::{MATERIAL_DEPTH_FORMAT, MaterialTargets};
use crate::passes::shade::{ALBEDO_FORMAT, NORMAL_FORMAT, PARAMS_FORMAT};
use crate::passes::{FrameBuffers, VisPath, with_geometry};
use crate::scene_gpu::GpuScene;

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "emit_gbuffer";

/// How `emit_gbuffer` runs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum EmitPath {
    /// One compute dispatch per material over the classification tiles (no material depth).
    #[default]
    Compute,
    /// One draw per material of tile quads against the material depth (depth test EQUAL).
    Raster,
}

impl EmitPath {
    /// `compute` or `raster`.
    pub fn parse(s: &str) -> Option<Self> {
        match s.to_ascii_lowercase().as_str() {
            "compute" => Some(EmitPath::Compute),
            "raster" => Some(EmitPath::Raster),
            _ => None,
        }
    }
}

/// The GBuffer pipelines (made for one material table's texture array and visibility-buffer path).
pub struct EmitGbuffer {
    pipeline: GraphicsPipeline,
    compute: ComputePipeline,
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
        bindings.extend([D::STORAGE_BUFFER; 8]);
        bindings.push(vis);
        bindings.push(D::STORAGE_BUFFER);
        let pipeline = GraphicsPipeline::with_textures(
            ctx,
            &GraphicsPipelineDesc {
                name: NAME,
                geometry: GeometryStage::Vertex(ShaderStage {
                    name: "emit_gbuffer.vert",
                    spirv: crate::shaders::EMIT_GBUFFER_VERT,
                }),
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
        let comp = match path {
            VisPath::Buffer => crate::shaders::EMIT_GBUFFER_COMP,
            VisPath::Image => crate::shaders::EMIT_GBUFFER_COMP_IMAGE,
        };
        bindings.extend([
            D::STORAGE_BUFFER,
            D::STORAGE_IMAGE,
            D::STORAGE_IMAGE,
            D::STORAGE_IMAGE,
        ]);
        let compute = ComputePipeline::with_textures(
            ctx,
            ShaderStage {
                name: NAME,
                spirv: comp,
            },
            &bindings,
            4,
            &materials.textures,
        )?;
        Ok(Self { pipeline, compute })
    }

    /// Records the compute form: one dispatch per material, writing the covered pixels only (no
    /// clear: `shade` tells coverage by the per-pixel materials). `material_classify`'s tiles and per-pixel materials must be visible
    /// to compute shaders.
    pub fn record_compute(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        materials: &GpuMaterials,
        fb: &FrameBuffers,
        t: &MaterialTargets,
    ) {
        self.record_compute_into(cmd, timer, scene, materials, fb, t, None);
    }

    /// [`EmitGbuffer::record_compute`] into `out` (albedo, normal, params: a host's GBuffer in the
    /// formats of [`crate::passes::shade`], storage images of the frame's size) when given; either
    /// way only pixels vgeo's geometry covers are written (a host's own pixels stay).
    #[allow(clippy::too_many_arguments)]
    pub fn record_compute_into(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        materials: &GpuMaterials,
        fb: &FrameBuffers,
        t: &MaterialTargets,
        out: Option<[&Image; 3]>,
    ) {
        timer.begin(cmd, NAME);
        let g = &t.gbuffer;
        let [albedo, normal, params] = match out {
            Some(images) => {
                for i in images {
                    cmd.to_general(i);
                }
                images
            }
            // No clear: `shade` tells covered pixels by the per-pixel materials
            // (SHADE_FLAG_PIXEL_MATERIALS), and this pass writes every one of them.
            None => {
                for i in [&g.albedo, &g.normal, &g.params] {
                    cmd.to_general(i);
                }
                [&g.albedo, &g.normal, &g.params]
            }
        };
        let vis = fb.visbuffer_desc(cmd);
        cmd.bind_compute(&self.compute);
        let mut descs = descriptors(scene, materials, fb, t, vis);
        descs.extend([
            Desc::Storage(&t.pixel_materials),
            Desc::StorageImage(albedo),
            Desc::StorageImage(normal),
            Desc::StorageImage(params),
        ]);
        cmd.push_compute_descriptors(&self.compute, &descs);
        cmd.bind_compute_textures(&self.compute, &materials.textures);
        for m in 0..materials.count {
            cmd.compute_push_constants(&self.compute, bytemuck::bytes_of(&m));
            cmd.dispatch(t.tiles_x, t.tiles_y, 1);
        }
        timer.end(cmd);
    }

    /// Records the raster form: clears the GBuffer, then one draw per material. The material depth must be
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
        cmd.push_graphics_descriptors(&self.pipeline, &descriptors(scene, materials, fb, t, vis));
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

/// The descriptors both forms bind (bindings 0-12; the compute form appends 13-16).
fn descriptors<'a>(
    scene: &'a GpuScene,
    materials: &'a GpuMaterials,
    fb: &'a FrameBuffers,
    t: &'a MaterialTargets,
    vis: Desc<'a>,
) -> DescList<'a> {
    with_geometry(
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
    )
}
