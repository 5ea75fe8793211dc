//! Streaming (issue 13) on lavapipe: a mesh kept resident under a budget of 1/8 of its pages'
//! bytes, its pages loaded on the cull's requests. Along a camera path every frame's cut equals
//! the CPU cut under the residency it was drawn with, is crack-free (every leaf-to-root path of the
//! DAG crosses it once), draws only resident pages, and resident bytes never exceed the budget;
//! once the camera stops, the visibility buffer equals the all-resident one bit for bit within a
//! bounded number of frames. Pages that cannot be read are reported once and the mesh stays
//! coarser, without a panic or a validation error.

mod common;

#[allow(dead_code)]
#[path = "../examples/stream_sizes.rs"]
mod stream_sizes;

use std::collections::BTreeSet;

use common::{assert_no_validation_errors, gpu, shared_assets};
use glam::{DMat4, DVec3, Vec3};
use vgeo::builder::page::{close_residency, group_needs, paginate};
use vgeo::builder::{BuiltMesh, build};
use vgeo::camera::Camera;
use vgeo::frame::{VgeoFrame, VgeoRenderer};
use vgeo::passes::debug_view::ViewMode;
use vgeo::passes::view::FrameSettings;
use vgeo::reference::cut::{reference_cut_resident, view_for};
use vgeo::render::{Light, Placement};
use vgeo::scene_gpu::InstanceDesc;
use vgeo::shared::VIEW_FLAG_NO_FRUSTUM;
use vgeo::streaming::{PageSource, StreamOptions, Streamer};

const W: u32 = 160;
const H: u32 = 120;

/// Bunny in pages of 16 KiB, so that it has many. Built at the step ratio 0.5, the default
/// until session 37: these tests' cameras, budgets and page counts were made for that DAG (at
/// 0.35 level 0 is a larger share of the pages, so the close view after the camera cut needs more
/// than 1/8 of them; a view a sixth farther needs no page the path left out). What they test,
/// the streamer and the cut under partial residency, does not depend on the ratio.
fn bunny() -> BuiltMesh {
    let (mesh, _) = vgeo::mesh::load_mesh(&shared_assets().join("scanned/bunny.ply")).unwrap();
    let mut b = build(&mesh, &common::options_at_ratio(0.5)).unwrap();
    let level = b.fallback_level(2000);
    paginate(&mut b, 16384, level);
    b
}

fn settings() -> FrameSettings {
    // The whole LOD cut: no frustum or occlusion culling.
    FrameSettings {
        error_px: 1.0,
        flags: VIEW_FLAG_NO_FRUSTUM,
        occlusion: false,
        ..Default::default()
    }
}

fn camera_at(t: f64) -> Camera {
    let center = DVec3::new(-0.017, 0.11, 0.0);
    // Around the mesh close by (more detail than the budget holds, changing with the side
    // seen), then away from it (a cut that fits).
    let a = t.min(0.75) * 8.0;
    let dir = DVec3::new(a.sin(), 0.3, a.cos()).normalize();
    let dist = if t < 0.75 {
        0.3
    } else {
        0.3 + 4.0 * (t - 0.75)
    };
    Camera::look_at(
        center + dir * dist,
        center,
        Vec3::Y,
        45f32.to_radians(),
        0.01,
    )
}

fn render(r: &mut VgeoRenderer, camera: &Camera) -> VgeoFrame {
    render_with(r, camera, &settings())
}

/// A checked frame at `camera` with `settings` (the `Lambert` view).
fn render_with(r: &mut VgeoRenderer, camera: &Camera, settings: &FrameSettings) -> VgeoFrame {
    let f = r
        .render(camera, W, H, settings, ViewMode::Lambert, &Light::default())
        .expect("frame renders");
    f.check().expect("no overflow, no watchdog");
    f
}

/// Frustum culling on, occlusion off (the streamed-image tests' `settings()` turn both off).
fn frustum_settings() -> FrameSettings {
    FrameSettings {
        error_px: 1.0,
        occlusion: false,
        ..Default::default()
    }
}

/// Frames at `camera`, each followed by a streaming step, until a step asks for and moves
/// nothing (true) or `frames` have passed (false).
fn settle(
    r: &mut VgeoRenderer,
    streamer: &mut Streamer,
    camera: &Camera,
    settings: &FrameSettings,
    frames: usize,
) -> bool {
    for _ in 0..frames {
        render_with(r, camera, settings);
        let st = streamer.update(&mut r.scene).expect("streaming step");
        if st.requests == 0 && st.settled() {
            return true;
        }
    }
    false
}

/// Every level-0 cluster's leaf-to-root paths cross `cut` exactly once.
fn crosses_once(m: &BuiltMesh, cut: &BTreeSet<u32>) -> bool {
    let cut: Vec<u32> = cut.iter().copied().collect();
    let up = common::path_crossings(m, &cut);
    m.clusters
        .iter()
        .enumerate()
        .all(|(ci, c)| c.level != 0 || up[ci] == (1, 1))
}

fn place() -> Placement {
    Placement {
        mesh: 0,
        transform: DMat4::IDENTITY,
        color: [1.0; 3],
    }
}

fn streamed(
    ctx: &vgeo::gpu::Context,
    mesh: &BuiltMesh,
    source: Box<dyn PageSource>,
    opts: StreamOptions,
) -> (VgeoRenderer, Streamer) {
    let mut r = VgeoRenderer::new(ctx, &[] as &[BuiltMesh], &[]).expect("empty renderer");
    let (s, handles) =
        Streamer::new(&mut r.scene, vec![(mesh.clone(), source)], opts).expect("streamer");
    r.scene
        .add_instance(&InstanceDesc {
            mesh: handles[0],
            transform: DMat4::IDENTITY,
            color: [1.0; 3],
        })
        .expect("instance");
    (r, s)
}

/// Copies of the mesh in a row along x (each its own mesh: unique geometry to the streamer).
const ROW: usize = 8;
const SPACING: f64 = 0.3;

/// Along the row close by (more detail than the budget holds, changing with the mesh seen),
/// then away from it (a cut that fits the budget).
fn row_camera(t: f64) -> Camera {
    let y = 0.11;
    if t < 0.75 {
        let x = (t / 0.75) * SPACING * (ROW - 1) as f64;
        let eye = DVec3::new(x - 0.05, y + 0.05, 0.32);
        Camera::look_at(
            eye,
            DVec3::new(x, y, 0.0),
            Vec3::Y,
            45f32.to_radians(),
            0.01,
        )
    } else {
        let c = DVec3::new(SPACING * (ROW - 1) as f64 / 2.0, y, 0.0);
        let eye = c + DVec3::new(0.0, 0.2, 0.5 + 8.0 * (t - 0.75));
        Camera::look_at(eye, c, Vec3::Y, 45f32.to_radians(), 0.01)
    }
}

