//! One vgeo frame: orders the passes, owns the per-frame buffers, reads back results and stats.
//!
//! `instance_cull` -> `cluster_cull` -> `raster_sw` + `raster_hw` -> `debug_view` (or, for the
//! material views, `material_classify` -> `material_depth` -> `emit_gbuffer` -> `shade`). The CPU records a
//! fixed command buffer: nothing in it depends on the number of instances or clusters, the counts
//! live on the GPU and reach the rasterizers through indirect arguments.

use std::borrow::Borrow;

mod embed;
pub mod split;
pub use embed::{
    DEFAULT_FRAMES_IN_FLIGHT, FrameStats, HOST_COLOR_FORMAT, HOST_DEPTH_FORMAT,
    HOST_GBUFFER_FORMATS, HostTargets, View, ViewFrame,
};
use split::SplitTuner;

use crate::builder::BuiltMesh;
use crate::camera::Camera;
use crate::gpu::{Buffer, Cmd, Context, GpuError, GpuResult, Image, Timer, vk};
use crate::material::SceneMaterials;
use crate::passes::cluster_cull::{ClusterCull, default_workgroups};
use crate::passes::cull::Phase;
use crate::passes::debug_view::{DebugView, ViewMode};
use crate::passes::depth_export::DepthExport;
use crate::passes::depth_import::{DepthImport, HostDepthBuffer};
use crate::passes::depth_pyramid::DepthPyramid;
use crate::passes::emit_gbuffer::EmitPath;
use crate::passes::instance_cull::InstanceCull;
use crate::passes::material_classify::MaterialTargets;
use crate::passes::materials::{MaterialOutput, MaterialPasses};
use crate::passes::occluder_select::OccluderSelect;
use crate::passes::raster_hw::{HwPath, RasterHw};
use crate::passes::raster_sw::RasterSw;
use crate::passes::view::{FrameSettings, MaterialViewGpu, view_gpu};
use crate::passes::{FrameBuffers, VisPath, visbuffer};
use crate::render::{Frame, Light, Placement};
use crate::scene_gpu::{GpuScene, PoolWords};
use crate::shared::{
    CullCounters, HW_ENTRY_CULL, HW_ENTRY_MIRRORED, MESH_MAX_CLUSTERS, OcclusionGpu,
    VIEW_FLAG_COLD_FRAME, VIEW_FLAG_COUNT_OVERDRAW, VIEW_FLAG_CULL_STATS, VIEW_FLAG_DIRECT_VISIBLE,
    VIEW_FLAG_HW_MESH, ViewGpu,
};

/// Largest visible-cluster list: the visibility buffer's cluster field has 25 bits, and its
/// largest value belongs to the host's pixels ([`crate::shared::VISBUFFER_HOST`]).
pub const MAX_VISIBLE: u32 = (1 << crate::shared::VISBUFFER_CLUSTER_BITS) - 1;
/// Largest cull work queue (items of 8 bytes).
pub const MAX_QUEUE: u32 = 1 << 25;

/// Culling results read back from the GPU.
#[derive(Clone, Debug)]
pub struct CullResult {
    /// Counters the culling passes wrote.
    pub counters: CullCounters,
    /// `(instance, global cluster)` of every drawn cluster, in the order of the lists: the SW list's
    /// front, then its small end (`CullCounters::sw_small_count`), then the HW list's end (the
    /// smallest SW clusters, `sw_quarter_count`), then the HW list, each in the GPU's
    /// (unspecified) order.
    pub visible: Vec<[u32; 2]>,
    /// Visible-list indices per rasterizer.
    pub sw: Vec<u32>,
    /// Visible-list indices the hardware rasterizer drew.
    pub hw: Vec<u32>,
    /// Of those, how many it drew without the faces turned away (a closed solid seen from
    /// outside: `HW_ENTRY_CULL`).
    pub hw_cull_back: usize,
    /// GPU milliseconds per pass of the culling run.
    pub gpu_ms: Vec<(String, f64)>,
}

impl CullResult {
    /// Fails when a capacity overflowed or the watchdog tripped: results would be incomplete.
    pub fn check(&self) -> Result<(), String> {
        let c = &self.counters;
        if c.watchdog != 0 {
            return Err(format!(
                "cluster_cull watchdog tripped (code {}): the work queue did not drain",
                c.watchdog
            ));
        }
        if c.queue_overflow != 0 {
            return Err(format!(
                "cull work queue overflowed: {} items dropped",
                c.queue_overflow
            ));
        }
        if c.visible_overflow != 0 {
            return Err(format!(
                "visible-cluster list overflowed: {} clusters dropped",
                c.visible_overflow
            ));
        }
        if c.hw_overflow != 0 {
            return Err(format!(
                "raster_hw's mesh path draws at most {MESH_MAX_CLUSTERS} clusters per phase: {} \
                 dropped (--hw-path vertex has no such limit)",
                c.hw_overflow
            ));
        }
        Ok(())
    }
}

/// The vgeo renderer: the scene on the GPU, the pass pipelines and the frame buffers.
pub struct VgeoRenderer {
    ctx: Context,
    /// The scene on the GPU: add, move and remove meshes and instances here between frames.
    pub scene: GpuScene,
    instance_cull: InstanceCull,
    occluder_select: OccluderSelect,
    cluster_cull: ClusterCull,
    raster_sw: RasterSw,
    raster_hw: RasterHw,
    depth_import: DepthImport,
    depth_export: DepthExport,
    fb: Option<FrameBuffers>,
    pyramid: Option<DepthPyramid>,
    debug_view: Option<DebugView>,
    /// Per-pixel overdraw counters (u32, the frame's size), allocated by the first frame that
    /// counts ([`ViewMode::Overdraw`] or [`VIEW_FLAG_COUNT_OVERDRAW`]).
    overdraw: Option<Buffer>,
    /// The scene's materials (CPU) and, once a material view was rendered, the material passes.
    scene_materials: SceneMaterials,
    materials: Option<MaterialPasses>,
    /// Whether `emit_gbuffer` counts fragments per material (tests).
    count_fragments: bool,
    emit_path: EmitPath,
    /// The view whose HZB is in the pyramid (the previous frame's), if any.
    history: Option<OcclusionGpu>,
    vis_path: VisPath,
    queue_capacity: u32,
    visible_capacity: u32,
    /// Set by [`VgeoRenderer::set_capacities`]: the capacities no longer follow the scene.
    fixed_capacities: bool,
    /// The scene's mesh epoch the materials were built for.
    materials_epoch: u64,
    /// Host frames since the scene retired buffers (freed once no frame in flight uses them).
    retire_age: u32,
    /// The automatic SW/HW split of [`VgeoRenderer::render`]'s frames ([`split`]).
    split: SplitTuner,
    /// Set by [`VgeoRenderer::force_streaming_cull`]: the culls take their streaming pipelines in
    /// every frame, not only in frames with a partial mesh.
    force_streaming_cull: bool,
}

