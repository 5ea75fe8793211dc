//! `vgeo bench`: the benchmark scenes in the three modes (`brute`, `lod`, `vgeo`), speed against
//! image error, and scaling to billions of triangles (DESIGN.md, "Baselines" and "Measures").
//!
//! For every scene and every frame of its camera path, `brute` renders the reference: the frame at
//! `--reference-spp` samples per pixel (default 16: 4x4), box-filtered
//! ([`Brute::render_reference`], [`crate::imgerr`]), and the frame at one sample per pixel, whose
//! error against the reference is the floor any one-sample renderer can reach. `lod` and `vgeo`
//! render at every pixel threshold of the sweep, each threshold's whole path in order (so vgeo's
//! occlusion culling sees the previous frame of the same run). Each path is run twice: first timed,
//! the path's frames recorded back to back into one submission without read-back (GPU ms per pass
//! from timestamps; CPU ms: the submission's wall time over its frames), so the GPU is busy as in
//! an application with frames in flight rather than idled, clocks dropping, by waits and
//! read-backs between frames; then again with read-back for the triangles, clusters and instances
//! drawn and the image error against the reference ([`crate::imgerr::image_error`]: PSNR of the
//! lit image, surface difference, depth error).
//!
//! "At equal error" ([`EqualError`]): per scene and mode, the cheapest threshold (GPU ms) whose
//! PSNR is within `--psnr-margin` dB of brute's floor: thresholds are picked by measured error,
//! not by equal numbers. Results go to `--out`: `bench.json`, `bench.md`, SVG plots and a few
//! images.
//!
//! Scenes are the TOML files `outdoor`, `indoor`, `foliage`, `drawcalls` and `stress` under
//! `assets/scenes`, loaded through [`crate::scene::load`] (the loader of `vgeo render`, every scene
//! option applied) with one mesh cache for the run. `stress` is a template instance repeated on an
//! N x N x N grid (N from the suite or `--stress-n`); its camera path is made from the grid's size.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context as _, Result, bail};
use glam::{DMat4, DVec3, Vec3};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;

use crate::baseline::brute::Brute;
use crate::baseline::lod::{Lod, LodOptions};
use crate::camera::Camera;
use crate::frame::VgeoRenderer;
use crate::gpu::Context;
use crate::imgerr::{ImageError, Reference, image_error, psnr};
use crate::mesh::Mesh;
use crate::passes::debug_view::ViewMode;
use crate::passes::emit_gbuffer::EmitPath;
use crate::passes::view::FrameSettings;
use crate::render::{Frame, Light, Placement};
use crate::scene::Scene;
use crate::scene::load::{LoadedScene, MeshCache, PreparedMesh, thin, triangles_of};

/// The benchmark scenes with a scene file of their own, in run order (`stress` comes last).
pub const SCENES: [&str; 4] = ["outdoor", "indoor", "foliage", "drawcalls"];

/// Default `--reference-spp`: 4 x 4 samples per pixel.
pub const DEFAULT_REFERENCE_SPP: u32 = 16;

/// Default `--psnr-margin` (dB): "equal error" is a PSNR at most this far below brute's floor.
pub const DEFAULT_PSNR_MARGIN_DB: f64 = 1.0;

/// A benchmark suite: sizes and sweeps.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Suite {
    /// Tiny: CI on lavapipe (160x120, 2 frames, scenes thinned, small stress grids).
    Quick,
    /// The real sizes, for a discrete GPU (1920x1080, full scenes, stress up to N = 100).
    Full,
}

impl Suite {
    /// `quick` or `full`.
    pub fn parse(s: &str) -> Option<Self> {
        match s {
            "quick" => Some(Suite::Quick),
            "full" => Some(Suite::Full),
            _ => None,
        }
    }

    /// The suite's settings.
    pub fn settings(self) -> BenchSettings {
        match self {
            Suite::Quick => BenchSettings {
                suite: self,
                width: 160,
                height: 120,
                frames: 2,
                // 0 (full detail) checks the comparison: vgeo and lod must then equal brute.
                error_sweep: vec![0.0, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0],
                stress_n: vec![1, 2],
                max_scene_triangles: Some(1_500_000),
                brute_max_triangles: 2_000_000_000,
                warmup: false,
                scenes: SCENES.iter().map(|s| s.to_string()).collect(),
                stress: true,
                modes: MODES.iter().map(|s| s.to_string()).collect(),
                hw_threshold_px: FrameSettings::default().hw_threshold_px,
                emit: EmitPath::default(),
                reference_spp: DEFAULT_REFERENCE_SPP,
                psnr_margin_db: DEFAULT_PSNR_MARGIN_DB,
            },
            Suite::Full => BenchSettings {
                suite: self,
                width: 1920,
                height: 1080,
                frames: 16,
                error_sweep: vec![0.25, 0.5, 1.0, 2.0, 4.0, 8.0],
                stress_n: vec![1, 2, 4, 8, 12, 16, 20, 32, 64, 100],
                max_scene_triangles: None,
                brute_max_triangles: 2_000_000_000,
                warmup: true,
                scenes: SCENES.iter().map(|s| s.to_string()).collect(),
                stress: true,
                modes: MODES.iter().map(|s| s.to_string()).collect(),
                hw_threshold_px: FrameSettings::default().hw_threshold_px,
                emit: EmitPath::default(),
                reference_spp: DEFAULT_REFERENCE_SPP,
                psnr_margin_db: DEFAULT_PSNR_MARGIN_DB,
            },
        }
    }
}

/// What a benchmark run does.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BenchSettings {
    /// The suite these settings started from.
    pub suite: Suite,
    /// Image size in pixels.
    pub width: u32,
    pub height: u32,
    /// Frames along each scene's camera path.
    pub frames: u32,
    /// Pixel thresholds of `lod` and `vgeo` (the first of them equal to 1 is "the" 1 px figure).
    pub error_sweep: Vec<f32>,
    /// Grid sizes of the `stress` scene (N x N x N instances each).
    pub stress_n: Vec<u32>,
    /// Thin scenes above this many (instanced) triangles by keeping every k-th instance.
    pub max_scene_triangles: Option<u64>,
    /// `brute` and `lod` skip frames that would draw more triangles than this.
    pub brute_max_triangles: u64,
    /// Render each mode once before measuring (pipeline warm-up).
    pub warmup: bool,
    /// Scenes with a scene file to run (of [`SCENES`]).
    pub scenes: Vec<String>,
    /// Run the `stress` grids.
    pub stress: bool,
    /// Modes to run (of [`MODES`]); without `brute` there is no reference and no image error.
    pub modes: Vec<String>,
    /// vgeo: clusters with longer projected edges than this (pixels) go to the hardware rasterizer.
    pub hw_threshold_px: f32,
    /// vgeo: how `emit_gbuffer` runs.
    pub emit: EmitPath,
    /// Samples per pixel of the reference (a square: n x n on a regular grid, box-filtered).
    pub reference_spp: u32,
    /// "Equal error": a mode's threshold qualifies when its PSNR is at most this many dB below
    /// brute's at one sample per pixel ([`EqualError`]).
    pub psnr_margin_db: f64,
}

/// The rendering modes a benchmark compares.
pub const MODES: [&str; 3] = ["brute", "lod", "vgeo"];

/// Command-line arguments of `vgeo bench`.
#[derive(clap::Args, Clone, Debug)]
pub struct BenchArgs {
    /// `quick` (tiny, CI on lavapipe) or `full` (1920x1080, the real sizes).
    #[arg(long, default_value = "quick")]
    pub suite: String,
    /// Output folder (created): bench.json, bench.md, plots, images.
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Folder with the scene files (default: assets/scenes here, else in the source tree).
    #[arg(long)]
    pub scenes_dir: Option<PathBuf>,
    /// Scenes to run, comma-separated (outdoor, indoor, foliage, drawcalls, stress); default all.
    #[arg(long, value_delimiter = ',')]
    pub scenes: Option<Vec<String>>,
    /// Stress grid sizes N, comma-separated (N x N x N instances), instead of the suite's.
    #[arg(long, value_delimiter = ',')]
    pub stress_n: Option<Vec<u32>>,
    /// Pixel thresholds to sweep, comma-separated, instead of the suite's.
    #[arg(long, value_delimiter = ',')]
    pub sweep: Option<Vec<f32>>,
    /// Frames along each camera path, instead of the suite's.
    #[arg(long)]
    pub frames: Option<u32>,
    /// Image width, instead of the suite's.
    #[arg(long)]
    pub width: Option<u32>,
    /// Image height, instead of the suite's.
    #[arg(long)]
    pub height: Option<u32>,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Only these modes (comma-separated of brute, lod, vgeo; default all). Without brute there is
    /// no reference image, so no image error is reported.
    #[arg(long, value_delimiter = ',')]
    pub modes: Option<Vec<String>>,
    /// vgeo: clusters whose projected edges are longer than this many pixels go to the hardware
    /// rasterizer (default 32), for tuning the SW/HW split.
    #[arg(long)]
    pub hw_threshold: Option<f32>,
    /// vgeo: `emit_gbuffer` as `compute` (default: a dispatch per material) or `raster` (a draw
    /// of tile quads per material against the material depth, DESIGN.md's form).
    #[arg(long)]
    pub emit: Option<String>,
    /// Samples per pixel of the reference every mode's image error (PSNR of the lit image,
    /// surface difference %) is measured against: a square N = n x n, brute rendered at n times
    /// the resolution (in tiles) and box-filtered n x n back. Default 16 (4x4). Brute at 1 sample
    /// per pixel is measured against it too: its error is the floor any mode can reach, reported
    /// per scene. 1: the reference is brute's own frame (floor 0: exact equality).
    #[arg(long)]
    pub reference_spp: Option<u32>,
    /// "At equal error": per scene and mode, the cheapest threshold whose PSNR is at most this
    /// many dB below brute's at one sample per pixel (default 1.0).
    #[arg(long)]
    pub psnr_margin: Option<f64>,
}

