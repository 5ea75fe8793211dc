//! `vgeo render MESH --lod-strip`: one image of the same mesh at several distances, clusters
//! coloured, so one sees how the LOD cut follows distance and the error threshold.
//!
//! Panel `i` (from 0) shows the cut of a camera at distance `d_i = d0 * 2^i` from the framed point,
//! `d0` being the base camera's distance (the auto-framing one for a mesh). Drawn honestly at that
//! distance the mesh would shrink to `1 / 2^i` of panel 0's size, too small to see its clusters, so
//! each panel is *magnified* instead: the camera really stands at `d_i`, with its field of view
//! narrowed so that `tan(fov_i / 2) = tan(fov_0 / 2) / 2^i` (the mesh keeps panel 0's apparent size),
//! and with the error threshold (and the HW/SW split size) multiplied by `2^i`. The cull measures
//! errors in pixels of the view it gets, and the narrowed view has `2^i` times as many pixels per
//! radian, so `error * proj_scale_i / d <= tau * 2^i` is exactly `error * proj_scale_0 / d <= tau`:
//! every panel draws the cut of the *unmagnified* view (`fov_0`, the panel's resolution) at `d_i`,
//! shown through a magnifying glass. (Narrowing the field of view without scaling the threshold would
//! keep the cut of panel 0 in every panel: a telephoto lens sees as much detail as a near camera.)
//! Occlusion culling is off, so the counts are the whole cut inside the view.

use std::path::Path;

use glam::DVec3;

use crate::camera::Camera;
use crate::frame::VgeoRenderer;
use crate::gpu::{Context, GpuError};
use crate::passes::debug_view::ViewMode;
use crate::passes::view::FrameSettings;
use crate::render::{Frame, Light};
use crate::scene::load::LoadedScene;

/// Most panels of one strip (`2^15` times the base distance at the last).
pub const MAX_PANELS: u32 = 16;

/// Errors of a LOD strip.
#[derive(Debug, thiserror::Error)]
pub enum LodStripError {
    /// Unusable options (panel count, size, threshold, view).
    #[error("lod strip: {0}")]
    Options(String),
    /// A panel's frame overflowed a capacity or hit the cull watchdog.
    #[error("lod strip panel {panel}: the frame is incomplete: {msg}")]
    Incomplete {
        /// The panel, from 0 at the left.
        panel: u32,
        /// What overflowed.
        msg: String,
    },
    /// The GPU failed.
    #[error(transparent)]
    Gpu(#[from] GpuError),
}

/// What a strip shows and how.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LodStripOptions {
    /// Number of panels, side by side (1 ..= [`MAX_PANELS`]).
    pub panels: u32,
    /// Size of one panel in pixels (the image is `panels * width` x `height`).
    pub width: u32,
    /// Height of one panel in pixels.
    pub height: u32,
    /// LOD threshold in pixels of the unmagnified view (see the module documentation).
    pub error_px: f32,
    /// The HW/SW split (`FrameSettings::hw_threshold_px`: the edge-length equivalent of a cluster's
    /// triangles) in pixels of the unmagnified view; negative (`FrameSettings::AUTO_HW_THRESHOLD`):
    /// the fixed default (a strip times nothing to choose by, and its panels must agree).
    pub hw_threshold_px: f32,
    /// Extra `VIEW_FLAG_*` (force SW / HW).
    pub flags: u32,
    /// The view of the panels (default [`ViewMode::Clusters`]; [`ViewMode::Fallback`], which
    /// replaces the cut, is refused).
    pub view: ViewMode,
}

impl Default for LodStripOptions {
    fn default() -> Self {
        Self {
            panels: 5,
            width: 320,
            height: 240,
            error_px: 1.0,
            hw_threshold_px: crate::shared::DEFAULT_HW_THRESHOLD_PX,
            flags: 0,
            view: ViewMode::Clusters,
        }
    }
}

