//! Embedding: vgeo records a whole frame of a view into a command buffer the host owns and
//! submits, into the host's images, with frames in flight and several views (issue 12).
//!
//! - [`View`]: what one view owns (frame buffers, HZB and occlusion history, material targets,
//!   the float buffer the host's depth goes through) plus a ring of per-frame-in-flight slots
//!   (timestamp queries and a counter read-back). Several views coexist, each with its history.
//! - [`VgeoRenderer::record`] (or [`VgeoRenderer::record_cmd`] with vgeo's own [`Cmd`]): one call
//!   records the frame (culls, rasters, HZBs, material passes) through the same function as
//!   [`VgeoRenderer::render`]; it submits nothing, waits for nothing and creates no Vulkan object.
//! - [`View::try_stats`]: the counters and pass times of a frame, once its submission completed
//!   (the host knows from its fence, N frames later), without waiting.
//!
//! The contract with the host's images (also in docs/architecture.md, "Embedding"):
//! - depth: `D32_SFLOAT`, usage `TRANSFER_SRC | TRANSFER_DST`, reverse-Z (0 = far, cleared to 0,
//!   compare `GREATER`) with vgeo's projection ([`Camera::view_proj`], camera-relative). vgeo
//!   reads it (the host's surfaces occlude vgeo's geometry and feed its HZB) and writes back the
//!   nearer of the two per pixel (so the host's later draws are occluded by vgeo's geometry).
//! - colour: `R8G8B8A8_UNORM` with `STORAGE` usage; vgeo's `shade` writes sRGB-encoded values only
//!   where its own geometry is visible (the host's pixels and background stay as they were).
//! - or the GBuffer ([`HOST_GBUFFER_FORMATS`], `STORAGE` usage): written only where vgeo's
//!   geometry is visible, for the host's lighting.
//! - layouts: each image is in [`HostImage::layout`] at entry and is left in it at exit. vgeo's
//!   first command is a global barrier from all earlier commands (all stages, memory read and
//!   write); its first barrier on each image has the source scope its layout implies
//!   (`COLOR_ATTACHMENT_OPTIMAL`: colour-attachment output, read/write; `DEPTH_ATTACHMENT_OPTIMAL`:
//!   early and late fragment tests, depth read/write; `SHADER_READ_ONLY_OPTIMAL`: fragment and
//!   compute shaders, sampled read; `TRANSFER_*`: transfers; any other, `GENERAL` included: all
//!   commands, all memory access), and its last barrier on each image returns it to that layout
//!   with the same scope as destination (synchronization2).

use crate::camera::Camera;
use crate::frame::split::SplitTuner;
use crate::frame::{Finish, FrameData, FrameInputs, VgeoRenderer, occlusion_of, words};
use crate::gpu::{Buffer, Cmd, GpuError, GpuResult, HostImage, Image, MemoryKind, Timer, vk};
use crate::material::ShadeMode;
use crate::passes::FrameBuffers;
use crate::passes::depth_import::HostDepthBuffer;
use crate::passes::depth_pyramid::DepthPyramid;
use crate::passes::material_classify::MaterialTargets;
use crate::passes::materials::MaterialOutput;
use crate::passes::shade::{ALBEDO_FORMAT, NORMAL_FORMAT, OUTPUT_FORMAT, PARAMS_FORMAT};
use crate::passes::view::FrameSettings;
use crate::render::Light;
use crate::shared::{CullCounters, OcclusionGpu, SHADE_FLAG_COVERED_ONLY};

/// Default number of frames in flight.
pub const DEFAULT_FRAMES_IN_FLIGHT: u32 = 2;

/// The depth format vgeo shares with the host.
pub const HOST_DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The colour format vgeo's `shade` writes into a host's image (sRGB-encoded values).
pub const HOST_COLOR_FORMAT: vk::Format = OUTPUT_FORMAT;

