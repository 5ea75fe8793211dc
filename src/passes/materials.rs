//! The material passes' driver: `material_classify` -> `material_depth` (raster emit only) ->
//! `emit_gbuffer` -> `shade`, with the scene's materials on the GPU ([`GpuMaterials`]) and the
//! targets for the current resolution. The material data itself (table, textures, [`ShadeMode`])
//! lives one layer down, in `crate::material`, which the passes read and never the reverse.

use glam::Vec3;

use crate::camera::Camera;
use crate::gpu::{Cmd, Context, GpuError, GpuResult, Image, Timer, vk};
use crate::material::{GpuMaterials, SceneMaterials, ShadeMode};
use crate::passes::emit_gbuffer::{EmitGbuffer, EmitPath};
use crate::passes::material_classify::{MaterialClassify, MaterialTargets};
use crate::passes::material_depth::MaterialDepth;
use crate::passes::shade::Shade;
use crate::passes::view::MaterialViewGpu;
use crate::passes::{FrameBuffers, VisPath};
use crate::scene_gpu::GpuScene;
use crate::shared::SHADE_FLAG_PIXEL_MATERIALS;

/// What the material passes write.
#[derive(Clone, Copy)]
pub enum MaterialOutput<'a> {
    /// `shade` into this image (an [`crate::passes::shade::OUTPUT_FORMAT`] storage image), or
    /// into the targets' own output.
    Shaded(Option<&'a Image>),
    /// The GBuffer (albedo, normal, params) into these images instead of `shade` (embedding: the
    /// host lights it); `emit_gbuffer` runs as compute and writes only vgeo's pixels.
    Gbuffer([&'a Image; 3]),
}

/// The material passes of a frame (`material_classify`, `material_depth`, `emit_gbuffer`, `shade`)
/// with the scene's materials on the GPU and the targets for the current resolution.
pub struct MaterialPasses {
    ctx: Context,
    /// The scene's materials on the GPU.
    pub gpu: GpuMaterials,
    classify: MaterialClassify,
    depth: MaterialDepth,
    emit: EmitGbuffer,
    shade: Shade,
    targets: Option<MaterialTargets>,
    /// Whether `emit_gbuffer` counts its fragments per material (tests).
    pub count_fragments: bool,
    /// How `emit_gbuffer` runs (compute by default).
    pub emit_path: EmitPath,
}

impl MaterialPasses {
    /// Uploads `materials` (decoding the textures) and creates the pipelines for `path`.
    pub fn new(ctx: &Context, materials: &SceneMaterials, path: VisPath) -> GpuResult<Self> {
        let gpu = GpuMaterials::new(ctx, materials)?;
        Ok(Self {
            ctx: ctx.clone(),
            classify: MaterialClassify::new(ctx, path)?,
            depth: MaterialDepth::new(ctx)?,
            emit: EmitGbuffer::new(ctx, path, &gpu)?,
            shade: Shade::new(ctx)?,
            gpu,
            targets: None,
            count_fragments: false,
            emit_path: EmitPath::default(),
        })
    }

    /// The targets of the last frame.
    pub fn targets(&self) -> Option<&MaterialTargets> {
        self.targets.as_ref()
    }

    /// Sizes the targets for `fb` and writes the view (call before recording).
    pub fn prepare(
        &mut self,
        fb: &FrameBuffers,
        camera: &Camera,
        light_dir: Vec3,
        mode: ShadeMode,
    ) -> GpuResult<()> {
        let ok = self
            .targets
            .as_ref()
            .is_some_and(|t| t.width == fb.width && t.height == fb.height);
        if !ok {
            self.targets = Some(MaterialTargets::new(
                &self.ctx,
                fb.width,
                fb.height,
                self.gpu.count,
            )?);
        }
        let view = self.view_for(fb, camera, light_dir, mode)?;
        let t = self
            .targets
            .as_mut()
            .ok_or_else(|| GpuError::Other("material targets missing".into()))?;
        t.gbuffer.view.write(0, bytemuck::bytes_of(&view))
    }

    /// The material view of a frame seen from `camera` (targets sized by
    /// [`MaterialPasses::prepare`] first); for recording several frames in one submission.
    pub fn view_for(
        &self,
        fb: &FrameBuffers,
        camera: &Camera,
        light_dir: Vec3,
        mode: ShadeMode,
    ) -> GpuResult<MaterialViewGpu> {
        let t = self
            .targets
            .as_ref()
            .ok_or_else(|| GpuError::Other("material targets missing".into()))?;
        Ok(self.view_for_targets(t, fb, camera, light_dir, mode))
    }

    /// The material view of a frame seen from `camera` drawn into `t` (a view's own targets,
    /// [`MaterialPasses::new_targets`]).
    pub fn view_for_targets(
        &self,
        t: &MaterialTargets,
        fb: &FrameBuffers,
        camera: &Camera,
        light_dir: Vec3,
        mode: ShadeMode,
    ) -> MaterialViewGpu {
        let base = t.gbuffer.view_for(camera, light_dir, mode);
        let coverage = match self.emit_path {
            EmitPath::Compute => SHADE_FLAG_PIXEL_MATERIALS,
            EmitPath::Raster => 0,
        };
        MaterialViewGpu {
            flags: base.flags | coverage,
            tiles_x: t.tiles_x,
            tiles_y: t.tiles_y,
            material_count: self.gpu.count,
            visible_capacity: fb.visible_capacity,
            count_fragments: self.count_fragments as u32,
            ..base
        }
    }

    /// Targets for a `width` x `height` view of its own (several views, embedding).
    pub fn new_targets(&self, width: u32, height: u32) -> GpuResult<MaterialTargets> {
        MaterialTargets::new(&self.ctx, width, height, self.gpu.count)
    }

    /// Records the four passes after the rasterizers (the visibility buffer and visible list must
    /// be visible to compute shaders). [`MaterialPasses::prepare`] must have run for `fb`.
    pub fn record(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
    ) -> GpuResult<()> {
        let t = self
            .targets
            .as_ref()
            .filter(|t| t.width == fb.width && t.height == fb.height)
            .ok_or_else(|| GpuError::Other("material passes not prepared for this frame".into()))?;
        self.record_with(cmd, timer, scene, fb, t, MaterialOutput::Shaded(None))
    }

    /// [`MaterialPasses::record`] into explicit targets (`t`, of `fb`'s size) and `output`.
    pub fn record_with(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
        t: &MaterialTargets,
        output: MaterialOutput<'_>,
    ) -> GpuResult<()> {
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        if t.width != fb.width || t.height != fb.height {
            return Err(GpuError::Other(
                "material targets and frame buffers differ in size".into(),
            ));
        }
        if self.count_fragments {
            cmd.fill_buffer(&t.fragment_counts, 0);
            cmd.barrier(
                (S::ALL_TRANSFER, A::TRANSFER_WRITE),
                (
                    S::FRAGMENT_SHADER | S::COMPUTE_SHADER,
                    A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE,
                ),
            );
        }
        self.classify.record(cmd, timer, scene, &self.gpu, fb, t);
        cmd.barrier(
            (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
            (
                S::VERTEX_SHADER | S::FRAGMENT_SHADER | S::COMPUTE_SHADER,
                A::SHADER_STORAGE_READ,
            ),
        );
        if let MaterialOutput::Gbuffer(images) = output {
            self.emit
                .record_compute_into(cmd, timer, scene, &self.gpu, fb, t, Some(images));
            cmd.barrier(
                (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
                (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
            );
            return Ok(());
        }
        let shaded = match output {
            MaterialOutput::Shaded(o) => o,
            MaterialOutput::Gbuffer(_) => None,
        };
        match self.emit_path {
            EmitPath::Compute => {
                self.emit
                    .record_compute(cmd, timer, scene, &self.gpu, fb, t);
                cmd.barrier(
                    (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
                    (S::COMPUTE_SHADER, A::SHADER_STORAGE_READ),
                );
            }
            EmitPath::Raster => {
                self.depth.record(cmd, timer, t);
                self.emit.record(cmd, timer, scene, &self.gpu, fb, t);
            }
        }
        let coverage = (self.emit_path == EmitPath::Compute).then_some(&t.pixel_materials);
        self.shade.record_to(
            cmd,
            timer,
            &t.gbuffer,
            shaded.unwrap_or(&t.gbuffer.output),
            coverage,
        );
        cmd.barrier(
            (
                S::COMPUTE_SHADER | S::FRAGMENT_SHADER,
                A::SHADER_STORAGE_WRITE,
            ),
            (S::ALL_TRANSFER | S::HOST, A::TRANSFER_READ | A::HOST_READ),
        );
        Ok(())
    }

    /// The output image of the last frame (RGBA8, sRGB-encoded).
    pub fn download(&self) -> GpuResult<Vec<u8>> {
        self.targets
            .as_ref()
            .ok_or_else(|| GpuError::Other("no material frame rendered".into()))?
            .gbuffer
            .output
            .download()
    }

    /// Fragments `emit_gbuffer` ran per material in the last frame (zeros unless
    /// [`MaterialPasses::count_fragments`] was on).
    pub fn fragment_counts(&self) -> GpuResult<Vec<u32>> {
        let t = self
            .targets
            .as_ref()
            .ok_or_else(|| GpuError::Other("no material frame rendered".into()))?;
        let bytes = t.fragment_counts.download()?;
        Ok(bytemuck::cast_slice::<u8, u32>(&bytes)[..self.gpu.count as usize].to_vec())
    }

    /// Per tile `[min, max]` material of the last frame (`[u32::MAX, 0]` where empty), row-major.
    pub fn tile_ranges(&self) -> GpuResult<Vec<[u32; 2]>> {
        let t = self
            .targets
            .as_ref()
            .ok_or_else(|| GpuError::Other("no material frame rendered".into()))?;
        let bytes = t.tiles.download()?;
        let n = (t.tiles_x * t.tiles_y) as usize;
        Ok(bytemuck::cast_slice::<u8, [u32; 2]>(&bytes)[..n].to_vec())
    }

    /// Global material id per pixel of the last frame (`u32::MAX` where empty).
    pub fn pixel_materials(&self) -> GpuResult<Vec<u32>> {
        let t = self
            .targets
            .as_ref()
            .ok_or_else(|| GpuError::Other("no material frame rendered".into()))?;
        let bytes = t.pixel_materials.download()?;
        let n = (t.width * t.height) as usize;
        Ok(bytemuck::cast_slice::<u8, u32>(&bytes)[..n].to_vec())
    }
}