impl VgeoRenderer {
    /// Uploads the scene and creates the pipelines.
    /// `built` may hold the meshes or references to them (anything that borrows as one).
    pub fn new<B: Borrow<BuiltMesh>>(
        ctx: &Context,
        built: &[B],
        placements: &[Placement],
    ) -> GpuResult<Self> {
        let vis_path = VisPath::choose(ctx).map_err(GpuError::Other)?;
        Self::with_path(ctx, built, placements, vis_path)
    }

    /// A renderer whose meshes stream under `opts`' budget: the meshes are added with only their
    /// always-resident pages by a [`crate::Streamer`] (which serves the rest on the cull's
    /// requests, [`crate::Streamer::update`] between frames), then the instances of
    /// `placements` (whose `mesh` indexes `meshes`). What `vgeo render` and `vgeo bench` do
    /// under `--geometry-budget`.
    pub fn streamed(
        ctx: &Context,
        meshes: Vec<(BuiltMesh, Box<dyn crate::streaming::PageSource>)>,
        placements: &[Placement],
        opts: crate::streaming::StreamOptions,
    ) -> GpuResult<(Self, crate::streaming::Streamer)> {
        if let Some(p) = placements.iter().find(|p| p.mesh as usize >= meshes.len()) {
            return Err(GpuError::Other(format!(
                "placement refers to mesh {} of {}",
                p.mesh,
                meshes.len()
            )));
        }
        let mut r = Self::new(ctx, &[] as &[BuiltMesh], &[])?;
        let (streamer, handles) = crate::streaming::Streamer::new(&mut r.scene, meshes, opts)?;
        r.scene
            .add_instances(&crate::scene_gpu::InstanceDesc::placed(
                placements, &handles,
            ))?;
        Ok((r, streamer))
    }

    /// Like [`VgeoRenderer::new`] with an explicit visibility-buffer path (the image path needs
    /// `VK_EXT_shader_image_atomic_int64`).
    pub fn with_path<B: Borrow<BuiltMesh>>(
        ctx: &Context,
        built: &[B],
        placements: &[Placement],
        vis_path: VisPath,
    ) -> GpuResult<Self> {
        if vis_path == VisPath::Image && !ctx.caps().image_int64_atomics {
            return Err(GpuError::Other(
                "the image visibility-buffer path needs VK_EXT_shader_image_atomic_int64".into(),
            ));
        }
        let scene = GpuScene::new(ctx, built, placements)?;
        let scene_materials = scene.materials().map_err(GpuError::Other)?;
        let (queue_capacity, visible_capacity) = scene_capacities(&scene);
        Ok(Self {
            ctx: ctx.clone(),
            instance_cull: InstanceCull::new(ctx)?,
            occluder_select: OccluderSelect::new(ctx)?,
            cluster_cull: ClusterCull::new(ctx, default_workgroups(ctx.caps()))?,
            raster_sw: RasterSw::new(ctx, vis_path)?,
            raster_hw: RasterHw::new(ctx, vis_path, HwPath::Auto)?,
            depth_import: DepthImport::new(ctx, vis_path)?,
            depth_export: DepthExport::new(ctx, vis_path)?,
            fb: None,
            pyramid: None,
            debug_view: None,
            overdraw: None,
            scene_materials,
            materials: None,
            count_fragments: false,
            emit_path: EmitPath::default(),
            history: None,
            vis_path,
            queue_capacity,
            visible_capacity,
            fixed_capacities: false,
            materials_epoch: scene.mesh_epoch(),
            retire_age: 0,
            split: SplitTuner::new(),
            force_streaming_cull: false,
            scene,
        })
    }

    /// Overrides the capacities of the cull work queue and the visible-cluster list (defaults: what
    /// the scene can need at most). Smaller ones save memory; an overflow is counted and reported
    /// by [`VgeoFrame::check`], never silent.
    pub fn set_capacities(&mut self, queue: u32, visible: u32) {
        self.queue_capacity = queue.clamp(1, MAX_QUEUE);
        self.visible_capacity = visible.clamp(1, MAX_VISIBLE);
        self.fixed_capacities = true;
        self.fb = None;
    }

    /// Follows the scene's changes before a frame: rebuilds the material table when meshes came
    /// or went (the material passes are re-created at the next material view), and grows the
    /// capacities (doubling, unless fixed by [`VgeoRenderer::set_capacities`]) and the per-instance
    /// frame buffers when the scene outgrew them. O(1) when nothing structural changed.
    pub(crate) fn follow_scene(&mut self) -> GpuResult<()> {
        if self.scene.mesh_epoch() != self.materials_epoch {
            self.scene_materials = self.scene.materials().map_err(GpuError::Other)?;
            self.materials = None;
            self.materials_epoch = self.scene.mesh_epoch();
        }
        if !self.fixed_capacities {
            let (queue, visible) = scene_capacities(&self.scene);
            if queue > self.queue_capacity {
                self.queue_capacity = queue
                    .max(self.queue_capacity.saturating_mul(2))
                    .min(MAX_QUEUE);
                self.fb = None;
            }
            if visible > self.visible_capacity {
                self.visible_capacity = visible
                    .max(self.visible_capacity.saturating_mul(2))
                    .min(MAX_VISIBLE);
                self.fb = None;
            }
        }
        let instances = 4 * self.scene.instance_capacity().max(1) as u64;
        if self
            .fb
            .as_ref()
            .is_some_and(|fb| fb.post_instances.size() < instances)
        {
            self.fb = None;
        }
        Ok(())
    }

    /// The capacities of the cull work queue and the visible list in use.
    pub fn capacities(&self) -> (u32, u32) {
        (self.queue_capacity, self.visible_capacity)
    }