/// The formats of a host's GBuffer: albedo (sRGB-encoded colour, alpha 1 where covered), normal
/// (world space, facing the camera), params (metallic, roughness, material id low and high byte).
pub const HOST_GBUFFER_FORMATS: [vk::Format; 3] = [ALBEDO_FORMAT, NORMAL_FORMAT, PARAMS_FORMAT];

/// Most timed passes of one recorded frame.
const MAX_PASSES: u32 = 32;

/// Bytes of a slot's read-back: both phases' counters, then the frame number (low, high word).
const READBACK_BYTES: u64 = 2 * size_of::<CullCounters>() as u64 + 8;

/// The per-frame-in-flight part of a view: what the GPU writes for the host to read later.
struct Slot {
    timer: Timer,
    /// Main and post counters, then the frame number, written at the end of the frame.
    readback: Buffer,
    /// The frame last recorded into this slot.
    frame: Option<u64>,
    /// The SW/HW split it was drawn with.
    threshold: f32,
}

/// One view of the scene (a camera into a target of one size), with its own frame buffers,
/// HZB and occlusion history, and `frames_in_flight` read-back slots.
pub struct View {
    name: String,
    fb: FrameBuffers,
    pyramid: DepthPyramid,
    /// The scene's mesh epoch the view's material targets were made for.
    materials_epoch: u64,
    /// The view whose HZB is in the pyramid (the frame recorded last), if any.
    history: Option<OcclusionGpu>,
    targets: MaterialTargets,
    host_depth: HostDepthBuffer,
    slots: Vec<Slot>,
    /// The automatic SW/HW split of this view's frames (`frame::split`): fed with each slot's
    /// times when the slot is recorded again (its frame is done by then).
    split: SplitTuner,
}

/// What the GPU reported about one recorded frame of a view.
#[derive(Clone, Debug)]
pub struct FrameStats {
    /// The host's frame number it was recorded with.
    pub frame: u64,
    /// Counters of the main culling phase.
    pub main: CullCounters,
    /// Counters of the post phase (what the main phase deferred, tested against the new HZB).
    pub post: CullCounters,
    /// GPU milliseconds per pass (empty without timestamps).
    pub gpu_ms: Vec<(String, f64)>,
}

impl FrameStats {
    /// Triangles drawn by both phases.
    pub fn triangles(&self) -> u64 {
        self.main.triangles as u64 + self.post.triangles as u64
    }

    /// Fails when a capacity overflowed or the watchdog tripped (the frame was incomplete).
    pub fn check(&self) -> Result<(), String> {
        for c in [&self.main, &self.post] {
            if c.watchdog != 0 {
                return Err(format!(
                    "cluster_cull watchdog tripped (code {})",
                    c.watchdog
                ));
            }
            if c.queue_overflow != 0 || c.visible_overflow != 0 {
                return Err(format!(
                    "capacity overflow: {} queue items, {} visible clusters dropped",
                    c.queue_overflow, c.visible_overflow
                ));
            }
        }
        Ok(())
    }
}

/// The host's targets of one view's frame.
#[derive(Clone, Copy, Debug, Default)]
pub struct HostTargets {
    /// The host's depth ([`HOST_DEPTH_FORMAT`], transfer source and destination): read as
    /// occluder, written back with vgeo's geometry. `None`: vgeo's depth stays its own.
    pub depth: Option<HostImage>,
    /// The host's colour ([`HOST_COLOR_FORMAT`], storage): lit where vgeo's geometry is visible.
    pub color: Option<HostImage>,
    /// The host's GBuffer (albedo, normal, params in [`HOST_GBUFFER_FORMATS`], storage), written
    /// where vgeo's geometry is visible, for the host's lighting (instead of `color`: one or the
    /// other). Neither: no material passes (the visibility buffer and depth only).
    pub gbuffer: Option<[HostImage; 3]>,
}

