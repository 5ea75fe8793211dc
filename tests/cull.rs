//! GPU culling (`instance_cull` + persistent `cluster_cull`) against the CPU cut, on lavapipe with
//! validation on: the drawn (instance, cluster) set must equal the CPU reference cut (frustum off)
//! for several cameras and thresholds, with 1 and several persistent workgroups.

mod common;

use std::collections::BTreeSet;

use common::{assert_no_validation_errors, assets, gpu, shared_assets};
use glam::{DMat4, DQuat, DVec3, Vec3};
use vgeo::builder::{BuildOptions, BuiltMesh, build};
use vgeo::camera::Camera;
use vgeo::frame::VgeoRenderer;
use vgeo::passes::view::FrameSettings;
use vgeo::reference::cut::{reference_cut, view_for};
use vgeo::render::Placement;
use vgeo::shared::VIEW_FLAG_NO_FRUSTUM;

fn built(path: &std::path::Path) -> BuiltMesh {
    let (mesh, _) = vgeo::mesh::load_mesh(path).expect("mesh loads");
    build(&mesh, &BuildOptions::default()).expect("mesh builds")
}

/// A camera over a field of instances: 50 degrees, near plane at 0.05.
fn field_camera(eye: DVec3, target: DVec3) -> Camera {
    Camera::look_at(eye, target, Vec3::Y, 50f32.to_radians(), 0.05)
}

/// How many of the `placements` of mesh `index` (`mesh`) project to a radius over
/// `TINY_CUT_RADIUS_PX` in `compare`'s 320 x 240 view from a `field_camera` (half the mesh's
/// largest extent, at its box's centre: no sphere around it is smaller).
fn over_tiny_cut_size(
    mesh: &BuiltMesh,
    placements: &[Placement],
    index: u32,
    camera: &Camera,
) -> usize {
    let (lo, hi) = mesh.clusters.iter().fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), c| (lo.min(c.bounds_min.into()), hi.max(c.bounds_max.into())),
    );
    let proj_scale = 240.0 / (2.0 * 25f32.to_radians().tan());
    placements
        .iter()
        .filter(|p| p.mesh == index)
        .filter(|p| {
            let c = p.transform.transform_point3(((lo + hi) * 0.5).as_dvec3());
            let d = (c - camera.position).length() as f32;
            (hi - lo).max_element() * 0.5 * proj_scale / d > vgeo::shared::TINY_CUT_RADIUS_PX
        })
        .count()
}

/// Compares GPU and CPU cuts; returns (cut size, borderline differences).
fn compare(
    r: &mut VgeoRenderer,
    meshes: &[BuiltMesh],
    placements: &[Placement],
    camera: &Camera,
    error_px: f32,
) -> (usize, usize) {
    let (w, h) = (320, 240);
    let settings = FrameSettings {
        error_px,
        flags: VIEW_FLAG_NO_FRUSTUM,
        ..Default::default()
    };
    let res = r.cull(camera, w, h, &settings).expect("cull runs");
    res.check().expect("no overflow, no watchdog");
    let gpu: BTreeSet<(u32, u32)> = res.visible.iter().map(|v| (v[0], v[1])).collect();
    assert_eq!(gpu.len(), res.visible.len(), "a cluster was emitted twice");
    assert_eq!(
        res.sw.len() + res.hw.len(),
        res.visible.len(),
        "every visible cluster goes to one rasterizer"
    );
    let view = view_for(camera, w, h, &settings);
    let (cut, borderline) = reference_cut(meshes, placements, &view, 1e-4);
    let cpu: BTreeSet<(u32, u32)> = cut.iter().map(|e| (e.instance, e.cluster)).collect();
    let border: BTreeSet<(u32, u32)> = borderline.iter().map(|e| (e.instance, e.cluster)).collect();
    let diff: Vec<_> = gpu.symmetric_difference(&cpu).collect();
    let hard: Vec<_> = diff.iter().filter(|d| !border.contains(d)).collect();
    assert!(
        hard.is_empty(),
        "GPU cut differs from the CPU cut at tau={error_px} on {} clusters (not borderline), e.g. {:?}; gpu {} cpu {}",
        hard.len(),
        &hard[..hard.len().min(5)],
        gpu.len(),
        cpu.len()
    );
    let tris: u32 = res.visible.iter().map(|v| r_triangles(meshes, v[1])).sum();
    assert_eq!(res.counters.triangles, tris, "triangle counter");
    (cpu.len(), diff.len())
}

/// The (instance, cluster) pairs in which `gpu` and the CPU's `cut` differ, but for the
/// `borderline` ones (either side acceptable).
fn off_borderline(
    gpu: &BTreeSet<(u32, u32)>,
    cut: &[vgeo::reference::cut::CutEntry],
    borderline: &[vgeo::reference::cut::CutEntry],
) -> Vec<(u32, u32)> {
    let cpu: BTreeSet<(u32, u32)> = cut.iter().map(|e| (e.instance, e.cluster)).collect();
    let border: BTreeSet<(u32, u32)> = borderline.iter().map(|e| (e.instance, e.cluster)).collect();
    gpu.symmetric_difference(&cpu)
        .filter(|c| !border.contains(c))
        .copied()
        .collect()
}

fn r_triangles(meshes: &[BuiltMesh], global: u32) -> u32 {
    global_cluster(meshes, global).triangle_count()
}

/// The cluster of global index `global` (the meshes' clusters one after the other, as uploaded).
fn global_cluster(meshes: &[BuiltMesh], global: u32) -> &vgeo::builder::Cluster {
    let mut g = global as usize;
    for m in meshes {
        if g < m.clusters.len() {
            return &m.clusters[g];
        }
        g -= m.clusters.len();
    }
    panic!("cluster index {global} out of range")
}