    /// Replaces the number of persistent `cluster_cull` workgroups.
    pub fn set_cull_workgroups(&mut self, n: u32) -> GpuResult<()> {
        self.cluster_cull = ClusterCull::new(&self.ctx, n)?;
        Ok(())
    }

    /// Makes `instance_cull` take its `shared` variant (`Some(true)`), its plain one
    /// (`Some(false)`) or choose by the view's instances (`None`, the default:
    /// [`crate::passes::instance_cull::shares_runs`]). For tests: both draw the same cut.
    pub fn set_shared_runs(&mut self, force: Option<bool>) {
        self.instance_cull.force_shared = force;
    }

    /// Makes the culls take their pipelines with the partial-residency code in every frame
    /// (`true`), or only in frames in which some mesh is partial (`false`, the default:
    /// [`VgeoRenderer::streaming_cull`]). For tests: both draw the same cut of an all-resident
    /// frame.
    pub fn force_streaming_cull(&mut self, on: bool) {
        self.force_streaming_cull = on;
    }

    /// Whether the next frame's culls take their pipelines with the partial-residency code
    /// ([`crate::passes::cull::CullPipelines`]): when some mesh of the scene may be partial on the
    /// GPU ([`GpuScene::may_be_partial`]) or [`VgeoRenderer::force_streaming_cull`] is on.
    pub fn streaming_cull(&self) -> bool {
        self.force_streaming_cull || self.scene.may_be_partial()
    }

    /// Caps `instance_cull`'s workgroups at `max` in both phases, dispatched by the instance
    /// count (`None`: the main phase a thread per instance, the post phase a thread per deferred
    /// item). For tests: its grid-stride loop then gives each workgroup several rounds of items.
    pub fn set_instance_cull_workgroups(&mut self, max: Option<u32>) {
        self.instance_cull.max_workgroups = max;
    }

    /// The scene's material table (global ids: each mesh's ids offset by the mesh slots before it),
    /// as of construction or the last frame (mesh changes rebuild it before the next frame).
    pub fn scene_materials(&self) -> &SceneMaterials {
        &self.scene_materials
    }

    /// The material passes, once a material view ([`ViewMode::is_material`]) was rendered.
    pub fn material_passes(&self) -> Option<&MaterialPasses> {
        self.materials.as_ref()
    }

    /// Makes `emit_gbuffer` count its fragments per material (read with
    /// [`MaterialPasses::fragment_counts`]).
    pub fn set_count_fragments(&mut self, on: bool) {
        self.count_fragments = on;
        if let Some(m) = self.materials.as_mut() {
            m.count_fragments = on;
        }
    }

    /// Chooses how `emit_gbuffer` runs (compute by default; raster is DESIGN.md's tile-quad form).
    pub fn set_emit_path(&mut self, path: EmitPath) {
        self.emit_path = path;
        if let Some(m) = self.materials.as_mut() {
            m.emit_path = path;
        }
    }

    /// Uploads the materials (decoding the textures) and creates the material passes, if not yet
    /// done; returns the texture warnings (unreadable files, drawn white).
    pub fn prepare_materials(&mut self) -> GpuResult<Vec<String>> {
        if self.materials.is_none() {
            let mut m = MaterialPasses::new(&self.ctx, &self.scene_materials, self.vis_path)?;
            m.count_fragments = self.count_fragments;
            m.emit_path = self.emit_path;
            self.materials = Some(m);
        }
        Ok(self
            .materials
            .as_ref()
            .map(|m| m.gpu.warnings.clone())
            .unwrap_or_default())
    }

    /// The visibility-buffer path in use.
    pub fn vis_path(&self) -> VisPath {
        self.vis_path
    }

    /// Chooses how `raster_hw` draws (`--hw-path`; [`HwPath::Auto`] at creation: vertex
    /// pulling, measured the faster). [`HwPath::Mesh`] on a device without `VK_EXT_mesh_shader` is
    /// an error (the renderer keeps its path).
    pub fn set_hw_path(&mut self, path: HwPath) -> GpuResult<()> {
        let resolved = path.resolve(self.ctx.caps()).map_err(GpuError::Other)?;
        if resolved != self.raster_hw.hw_path() {
            self.raster_hw = RasterHw::new(&self.ctx, self.vis_path, resolved)?;
        }
        Ok(())
    }

    /// The path `raster_hw` draws with: [`HwPath::Mesh`] or [`HwPath::Vertex`].
    pub fn hw_path(&self) -> HwPath {
        self.raster_hw.hw_path()
    }

    /// A view's frame buffers (debug names prefixed with `view`, none for vgeo's own) and HZB at
    /// the renderer's capacities and the scene's instance capacity.
    pub(crate) fn view_buffers(
        &self,
        view: &str,
        width: u32,
        height: u32,
    ) -> GpuResult<(FrameBuffers, DepthPyramid)> {
        let fb = FrameBuffers::named(
            &self.ctx,
            view,
            width,
            height,
            self.vis_path,
            self.queue_capacity,
            self.visible_capacity,
            self.scene.instance_capacity(),
        )?;
        let pyramid = DepthPyramid::new(&self.ctx, &fb)?;
        Ok((fb, pyramid))
    }

    fn frame_buffers(&mut self, width: u32, height: u32) -> GpuResult<()> {
        let ok = self
            .fb
            .as_ref()
            .is_some_and(|f| f.width == width && f.height == height);
        if !ok {
            let (fb, pyramid) = self.view_buffers("", width, height)?;
            self.pyramid = Some(pyramid);
            self.debug_view = Some(DebugView::new(&self.ctx, &fb)?);
            self.overdraw = None;
            self.fb = Some(fb);
            self.history = None;
        }
        Ok(())
    }