/// One frame of one view, as the host records it.
#[derive(Clone, Copy, Debug)]
pub struct ViewFrame<'a> {
    /// The host's frame number (counting up by one per frame): picks the slot
    /// (`frame % frames_in_flight`) and names the frame in [`View::try_stats`].
    pub frame: u64,
    /// The view's camera (f64 position; vgeo's reverse-Z projection with an infinite far plane).
    pub camera: &'a Camera,
    /// Pixel error threshold, SW/HW split, occlusion and debug flags.
    pub settings: FrameSettings,
    /// The directional light `shade` uses.
    pub light: Light,
    /// What `shade` writes into the host's colour.
    pub shade: ShadeMode,
    /// The host's images vgeo writes (depth, colour or GBuffer).
    pub targets: HostTargets,
}

impl View {
    /// Width and height.
    pub fn size(&self) -> (u32, u32) {
        (self.fb.width, self.fb.height)
    }

    /// Frames in flight (read-back slots).
    pub fn frames_in_flight(&self) -> u32 {
        self.slots.len() as u32
    }

    /// The automatic SW/HW split of this view's frames: the threshold chosen so far (pixels) and
    /// whether its tuner has settled on it (`frame::split::SplitTuner`).
    pub fn hw_split(&self) -> (f32, bool) {
        (self.split.chosen(), self.split.settled())
    }

    /// Debug name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// Forgets the occlusion history (after a camera cut; correct either way).
    pub fn reset_history(&mut self) {
        self.history = None;
    }

    /// The stats of `frame`, when its submission has completed: `None` while its timestamps are not
    /// yet available, or when the slot has been recorded again since (more than
    /// `frames_in_flight` frames ago). Never waits. The counters are read from host-visible memory
    /// written at the end of the frame; call after the host has waited for the frame's fence (as it
    /// does before reusing the slot, `frames_in_flight` frames later).
    pub fn try_stats(&self, frame: u64) -> GpuResult<Option<FrameStats>> {
        let slot = &self.slots[(frame % self.slots.len() as u64) as usize];
        if slot.frame != Some(frame) {
            return Ok(None);
        }
        let Some(gpu_ms) = slot.timer.try_results()? else {
            return Ok(None);
        };
        let w = words(&slot.readback.read()?);
        let n = size_of::<CullCounters>() / 4;
        let marker = w[2 * n] as u64 | (w[2 * n + 1] as u64) << 32;
        if marker != frame {
            return Ok(None);
        }
        let counters = |i: usize| {
            *bytemuck::from_bytes::<CullCounters>(bytemuck::cast_slice(&w[i * n..(i + 1) * n]))
        };
        Ok(Some(FrameStats {
            frame,
            main: counters(0),
            post: counters(1),
            gpu_ms,
        }))
    }
}

impl VgeoRenderer {
    /// Creates a view of `width` x `height` with `frames_in_flight` read-back slots (at least 1;
    /// [`DEFAULT_FRAMES_IN_FLIGHT`] is the usual). Uploads the materials if not yet done. This
    /// allocates and waits (once); recording frames does neither.
    pub fn create_view(
        &mut self,
        name: &str,
        width: u32,
        height: u32,
        frames_in_flight: u32,
    ) -> GpuResult<View> {
        // Meshes added since the renderer was made (an empty one filled by a streamer) bring
        // their materials.
        self.follow_scene()?;
        self.prepare_materials()?;
        let m = self
            .materials
            .as_ref()
            .ok_or_else(|| GpuError::Other("material passes missing".into()))?;
        let (fb, pyramid) = self.view_buffers(name, width, height)?;
        let targets = m.new_targets(width, height)?;
        let host_depth =
            HostDepthBuffer::new(&self.ctx, &format!("{name} host depth"), width, height)?;
        let slots = (0..frames_in_flight.max(1))
            .map(|i| {
                Ok(Slot {
                    timer: Timer::new(&self.ctx, MAX_PASSES)?,
                    readback: Buffer::new(
                        &self.ctx,
                        &format!("{name} stats {i}"),
                        READBACK_BYTES,
                        vk::BufferUsageFlags::TRANSFER_DST,
                        MemoryKind::Readback,
                    )?,
                    frame: None,
                    threshold: 0.0,
                })
            })
            .collect::<GpuResult<Vec<_>>>()?;
        Ok(View {
            name: name.into(),
            fb,
            pyramid,
            materials_epoch: self.scene.mesh_epoch(),
            history: None,
            targets,
            host_depth,
            slots,
            split: SplitTuner::new(),
        })
    }

