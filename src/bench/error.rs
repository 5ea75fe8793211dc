//! Speed against error: per (scene, mode, threshold) summaries of the records (means of GPU
//! time, triangles and image error; PSNR below brute's one-sample floor) and, per scene and mode,
//! the cheapest threshold at equal error. The image metric itself is [`crate::imgerr`].

use super::report::{BenchReport, EqualError, FrameRecord, Summary};
use crate::imgerr::{ImageError, psnr};

fn mean(v: impl Iterator<Item = f64>) -> Option<f64> {
    let (mut s, mut n) = (0.0, 0usize);
    for x in v {
        s += x;
        n += 1;
    }
    (n > 0).then(|| s / n as f64)
}

pub(super) fn summarize(report: &BenchReport) -> Vec<Summary> {
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
                hw_clusters_mean: mean(rs.iter().filter_map(|r| r.hw_clusters.map(|c| c as f64))),
                hw_threshold_px: rs.iter().find_map(|r| r.hw_threshold_px),
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
pub(super) fn equal_error(report: &BenchReport) -> Vec<EqualError> {
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