impl BenchArgs {
    /// The settings these arguments ask for (the suite's, with the overrides), validated.
    pub fn settings(&self) -> Result<BenchSettings> {
        let suite = Suite::parse(&self.suite).with_context(|| {
            format!("unknown --suite `{}` (available: quick, full)", self.suite)
        })?;
        let mut s = suite.settings();
        if let Some(names) = &self.scenes {
            s.stress = names.iter().any(|n| n == "stress");
            s.scenes = Vec::new();
            for n in names {
                if SCENES.contains(&n.as_str()) {
                    s.scenes.push(n.clone());
                } else if n != "stress" {
                    bail!(
                        "unknown scene `{n}` in --scenes (available: {}, stress)",
                        SCENES.join(", ")
                    );
                }
            }
        }
        if let Some(n) = &self.stress_n {
            s.stress_n = n.clone();
        }
        if let Some(e) = &self.sweep {
            s.error_sweep = e.clone();
        }
        if let Some(f) = self.frames {
            s.frames = f;
        }
        if let Some(w) = self.width {
            s.width = w;
        }
        if let Some(h) = self.height {
            s.height = h;
        }
        if let Some(m) = &self.modes {
            if let Some(bad) = m.iter().find(|m| !MODES.contains(&m.as_str())) {
                bail!(
                    "unknown mode `{bad}` in --modes (available: {})",
                    MODES.join(", ")
                );
            }
            s.modes = m.clone();
        }
        if let Some(t) = self.hw_threshold {
            s.hw_threshold_px = t;
        }
        if let Some(e) = &self.emit {
            s.emit = EmitPath::parse(e)
                .with_context(|| format!("unknown --emit `{e}` (available: compute, raster)"))?;
        }
        if let Some(n) = self.reference_spp {
            s.reference_spp = n;
        }
        if let Some(m) = self.psnr_margin {
            s.psnr_margin_db = m;
        }
        s.validate()?;
        Ok(s)
    }
}

impl BenchSettings {
    /// The reference's samples per pixel along each axis (`sqrt(reference_spp)`, rounded).
    pub fn reference_samples_per_axis(&self) -> u32 {
        (self.reference_spp as f64).sqrt().round() as u32
    }

    /// Checks sizes, frame count, sweep values, reference samples and grid sizes.
    pub fn validate(&self) -> Result<()> {
        if !(1..=16384).contains(&self.width) || !(1..=16384).contains(&self.height) {
            bail!("width and height must be between 1 and 16384");
        }
        if self.frames == 0 {
            bail!("frames must be at least 1");
        }
        if self.modes.is_empty() {
            bail!("at least one mode must run");
        }
        if self.hw_threshold_px.is_nan() || self.hw_threshold_px < 0.0 {
            bail!("the hardware-rasterizer threshold must be a number >= 0 (pixels)");
        }
        if self.error_sweep.is_empty()
            || self.error_sweep.iter().any(|e| !e.is_finite() || *e < 0.0)
        {
            bail!("the sweep needs at least one threshold, each finite and >= 0 (0: full detail)");
        }
        let n = self.reference_samples_per_axis();
        if n * n != self.reference_spp || !(1..=16).contains(&n) {
            bail!(
                "the reference's samples per pixel must be a square of 1 to 16 (1, 4, 9, ..., 256), not {}",
                self.reference_spp
            );
        }
        if !self.psnr_margin_db.is_finite() || self.psnr_margin_db < 0.0 {
            bail!("the PSNR margin must be a finite number of dB >= 0");
        }
        if self.stress && (self.stress_n.is_empty() || self.stress_n.contains(&0)) {
            bail!("stress grid sizes must be >= 1");
        }
        let most = self.stress_n.iter().map(|&n| (n as u64).pow(3)).max();
        if most.unwrap_or(0) > crate::scene::MAX_INSTANCES {
            bail!(
                "a stress grid has more than {} instances",
                crate::scene::MAX_INSTANCES
            );
        }
        Ok(())
    }
}

/// One measured render.
#[derive(Clone, Debug, Serialize)]
pub struct FrameRecord {
    pub scene: String,
    /// `brute`, `lod` or `vgeo`.
    pub mode: String,
    /// Pixel threshold (`None` for brute).
    pub error_px: Option<f32>,
    /// Index along the camera path.
    pub frame: u32,
    /// GPU milliseconds, all passes.
    pub gpu_ms: f64,
    /// GPU milliseconds per pass, in recording order.
    pub passes: Vec<(String, f64)>,
    /// Wall-clock milliseconds of the render call (recording, submission, wait and read-back).
    pub cpu_ms: f64,
    /// Triangles drawn (vgeo: of the drawn clusters).
    pub triangles: u64,
    /// Clusters drawn (vgeo only).
    pub clusters: Option<u64>,
    /// Instances drawn: brute draws all; vgeo counts those passing frustum and occlusion culling;
    /// `None` for lod (its renderer does not report it).
    pub instances_visible: Option<u64>,
    /// Against the supersampled reference of the same frame (brute's own: the floor); `None`
    /// when brute was skipped (no reference).
    pub error: Option<ImageError>,
}

/// A mode that did not run (or failed) for a scene, and why.
#[derive(Clone, Debug, Serialize)]
pub struct Skipped {
    pub scene: String,
    pub mode: String,
    pub error_px: Option<f32>,
    pub reason: String,
}

/// A scene as run.
#[derive(Clone, Debug, Serialize)]
pub struct SceneInfo {
    /// `outdoor`, ..., or `stress_n{N}`.
    pub name: String,
    pub file: PathBuf,
    /// Stress grid size.
    pub stress_n: Option<u32>,
    /// Instances rendered, and in the scene (more when the suite thinned it).
    pub instances: u64,
    pub instances_in_scene: u64,
    /// Instanced triangles rendered (full detail).
    pub scene_triangles: u64,
    /// Triangles of the unique meshes (full detail).
    pub stored_triangles: u64,
    pub meshes: Vec<String>,
    pub frames: u32,
    /// Seconds to import the meshes not cached yet.
    pub prepare_s: f64,
    /// Seconds to build the cluster DAGs not built yet (vgeo).
    pub build_s: f64,
    /// Seconds spent rendering the supersampled references of the path (0 without brute).
    pub reference_s: f64,
}

/// Per scene, mode and threshold: means over the frames and memory.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub scene: String,
    pub mode: String,
    pub error_px: Option<f32>,
    pub frames: u32,
    pub scene_triangles: u64,
    pub gpu_ms_mean: f64,
    pub gpu_ms_max: f64,
    /// Mean GPU ms per pass name (passes recorded twice, e.g. per culling phase, are added).
    pub passes_mean: Vec<(String, f64)>,
    pub cpu_ms_mean: f64,
    pub triangles_mean: f64,
    pub clusters_mean: Option<f64>,
    pub instances_visible_mean: Option<f64>,
    pub surface_diff_mean: Option<f64>,
    pub surface_diff_max: Option<f64>,
    pub depth_err_mean: Option<f64>,
    pub depth_err_max: Option<f64>,
    /// Against the reference, from the mean squared error over all frames; `null` when every
    /// frame was equal to it.
    #[serde(serialize_with = "opt_finite_or_null")]
    pub psnr_db: Option<f64>,
    /// Brute's PSNR at one sample per pixel (the floor) minus this one (brute: 0; `None`
    /// without a reference).
    pub psnr_below_floor_db: Option<f64>,
    /// GPU bytes of geometry (meshes, LOD chains or cluster DAGs) and of instance records.
    pub geometry_bytes: u64,
    pub instance_bytes: u64,
    /// `geometry_bytes` per full-detail triangle of the unique meshes.
    pub bytes_per_stored_triangle: f64,
}

