//! Pass `shade` (shaders_glsl/shade.comp.glsl): one directional light plus ambient from the GBuffer
//! into the output image (RGBA8, sRGB-encoded), the background where nothing was drawn; or one of
//! the GBuffer's channels (albedo, normals, materials), by the view's mode. Every path ends with it:
//! vgeo after `emit_gbuffer`, `brute` and `lod` after their forward GBuffer draws.
//!
//! Also home of [`GbufferTargets`], the GBuffer and output images every path shades from.

use crate::camera::Camera;
use crate::gpu::{
    Buffer, Cmd, ComputePipeline, Context, Desc, GpuResult, Image, MemoryKind, ShaderStage, Timer,
    vk,
};
use crate::material::ShadeMode;
use crate::passes::view::MaterialViewGpu;
use crate::render::BACKGROUND;

/// GBuffer albedo: sRGB-encoded colour, alpha 1 where covered.
pub const ALBEDO_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
/// GBuffer normal: world space, facing the camera.
pub const NORMAL_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
/// GBuffer params: metallic, roughness, material id low byte, high byte.
pub const PARAMS_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;
/// The shaded output (sRGB-encoded).
pub const OUTPUT_FORMAT: vk::Format = vk::Format::R8G8B8A8_UNORM;

/// The GBuffer, the material view and the shaded output of one resolution.
pub struct GbufferTargets {
    /// Size in pixels.
    pub width: u32,
    pub height: u32,
    /// [`MaterialViewGpu`] (host-visible, written each frame).
    pub view: Buffer,
    /// Albedo (sRGB-encoded, alpha 1 where covered), normal (world), params (metallic,
    /// roughness, material id bytes).
    pub albedo: Image,
    pub normal: Image,
    pub params: Image,
    /// The output of `shade` (RGBA8, sRGB-encoded).
    pub output: Image,
}

impl GbufferTargets {
    /// Creates the targets for `width` x `height`; `prefix` names them (`"gbuffer"`,
    /// `"brute gbuffer"`, ...).
    pub fn new(ctx: &Context, prefix: &str, width: u32, height: u32) -> GpuResult<Self> {
        let gbuf = |name: &str, format| {
            Image::new(
                ctx,
                &format!("{prefix} {name}"),
                width,
                height,
                format,
                vk::ImageUsageFlags::COLOR_ATTACHMENT
                    | vk::ImageUsageFlags::STORAGE
                    | vk::ImageUsageFlags::TRANSFER_SRC
                    | vk::ImageUsageFlags::TRANSFER_DST,
            )
        };
        Ok(Self {
            width,
            height,
            view: Buffer::new(
                ctx,
                &format!("{prefix} material view"),
                size_of::<MaterialViewGpu>() as u64,
                vk::BufferUsageFlags::UNIFORM_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
                MemoryKind::Upload,
            )?,
            albedo: gbuf("albedo", ALBEDO_FORMAT)?,
            normal: gbuf("normal", NORMAL_FORMAT)?,
            params: gbuf("params", PARAMS_FORMAT)?,
            output: Image::new(
                ctx,
                &format!("{prefix} shade output"),
                width,
                height,
                OUTPUT_FORMAT,
                vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
            )?,
        })
    }

    /// The view of a frame seen from `camera` with light towards `light_dir` (normalized here),
    /// drawn as `mode`; the material-pass fields (tiles, counts) are left 0 for the caller.
    pub fn view_for(
        &self,
        camera: &Camera,
        light_dir: glam::Vec3,
        mode: ShadeMode,
    ) -> MaterialViewGpu {
        let view_proj = camera.view_proj(self.width, self.height);
        self.view_for_matrix(&view_proj, light_dir, mode)
    }

    /// [`GbufferTargets::view_for`] with the projection given (e.g. a tile's,
    /// [`Camera::view_proj_window`]).
    pub fn view_for_matrix(
        &self,
        view_proj: &glam::Mat4,
        light_dir: glam::Vec3,
        mode: ShadeMode,
    ) -> MaterialViewGpu {
        let bg = BACKGROUND.map(|c| c.clamp(0.0, 1.0).powf(1.0 / 2.2));
        let (w, h) = (self.width, self.height);
        MaterialViewGpu {
            inv_view_proj: view_proj.inverse().to_cols_array_2d(),
            light_dir: light_dir.normalize_or_zero().extend(0.0).into(),
            background: [bg[0], bg[1], bg[2], 1.0],
            viewport: [w as f32, h as f32, 1.0 / w as f32, 1.0 / h as f32],
            mode: mode as u32,
            ..Default::default()
        }
    }

    /// The colour attachments of a pass writing this GBuffer (albedo, normal, params), cleared to 0
    /// (alpha 0: not covered).
    pub fn attachments(&self) -> [crate::gpu::RenderTarget<'_>; 3] {
        let clear = Some([0.0; 4]);
        [&self.albedo, &self.normal, &self.params]
            .map(|image| crate::gpu::RenderTarget { image, clear })
    }
}

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "shade";

/// The shading pipeline.
pub struct Shade {
    pipeline: ComputePipeline,
    /// Bound as the per-pixel materials when the GBuffer's alpha tells coverage.
    no_materials: Buffer,
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
            D::STORAGE_BUFFER,
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
            no_materials: Buffer::new(
                ctx,
                "shade no pixel materials",
                4,
                vk::BufferUsageFlags::STORAGE_BUFFER,
                MemoryKind::Gpu,
            )?,
        })
    }

    /// Records the pass (the GBuffer images move to `GENERAL`).
    pub fn record(&self, cmd: &mut Cmd, timer: &mut Timer, t: &GbufferTargets) {
        self.record_to(cmd, timer, t, &t.output, None);
    }

    /// Records the pass into `output` (an [`OUTPUT_FORMAT`] storage image of the GBuffer's size,
    /// moved to `GENERAL`): the GBuffer's own output or a host's image. `pixel_materials`:
    /// `material_classify`'s per-pixel materials when the view sets
    /// [`crate::shared::SHADE_FLAG_PIXEL_MATERIALS`] (else the albedo's alpha tells coverage).
    pub fn record_to(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        t: &GbufferTargets,
        output: &Image,
        pixel_materials: Option<&Buffer>,
    ) {
        timer.begin(cmd, NAME);
        for i in [&t.albedo, &t.normal, &t.params, output] {
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
                Desc::StorageImage(output),
                Desc::Storage(pixel_materials.unwrap_or(&self.no_materials)),
            ],
        );
        let tile = crate::shared::SHADE_TILE;
        cmd.dispatch(t.width.div_ceil(tile), t.height.div_ceil(tile), 1);
        timer.end(cmd);
    }
}