    /// Records one phase's culling passes (with their clears and barriers). The post phase keeps
    /// numbering visible clusters after the main phase's.
    fn record_cull(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        fb: &FrameBuffers,
        hzb: &Buffer,
        phase: Phase,
        cold: bool,
    ) {
        let counters = match phase {
            Phase::Main => &fb.counters,
            Phase::Post => &fb.counters_post,
        };
        cmd.fill_buffer(counters, 0);
        cmd.fill_buffer(&fb.queue, u32::MAX);
        if phase == Phase::Post {
            let t = (
                vk::PipelineStageFlags2::ALL_TRANSFER,
                vk::AccessFlags2::TRANSFER_WRITE,
            );
            cmd.barrier(t, t);
            let off = std::mem::offset_of!(CullCounters, visible_count) as u64;
            cmd.copy_buffer_region(&fb.counters, off, &fb.counters_post, off, 4);
        }
        let rw = vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE;
        cmd.barrier(
            (
                vk::PipelineStageFlags2::ALL_TRANSFER,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (vk::PipelineStageFlags2::COMPUTE_SHADER, rw),
        );
        if cold && phase == Phase::Main {
            self.occluder_select
                .record(cmd, timer, &self.scene, fb, hzb);
            cmd.barrier(
                (vk::PipelineStageFlags2::COMPUTE_SHADER, rw),
                (vk::PipelineStageFlags2::COMPUTE_SHADER, rw),
            );
        }
        let streaming = self.streaming_cull();
        self.instance_cull
            .record(cmd, timer, &self.scene, fb, hzb, phase, streaming);
        cmd.barrier(
            (vk::PipelineStageFlags2::COMPUTE_SHADER, rw),
            (vk::PipelineStageFlags2::COMPUTE_SHADER, rw),
        );
        self.cluster_cull
            .record(cmd, timer, &self.scene, fb, hzb, phase, streaming);
        cmd.barrier(
            (
                vk::PipelineStageFlags2::COMPUTE_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_WRITE,
            ),
            (
                vk::PipelineStageFlags2::COMPUTE_SHADER
                    | vk::PipelineStageFlags2::DRAW_INDIRECT
                    | self.raster_hw.input_stages()
                    | vk::PipelineStageFlags2::ALL_TRANSFER,
                vk::AccessFlags2::SHADER_STORAGE_READ
                    | vk::AccessFlags2::INDIRECT_COMMAND_READ
                    | vk::AccessFlags2::TRANSFER_READ,
            ),
        );
    }

    /// The view uniform of `camera` with the renderer's instance count and capacities, and
    /// `VIEW_FLAG_DIRECT_VISIBLE` when the visible list holds every (instance, cluster) pair.
    pub(crate) fn view_of(
        &self,
        camera: &Camera,
        width: u32,
        height: u32,
        settings: &FrameSettings,
    ) -> ViewGpu {
        let mut settings = *settings;
        // Only FrameData::new says a frame is cold (and records occluder_select with it).
        settings.flags &= !VIEW_FLAG_COLD_FRAME;
        if settings.auto_split() {
            settings.hw_threshold_px = self.split.threshold();
        }
        if self.direct_visible() {
            settings.flags |= VIEW_FLAG_DIRECT_VISIBLE;
        }
        if self.raster_hw.hw_path() == HwPath::Mesh {
            settings.flags |= VIEW_FLAG_HW_MESH;
        }
        view_gpu(
            camera,
            width,
            height,
            &settings,
            self.scene.instance_count,
            self.queue_capacity,
            self.visible_capacity,
        )
    }

    /// Whether visible-list slots are assigned directly (deterministic): every (instance, cluster)
    /// pair of the scene fits the visible list.
    pub fn direct_visible(&self) -> bool {
        self.scene.instance_clusters <= self.visible_capacity as u64
    }

    fn write_view(
        &mut self,
        camera: &Camera,
        width: u32,
        height: u32,
        settings: &FrameSettings,
    ) -> GpuResult<()> {
        self.follow_scene()?;
        self.frame_buffers(width, height)?;
        let view = self.view_of(camera, width, height, settings);
        let fb = self
            .fb
            .as_mut()
            .ok_or_else(|| GpuError::Other("frame buffers missing".into()))?;
        fb.view.write(0, bytemuck::bytes_of(&view))?;
        // Culling only: no HZB, nothing occluded.
        let off = OcclusionGpu::default();
        fb.occ_main.write(0, bytemuck::bytes_of(&off))?;
        fb.occ_post.write(0, bytemuck::bytes_of(&off))
    }

    /// Forgets the previous frame's depth (after a camera cut): the next frame's main phase culls
    /// nothing by occlusion (the post phase still does). Correct either way; this only saves work.
    pub fn reset_history(&mut self) {
        self.history = None;
    }

    /// Renders one frame: both culling phases, both rasterizers, the HZB, and `mode`'s debug view,
    /// and reads back the image, the visibility buffer and the counters.
    ///
    /// Two views change the frame itself: [`ViewMode::Fallback`] draws each mesh's fallback mesh
    /// (the complete DAG level nearest the fallback triangle count,
    /// [`crate::shared::VIEW_FLAG_FALLBACK_CUT`]) instead of the LOD cut, and [`ViewMode::Overdraw`] (like [`VIEW_FLAG_COUNT_OVERDRAW`] in
    /// `settings.flags` with any view) makes the rasterizers count writes per pixel, returned in
    /// [`VgeoFrame::overdraw`].
    pub fn render(
        &mut self,
        camera: &Camera,
        width: u32,
        height: u32,
        settings: &FrameSettings,
        mode: ViewMode,
        light: &Light,
    ) -> GpuResult<VgeoFrame> {
        let gpu_ms = self.run_frame(camera, width, height, settings, mode, light)?;
        let counting = mode == ViewMode::Overdraw || settings.flags & VIEW_FLAG_COUNT_OVERDRAW != 0;
        let fb = present(self.fb.as_ref(), "frame buffers")?;
        let debug_view = present(self.debug_view.as_ref(), "debug view")?;
        let materials = self.materials.as_ref().filter(|_| mode.is_material());
        let overdraw = self.overdraw.as_ref().filter(|_| counting);
        let pool = self.scene.pool_words();
        let main_res = read_cull(fb, &pool, Phase::Main, Vec::new())?;
        let post_res = read_cull(fb, &pool, Phase::Post, Vec::new())?;
        let vis = visbuffer::download(fb)?;
        let max_slot = vis
            .iter()
            .filter(|v| **v != 0)
            .map(|v| (*v as u32) >> crate::shared::VISBUFFER_TRIANGLE_BITS)
            .max();
        let visible_table = read_visible_table(fb, &pool, max_slot)?;
        let color = match materials {
            Some(m) => m.download()?,
            None => debug_view.download()?,
        };
        let overdraw = match overdraw {
            Some(o) => Some(words(&o.download()?)),
            None => None,
        };
        let triangles = main_res.counters.triangles as u64 + post_res.counters.triangles as u64;
        let depth = vis
            .iter()
            .map(|v| f32::from_bits((v >> 32) as u32))
            .collect();
        Ok(VgeoFrame {
            frame: Frame {
                width,
                height,
                color,
                depth,
                gpu_ms,
                triangles,
            },
            visbuffer: vis,
            main: main_res,
            post: post_res,
            visible_table,
            overdraw,
        })
    }

    /// Records, submits and waits for one frame; updates the occlusion history; the GPU times.
    fn run_frame(
        &mut self,
        camera: &Camera,
        width: u32,
        height: u32,
        settings: &FrameSettings,
        mode: ViewMode,
        light: &Light,
    ) -> GpuResult<Vec<(String, f64)>> {
        let cams = std::slice::from_ref(camera);
        // Its counters are read back (`render`): the cull keeps its statistics.
        let mut frames = self.run_frames(cams, width, height, settings, mode, light, true)?;
        Ok(frames.pop().unwrap_or_default())
    }

    /// The frames of `cameras` (a camera path) in one submission, back to back, without read-back:
    /// the GPU times per pass of each frame. Each frame's view, occlusion and material view are
    /// written into the command buffer, so the GPU never waits for the CPU between frames (as in
    /// an application with frames in flight; the benchmark times paths this way). The occlusion
    /// history flows from frame to frame and stays for the next call.
    pub fn render_path_timed(
        &mut self,
        cameras: &[Camera],
        width: u32,
        height: u32,
        settings: &FrameSettings,
        mode: ViewMode,
        light: &Light,
    ) -> GpuResult<Vec<Vec<(String, f64)>>> {
        // Nothing reads these frames' counters: the cull skips its statistics.
        self.run_frames(cameras, width, height, settings, mode, light, false)
    }

    /// `stats`: the cull keeps its statistics ([`VIEW_FLAG_CULL_STATS`]), for frames whose
    /// counters are read.
    #[allow(clippy::too_many_arguments)]
    fn run_frames(
        &mut self,
        cameras: &[Camera],
        width: u32,
        height: u32,
        settings: &FrameSettings,
        mode: ViewMode,
        light: &Light,
        stats: bool,
    ) -> GpuResult<Vec<Vec<(String, f64)>>> {
        let Some(first) = cameras.first() else {
            return Ok(Vec::new());
        };
        let mut settings = *settings;
        // One split for the whole submission; its frames' times tell the tuner. A view that
        // shows the split (hwsw) shows the choice, not a threshold being tried.
        let auto = settings.auto_split();
        if auto {
            settings.hw_threshold_px = if mode == ViewMode::HwSw {
                self.split.chosen()
            } else {
                self.split.threshold()
            };
        }
        if mode == ViewMode::Fallback {
            settings.flags |= crate::shared::VIEW_FLAG_FALLBACK_CUT;
        }
        if mode == ViewMode::Overdraw {
            settings.flags |= VIEW_FLAG_COUNT_OVERDRAW;
        }
        if stats {
            settings.flags |= VIEW_FLAG_CULL_STATS;
        }
        let counting = settings.flags & VIEW_FLAG_COUNT_OVERDRAW != 0;
        self.write_view(first, width, height, &settings)?;
        if counting && self.overdraw.is_none() {
            self.overdraw = Some(Buffer::new(
                &self.ctx,
                "overdraw counters",
                4 * width as u64 * height as u64,
                vk::BufferUsageFlags::STORAGE_BUFFER
                    | vk::BufferUsageFlags::TRANSFER_DST
                    | vk::BufferUsageFlags::TRANSFER_SRC,
                crate::gpu::MemoryKind::Gpu,
            )?);
        }
        let shade = mode.shade_mode();
        if let Some(sm) = shade {
            self.prepare_materials()?;
            let fb = present(self.fb.as_ref(), "frame buffers")?;
            if let Some(m) = self.materials.as_mut() {
                m.prepare(fb, first, light.direction, sm)?;
            }
        }
        let levels = self
            .pyramid
            .as_ref()
            .map(|p| p.levels.len() as u32)
            .unwrap_or(0);
        let fb = present(self.fb.as_ref(), "frame buffers")?;
        let materials = self.materials.as_ref().filter(|_| mode.is_material());
        // Per frame: view, occlusion of the main phase (the previous frame's) and of the post
        // phase (this frame's), material view.
        let mut history = self.history;
        let mut data: Vec<FrameData> = Vec::with_capacity(cameras.len());
        for cam in cameras {
            let current = occlusion_of(cam, width, height, levels, settings.occlusion);
            let main = match (history, settings.occlusion) {
                (Some(h), true) => h,
                _ => OcclusionGpu::default(),
            };
            let view = self.view_of(cam, width, height, &settings);
            let mview = match (shade, materials) {
                (Some(sm), Some(m)) => Some(m.view_for(fb, cam, light.direction, sm)?),
                _ => None,
            };
            data.push(FrameData::new(view, main, current, mview));
            history = settings.occlusion.then_some(current);
        }
        let pyramid = present(self.pyramid.as_ref(), "HZB")?;
        let debug_view = present(self.debug_view.as_ref(), "debug view")?;
        let material_view = materials.and_then(|m| m.targets()).map(|t| &t.gbuffer.view);
        let overdraw = self.overdraw.as_ref().filter(|_| counting);
        let mut timer = Timer::new(&self.ctx, 24 * cameras.len() as u32)?;
        let mut starts = Vec::with_capacity(cameras.len());
        let mut result = Ok(());
        self.scene.prepare_updates()?;
        let scene = &self.scene;
        self.ctx.submit_and_wait("vgeo frame", |cmd| {
            timer.reset(cmd);
            scene.record_updates(cmd);
            for d in &data {
                starts.push(timer.count());
                let finish = match materials.and_then(|m| m.targets()) {
                    Some(targets) => Finish::Materials {
                        targets,
                        output: MaterialOutput::Shaded(None),
                    },
                    None => Finish::Debug {
                        view: debug_view,
                        mode,
                        light_dir: light.direction,
                    },
                };
                let inputs = FrameInputs {
                    fb,
                    pyramid,
                    material_view,
                    overdraw,
                    host_depth: None,
                };
                result = self.record_frame(cmd, &mut timer, &inputs, d, finish);
                if result.is_err() {
                    break;
                }
            }
            // What the frames asked of the streamer, for `Streamer::update` to read without
            // waiting.
            scene.record_feedback(cmd);
        })?;
        self.scene.updates_submitted();
        self.scene.release_retired();
        result?;
        let all = timer.results()?;
        self.history = history;
        if all.is_empty() {
            return Ok(vec![Vec::new(); cameras.len()]);
        }
        let mut ends: Vec<usize> = starts.iter().skip(1).copied().collect();
        ends.push(all.len());
        let frames: Vec<Vec<(String, f64)>> = starts
            .iter()
            .zip(ends)
            .map(|(&a, b)| all[a.min(all.len())..b.min(all.len())].to_vec())
            .collect();
        if auto {
            for f in &frames {
                self.split
                    .observe(settings.hw_threshold_px, f.iter().map(|p| p.1).sum());
            }
        }
        Ok(frames)
    }

    /// The automatic SW/HW split of [`VgeoRenderer::render`]'s frames: the threshold chosen so
    /// far (pixels) and whether the tuner has settled on it ([`SplitTuner::settled`]).
    pub fn hw_split(&self) -> (f32, bool) {
        (self.split.chosen(), self.split.settled())
    }

    /// Renders the first frames of `cameras` (a path) in `mode` with the automatic split, a fresh
    /// round of the tuner from its current choice, until it settles or `budget_ms` of wall time
    /// pass, and returns the threshold chosen: what a benchmark fixes before it times a path (so
    /// that no timed frame probes another split). Every candidate is measured on the same
    /// cameras (the path's first [`split::SPLIT_WINDOW`], repeated when it has fewer), so the
    /// choice compares splits, not parts of the path. Settings with a fixed split return it at
    /// once. The occlusion history is left reset.
    #[allow(clippy::too_many_arguments)]
    pub fn settle_split(
        &mut self,
        cameras: &[Camera],
        width: u32,
        height: u32,
        settings: &FrameSettings,
        mode: ViewMode,
        light: &Light,
        budget_ms: f64,
    ) -> GpuResult<f32> {
        if !settings.auto_split() || cameras.is_empty() {
            return Ok(settings.hw_threshold_px);
        }
        let t = std::time::Instant::now();
        // Earlier frames (other views, other settings) do not count.
        self.split.restart();
        let cams = &cameras[..split::SPLIT_WINDOW.min(cameras.len())];
        while !self.split.settled() && t.elapsed().as_secs_f64() * 1e3 < budget_ms {
            self.reset_history();
            if self
                .render_path_timed(cams, width, height, settings, mode, light)?
                .iter()
                .all(|f| f.is_empty())
            {
                break; // no timestamps: nothing to measure
            }
        }
        self.reset_history();
        Ok(self.split.chosen())
    }

    /// Records one frame (the one frame recording: `render`, `render_path_timed` and the embedded
    /// [`VgeoRenderer::record`] all go through it): the frame's uniforms written in command order
    /// behind a barrier on everything before (so frames and views recorded back to back, and frames
    /// in flight on one queue, never race), the visibility buffer cleared or seeded from the host's
    /// depth, both culling phases with their rasterizers and HZBs, the host's depth written back,
    /// then `finish`.
    fn record_frame(
        &self,
        cmd: &mut Cmd,
        timer: &mut Timer,
        inputs: &FrameInputs<'_>,
        d: &FrameData,
        finish: Finish<'_>,
    ) -> GpuResult<()> {
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        let fb = inputs.fb;
        // The previous frame is done with this frame's inputs before they are rewritten.
        cmd.barrier(
            (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
            (S::ALL_TRANSFER, A::TRANSFER_WRITE),
        );
        cmd.update_buffer(&fb.view, 0, bytemuck::bytes_of(&d.view));
        cmd.update_buffer(&fb.occ_main, 0, bytemuck::bytes_of(&d.main));
        cmd.update_buffer(&fb.occ_post, 0, bytemuck::bytes_of(&d.current));
        if let (Some(mv), Some(buf)) = (&d.mview, inputs.material_view) {
            cmd.update_buffer(buf, 0, bytemuck::bytes_of(mv));
        }
        match inputs.host_depth {
            // The host's depth into a float buffer; `depth_import` seeds the visibility buffer.
            Some((buf, image)) => cmd.copy_image_to_buffer(image, &buf.buffer),
            None => visbuffer::clear(cmd, fb),
        }
        // Direct slots leave holes: empty entries read as all ones.
        cmd.fill_buffer(&fb.visible, u32::MAX);
        if let Some(o) = inputs.overdraw {
            cmd.fill_buffer(o, 0);
        }
        let rw = A::SHADER_STORAGE_READ | A::SHADER_STORAGE_WRITE;
        let raster_stages = S::COMPUTE_SHADER | S::FRAGMENT_SHADER;
        cmd.barrier(
            (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            (S::ALL_COMMANDS, A::MEMORY_READ | A::MEMORY_WRITE),
        );
        if let Some((buf, _)) = inputs.host_depth {
            self.depth_import.record(cmd, timer, fb, buf);
            cmd.barrier((S::COMPUTE_SHADER, rw), (raster_stages, rw));
        }
        // The culls write page feedback: the next `record_feedback` copies it.
        self.scene.note_feedback_frame();
        for phase in [Phase::Main, Phase::Post] {
            self.record_cull(cmd, timer, fb, &inputs.pyramid.hzb, phase, d.cold());
            self.raster_sw
                .record_counting(cmd, timer, &self.scene, fb, phase, inputs.overdraw);
            // Both rasterizers do atomics on the visibility buffer.
            cmd.barrier((raster_stages, rw), (raster_stages, rw));
            self.raster_hw
                .record_counting(cmd, timer, &self.scene, fb, phase, inputs.overdraw);
            cmd.barrier((raster_stages, rw), (S::COMPUTE_SHADER, rw));
            // After the main phase: this frame's HZB for the post phase; after the post
            // phase: the HZB the next frame's main phase tests against, made only when the
            // post phase drew anything (its cull wrote the dispatch; before the rasterizers,
            // behind the barrier that made their indirect arguments visible).
            match phase {
                Phase::Main => inputs.pyramid.record(cmd, timer, fb),
                Phase::Post => {
                    let (counters, _, _) = fb.phase_lists(phase);
                    inputs.pyramid.record_indirect(
                        cmd,
                        timer,
                        fb,
                        counters,
                        std::mem::offset_of!(CullCounters, hzb_dispatch) as u64,
                    )
                }
            }
        }
        if let Some((buf, image)) = inputs.host_depth {
            self.depth_export.record(cmd, timer, fb, buf);
            cmd.barrier(
                (S::COMPUTE_SHADER, A::SHADER_STORAGE_WRITE),
                (S::ALL_TRANSFER, A::TRANSFER_READ),
            );
            cmd.copy_buffer_to_image(&buf.buffer, image, &[(0, fb.width, fb.height)]);
        }
        match finish {
            Finish::Materials { targets, output } => {
                let m = present(self.materials.as_ref(), "material passes")?;
                m.record_with(cmd, timer, &self.scene, fb, targets, output)
            }
            Finish::Debug {
                view,
                mode,
                light_dir,
            } => view.record_with_overdraw(
                cmd,
                timer,
                &self.scene,
                fb,
                mode,
                light_dir,
                inputs.overdraw,
            ),
            Finish::Nothing => Ok(()),
        }
    }

    /// The overdraw counters as the last counting frame left them (`None` before any frame
    /// counted). Frames that do not count neither clear nor write them.
    pub fn overdraw_counts(&self) -> GpuResult<Option<Vec<u32>>> {
        match &self.overdraw {
            Some(o) => Ok(Some(words(&o.download()?))),
            None => Ok(None),
        }
    }

    /// Both phases' cull counters as the last frame left them (main, post); `None` before the
    /// first frame. For tests: a timed path's frames keep no statistics
    /// ([`VIEW_FLAG_CULL_STATS`]).
    #[doc(hidden)]
    pub fn last_cull_counters(&self) -> GpuResult<Option<(CullCounters, CullCounters)>> {
        let Some(fb) = self.fb.as_ref() else {
            return Ok(None);
        };
        Ok(Some((
            read_counters(fb, Phase::Main)?,
            read_counters(fb, Phase::Post)?,
        )))
    }

    /// The HZB of vgeo's own view as the last frame left it (built from that frame's final
    /// visibility buffer), every level one after another (`depth_pyramid::hzb_levels`); `None`
    /// before the first frame. For tests.
    pub fn hzb(&self) -> GpuResult<Option<Vec<f32>>> {
        match &self.pyramid {
            Some(p) => Ok(Some(bytemuck::pod_collect_to_vec(&p.hzb.download()?))),
            None => Ok(None),
        }
    }

    /// Runs only the culling passes and reads back their results (tests compare them with the CPU cut).
    pub fn cull(
        &mut self,
        camera: &Camera,
        width: u32,
        height: u32,
        settings: &FrameSettings,
    ) -> GpuResult<CullResult> {
        let mut settings = *settings;
        settings.flags |= VIEW_FLAG_CULL_STATS;
        self.write_view(camera, width, height, &settings)?;
        let fb = present(self.fb.as_ref(), "frame buffers")?;
        let hzb = &present(self.pyramid.as_ref(), "HZB")?.hzb;
        let mut timer = Timer::new(&self.ctx, 8)?;
        self.scene.prepare_updates()?;
        let scene = &self.scene;
        self.ctx.submit_and_wait("vgeo cull", |cmd| {
            timer.reset(cmd);
            scene.record_updates(cmd);
            cmd.fill_buffer(&fb.visible, u32::MAX);
            self.record_cull(cmd, &mut timer, fb, hzb, Phase::Main, false);
            scene.note_feedback_frame();
            scene.record_feedback(cmd);
        })?;
        self.scene.updates_submitted();
        self.scene.release_retired();
        let gpu_ms = timer.results()?;
        read_cull(fb, &self.scene.pool_words(), Phase::Main, gpu_ms)
    }
}

/// What one frame's recording reads and writes besides the renderer's pipelines.
struct FrameInputs<'a> {
    fb: &'a FrameBuffers,
    pyramid: &'a DepthPyramid,
    /// Where the material view goes (the material targets' uniform), for the material views.
    material_view: Option<&'a Buffer>,
    overdraw: Option<&'a Buffer>,
    /// Embedding: the host's D32 depth image and the float buffer it is copied through.
    host_depth: Option<(&'a HostDepthBuffer, &'a Image)>,
}

/// The uniforms of one frame, written into the command buffer.
struct FrameData {
    view: ViewGpu,
    /// The HZB the main phase tests (the previous frame's) and the post phase's (this frame's).
    main: OcclusionGpu,
    current: OcclusionGpu,
    mview: Option<MaterialViewGpu>,
}

impl FrameData {
    /// A frame's uniforms; a frame whose main phase has no HZB to test while its post phase has
    /// one gets [`VIEW_FLAG_COLD_FRAME`] (its main phase draws only the nearest instances).
    fn new(
        mut view: ViewGpu,
        main: OcclusionGpu,
        current: OcclusionGpu,
        mview: Option<MaterialViewGpu>,
    ) -> Self {
        if main.enabled == 0 && current.enabled != 0 {
            view.flags |= VIEW_FLAG_COLD_FRAME;
        }
        Self {
            view,
            main,
            current,
            mview,
        }
    }

    /// Whether the frame is cold ([`VIEW_FLAG_COLD_FRAME`]): `occluder_select` runs first.
    fn cold(&self) -> bool {
        self.view.flags & VIEW_FLAG_COLD_FRAME != 0
    }
}

/// What a frame ends with after the rasterizers.
enum Finish<'a> {
    /// A debug view into the debug view's image.
    Debug {
        view: &'a DebugView,
        mode: ViewMode,
        light_dir: glam::Vec3,
    },
    /// The material passes into `targets` and `output`.
    Materials {
        targets: &'a MaterialTargets,
        output: MaterialOutput<'a>,
    },
    /// Nothing more: the visibility buffer (and the host's depth) is the output.
    Nothing,
}

/// What the scene can need at most: every BVH node visited once per instance (cull queue), every
/// (instance, cluster) pair (visible list), at least 64 each, capped at the maxima.
fn scene_capacities(scene: &GpuScene) -> (u32, u32) {
    (
        scene.instance_nodes().clamp(64, MAX_QUEUE as u64) as u32,
        scene.instance_clusters.clamp(64, MAX_VISIBLE as u64) as u32,
    )
}

/// The occlusion view of a camera (what its HZB is tested with).
fn occlusion_of(
    camera: &Camera,
    width: u32,
    height: u32,
    levels: u32,
    enabled: bool,
) -> OcclusionGpu {
    let v = view_gpu(camera, width, height, &FrameSettings::default(), 0, 0, 0);
    OcclusionGpu {
        view_proj: v.view_proj,
        camera_hi: v.camera_hi,
        camera_lo: v.camera_lo,
        viewport: [width as f32, height as f32, 0.0, 0.0],
        near: camera.near,
        levels,
        enabled: (enabled && levels > 0) as u32,
        _pad: 0,
    }
}

/// One rendered vgeo frame.
pub struct VgeoFrame {
    /// The debug view's image, depth from the visibility buffer, GPU times per pass.
    pub frame: Frame,
    /// The visibility buffer (`depth bits << 32 | visible index << 7 | triangle`).
    pub visbuffer: Vec<u64>,
    /// Culling results of each phase (the post phase's visible entries follow the main phase's).
    pub main: CullResult,
    /// Culling results of the post phase (what the main phase deferred).
    pub post: CullResult,
    /// The visible list up to the largest slot in use, as (instance, cluster index): what a
    /// visibility-buffer value's visible index points at. Unused slots are all ones.
    pub visible_table: Vec<[u32; 2]>,
    /// Rasterizer writes per pixel (row-major, both phases), when the frame counted them
    /// ([`ViewMode::Overdraw`] or [`VIEW_FLAG_COUNT_OVERDRAW`]).
    pub overdraw: Option<Vec<u32>>,
}

impl VgeoFrame {
    /// The (instance, cluster) a visibility-buffer value points at; `None` for an empty pixel.
    pub fn resolve(&self, value: u64) -> Option<([u32; 2], u32)> {
        if value == 0 {
            return None;
        }
        let low = value as u32;
        let entry = *self
            .visible_table
            .get((low >> crate::shared::VISBUFFER_TRIANGLE_BITS) as usize)?;
        Some((
            entry,
            low & ((1 << crate::shared::VISBUFFER_TRIANGLE_BITS) - 1),
        ))
    }