#[test]
fn streamed_frames_are_crack_free_within_budget_and_settle_to_the_all_resident_image() {
    let ctx = gpu();
    let mut one = bunny();
    // Only the root's page always resident, so that the budget is mostly slots.
    paginate(&mut one, 12288, u32::MAX);
    let meshes: Vec<BuiltMesh> = (0..ROW)
        .map(|i| BuiltMesh {
            name: format!("bunny {i}"),
            ..one.clone()
        })
        .collect();
    let placements: Vec<Placement> = (0..ROW)
        .map(|i| Placement {
            mesh: i as u32,
            transform: DMat4::from_translation(DVec3::new(SPACING * i as f64, 0.0, 0.0)),
            color: [1.0; 3],
        })
        .collect();
    let total: u64 = meshes
        .iter()
        .flat_map(|m| m.pages.iter().map(|p| p.bytes as u64))
        .sum();
    let budget = total / 8;
    let opts = StreamOptions {
        budget_bytes: budget,
        upload_bytes_per_frame: 96 << 10,
    };
    let mut r = VgeoRenderer::new(&ctx, &[] as &[BuiltMesh], &[]).expect("empty renderer");
    let sources: Vec<(BuiltMesh, Box<dyn PageSource>)> = meshes
        .iter()
        .map(|m| (m.clone(), Box::new(m.clone()) as Box<dyn PageSource>))
        .collect();
    let (mut streamer, handles) = Streamer::new(&mut r.scene, sources, opts).expect("streamer");
    for p in &placements {
        r.scene
            .add_instance(&InstanceDesc {
                mesh: handles[p.mesh as usize],
                transform: p.transform,
                color: p.color,
            })
            .expect("instance");
    }
    assert!(
        streamer.slot_count() >= 8,
        "{} slots",
        streamer.slot_count()
    );
    let needs = group_needs(&one);
    let offsets: Vec<u32> = (0..ROW as u32)
        .map(|i| i * one.clusters.len() as u32)
        .collect();
    let (mut uploads, mut evictions) = (0, 0);
    // Load sets the previous step started: their pages are the ones a step stages.
    let mut sets_before = 0;
    let mut residency = streamer.residency();
    let frames = 64;
    let mut settled_at = None;
    for k in 0..frames + 40 {
        let camera = row_camera(k.min(frames) as f64 / frames as f64);
        let f = render(&mut r, &camera);
        // The cut of this frame against the CPU's under the residency it was drawn with.
        let gpu_cut: BTreeSet<(u32, u32)> = f.visible().iter().map(|v| (v[0], v[1])).collect();
        let view = view_for(&camera, W, H, &settings());
        let res: Vec<Option<&[bool]>> = residency.iter().map(|r| Some(r.as_slice())).collect();
        let (cut, borderline) = reference_cut_resident(&meshes, &res, &placements, &view, 1e-4);
        let cpu: BTreeSet<(u32, u32)> = cut.iter().map(|e| (e.instance, e.cluster)).collect();
        let border: BTreeSet<(u32, u32)> =
            borderline.iter().map(|e| (e.instance, e.cluster)).collect();
        let hard: Vec<_> = gpu_cut
            .symmetric_difference(&cpu)
            .filter(|c| !border.contains(c))
            .collect();
        assert!(
            hard.is_empty(),
            "frame {k}: GPU and CPU cuts differ on {hard:?}"
        );
        for (i, &off) in offsets.iter().enumerate() {
            let mine: BTreeSet<u32> = cpu
                .iter()
                .filter(|e| e.0 == i as u32)
                .map(|e| e.1 - off)
                .collect();
            assert!(
                crosses_once(&one, &mine),
                "frame {k}: mesh {i}'s cut cracks"
            );
            for &c in &mine {
                let page = one.clusters[c as usize].page as usize;
                assert!(residency[i][page], "frame {k}: mesh {i} cluster {c} absent");
            }
        }
        let waits = ctx.waited_submissions();
        let stats = streamer.update(&mut r.scene).expect("streaming step");
        // The step reads the feedback copy the frame left in host memory and stages its
        // uploads for the next frame: it submits nothing and waits for nothing.
        assert_eq!(
            ctx.waited_submissions(),
            waits,
            "frame {k}: the streaming step waited for the GPU"
        );
        assert!(
            stats.resident_bytes <= budget,
            "frame {k}: {stats:?} over {budget}"
        );
        // At most the per-frame bytes, but for a load set larger than that alone (the pages a
        // step stages were chosen by the step before).
        assert!(
            stats.upload_bytes <= opts.upload_bytes_per_frame || sets_before == 1,
            "frame {k}: {stats:?} after {sets_before} load sets"
        );
        sets_before = stats.load_sets;
        uploads += stats.uploads;
        evictions += stats.evictions;
        residency = streamer.residency();
        for (i, res) in residency.iter().enumerate() {
            let mut closed = res.clone();
            close_residency(&one, &needs, &mut closed);
            assert_eq!(
                &closed, res,
                "frame {k}: mesh {i}'s residency is not closed"
            );
        }
        if k >= frames && stats.requests == 0 && stats.settled() {
            settled_at = Some(k - frames);
            break;
        }
    }
    assert!(
        uploads > 50 && evictions > 20,
        "{uploads} uploads, {evictions} evictions"
    );
    let settled_at = settled_at.expect("settles within 40 frames of the camera stopping");
    eprintln!(
        "{uploads} uploads, {evictions} evictions, settled {settled_at} frames after the stop"
    );
    // Settled: the same image as every page resident.
    let mut full = VgeoRenderer::new(&ctx, &meshes, &placements).expect("all resident");
    let last = row_camera(1.0);
    let settled = render(&mut r, &last);
    let reference = render(&mut full, &last);
    assert!(
        settled.visbuffer == reference.visbuffer,
        "the settled streamed frame differs from the all-resident one"
    );
    assert_eq!(settled.frame.color, reference.frame.color);
    // A camera cut to another view: it settles again, within a bounded number of frames.
    let cut_to = Camera::look_at(
        DVec3::new(1.119, 0.314, -0.552),
        DVec3::new(0.883, 0.11, 0.0),
        Vec3::Y,
        45f32.to_radians(),
        0.01,
    );
    {
        let view = view_for(&cut_to, W, H, &settings());
        let (cut, _) = reference_cut_resident(&meshes, &[None; ROW], &placements, &view, 1e-4);
        let mut need: Vec<Vec<bool>> = vec![vec![false; one.pages.len()]; ROW];
        for e in &cut {
            let i = e.instance as usize;
            need[i][one.clusters[(e.cluster - offsets[i]) as usize].page as usize] = true;
        }
        let mut bytes = 0u64;
        for n in &mut need {
            close_residency(&one, &needs, n);
            bytes += n.iter().filter(|&&x| x).count() as u64 * streamer.slot_bytes();
        }
        assert!(
            bytes <= budget,
            "the view after the cut needs {bytes} B, over {budget}"
        );
        eprintln!("the view after the cut needs {bytes} B of the budget's {budget}");
        // ... and pages the view before it did not leave resident (a closer look at bunny 3).
        let res = streamer.residency();
        let missing: usize = need
            .iter()
            .zip(&res)
            .map(|(n, r)| n.iter().zip(r).filter(|(a, b)| **a && !**b).count())
            .sum();
        assert!(missing > 0, "the view after the cut needs no new page");
    }
    let mut frames_to_settle = None;
    let mut cut_uploads = 0;
    for k in 0..40 {
        let _ = render(&mut r, &cut_to);
        let stats = streamer.update(&mut r.scene).expect("streaming step");
        assert!(stats.resident_bytes <= budget, "{stats:?} over {budget}");
        cut_uploads += stats.uploads;
        if stats.requests == 0 && stats.settled() {
            frames_to_settle = Some(k + 1);
            break;
        }
    }
    let frames_to_settle = frames_to_settle.expect("settles within 40 frames of a camera cut");
    eprintln!("settled {frames_to_settle} frames after a camera cut");
    assert!(cut_uploads > 0, "the view after the cut needed pages");
    let settled = render(&mut r, &cut_to);
    let reference = render(&mut full, &cut_to);
    assert!(
        settled.visbuffer == reference.visbuffer,
        "after the camera cut"
    );
    assert!(streamer.take_errors().is_empty());
    assert_no_validation_errors(&ctx);
}

/// A source whose pages from `bad` on fail to read (a corrupt or missing page).
struct Failing {
    mesh: BuiltMesh,
    bad: u32,
}