impl LodStripOptions {
    fn check(&self) -> Result<(), LodStripError> {
        let bad = |m: String| Err(LodStripError::Options(m));
        if self.panels == 0 || self.panels > MAX_PANELS {
            return bad(format!(
                "{} panels: between 1 and {MAX_PANELS}",
                self.panels
            ));
        }
        if self.width == 0 || self.height == 0 || self.width as u64 * self.panels as u64 > 16384 {
            return bad(format!(
                "{} panels of {}x{}: the strip must be 1 to 16384 pixels wide",
                self.panels, self.width, self.height
            ));
        }
        if !(self.error_px.is_finite() && self.error_px >= 0.0) {
            return bad(format!(
                "error threshold {}: a finite number >= 0",
                self.error_px
            ));
        }
        if self.view == ViewMode::Fallback {
            return bad(
                "view `fallback` replaces the cut by the fallback mesh: a strip needs a view that \
                 shows the cut (clusters, lod, groups, triangles, ...)"
                    .into(),
            );
        }
        Ok(())
    }
}

/// One panel of a strip.
#[derive(Clone, Debug, PartialEq)]
pub struct LodPanel {
    /// The camera's distance from the framed point: `d0 * 2^index`.
    pub distance: f64,
    /// `2^index`: the panel's magnification (field of view narrowed, threshold multiplied by it).
    pub magnification: f64,
    /// The camera the panel was rendered with (narrowed field of view).
    pub camera: Camera,
    /// The threshold the panel was rendered with (`error_px * magnification`).
    pub error_px: f32,
    /// Clusters drawn (both culling phases).
    pub clusters: usize,
    /// Triangles drawn (both culling phases).
    pub triangles: u64,
    /// The drawn `(instance, cluster)` pairs, sorted.
    pub visible: Vec<[u32; 2]>,
}

/// A rendered strip: the image (panels side by side, a one-pixel grey line between panels) and
/// each panel's figures.
pub struct LodStrip {
    /// `panels * width` x `height`; `triangles` is the sum over the panels.
    pub frame: Frame,
    /// What each panel shows, from the left.
    pub panels: Vec<LodPanel>,
}

impl LodStrip {
    /// One line per panel: distance, magnification, clusters and triangles drawn.
    pub fn report(&self) -> Vec<String> {
        self.panels
            .iter()
            .enumerate()
            .map(|(i, p)| {
                format!(
                    "panel {i}: distance {:.4} (x{}), {} clusters, {} triangles",
                    p.distance, p.magnification, p.clusters, p.triangles
                )
            })
            .collect()
    }
}

/// The camera and error threshold of panel `index`: `base` moved back along its view direction so
/// that the point `d0` ahead of it is `d0 * 2^index` away, its field of view narrowed by `2^index`
/// (in tangent) and its near plane pushed out by the same factor; the threshold multiplied by
/// `2^index` (see the module documentation for why this draws the unmagnified view's cut).
pub fn panel_view(base: &Camera, d0: f64, index: u32, error_px: f32) -> (Camera, f32) {
    let m = (1u64 << index.min(62)) as f64;
    let forward = base.forward.as_dvec3();
    let target = base.position + forward * d0;
    let fov = 2.0 * ((base.fov_y as f64 * 0.5).tan() / m).atan();
    let camera = Camera {
        position: target - forward * d0 * m,
        forward: base.forward,
        up: base.up,
        fov_y: fov as f32,
        near: (base.near as f64 * m) as f32,
    };
    (camera, error_px * m as f32)
}