fn opt_finite_or_null<S: serde::Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
    match v {
        Some(v) if v.is_finite() => s.serialize_f64(*v),
        _ => s.serialize_none(),
    }
}

/// Everything a run measured.
#[derive(Clone, Debug, Serialize)]
pub struct BenchReport {
    pub device: String,
    pub driver: String,
    pub api_version: String,
    pub validation: bool,
    /// The commit the binary was built from (`git rev-parse --short HEAD`, `-dirty` for local
    /// changes), where git was available.
    pub commit: Option<String>,
    /// UTC, ISO 8601.
    pub date: String,
    pub settings: BenchSettings,
    pub scenes: Vec<SceneInfo>,
    pub records: Vec<FrameRecord>,
    pub summary: Vec<Summary>,
    /// Per scene and mode (lod, vgeo): the threshold picked "at equal error".
    pub equal_error: Vec<EqualError>,
    pub skipped: Vec<Skipped>,
    /// GPU memory per scene and mode.
    pub memory: Vec<MemoryRecord>,
    pub wall_s: f64,
    /// Example images for the output folder (file stem, frame): the middle frame of each path,
    /// the reference, brute and both other modes at the threshold nearest 1 px.
    #[serde(skip)]
    pub images: Vec<(String, Frame)>,
}

/// A mode's threshold "at equal error": the cheapest (lowest mean GPU ms) of the sweep whose
/// PSNR against the reference is at most `psnr_margin_db` below brute's at one sample per pixel.
#[derive(Clone, Debug, Serialize)]
pub struct EqualError {
    pub scene: String,
    /// `lod` or `vgeo`.
    pub mode: String,
    pub psnr_margin_db: f64,
    /// Brute's PSNR at one sample per pixel.
    #[serde(serialize_with = "finite_or_null")]
    pub floor_psnr_db: f64,
    /// The threshold picked; `None` when none of the sweep is within the margin.
    pub error_px: Option<f32>,
    /// Its figures (`None` with no threshold).
    pub gpu_ms_mean: Option<f64>,
    pub triangles_mean: Option<f64>,
    #[serde(serialize_with = "opt_finite_or_null")]
    pub psnr_db: Option<f64>,
    pub surface_diff_mean: Option<f64>,
}

fn finite_or_null<S: serde::Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    opt_finite_or_null(&Some(*v), s)
}

/// GPU memory a mode holds for a scene.
#[derive(Clone, Debug, Serialize)]
pub struct MemoryRecord {
    pub scene: String,
    pub mode: String,
    /// Meshes (brute), all LOD levels (lod) or cluster DAGs with BVH (vgeo).
    pub geometry_bytes: u64,
    /// Instance records (vgeo's per-frame work buffers are not counted).
    pub instance_bytes: u64,
}

// ---------------------------------------------------------------------------------------------
// Scene preparation.

/// A scene ready to render: meshes (prepared through the run's [`MeshCache`]), placements and
/// the cameras of its path.
struct BenchScene {
    info: SceneInfo,
    meshes: Vec<Arc<PreparedMesh>>,
    placements: Vec<Placement>,
    cameras: Vec<Camera>,
    light: Light,
}

impl BenchScene {
    fn mesh_list(&self) -> Vec<&Mesh> {
        self.meshes.iter().map(|p| &p.mesh).collect()
    }
}

fn load_scene(
    cache: &mut MeshCache,
    file: &Path,
    name: &str,
    settings: &BenchSettings,
    stress_n: Option<u32>,
) -> Result<BenchScene> {
    let t0 = Instant::now();
    let loaded = LoadedScene::load_with(cache, file)?;
    let prepare_s = t0.elapsed().as_secs_f64();
    let bounds = loaded.mesh_bounds();
    let aspect = settings.width as f32 / settings.height as f32;
    let (placements, cameras) = match stress_n {
        None => {
            let cameras = loaded.scene.path_cameras(&bounds, aspect, settings.frames);
            (loaded.placements.clone(), cameras)
        }
        Some(n) => stress_grid(&loaded.scene, &bounds, n, settings.frames)?,
    };
    let meshes = loaded.meshes();
    let instances_in_scene = placements.len() as u64;
    let placements = thin(placements, &meshes, settings.max_scene_triangles);
    let stored_triangles = meshes.iter().map(|m| m.triangle_count() as u64).sum();
    Ok(BenchScene {
        info: SceneInfo {
            name: name.to_string(),
            file: file.to_path_buf(),
            stress_n,
            instances: placements.len() as u64,
            instances_in_scene,
            scene_triangles: triangles_of(&placements, &meshes),
            stored_triangles,
            meshes: loaded.scene.meshes.iter().map(|m| m.name.clone()).collect(),
            frames: cameras.len() as u32,
            prepare_s,
            build_s: 0.0,
            reference_s: 0.0,
        },
        meshes: loaded.prepared.clone(),
        placements,
        cameras,
        light: loaded.light,
    })
}

/// The stress scene: the file's first instance repeated on an `n`^3 grid (spacing 1.3 times the
/// instance's largest extent), and a path from outside the grid's corner into it.
fn stress_grid(
    scene: &Scene,
    bounds: &[([f32; 3], [f32; 3])],
    n: u32,
    frames: u32,
) -> Result<(Vec<Placement>, Vec<Camera>)> {
    let template = scene
        .instances
        .first()
        .context("the stress scene needs an instance to repeat")?;
    let one = Scene {
        instances: vec![template.clone()],
        ..scene.clone()
    };
    let (lo, hi) = one
        .bounds(bounds)
        .context("the stress scene's mesh is empty")?;
    let size = (hi - lo).max_element();
    let spacing = size * 1.3;
    let centre0 = (lo + hi) * 0.5;
    let mut placements = Vec::with_capacity((n as usize).pow(3));
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let offset = DVec3::new(i as f64, j as f64, k as f64) * spacing - centre0;
                placements.push(Placement {
                    mesh: template.mesh,
                    transform: DMat4::from_translation(offset) * template.transform,
                    color: template.color,
                });
            }
        }
    }
    // The grid spans [-size/2, (n - 1) spacing + size/2] on every axis.
    let extent = (n - 1) as f64 * spacing + size;
    let centre = DVec3::splat((n - 1) as f64 * spacing * 0.5);
    let keys = [
        crate::scene::PathKey {
            eye: centre + DVec3::new(0.9, 0.55, 1.6) * extent,
            target: centre,
        },
        crate::scene::PathKey {
            eye: centre + DVec3::new(0.35, 0.3, 0.75) * extent,
            target: centre + DVec3::new(-0.1, 0.0, 0.0) * extent,
        },
    ];
    let near = (size * 0.01) as f32;
    let cameras = crate::scene::interpolate_path(&keys, frames)
        .into_iter()
        .map(|k| Camera::look_at(k.eye, k.target, Vec3::Y, 45f32.to_radians(), near))
        .collect();
    Ok((placements, cameras))
}

// ---------------------------------------------------------------------------------------------
// Running.

/// Where scene files are: `assets/scenes` in the working directory, else in the source tree.
pub fn default_scenes_dir() -> PathBuf {
    let local = Path::new("assets/scenes");
    if local.join("outdoor.toml").exists() {
        return local.to_path_buf();
    }
    Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/scenes")
}