impl PageSource for Failing {
    fn read_page(&self, page: u32) -> Result<Vec<u8>, String> {
        if page >= self.bad {
            return Err(format!("page {page}: checksum mismatch"));
        }
        self.mesh.read_page(page)
    }
}

#[test]
fn unreadable_pages_are_reported_once_and_the_mesh_stays_coarser() {
    let ctx = gpu();
    let m = bunny();
    let bad = m.resident_pages + 2;
    let opts = StreamOptions {
        budget_bytes: 8 << 20,
        upload_bytes_per_frame: 8 << 20,
    };
    let source = Box::new(Failing {
        mesh: m.clone(),
        bad,
    });
    let (mut r, mut streamer) = streamed(&ctx, &m, source, opts);
    let camera = camera_at(0.5);
    let mut errors = Vec::new();
    for _ in 0..30 {
        let _ = render(&mut r, &camera);
        streamer
            .update(&mut r.scene)
            .expect("a failed page is no error of the frame");
        errors.extend(streamer.take_errors());
    }
    assert!(!errors.is_empty(), "the failed pages are reported");
    let mut pages: Vec<&str> = errors
        .iter()
        .map(|e| e.split(" cannot").next().unwrap())
        .collect();
    let n = pages.len();
    pages.sort();
    pages.dedup();
    assert_eq!(pages.len(), n, "each page reported once: {errors:?}");
    // Coarser than all resident, but drawn.
    let f = render(&mut r, &camera);
    let mut full = VgeoRenderer::new(&ctx, std::slice::from_ref(&m), &[place()]).unwrap();
    let reference = render(&mut full, &camera);
    let covered = |f: &VgeoFrame| f.visbuffer.iter().filter(|&&v| v != 0).count();
    assert!(
        covered(&f) > covered(&reference) / 2,
        "the mesh is still drawn"
    );
    assert!(
        f.main.counters.triangles + f.post.counters.triangles
            < reference.main.counters.triangles + reference.post.counters.triangles
    );
    let residency = streamer.residency().remove(0);
    assert!(residency[bad as usize..].iter().all(|&r| !r));
    // A budget below the always-resident pages is an error at load, not a panic.
    let mut r2 = VgeoRenderer::new(&ctx, &[] as &[BuiltMesh], &[]).unwrap();
    let tiny = StreamOptions {
        budget_bytes: 1024,
        upload_bytes_per_frame: 1 << 20,
    };
    let err = Streamer::new(&mut r2.scene, vec![(m.clone(), Box::new(m.clone()))], tiny)
        .err()
        .expect("too small a budget");
    assert!(
        err.to_string().contains("smaller than the always-resident"),
        "{err}"
    );
    assert_no_validation_errors(&ctx);
}

