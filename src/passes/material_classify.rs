//! Pass `material_classify` (shaders_glsl/material_classify.comp.glsl): the global material id of
//! every pixel (the material of its triangle's first vertex) and, per 64x64 tile, the range
//! `uvec2(min, max)` of the ids present (`(u32::MAX, 0)` for an empty tile), which `emit_gbuffer`'s
//! vertex shader reads to drop tiles a material does not touch.
//!
//! Also home of [`MaterialTargets`], the buffers and images the material passes share.

use crate::gpu::{
    Buffer, Cmd, ComputePipeline, Context, Desc, GpuResult, Image, MemoryKind, ShaderStage, Timer,
    vk,
};
use crate::material::GpuMaterials;
use crate::passes::shade::GbufferTargets;
use crate::passes::{FrameBuffers, VisPath};
use crate::scene_gpu::GpuScene;

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "material_classify";

/// Side of a classification tile in pixels (`MATERIAL_TILE` in GLSL).
pub const MATERIAL_TILE: u32 = 64;

/// "No material" in the per-pixel ids and the empty tile's minimum.
pub const NO_MATERIAL: u32 = u32::MAX;

/// Material depth: `(id + 1) / 2^24`, 0 where empty.
pub const MATERIAL_DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// Buffers and images of the material passes, for one resolution and material count.
pub struct MaterialTargets {
    /// Size in pixels.
    pub width: u32,
    pub height: u32,
    /// Classification tiles per row and per column.
    pub tiles_x: u32,
    pub tiles_y: u32,
    /// `uvec2(min, max)` material per tile.
    pub tiles: Buffer,
    /// Global material id per pixel ([`NO_MATERIAL`] where empty).
    pub pixel_materials: Buffer,
    /// Fragments `emit_gbuffer` ran per material (when counting is on).
    pub fragment_counts: Buffer,
    /// Material id as depth (`D32_SFLOAT`).
    pub material_depth: Image,
    /// The GBuffer, the material view and `shade`'s output.
    pub gbuffer: GbufferTargets,
}

impl MaterialTargets {
    /// Creates the targets for `width` x `height` and `material_count` materials.
    pub fn new(ctx: &Context, width: u32, height: u32, material_count: u32) -> GpuResult<Self> {
        let tiles_x = width.div_ceil(MATERIAL_TILE);
        let tiles_y = height.div_ceil(MATERIAL_TILE);
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        Ok(Self {
            width,
            height,
            tiles_x,
            tiles_y,
            tiles: Buffer::new(
                ctx,
                "material tiles",
                8 * (tiles_x * tiles_y) as u64,
                storage,
                MemoryKind::Gpu,
            )?,
            pixel_materials: Buffer::new(
                ctx,
                "pixel materials",
                4 * width as u64 * height as u64,
                storage,
                MemoryKind::Gpu,
            )?,
            fragment_counts: Buffer::new(
                ctx,
                "emit_gbuffer fragment counts",
                4 * material_count.max(1) as u64,
                storage,
                MemoryKind::Gpu,
            )?,
            material_depth: Image::new(
                ctx,
                "material depth",
                width,
                height,
                MATERIAL_DEPTH_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            )?,
            gbuffer: GbufferTargets::new(ctx, "gbuffer", width, height)?,
        })
    }
}

/// The classification pipeline for one visibility-buffer path.
pub struct MaterialClassify {
    pipeline: ComputePipeline,
}

impl MaterialClassify {
    /// Creates the pipeline for `path`.
    pub fn new(ctx: &Context, path: VisPath) -> GpuResult<Self> {
        use vk::DescriptorType as D;
        let spirv = match path {
            VisPath::Buffer => crate::shaders::MATERIAL_CLASSIFY_COMP,
            VisPath::Image => crate::shaders::MATERIAL_CLASSIFY_COMP_IMAGE,
        };
        let vis = path.descriptor_type();
        let mut bindings = vec![D::UNIFORM_BUFFER];
        bindings.extend([D::STORAGE_BUFFER; 8]);
        bindings.push(vis);
        bindings.push(D::STORAGE_BUFFER);
        bindings.push(D::UNIFORM_BUFFER);
        Ok(Self {
            pipeline: ComputePipeline::new(ctx, ShaderStage { name: NAME, spirv }, &bindings, 0)?,
        })
    }

    /// Records the pass. The visibility buffer and visible list must be visible to compute shaders.
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
        cmd.bind_compute(&self.pipeline);
        cmd.push_compute_descriptors(
            &self.pipeline,
            &[
                Desc::Uniform(&t.gbuffer.view),
                Desc::Storage(&fb.visible),
                Desc::Storage(&scene.instances),
                Desc::Storage(&scene.meshes),
                Desc::Storage(&scene.clusters),
                Desc::Storage(&scene.pages),
                Desc::Storage(&scene.pool),
                Desc::Storage(&materials.meshes),
                Desc::Storage(&t.tiles),
                vis,
                Desc::Storage(&t.pixel_materials),
                Desc::Uniform(&fb.view),
            ],
        );
        cmd.dispatch(t.tiles_x, t.tiles_y, 1);
        timer.end(cmd);
    }
}