/// Runs the benchmark with `settings` on `ctx`, reading scene files from `scenes_dir`; `progress`
/// shows a progress bar. Writes nothing (see [`write_outputs`]).
pub fn run(
    ctx: &Context,
    settings: &BenchSettings,
    scenes_dir: &Path,
    progress: bool,
) -> Result<BenchReport> {
    settings.validate()?;
    let t0 = Instant::now();
    let mut jobs: Vec<(String, PathBuf, Option<u32>)> = settings
        .scenes
        .iter()
        .map(|s| (s.clone(), scenes_dir.join(format!("{s}.toml")), None))
        .collect();
    if settings.stress {
        for &n in &settings.stress_n {
            jobs.push((
                format!("stress_n{n}"),
                scenes_dir.join("stress.toml"),
                Some(n),
            ));
        }
    }
    let sweep = settings.error_sweep.len() as u64;
    let per_scene = settings.frames as u64 * (1 + 2 * sweep);
    let bar = if progress {
        let b = ProgressBar::new(per_scene * jobs.len() as u64);
        b.set_style(
            ProgressStyle::with_template("{elapsed_precise} [{bar:40}] {pos}/{len} renders  {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
        );
        b
    } else {
        ProgressBar::hidden()
    };
    let caps = ctx.caps();
    let mut report = BenchReport {
        device: caps.device_name.clone(),
        driver: format!("{} {}", caps.driver_name, caps.driver_info),
        api_version: caps.api_version.clone(),
        validation: caps.validation,
        commit: git_commit(),
        date: utc_now(),
        settings: settings.clone(),
        scenes: Vec::new(),
        records: Vec::new(),
        summary: Vec::new(),
        equal_error: Vec::new(),
        skipped: Vec::new(),
        memory: Vec::new(),
        wall_s: 0.0,
        images: Vec::new(),
    };
    let mut cache = MeshCache::default();
    for (name, file, stress_n) in &jobs {
        bar.set_message(format!("{name}: building meshes"));
        let scene = load_scene(&mut cache, file, name, settings, *stress_n)
            .with_context(|| format!("scene `{name}`"))?;
        let times = run_scene(ctx, settings, &scene, &mut report, &bar)
            .with_context(|| format!("scene `{name}`"))?;
        report.scenes.push(SceneInfo {
            build_s: times.build_s,
            reference_s: times.reference_s,
            ..scene.info
        });
    }
    bar.finish_and_clear();
    report.summary = summarize(&report);
    report.equal_error = equal_error(&report);
    report.wall_s = t0.elapsed().as_secs_f64();
    Ok(report)
}

/// The memory a mode holds for a scene: (geometry bytes, instance bytes).
type Memory = (u64, u64);

/// GPU ms per pass of one frame.
type PassTimes = Vec<(String, f64)>;

/// How long the GPU is kept busy before a path is timed (see [`time_path`]).
const WARMUP_MS: f64 = 500.0;

/// Per frame of `cameras`, the GPU times and CPU ms of `path` (frames rendered back to back in
/// one submission, no read-back; `path(first, frames)` renders the frames from index `first`).
///
/// With `warmup`, the first frame is rendered twice (the second timing, free of one-time setup,
/// estimates a frame), then the GPU is kept busy for about [`WARMUP_MS`]: the whole path again and
/// again when it is short (a GPU left idle by the read-backs and image comparisons between
/// paths runs at a low clock; a 1 ms frame after idling measured up to 3.5x slower on the H100),
/// or its first frame once when frames are long. The warm-up also sizes the submissions to about
/// 100 ms of work each so that heavy frames never make one long submission. CPU ms of a frame:
/// the wall time of its submission (record, submit, wait) over its frames.
fn time_path(
    warmup: bool,
    cameras: &[Camera],
    mut path: impl FnMut(usize, &[Camera]) -> Result<Vec<PassTimes>>,
) -> Result<Vec<(PassTimes, f64)>> {
    let mut per_frame_ms = 0.0;
    if warmup && !cameras.is_empty() {
        // The first frame may include one-time work (pipelines, textures): time the second.
        path(0, &cameras[..1])?;
        let t = Instant::now();
        path(0, &cameras[..1])?;
        per_frame_ms = t.elapsed().as_secs_f64() * 1e3;
        if per_frame_ms * (cameras.len() as f64) < WARMUP_MS {
            let t = Instant::now();
            while t.elapsed().as_secs_f64() * 1e3 < WARMUP_MS {
                path(0, cameras)?;
            }
        }
    }
    let chunk = if per_frame_ms > 0.0 {
        ((100.0 / per_frame_ms) as usize).clamp(1, cameras.len().max(1))
    } else {
        cameras.len().max(1)
    };
    let mut out = Vec::with_capacity(cameras.len());
    for (i, frames) in cameras.chunks(chunk).enumerate() {
        let t = Instant::now();
        let times = path(i * chunk, frames)?;
        let cpu = t.elapsed().as_secs_f64() * 1e3 / frames.len() as f64;
        if times.len() != frames.len() {
            bail!("{} frames timed, {} expected", times.len(), frames.len());
        }
        out.extend(times.into_iter().map(|p| (p, cpu)));
    }
    Ok(out)
}

/// Seconds a scene spent outside the measured renders.
#[derive(Default)]
struct SceneTimes {
    /// Building the cluster DAGs not built yet.
    build_s: f64,
    /// Rendering the supersampled references.
    reference_s: f64,
}

/// Runs one scene in every mode.
fn run_scene(
    ctx: &Context,
    settings: &BenchSettings,
    scene: &BenchScene,
    report: &mut BenchReport,
    bar: &ProgressBar,
) -> Result<SceneTimes> {
    let (w, h) = (settings.width, settings.height);
    let name = &scene.info.name;
    let frames = scene.cameras.len() as u64;
    let sweep = &settings.error_sweep;
    let skip = |report: &mut BenchReport, mode: &str, e: Option<f32>, reason: String| {
        report.skipped.push(Skipped {
            scene: name.clone(),
            mode: mode.into(),
            error_px: e,
            reason,
        });
    };
    let mut memory: HashMap<&'static str, Memory> = HashMap::new();

    // brute: the references (supersampled) and its own frames at one sample per pixel.
    bar.set_message(format!("{name}: brute"));
    let mut reference: Vec<Option<Reference>> = vec![None; scene.cameras.len()];
    let mut times = SceneTimes::default();
    let meshes = scene.mesh_list();
    let runs = |mode: &str| settings.modes.iter().any(|m| m == mode);
    if !runs("brute") {
        bar.inc(frames);
    } else if scene.info.scene_triangles > settings.brute_max_triangles {
        skip(
            report,
            "brute",
            None,
            format!(
                "{} scene triangles, more than the limit of {}",
                scene.info.scene_triangles, settings.brute_max_triangles
            ),
        );
        bar.inc(frames);
    } else {
        let brute = Brute::new(ctx, &meshes)?;
        memory.insert(
            "brute",
            (
                brute.geometry_bytes(),
                scene.placements.len() as u64 * size_of::<crate::shared::InstanceGpu>() as u64,
            ),
        );
        let timed = time_path(settings.warmup, &scene.cameras, |_, cams| {
            Ok(brute.render_path_timed(&scene.placements, cams, &scene.light, w, h)?)
        })?;
        let n = settings.reference_samples_per_axis();
        for ((f, cam), (passes, cpu_ms)) in scene.cameras.iter().enumerate().zip(timed) {
            let frame = brute.render(&scene.placements, cam, &scene.light, w, h)?;
            let t = Instant::now();
            let r = brute.render_reference(&scene.placements, cam, &scene.light, (w, h), n)?;
            times.reference_s += t.elapsed().as_secs_f64();
            report.records.push(FrameRecord {
                scene: name.clone(),
                mode: "brute".into(),
                error_px: None,
                frame: f as u32,
                gpu_ms: passes.iter().map(|p| p.1).sum(),
                passes,
                cpu_ms,
                triangles: frame.triangles,
                clusters: None,
                instances_visible: Some(scene.placements.len() as u64),
                error: Some(image_error(&r, &frame)?),
            });
            save_example(report, name, "brute", None, f, &frame, Some(&r));
            reference[f] = Some(r);
            bar.inc(1);
        }
    }

    // lod, every threshold.
    bar.set_message(format!("{name}: lod"));
    let lod = if runs("lod") {
        Some(Lod::new(ctx, &meshes, &LodOptions::default())?)
    } else {
        bar.inc(frames * sweep.len() as u64);
        None
    };
    if let Some(lod) = lod.as_ref() {
        let lod_instance_bytes =
            scene.placements.len() as u64 * size_of::<crate::shared::InstanceGpu>() as u64;
        memory.insert("lod", (lod.geometry_bytes(), lod_instance_bytes));
        for &e in sweep {
            // Triangles the selection would draw at the frame with the most (frustum culling aside).
            let mut most = 0u64;
            for cam in &scene.cameras {
                let levels = lod.selection(&scene.placements, cam, h, e)?;
                let tris: u64 = scene
                    .placements
                    .iter()
                    .zip(&levels)
                    .map(|(p, &l)| lod.lod_triangle_counts(p.mesh as usize)[l as usize] as u64)
                    .sum();
                most = most.max(tris);
            }
            if most > settings.brute_max_triangles {
                skip(
                    report,
                    "lod",
                    Some(e),
                    format!(
                        "would draw up to {most} triangles, more than the limit of {}",
                        settings.brute_max_triangles
                    ),
                );
                bar.inc(frames);
                continue;
            }
            let timed = time_path(settings.warmup, &scene.cameras, |_, cams| {
                Ok(lod.render_path_timed(&scene.placements, cams, &scene.light, (w, h), e)?)
            })?;
            for ((f, cam), (passes, cpu_ms)) in scene.cameras.iter().enumerate().zip(timed) {
                let frame = lod.render(&scene.placements, cam, &scene.light, w, h, e)?;
                let error = match &reference[f] {
                    Some(r) => Some(image_error(r, &frame)?),
                    None => None,
                };
                report.records.push(FrameRecord {
                    scene: name.clone(),
                    mode: "lod".into(),
                    error_px: Some(e),
                    frame: f as u32,
                    gpu_ms: passes.iter().map(|p| p.1).sum(),
                    passes,
                    cpu_ms,
                    triangles: frame.triangles,
                    clusters: None,
                    instances_visible: None,
                    error,
                });
                save_example(report, name, "lod", Some(e), f, &frame, None);
                bar.inc(1);
            }
        }
    }
    drop(lod);

    // vgeo, every threshold, each threshold's path from a fresh history.
    bar.set_message(format!("{name}: vgeo"));
    let t = Instant::now();
    let built = if runs("vgeo") {
        use rayon::prelude::*;
        match (scene.meshes.par_iter())
            .map(|p| p.built())
            .collect::<Result<Vec<_>>>()
        {
            Ok(b) => Some(b),
            Err(err) => {
                skip(report, "vgeo", None, format!("build failed: {err:#}"));
                None
            }
        }
    } else {
        None
    };
    times.build_s = t.elapsed().as_secs_f64();
    let mut vgeo = match &built {
        None => {
            bar.inc(frames * sweep.len() as u64);
            None
        }
        Some(built) => match VgeoRenderer::new(ctx, built, &scene.placements) {
            Ok(r) => Some(r),
            Err(err) => {
                skip(report, "vgeo", None, format!("failed: {err}"));
                bar.inc(frames * sweep.len() as u64);
                None
            }
        },
    };
    if let Some(r) = vgeo.as_mut() {
        r.set_emit_path(settings.emit);
        memory.insert(
            "vgeo",
            (
                r.scene.geometry_bytes(),
                scene.placements.len() as u64 * size_of::<crate::shared::InstanceVgeo>() as u64,
            ),
        );
        for &e in sweep {
            let fs = FrameSettings {
                error_px: e,
                hw_threshold_px: settings.hw_threshold_px,
                ..FrameSettings::default()
            };
            // Timed along the path (history flows frame to frame as in an application), then
            // rendered again with read-back for the counters and the image error.
            let timed = time_path(settings.warmup, &scene.cameras, |first, cams| {
                if first == 0 {
                    r.reset_history();
                }
                Ok(r.render_path_timed(cams, w, h, &fs, ViewMode::Lit, &scene.light)?)
            })?;
            r.reset_history();
            for ((f, cam), (passes, cpu_ms)) in scene.cameras.iter().enumerate().zip(timed) {
                let vf = r.render(cam, w, h, &fs, ViewMode::Lit, &scene.light)?;
                if let Err(msg) = vf.check() {
                    skip(
                        report,
                        "vgeo",
                        Some(e),
                        format!("failed at frame {f}: {msg}"),
                    );
                    bar.inc(frames - f as u64);
                    break;
                }
                let (m, p) = (&vf.main.counters, &vf.post.counters);
                let error = match &reference[f] {
                    Some(rf) => Some(image_error(rf, &vf.frame)?),
                    None => None,
                };
                report.records.push(FrameRecord {
                    scene: name.clone(),
                    mode: "vgeo".into(),
                    error_px: Some(e),
                    frame: f as u32,
                    gpu_ms: passes.iter().map(|p| p.1).sum(),
                    passes,
                    cpu_ms,
                    triangles: vf.frame.triangles,
                    clusters: Some(
                        (m.sw_count + m.hw_count) as u64 + (p.sw_count + p.hw_count) as u64,
                    ),
                    instances_visible: Some(
                        m.instances_visible as u64 + p.instances_visible as u64,
                    ),
                    error,
                });
                save_example(report, name, "vgeo", Some(e), f, &vf.frame, None);
                bar.inc(1);
            }
        }
    }
    for mode in ["brute", "lod", "vgeo"] {
        if let Some(&(geometry_bytes, instance_bytes)) = memory.get(mode) {
            report.memory.push(MemoryRecord {
                scene: name.clone(),
                mode: mode.into(),
                geometry_bytes,
                instance_bytes,
            });
        }
    }
    Ok(times)
}

/// Keeps the middle frame's images for the output folder: brute's and its reference, lod's and
/// vgeo's at the threshold nearest 1 px.
fn save_example(
    report: &mut BenchReport,
    scene: &str,
    mode: &str,
    e: Option<f32>,
    f: usize,
    frame: &Frame,
    reference: Option<&Reference>,
) {
    let mid = (report.settings.frames as usize - 1) / 2;
    if f != mid {
        return;
    }
    if mode == "brute" {
        report
            .images
            .push((format!("{scene}_brute"), frame.clone()));
        if let Some(r) = reference {
            let stem = format!("{scene}_reference_{}spp", r.spp());
            report.images.push((stem, r.to_frame()));
        }
    } else if e == first_one_px(&report.settings.error_sweep) {
        report
            .images
            .push((format!("{scene}_{mode}_1px"), frame.clone()));
    }
}

/// The sweep's threshold closest to 1 px (the headline figure).
fn first_one_px(sweep: &[f32]) -> Option<f32> {
    sweep
        .iter()
        .copied()
        .min_by(|a, b| (a - 1.0).abs().total_cmp(&(b - 1.0).abs()))
}

fn mean(v: impl Iterator<Item = f64>) -> Option<f64> {
    let (mut s, mut n) = (0.0, 0usize);
    for x in v {
        s += x;
        n += 1;
    }
    (n > 0).then(|| s / n as f64)
}

fn summarize(report: &BenchReport) -> Vec<Summary> {
    let mut keys: Vec<(String, String, Option<f32>)> = Vec::new();
    for r in &report.records {
        let k = (r.scene.clone(), r.mode.clone(), r.error_px);
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let mut out: Vec<Summary> = keys
        .into_iter()
        .map(|(scene, mode, e)| {
            let rs: Vec<&FrameRecord> = report
                .records
                .iter()
                .filter(|r| r.scene == scene && r.mode == mode && r.error_px == e)
                .collect();
            let info = report.scenes.iter().find(|s| s.name == scene);
            let mut passes: Vec<(String, f64)> = Vec::new();
            for r in &rs {
                for (p, ms) in &r.passes {
                    match passes.iter_mut().find(|(n, _)| n == p) {
                        Some(x) => x.1 += ms,
                        None => passes.push((p.clone(), *ms)),
                    }
                }
            }
            for p in passes.iter_mut() {
                p.1 /= rs.len().max(1) as f64;
            }
            let errs: Vec<&ImageError> = rs.iter().filter_map(|r| r.error.as_ref()).collect();
            let (geometry_bytes, instance_bytes) = report
                .memory
                .iter()
                .find(|m| m.scene == scene && m.mode == mode)
                .map_or((0, 0), |m| (m.geometry_bytes, m.instance_bytes));
            let stored = info.map_or(0, |i| i.stored_triangles);
            Summary {
                frames: rs.len() as u32,
                scene_triangles: info.map_or(0, |i| i.scene_triangles),
                gpu_ms_mean: mean(rs.iter().map(|r| r.gpu_ms)).unwrap_or(0.0),
                gpu_ms_max: rs.iter().map(|r| r.gpu_ms).fold(0.0, f64::max),
                passes_mean: passes,
                cpu_ms_mean: mean(rs.iter().map(|r| r.cpu_ms)).unwrap_or(0.0),
                triangles_mean: mean(rs.iter().map(|r| r.triangles as f64)).unwrap_or(0.0),
                clusters_mean: mean(rs.iter().filter_map(|r| r.clusters.map(|c| c as f64))),
                instances_visible_mean: mean(
                    rs.iter()
                        .filter_map(|r| r.instances_visible.map(|c| c as f64)),
                ),
                surface_diff_mean: mean(errs.iter().map(|e| e.surface_diff)),
                surface_diff_max: errs.iter().map(|e| e.surface_diff).reduce(f64::max),
                depth_err_mean: mean(errs.iter().map(|e| e.depth_err_mean)),
                depth_err_max: errs.iter().map(|e| e.depth_err_max).reduce(f64::max),
                psnr_db: mean(errs.iter().map(|e| e.mse)).map(psnr),
                psnr_below_floor_db: None,
                geometry_bytes,
                instance_bytes,
                bytes_per_stored_triangle: geometry_bytes as f64 / stored.max(1) as f64,
                scene,
                mode,
                error_px: e,
            }
        })
        .collect();
    // How far each is from the floor: brute's PSNR at one sample per pixel.
    let floors: Vec<(String, f64)> = out
        .iter()
        .filter(|s| s.mode == "brute")
        .filter_map(|s| Some((s.scene.clone(), s.psnr_db?)))
        .collect();
    for s in &mut out {
        let floor = floors.iter().find(|(n, _)| *n == s.scene).map(|f| f.1);
        s.psnr_below_floor_db = match (floor, s.psnr_db) {
            (Some(f), Some(p)) if f.is_finite() && p.is_finite() => Some(f - p),
            (Some(f), Some(p)) if f == p => Some(0.0),
            _ => None,
        };
    }
    out
}

/// Per scene and mode (lod, vgeo): the cheapest threshold whose PSNR is within the margin of
/// brute's floor ([`EqualError`]); scenes without a reference get none.
fn equal_error(report: &BenchReport) -> Vec<EqualError> {
    let margin = report.settings.psnr_margin_db;
    let mut out = Vec::new();
    for info in &report.scenes {
        let Some(floor) = report
            .summary
            .iter()
            .find(|s| s.scene == info.name && s.mode == "brute")
            .and_then(|s| s.psnr_db)
        else {
            continue;
        };
        for mode in ["lod", "vgeo"] {
            let best = report
                .summary
                .iter()
                .filter(|s| s.scene == info.name && s.mode == mode)
                .filter(|s| s.psnr_db.is_some_and(|p| p >= floor - margin))
                .min_by(|a, b| a.gpu_ms_mean.total_cmp(&b.gpu_ms_mean));
            if best.is_none()
                && !report
                    .summary
                    .iter()
                    .any(|s| s.scene == info.name && s.mode == mode)
            {
                continue;
            }
            out.push(EqualError {
                scene: info.name.clone(),
                mode: mode.into(),
                psnr_margin_db: margin,
                floor_psnr_db: floor,
                error_px: best.and_then(|s| s.error_px),
                gpu_ms_mean: best.map(|s| s.gpu_ms_mean),
                triangles_mean: best.map(|s| s.triangles_mean),
                psnr_db: best.and_then(|s| s.psnr_db),
                surface_diff_mean: best.and_then(|s| s.surface_diff_mean),
            });
        }
    }
    out
}

fn git_commit() -> Option<String> {
    // The commit the binary was built from (build.rs), else the source tree's now.
    if let Some(c) = option_env!("VGEO_BUILD_COMMIT") {
        return Some(c.to_string());
    }
    let dir = Path::new(env!("CARGO_MANIFEST_DIR"));
    let out = std::process::Command::new("git")
        .args(["rev-parse", "--short", "HEAD"])
        .current_dir(dir)
        .output()
        .ok()?;
    if !out.status.success() {
        return None;
    }
    let mut c = String::from_utf8_lossy(&out.stdout).trim().to_string();
    let dirty = std::process::Command::new("git")
        .args(["status", "--porcelain", "--untracked-files=no"])
        .current_dir(dir)
        .output()
        .ok()
        .is_some_and(|o| o.status.success() && !o.stdout.is_empty());
    if dirty {
        c.push_str("-dirty");
    }
    (!c.is_empty()).then_some(c)
}

/// The current UTC time, ISO 8601 (no date crate: days since 1970 to the civil date).
fn utc_now() -> String {
    let secs = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_secs()) as i64;
    let (days, rem) = (secs.div_euclid(86_400), secs.rem_euclid(86_400));
    // Howard Hinnant's civil_from_days.
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z - era * 146_097;
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = doy - (153 * mp + 2) / 5 + 1;
    let m = if mp < 10 { mp + 3 } else { mp - 9 };
    let y = yoe + era * 400 + (m <= 2) as i64;
    format!(
        "{y:04}-{m:02}-{d:02}T{:02}:{:02}:{:02}Z",
        rem / 3600,
        rem / 60 % 60,
        rem % 60
    )
}

// ---------------------------------------------------------------------------------------------
// Output.

/// Writes `bench.json`, `bench.md`, the plots (`speed_error_<scene>.svg`, `stress_scaling.svg`,
/// `stress_memory.svg`) and example images (`images/`) into `out` (created).
pub fn write_outputs(report: &BenchReport, out: &Path) -> Result<()> {
    std::fs::create_dir_all(out).with_context(|| format!("cannot create {}", out.display()))?;
    let json = serde_json::to_string_pretty(report)?;
    let p = out.join("bench.json");
    std::fs::write(&p, json).with_context(|| format!("cannot write {}", p.display()))?;
    let p = out.join("bench.md");
    std::fs::write(&p, markdown(report))
        .with_context(|| format!("cannot write {}", p.display()))?;
    for s in &report.scenes {
        for (axis, stem) in [
            (ErrorAxis::SurfaceDiff, "speed_error"),
            (ErrorAxis::Psnr, "speed_psnr"),
        ] {
            let series = speed_series(report, &s.name, axis);
            if series
                .iter()
                .any(|(m, pts)| m != "brute" && !pts.is_empty())
            {
                let path = out.join(format!("{stem}_{}.svg", s.name));
                plot_speed_error(&path, report, &s.name, &series, axis)?;
            }
        }
    }
    let scaling = scaling_series(report);
    if scaling.iter().any(|(_, pts)| !pts.is_empty()) {
        plot_scaling(
            &out.join("stress_scaling.svg"),
            "stress: GPU time against scene triangles (1 px)",
            "GPU ms per frame",
            &scaling
                .iter()
                .map(|(m, p)| (m.clone(), p.iter().map(|x| (x.0, x.1)).collect()))
                .collect::<Vec<_>>(),
        )?;
        plot_scaling(
            &out.join("stress_memory.svg"),
            "stress: GPU memory (geometry + instances) against scene triangles",
            "MiB",
            &scaling
                .iter()
                .map(|(m, p)| (m.clone(), p.iter().map(|x| (x.0, x.2)).collect()))
                .collect::<Vec<_>>(),
        )?;
    }
    if !report.images.is_empty() {
        let dir = out.join("images");
        std::fs::create_dir_all(&dir)
            .with_context(|| format!("cannot create {}", dir.display()))?;
        for (stem, frame) in &report.images {
            frame.save_png(&dir.join(format!("{stem}.png")))?;
        }
    }
    Ok(())
}

/// The error axis of a speed plot.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum ErrorAxis {
    /// Pixels whose visible surface differs from the reference's (%).
    SurfaceDiff,
    /// PSNR of the lit image against the reference (dB).
    Psnr,
}