/// Streaming from a `.vgeo` file read page by page (`VgeoFile`): the head alone is loaded, pages
/// come from the file as the cull asks; the settled frame equals the all-resident one. With one
/// page of the file corrupted, that page is reported once (by its checksum) and the frame is
/// drawn coarser there, without a panic or a validation error.
#[test]
fn meshes_stream_from_vgeo_files_and_corrupt_pages_are_reported() {
    use vgeo::format::{VgeoFile, save};
    let ctx = gpu();
    let m = bunny();
    let dir = std::env::temp_dir().join(format!("vgeo-stream-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("bunny.vgeo");
    let bytes = save(&m);
    std::fs::write(&path, &bytes).unwrap();
    let camera = camera_at(0.5);
    let opts = StreamOptions {
        budget_bytes: 8 << 20,
        upload_bytes_per_frame: 8 << 20,
    };
    let mut full = VgeoRenderer::new(&ctx, std::slice::from_ref(&m), &[place()]).unwrap();
    let reference = render(&mut full, &camera);
    let mut wanted = 0u32;
    for corrupt in [false, true] {
        if corrupt {
            let f = VgeoFile::open(&path).unwrap();
            // A page the view loaded from the intact file.
            let e = *f.page_entry(wanted).unwrap();
            let mut v = bytes.clone();
            v[(e.offset + 3) as usize] ^= 0xff;
            std::fs::write(&path, &v).unwrap();
        }
        let file = VgeoFile::open(&path).expect("the head opens");
        let head = file.head().clone();
        let (mut r, mut streamer) = streamed(&ctx, &head, Box::new(file), opts);
        let mut errors = Vec::new();
        let mut settled = false;
        for _ in 0..30 {
            let _ = render(&mut r, &camera);
            let st = streamer.update(&mut r.scene).expect("streaming step");
            errors.extend(streamer.take_errors());
            if st.requests == 0 && st.settled() {
                settled = true;
                break;
            }
        }
        let f = render(&mut r, &camera);
        if corrupt {
            assert_eq!(errors.len(), 1, "{errors:?}");
            assert!(errors[0].contains("checksum"), "{errors:?}");
            assert!(
                f.visbuffer != reference.visbuffer,
                "drawn coarser where the page is missing"
            );
        } else {
            assert!(settled && errors.is_empty(), "{errors:?}");
            assert!(f.visbuffer == reference.visbuffer, "settled from the file");
            let res = streamer.residency().remove(0);
            wanted = (head.resident_pages..res.len() as u32)
                .rev()
                .find(|&p| res[p as usize])
                .expect("the view loaded pages");
        }
    }
    std::fs::remove_dir_all(&dir).ok();
    assert_no_validation_errors(&ctx);
}

/// A per-frame upload cap smaller than any request's load set (the request's pages with those
/// that keep the residency closed) still streams: each update loads one set alone, and the frame
/// settles to the all-resident image. (Before, the first set that did not fit stopped every
/// later request: nothing more was ever loaded.)
#[test]
fn a_per_frame_cap_below_every_load_set_still_streams_one_set_per_frame() {
    let ctx = gpu();
    let m = bunny();
    let camera = camera_at(0.5);
    let opts = StreamOptions {
        budget_bytes: 8 << 20,
        upload_bytes_per_frame: 1,
    };
    let mut full = VgeoRenderer::new(&ctx, std::slice::from_ref(&m), &[place()]).unwrap();
    let reference = render(&mut full, &camera);
    let (mut r, mut streamer) = streamed(&ctx, &m, Box::new(m.clone()), opts);
    let mut settled = false;
    let mut sets = 0;
    for _ in 0..400 {
        let _ = render(&mut r, &camera);
        let st = streamer.update(&mut r.scene).expect("streaming step");
        assert!(st.load_sets <= 1, "{st:?}");
        sets += st.load_sets;
        if st.requests == 0 && st.settled() {
            settled = true;
            break;
        }
    }
    assert!(
        settled && sets > 1,
        "settled {settled} after {sets} load sets"
    );
    let f = render(&mut r, &camera);
    assert!(
        f.visbuffer == reference.visbuffer,
        "settled one set at a time"
    );
    assert_no_validation_errors(&ctx);
}

/// Bytes the streamer's slots should take for `residency` with `reading` pages being read: the
/// always-resident pages, and a slot per other resident page and per page being read.
fn slot_accounting(m: &BuiltMesh, residency: &[bool], reading: u64, slot_bytes: u64) -> u64 {
    let fixed: u64 = m.pages[..m.resident_pages as usize]
        .iter()
        .map(|p| p.bytes as u64)
        .sum();
    let in_slots = residency[m.resident_pages as usize..]
        .iter()
        .filter(|&&r| r)
        .count() as u64;
    fixed + (in_slots + reading) * slot_bytes
}

/// Many load sets in one step, with no per-frame cap to speak of: every slot in use holds a page
/// (resident or being read). Before, a set that took a page an earlier set of the same step was
/// reading (a parent both needed to stay closed) gave it a second slot and lost the first: a cold
/// cut of 4 meshes of 4.4 M triangles held 30 slots of 105 with no page in them.
#[test]
fn load_sets_of_one_step_never_lose_a_slot() {
    let ctx = gpu();
    // Pages of 4 KiB: many load sets per step, sharing the parents that keep them closed.
    let mut m = bunny();
    let level = m.fallback_level(2000);
    paginate(&mut m, 4096, level);
    let camera = camera_at(0.1);
    let opts = StreamOptions {
        budget_bytes: 64 << 20,
        upload_bytes_per_frame: 64 << 20,
    };
    let (mut r, mut streamer) = streamed(&ctx, &m, Box::new(m.clone()), opts);
    let mut most_sets = 0;
    let mut settled = false;
    for k in 0..40 {
        let _ = render(&mut r, &camera);
        let st = streamer.update(&mut r.scene).expect("streaming step");
        most_sets = most_sets.max(st.load_sets);
        let res = streamer.residency().remove(0);
        assert_eq!(
            st.resident_bytes,
            slot_accounting(&m, &res, st.reading, streamer.slot_bytes()),
            "step {k}: slots in use that hold no page ({st:?})"
        );
        if st.requests == 0 && st.settled() {
            settled = true;
            break;
        }
    }
    eprintln!("{most_sets} load sets in a step at most");
    assert!(
        settled && most_sets > 1,
        "settled {settled}, {most_sets} load sets in a step at most"
    );
    let f = render(&mut r, &camera);
    let mut full = VgeoRenderer::new(&ctx, std::slice::from_ref(&m), &[place()]).unwrap();
    assert!(f.visbuffer == render(&mut full, &camera).visbuffer);
    assert_no_validation_errors(&ctx);
}

/// Frustum culling on (the other streamed-image tests turn it off), a view the mesh overflows:
/// coarse clusters straddle the frustum's edges, where the cull asks for no group whose LOD
/// sphere (enclosing all it could draw) is outside the frustum. The view settles to the
/// all-resident image bit for bit. (Here no request happens to be dropped: 42 of 80 pages end
/// resident either way; stream_sizes' cold cut is where the rule counts.)
#[test]
fn a_view_the_mesh_overflows_settles_to_the_all_resident_image_with_frustum_culling() {
    let ctx = gpu();
    let m = bunny();
    let settings = frustum_settings();
    let camera = Camera::look_at(
        DVec3::new(0.03, 0.13, 0.1),
        DVec3::new(-0.01, 0.11, 0.0),
        Vec3::Y,
        45f32.to_radians(),
        0.01,
    );
    let frame = |r: &mut VgeoRenderer| render_with(r, &camera, &settings);
    let opts = StreamOptions {
        budget_bytes: 8 << 20,
        upload_bytes_per_frame: 8 << 20,
    };
    let (mut r, mut streamer) = streamed(&ctx, &m, Box::new(m.clone()), opts);
    let settled = settle(&mut r, &mut streamer, &camera, &settings, 40);
    assert!(settled, "settles within 40 frames");
    let f = frame(&mut r);
    let mut full = VgeoRenderer::new(&ctx, std::slice::from_ref(&m), &[place()]).unwrap();
    let reference = frame(&mut full);
    let covered = reference.visbuffer.iter().filter(|&&v| v != 0).count();
    assert!(
        covered > W as usize * H as usize / 2,
        "{covered} pixels covered: the mesh overflows the view"
    );
    let all = streamer.residency().remove(0);
    assert!(
        all.iter().any(|&r| !r),
        "the view needs only part of the mesh"
    );
    assert!(
        f.visbuffer == reference.visbuffer,
        "settled with frustum culling"
    );
    assert_no_validation_errors(&ctx);
}

/// A load of mesh `h`'s page `p` (`m`'s bytes) into a newly reserved pool slot, for
/// `GpuScene::update_pages` without a streamer.
fn load_by_hand(
    r: &mut VgeoRenderer,
    m: &BuiltMesh,
    h: vgeo::scene_gpu::MeshHandle,
    p: u32,
) -> vgeo::scene_gpu::PageChange {
    let bytes = m.read_page(p).expect("page");
    assert_eq!(bytes.len() as u64, m.pages[p as usize].bytes as u64);
    let word = r
        .scene
        .reserve_page_slots(bytes.len().div_ceil(4) as u64)
        .expect("slot");
    vgeo::scene_gpu::PageChange {
        mesh: h,
        page: p,
        load: Some((word, bytes)),
    }
}

/// The culls run their pipelines without the partial-residency code (`CULL_STREAMING` false)
/// only in frames in which no mesh can be partial on the GPU: a streamed mesh takes the streaming
/// ones while a page is absent, and still in the `render` that copies its last page in (its
/// flag in the CPU's table is already clear, the GPU's not yet); then the resident ones, and its image
/// and depth are the all-resident renderer's bit for bit; an eviction takes it back.
#[test]
fn the_culls_leave_out_streaming_code_only_once_every_page_is_in() {
    let ctx = gpu();
    let one = bunny();
    let total: u64 = one.pages.iter().map(|p| p.bytes as u64).sum();
    let opts = StreamOptions {
        budget_bytes: 2 * total,
        upload_bytes_per_frame: 64 << 20,
    };
    let (mut r, _streamer) = streamed(&ctx, &one, Box::new(one.clone()), opts);
    let h = r.scene.mesh_handle(0).expect("mesh");
    let camera = camera_at(0.1);
    assert_eq!(r.scene.partial_meshes(), 1);
    assert!(r.streaming_cull(), "only the always-resident pages are in");
    render(&mut r, &camera);
    // Every absent page in, by hand (the streamer, never updated here, loaded only the
    // always-resident ones; it would load only what a view asks for).
    let changes: Vec<_> = (one.resident_pages..one.pages.len() as u32)
        .map(|p| load_by_hand(&mut r, &one, h, p))
        .collect();
    assert!(!changes.is_empty());
    r.scene.update_pages(&changes).expect("loads");
    assert_eq!(
        r.scene.partial_meshes(),
        0,
        "the CPU's table has every page"
    );
    assert!(
        r.scene.may_be_partial() && r.streaming_cull(),
        "the GPU has not had the copies yet"
    );
    let copied = render(&mut r, &camera);
    assert!(!r.scene.may_be_partial() && !r.streaming_cull());
    let streamed_image = render(&mut r, &camera);
    let mut all =
        VgeoRenderer::new(&ctx, std::slice::from_ref(&one), &[place()]).expect("renderer");
    assert!(!all.streaming_cull());
    let want = render(&mut all, &camera);
    for (what, f) in [("copying", &copied), ("resident", &streamed_image)] {
        assert!(
            f.frame.color == want.frame.color && f.frame.depth == want.frame.depth,
            "{what} frame: the image differs from the all-resident one"
        );
    }
    // An eviction makes the mesh partial again.
    let last = one.pages.len() as u32 - 1;
    assert!(last >= one.resident_pages);
    r.scene
        .update_pages(&[vgeo::scene_gpu::PageChange {
            mesh: h,
            page: last,
            load: None,
        }])
        .expect("eviction");
    assert_eq!(r.scene.partial_meshes(), 1);
    assert!(r.streaming_cull());
    render(&mut r, &camera);
    assert!(r.streaming_cull(), "still partial after its copy");
    assert_no_validation_errors(&ctx);
}

/// Pages `set_page_residency` marked absent stay absent, and the mesh partial, when
/// `update_pages` later loads another of its pages (found by session 43's second read: the flag
/// followed only the pages' bytes, which `set_page_residency` leaves in the pool, so the load
/// cleared it while a page was absent on the GPU). Every page made resident again clears it.
#[test]
fn a_page_change_keeps_pages_set_absent_absent() {
    let ctx = gpu();
    let one = bunny();
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&one), &[place()]).expect("renderer");
    let h = r.scene.mesh_handle(0).expect("mesh");
    let n = one.pages.len();
    assert!(n >= one.resident_pages as usize + 2);
    let (p, q) = (n - 2, n - 1);
    let mut res = vec![true; n];
    res[p] = false;
    res[q] = false;
    r.scene.set_page_residency(h, &res).expect("residency");
    assert_eq!(r.scene.partial_meshes(), 1);
    let change = load_by_hand(&mut r, &one, h, p as u32);
    r.scene.update_pages(&[change]).expect("load p");
    let camera = camera_at(0.1);
    let f = render(&mut r, &camera);
    assert_eq!(r.scene.partial_meshes(), 1, "page {q} is still absent");
    assert!(r.streaming_cull());
    // Nothing of page q is drawn.
    let pages: BTreeSet<u32> = f
        .visible()
        .iter()
        .map(|v| one.clusters[v[1] as usize].page)
        .collect();
    assert!(
        !pages.is_empty() && !pages.contains(&(q as u32)),
        "{pages:?}"
    );
    r.scene
        .set_page_residency(h, &vec![true; n])
        .expect("all resident");
    assert_eq!(r.scene.partial_meshes(), 0);
    assert!(!r.streaming_cull());
    assert_no_validation_errors(&ctx);
}

