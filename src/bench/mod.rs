//! `vgeo bench`: the benchmark scenes in the three modes (`brute`, `lod`, `vgeo`), speed against
//! image error, and scaling to billions of triangles (DESIGN.md, "Baselines" and "Measures").
//!
//! For every scene and every frame of its camera path, `brute` renders the reference: the frame at
//! `--reference-spp` samples per pixel (default 16: 4x4), box-filtered
//! ([`Brute::render_reference`](crate::baseline::brute::Brute::render_reference),
//! [`crate::imgerr`]), and the frame at one sample per pixel, whose error against the reference is the floor any one-sample renderer can reach. `lod` and `vgeo`
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
//!
//! The module by concern: `scenes` loads a benchmark scene (and makes the stress grid),
//! `timing` renders a scene in every mode (timed paths, then read-back for counters and image
//! error), `error` turns the records into per-threshold summaries and the thresholds at equal
//! error (the metric itself is [`crate::imgerr`]), [`report`] holds the records and writes
//! `bench.json`, `bench.md`, the plots and images. Nothing else in the library imports this module.

mod error;
pub mod record_cpu;
pub mod report;
mod scenes;
mod timing;

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context as _, Result, bail};
use indicatif::{ProgressBar, ProgressStyle};
use serde::Serialize;

use crate::Context;
use crate::EmitPath;
use crate::FrameSettings;
use crate::GeometryBudget;
use crate::HwPath;
use crate::scene::load::MeshCache;
use error::{equal_error, summarize};
use report::{git_commit, utc_now};
use scenes::load_scene;
use timing::run_scene;

pub use report::{
    BenchReport, EqualError, FrameRecord, MemoryRecord, SceneInfo, Skipped, StreamRecord, Summary,
    markdown, write_outputs,
};

/// The benchmark scenes with a scene file of their own, in run order (`stress` comes last).
pub const SCENES: [&str; 4] = ["outdoor", "indoor", "foliage", "drawcalls"];

/// Scenes `--scenes` may name besides [`SCENES`], not in the suites: `demo`, what `vgeo` with no
/// arguments renders (so its speed comes with its error).
pub const EXTRA_SCENES: [&str; 1] = ["demo"];

/// Default `--reference-spp`: 4 x 4 samples per pixel.
pub const DEFAULT_REFERENCE_SPP: u32 = 16;

/// Default `--psnr-margin` (dB): "equal error" is a PSNR at most this far below brute's floor.
pub const DEFAULT_PSNR_MARGIN_DB: f64 = 1.0;

/// Default `--stream-mib-per-frame` (MiB), as `vgeo render`'s.
pub const DEFAULT_STREAM_MIB_PER_FRAME: f64 = 16.0;

/// Most frames a camera of the path is rendered (streaming between them) to settle before its
/// frame is timed, with `--geometry-budget`.
pub const SETTLE_FRAMES: u32 = 64;

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
                hw_path: HwPath::default(),
                reference_spp: DEFAULT_REFERENCE_SPP,
                psnr_margin_db: DEFAULT_PSNR_MARGIN_DB,
                geometry_budget: None,
                stream_mib_per_frame: DEFAULT_STREAM_MIB_PER_FRAME,
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
                hw_path: HwPath::default(),
                reference_spp: DEFAULT_REFERENCE_SPP,
                psnr_margin_db: DEFAULT_PSNR_MARGIN_DB,
                geometry_budget: None,
                stream_mib_per_frame: DEFAULT_STREAM_MIB_PER_FRAME,
            },
        }
    }
}

/// What a benchmark run does.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct BenchSettings {
    /// The suite these settings started from.
    pub suite: Suite,
    /// Image width in pixels.
    pub width: u32,
    /// Image height in pixels.
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
    /// vgeo: the SW/HW split ([`FrameSettings::hw_threshold_px`]: clusters whose triangles'
    /// projected edge-length equivalent exceeds this many pixels go to the hardware rasterizer).
    pub hw_threshold_px: f32,
    /// vgeo: how `emit_gbuffer` runs.
    pub emit: EmitPath,
    /// vgeo: how `raster_hw` draws (`auto`: vertex pulling, measured the faster).
    pub hw_path: HwPath,
    /// Samples per pixel of the reference (a square: n x n on a regular grid, box-filtered).
    pub reference_spp: u32,
    /// "Equal error": a mode's threshold qualifies when its PSNR is at most this many dB below
    /// brute's at one sample per pixel ([`EqualError`]).
    pub psnr_margin_db: f64,
    /// vgeo: stream the meshes' pages under this budget (`None`: every page resident). Each
    /// camera of the path is rendered until the streaming settles (no more uploads) before its
    /// frame is timed; [`StreamRecord`] reports the residency.
    pub geometry_budget: Option<GeometryBudget>,
    /// With a budget: most page bytes read and uploaded between two frames (MiB).
    pub stream_mib_per_frame: f64,
}