/// Per mode: (error, GPU ms, label) points; brute's one point (its frame at one sample per pixel,
/// the floor) labelled `1 spp`, lod's and vgeo's one per threshold labelled with it.
type SpeedSeries = Vec<(String, Vec<(f64, f64, String)>)>;

fn speed_series(report: &BenchReport, scene: &str, axis: ErrorAxis) -> SpeedSeries {
    MODES
        .iter()
        .map(|mode| {
            let mut rows: Vec<&Summary> = report
                .summary
                .iter()
                .filter(|s| s.scene == scene && s.mode == *mode)
                .collect();
            rows.sort_by(|a, b| {
                a.error_px
                    .unwrap_or(0.0)
                    .total_cmp(&b.error_px.unwrap_or(0.0))
            });
            let pts = rows
                .iter()
                .filter_map(|s| {
                    let x = match axis {
                        ErrorAxis::SurfaceDiff => s.surface_diff_mean? * 100.0,
                        ErrorAxis::Psnr => s.psnr_db.filter(|p| p.is_finite())?,
                    };
                    let label = s.error_px.map_or("1 spp".into(), |e| format!("{e}"));
                    Some((x, s.gpu_ms_mean, label))
                })
                .collect();
            (mode.to_string(), pts)
        })
        .collect()
}