/// A mesh just behind the camera streams in nothing. The eye is 0.02 in front of the bunny's
/// nearest point, looking away from it: the spheres of its coarse clusters reach past the near
/// plane, but their boxes lie wholly behind it, and a cluster outside the frustum asks for no
/// children (before, such a mesh behind the camera of `stream_sizes`' cold cut streamed in 21 MiB
/// of detail it never showed). Turned around, the same eye streams the detail in.
#[test]
fn a_mesh_behind_the_camera_streams_in_nothing() {
    let ctx = gpu();
    let m = bunny();
    let settings = frustum_settings();
    let zmax = m
        .clusters
        .iter()
        .map(|c| c.bounds_max[2])
        .fold(f32::MIN, f32::max) as f64;
    let eye = DVec3::new(-0.017, 0.11, zmax + 0.02);
    let settle = |target: DVec3| {
        let camera = Camera::look_at(eye, target, Vec3::Y, 45f32.to_radians(), 0.01);
        let opts = StreamOptions {
            budget_bytes: 8 << 20,
            upload_bytes_per_frame: 8 << 20,
        };
        let (mut r, mut streamer) = streamed(&ctx, &m, Box::new(m.clone()), opts);
        settle(&mut r, &mut streamer, &camera, &settings, 20);
        let res = streamer.residency().remove(0);
        res[m.resident_pages as usize..]
            .iter()
            .filter(|&&r| r)
            .count()
    };
    let away = settle(eye + DVec3::new(0.0, 0.0, 1.0));
    let towards = settle(eye - DVec3::new(0.0, 0.0, 1.0));
    assert_eq!(away, 0, "pages streamed in for a mesh behind the camera");
    assert!(
        towards > 0,
        "the view towards the mesh streams its detail in"
    );
    assert_no_validation_errors(&ctx);
}

/// The residency view's colour of each state, as the image holds it (RGBA8).
fn residency_rgba(state: u32) -> [u8; 4] {
    state.to_le_bytes()
}

/// Per pixel of `f` (one mesh `m`, instances `placements`, drawn with page residency `resident`
/// and having written the page requests `wish`), the colour the residency view must show: `None`
/// for the background and for clusters whose decision is within rounding of the threshold.
fn expected_residency(
    m: &BuiltMesh,
    placements: &[Placement],
    f: &VgeoFrame,
    resident: &[bool],
    wish: &[f32],
    camera: &Camera,
) -> Vec<Option<[u8; 4]>> {
    use vgeo::shared::{
        RESIDENCY_COLOR_MISSING, RESIDENCY_COLOR_NOT_NEEDED, RESIDENCY_COLOR_REQUESTED,
        RESIDENCY_COLOR_RESIDENT,
    };
    let view = view_for(camera, W, H, &settings());
    let tau = view.error_px;
    f.visbuffer
        .iter()
        .map(|&v| {
            if v == 0 {
                return None;
            }
            let slot = (v as u32 >> vgeo::shared::VISBUFFER_TRIANGLE_BITS) as usize;
            let [instance, cluster] = f.visible_table[slot];
            let c = &m.clusters[cluster as usize];
            if c.creator == vgeo::builder::NO_GROUP {
                return Some(residency_rgba(RESIDENCY_COLOR_RESIDENT));
            }
            let g = &m.groups[c.creator as usize];
            let pages = g.page_first as usize..(g.page_first + g.page_count) as usize;
            if pages.clone().all(|p| resident[p]) {
                return Some(residency_rgba(RESIDENCY_COLOR_RESIDENT));
            }
            let requested = pages.clone().any(|p| !resident[p] && wish[p] > 0.0);
            // The cluster's self pair is its creator group's, weighted as the cull weighs it.
            let inst = vgeo::scene_gpu::instance_gpu(&placements[instance as usize]);
            let w = vgeo::reference::cut::instance_weight(m, &inst, &view);
            let px = vgeo::reference::cut::group_error_px(m, &inst, &view, c.creator, w);
            if (px - tau).abs() <= 1e-4 * tau {
                return None;
            }
            Some(residency_rgba(if px > tau {
                RESIDENCY_COLOR_MISSING
            } else if requested {
                RESIDENCY_COLOR_REQUESTED
            } else {
                RESIDENCY_COLOR_NOT_NEEDED
            }))
        })
        .collect()
}

/// Pixels of each residency colour in `f`'s image, after checking every covered pixel against
/// `expected` (within one step of rounding): (resident, not needed, requested, missing).
fn residency_counts(f: &VgeoFrame, expected: &[Option<[u8; 4]>], what: &str) -> [usize; 4] {
    use vgeo::shared::{
        RESIDENCY_COLOR_MISSING, RESIDENCY_COLOR_NOT_NEEDED, RESIDENCY_COLOR_REQUESTED,
        RESIDENCY_COLOR_RESIDENT,
    };
    let states = [
        RESIDENCY_COLOR_RESIDENT,
        RESIDENCY_COLOR_NOT_NEEDED,
        RESIDENCY_COLOR_REQUESTED,
        RESIDENCY_COLOR_MISSING,
    ]
    .map(residency_rgba);
    let close = |a: &[u8], b: &[u8; 4]| (0..3).all(|k| a[k].abs_diff(b[k]) <= 1);
    let mut counts = [0usize; 4];
    let mut wrong = 0;
    for (i, (px, want)) in f.frame.color.chunks(4).zip(expected).enumerate() {
        let Some(want) = want else { continue };
        if !close(px, want) {
            if wrong < 5 {
                eprintln!("{what}: pixel {i} is {px:?}, expected {want:?}");
            }
            wrong += 1;
        }
        if let Some(k) = states.iter().position(|s| close(px, s)) {
            counts[k] += 1;
        }
    }
    assert_eq!(wrong, 0, "{what}: {wrong} pixels show another state");
    counts
}