#[test]
fn gpu_cut_equals_cpu_cut_on_bunny() {
    let ctx = gpu();
    let bunny = built(&shared_assets().join("scanned/bunny.ply"));
    let meshes = vec![bunny];
    let placements = vec![Placement {
        mesh: 0,
        transform: DMat4::IDENTITY,
        color: [1.0; 3],
    }];
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).expect("renderer");
    let center = DVec3::new(-0.017, 0.11, 0.0);
    let level0 = meshes[0].clusters.iter().filter(|c| c.level == 0).count();
    for (k, dist) in [0.25, 0.6, 2.0, 10.0].into_iter().enumerate() {
        let eye = center + DVec3::new(0.3, 0.2, 1.0).normalize() * dist;
        let camera = Camera::look_at(eye, center, Vec3::Y, 45f32.to_radians(), 0.01);
        for tau in [0.0, 0.5, 1.0, 4.0, 32.0] {
            let workgroups = [1, 3][k % 2];
            r.set_cull_workgroups(workgroups).unwrap();
            let (n, border) = compare(&mut r, &meshes, &placements, &camera, tau);
            if tau == 0.0 {
                assert_eq!(n, level0, "threshold 0 draws exactly level 0");
            }
            eprintln!(
                "bunny d={dist} tau={tau} wg={workgroups}: cut {n} clusters, {border} borderline differences"
            );
        }
    }
    assert_no_validation_errors(&ctx);
}

#[test]
fn gpu_cut_equals_cpu_cut_on_many_instances() {
    let ctx = gpu();
    let spot = built(&assets().join("spot.obj"));
    let meshes = vec![spot];
    let mut placements = Vec::new();
    for i in 0..6 {
        for j in 0..5 {
            let t = DVec3::new(i as f64 * 2.5, 0.0, -(j as f64) * 3.0);
            let rot = DQuat::from_rotation_y(0.7 * (i * 5 + j) as f64);
            let s = 0.5 + 0.25 * ((i + j) % 4) as f64;
            placements.push(Placement {
                mesh: 0,
                transform: DMat4::from_scale_rotation_translation(DVec3::splat(s), rot, t),
                color: [1.0; 3],
            });
        }
    }
    // One instance far from the origin, with the camera near it too.
    placements.push(Placement {
        mesh: 0,
        transform: DMat4::from_translation(DVec3::new(1.0e6, 2.0e5, -3.0e6)),
        color: [1.0; 3],
    });
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).expect("renderer");
    let cams = [
        Camera::look_at(
            DVec3::new(6.0, 4.0, 8.0),
            DVec3::new(6.0, 0.0, -6.0),
            Vec3::Y,
            50f32.to_radians(),
            0.05,
        ),
        Camera::look_at(
            DVec3::new(-2.0, 1.0, 2.0),
            DVec3::new(0.0, 0.0, 0.0),
            Vec3::Y,
            60f32.to_radians(),
            0.05,
        ),
        Camera::look_at(
            DVec3::new(1.0e6 + 2.0, 2.0e5 + 1.0, -3.0e6 + 3.0),
            DVec3::new(1.0e6, 2.0e5, -3.0e6),
            Vec3::Y,
            45f32.to_radians(),
            0.05,
        ),
    ];
    for (k, camera) in cams.iter().enumerate() {
        for tau in [0.0, 1.0, 2.0, 8.0] {
            r.set_cull_workgroups([1, 2, 4][k]).unwrap();
            let (n, border) = compare(&mut r, &meshes, &placements, camera, tau);
            eprintln!(
                "spot x31 camera {k} tau={tau}: cut {n} clusters, {border} borderline differences"
            );
        }
    }
    assert_no_validation_errors(&ctx);
}

#[test]
fn frustum_culling_removes_what_is_behind_the_camera() {
    let ctx = gpu();
    let spot = built(&assets().join("spot.obj"));
    let meshes = vec![spot];
    let placements: Vec<Placement> = (0..8)
        .map(|i| Placement {
            mesh: 0,
            // Instances 0..4 in front of the camera (looking down -z), 4..8 behind it.
            transform: DMat4::from_translation(DVec3::new(
                (i % 4) as f64 * 1.5 - 2.0,
                0.0,
                if i < 4 { -6.0 } else { 6.0 },
            )),
            color: [1.0; 3],
        })
        .collect();
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).expect("renderer");
    let camera = Camera::look_at(
        DVec3::ZERO,
        DVec3::new(0.0, 0.0, -1.0),
        Vec3::Y,
        60f32.to_radians(),
        0.05,
    );
    let res = r
        .cull(&camera, 320, 240, &FrameSettings::default())
        .expect("cull");
    res.check().unwrap();
    assert_eq!(res.counters.instances_tested, 8);
    assert_eq!(
        res.counters.instances_visible, 4,
        "the 4 instances behind the camera are culled"
    );
    assert!(
        res.visible.iter().all(|v| v[0] < 4),
        "no cluster of an instance behind the camera"
    );
    assert!(!res.visible.is_empty());
    assert_no_validation_errors(&ctx);
}

/// In a view of many instances (`WALK_WIDE_INSTANCES`), small instances take their cut from their
/// mesh's table (`emit_tiny_cut`: no BVH walk, no global queue): grass clumps (a DAG of 6
/// clusters, at most `WALK_CLUSTERS`: always, the ones nearest the camera too, over
/// `TINY_CUT_RADIUS_PX`) and spots at many distances (only where the table holds a fine enough
/// cut: `TINY_CUT_CLUSTERS`); the nearest spots go through `cluster_cull`'s queue. In a view of fewer,
/// small instances walk their BVH inside `instance_cull` (where at most `WALK_CLUSTERS` of their
/// clusters can be in the cut). The cut is the CPU's (`reference_cut`, which projects a small
/// instance's errors as the table does) either way.
#[test]
fn small_instances_take_their_cut_from_the_table_with_the_same_cut() {
    use vgeo::shared::{WALK_CLUSTERS, WALK_WIDE_INSTANCES};
    let ctx = gpu();
    let meshes = spot_and_grass();
    assert!(meshes[1].clusters.len() <= WALK_CLUSTERS as usize);
    assert!(meshes[0].clusters.len() > WALK_CLUSTERS as usize);
    let camera = field_camera(DVec3::new(0.0, 1.0, 2.0), DVec3::new(0.0, 0.0, -10.0));
    // 12 x 12 instances (the narrow bound), then 64 x 64 (the wide one).
    for side in [12usize, 64] {
        let placements = spot_and_grass_field(side);
        assert_eq!(
            placements.len() >= WALK_WIDE_INSTANCES as usize,
            side == 64,
            "the second grid uses the wide bound"
        );
        let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).expect("renderer");
        let taus: &[f32] = &[0.5, 1.0, 4.0];
        for &tau in taus {
            r.set_cull_workgroups(2).unwrap();
            let (n, border) = compare(&mut r, &meshes, &placements, &camera, tau);
            let settings = FrameSettings {
                error_px: tau,
                flags: VIEW_FLAG_NO_FRUSTUM,
                ..Default::default()
            };
            let res = r.cull(&camera, 320, 240, &settings).expect("cull runs");
            let tiny = res.counters.tiny_cuts as usize;
            let grass = placements.iter().filter(|p| p.mesh == 1).count();
            eprintln!(
                "{side}x{side}, tau={tau}: cut {n} clusters, {border} borderline, {tiny} of {} instances cut from the table",
                placements.len()
            );
            if side == 64 {
                // Every grass clump (whose root alone is not fine), close ones too, and some
                // spots take the table's cut; the nearest spots still go through cluster_cull's
                // queue.
                let large = over_tiny_cut_size(&meshes[1], &placements, 1, &camera);
                assert!(large > 0, "no grass clump is over the table's size limit");
                assert!(tiny > grass && tiny < placements.len(), "{tiny} of {grass}");
            } else {
                // A view of few instances walks them instead (one thread's whole cut would be
                // its latency): every grass clump and some spots locally.
                let local = res.counters.local_walks as usize;
                assert_eq!(tiny, 0);
                assert!(local > grass / 2 && local < placements.len(), "{local}");
            }
        }
    }
    assert_no_validation_errors(&ctx);
}

