//! The bench's records ([`BenchReport`]: every measured frame, summaries, skips, memory) and its
//! outputs: `bench.json`, `bench.md`, SVG plots and example images.

use std::path::{Path, PathBuf};

use anyhow::{Context as _, Result};
use serde::Serialize;

use super::{BenchSettings, MODES};
use crate::Frame;
use crate::imgerr::ImageError;

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
    /// Of those, clusters the hardware rasterizer drew (vgeo only; the rest went to software).
    pub hw_clusters: Option<u64>,
    /// The SW/HW split the frame was timed with (vgeo only; with `--hw-threshold auto`, the
    /// threshold the renderer settled on before timing).
    pub hw_threshold_px: Option<f32>,
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
    /// Clusters to the hardware rasterizer (vgeo).
    pub hw_clusters_mean: Option<f64>,
    /// vgeo: the SW/HW split its frames were timed with ([`FrameRecord::hw_threshold_px`]).
    pub hw_threshold_px: Option<f32>,
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
    /// The path `raster_hw` took on the device (`mesh` or `vertex`: `settings.hw_path` resolved).
    pub hw_path: String,
    pub scenes: Vec<SceneInfo>,
    pub records: Vec<FrameRecord>,
    pub summary: Vec<Summary>,
    /// Per scene and mode (lod, vgeo): the threshold picked "at equal error".
    pub equal_error: Vec<EqualError>,
    pub skipped: Vec<Skipped>,
    /// GPU memory per scene and mode.
    pub memory: Vec<MemoryRecord>,
    /// vgeo's streaming per scene and threshold (with `--geometry-budget`; empty otherwise).
    pub streaming: Vec<StreamRecord>,
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

/// vgeo under a geometry budget (`--geometry-budget`): the streaming of one scene at one
/// threshold, over its whole path (each camera settled before its frame was timed).
#[derive(Clone, Debug, Serialize)]
pub struct StreamRecord {
    pub scene: String,
    pub error_px: f32,
    /// The budget the pages stream under (bytes), and one page slot's bytes.
    pub budget_bytes: u64,
    pub slot_bytes: u64,
    /// Page bytes resident after the path's last frame: the always-resident pages and the slots
    /// in use (counted whole).
    pub resident_bytes: u64,
    /// The most page bytes resident after any streaming step of the path.
    pub peak_resident_bytes: u64,
    /// Over the path, settling included: pages the cull asked for (summed over the steps), pages
    /// loaded and their bytes, pages evicted, pages that could not be read.
    pub requests: u64,
    pub uploads: u64,
    pub upload_bytes: u64,
    pub evictions: u64,
    pub failed: u64,
    /// Page bytes the path's last frame used (pages holding a drawn cluster): what its cut needs
    /// resident.
    pub used_bytes_last_frame: u64,
    /// Pages the cull still asked for after the last frame (0: everything the view wants is
    /// resident; more: the budget or the per-frame uploads did not allow it).
    pub requests_last_frame: u64,
    /// The most frames a camera of the path was rendered to settle (no more uploads), and
    /// whether every camera settled within [`super::SETTLE_FRAMES`].
    pub settle_frames_max: u32,
    pub settled: bool,
    /// Pages that could not be read, one line each.
    pub errors: Vec<String>,
    /// Mean GPU ms of the path's frames, each timed once its camera settled.
    #[serde(default)]
    pub gpu_ms_mean: f64,
    /// The same cameras with every page resident (timed the same way, by a renderer of its own),
    /// when the scene fits the device that way (`None`: it does not, or it failed).
    #[serde(default)]
    pub resident_gpu_ms_mean: Option<f64>,
    /// Wall seconds of the settling (frames and streaming steps until each camera settled): the
    /// uploaded bytes over them are the rate the views were served at.
    #[serde(default)]
    pub settle_seconds: f64,
}