/// Per mode: (scene triangles, GPU ms, MiB) for each stress grid, at the sweep's threshold
/// nearest 1 px (a fixed threshold, not equal error: the largest grids have no reference).
type ScalingSeries = Vec<(String, Vec<(f64, f64, f64)>)>;

fn scaling_series(report: &BenchReport) -> ScalingSeries {
    let one = first_one_px(&report.settings.error_sweep);
    ["brute", "lod", "vgeo"]
        .iter()
        .map(|mode| {
            let mut pts: Vec<(f64, f64, f64)> = report
                .summary
                .iter()
                .filter(|s| s.scene.starts_with("stress_n") && s.mode == *mode)
                .filter(|s| *mode == "brute" || s.error_px == one)
                .map(|s| {
                    (
                        s.scene_triangles as f64,
                        s.gpu_ms_mean,
                        (s.geometry_bytes + s.instance_bytes) as f64 / (1u64 << 20) as f64,
                    )
                })
                .collect();
            pts.sort_by(|a, b| a.0.total_cmp(&b.0));
            (mode.to_string(), pts)
        })
        .collect()
}

fn color_of(mode: &str) -> plotters::style::RGBColor {
    match mode {
        "brute" => plotters::style::RGBColor(90, 90, 90),
        "lod" => plotters::style::RGBColor(220, 110, 30),
        _ => plotters::style::RGBColor(30, 110, 220),
    }
}