/// Spot (mesh 0, more than `WALK_CLUSTERS` clusters) and a grass clump (mesh 1, at most that).
fn spot_and_grass() -> Vec<BuiltMesh> {
    let spot = built(&assets().join("spot.obj"));
    let grass = build(
        &vgeo::generated_mesh("grass").expect("grass"),
        &BuildOptions::default(),
    )
    .expect("grass builds");
    vec![spot, grass]
}

/// `side` x `side` instances of meshes 0 and 1 in turn, rotated, from 1.5 to 1.5 x 1.35^12 in
/// front of `field_camera(0, 1, 2)` looking down -z, spread wider with distance.
fn spot_and_grass_field(side: usize) -> Vec<Placement> {
    let mut placements = Vec::new();
    for i in 0..side {
        for j in 0..side {
            let z = -1.5 * (1.35f64).powf(j as f64 * 12.0 / side as f64);
            let x = (i as f64 / side as f64 - 0.5) * 2.4 * z.abs().sqrt();
            placements.push(Placement {
                mesh: ((i + j) % 2) as u32,
                transform: DMat4::from_rotation_translation(
                    DQuat::from_rotation_y(0.37 * (i * side + j) as f64),
                    DVec3::new(x, 0.0, z),
                ),
                color: [1.0; 3],
            });
        }
    }
    placements
}

/// In a view of `WALK_WIDE_INSTANCES` to `SHARED_RUNS_MAX_INSTANCES` instances `instance_cull`
/// takes its `shared` variant: the workgroup tests the clusters of its threads' small-instance
/// cuts and local walks (a walk's groups past `SHARED_RUNS_PER_THREAD` go to `cluster_cull`'s
/// queue). Its cut is the plain variant's and the CPU's, cluster for cluster, with the same
/// table cuts and local walks, at three thresholds (one where walks reach many groups).
#[test]
fn shared_runs_draw_the_plain_variants_cut() {
    use vgeo::passes::instance_cull::shares_runs;
    use vgeo::shared::{SHARED_RUNS_MAX_INSTANCES, WALK_WIDE_INSTANCES};
    assert!(!shares_runs(WALK_WIDE_INSTANCES - 1) && shares_runs(WALK_WIDE_INSTANCES));
    assert!(shares_runs(SHARED_RUNS_MAX_INSTANCES - 1) && !shares_runs(SHARED_RUNS_MAX_INSTANCES));
    let ctx = gpu();
    let meshes = spot_and_grass();
    let camera = field_camera(DVec3::new(0.0, 1.0, 2.0), DVec3::new(0.0, 0.0, -10.0));
    let placements = spot_and_grass_field(64);
    assert!(shares_runs(placements.len() as u32));
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).expect("renderer");
    let (mut tiny, mut walks) = (0, 0);
    for tau in [0.25f32, 1.0, 4.0] {
        let settings = FrameSettings {
            error_px: tau,
            flags: VIEW_FLAG_NO_FRUSTUM,
            ..Default::default()
        };
        let mut runs = Vec::new();
        for force in [true, false] {
            r.set_shared_runs(Some(force));
            compare(&mut r, &meshes, &placements, &camera, tau);
            let res = r.cull(&camera, 320, 240, &settings).expect("cull runs");
            let cut: BTreeSet<(u32, u32)> = res.visible.iter().map(|v| (v[0], v[1])).collect();
            let c = res.counters;
            runs.push((cut, c.tiny_cuts, c.local_walks, c.triangles));
        }
        let (shared, plain) = (&runs[0], &runs[1]);
        eprintln!(
            "tau={tau}: {} clusters, {} table cuts, {} local walks",
            shared.0.len(),
            shared.1,
            shared.2
        );
        assert!(shared == plain, "tau={tau}: the variants' cuts differ");
        tiny += shared.1;
        walks += shared.2;
    }
    assert!(tiny > 0 && walks > 0, "the views have table cuts and walks");
    r.set_shared_runs(None);
    assert_no_validation_errors(&ctx);
}

