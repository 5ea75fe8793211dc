//! Pass `debug_view`: the visibility buffer made visible (shaders_glsl/debug_view.comp.glsl), into
//! an `R8G8B8A8_UNORM` storage image owned by the pass. Two dispatches: `mark` flags every visible
//! entry that is in the HW list (for [`ViewMode::HwSw`]), then one thread per pixel colours it by
//! [`ViewMode`]; empty pixels get [`crate::render::BACKGROUND`].

use glam::Vec3;

use crate::gpu::{
    Buffer, Cmd, ComputePipeline, Context, Desc, GpuError, GpuResult, Image, MemoryKind,
    ShaderStage, Timer, vk,
};
use crate::passes::cull::Phase;
use crate::passes::{FrameBuffers, VisPath, with_geometry};
use crate::render::BACKGROUND;
use crate::scene_gpu::GpuScene;
use crate::shared::TILE_WORKGROUP_SIZE;

/// The pass's name: debug label, timer scope and pipeline name.
pub const NAME: &str = "debug_view";

/// What the debug view shows per pixel.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ViewMode {
    /// Lambert shading of the interpolated vertex normal with the instance colour, no materials
    /// (a cheap check of the geometry alone).
    Lambert,
    /// Distance on a log scale: darker per stop (doubling) from the near plane, hue bands per
    /// quarter stop.
    Depth,
    /// A hashed colour per (visible cluster, triangle).
    Triangles,
    /// A hashed colour per (instance, cluster).
    Clusters,
    /// A hashed colour per instance.
    Instances,
    /// A colour per DAG level of the cluster (0 = finest, blue).
    Lod,
    /// Orange for clusters drawn by `raster_hw`, blue for `raster_sw`.
    HwSw,
    /// A colour per (instance, DAG group) of the pixel's cluster (the group it is a member of,
    /// [`crate::builder::Cluster::group`]): hue from the golden-ratio sequence over the group index
    /// (offset per instance), saturation and brightness from a hash, so neighbouring groups differ.
    Groups,
    /// How many times each pixel was written by the rasterizers (`raster_sw`: each covered pixel
    /// of a triangle; `raster_hw`: each fragment), both culling phases together, as a heat ramp
    /// interpolated on log2 of the count: 0 background, 1 dark blue, 2 light blue, 4 green,
    /// 8 red, 16 and more white. The frame counts only for this view
    /// ([`VIEW_FLAG_COUNT_OVERDRAW`](crate::shared::VIEW_FLAG_COUNT_OVERDRAW)).
    Overdraw,
    /// The fallback mesh: the complete DAG level whose triangle count is nearest the builder's
    /// fallback target (2,000 triangles; [`crate::builder::BuiltMesh::fallback_level`]), what a
    /// renderer without virtualized geometry would draw. The frame draws that level instead of the
    /// LOD cut ([`crate::shared::VIEW_FLAG_FALLBACK_CUT`]), Lambert shaded like
    /// [`ViewMode::Lambert`], tinted per cluster with dark cluster borders.
    Fallback,
    /// The image: materials (base colour, textures, normal maps, metallic/roughness) lit by the
    /// directional light plus ambient (`material_classify` -> `material_depth` -> `emit_gbuffer`
    /// -> `shade`; not drawn by this pass). `brute` and `lod` shade the same way.
    Lit,
    /// The GBuffer's albedo (material passes).
    Albedo,
    /// The GBuffer's world normal as colour (material passes).
    Normals,
    /// A hashed colour per material (material passes).
    Materials,
    /// Streaming: per drawn cluster, the state of the pages of the group it would refine into
    /// (the group that produced it, [`crate::builder::Cluster::creator`]), as flat colours
    /// ([`crate::shared::RESIDENCY_COLOR_RESIDENT`] and the others): resident (green: those pages
    /// are resident, or the cluster is a leaf, or its mesh is wholly resident), not needed (dark
    /// green: absent, but the cluster is fine at this threshold and nothing asked for them),
    /// requested (amber: absent and fine here, but the cull asked for one of them this frame, for
    /// another instance), wanted but missing (red: the cut would refine the cluster at this
    /// threshold but those pages are absent; the cull asked for them). Without streaming every
    /// covered pixel reads resident.
    Residency,
}