/// The `residency` debug view (issue 13, item 6). Under a budget well below the mesh's pages, a
/// close view's first frame (only the always-resident pages there) shows "wanted but missing"
/// where the cut would refine, and "requested" on a second, distant instance of the same mesh
/// whose coarse clusters the near one asked to refine; once the detail has streamed in, no pixel
/// is wanted but missing. Every covered pixel of every frame shows the state the CPU derives from
/// the residency the frame was drawn with and the page requests it wrote. With every page
/// resident (no streaming), every covered pixel reads resident.
#[test]
fn residency_view_shows_missing_detail_until_it_streams_in() {
    use vgeo::shared::RESIDENCY_COLOR_RESIDENT;
    let ctx = gpu();
    let m = bunny();
    let placements = [
        place(),
        Placement {
            mesh: 0,
            transform: DMat4::from_translation(DVec3::new(0.35, 0.0, -1.2)),
            color: [1.0; 3],
        },
    ];
    let camera = Camera::look_at(
        DVec3::new(0.05, 0.13, 0.28),
        DVec3::new(0.06, 0.1, 0.0),
        Vec3::Y,
        45f32.to_radians(),
        0.01,
    );
    // A budget of the always-resident pages, the pages this view needs (closed) and two spare
    // slots: well below the whole mesh.
    let slot = m
        .pages
        .iter()
        .map(|p| p.bytes as u64)
        .max()
        .unwrap()
        .next_multiple_of(4);
    let fixed: u64 = m.pages[..m.resident_pages as usize]
        .iter()
        .map(|p| p.bytes as u64)
        .sum();
    let view = view_for(&camera, W, H, &settings());
    let (cut, _) =
        reference_cut_resident(std::slice::from_ref(&m), &[None], &placements, &view, 1e-4);
    let mut need = vec![false; m.pages.len()];
    for e in &cut {
        need[m.clusters[e.cluster as usize].page as usize] = true;
    }
    close_residency(&m, &group_needs(&m), &mut need);
    let slots = need[m.resident_pages as usize..]
        .iter()
        .filter(|&&n| n)
        .count() as u64;
    let budget = fixed + (slots + 2) * slot;
    let total: u64 = m.pages.iter().map(|p| p.bytes as u64).sum();
    assert!(
        budget < total * 3 / 4,
        "the view needs {budget} B of {total}: pick a farther view"
    );
    let opts = StreamOptions {
        budget_bytes: budget,
        upload_bytes_per_frame: 64 << 10,
    };
    let mut r = VgeoRenderer::new(&ctx, &[] as &[BuiltMesh], &[]).expect("empty renderer");
    let (mut streamer, handles) = Streamer::new(
        &mut r.scene,
        vec![(m.clone(), Box::new(m.clone()) as Box<dyn PageSource>)],
        opts,
    )
    .expect("streamer");
    for p in &placements {
        r.scene
            .add_instance(&InstanceDesc {
                mesh: handles[0],
                transform: p.transform,
                color: p.color,
            })
            .expect("instance");
    }
    let residency_frame = |r: &mut VgeoRenderer| {
        let f = r
            .render(
                &camera,
                W,
                H,
                &settings(),
                ViewMode::Residency,
                &Light::default(),
            )
            .expect("frame renders");
        f.check().expect("no overflow, no watchdog");
        f
    };
    let mut first = None;
    let mut last = None;
    for k in 0..40 {
        let resident = streamer.residency().remove(0);
        let f = residency_frame(&mut r);
        let (wish, _) = r.scene.page_feedback(handles[0]).expect("feedback");
        let expected = expected_residency(&m, &placements, &f, &resident, &wish, &camera);
        let counts = residency_counts(&f, &expected, &format!("frame {k}"));
        eprintln!("frame {k}: resident, not needed, requested, missing = {counts:?}");
        if let Ok(dir) = std::env::var("VGEO_TEST_DUMP") {
            let path = std::path::Path::new(&dir).join(format!("residency_{k}.png"));
            image::save_buffer(&path, &f.frame.color, W, H, image::ColorType::Rgba8)
                .expect("save dump");
        }
        if k == 0 {
            first = Some(counts);
        }
        let st = streamer.update(&mut r.scene).expect("streaming step");
        assert!(st.resident_bytes <= budget, "{st:?} over {budget}");
        if st.requests == 0 && st.settled() {
            last = Some(counts);
            break;
        }
    }
    let [_, _, requested, missing] = first.unwrap();
    assert!(
        missing > 100,
        "the first frame shows {missing} pixels wanted but missing"
    );
    assert!(
        requested > 0,
        "the far instance's clusters the near one asked to refine read requested"
    );
    let [resident, not_needed, requested, missing] = last.expect("settles within 40 frames");
    assert_eq!(
        (missing, requested),
        (0, 0),
        "settled: no pixel is wanted but missing or requested"
    );
    assert!(
        resident > 0 && resident + not_needed > 1000,
        "settled: {resident} pixels resident, {not_needed} not needed"
    );
    // Every page resident: every covered pixel reads resident.
    let mut full = VgeoRenderer::new(&ctx, std::slice::from_ref(&m), &placements).unwrap();
    let f = residency_frame(&mut full);
    let green = residency_rgba(RESIDENCY_COLOR_RESIDENT);
    let covered: Vec<usize> = (0..f.visbuffer.len())
        .filter(|&i| f.visbuffer[i] != 0)
        .collect();
    assert!(covered.len() > 1000, "{} pixels covered", covered.len());
    for &i in &covered {
        assert_eq!(
            f.frame.color[4 * i..4 * i + 3],
            green[..3],
            "all resident: pixel {i}"
        );
    }
    assert_no_validation_errors(&ctx);
}

