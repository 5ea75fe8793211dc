//! `vgeo bench --record-cpu N,...`: the CPU cost of a host's frame, what an engine pays on its
//! render thread per frame: [`VgeoRenderer::update_scene_cmd`] (the changed instances staged and
//! their copy recorded) and [`VgeoRenderer::record_cmd`] (the whole frame recorded), for scenes of
//! N instances, with nothing changed and with `--record-changed` transforms changed per frame
//! (their `set_transform` calls timed too). Each frame is submitted and waited for outside the
//! timed span, so only the CPU work is measured.

use std::time::Instant;

use anyhow::{Context as _, Result};
use glam::{DMat4, DVec3};
use serde::Serialize;

use crate::Camera;
use crate::FrameSettings;
use crate::ShadeMode;
use crate::gpu::{CmdCounts, Context, GpuError, RenderTarget};
use crate::{BuildOptions, BuiltMesh};
use crate::{HostTargets, Renderer as VgeoRenderer, ViewFrame};
use crate::{Light, Placement};

/// One measured configuration.
#[derive(Clone, Debug, Serialize)]
pub struct RecordCpuRow {
    /// Instances in the scene.
    pub instances: u32,
    /// Transforms changed per frame.
    pub changed: u32,
    /// Median CPU ms per frame: `set_transform` of the changed instances.
    pub set_transform_ms: f64,
    /// Median CPU ms per frame: `update_scene_cmd`.
    pub update_ms: f64,
    /// Median CPU ms per frame: `record_cmd` of one view.
    pub record_ms: f64,
    /// Median CPU ms per frame, all three.
    pub total_ms: f64,
    /// Frames measured (after warm-up).
    pub frames: u32,
    /// Vulkan commands `record_cmd` recorded in the last frame, by kind.
    pub commands: CmdCounts,
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(0.0)
}

/// A grid of `n` instances of `mesh`, one unit apart, in front of the camera.
fn grid(n: u32) -> Vec<Placement> {
    let side = (n as f64).sqrt().ceil() as u32;
    (0..n)
        .map(|i| Placement {
            mesh: 0,
            transform: DMat4::from_translation(DVec3::new(
                (i % side) as f64 - side as f64 / 2.0,
                0.0,
                -((i / side) as f64) - 2.0,
            )),
            color: [1.0; 3],
        })
        .collect()
}