impl ViewMode {
    /// Every mode.
    pub const ALL: [ViewMode; 11] = [
        ViewMode::Lambert,
        ViewMode::Depth,
        ViewMode::Triangles,
        ViewMode::Clusters,
        ViewMode::Instances,
        ViewMode::Lod,
        ViewMode::HwSw,
        ViewMode::Groups,
        ViewMode::Overdraw,
        ViewMode::Fallback,
        ViewMode::Residency,
    ];

    /// The modes drawn by the material passes instead of this one.
    pub const MATERIAL: [ViewMode; 4] = [
        ViewMode::Lit,
        ViewMode::Albedo,
        ViewMode::Normals,
        ViewMode::Materials,
    ];

    /// What `shade` draws for a material-pass mode (`None` for the debug views).
    pub fn shade_mode(self) -> Option<crate::material::ShadeMode> {
        use crate::material::ShadeMode;
        match self {
            ViewMode::Lit => Some(ShadeMode::Lit),
            ViewMode::Albedo => Some(ShadeMode::Albedo),
            ViewMode::Normals => Some(ShadeMode::Normals),
            ViewMode::Materials => Some(ShadeMode::Materials),
            _ => None,
        }
    }

    /// Whether the material passes draw this mode (see [`ViewMode::MATERIAL`]).
    pub fn is_material(self) -> bool {
        ViewMode::MATERIAL.contains(&self)
    }

    /// The mode's name on the command line (`lambert`, `depth`, `triangles`, `clusters`, `instances`,
    /// `lod`, `hwsw`, `groups`, `overdraw`, `fallback`, `residency`, `lit`, `albedo`, `normals`,
    /// `materials`).
    pub fn name(self) -> &'static str {
        match self {
            ViewMode::Lambert => "lambert",
            ViewMode::Depth => "depth",
            ViewMode::Triangles => "triangles",
            ViewMode::Clusters => "clusters",
            ViewMode::Instances => "instances",
            ViewMode::Lod => "lod",
            ViewMode::HwSw => "hwsw",
            ViewMode::Groups => "groups",
            ViewMode::Overdraw => "overdraw",
            ViewMode::Fallback => "fallback",
            ViewMode::Residency => "residency",
            ViewMode::Lit => "lit",
            ViewMode::Albedo => "albedo",
            ViewMode::Normals => "normals",
            ViewMode::Materials => "materials",
        }
    }

    /// Parses [`ViewMode::name`] (also accepts `hw-sw`, `level`, and `shaded` for `lit`).
    pub fn parse(s: &str) -> Option<Self> {
        let s = s.to_ascii_lowercase();
        match s.as_str() {
            "hw-sw" | "hw_sw" => Some(ViewMode::HwSw),
            "level" => Some(ViewMode::Lod),
            "shaded" => Some(ViewMode::Lit),
            _ => ViewMode::ALL
                .into_iter()
                .chain(ViewMode::MATERIAL)
                .find(|m| m.name() == s),
        }
    }

    fn code(self) -> u32 {
        match self {
            ViewMode::Lambert => 0,
            ViewMode::Depth => 1,
            ViewMode::Triangles => 2,
            ViewMode::Clusters => 3,
            ViewMode::Instances => 4,
            ViewMode::Lod => 5,
            ViewMode::HwSw => 6,
            ViewMode::Groups => 7,
            ViewMode::Overdraw => 8,
            ViewMode::Fallback => 9,
            ViewMode::Residency => 10,
            // Drawn by the material passes; `record` refuses them.
            ViewMode::Lit | ViewMode::Albedo | ViewMode::Normals | ViewMode::Materials => 0,
        }
    }
}