    /// Brings the GPU scene up to date for the next frame, once per frame before its views are
    /// recorded: the instances changed since the last frame ([`crate::scene_gpu::GpuScene`]'s
    /// `set_transform`, `set_color`, adds and removes) and the page loads and evictions a
    /// streamer staged (`GpuScene::update_pages`) are written into the scene's staging ring and
    /// their copies recorded into `cb`, O(changed) and without heap allocation once warm; before
    /// them, the page feedback the earlier frames' culls wrote is copied for the streamer to read
    /// once this frame is done (`GpuScene::record_feedback`). The ring has a slot per frame in
    /// flight (the views' slot counts). When the scene
    /// outgrew the cull capacities, the material table or a view's per-instance buffers (meshes or
    /// instances added), the renderer and `views` are resized first: that allocates and waits, and
    /// only then. Buffers a growth replaced are freed `frames_in_flight` calls later, when the
    /// frames that used them are done.
    ///
    /// # Safety
    /// As [`VgeoRenderer::record`]: `cb` is recording, outside a render pass; the host submits it
    /// before the frame's views' command buffers (or it is the same one), and submits every
    /// command buffer it recorded, in order. The scene changes before this call, not between it
    /// and the submission of the frame's views: a change that writes the GPU at once (meshes
    /// added, `GpuScene::set_page_residency`) would meet frames recorded for the scene as it was
    /// (their culls' pipelines are chosen by whether a mesh may be partial, their ranges by the
    /// arenas as they were).
    pub unsafe fn update_scene(
        &mut self,
        cb: vk::CommandBuffer,
        views: &mut [&mut View],
    ) -> GpuResult<()> {
        let ctx = self.ctx.clone();
        // SAFETY: the caller guarantees `cb` (see above).
        unsafe { ctx.record_into(cb, |cmd| self.update_scene_cmd(cmd, views)) }
    }

    /// [`VgeoRenderer::update_scene`] into vgeo's own recorder.
    pub fn update_scene_cmd(&mut self, cmd: &mut Cmd, views: &mut [&mut View]) -> GpuResult<()> {
        self.follow_scene()?;
        self.prepare_materials()?;
        let epoch = self.scene.mesh_epoch();
        let instances = self.scene.instance_capacity();
        for view in views.iter_mut() {
            let (w, h) = view.size();
            let small = view.fb.queue_capacity < self.queue_capacity
                || view.fb.visible_capacity < self.visible_capacity
                || view.fb.post_instances.size() < 4 * instances.max(1) as u64;
            if small {
                (view.fb, view.pyramid) = self.view_buffers(&view.name, w, h)?;
                view.history = None;
            }
            if view.materials_epoch != epoch {
                let m = self
                    .materials
                    .as_ref()
                    .ok_or_else(|| GpuError::Other("material passes missing".into()))?;
                view.targets = m.new_targets(w, h)?;
                view.materials_epoch = epoch;
            }
        }
        let in_flight = views
            .iter()
            .map(|v| v.slots.len() as u32)
            .max()
            .unwrap_or(1);
        self.scene.set_frames_in_flight(in_flight as usize);
        self.retire_age = if self.scene.has_retired() {
            self.retire_age + 1
        } else {
            0
        };
        if self.retire_age > in_flight {
            self.scene.release_retired();
            self.retire_age = 0;
        }
        self.scene.prepare_updates()?;
        // The page feedback the previous frames' culls wrote, copied for the streamer (it reads
        // it once this frame is done, without waiting), then the staged instance and page
        // changes.
        self.scene.record_feedback(cmd);
        self.scene.record_updates(cmd);
        self.scene.updates_submitted();
        Ok(())
    }