/// Whole frames with both `instance_cull` variants: a cold frame, then two as the camera moves
/// (frustum and two-phase occlusion culling on) over 67 x 67 spots and clumps, with one thread
/// per instance and with 7 workgroups (each then takes several rounds of items, with runs in
/// consecutive rounds). Each frame's image, depth, triangles, and per phase the drawn clusters
/// (none twice), table cuts, local walks and deferred items are the plain variant's; at one
/// thread per instance, so are those of the culls' pipelines with the partial-residency code,
/// which this all-resident scene does not otherwise run (`CullPipelines`).
#[test]
fn shared_runs_render_the_plain_variants_frames() {
    use vgeo::ViewMode;
    use vgeo::frame::VgeoFrame;
    use vgeo::passes::instance_cull::shares_runs;
    use vgeo::render::Light;
    use vgeo::shared::INSTANCE_CULL_WORKGROUP_SIZE;
    let ctx = gpu();
    let meshes = spot_and_grass();
    let placements = spot_and_grass_field(67);
    assert!(shares_runs(placements.len() as u32));
    let cameras = [
        field_camera(DVec3::new(0.0, 1.0, 2.0), DVec3::new(0.0, 0.0, -10.0)),
        field_camera(DVec3::new(0.3, 0.8, 0.5), DVec3::new(-0.5, 0.0, -10.0)),
        field_camera(DVec3::new(0.6, 0.6, -1.0), DVec3::new(-1.0, 0.0, -10.0)),
    ];
    let settings = FrameSettings {
        error_px: 1.0,
        ..Default::default()
    };
    for cap in [None, Some(7u32)] {
        let threads = (placements.len() as u32)
            .div_ceil(INSTANCE_CULL_WORKGROUP_SIZE)
            .min(cap.unwrap_or(u32::MAX))
            * INSTANCE_CULL_WORKGROUP_SIZE;
        let mut frames: Vec<Vec<VgeoFrame>> = Vec::new();
        // (shared, streaming): the plain variant is compared with the shared one, and at one
        // thread per instance the shared one with the streaming pipelines.
        let configs = [(true, false), (false, false), (true, true)];
        let n = if cap.is_none() { 3 } else { 2 };
        for &(force, streaming) in &configs[..n] {
            let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).expect("renderer");
            r.set_shared_runs(Some(force));
            r.set_instance_cull_workgroups(cap);
            assert!(!r.streaming_cull(), "all resident");
            r.force_streaming_cull(streaming);
            assert_eq!(r.streaming_cull(), streaming);
            frames.push(
                cameras
                    .iter()
                    .map(|c| {
                        let f = r
                            .render(c, 320, 240, &settings, ViewMode::Lambert, &Light::default())
                            .expect("frame renders");
                        f.check().expect("no overflow, no watchdog");
                        f
                    })
                    .collect(),
            );
        }
        let mut rounds = false;
        let pairs = frames[1..].iter().flat_map(|f| frames[0].iter().zip(f));
        for (k, (s, p)) in pairs.enumerate() {
            let i = k % cameras.len();
            let (m, q) = (&s.main.counters, &s.post.counters);
            let post_items = m.post_instance_count + m.post_node_count + m.post_cluster_count;
            eprintln!(
                "{threads} threads, frame {i}: {} triangles; main {} table cuts, {} walks; post {} items",
                s.frame.triangles, m.tiny_cuts, m.local_walks, post_items
            );
            rounds |= post_items > threads && q.visible_count > 0;
            assert!(
                s.frame.color == p.frame.color,
                "frame {i}: the image differs"
            );
            assert!(
                s.frame.depth == p.frame.depth,
                "frame {i}: the depth differs"
            );
            assert_eq!(s.frame.triangles, p.frame.triangles, "frame {i}: triangles");
            for (phase, a, b) in [("main", &s.main, &p.main), ("post", &s.post, &p.post)] {
                let set = |c: &vgeo::frame::CullResult| -> BTreeSet<(u32, u32)> {
                    c.visible.iter().map(|v| (v[0], v[1])).collect()
                };
                assert_eq!(
                    set(a).len(),
                    a.visible.len(),
                    "frame {i}, {phase}: a cluster drawn twice"
                );
                assert!(
                    set(a) == set(b),
                    "frame {i}, {phase} phase: the drawn clusters differ"
                );
                let (x, y) = (&a.counters, &b.counters);
                assert_eq!(
                    (
                        x.tiny_cuts,
                        x.local_walks,
                        x.post_instance_count,
                        x.post_cluster_count
                    ),
                    (
                        y.tiny_cuts,
                        y.local_walks,
                        y.post_instance_count,
                        y.post_cluster_count
                    ),
                    "frame {i}, {phase} phase: counters"
                );
            }
        }
        assert!(
            rounds,
            "no frame's post phase took several rounds of a workgroup"
        );
    }
    assert_no_validation_errors(&ctx);
}

/// A mesh of at most `WALK_CLUSTERS` clusters (a grass clump) takes its cut from its table at any
/// size in a view of many instances: clumps from far to around the camera (over
/// `TINY_CUT_RADIUS_PX`, some reaching the near plane) all take it, none walks its BVH, and the
/// cut is the CPU's.
#[test]
fn clumps_of_any_size_take_their_cut_from_the_table() {
    use vgeo::shared::{WALK_CLUSTERS, WALK_WIDE_INSTANCES};
    let ctx = gpu();
    let grass = build(
        &vgeo::generated_mesh("grass").expect("grass"),
        &BuildOptions::default(),
    )
    .expect("grass builds");
    assert!(grass.clusters.len() <= WALK_CLUSTERS as usize);
    let meshes = vec![grass];
    let camera = field_camera(DVec3::new(0.0, 0.5, 0.5), DVec3::new(0.0, 0.3, -10.0));
    let side = 64usize;
    let mut placements = Vec::new();
    for i in 0..side {
        for j in 0..side {
            placements.push(Placement {
                mesh: 0,
                transform: DMat4::from_rotation_translation(
                    DQuat::from_rotation_y(0.61 * (i * side + j) as f64),
                    DVec3::new((i as f64 - side as f64 / 2.0) * 0.6, 0.0, -(j as f64) * 0.6),
                ),
                color: [1.0; 3],
            });
        }
    }
    assert!(placements.len() >= WALK_WIDE_INSTANCES as usize);
    let large = over_tiny_cut_size(&meshes[0], &placements, 0, &camera);
    assert!(large > 8, "{large} clumps over the size limit");
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).expect("renderer");
    for tau in [0.5f32, 1.0, 4.0] {
        compare(&mut r, &meshes, &placements, &camera, tau);
        let settings = FrameSettings {
            error_px: tau,
            flags: VIEW_FLAG_NO_FRUSTUM,
            ..Default::default()
        };
        let res = r.cull(&camera, 320, 240, &settings).expect("cull runs");
        let c = &res.counters;
        eprintln!(
            "tau={tau}: {} of {} instances cut from the table ({large} over the size limit), {} walks, {} BVH nodes",
            c.tiny_cuts,
            placements.len(),
            c.local_walks,
            c.nodes_visited
        );
        assert_eq!(c.local_walks, 0, "a clump walked its BVH");
        assert_eq!(c.nodes_visited, 0, "a clump walked its BVH");
        // Every clump takes the table, but those the HZB defers to the post phase (`cull`
        // runs the main phase only).
        assert_eq!(
            (c.tiny_cuts + c.post_instance_count) as usize,
            placements.len(),
            "instances neither cut from the table nor deferred"
        );
    }
    assert_no_validation_errors(&ctx);
}