/// Push constants of the colouring dispatch (mirrors `Push` in debug_view.comp.glsl).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct DebugViewPush {
    background: [f32; 4],
    light_dir: [f32; 4],
    mode: u32,
    visible_capacity: u32,
    _pad: [u32; 2],
}
const _: () = assert!(size_of::<DebugViewPush>() == 48);

/// Threads per workgroup of the `mark` dispatch (`local_size_x` of its shader).
const MARK_WORKGROUP_SIZE: u32 = 64;

/// The debug view: pipelines, the HW flag per visible entry and the output image.
pub struct DebugView {
    mark: ComputePipeline,
    view: ComputePipeline,
    hw_flags: Buffer,
    /// Bound as the overdraw counter for the other views.
    no_overdraw: Buffer,
    image: Image,
    visible_capacity: u32,
    path: VisPath,
}

impl DebugView {
    /// Creates the pass for `fb`'s size, visible-list capacity and visibility-buffer path.
    pub fn new(ctx: &Context, fb: &FrameBuffers) -> GpuResult<Self> {
        use vk::DescriptorType as D;
        let path = fb.vis_path();
        let spirv = match path {
            VisPath::Buffer => crate::shaders::DEBUG_VIEW_COMP,
            VisPath::Image => crate::shaders::DEBUG_VIEW_COMP_IMAGE,
        };
        let vis = path.descriptor_type();
        let mut bindings = vec![D::UNIFORM_BUFFER];
        bindings.extend([D::STORAGE_BUFFER; 7]);
        bindings.push(D::STORAGE_IMAGE);
        bindings.push(vis);
        // Overdraw counters; groups and page requests (the residency view).
        bindings.extend([D::STORAGE_BUFFER; 3]);
        let view = ComputePipeline::new(
            ctx,
            ShaderStage { name: NAME, spirv },
            &bindings,
            size_of::<DebugViewPush>() as u32,
        )?;
        let mark = ComputePipeline::new(
            ctx,
            ShaderStage {
                name: "debug_view mark",
                spirv: crate::shaders::DEBUG_VIEW_COMP_MARK,
            },
            &[D::STORAGE_BUFFER; 3],
            4,
        )?;
        let hw_flags = Buffer::new(
            ctx,
            "debug_view hw flags",
            4 * fb.visible_capacity.max(1) as u64,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryKind::Gpu,
        )?;
        let image = Image::new(
            ctx,
            "debug_view",
            fb.width,
            fb.height,
            vk::Format::R8G8B8A8_UNORM,
            vk::ImageUsageFlags::STORAGE | vk::ImageUsageFlags::TRANSFER_SRC,
        )?;
        let no_overdraw = crate::passes::raster_sw::overdraw_placeholder(ctx, NAME)?;
        Ok(Self {
            mark,
            view,
            hw_flags,
            no_overdraw,
            image,
            visible_capacity: fb.visible_capacity,
            path,
        })
    }

    /// The output image (`R8G8B8A8_UNORM`, sRGB-encoded values; `GENERAL` layout after the pass).
    pub fn image(&self) -> &Image {
        &self.image
    }

    /// Reads the output image back: RGBA8, row-major, top row first.
    pub fn download(&self) -> GpuResult<Vec<u8>> {
        self.image.download()
    }

    /// Records the pass: colours every pixel of `fb.visbuffer` by `mode`; `light_dir` points towards
    /// the light (world space) for [`ViewMode::Lambert`] and [`ViewMode::Fallback`]. The visibility
    /// buffer, lists and counters must be visible to compute shaders (the frame records that
    /// barrier). [`ViewMode::Overdraw`] needs the counters: use [`DebugView::record_with_overdraw`].
    pub fn record(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
        mode: ViewMode,
        light_dir: Vec3,
    ) -> GpuResult<()> {
        self.record_with_overdraw(cmd, timer, scene, fb, mode, light_dir, None)
    }