/// Measures every (instances, changed) pair over `frames` frames after 3 warm-up frames, at
/// `width` x `height`, into a depth target only (no material pass: the recording is what is
/// timed, the same either way).
pub fn measure(
    ctx: &Context,
    counts: &[u32],
    changed: &[u32],
    frames: u32,
    (width, height): (u32, u32),
) -> Result<Vec<RecordCpuRow>> {
    let mesh = crate::scene::generated::generated_mesh("box").context("the generated box")?;
    let built: BuiltMesh = crate::builder::build(&mesh, &BuildOptions::default())
        .map_err(|e| anyhow::anyhow!("{e}"))?;
    let camera = Camera::look_at(
        DVec3::new(0.0, 20.0, 30.0),
        DVec3::new(0.0, 0.0, -40.0),
        glam::Vec3::Y,
        50f32.to_radians(),
        0.05,
    );
    let mut rows = Vec::new();
    for &n in counts {
        let placements = grid(n);
        let mut r = VgeoRenderer::new(ctx, std::slice::from_ref(&built), &placements)?;
        let mut view = r.create_view("record_cpu", width, height, 2)?;
        let depth = crate::gpu::Image::new(
            ctx,
            "record_cpu depth",
            width,
            height,
            crate::frame::HOST_DEPTH_FORMAT,
            crate::gpu::vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
                | crate::gpu::vk::ImageUsageFlags::TRANSFER_SRC
                | crate::gpu::vk::ImageUsageFlags::TRANSFER_DST,
        )?;
        let handles: Vec<_> = (0..n)
            .map(|j| r.scene.instance_handle(j))
            .collect::<Option<_>>()
            .context("an instance without a handle")?;
        for &c in changed {
            let c = c.min(n);
            let (mut set_ms, mut upd_ms, mut rec_ms) = (Vec::new(), Vec::new(), Vec::new());
            let mut commands = CmdCounts::default();
            for f in 0..frames + 3 {
                let t0 = Instant::now();
                for (j, &h) in handles.iter().take(c as usize).enumerate() {
                    let p = &placements[j];
                    let up = DMat4::from_translation(DVec3::new(0.0, 0.01 * (f % 7) as f64, 0.0));
                    r.scene
                        .set_transform(h, &(up * p.transform))
                        .map_err(GpuError::from)?;
                }
                let t_set = t0.elapsed().as_secs_f64() * 1e3;
                // The host's own pass: clears its depth (untimed, its own submission).
                ctx.submit_and_wait("record_cpu clear", |cmd| {
                    cmd.begin_rendering(
                        &[],
                        Some(RenderTarget {
                            image: &depth,
                            clear: Some([0.0; 4]),
                        }),
                    );
                    cmd.end_rendering();
                })?;
                let frame = ViewFrame {
                    frame: f as u64,
                    camera: &camera,
                    settings: FrameSettings::default(),
                    light: Light::default(),
                    shade: ShadeMode::Lit,
                    targets: HostTargets {
                        depth: Some(depth.as_host()),
                        color: None,
                        gbuffer: None,
                    },
                };
                let (mut t_upd, mut t_rec) = (0.0, 0.0);
                let mut res = Ok(());
                ctx.submit_and_wait("record_cpu", |cmd| {
                    let t1 = Instant::now();
                    res = r.update_scene_cmd(cmd, &mut [&mut view]);
                    t_upd = t1.elapsed().as_secs_f64() * 1e3;
                    if res.is_ok() {
                        let before = *cmd.counts();
                        let t2 = Instant::now();
                        res = r.record_cmd(cmd, &mut view, &frame);
                        t_rec = t2.elapsed().as_secs_f64() * 1e3;
                        commands = cmd.counts().since(&before);
                    }
                })?;
                res?;
                if f >= 3 {
                    set_ms.push(t_set);
                    upd_ms.push(t_upd);
                    rec_ms.push(t_rec);
                }
            }
            let total: Vec<f64> = (0..set_ms.len())
                .map(|i| set_ms[i] + upd_ms[i] + rec_ms[i])
                .collect();
            rows.push(RecordCpuRow {
                instances: n,
                changed: c,
                set_transform_ms: median(set_ms),
                update_ms: median(upd_ms),
                record_ms: median(rec_ms),
                total_ms: median(total),
                frames,
                commands,
            });
        }
    }
    Ok(rows)
}

/// The rows as a Markdown table.
pub fn markdown(rows: &[RecordCpuRow], device: &str) -> String {
    let mut s = format!(
        "CPU ms per host frame (median), {device}: set_transform of the changed instances, \
         update_scene, record of one view\n\n\
         | instances | changed | set_transform ms | update_scene ms | record ms | total ms | commands recorded |\n\
         |---|---|---|---|---|---|---|\n"
    );
    for r in rows {
        let c = &r.commands;
        s.push_str(&format!(
            "| {} | {} | {:.4} | {:.4} | {:.4} | {:.4} | {} ({} barriers, {} dispatches, {} draws, \
             {} bindings, {} transfers, {} labels, {} timestamps, {} other) |\n",
            r.instances,
            r.changed,
            r.set_transform_ms,
            r.update_ms,
            r.record_ms,
            r.total_ms,
            c.total(),
            c.barriers,
            c.dispatches,
            c.draws,
            c.bindings,
            c.transfers,
            c.labels,
            c.timestamps,
            c.other
        ));
    }
    s
}