pub(super) fn git_commit() -> Option<String> {
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
pub(super) fn utc_now() -> String {
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
        const TRIANGLES: &str = "scene triangles (instanced, full detail)";
        type Axes = fn(&(f64, f64, f64, f64)) -> (f64, f64);
        let plots: [(&str, &str, &str, &str, Axes); 3] = [
            (
                "stress_scaling.svg",
                "stress: GPU time against scene triangles (1 px)",
                TRIANGLES,
                "GPU ms per frame",
                |x| (x.0, x.1),
            ),
            (
                "stress_memory.svg",
                "stress: GPU memory (geometry + instances) against scene triangles",
                TRIANGLES,
                "MiB",
                |x| (x.0, x.2),
            ),
            (
                "stress_instances.svg",
                "stress: GPU time against instances (1 px)",
                "instances",
                "GPU ms per frame",
                |x| (x.3, x.1),
            ),
        ];
        for (file, title, x_desc, y_desc, axes) in plots {
            let series: Vec<(String, Vec<(f64, f64)>)> = scaling
                .iter()
                .map(|(m, p)| (m.clone(), p.iter().map(axes).collect()))
                .collect();
            plot_scaling(&out.join(file), title, x_desc, y_desc, &series)?;
        }
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

/// Per mode: (scene triangles, GPU ms, MiB, instances) for each stress grid, at the sweep's
/// threshold nearest 1 px (a fixed threshold, not equal error: the largest grids have no
/// reference).
type ScalingSeries = Vec<(String, Vec<(f64, f64, f64, f64)>)>;

fn scaling_series(report: &BenchReport) -> ScalingSeries {
    let one = report.settings.first_one_px();
    ["brute", "lod", "vgeo"]
        .iter()
        .map(|mode| {
            let mut pts: Vec<(f64, f64, f64, f64)> = report
                .summary
                .iter()
                .filter(|s| s.scene.starts_with("stress_n") && s.mode == *mode)
                .filter(|s| *mode == "brute" || s.error_px == one)
                .map(|s| {
                    let instances = report
                        .scenes
                        .iter()
                        .find(|i| i.name == s.scene)
                        .map_or(0.0, |i| i.instances as f64);
                    (
                        s.scene_triangles as f64,
                        s.gpu_ms_mean,
                        (s.geometry_bytes + s.instance_bytes) as f64 / (1u64 << 20) as f64,
                        instances,
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
    x_desc: &str,
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
        .x_desc(x_desc)
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
        "- {}x{}, {} frames per path, thresholds {:?} px, modes {}, vgeo hardware-rasterizer threshold {} ({} path), emit_gbuffer {:?}; GPU ms from timestamps, frames of the path recorded back to back in one submission (no read-back, no CPU wait between them; heavy frames in submissions of ~100 ms) after ~0.5 s of GPU warm-up, mean over the path; CPU ms: a submission's wall time over its frames; images and counters from a second pass with read-back",
        s.width,
        s.height,
        s.frames,
        s.error_sweep,
        s.modes.join(", "),
        if s.hw_threshold_px < 0.0 {
            "auto (settled per scene and threshold before timing, in the clusters column)".into()
        } else {
            format!("{} px", s.hw_threshold_px)
        },
        report.hw_path,
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
                match (r.clusters_mean, r.hw_clusters_mean) {
                    (Some(c), Some(h)) => match r.hw_threshold_px {
                        Some(t) if t >= crate::frame::split::SOFTWARE_ONLY_PX => {
                            format!("{c:.0} ({h:.0} HW, split: software only)")
                        }
                        Some(t) => format!("{c:.0} ({h:.0} HW, split {t} px)"),
                        None => format!("{c:.0} ({h:.0} HW)"),
                    },
                    (c, _) => fmt_opt(c, |c| format!("{c:.0}")),
                },
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
        let streamed: Vec<&StreamRecord> = (report.streaming.iter())
            .filter(|r| r.scene == info.name)
            .collect();
        if let Some(first) = streamed.first() {
            let _ = writeln!(
                md,
                "vgeo streamed under a geometry budget of {:.2} MiB (slots of {:.1} KiB; each camera settled before its frame was timed; counts over the path, settling included; GPU ms all resident: the same cameras, every page resident, timed the same way; upload MiB/s: uploaded MiB over the settling's wall time):\n\n| px | GPU ms streamed | GPU ms all resident | resident MiB | peak resident MiB | used by the last frame MiB | requests | uploads | uploaded MiB | upload MiB/s | evictions | failed | still requested | frames to settle (most) |\n|---|---|---|---|---|---|---|---|---|---|---|---|---|---|",
                mib(first.budget_bytes),
                first.slot_bytes as f64 / 1024.0
            );
            for r in streamed {
                let _ = writeln!(
                    md,
                    "| {} | {:.3} | {} | {:.2} | {:.2} | {:.2} | {} | {} | {:.2} | {} | {} | {} | {} | {}{} |",
                    r.error_px,
                    r.gpu_ms_mean,
                    fmt_opt(r.resident_gpu_ms_mean, |x| format!("{x:.3}")),
                    mib(r.resident_bytes),
                    mib(r.peak_resident_bytes),
                    mib(r.used_bytes_last_frame),
                    r.requests,
                    r.uploads,
                    mib(r.upload_bytes),
                    if r.settle_seconds > 0.0 {
                        format!("{:.0}", mib(r.upload_bytes) / r.settle_seconds)
                    } else {
                        "-".into()
                    },
                    r.evictions,
                    r.failed,
                    r.requests_last_frame,
                    r.settle_frames_max,
                    if r.settled { "" } else { " (not settled)" }
                );
            }
            md.push('\n');
        }
    }
    let scaling = scaling_series(report);
    if scaling.iter().any(|(_, p)| !p.is_empty()) {
        md.push_str("## stress scaling (threshold nearest 1 px, not equal error)\n\n| mode | instances | scene triangles | GPU ms | MiB (geometry + instances) |\n|---|---|---|---|---|\n");
        for (mode, pts) in &scaling {
            for p in pts {
                let _ = writeln!(
                    md,
                    "| {mode} | {:.0} | {:.3e} | {:.3} | {:.1} |",
                    p.3, p.0, p.1, p.2
                );
            }
        }
        md.push('\n');
    }
    md
}

fn mib(bytes: u64) -> f64 {
    bytes as f64 / (1u64 << 20) as f64
}
