//! Rendering one scene in every mode: each path timed (frames back to back in one submission,
//! after a warm-up), then rendered again with read-back for the counters and the image error
//! against brute's supersampled reference.

use std::collections::HashMap;
use std::time::Instant;

use anyhow::{Result, bail};
use indicatif::ProgressBar;

use super::report::{BenchReport, FrameRecord, MemoryRecord, Skipped, StreamRecord};
use super::scenes::BenchScene;
use super::{BenchSettings, SETTLE_FRAMES};
use crate::BruteRenderer as Brute;
use crate::Camera;
use crate::Context;
use crate::Frame;
use crate::FrameSettings;
use crate::Renderer as VgeoRenderer;
use crate::ViewMode;
use crate::imgerr::{Reference, image_error};
use crate::{BuiltMesh, PageSource, Placement, StreamOptions, StreamStats, Streamer};
use crate::{LodOptions, LodRenderer as Lod};

/// The memory a mode holds for a scene: (geometry bytes, instance bytes).
type Memory = (u64, u64);

/// GPU ms per pass of one frame.
type PassTimes = Vec<(String, f64)>;

/// How long the GPU is kept busy before a path is timed (see [`time_path`]).
const WARMUP_MS: f64 = 500.0;

/// Most wall time the automatic SW/HW split may take to settle before a path is timed
/// ([`crate::frame::VgeoRenderer::settle_split`]).
const SPLIT_SETTLE_MS: f64 = 5000.0;

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
                hw_clusters: None,
                hw_threshold_px: None,
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
        let lod_instance_bytes = lod.instance_bytes(scene.placements.len());
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
                let (frame, stats) = lod.render_with_stats(
                    &scene.placements,
                    cam,
                    &scene.light,
                    (w, h),
                    e,
                    crate::material::ShadeMode::Lit,
                )?;
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
                    hw_clusters: None,
                    hw_threshold_px: None,
                    instances_visible: Some(stats.drawn() as u64),
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
    let stream = settings.geometry_budget.map(|b| StreamOptions {
        budget_bytes: b.bytes_on(ctx.caps()),
        upload_bytes_per_frame: (settings.stream_mib_per_frame * (1u64 << 20) as f64) as u64,
    });
    let mut vgeo = match &built {
        None => {
            bar.inc(frames * sweep.len() as u64);
            None
        }
        Some(built) => match new_vgeo(ctx, built, &scene.placements, stream) {
            Ok(r) => Some(r),
            Err(err) => {
                skip(report, "vgeo", None, format!("failed: {err:#}"));
                bar.inc(frames * sweep.len() as u64);
                None
            }
        },
    };
    if let Some((r, streamer)) = vgeo.as_mut() {
        r.set_emit_path(settings.emit);
        r.set_hw_path(settings.hw_path)
            .map_err(|e| anyhow::anyhow!("--hw-path {}: {e}", settings.hw_path.name()))?;
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
            if let Some(streamer) = streamer.as_mut() {
                // Streamed frames are timed one by one while pages land: the split stays at the
                // fixed default (settling would draw frames the streamer never saw), and the
                // all-resident frames it is compared with take the same.
                let fs = FrameSettings {
                    hw_threshold_px: FrameSettings::fixed_split(fs.hw_threshold_px),
                    ..fs
                };
                let budget = stream.map_or(0, |o| o.budget_bytes);
                run_streamed(
                    settings,
                    scene,
                    r,
                    streamer,
                    (&fs, budget),
                    &reference,
                    report,
                    bar,
                )?;
                // The same cameras with every page resident, where the scene fits that way.
                if let Some(built) = &built {
                    let resident = new_vgeo(ctx, built, &scene.placements, None)
                        .and_then(|(mut full, _)| {
                            full.set_emit_path(settings.emit);
                            full.set_hw_path(settings.hw_path)?;
                            resident_gpu_ms(settings, scene, &mut full, &fs)
                        })
                        .ok();
                    if let Some(last) = report.streaming.last_mut() {
                        last.resident_gpu_ms_mean = resident;
                    }
                }
                continue;
            }
            // The automatic split settles on the path's first frames (a fresh round at each
            // threshold) and is then held: no timed frame probes another (the same split for
            // the read-back pass below).
            let fs = FrameSettings {
                hw_threshold_px: r.settle_split(
                    &scene.cameras,
                    w,
                    h,
                    &fs,
                    ViewMode::Lit,
                    &scene.light,
                    SPLIT_SETTLE_MS,
                )?,
                ..fs
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
                let rec = vgeo_record(name, &fs, f, &vf, passes, cpu_ms, reference[f].as_ref())?;
                report.records.push(rec);
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

/// vgeo's renderer for a scene: every page resident, or with `stream` the meshes added with
/// only their always-resident pages and a [`Streamer`] for the rest (as `vgeo render
/// --geometry-budget` builds it; the pages come from the built meshes in memory).
fn new_vgeo(
    ctx: &Context,
    built: &[&BuiltMesh],
    placements: &[Placement],
    stream: Option<StreamOptions>,
) -> Result<(VgeoRenderer, Option<Streamer>)> {
    let Some(opts) = stream else {
        return Ok((VgeoRenderer::new(ctx, built, placements)?, None));
    };
    let sources: Vec<(BuiltMesh, Box<dyn PageSource>)> = built
        .iter()
        .map(|&b| (b.clone(), Box::new(b.clone()) as Box<dyn PageSource>))
        .collect();
    let (r, streamer) = VgeoRenderer::streamed(ctx, sources, placements, opts)?;
    Ok((r, Some(streamer)))
}

/// A vgeo frame's record: counters from the read-back frame `vf`, times from its timed run with
/// settings `fs`.
fn vgeo_record(
    scene: &str,
    fs: &FrameSettings,
    f: usize,
    vf: &crate::VgeoFrame,
    passes: PassTimes,
    cpu_ms: f64,
    reference: Option<&Reference>,
) -> Result<FrameRecord> {
    let (m, p) = (&vf.main.counters, &vf.post.counters);
    let error = match reference {
        Some(rf) => Some(image_error(rf, &vf.frame)?),
        None => None,
    };
    Ok(FrameRecord {
        scene: scene.to_string(),
        mode: "vgeo".into(),
        error_px: Some(fs.error_px),
        frame: f as u32,
        gpu_ms: passes.iter().map(|p| p.1).sum(),
        passes,
        cpu_ms,
        triangles: vf.frame.triangles,
        clusters: Some((m.sw_count + m.hw_count) as u64 + (p.sw_count + p.hw_count) as u64),
        hw_clusters: Some(m.hw_count as u64 + p.hw_count as u64),
        hw_threshold_px: Some(fs.hw_threshold_px),
        instances_visible: Some(m.instances_visible as u64 + p.instances_visible as u64),
        error,
    })
}

/// One streaming step after a frame, added to `rec`'s totals.
fn stream_step(
    r: &mut VgeoRenderer,
    streamer: &mut Streamer,
    rec: &mut StreamRecord,
) -> Result<StreamStats> {
    let st = streamer.update(&mut r.scene)?;
    rec.errors.extend(streamer.take_errors());
    rec.requests += st.requests;
    rec.uploads += st.uploads;
    rec.upload_bytes += st.upload_bytes;
    rec.evictions += st.evictions;
    rec.failed += st.failed;
    rec.resident_bytes = st.resident_bytes;
    rec.peak_resident_bytes = rec.peak_resident_bytes.max(st.resident_bytes);
    Ok(st)
}

/// vgeo at threshold `fs.error_px` along the path, streaming under the budget: per camera,
/// frames rendered with a streaming step after each until a step uploads nothing (settled: what
/// the view wants is resident, or the budget holds no more of it; at most [`SETTLE_FRAMES`]),
/// then the frame timed alone ([`time_path`], with the warm-up: the settling's waits let the GPU
/// clock fall) with the residency fixed, then rendered with read-back for its record, and its
/// usage and remaining requests read by one more step. The occlusion history flows along the
/// path. Pushes the frames' records and one [`StreamRecord`].
#[allow(clippy::too_many_arguments)]
fn run_streamed(
    settings: &BenchSettings,
    scene: &BenchScene,
    r: &mut VgeoRenderer,
    streamer: &mut Streamer,
    (fs, budget_bytes): (&FrameSettings, u64),
    reference: &[Option<Reference>],
    report: &mut BenchReport,
    bar: &ProgressBar,
) -> Result<()> {
    let (w, h) = (settings.width, settings.height);
    let name = &scene.info.name;
    let e = fs.error_px;
    let mut rec = StreamRecord {
        scene: name.clone(),
        error_px: e,
        budget_bytes,
        slot_bytes: streamer.slot_bytes(),
        resident_bytes: 0,
        peak_resident_bytes: 0,
        requests: 0,
        uploads: 0,
        upload_bytes: 0,
        evictions: 0,
        failed: 0,
        used_bytes_last_frame: 0,
        requests_last_frame: 0,
        settle_frames_max: 0,
        settled: true,
        errors: Vec::new(),
        gpu_ms_mean: 0.0,
        resident_gpu_ms_mean: None,
        settle_seconds: 0.0,
    };
    let mut gpu_ms = Vec::new();
    r.reset_history();
    let light = &scene.light;
    for (f, cam) in scene.cameras.iter().enumerate() {
        let one = std::slice::from_ref(cam);
        let mut settle = 0;
        let settling = Instant::now();
        loop {
            if settle == SETTLE_FRAMES {
                rec.settled = false;
                break;
            }
            r.render_path_timed(one, w, h, fs, ViewMode::Lit, light)?;
            settle += 1;
            if stream_step(r, streamer, &mut rec)?.settled() {
                break;
            }
        }
        rec.settle_seconds += settling.elapsed().as_secs_f64();
        rec.settle_frames_max = rec.settle_frames_max.max(settle);
        let timed = time_path(settings.warmup, one, |_, cams| {
            Ok(r.render_path_timed(cams, w, h, fs, ViewMode::Lit, light)?)
        })?;
        let Some((passes, cpu_ms)) = timed.into_iter().next() else {
            bail!("{name}: frame {f} was not timed");
        };
        gpu_ms.push(passes.iter().map(|p| p.1).sum::<f64>());
        let vf = r.render(cam, w, h, fs, ViewMode::Lit, light)?;
        if let Err(msg) = vf.check() {
            report.skipped.push(Skipped {
                scene: name.clone(),
                mode: "vgeo".into(),
                error_px: Some(e),
                reason: format!("failed at frame {f}: {msg}"),
            });
            bar.inc(scene.cameras.len() as u64 - f as u64);
            break;
        }
        report.records.push(vgeo_record(
            name,
            fs,
            f,
            &vf,
            passes,
            cpu_ms,
            reference[f].as_ref(),
        )?);
        save_example(report, name, "vgeo", Some(e), f, &vf.frame, None);
        let st = stream_step(r, streamer, &mut rec)?;
        rec.used_bytes_last_frame = st.used_bytes;
        rec.requests_last_frame = st.requests;
        bar.inc(1);
    }
    rec.gpu_ms_mean = gpu_ms.iter().sum::<f64>() / gpu_ms.len().max(1) as f64;
    report.streaming.push(rec);
    Ok(())
}

/// The mean GPU ms of `scene`'s cameras at `fs` with every page resident, each camera rendered
/// once (its occlusion history) and then timed alone as [`run_streamed`] times a settled one.
fn resident_gpu_ms(
    settings: &BenchSettings,
    scene: &BenchScene,
    r: &mut VgeoRenderer,
    fs: &FrameSettings,
) -> Result<f64> {
    let (w, h) = (settings.width, settings.height);
    let mut sum = 0.0;
    r.reset_history();
    for cam in &scene.cameras {
        let one = std::slice::from_ref(cam);
        r.render_path_timed(one, w, h, fs, ViewMode::Lit, &scene.light)?;
        let timed = time_path(settings.warmup, one, |_, cams| {
            Ok(r.render_path_timed(cams, w, h, fs, ViewMode::Lit, &scene.light)?)
        })?;
        sum += timed
            .first()
            .map_or(0.0, |(p, _)| p.iter().map(|x| x.1).sum::<f64>());
    }
    Ok(sum / scene.cameras.len().max(1) as f64)
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