/// A small instance counts a share of its errors (`small_instance_weight`: under
/// `SMALL_WEIGHT_RADIUS_PX`, its radius over that, at least `SMALL_WEIGHT_MIN`) in every test of its
/// cut. Spots 4-20 px in radius, in a view of many instances (their cuts from the table) and of one
/// fewer (below `WALK_WIDE_INSTANCES`: the per-group rule): the GPU's cut is the CPU oracle's,
/// which weighs them the same, and both draw fewer triangles than the per-group rule with whole
/// errors (`cluster_in_cut`), which neither would undercut without the weight (the table's cut is
/// never coarser than that rule).
#[test]
fn small_instances_count_a_share_of_their_errors() {
    use vgeo::builder::cut::{cluster_in_cut, proj_scale, small_instance_weight};
    use vgeo::shared::{SMALL_WEIGHT_MIN, SMALL_WEIGHT_RADIUS_PX, WALK_WIDE_INSTANCES};
    // The weight itself: 1 from the radius up (and for infinity and NaN), proportional below, and
    // at least the minimum.
    let r = SMALL_WEIGHT_RADIUS_PX;
    assert_eq!(small_instance_weight(r), 1.0);
    assert_eq!(small_instance_weight(2.0 * r), 1.0);
    assert_eq!(small_instance_weight(f32::INFINITY), 1.0);
    assert_eq!(small_instance_weight(f32::NAN), 1.0);
    assert_eq!(small_instance_weight(0.5 * r), 0.5f32.max(SMALL_WEIGHT_MIN));
    assert_eq!(small_instance_weight(0.0), SMALL_WEIGHT_MIN);
    let ctx = gpu();
    let meshes = vec![built(&assets().join("spot.obj"))];
    let camera = field_camera(DVec3::new(0.0, 0.5, 0.0), DVec3::new(0.0, 0.0, -30.0));
    let side = 64usize;
    let mut placements = Vec::new();
    for i in 0..side {
        for j in 0..side {
            // Rows from 12 to 60 units away.
            let z = -12.0 * 5f64.powf(j as f64 / (side - 1) as f64);
            let x = (i as f64 / side as f64 - 0.5) * 0.8 * z.abs();
            placements.push(Placement {
                mesh: 0,
                transform: DMat4::from_rotation_translation(
                    DQuat::from_rotation_y(0.37 * (i * side + j) as f64),
                    DVec3::new(x, 0.0, z),
                ),
                color: [1.0; 3],
            });
        }
    }
    assert_eq!(placements.len(), WALK_WIDE_INSTANCES as usize);
    let (w, h) = (320, 240);
    let settings = FrameSettings {
        error_px: 1.0,
        flags: VIEW_FLAG_NO_FRUSTUM,
        ..Default::default()
    };
    // Triangles of `placements`' cut on the GPU (checked against the CPU oracle's), instances cut
    // from the table, and triangles of the per-group rule with whole errors (the spots are rigid:
    // the camera in each one's object space sees the same distances).
    let ps = proj_scale(h as f32, camera.fov_y);
    let cut = |placements: &[Placement]| {
        let mut r = VgeoRenderer::new(&ctx, &meshes, placements).expect("renderer");
        compare(&mut r, &meshes, placements, &camera, settings.error_px);
        let res = r.cull(&camera, w, h, &settings).expect("cull runs");
        let whole: u64 = placements
            .iter()
            .map(|p| {
                let eye = p.transform.inverse().transform_point3(camera.position);
                meshes[0]
                    .clusters
                    .iter()
                    .filter(|c| cluster_in_cut(c, eye.as_vec3(), ps, settings.error_px))
                    .map(|c| c.triangle_count() as u64)
                    .sum::<u64>()
            })
            .sum();
        (res.counters.triangles as u64, res.counters.tiny_cuts, whole)
    };
    for (n, table) in [(placements.len(), true), (placements.len() - 1, false)] {
        let (weighted, tiny, whole) = cut(&placements[..n]);
        eprintln!(
            "{n} instances, {tiny} cut from the table: {weighted} triangles; with whole errors by the per-group rule {whole}"
        );
        if table {
            assert_eq!(tiny as usize, n, "every spot takes the table");
        } else {
            assert_eq!(tiny, 0, "a view of fewer instances took the table");
        }
        assert!(
            (weighted as f64) < 0.95 * whole as f64,
            "small instances drew {weighted} triangles, with whole errors {whole}"
        );
    }
    assert_no_validation_errors(&ctx);
}

