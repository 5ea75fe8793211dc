//! Rendering one scene in every mode: each path timed (frames back to back in one submission,
//! after a warm-up), then rendered again with read-back for the counters and the image error
//! against brute's supersampled reference.

use std::collections::HashMap;
use std::time::Instant;

use anyhow::{Result, bail};
use indicatif::ProgressBar;

use super::BenchSettings;
use super::report::{BenchReport, FrameRecord, MemoryRecord, Skipped};
use super::scenes::BenchScene;
use crate::BruteRenderer as Brute;
use crate::Camera;
use crate::Context;
use crate::Frame;
use crate::FrameSettings;
use crate::Renderer as VgeoRenderer;
use crate::ViewMode;
use crate::imgerr::{Reference, image_error};
use crate::{LodOptions, LodRenderer as Lod};

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
pub(super) struct SceneTimes {
    /// Building the cluster DAGs not built yet.
    pub(super) build_s: f64,
    /// Rendering the supersampled references.
    pub(super) reference_s: f64,
}

/// Runs one scene in every mode.
pub(super) fn run_scene(
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
    } else if e == report.settings.first_one_px() {
        report
            .images
            .push((format!("{scene}_{mode}_1px"), frame.clone()));
    }
}