/// The rendering modes a benchmark compares.
pub const MODES: [&str; 3] = ["brute", "lod", "vgeo"];

/// Command-line arguments of `vgeo bench`.
#[derive(clap::Args, Clone, Debug)]
pub struct BenchArgs {
    /// Instead of the scenes: the CPU cost of a host's frame (set_transform of the changed
    /// instances, update_scene, record of one view) for scenes of these instance counts,
    /// comma-separated (e.g. 8000,125000,1000000); writes record_cpu.json and record_cpu.md.
    #[arg(long, value_delimiter = ',', value_name = "N,...")]
    pub record_cpu: Option<Vec<u32>>,
    /// With --record-cpu: transforms changed per frame, comma-separated.
    #[arg(long, value_delimiter = ',', default_value = "0,10000")]
    pub record_changed: Vec<u32>,
    /// `quick` (tiny, CI on lavapipe) or `full` (1920x1080, the real sizes).
    #[arg(long, default_value = "quick")]
    pub suite: String,
    /// Output folder (created): bench.json, bench.md, plots, images.
    #[arg(long, default_value = "bench-out")]
    pub out: PathBuf,
    /// Folder with the scene files (default: assets/scenes here, else in the source tree).
    #[arg(long)]
    pub scenes_dir: Option<PathBuf>,
    /// Scenes to run, comma-separated (outdoor, indoor, foliage, drawcalls, stress; also demo, the
    /// first-run scene, only when named); default the four and stress.
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
    /// vgeo, the SW/HW split: clusters whose triangles' edge-length equivalent (sqrt(2 x their
    /// area-weighted mean area), projected at the cluster's nearest point) exceeds this many
    /// pixels go to the hardware rasterizer (0: all to hardware; 100000: software only but the
    /// near plane's clusters). Default `auto`, the renderer's: chosen by measured frame time,
    /// settled on each scene's path before it is timed and then held (the split each scene was
    /// timed with is in bench.md's clusters column and the JSON's `hw_threshold_px`); streamed
    /// scenes keep 64.
    #[arg(long, value_parser = FrameSettings::parse_hw_threshold)]
    pub hw_threshold: Option<f32>,
    /// vgeo: `emit_gbuffer` as `compute` (default: a dispatch per material) or `raster` (a draw
    /// of tile quads per material against the material depth, DESIGN.md's form).
    #[arg(long)]
    pub emit: Option<String>,
    /// vgeo: `raster_hw` as `mesh` (a mesh-shader workgroup per cluster; needs
    /// VK_EXT_mesh_shader), `vertex` (vertex pulling) or `auto` (default: vertex, measured the faster).
    #[arg(long)]
    pub hw_path: Option<String>,
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
    /// vgeo: stream the meshes' geometry pages under this GPU budget (MiB), as `vgeo render
    /// --geometry-budget` does; `auto` (also the flag alone): a quarter of the device's largest
    /// device-local heap, at most what one storage buffer binds, printed at the start. Each
    /// camera of a path is rendered, streaming between frames, until nothing more is uploaded
    /// (at most 64 frames) before its frame is timed (then alone, after the warm-up);
    /// bench.json and bench.md report per scene and
    /// threshold the resident page bytes, their peak, requests, uploads, evictions and the
    /// bytes the last frame used. Default: every page resident.
    #[arg(long, value_name = "MIB|auto", num_args = 0..=1, default_missing_value = "auto")]
    pub geometry_budget: Option<String>,
    /// With --geometry-budget: most page bytes read and uploaded between two frames (MiB,
    /// default 16).
    #[arg(long, value_name = "MIB")]
    pub stream_mib_per_frame: Option<f64>,
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
                if SCENES.contains(&n.as_str()) || EXTRA_SCENES.contains(&n.as_str()) {
                    s.scenes.push(n.clone());
                } else if n != "stress" {
                    bail!(
                        "unknown scene `{n}` in --scenes (available: {}, {}, stress)",
                        SCENES.join(", "),
                        EXTRA_SCENES.join(", ")
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
        if let Some(p) = &self.hw_path {
            s.hw_path = HwPath::parse(p).with_context(|| {
                format!("unknown --hw-path `{p}` (available: auto, mesh, vertex)")
            })?;
        }
        if let Some(n) = self.reference_spp {
            s.reference_spp = n;
        }
        if let Some(m) = self.psnr_margin {
            s.psnr_margin_db = m;
        }
        if let Some(b) = &self.geometry_budget {
            s.geometry_budget = Some(
                GeometryBudget::parse(b).map_err(|e| anyhow::anyhow!("--geometry-budget: {e}"))?,
            );
        }
        if let Some(m) = self.stream_mib_per_frame {
            if s.geometry_budget.is_none() {
                bail!("--stream-mib-per-frame needs --geometry-budget");
            }
            s.stream_mib_per_frame = m;
        }
        s.validate()?;
        Ok(s)
    }
}

impl BenchSettings {
    /// The sweep's threshold closest to 1 px (the headline figure).
    pub fn first_one_px(&self) -> Option<f32> {
        self.error_sweep
            .iter()
            .copied()
            .min_by(|a, b| (a - 1.0).abs().total_cmp(&(b - 1.0).abs()))
    }

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
        if self.hw_threshold_px.is_nan() {
            bail!("the hardware-rasterizer threshold must be `auto` or a number >= 0 (pixels)");
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
        if !(self.stream_mib_per_frame.is_finite() && self.stream_mib_per_frame > 0.0) {
            bail!("the streaming bytes per frame must be a positive number of MiB");
        }
        if self.geometry_budget == Some(GeometryBudget::Bytes(0)) {
            bail!("the geometry budget must be positive");
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
    // `--hw-path mesh` on a device without mesh shaders fails here, before any scene loads.
    let hw_path = (settings.hw_path.resolve(caps))
        .map_err(|e| anyhow::anyhow!("--hw-path {}: {e}", settings.hw_path.name()))?;
    let mut report = BenchReport {
        device: caps.device_name.clone(),
        driver: format!("{} {}", caps.driver_name, caps.driver_info),
        api_version: caps.api_version.clone(),
        validation: caps.validation,
        commit: git_commit(),
        date: utc_now(),
        settings: settings.clone(),
        hw_path: hw_path.name().into(),
        scenes: Vec::new(),
        records: Vec::new(),
        summary: Vec::new(),
        equal_error: Vec::new(),
        skipped: Vec::new(),
        memory: Vec::new(),
        streaming: Vec::new(),
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

/// `vgeo bench`: runs the suite and writes the outputs; prints where they are.
pub fn run_bench(args: &BenchArgs) -> Result<()> {
    let settings = args.settings()?;
    let scenes_dir = args.scenes_dir.clone().unwrap_or_else(default_scenes_dir);
    let ctx =
        Context::new(&crate::gpu::ContextOptions::from_env()).context("cannot start Vulkan")?;
    if let Some(counts) = &args.record_cpu {
        if counts.contains(&0) {
            bail!("--record-cpu: instance counts must be at least 1");
        }
        let frames = args.frames.unwrap_or(20).max(1);
        let size = (settings.width, settings.height);
        let rows = record_cpu::measure(&ctx, counts, &args.record_changed, frames, size)?;
        let md = record_cpu::markdown(&rows, &ctx.caps().device_name);
        std::fs::create_dir_all(&args.out)
            .with_context(|| format!("creating {}", args.out.display()))?;
        std::fs::write(args.out.join("record_cpu.md"), &md)?;
        std::fs::write(
            args.out.join("record_cpu.json"),
            serde_json::to_string_pretty(&rows)?,
        )?;
        print!("{md}");
        println!("wrote {}", args.out.display());
        return Ok(());
    }
    if let Some(b) = settings.geometry_budget {
        println!("{}", b.describe_on(ctx.caps()));
    }
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
    use crate::imgerr::{ImageError, psnr};

    /// `--scenes` takes the demo when named, not by default, and refuses unknown names.
    #[test]
    fn scenes_name_the_demo_only_when_asked() {
        #[derive(clap::Parser)]
        struct Cli {
            #[command(flatten)]
            bench: BenchArgs,
        }
        use clap::Parser as _;
        let parse = |args: &[&str]| {
            let mut v = vec!["bench"];
            v.extend_from_slice(args);
            Cli::try_parse_from(v).unwrap().bench.settings()
        };
        let s = parse(&["--scenes", "demo,outdoor"]).unwrap();
        assert_eq!(s.scenes, ["demo", "outdoor"]);
        assert!(!parse(&[]).unwrap().scenes.iter().any(|n| n == "demo"));
        assert!(parse(&["--scenes", "dmeo"]).is_err());
    }

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
            hw_clusters: None,
            hw_threshold_px: None,
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
            hw_path: "vertex".into(),
            scenes: vec![info],
            records,
            summary: Vec::new(),
            equal_error: Vec::new(),
            skipped: Vec::new(),
            memory: Vec::new(),
            streaming: Vec::new(),
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
        assert_eq!(full.first_one_px(), Some(1.0));
    }
}