/// Partial residency on the GPU: with random closed sets of bunny's pages marked absent
/// (`GpuScene::set_page_residency`), the GPU cut equals the CPU cut under the same residency
/// (`reference_cut_resident`, the rule of `builder::cut`), draws only resident pages, marks
/// exactly the pages of drawn clusters used, and asks for exactly the absent pages of the groups
/// that drawn clusters would refine into.
#[test]
fn gpu_cut_under_partial_residency_equals_the_cpu_cut_and_asks_for_the_missing_pages() {
    use vgeo::builder::cut::group_resident;
    use vgeo::builder::page::{close_residency, group_needs, paginate};
    use vgeo::reference::cut::reference_cut_resident;
    let ctx = gpu();
    let mut bunny = built(&shared_assets().join("scanned/bunny.ply"));
    // Small pages, so that residency has many pages to choose from.
    let level = bunny.fallback_level(2000);
    paginate(&mut bunny, 8192, level);
    assert!(bunny.pages.len() > 40, "{} pages", bunny.pages.len());
    let needs = group_needs(&bunny);
    let meshes = vec![bunny];
    let m = &meshes[0];
    let placements = vec![Placement {
        mesh: 0,
        transform: DMat4::IDENTITY,
        color: [1.0; 3],
    }];
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).expect("renderer");
    assert!(!r.streaming_cull(), "all resident");
    let h = r.scene.mesh_handle(0).expect("mesh");
    let center = DVec3::new(-0.017, 0.11, 0.0);
    let (w, hgt) = (320, 240);
    let mut asked_total = 0;
    for seed in 0..6u32 {
        let mut res: Vec<bool> = (0..m.pages.len())
            .map(|p| (p as u32 * 7 + seed * 11) % 6 < seed % 6)
            .collect();
        close_residency(m, &needs, &mut res);
        r.scene.set_page_residency(h, &res).expect("residency");
        let partial = res.iter().any(|&p| !p);
        assert_eq!(r.scene.partial_meshes(), partial as u32);
        assert_eq!(r.streaming_cull(), partial, "the culls' pipelines");
        for (dist, tau) in [(0.3, 1.0), (0.8, 0.5), (3.0, 2.0)] {
            let eye = center + DVec3::new(0.3, 0.2, 1.0).normalize() * dist;
            let camera = Camera::look_at(eye, center, Vec3::Y, 45f32.to_radians(), 0.01);
            let settings = FrameSettings {
                error_px: tau,
                flags: VIEW_FLAG_NO_FRUSTUM,
                ..Default::default()
            };
            r.scene.clear_page_feedback().expect("clear");
            let out = r.cull(&camera, w, hgt, &settings).expect("cull runs");
            out.check().expect("no overflow, no watchdog");
            let gpu: BTreeSet<u32> = out.visible.iter().map(|v| v[1]).collect();
            let view = view_for(&camera, w, hgt, &settings);
            let (cut, borderline) =
                reference_cut_resident(&meshes, &[Some(&res)], &placements, &view, 1e-4);
            let cpu: BTreeSet<u32> = cut.iter().map(|e| e.cluster).collect();
            let border: BTreeSet<u32> = borderline.iter().map(|e| e.cluster).collect();
            let hard: Vec<_> = gpu
                .symmetric_difference(&cpu)
                .filter(|c| !border.contains(c))
                .collect();
            assert!(
                hard.is_empty(),
                "seed {seed}: GPU and CPU cuts differ on {hard:?}"
            );
            for &c in &gpu {
                assert!(
                    res[m.clusters[c as usize].page as usize],
                    "cluster {c} not resident"
                );
            }
            // Feedback: used pages are the drawn clusters'; asked pages are the absent children
            // of drawn clusters coarser than wanted.
            let (wish, used) = r.scene.page_feedback(h).expect("feedback");
            let want_used: BTreeSet<u32> =
                gpu.iter().map(|&c| m.clusters[c as usize].page).collect();
            let got_used: BTreeSet<u32> = (0..used.len() as u32)
                .filter(|&p| used[p as usize])
                .collect();
            assert_eq!(got_used, want_used, "seed {seed}: used pages");
            let mut want_asked = BTreeSet::new();
            let mut near = BTreeSet::new();
            for &c in &cpu {
                let cl = &m.clusters[c as usize];
                if cl.creator == vgeo::builder::NO_GROUP
                    || group_resident(m, Some(&res), cl.creator)
                {
                    continue;
                }
                // Its self pair (its creator group's), weighted as the cull weighs it.
                let inst = vgeo::scene_gpu::instance_gpu(&placements[0]);
                let w = vgeo::reference::cut::instance_weight(m, &inst, &view);
                let px = vgeo::reference::cut::group_error_px(m, &inst, &view, cl.creator, w);
                let g = &m.groups[cl.creator as usize];
                for p in g.page_first..g.page_first + g.page_count {
                    if res[p as usize] {
                        continue;
                    }
                    if (px - tau).abs() <= 1e-3 * tau {
                        near.insert(p);
                    } else if px > tau {
                        want_asked.insert(p);
                    }
                }
            }
            let got_asked: BTreeSet<u32> = (0..wish.len() as u32)
                .filter(|&p| wish[p as usize] > 0.0)
                .collect();
            let diff: Vec<_> = got_asked
                .symmetric_difference(&want_asked)
                .filter(|p| !near.contains(p))
                .collect();
            assert!(
                diff.is_empty(),
                "seed {seed}: asked pages differ on {diff:?}"
            );
            for &p in &got_asked {
                assert!(
                    !res[p as usize] && wish[p as usize] >= 1.0,
                    "page {p}: wish {}",
                    wish[p as usize]
                );
            }
            asked_total += got_asked.len();
        }
    }
    assert!(asked_total > 10, "only {asked_total} pages asked for");
    // The always-resident pages cannot be marked absent.
    let mut bad = vec![true; m.pages.len()];
    bad[0] = false;
    assert!(r.scene.set_page_residency(h, &bad).is_err());
    // Every page back: the culls leave the partial-residency code out again.
    r.scene
        .set_page_residency(h, &vec![true; m.pages.len()])
        .expect("all resident");
    assert!(r.scene.partial_meshes() == 0 && !r.streaming_cull());
    // Removing a partial mesh leaves no partial mesh behind.
    let mut res = vec![false; m.pages.len()];
    close_residency(m, &needs, &mut res);
    r.scene.set_page_residency(h, &res).expect("residency");
    assert_eq!(r.scene.partial_meshes(), 1);
    let i = r.scene.instance_handle(0).expect("instance");
    r.scene.remove_instance(i).expect("instance removed");
    r.scene.remove_mesh(h).expect("mesh removed");
    assert!(r.scene.partial_meshes() == 0 && !r.streaming_cull());
    assert_no_validation_errors(&ctx);
}