fn plot_speed_error(
    path: &Path,
    report: &BenchReport,
    scene: &str,
    series: &SpeedSeries,
    axis: ErrorAxis,
) -> Result<()> {
    use plotters::prelude::*;
    let spp = report.settings.reference_spp;
    let pts = series.iter().flat_map(|(_, p)| p.iter());
    let ymax = pts.clone().map(|p| p.1).fold(0.0, f64::max).max(1e-3) * 1.1;
    let (xlo, xhi) = pts
        .map(|p| p.0)
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), x| {
            (a.min(x), b.max(x))
        });
    // The "equal error" limit: brute's floor minus the margin.
    let floor = series
        .iter()
        .find(|(m, _)| m == "brute")
        .and_then(|(_, p)| p.first())
        .map(|p| p.0);
    let limit = floor
        .filter(|_| axis == ErrorAxis::Psnr)
        .map(|f| f - report.settings.psnr_margin_db);
    let (xmin, xmax, caption, x_desc) = match axis {
        ErrorAxis::SurfaceDiff => (
            0.0,
            xhi.max(1e-3) * 1.1,
            format!("{scene}: GPU time against surface difference (labels: px threshold)"),
            format!("pixels whose visible surface is none the {spp}-spp reference sees there (%)"),
        ),
        ErrorAxis::Psnr => {
            let (lo, hi) = (xlo.min(limit.unwrap_or(xlo)), xhi.max(xlo + 1.0));
            (
                lo - 0.05 * (hi - lo),
                hi + 0.05 * (hi - lo),
                format!("{scene}: GPU time against PSNR (labels: px threshold)"),
                format!(
                    "PSNR of the lit image against the {spp}-spp reference (dB; line: brute 1 spp - {} dB)",
                    report.settings.psnr_margin_db
                ),
            )
        }
    };
    let root = SVGBackend::new(path, (800, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(caption, ("sans-serif", 18))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(60)
        .build_cartesian_2d(xmin..xmax, 0f64..ymax)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc("GPU ms per frame (mean over the path)")
        .draw()?;
    if let Some(x) = limit {
        chart.draw_series(LineSeries::new(
            [(x, 0.0), (x, ymax)],
            RGBColor(160, 160, 160),
        ))?;
    }
    for (mode, pts) in series {
        let c = color_of(mode);
        let label = if mode == "brute" {
            "brute (1 spp: the floor)".to_string()
        } else {
            mode.clone()
        };
        chart
            .draw_series(LineSeries::new(pts.iter().map(|p| (p.0, p.1)), c))?
            .label(label)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
        chart.draw_series(pts.iter().map(|p| Circle::new((p.0, p.1), 3, c.filled())))?;
        chart.draw_series(
            pts.iter()
                .map(|p| Text::new(p.2.clone(), (p.0, p.1), ("sans-serif", 11))),
        )?;
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()?;
    root.present()?;
    Ok(())
}

fn plot_scaling(
    path: &Path,
    title: &str,
    y_desc: &str,
    series: &[(String, Vec<(f64, f64)>)],
) -> Result<()> {
    use plotters::prelude::*;
    let pts: Vec<(f64, f64)> = series
        .iter()
        .flat_map(|(_, p)| p.iter().copied())
        .filter(|p| p.0 > 0.0 && p.1 > 0.0)
        .collect();
    let (xmin, xmax) = pts
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), p| (a.min(p.0), b.max(p.0)));
    let (ymin, ymax) = pts
        .iter()
        .fold((f64::MAX, 0.0f64), |(a, b), p| (a.min(p.1), b.max(p.1)));
    if pts.is_empty() {
        return Ok(());
    }
    let root = SVGBackend::new(path, (800, 500)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 18))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(
            (xmin * 0.7..xmax * 1.4).log_scale(),
            (ymin * 0.7..ymax * 1.4).log_scale(),
        )?;
    chart
        .configure_mesh()
        .x_desc("scene triangles (instanced, full detail)")
        .y_desc(y_desc)
        .x_label_formatter(&|x| format!("{x:.0e}"))
        .draw()?;
    for (mode, pts) in series {
        let c = color_of(mode);
        let pts: Vec<(f64, f64)> = pts
            .iter()
            .copied()
            .filter(|p| p.0 > 0.0 && p.1 > 0.0)
            .collect();
        chart
            .draw_series(LineSeries::new(pts.iter().copied(), c))?
            .label(mode.as_str())
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
        chart.draw_series(pts.iter().map(|p| Circle::new(*p, 3, c.filled())))?;
    }
    chart
        .configure_series_labels()
        .border_style(BLACK)
        .background_style(WHITE.mix(0.8))
        .draw()?;
    root.present()?;
    Ok(())
}

fn fmt_opt(v: Option<f64>, f: impl Fn(f64) -> String) -> String {
    v.map_or("-".into(), f)
}

/// The Markdown report: settings, one table per scene, the stress scaling, what was skipped.
pub fn markdown(report: &BenchReport) -> String {
    use std::fmt::Write as _;
    let s = &report.settings;
    let mut md = String::new();
    let _ = writeln!(md, "# vgeo bench ({:?} suite)\n", s.suite);
    let _ = writeln!(
        md,
        "- device: {} ({}), Vulkan {}{}",
        report.device,
        report.driver,
        report.api_version,
        if report.validation {
            ", validation on"
        } else {
            ""
        }
    );
    let _ = writeln!(
        md,
        "- commit: {}; date: {}; wall time {:.1} s",
        report.commit.as_deref().unwrap_or("unknown"),
        report.date,
        report.wall_s
    );
    let _ = writeln!(
        md,
        "- {}x{}, {} frames per path, thresholds {:?} px, modes {}, vgeo hardware-rasterizer threshold {} px, emit_gbuffer {:?}; GPU ms from timestamps, frames of the path recorded back to back in one submission (no read-back, no CPU wait between them; heavy frames in submissions of ~100 ms) after ~0.5 s of GPU warm-up, mean over the path; CPU ms: a submission's wall time over its frames; images and counters from a second pass with read-back",
        s.width,
        s.height,
        s.frames,
        s.error_sweep,
        s.modes.join(", "),
        s.hw_threshold_px,
        s.emit
    );
    let n = s.reference_samples_per_axis();
    let _ = writeln!(
        md,
        "- image error against the reference of the same frame: brute at {} samples per pixel ({n}x{n} on a regular grid, box-filtered; the brute row is brute at 1 sample per pixel against it, the floor); surface diff = pixels whose visible surface is none the reference's samples see there (coverage, or a depth outside their range by > {} relative); depth error: relative distance to that range; PSNR of the lit image; below floor = brute's PSNR minus the row's",
        s.reference_spp,
        crate::imgerr::DEPTH_TOLERANCE
    );
    let _ = writeln!(
        md,
        "- at equal error: per mode, the cheapest threshold (GPU ms) whose PSNR is at most {} dB below brute's at 1 sample per pixel\n",
        s.psnr_margin_db
    );
    for info in &report.scenes {
        let _ = writeln!(
            md,
            "## {}\n\n{} instances{}, {} scene triangles, {} stored triangles ({})\n",
            info.name,
            info.instances,
            if info.instances != info.instances_in_scene {
                format!(" (thinned from {})", info.instances_in_scene)
            } else {
                String::new()
            },
            info.scene_triangles,
            info.stored_triangles,
            info.meshes.join(", ")
        );
        md.push_str("| mode | px | GPU ms | CPU ms | triangles | clusters | instances | surface diff % | depth err mean / max | PSNR dB | below floor dB | geometry MiB | B/stored tri |\n");
        md.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
        for r in report.summary.iter().filter(|r| r.scene == info.name) {
            let _ = writeln!(
                md,
                "| {} | {} | {:.3} | {:.1} | {:.0} | {} | {} | {} | {} | {} | {} | {:.1} | {:.1} |",
                r.mode,
                r.error_px.map_or("-".into(), |e| e.to_string()),
                r.gpu_ms_mean,
                r.cpu_ms_mean,
                r.triangles_mean,
                fmt_opt(r.clusters_mean, |c| format!("{c:.0}")),
                fmt_opt(r.instances_visible_mean, |c| format!("{c:.0}")),
                fmt_opt(r.surface_diff_mean, |x| format!("{:.3}", x * 100.0)),
                match (r.depth_err_mean, r.depth_err_max) {
                    (Some(a), Some(b)) => format!("{a:.1e} / {b:.1e}"),
                    _ => "-".into(),
                },
                match r.psnr_db {
                    Some(p) if p.is_finite() => format!("{p:.2}"),
                    Some(_) => "inf (equal)".into(),
                    None => "-".into(),
                },
                fmt_opt(r.psnr_below_floor_db, |x| format!("{x:.2}")),
                r.geometry_bytes as f64 / (1u64 << 20) as f64,
                r.bytes_per_stored_triangle,
            );
        }
        for k in report.skipped.iter().filter(|k| k.scene == info.name) {
            let _ = writeln!(
                md,
                "| {} | {} | skipped: {} ||||||||||| ",
                k.mode,
                k.error_px.map_or("-".into(), |e| e.to_string()),
                k.reason
            );
        }
        md.push('\n');
        let eq: Vec<&EqualError> = (report.equal_error.iter())
            .filter(|e| e.scene == info.name)
            .collect();
        if let Some(first) = eq.first() {
            let _ = writeln!(
                md,
                "At equal error (PSNR at least {:.2} dB: brute at 1 spp {:.2} dB - {} dB):\n\n| mode | px | GPU ms | triangles | PSNR dB | surface diff % |\n|---|---|---|---|---|---|",
                first.floor_psnr_db - first.psnr_margin_db,
                first.floor_psnr_db,
                first.psnr_margin_db
            );
            for e in eq {
                match e.error_px {
                    Some(px) => {
                        let _ = writeln!(
                            md,
                            "| {} | {px} | {} | {} | {} | {} |",
                            e.mode,
                            fmt_opt(e.gpu_ms_mean, |x| format!("{x:.3}")),
                            fmt_opt(e.triangles_mean, |x| format!("{x:.0}")),
                            fmt_opt(e.psnr_db, |x| format!("{x:.2}")),
                            fmt_opt(e.surface_diff_mean, |x| format!("{:.3}", x * 100.0)),
                        );
                    }
                    None => {
                        let _ = writeln!(md, "| {} | none of the sweep |||||", e.mode);
                    }
                }
            }
            md.push('\n');
        }
    }
    let scaling = scaling_series(report);
    if scaling.iter().any(|(_, p)| !p.is_empty()) {
        md.push_str("## stress scaling (threshold nearest 1 px, not equal error)\n\n| mode | scene triangles | GPU ms | MiB (geometry + instances) |\n|---|---|---|---|\n");
        for (mode, pts) in &scaling {
            for p in pts {
                let _ = writeln!(md, "| {mode} | {:.3e} | {:.3} | {:.1} |", p.0, p.1, p.2);
            }
        }
        md.push('\n');
    }
    md
}