    /// Every drawn (instance, cluster), both phases.
    pub fn visible(&self) -> Vec<[u32; 2]> {
        let mut v = self.main.visible.clone();
        v.extend_from_slice(&self.post.visible);
        v
    }

    /// Fails when either phase overflowed or hit the watchdog.
    pub fn check(&self) -> Result<(), String> {
        self.main.check()?;
        self.post.check()
    }
}

/// A phase's cull counters as the last frame left them.
fn read_counters(fb: &FrameBuffers, phase: Phase) -> GpuResult<CullCounters> {
    let (buf, _, _) = fb.phase_lists(phase);
    Ok(*bytemuck::from_bytes(
        &buf.download()?[..size_of::<CullCounters>()],
    ))
}

/// Reads one phase's counters, its SW and HW lists and the visible entries they name (in list
/// order: SW, then HW). With direct slots the visible list has holes, so entries are found through
/// the lists, never by position.
fn read_cull(
    fb: &FrameBuffers,
    pool: &PoolWords,
    phase: Phase,
    gpu_ms: Vec<(String, f64)>,
) -> GpuResult<CullResult> {
    let (_, sw_buf, hw_buf) = fb.phase_lists(phase);
    let counters = read_counters(fb, phase)?;
    let list = |b: &Buffer, n: u32| -> GpuResult<Vec<u32>> {
        let n = (n.min(fb.visible_capacity)) as usize;
        Ok(words(&b.download_prefix(4 * n as u64)?))
    };
    // The small SW clusters fill the SW list from its end (`CullCounters::sw_small_count`), the
    // smallest the HW list from its end (`sw_quarter_count`); `sw_count` counts all three.
    let small = counters
        .sw_small_count
        .min(counters.sw_count)
        .min(fb.visible_capacity);
    let quarter = counters
        .sw_quarter_count
        .min(counters.sw_count - small)
        .min(fb.visible_capacity);
    // Only a list's tail: its last `n` entries, stored from the end backwards.
    let tail = |b: &Buffer, n: u32| -> GpuResult<Vec<u32>> {
        if n == 0 {
            return Ok(Vec::new());
        }
        let first = (fb.visible_capacity - n) as u64;
        let mut t = words(&b.download_range(4 * first, 4 * n as u64)?);
        t.reverse();
        Ok(t)
    };
    let mut sw = list(sw_buf, counters.sw_count - small - quarter)?;
    sw.extend(tail(sw_buf, small)?);
    sw.extend(tail(hw_buf, quarter)?);
    // A HW entry's high bits are its flags (`HW_ENTRY_*`), the low bits its visible index.
    let mut hw = list(hw_buf, counters.hw_count)?;
    let hw_cull_back = hw.iter().filter(|&&v| v & HW_ENTRY_CULL != 0).count();
    for v in &mut hw {
        *v &= !(HW_ENTRY_CULL | HW_ENTRY_MIRRORED);
    }
    let table = read_visible_table(fb, pool, sw.iter().chain(&hw).copied().max())?;
    let visible = sw
        .iter()
        .chain(&hw)
        .filter_map(|&v| table.get(v as usize).copied())
        .collect();
    Ok(CullResult {
        sw,
        hw,
        hw_cull_back,
        counters,
        visible,
        gpu_ms,
    })
}

/// The visible list up to and including slot `max` (empty when `None`), as (instance, cluster
/// index): the GPU's entries name a cluster by the pool word of its data
/// ([`GpuScene::clusters_at_words`]; `pool`: the frame's index of the pool's pages).
fn read_visible_table(
    fb: &FrameBuffers,
    pool: &PoolWords,
    max: Option<u32>,
) -> GpuResult<Vec<[u32; 2]>> {
    let Some(max) = max else {
        return Ok(Vec::new());
    };
    let n = (max as usize + 1).min(fb.visible_capacity as usize);
    let w = words(&fb.visible.download_prefix(8 * n as u64)?);
    let mut table: Vec<[u32; 2]> = w.chunks_exact(2).map(|c| [c[0], c[1]]).collect();
    pool.clusters_at_words(&mut table)
        .map_err(GpuError::Other)?;
    Ok(table)
}

/// Little-endian u32 words of a readback (whatever the byte vector's alignment).
fn words(bytes: &[u8]) -> Vec<u32> {
    bytes
        .chunks_exact(4)
        .map(|c| u32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// `o`, or an error naming what is missing (state an earlier step sets up).
fn present<'a, T>(o: Option<&'a T>, what: &str) -> GpuResult<&'a T> {
    o.ok_or_else(|| GpuError::Other(format!("{what} missing")))
}