/// Renders a strip with `renderer` (its scene loaded): panel 0 is `base`, which looks at a point
/// `d0` ahead of it (the framed point).
pub fn render_lod_strip(
    renderer: &mut VgeoRenderer,
    base: &Camera,
    d0: f64,
    light: &Light,
    opts: &LodStripOptions,
) -> Result<LodStrip, LodStripError> {
    opts.check()?;
    if !(d0.is_finite() && d0 > 0.0) {
        return Err(LodStripError::Options(format!(
            "base distance {d0}: a finite number > 0"
        )));
    }
    let (w, h) = (opts.width, opts.height);
    let strip_w = w * opts.panels;
    let mut color = vec![0u8; strip_w as usize * h as usize * 4];
    let mut depth = vec![0f32; strip_w as usize * h as usize];
    let mut gpu_ms = Vec::new();
    let mut panels = Vec::new();
    for i in 0..opts.panels {
        let (camera, tau) = panel_view(base, d0, i, opts.error_px);
        let m = (1u64 << i) as f64;
        let settings = FrameSettings {
            error_px: tau,
            hw_threshold_px: FrameSettings::fixed_split(opts.hw_threshold_px) * m as f32,
            flags: opts.flags,
            occlusion: false,
        };
        renderer.reset_history();
        let vf = renderer.render(&camera, w, h, &settings, opts.view, light)?;
        vf.check()
            .map_err(|msg| LodStripError::Incomplete { panel: i, msg })?;
        for y in 0..h as usize {
            let src = y * w as usize;
            let dst = y * strip_w as usize + i as usize * w as usize;
            color[4 * dst..4 * (dst + w as usize)]
                .copy_from_slice(&vf.frame.color[4 * src..4 * (src + w as usize)]);
            depth[dst..dst + w as usize].copy_from_slice(&vf.frame.depth[src..src + w as usize]);
            if i > 0 {
                color[4 * dst..4 * dst + 4].copy_from_slice(&[128, 128, 128, 255]);
            }
        }
        gpu_ms.extend(
            vf.frame
                .gpu_ms
                .iter()
                .map(|(pass, ms)| (format!("panel {i} {pass}"), *ms)),
        );
        let mut visible = vf.visible();
        visible.sort_unstable();
        panels.push(LodPanel {
            distance: d0 * m,
            magnification: m,
            camera,
            error_px: tau,
            clusters: visible.len(),
            triangles: vf.frame.triangles,
            visible,
        });
    }
    let triangles = panels.iter().map(|p| p.triangles).sum();
    Ok(LodStrip {
        frame: Frame {
            width: strip_w,
            height: h,
            color,
            depth,
            gpu_ms,
            triangles,
        },
        panels,
    })
}

/// The base camera of a loaded scene for panels of `width` x `height` (its own camera, or the
/// auto-framing one for a single mesh) and its distance to the framed point: the centre of the
/// instances' bounds, measured along the view direction (the whole distance when that is not
/// ahead).
pub fn base_view(loaded: &LoadedScene, width: u32, height: u32) -> (Camera, f64) {
    let camera = loaded.camera(width, height);
    let centre = loaded
        .scene
        .bounds(&loaded.mesh_bounds())
        .map(|(lo, hi)| (lo + hi) * 0.5)
        .unwrap_or(DVec3::ZERO);
    let to = centre - camera.position;
    let along = to.dot(camera.forward.as_dvec3());
    let d0 = if along > 0.0 { along } else { to.length() };
    (camera, if d0 > 0.0 { d0 } else { 1.0 })
}

/// Loads a mesh or scene file, builds its DAGs, and renders its strip (what the CLI runs).
/// `progress` gets one line per mesh built.
pub fn render_file(
    ctx: &Context,
    path: &Path,
    opts: &LodStripOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> anyhow::Result<LodStrip> {
    opts.check()?;
    let loaded = LoadedScene::load(path)?;
    for w in &loaded.warnings {
        progress(&format!("warning: {w}"));
    }
    let (base, d0) = base_view(&loaded, opts.width, opts.height);
    let built = loaded.built_meshes(progress)?;
    let mut r = VgeoRenderer::new(ctx, &built, &loaded.placements)?;
    Ok(render_lod_strip(&mut r, &base, d0, &loaded.light, opts)?)
}