    /// [`DebugView::record`] with the overdraw counter buffer (`fb.width * fb.height` u32, filled
    /// by the rasterizers' `record_counting`), which [`ViewMode::Overdraw`] requires and the other
    /// modes ignore.
    #[allow(clippy::too_many_arguments)]
    pub fn record_with_overdraw(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        scene: &GpuScene,
        fb: &FrameBuffers,
        mode: ViewMode,
        light_dir: Vec3,
        overdraw: Option<&Buffer>,
    ) -> GpuResult<()> {
        if fb.vis_path() != self.path
            || fb.width != self.image.width
            || fb.height != self.image.height
            || fb.visible_capacity != self.visible_capacity
        {
            return Err(GpuError::Other(format!(
                "{NAME}: created for {}x{} {:?} (visible capacity {}), used with {}x{} {:?} ({})",
                self.image.width,
                self.image.height,
                self.path,
                self.visible_capacity,
                fb.width,
                fb.height,
                fb.vis_path(),
                fb.visible_capacity
            )));
        }
        let pixels = fb.width as u64 * fb.height as u64 * 4;
        let overdraw = match (mode, overdraw) {
            (ViewMode::Overdraw, Some(b)) if b.size() >= pixels => b,
            (ViewMode::Overdraw, _) => {
                return Err(GpuError::Other(format!(
                    "{NAME}: view `overdraw` needs the overdraw counter buffer of {}x{} u32",
                    fb.width, fb.height
                )));
            }
            _ => &self.no_overdraw,
        };
        if mode.is_material() {
            return Err(GpuError::Other(format!(
                "{NAME}: view `{}` is drawn by the material passes",
                mode.name()
            )));
        }
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        timer.begin(cmd, NAME);
        // Step 1: flag the HW list's entries.
        cmd.fill_buffer(&self.hw_flags, 0);
        cmd.barrier(
            (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            (
                S::COMPUTE_SHADER,
                A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE,
            ),
        );
        cmd.bind_compute(&self.mark);
        // Both phases of the two-pass occlusion culling have an HW list.
        for phase in [Phase::Main, Phase::Post] {
            let (counters, _, hw_list) = fb.phase_lists(phase);
            cmd.push_compute_descriptors(
                &self.mark,
                &[
                    Desc::Storage(counters),
                    Desc::Storage(hw_list),
                    Desc::Storage(&self.hw_flags),
                ],
            );
            cmd.compute_push_constants(&self.mark, bytemuck::bytes_of(&self.visible_capacity));
            let mark_groups = self
                .visible_capacity
                .div_ceil(MARK_WORKGROUP_SIZE)
                .clamp(1, 1024);
            cmd.dispatch(mark_groups, 1, 1);
        }
        cmd.barrier(
            (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
            (S::COMPUTE_SHADER, A::SHADER_STORAGE_READ),
        );
        // Step 2: colour the pixels.
        cmd.to_general(&self.image);
        let vis = fb.visbuffer_desc(cmd);
        let bg = BACKGROUND.map(|c| c.clamp(0.0, 1.0).powf(1.0 / 2.2));
        let push = DebugViewPush {
            background: [bg[0], bg[1], bg[2], 1.0],
            light_dir: light_dir.normalize_or_zero().extend(0.0).into(),
            mode: mode.code(),
            visible_capacity: self.visible_capacity,
            _pad: [0; 2],
        };
        cmd.bind_compute(&self.view);
        cmd.push_compute_descriptors(
            &self.view,
            &with_geometry(
                &[
                    Desc::Uniform(&fb.view),
                    Desc::Storage(&fb.visible),
                    Desc::Storage(&self.hw_flags),
                ],
                scene,
                &[
                    Desc::StorageImage(&self.image),
                    vis,
                    Desc::Storage(overdraw),
                    Desc::Storage(&scene.groups),
                    Desc::Storage(&scene.page_requests),
                ],
            ),
        );
        cmd.compute_push_constants(&self.view, bytemuck::bytes_of(&push));
        cmd.dispatch(
            fb.width.div_ceil(TILE_WORKGROUP_SIZE),
            fb.height.div_ceil(TILE_WORKGROUP_SIZE),
            1,
        );
        timer.end(cmd);
        Ok(())
    }
}