    /// Records one frame of `view` into `cb`, a command buffer the host owns, begins, ends and
    /// submits: both culling phases, both rasterizers, the HZBs, the host's depth in and out and
    /// the material passes into the host's colour or GBuffer (see [`HostTargets`] and the module's
    /// contract on formats, layouts and barriers). Nothing is submitted, waited for, created or
    /// heap-allocated. Frames of one view must be submitted in the order they were recorded (the
    /// occlusion history flows from each to the next); the frame's stats come back with
    /// [`View::try_stats`]. Targets that do not match the view (format, size, an undefined layout,
    /// colour and GBuffer both) are refused before anything is recorded; any other error leaves
    /// `cb` partly recorded, to be reset by the host.
    ///
    /// # Safety
    /// `cb` must be a primary command buffer of the renderer's device in the recording state,
    /// from a pool of a queue family with graphics and compute, outside a render pass; the
    /// host's images must be valid as [`HostTargets`] describes; the host keeps them, the
    /// renderer and the view alive (and does not record `frame`'s slot again) until the
    /// submission completed.
    pub unsafe fn record(
        &self,
        cb: vk::CommandBuffer,
        view: &mut View,
        frame: &ViewFrame<'_>,
    ) -> GpuResult<()> {
        // SAFETY: the caller guarantees `cb` (see above).
        unsafe {
            self.ctx
                .record_into(cb, |cmd| self.record_cmd(cmd, view, frame))
        }
    }