/// Issue 13 acceptance 3 at a test's scale (the benchmark is examples/stream_sizes.rs): scenes of
/// 2, 4 and 8 unique meshes streamed from `.vgeo` files under one budget. The scene on disk grows
/// past several budgets; the page pool and the resident pages stay within the budget at every
/// size, and the plot and tables are written.
#[test]
fn resident_bytes_follow_the_budget_not_the_scene_size() {
    let ctx = gpu();
    let dir = std::env::temp_dir().join(format!("vgeo-stream-sizes-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let budget = 3u64 << 19;
    let opts = stream_sizes::Options {
        mesh: common::assets().join("spot.obj"),
        work: dir.join("work"),
        out: dir.join("out"),
        sizes: vec![2, 4, 8],
        budget_bytes: budget,
        upload_bytes_per_frame: 1 << 20,
        levels: 2,
        copies: 1,
        frames: 24,
        width: 160,
        height: 96,
        // The ratio docs/architecture.md ("The DAG's step") advises for geometry that streams.
        ratio: 0.35,
    };
    let recs = stream_sizes::run_on(&ctx, &opts).expect("the sizes run");
    assert_no_validation_errors(&ctx);
    for r in &recs {
        eprintln!("{r:?}");
    }
    assert_eq!(recs.len(), 3);
    assert!(
        recs.windows(2).all(|w| w[1].vgeo_bytes > w[0].vgeo_bytes),
        "the scenes grow"
    );
    let last = recs.last().unwrap();
    assert!(
        last.vgeo_bytes > 3 * budget,
        "the largest scene is several budgets on disk: {last:?}"
    );
    for r in &recs {
        assert!(
            r.peak_resident_bytes <= budget && r.pool_bytes <= budget,
            "{r:?}"
        );
        assert!(r.uploads > 0 && r.used_bytes_last_frame > 0, "{r:?}");
        // The cold cut settles, within the budget, holding at least what its frame uses and
        // what that needs (the closure of the used pages: the DAG above them, up to the root).
        assert!(r.cold_frames_to_settle.is_some(), "{r:?}");
        let c = &r.cold_residency;
        assert!(
            r.cold_used_bytes > 0
                && c.used_bytes == r.cold_used_bytes
                && c.resident_bytes == r.cold_resident_bytes
                && c.used_bytes <= c.needed_bytes
                && c.needed_bytes <= c.resident_page_bytes
                && c.resident_page_bytes <= c.resident_bytes
                && c.fixed_bytes <= c.needed_bytes
                && r.cold_resident_bytes <= budget,
            "{r:?}"
        );
        // Per mesh, the same figures: one per mesh of the scene, summing to the whole.
        let m = &r.cold_residency_by_mesh;
        let sum = |f: fn(&vgeo::CutResidency) -> u64| m.iter().map(f).sum::<u64>();
        assert!(
            m.len() == r.meshes
                && sum(|x| x.used_bytes) == c.used_bytes
                && sum(|x| x.needed_bytes) == c.needed_bytes
                && sum(|x| x.resident_page_bytes) == c.resident_page_bytes
                && sum(|x| x.other_bytes) == c.other_bytes
                && m.iter().all(|x| x.used_bytes <= x.needed_bytes),
            "{r:?}"
        );
        eprintln!(
            "{} meshes: cold cut settled in {:?} frames, resident / used {:.2}x, needed / used {:.2}x",
            r.meshes,
            r.cold_frames_to_settle,
            r.cold_resident_bytes as f64 / r.cold_used_bytes as f64,
            c.needed_bytes as f64 / r.cold_used_bytes as f64
        );
    }
    // The largest scene wants more than the budget along the path: it fills it and evicts.
    assert!(
        last.evictions > 0 && last.peak_resident_bytes * 4 > budget * 3,
        "{last:?}"
    );
    let svg = std::fs::read_to_string(opts.out.join("sizes.svg")).expect("the plot");
    assert_eq!(svg.matches("<polyline").count(), 4, "{svg}");
    assert!(opts.out.join("sizes.md").exists() && opts.out.join("sizes.json").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Side of `streamed_bunny_field`'s square of instances.
const BUNNY_FIELD: usize = 64;

/// A renderer with `BUNNY_FIELD` x `BUNNY_FIELD` instances of the bunny `one`, streamed under
/// `opts` (rows 0.25 apart going away along -z, each turned its own way), and its streamer.
fn streamed_bunny_field(
    ctx: &vgeo::gpu::Context,
    one: &BuiltMesh,
    opts: StreamOptions,
) -> (VgeoRenderer, Streamer) {
    let mut r = VgeoRenderer::new(ctx, &[] as &[BuiltMesh], &[]).expect("empty renderer");
    let source = Box::new(one.clone()) as Box<dyn PageSource>;
    let (s, handles) =
        Streamer::new(&mut r.scene, vec![(one.clone(), source)], opts).expect("streamer");
    let side = BUNNY_FIELD;
    for i in 0..side * side {
        let (x, z) = ((i % side) as f64, (i / side) as f64);
        r.scene
            .add_instance(&InstanceDesc {
                mesh: handles[0],
                transform: DMat4::from_rotation_translation(
                    glam::DQuat::from_rotation_y(0.61 * i as f64),
                    DVec3::new((x - side as f64 / 2.0) * 0.25, 0.0, -z * 0.25),
                ),
                color: [1.0; 3],
            })
            .expect("instance");
    }
    (r, s)
}

/// `instance_cull`'s `shared` variant (views of `WALK_WIDE_INSTANCES` to
/// `SHARED_RUNS_MAX_INSTANCES` instances) under partial residency: 64 x 64 instances of one
/// streamed bunny (only the root page fixed), the near ones walked and asking for pages, the far
/// ones taking their table's finest resident rows, streamed along a
/// camera path by two renderers in lockstep, one forced to each variant. Every frame draws the
/// same clusters, image, depth and triangles with the same counters, and every streaming step
/// asks for, loads and evicts the same pages. A third renderer, in the same lockstep, runs the
/// shared variant with `push_run` refusing a walk's groups as it does past a thread's runs
/// (through a shader folder): they go to `cluster_cull`'s queue, and some must. A fourth runs the
/// shared variant with `run_round` blind to residency (its runs' `partial` forced off): it must
/// draw other clusters somewhere on the path, or the path never had a walked instance draw a
/// cluster for want of its children there, and the comparison would prove nothing about it.
#[test]
fn the_shared_runs_variant_streams_as_the_plain_one() {
    use vgeo::passes::instance_cull::shares_runs;
    let ctx = gpu();
    // The blind shared runs: cull.glsl with run_round's residency flag false.
    let blind_ctx = cull_variant_context(
        "blind-runs",
        "            partial = mesh_partial(mesh);\n",
        "            partial = false;\n",
    );
    // The shared runs with no room for a walk's groups: push_run refuses them (its test for a
    // thread's full runs, taken for every walk's group), so all of them go the way groups past a
    // thread's SHARED_RUNS_PER_THREAD runs go, to cluster_cull's queue (none of this path's walks
    // fills its runs since process_node skips members whose resident creator is over the
    // threshold).
    let tight_ctx = cull_variant_context(
        "tight-runs",
        "    if (j >= SHARED_RUNS_PER_THREAD) {\n",
        "    if (j >= SHARED_RUNS_PER_THREAD || (count & RUN_TEST) != 0u) {\n",
    );

    let mut one = bunny();
    // Only the root's page always resident: small instances, walked by instance_cull, want
    // pages too, and draw coarser clusters for want of them.
    paginate(&mut one, 12288, u32::MAX);
    let total: u64 = one.pages.iter().map(|p| p.bytes as u64).sum();
    let opts = StreamOptions {
        budget_bytes: total / 4,
        upload_bytes_per_frame: 64 << 10,
    };
    assert!(shares_runs((BUNNY_FIELD * BUNNY_FIELD) as u32));
    let mut renderers = Vec::new();
    // Compared in lockstep: the shared variant, the plain one, the tight runs; then the blind.
    for (c, shared) in [
        (&ctx, true),
        (&ctx, false),
        (&tight_ctx, true),
        (&blind_ctx, true),
    ] {
        let (mut r, s) = streamed_bunny_field(c, &one, opts);
        r.set_shared_runs(Some(shared));
        renderers.push((r, s));
    }
    // At 8 px the near bunnies (over TINY_CUT_RADIUS_PX, each cut within WALK_CLUSTERS_WIDE)
    // are walked by instance_cull, the far ones take their table's rows; at 1 px (the default)
    // every bunny of this 160 x 120 view takes its table or goes to cluster_cull's queue, and no
    // walk is left to test (6 px: walks, but none draws for want of its children).
    let settings = FrameSettings {
        error_px: 8.0,
        ..Default::default()
    };
    let (mut requests, mut walks, mut blind_differs) = (0, 0, None);
    let (mut overflow, mut tight_overflow) = (0, 0);
    for k in 0..24 {
        // Low over the field's near edge, moving along it: the near bunnies want their detail.
        let x = -1.0 + 2.0 * (k.min(16) as f64 / 16.0);
        let eye = DVec3::new(x, 0.1, 0.15);
        let at = eye + DVec3::new(0.2, -0.05, -1.0);
        let camera = Camera::look_at(eye, at, Vec3::Y, 60f32.to_radians(), 0.01);
        let mut seen = Vec::new();
        // The blind runs until they have drawn other clusters (their streaming then differs).
        let n = if blind_differs.is_some() { 3 } else { 4 };
        for (r, s) in renderers.iter_mut().take(n) {
            let f = render_with(r, &camera, &settings);
            let cut: BTreeSet<(u32, u32)> = f.visible().iter().map(|v| (v[0], v[1])).collect();
            assert_eq!(
                cut.len(),
                f.visible().len(),
                "frame {k}: a cluster drawn twice"
            );
            let st = s.update(&mut r.scene).expect("streaming step");
            assert!(st.resident_bytes <= opts.budget_bytes, "frame {k}: {st:?}");
            // The queue's items are not compared: the shared variant sends a walk's groups past
            // a thread's runs there.
            let counters = [&f.main.counters, &f.post.counters].map(|c| {
                [
                    c.local_walks,
                    c.tiny_cuts,
                    c.post_instance_count,
                    c.post_node_count,
                    c.post_cluster_count,
                    c.visible_count,
                ]
            });
            seen.push((
                cut,
                f.frame,
                st,
                s.residency(),
                counters,
                f.main.counters.queue_tail,
            ));
        }
        let b = &seen[1];
        for (name, a) in [("shared", &seen[0]), ("tight", &seen[2])] {
            assert!(
                a.0 == b.0,
                "frame {k}: {name} and plain draw different clusters"
            );
            assert!(
                a.1.color == b.1.color,
                "frame {k}: {name} and plain images differ"
            );
            assert!(
                a.1.depth == b.1.depth,
                "frame {k}: {name} and plain depths differ"
            );
            assert_eq!(a.1.triangles, b.1.triangles, "frame {k}: {name}: triangles");
            assert_eq!(a.2, b.2, "frame {k}: {name}: the streaming steps differ");
            assert!(a.3 == b.3, "frame {k}: {name}: the residency differs");
            assert_eq!(
                a.4, b.4,
                "frame {k}: {name}: the counters (main, post) differ"
            );
        }
        let a = &seen[0];
        if seen.len() == 4 && seen[3].0 != a.0 {
            blind_differs = Some(k);
        }
        requests += a.2.requests;
        walks += a.4[0][0] + a.4[1][0];
        // Queue items the shared variants sent past a thread's runs (walks' groups).
        overflow = overflow.max(a.5.saturating_sub(b.5));
        tight_overflow = tight_overflow.max(seen[2].5.saturating_sub(b.5));
    }
    eprintln!(
        "{requests} requests, {walks} local walks, up to {overflow} more queue items shared ({tight_overflow} with no runs for walks), the blind runs differ at {blind_differs:?}"
    );
    assert!(requests > 0 && walks > 0, "the path streams and walks");
    assert!(
        tight_overflow > 0,
        "no walk's groups went past the tight runs"
    );
    assert!(
        blind_differs.is_some(),
        "no frame's cut depends on the shared runs' residency test"
    );
    assert_no_validation_errors(&ctx);
    assert_no_validation_errors(&tight_ctx);
    assert_no_validation_errors(&blind_ctx);
}

/// A device context whose shaders take `common/cull.glsl` with its one line `line` replaced by
/// `with` (a shader folder, `ContextOptions::shader_dir`), named `name` in the temporary folder.
fn cull_variant_context(name: &str, line: &str, with: &str) -> vgeo::gpu::Context {
    use vgeo::gpu::{Context, ContextOptions};
    let dir = std::env::temp_dir().join(format!("vgeo-{name}-{}", std::process::id()));
    std::fs::create_dir_all(dir.join("common")).unwrap();
    let cull = include_str!("../shaders_glsl/common/cull.glsl");
    assert_eq!(cull.matches(line).count(), 1, "{name}: the line to replace");
    std::fs::write(dir.join("common/cull.glsl"), cull.replace(line, with)).unwrap();
    let ctx = Context::new(&ContextOptions {
        validation: true,
        shader_dir: Some(dir.clone()),
        ..ContextOptions::from_env()
    })
    .expect("a device with the cull variant");
    let _ = std::fs::remove_dir_all(&dir);
    ctx
}

/// Small instances under a budget too small for the closure of the row they want: 64 x 64
/// streamed bunnies, all taking their table's rows (a wide view at 0.05 px), only the root page
/// fixed, a budget of about 11 page slots. They ask for the next finer row's pages before the
/// wanted row's, so the streamer, which takes requests by decreasing wish and stops at the first
/// load set it cannot free slots for, still refines them (asking only for the wanted row, whose
/// closure never fit, they stayed at the root: one page and 48 K triangles for good).
#[test]
fn a_tight_budget_still_refines_small_instances() {
    let ctx = gpu();
    let mut one = bunny();
    paginate(&mut one, 12288, u32::MAX);
    let opts = StreamOptions {
        budget_bytes: 150_000,
        upload_bytes_per_frame: 64 << 10,
    };
    let (mut r, mut s) = streamed_bunny_field(&ctx, &one, opts);
    assert!(s.slot_count() < 16, "{} slots", s.slot_count());
    let settings = FrameSettings {
        error_px: 0.05,
        ..Default::default()
    };
    let eye = DVec3::new(0.0, 1.5, 3.0);
    let camera = Camera::look_at(
        eye,
        DVec3::new(0.0, 0.0, -8.0),
        Vec3::Y,
        60f32.to_radians(),
        0.01,
    );
    let mut first = None;
    let mut last = None;
    for k in 0..10 {
        let f = render_with(&mut r, &camera, &settings);
        let st = s.update(&mut r.scene).expect("streaming step");
        assert!(st.resident_bytes <= opts.budget_bytes, "frame {k}: {st:?}");
        let (m, p) = (&f.main.counters, &f.post.counters);
        assert_eq!(
            m.local_walks + p.local_walks,
            0,
            "frame {k}: an instance walked"
        );
        assert!(m.tiny_cuts + p.tiny_cuts > 0, "frame {k}: no table cut");
        first.get_or_insert((f.frame.triangles, st.resident_pages));
        last = Some((f.frame.triangles, st.resident_pages));
    }
    let ((t0, _), (t1, p1)) = (first.unwrap(), last.unwrap());
    let fixed = one.resident_pages as u64;
    eprintln!("triangles {t0} -> {t1}, resident pages {fixed} -> {p1}");
    assert!(
        p1 > fixed && t1 > 10 * t0,
        "the small instances stayed coarse: {t0} -> {t1} triangles, {fixed} -> {p1} pages"
    );
    assert_no_validation_errors(&ctx);
}

/// The geometry pool (one storage buffer) grows by doubling, but never past what one buffer
/// binds: page slots of 55 % and then 44 % of `maxStorageBufferRange` fit (doubling the first
/// asked for 110 %, and the second was refused although both fit); past the limit, a clear error.
#[test]
fn the_pool_grows_up_to_the_binding_limit() {
    let ctx = gpu();
    let mut r = VgeoRenderer::new(&ctx, &[] as &[BuiltMesh], &[]).expect("empty renderer");
    let words = ctx.caps().max_storage_buffer_range as u64 / 4;
    let (a, b) = (words * 55 / 100, words * 44 / 100);
    let first = r.scene.reserve_page_slots(a).expect("55 % of the binding");
    let second = r
        .scene
        .reserve_page_slots(b)
        .expect("44 % more fit in the binding");
    assert!(second as u64 >= first as u64 + a, "{first} {second}");
    let err = r
        .scene
        .reserve_page_slots(words / 50)
        .expect_err("past the binding");
    assert!(err.to_string().contains("maxStorageBufferRange"), "{err}");
    assert_no_validation_errors(&ctx);
}

/// `stream_sizes` refuses a budget the device cannot bind (the page pool is one storage buffer)
/// before it makes any mesh (minutes each at its defaults), naming the largest that works.
#[test]
fn stream_sizes_refuses_an_unbindable_budget_before_making_meshes() {
    let ctx = gpu();
    let dir = std::env::temp_dir().join(format!("vgeo-stream-budget-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    let binds = ctx.caps().max_storage_buffer_range as u64;
    let opts = stream_sizes::Options {
        mesh: common::assets().join("spot.obj"),
        work: dir.join("work"),
        out: dir.join("out"),
        sizes: vec![1],
        budget_bytes: binds + (1 << 20),
        ..Default::default()
    };
    let err = stream_sizes::run_on(&ctx, &opts).expect_err("a budget over the binding");
    let msg = err.to_string();
    assert!(
        msg.contains("maxStorageBufferRange") && msg.contains(&format!("{} or less", binds >> 20)),
        "{msg}"
    );
    assert!(!dir.join("work").exists(), "no mesh was made");
    assert_no_validation_errors(&ctx);
}