/// `vgeo bench`: runs the suite and writes the outputs; prints where they are.
pub fn run_bench(args: &BenchArgs) -> Result<()> {
    let settings = args.settings()?;
    let scenes_dir = args.scenes_dir.clone().unwrap_or_else(default_scenes_dir);
    let ctx =
        Context::new(&crate::gpu::ContextOptions::from_env()).context("cannot start Vulkan")?;
    let report = run(&ctx, &settings, &scenes_dir, !args.quiet)?;
    write_outputs(&report, &args.out)?;
    print!("{}", markdown(&report));
    println!("wrote {}", args.out.display());
    let errors = ctx.validation_errors();
    if !errors.is_empty() {
        bail!("{} Vulkan validation error(s) (see above)", errors.len());
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A record of `mode` at `e` px with `gpu_ms` and lit-image `mse` against the reference.
    fn record(mode: &str, e: Option<f32>, gpu_ms: f64, mse: f64) -> FrameRecord {
        FrameRecord {
            scene: "s".into(),
            mode: mode.into(),
            error_px: e,
            frame: 0,
            gpu_ms,
            passes: vec![("p".into(), gpu_ms)],
            cpu_ms: 1.0,
            triangles: 100,
            clusters: None,
            instances_visible: None,
            error: Some(ImageError {
                surface_diff: 0.01,
                coverage_diff: 0.0,
                depth_err_mean: 0.0,
                depth_err_max: 0.0,
                mse,
                psnr_db: psnr(mse),
            }),
        }
    }

    #[test]
    fn equal_error_picks_the_cheapest_threshold_within_the_margin() {
        let settings = Suite::Quick.settings();
        let info = SceneInfo {
            name: "s".into(),
            file: PathBuf::new(),
            stress_n: None,
            instances: 1,
            instances_in_scene: 1,
            scene_triangles: 100,
            stored_triangles: 100,
            meshes: Vec::new(),
            frames: 1,
            prepare_s: 0.0,
            build_s: 0.0,
            reference_s: 0.0,
        };
        // Floor: brute at mse 10. PSNR falls 3 dB each time the mse doubles.
        let records = vec![
            record("brute", None, 9.0, 10.0),
            record("lod", Some(0.5), 5.0, 10.5),
            record("lod", Some(1.0), 4.0, 12.0),
            record("lod", Some(2.0), 3.0, 30.0),
            record("vgeo", Some(0.5), 2.0, 40.0),
            record("vgeo", Some(1.0), 1.0, 80.0),
        ];
        let mut report = BenchReport {
            device: String::new(),
            driver: String::new(),
            api_version: String::new(),
            validation: false,
            commit: None,
            date: String::new(),
            settings,
            scenes: vec![info],
            records,
            summary: Vec::new(),
            equal_error: Vec::new(),
            skipped: Vec::new(),
            memory: Vec::new(),
            wall_s: 0.0,
            images: Vec::new(),
        };
        report.summary = summarize(&report);
        let below = |mode: &str, e: Option<f32>| {
            (report.summary.iter())
                .find(|s| s.mode == mode && s.error_px == e)
                .and_then(|s| s.psnr_below_floor_db)
                .unwrap()
        };
        assert_eq!(below("brute", None), 0.0);
        assert!((below("lod", Some(1.0)) - 10.0 * 1.2f64.log10()).abs() < 1e-9);
        report.equal_error = equal_error(&report);
        fn pick(report: &BenchReport, mode: &str) -> EqualError {
            (report.equal_error.iter())
                .find(|e| e.mode == mode)
                .unwrap()
                .clone()
        }
        // lod: 1 px is 0.79 dB below the floor (2 px: 4.8 dB), the cheapest within 1 dB.
        let lod = pick(&report, "lod");
        assert_eq!(lod.error_px, Some(1.0));
        assert_eq!(lod.gpu_ms_mean, Some(4.0));
        assert!((lod.floor_psnr_db - psnr(10.0)).abs() < 1e-12);
        // vgeo: none within 1 dB; with a 7 dB margin 0.5 px (6 dB below) qualifies, 1 px not.
        assert_eq!(pick(&report, "vgeo").error_px, None);
        report.settings.psnr_margin_db = 7.0;
        report.equal_error = equal_error(&report);
        assert_eq!(pick(&report, "vgeo").error_px, Some(0.5));
        assert_eq!(
            pick(&report, "lod").error_px,
            Some(2.0),
            "cheaper, 4.8 dB below"
        );
        // The Markdown says what was picked.
        let md = markdown(&report);
        assert!(
            md.contains("At equal error") && md.contains("| vgeo | 0.5 |"),
            "{md}"
        );
    }

    #[test]
    fn utc_date_is_iso() {
        let d = utc_now();
        assert_eq!(d.len(), 20, "{d}");
        assert!(d.starts_with("20") && d.ends_with('Z'));
    }

    #[test]
    fn settings_overrides_and_validation() {
        let mut s = Suite::Quick.settings();
        s.validate().unwrap();
        s.error_sweep = vec![-1.0];
        assert!(s.validate().is_err());
        let mut s = Suite::Quick.settings();
        s.modes.clear();
        assert!(s.validate().is_err());
        s.modes = vec!["vgeo".into()];
        s.hw_threshold_px = f32::NAN;
        assert!(s.validate().is_err());
        s.hw_threshold_px = 64.0;
        s.validate().unwrap();
        for (spp, ok) in [
            (16, true),
            (1, true),
            (9, true),
            (256, true),
            (0, false),
            (8, false),
            (289, false),
        ] {
            s.reference_spp = spp;
            assert_eq!(s.validate().is_ok(), ok, "reference spp {spp}");
        }
        s.reference_spp = 16;
        assert_eq!(s.reference_samples_per_axis(), 4);
        s.psnr_margin_db = -1.0;
        assert!(s.validate().is_err());
        let full = Suite::Full.settings();
        assert_eq!(full.reference_spp, 16);
        assert_eq!((full.width, full.height), (1920, 1080));
        assert_eq!(*full.stress_n.last().unwrap(), 100);
        assert_eq!(first_one_px(&full.error_sweep), Some(1.0));
    }
}