    /// [`VgeoRenderer::record`] into vgeo's own recorder (e.g. inside
    /// [`crate::gpu::Context::submit_and_wait`]).
    pub fn record_cmd(
        &self,
        cmd: &mut Cmd,
        view: &mut View,
        frame: &ViewFrame<'_>,
    ) -> GpuResult<()> {
        use vk::{AccessFlags2 as A, PipelineStageFlags2 as S};
        let (width, height) = view.size();
        let check = |h: &HostImage, what: &str, format: vk::Format| {
            if h.format != format || h.width != width || h.height != height {
                return Err(GpuError::Other(format!(
                    "view `{}`: the host's {what} image is {:?} {}x{}, expected {format:?} {width}x{height}",
                    view.name, h.format, h.width, h.height
                )));
            }
            if h.layout == vk::ImageLayout::UNDEFINED {
                return Err(GpuError::Other(format!(
                    "view `{}`: the host's {what} image must be in a defined layout",
                    view.name
                )));
            }
            Ok(())
        };
        if let Some(d) = &frame.targets.depth {
            check(d, "depth", HOST_DEPTH_FORMAT)?;
        }
        if let Some(c) = &frame.targets.color {
            check(c, "colour", HOST_COLOR_FORMAT)?;
        }
        if let Some(g) = &frame.targets.gbuffer {
            for (h, f) in g.iter().zip(HOST_GBUFFER_FORMATS) {
                check(h, "GBuffer", f)?;
            }
            if frame.targets.color.is_some() {
                return Err(GpuError::Other(format!(
                    "view `{}`: lit colour or the GBuffer, not both",
                    view.name
                )));
            }
        }
        let materials = match (frame.targets.color, frame.targets.gbuffer) {
            (None, None) => None,
            _ => Some(
                self.materials
                    .as_ref()
                    .ok_or_else(|| GpuError::Other("material passes missing".into()))?,
            ),
        };
        let depth = frame
            .targets
            .depth
            .map(|h| Image::from_host(&self.ctx, "host depth", &h));
        let color = frame
            .targets
            .color
            .map(|h| Image::from_host(&self.ctx, "host colour", &h));
        let gbuffer = frame.targets.gbuffer.map(|[a, n, p]| {
            [
                Image::from_host(&self.ctx, "host gbuffer albedo", &a),
                Image::from_host(&self.ctx, "host gbuffer normal", &n),
                Image::from_host(&self.ctx, "host gbuffer params", &p),
            ]
        });

        let mut settings = frame.settings;
        // `View::try_stats` reads this frame's counters back: the cull keeps its statistics.
        settings.flags |= crate::shared::VIEW_FLAG_CULL_STATS;
        let slot_index = (frame.frame % view.slots.len() as u64) as usize;
        if settings.auto_split() {
            // The slot's last frame is done (the host waited for it before reusing the slot):
            // its time tells the view's tuner, which picks this frame's split.
            let slot = &mut view.slots[slot_index];
            if slot.frame.is_some()
                && let Ok(Some(ms)) = slot.timer.try_total_ms()
            {
                view.split.observe(slot.threshold, ms);
            }
            settings.hw_threshold_px = view.split.threshold();
        }
        let cam = frame.camera;
        let levels = view.pyramid.levels.len() as u32;
        let current = occlusion_of(cam, width, height, levels, settings.occlusion);
        let main = match (view.history, settings.occlusion) {
            (Some(h), true) => h,
            _ => OcclusionGpu::default(),
        };
        let mview = materials.map(|m| {
            let mut v = m.view_for_targets(
                &view.targets,
                &view.fb,
                cam,
                frame.light.direction,
                frame.shade,
            );
            v.flags |= SHADE_FLAG_COVERED_ONLY;
            v
        });
        let data = FrameData::new(
            self.view_of(cam, width, height, &settings),
            main,
            current,
            mview,
        );
        let View {
            fb,
            pyramid,
            targets,
            host_depth,
            slots,
            history,
            ..
        } = view;
        let slot = &mut slots[slot_index];
        slot.timer.reset(cmd);
        let inputs = FrameInputs {
            fb,
            pyramid,
            material_view: Some(&targets.gbuffer.view),
            overdraw: None,
            host_depth: depth.as_ref().map(|d| (&*host_depth, d)),
        };
        let finish = match (&color, &gbuffer) {
            (Some(out), None) => Finish::Materials {
                targets,
                output: MaterialOutput::Shaded(Some(out)),
            },
            (None, Some([a, n, p])) => Finish::Materials {
                targets,
                output: MaterialOutput::Gbuffer([a, n, p]),
            },
            // Both were refused above.
            (None, None) | (Some(_), Some(_)) => Finish::Nothing,
        };
        self.record_frame(cmd, &mut slot.timer, &inputs, &data, finish)?;
        // (Only a recorded frame's split: its time is the one the slot's timer will hold.)
        slot.threshold = settings.hw_threshold_px;
        // The frame's counters and number into the slot's read-back.
        let cc = size_of::<CullCounters>() as u64;
        cmd.barrier(
            (S::ALL_COMMANDS, A::MEMORY_WRITE),
            (S::ALL_TRANSFER, A::TRANSFER_READ | A::TRANSFER_WRITE),
        );
        cmd.copy_buffer_region(&fb.counters, 0, &slot.readback, 0, cc);
        cmd.copy_buffer_region(&fb.counters_post, 0, &slot.readback, cc, cc);
        cmd.update_buffer(
            &slot.readback,
            2 * cc,
            bytemuck::bytes_of(&[frame.frame as u32, (frame.frame >> 32) as u32]),
        );
        cmd.barrier(
            (S::ALL_TRANSFER, A::TRANSFER_WRITE),
            (S::HOST, A::HOST_READ),
        );
        // The host's images back in their entry layouts.
        let g = |i: usize| gbuffer.as_ref().map(|g| &g[i]);
        let gh = |i: usize| frame.targets.gbuffer.map(|g| g[i]);
        for (img, host) in [
            (depth.as_ref(), frame.targets.depth),
            (color.as_ref(), frame.targets.color),
            (g(0), gh(0)),
            (g(1), gh(1)),
            (g(2), gh(2)),
        ] {
            if let (Some(img), Some(host)) = (img, host)
                && img.current_layout() != host.layout
            {
                cmd.transition(img, host.layout);
            }
        }
        slot.frame = Some(frame.frame);
        *history = settings.occlusion.then_some(current);
        Ok(())
    }
}