/// Small instances under partial residency (a view of 64 x 64 spots and clumps, spot's pages
/// small and random closed sets of them absent): each takes the finest row of its mesh's table at
/// most as fine as wanted whose clusters are all resident, in both `instance_cull` variants,
/// exactly the CPU cut (`reference_cut_resident`); only resident pages are drawn and the drawn
/// ones are marked used; every page asked for is absent. Loading what is asked for (with what
/// keeps the residency closed) until nothing is asked reaches the all-resident cut: the table's
/// requests are enough to settle.
#[test]
fn small_instances_under_partial_residency_take_the_finest_resident_row() {
    use vgeo::builder::page::{close_residency, group_needs, paginate};
    use vgeo::reference::cut::reference_cut_resident;
    let ctx = gpu();
    let mut meshes = spot_and_grass();
    // Small pages, so that residency has many pages to choose from.
    let level = meshes[0].fallback_level(200);
    paginate(&mut meshes[0], 2048, level);
    let spot = &meshes[0];
    assert!(spot.pages.len() > 12, "{} pages", spot.pages.len());
    let needs = group_needs(spot);
    let placements = spot_and_grass_field(64);
    // Far enough back that every spot is under TINY_CUT_RADIUS_PX: every instance takes its
    // table (no walk asks for pages on its behalf).
    let camera = field_camera(DVec3::new(0.0, 2.5, 11.0), DVec3::new(0.0, 0.0, -10.0));
    assert_eq!(over_tiny_cut_size(spot, &placements, 0, &camera), 0);
    let (w, hgt) = (320, 240);
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).expect("renderer");
    let h = r.scene.mesh_handle(0).expect("mesh");
    let cull = |r: &mut VgeoRenderer, res: &[bool], tau: f32, shared: bool| {
        r.set_shared_runs(Some(shared));
        r.scene.set_page_residency(h, res).expect("residency");
        r.scene.clear_page_feedback().expect("clear");
        let settings = FrameSettings {
            error_px: tau,
            flags: VIEW_FLAG_NO_FRUSTUM,
            ..Default::default()
        };
        let out = r.cull(&camera, w, hgt, &settings).expect("cull runs");
        out.check().expect("no overflow, no watchdog");
        let gpu: BTreeSet<(u32, u32)> = out.visible.iter().map(|v| (v[0], v[1])).collect();
        assert_eq!(gpu.len(), out.visible.len(), "a cluster was emitted twice");
        let view = view_for(&camera, w, hgt, &settings);
        let (cut, borderline) =
            reference_cut_resident(&meshes, &[Some(res), None], &placements, &view, 1e-4);
        let hard = off_borderline(&gpu, &cut, &borderline);
        assert!(
            hard.is_empty(),
            "tau={tau}, shared {shared}: GPU and CPU cuts differ on {} clusters, e.g. {:?}",
            hard.len(),
            &hard[..hard.len().min(5)]
        );
        let spot = &meshes[0];
        let drawn: BTreeSet<u32> = gpu
            .iter()
            .filter(|c| (c.1 as usize) < spot.clusters.len())
            .map(|c| spot.clusters[c.1 as usize].page)
            .collect();
        for &p in &drawn {
            assert!(res[p as usize], "page {p} drawn but not resident");
        }
        let (wish, used) = r.scene.page_feedback(h).expect("feedback");
        let got_used: BTreeSet<u32> = (0..used.len() as u32)
            .filter(|&p| used[p as usize])
            .collect();
        // (A mesh with every page resident marks none.)
        if res.iter().any(|&x| !x) {
            assert_eq!(got_used, drawn, "tau={tau}: used pages");
        }
        let asked: Vec<u32> = (0..wish.len() as u32)
            .filter(|&p| wish[p as usize] > 0.0)
            .collect();
        for &p in &asked {
            assert!(
                !res[p as usize] && wish[p as usize] >= 1.0,
                "page {p}: wish {}",
                wish[p as usize]
            );
        }
        (gpu, out.counters.tiny_cuts, asked)
    };
    let (mut coarser, mut settled_partial) = (0, 0);
    for tau in [1.0f32, 2.0, 4.0] {
        let view = view_for(
            &camera,
            w,
            hgt,
            &FrameSettings {
                error_px: tau,
                flags: VIEW_FLAG_NO_FRUSTUM,
                ..Default::default()
            },
        );
        let (all, all_border) = reference_cut(&meshes, &placements, &view, 1e-4);
        for seed in 1..4u32 {
            let mut res: Vec<bool> = (0..spot.pages.len())
                .map(|p| (p as u32 * 7 + seed * 11) % 6 < seed)
                .collect();
            close_residency(spot, &needs, &mut res);
            assert!(res.iter().any(|&x| !x), "seed {seed}: every page resident");
            // Settle by hand: load what is asked for, closed, until nothing is.
            for step in 0..40 {
                let (plain, plain_tiny, plain_asked) = cull(&mut r, &res, tau, false);
                let (cut, tiny, asked) = cull(&mut r, &res, tau, true);
                assert!(
                    cut == plain && tiny == plain_tiny && asked == plain_asked,
                    "tau={tau}, seed {seed}, step {step}: the variants differ"
                );
                assert_eq!(tiny as usize, placements.len(), "tau={tau}: table cuts");
                if asked.is_empty() {
                    // Settled: the all-resident cut (but at the borderline).
                    let hard = off_borderline(&cut, &all, &all_border).len();
                    assert!(
                        hard == 0,
                        "tau={tau}, seed {seed}: settled after {step} steps, {hard} clusters off the all-resident cut"
                    );
                    let absent = res.iter().filter(|&&x| !x).count();
                    eprintln!(
                        "tau={tau}, seed {seed}: settled after {step} steps, {tiny} table cuts, {absent} pages still absent"
                    );
                    settled_partial += (absent > 0) as u32;
                    break;
                }
                assert!(step < 39, "tau={tau}, seed {seed}: still asking");
                coarser += 1;
                for p in asked {
                    res[p as usize] = true;
                }
                close_residency(spot, &needs, &mut res);
            }
        }
    }
    assert!(coarser > 3, "only {coarser} steps asked for pages");
    // The view settles with pages still absent.
    assert!(
        settled_partial >= 4,
        "{settled_partial} settled with pages absent"
    );
    r.set_shared_runs(None);
    assert_no_validation_errors(&ctx);
}

/// Which SW clusters `emit_cluster` sends to `raster_sw`'s small paths: exactly those of at most
/// `RASTER_SW_SMALL_VERTICES` vertices that project to at most `RASTER_SW_SMALL_PX` across with
/// triangles of at most `RASTER_SW_SMALL_TRIANGLE_PX` (the cluster's size code), by the CPU's
/// evaluation of the same formulas; of them, those of at most `RASTER_SW_QUARTER_VERTICES` to the
/// quarter path (`CullCounters::sw_quarter_count`, the HW list's end), the others to the small
/// path (`sw_small_count`, the SW list's end). Clusters within 0.1 % of a bound may go either
/// way. Spot's clusters and a grass field's, whose clusters hold more vertices.
#[test]
fn small_sw_clusters_follow_the_rule() {
    use vgeo::builder::size::size_ratio;
    use vgeo::shared::{
        RASTER_SW_QUARTER_VERTICES, RASTER_SW_SMALL_PX, RASTER_SW_SMALL_TRIANGLE_PX,
        RASTER_SW_SMALL_VERTICES, VIEW_FLAG_FORCE_SW,
    };
    let ctx = gpu();
    let spot = built(&assets().join("spot.obj"));
    // Clusters of more vertices than spot's: 128 to RASTER_SW_SMALL_VERTICES, and more.
    let grass = vgeo::builder::build(&common::shapes::grass_field(2), &BuildOptions::default())
        .expect("the grass field builds");
    let meshes = vec![spot, grass];
    let camera = field_camera(DVec3::new(0.0, 1.0, 2.0), DVec3::new(0.0, 0.0, -10.0));
    let side = 12usize;
    let mut placements = Vec::new();
    for i in 0..side {
        for j in 0..side {
            let z = -1.5 * (1.45f64).powf(j as f64);
            let x = (i as f64 / side as f64 - 0.5) * 2.4 * z.abs().sqrt();
            placements.push(Placement {
                // A third of them the grass.
                mesh: ((i + j) % 3 == 0) as u32,
                transform: DMat4::from_scale_rotation_translation(
                    DVec3::splat(0.5 + 0.1 * (i % 4) as f64),
                    DQuat::from_rotation_y(0.37 * (i * side + j) as f64),
                    DVec3::new(x, 0.0, z),
                ),
                color: [1.0; 3],
            });
        }
    }
    let (w, h) = (320, 240);
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).expect("renderer");
    // Small, other, borderline, small over 7 px across, others within RASTER_SW_SMALL_PX across
    // and the vertex bound but of larger triangles, small of over 127 vertices (session 23's
    // bound), others kept off by their vertices alone, and small ones on the quarter path.
    let mut n = [0u32; 8];
    // At 1 px, and at 8 px where coarse clusters of few large triangles are drawn small.
    for error_px in [1.0f32, 8.0] {
        let settings = FrameSettings {
            error_px,
            flags: VIEW_FLAG_NO_FRUSTUM | VIEW_FLAG_FORCE_SW,
            ..Default::default()
        };
        let res = r.cull(&camera, w, h, &settings).expect("cull runs");
        res.check().expect("no overflow, no watchdog");
        let view = view_for(&camera, w, h, &settings);
        let small_n = res.counters.sw_small_count as usize;
        let quarter_n = res.counters.sw_quarter_count as usize;
        let sw_n = res.sw.len();
        assert_eq!(res.visible.len(), sw_n + res.hw.len(), "SW, then HW");
        // The SW list's front, its small end, then the HW list's end (the quarter path).
        let front_n = sw_n - small_n - quarter_n;
        for (k, &[inst, ci]) in res.visible[..sw_n].iter().enumerate() {
            let path = (k >= front_n) as u32 + (k >= front_n + small_n) as u32;
            let p = &placements[inst as usize];
            let c = global_cluster(&meshes, ci);
            let (lo, hi) = (Vec3::from(c.bounds_min), Vec3::from(c.bounds_max));
            let centre = p.transform.transform_point3(((lo + hi) * 0.5).as_dvec3());
            let radius = (hi - lo).length() * 0.5 * vgeo::render::max_axis_scale(&p.transform);
            let dist = (centre - camera.position).length() as f32 - radius;
            if dist <= view.near {
                continue;
            }
            let across = 2.0 * radius * view.proj_scale / dist;
            let size = size_ratio(c.counts >> 24) as f32 * across;
            let near = |v: f32, bound: f32| (v - bound).abs() <= 1e-3 * bound;
            if near(across, RASTER_SW_SMALL_PX) || near(size, RASTER_SW_SMALL_TRIANGLE_PX) {
                n[2] += 1;
                continue;
            }
            let expected = across <= RASTER_SW_SMALL_PX
                && size <= RASTER_SW_SMALL_TRIANGLE_PX
                && c.vertex_count() <= RASTER_SW_SMALL_VERTICES;
            let quarter = expected && c.vertex_count() <= RASTER_SW_QUARTER_VERTICES;
            assert_eq!(
                path,
                expected as u32 + quarter as u32,
                "{error_px} px, cluster {ci} of instance {inst}: {across:.2} px across, \
                 triangles {size:.2} px, {} vertices (0: front, 1: small, 2: quarter path)",
                c.vertex_count()
            );
            n[7] += quarter as u32;
            if expected {
                n[0] += 1;
                n[3] += (across > 7.0) as u32;
                n[5] += (c.vertex_count() > 127) as u32;
            } else {
                n[1] += 1;
                // Kept off the small path by its triangles alone.
                n[4] += (across <= RASTER_SW_SMALL_PX
                    && c.vertex_count() <= RASTER_SW_SMALL_VERTICES) as u32;
                n[6] +=
                    (across <= RASTER_SW_SMALL_PX && size <= RASTER_SW_SMALL_TRIANGLE_PX) as u32;
            }
        }
    }
    let [
        small,
        other,
        borderline,
        over_7,
        coarse,
        many,
        too_many,
        quarter,
    ] = n;
    eprintln!(
        "{small} small ({quarter} on the quarter path, {over_7} over 7 px across, {many} of over \
         127 vertices), {other} other SW clusters ({coarse} within the size, of larger \
         triangles; {too_many} of too many vertices), {borderline} borderline"
    );
    assert!(
        quarter > 0 && quarter < small,
        "both small paths: {quarter} of {small} on the quarter path"
    );
    // Both kinds, small clusters beyond session 23's 7 px bound, and clusters kept off the small
    // path by their triangles alone.
    assert!(small > 10 && other > 10, "{small} small, {other} other");
    assert!(over_7 > 0, "no small cluster over 7 px across");
    assert!(
        coarse > 0,
        "no cluster kept off the small path by its triangles"
    );
    assert!(many > 0, "no small cluster of over 127 vertices");
    assert!(
        too_many > 0,
        "no cluster kept off the small path by its vertices"
    );
    assert_no_validation_errors(&ctx);
}
