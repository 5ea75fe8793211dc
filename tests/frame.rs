//! The whole vgeo frame on lavapipe with validation on: no cracks, threshold 0 equals brute, SW and
//! HW agree, determinism, two-pass occlusion culling.

mod common;

use common::shapes::{mesh_from, slivers};
use common::{
    assert_no_validation_errors, assets, filling_camera, gpu, load_built, shared_assets, wall_mesh,
};
use glam::{DMat4, DVec3, Vec3};
use vgeo::baseline::brute::Brute;
use vgeo::builder::{BuildOptions, BuiltMesh, build};
use vgeo::camera::Camera;
use vgeo::frame::{VgeoFrame, VgeoRenderer};
use vgeo::gpu::{Context, ContextOptions};
use vgeo::mesh::Mesh;
use vgeo::passes::debug_view::ViewMode;
use vgeo::passes::view::FrameSettings;
use vgeo::render::{Light, Placement};
use vgeo::shared::{
    COLD_OCCLUDER_COVER, INSTANCE_CULL_WORKGROUP_SIZE, VIEW_FLAG_FORCE_HW, VIEW_FLAG_FORCE_SW,
    post_dispatch_args,
};

const W: u32 = 192;
const H: u32 = 160;

fn one(mesh: u32) -> Vec<Placement> {
    vec![Placement {
        mesh,
        transform: DMat4::IDENTITY,
        color: [0.9, 0.8, 0.7],
    }]
}

fn render(r: &mut VgeoRenderer, camera: &Camera, settings: &FrameSettings) -> VgeoFrame {
    let f = r
        .render(camera, W, H, settings, ViewMode::Lambert, &Light::default())
        .expect("frame renders");
    f.check().expect("no overflow, no watchdog");
    f
}

/// [`render`] with the same settings but occlusion culling off: the frame an occlusion-culled one
/// must equal.
fn render_without_occlusion(
    r: &mut VgeoRenderer,
    camera: &Camera,
    settings: &FrameSettings,
) -> VgeoFrame {
    render(
        r,
        camera,
        &FrameSettings {
            occlusion: false,
            ..*settings
        },
    )
}

/// Brute coverage eroded by `margin` pixels: pixels whose whole (2 margin + 1)^2 neighbourhood is covered.
fn interior(depth: &[f32], margin: i32) -> Vec<bool> {
    let (w, h) = (W as i32, H as i32);
    let mut out = vec![false; depth.len()];
    for y in 0..h {
        for x in 0..w {
            let mut all = true;
            'n: for dy in -margin..=margin {
                for dx in -margin..=margin {
                    let (nx, ny) = (x + dx, y + dy);
                    if nx < 0
                        || ny < 0
                        || nx >= w
                        || ny >= h
                        || depth[(ny * w + nx) as usize] <= 0.0
                    {
                        all = false;
                        break 'n;
                    }
                }
            }
            out[(y * w + x) as usize] = all;
        }
    }
    out
}

#[test]
fn no_cracks_in_closed_meshes_at_1_2_8_px() {
    let ctx = gpu();
    for name in ["scanned/lucy.ply", "scanned/turbineblade.ply"] {
        let (mesh, built) = load_built(&shared_assets().join(name));
        let camera = filling_camera(&mesh, 1.3);
        let brute = Brute::new(&ctx, std::slice::from_ref(&mesh)).unwrap();
        let reference = brute
            .render(&one(0), &camera, &Light::default(), W, H)
            .unwrap();
        let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &one(0)).unwrap();
        for tau in [1.0f32, 2.0, 8.0] {
            let settings = FrameSettings {
                error_px: tau,
                ..Default::default()
            };
            let f = render(&mut r, &camera, &settings);
            // A simplified silhouette may move by up to tau pixels; inside it, every pixel brute
            // covers must be covered: a crack would show the background.
            let inside = interior(&reference.depth, tau.ceil() as i32 + 1);
            let n_inside = inside.iter().filter(|b| **b).count();
            let holes = (0..inside.len())
                .filter(|&i| inside[i] && f.frame.depth[i] <= 0.0)
                .count();
            eprintln!(
                "{name} tau={tau}: {} clusters drawn, {n_inside} interior pixels, {holes} holes",
                f.visible().len()
            );
            assert!(
                n_inside > 1000,
                "{name}: the mesh should fill the view ({n_inside} interior pixels)"
            );
            assert_eq!(
                holes, 0,
                "{name} at {tau} px: {holes} background pixels inside the silhouette (cracks)"
            );
        }
    }
    assert_no_validation_errors(&ctx);
}

#[test]
fn threshold_zero_equals_brute() {
    let ctx = gpu();
    let (mesh, built) = load_built(&shared_assets().join("scanned/bunny.ply"));
    // Far enough that the whole bunny is in view (frustum culling drops nothing).
    let camera = filling_camera(&mesh, 3.0);
    let brute = Brute::new(&ctx, std::slice::from_ref(&mesh)).unwrap();
    let reference = brute
        .render(&one(0), &camera, &Light::default(), W, H)
        .unwrap();
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &one(0)).unwrap();
    let f = render(
        &mut r,
        &camera,
        &FrameSettings {
            error_px: 0.0,
            ..Default::default()
        },
    );
    let level0 = built.clusters.iter().filter(|c| c.level == 0).count();
    assert_eq!(
        f.visible().len(),
        level0,
        "threshold 0 draws exactly level 0"
    );
    let n = (W * H) as usize;
    let same = (0..n)
        .filter(|&i| (f.frame.depth[i] > 0.0) == (reference.depth[i] > 0.0))
        .count();
    let both: Vec<usize> = (0..n)
        .filter(|&i| f.frame.depth[i] > 0.0 && reference.depth[i] > 0.0)
        .collect();
    let depth_ok = both
        .iter()
        .filter(|&&i| (f.frame.depth[i] - reference.depth[i]).abs() <= 1e-3 * reference.depth[i])
        .count();
    let coverage = same as f64 / n as f64;
    let depth = depth_ok as f64 / both.len().max(1) as f64;
    eprintln!(
        "threshold 0 vs brute: coverage agreement {coverage:.5}, depth agreement {depth:.5} over {} pixels",
        both.len()
    );
    assert!(both.len() > 3000);
    assert!(
        coverage >= 0.999,
        "coverage agreement {coverage:.5} < 99.9%"
    );
    assert!(depth >= 0.999, "depth agreement {depth:.5} < 99.9%");
    assert_no_validation_errors(&ctx);
}

/// Three spots in a row, each farther back, and a camera that the first one fills: a renderer for
/// comparing rasterizer paths.
fn three_spots(ctx: &Context) -> (VgeoRenderer, Camera) {
    let (mesh, built) = load_built(&assets().join("spot.obj"));
    let camera = filling_camera(&mesh, 1.5);
    let placements: Vec<Placement> = (0..3)
        .map(|i| Placement {
            mesh: 0,
            transform: DMat4::from_translation(DVec3::new(
                i as f64 * 0.4 - 0.4,
                0.0,
                -(i as f64) * 0.5,
            )),
            color: [1.0; 3],
        })
        .collect();
    let r = VgeoRenderer::new(ctx, std::slice::from_ref(&built), &placements).unwrap();
    (r, camera)
}

#[test]
fn sw_and_hw_rasterizers_give_identical_visibility_buffers_and_frames_are_deterministic() {
    let ctx = gpu();
    let (mut r, camera) = three_spots(&ctx);
    let base = FrameSettings {
        error_px: 1.0,
        occlusion: false,
        ..Default::default()
    };
    let sw = render(
        &mut r,
        &camera,
        &FrameSettings {
            flags: VIEW_FLAG_FORCE_SW,
            ..base
        },
    );
    let hw = render(
        &mut r,
        &camera,
        &FrameSettings {
            flags: VIEW_FLAG_FORCE_HW,
            ..base
        },
    );
    assert!(sw.main.counters.sw_count > 0 && hw.main.counters.hw_count > 0);
    let n = sw.visbuffer.len();
    let differ = (0..n)
        .filter(|&i| key(&sw, sw.visbuffer[i]) != key(&hw, hw.visbuffer[i]))
        .count();
    eprintln!("all-SW vs all-HW: {differ} of {n} pixels differ");
    assert!(
        differ as f64 <= n as f64 * 1e-4,
        "{differ} pixels differ between SW and HW"
    );
    let again = render(
        &mut r,
        &camera,
        &FrameSettings {
            flags: VIEW_FLAG_FORCE_SW,
            ..base
        },
    );
    let mixed1 = render(&mut r, &camera, &base);
    let mixed2 = render(&mut r, &camera, &base);
    let same_sw = sw
        .visbuffer
        .iter()
        .zip(&again.visbuffer)
        .all(|(a, b)| key(&sw, *a) == key(&again, *b));
    assert!(same_sw, "two all-SW renders of the same frame differ");
    let raw_differ = mixed1
        .visbuffer
        .iter()
        .zip(&mixed2.visbuffer)
        .filter(|(a, b)| a != b)
        .count();
    eprintln!(
        "determinism: {raw_differ} pixels with different raw visibility-buffer bits between two renders"
    );
    assert!(
        r.direct_visible(),
        "this scene fits the visible list: slots are assigned directly"
    );
    assert_eq!(
        raw_differ, 0,
        "direct visible slots must make the visibility buffer bit-identical"
    );
    let same = mixed1
        .visbuffer
        .iter()
        .zip(&mixed2.visbuffer)
        .all(|(a, b)| key(&mixed1, *a) == key(&mixed2, *b));
    assert!(same, "two renders of the same frame differ");
    assert_eq!(
        mixed1.frame.color, mixed2.frame.color,
        "two renders give different images"
    );
    assert_no_validation_errors(&ctx);
}

/// The automatic SW/HW split (the default, `frame::split`): the renderer settles on a threshold of
/// the ladder from its frames' GPU times, and the frames it draws while probing are the frames a
/// fixed split draws, bit for bit (the split changes only the time).
#[test]
fn the_automatic_split_settles_and_changes_no_pixel() {
    use vgeo::frame::split::SPLIT_LADDER;
    let ctx = gpu();
    // A wall of large triangles beside three spots of small ones: the thresholds the tuner tries
    // send different clusters to hardware.
    let (fov, eye) = (60f32.to_radians(), DVec3::new(0.0, 0.0, 2.0));
    let camera = Camera::look_at(eye, DVec3::ZERO, Vec3::Y, fov, 0.05);
    let wall = build(&wall_mesh(4), &BuildOptions::default()).unwrap();
    let (_, spot) = load_built(&assets().join("spot.obj"));
    let placements = [
        Placement {
            mesh: 0,
            transform: DMat4::from_translation(DVec3::new(0.5, 0.0, -0.5)),
            color: [0.8, 0.8, 0.8],
        },
        Placement {
            mesh: 1,
            transform: DMat4::from_translation(DVec3::new(-0.6, 0.0, 0.3))
                * DMat4::from_scale(DVec3::splat(0.4)),
            color: [0.9, 0.6, 0.4],
        },
    ];
    let mut r = VgeoRenderer::new(&ctx, &[wall, spot], &placements).unwrap();
    let auto = FrameSettings {
        error_px: 1.0,
        occlusion: false,
        ..Default::default()
    };
    assert!(auto.auto_split());
    let fixed = FrameSettings {
        hw_threshold_px: 64.0,
        ..auto
    };
    let reference = render(&mut r, &camera, &fixed);
    if reference.frame.gpu_ms.is_empty() {
        eprintln!(
            "no timestamps on {}: the split stays at 64",
            ctx.caps().device_name
        );
        assert_eq!(r.hw_split(), (64.0, false));
        return;
    }
    // Frames while the tuner probes: every threshold it tries draws the same visibility buffer
    // and image, with different clusters in hardware.
    let mut splits = Vec::new();
    for _ in 0..80 {
        let f = render(&mut r, &camera, &auto);
        let differ = (f.visbuffer.iter().zip(&reference.visbuffer))
            .filter(|(a, b)| a != b)
            .count();
        assert_eq!(
            differ, 0,
            "a frame of the automatic split differs from the fixed one"
        );
        assert_eq!(f.frame.color, reference.frame.color);
        let hw = f.main.counters.hw_count + f.post.counters.hw_count;
        if !splits.contains(&hw) {
            splits.push(hw);
        }
    }
    assert!(
        splits.len() >= 2,
        "the probed thresholds sent the same clusters to hardware: {splits:?}"
    );
    let light = Light::default();
    let one = std::slice::from_ref(&camera);
    let chosen = r
        .settle_split(one, W, H, &auto, ViewMode::Lit, &light, 60_000.0)
        .unwrap();
    let (held, settled) = r.hw_split();
    eprintln!(
        "{}: clusters in hardware along the way {splits:?}, settled on {chosen} px",
        ctx.caps().device_name
    );
    assert!(settled, "the tuner settles within a minute");
    assert_eq!(chosen, held);
    assert!(
        SPLIT_LADDER.contains(&chosen),
        "{chosen} is not on the ladder"
    );
    // The hwsw view shows the choice, not a threshold being tried.
    let shown = r
        .render(&camera, W, H, &auto, ViewMode::HwSw, &light)
        .unwrap();
    let chosen_frame = r
        .render(
            &camera,
            W,
            H,
            &FrameSettings {
                hw_threshold_px: chosen,
                ..auto
            },
            ViewMode::HwSw,
            &light,
        )
        .unwrap();
    assert_eq!(shown.frame.color, chosen_frame.frame.color);
    // A fixed split passes through untouched.
    let t = r
        .settle_split(one, W, H, &fixed, ViewMode::Lit, &light, 60_000.0)
        .unwrap();
    assert_eq!(t, 64.0);
    assert_no_validation_errors(&ctx);
}

/// The SW/HW split by the size of a cluster's triangles (common/cull.glsl::emit_cluster,
/// builder::size) at the default threshold: long thin slivers (grass blades seen from the front:
/// clusters a few hundred pixels across, triangles of a few pixels' area) go to the compute
/// rasterizer, a wall of big triangles to hardware. By the estimate the split used before (the
/// cluster's projected diameter over sqrt(triangles / 2)) the slivers went to hardware.
#[test]
fn split_by_triangle_size_sends_slivers_to_sw_and_big_triangles_to_hw() {
    let ctx = gpu();
    let (fov, eye) = (60f32.to_radians(), DVec3::new(0.0, 0.0, 2.0));
    let camera = Camera::look_at(eye, DVec3::ZERO, Vec3::Y, fov, 0.05);
    // Threshold 0: the level-0 clusters (the slivers' coarser levels may merge them).
    let settings = FrameSettings {
        error_px: 0.0,
        occlusion: false,
        ..Default::default()
    };
    assert!(settings.auto_split(), "the default split is measured");
    let settings = FrameSettings {
        hw_threshold_px: FrameSettings::DEFAULT_HW_THRESHOLD_PX,
        ..settings
    };
    let (p, i) = slivers(200, 1.8, 0.002, 0.01);
    let thin = build(&mesh_from("slivers", p, i), &BuildOptions::default()).unwrap();
    let wall = build(&wall_mesh(4), &BuildOptions::default()).unwrap();
    let scale = vgeo::builder::cut::proj_scale(H as f32, fov) as f64;
    for (what, built, to_hw) in [("slivers", thin, false), ("wall", wall, true)] {
        let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &one(0)).unwrap();
        let f = render(&mut r, &camera, &settings);
        let c = (&f.main.counters, &f.post.counters);
        let (sw, hw) = (c.0.sw_count + c.1.sw_count, c.0.hw_count + c.1.hw_count);
        let covered = f.frame.depth.iter().filter(|d| **d > 0.0).count();
        // The old estimate, on the CPU: projected diameter (at the nearest point) over
        // sqrt(triangles / 2).
        let old_hw = f
            .visible()
            .iter()
            .filter(|[_, ci]| {
                let c = &built.clusters[*ci as usize];
                let (lo, hi) = (
                    DVec3::from(c.bounds_min.map(f64::from)),
                    DVec3::from(c.bounds_max.map(f64::from)),
                );
                let r = (hi - lo).length() / 2.0;
                let dist = ((lo + hi) / 2.0 - eye).length() - r;
                2.0 * r * scale / dist / (c.triangle_count() as f64 / 2.0).sqrt() > 32.0
            })
            .count();
        eprintln!(
            "{what}: {sw} clusters to SW, {hw} to HW ({old_hw} by the old estimate), \
             {covered} pixels covered"
        );
        assert!(covered > 500, "{what}: {covered} pixels covered");
        if to_hw {
            assert!(hw > 0 && sw == 0, "{what}: {sw} to SW, {hw} to HW");
        } else {
            assert!(sw > 0 && hw == 0, "{what}: {sw} to SW, {hw} to HW");
            assert!(old_hw > 0, "the old estimate sent none of them to HW");
        }
    }
    assert_no_validation_errors(&ctx);
}

/// raster_hw's mesh path (where the device has mesh shaders: lavapipe does) against its vertex
/// path, through whole frames: all clusters to HW, `--hw-threshold 0` (every cluster that SW would
/// not need, with occlusion culling) and the default hybrid split give the same visibility buffer
/// bit for bit and the same image on both paths; forcing the vertex path works everywhere, and
/// asking for mesh where there is none is an error that says why.
#[test]
fn mesh_and_vertex_hw_paths_give_identical_frames() {
    use vgeo::HwPath;
    let ctx = gpu();
    let (mut r, camera) = three_spots(&ctx);
    let has_mesh = ctx.caps().mesh_shader;
    eprintln!(
        "{}: mesh shaders {has_mesh}, auto takes the {:?} path",
        ctx.caps().device_name,
        r.hw_path()
    );
    if std::env::var("VGEO_HW_PATH").is_err() {
        // Measured faster on the H100 and lavapipe alike (raster_hw.rs, HwPath::Auto).
        assert_eq!(r.hw_path(), HwPath::Vertex, "auto takes vertex pulling");
    }
    r.set_hw_path(HwPath::Vertex)
        .expect("the vertex path exists everywhere");
    assert_eq!(r.hw_path(), HwPath::Vertex);
    if !has_mesh {
        let err = r
            .set_hw_path(HwPath::Mesh)
            .expect_err("no mesh shaders here");
        assert!(err.to_string().contains("VK_EXT_mesh_shader"), "{err}");
        assert_eq!(
            r.hw_path(),
            HwPath::Vertex,
            "a refused path changes nothing"
        );
        eprintln!(
            "no mesh shaders: the mesh path is refused ({err}); checked on a device with them"
        );
        return;
    }
    let base = FrameSettings {
        error_px: 1.0,
        occlusion: false,
        ..Default::default()
    };
    let cases = [
        (
            "all HW",
            FrameSettings {
                flags: VIEW_FLAG_FORCE_HW,
                ..base
            },
        ),
        (
            "--hw-threshold 0",
            FrameSettings {
                hw_threshold_px: 0.0,
                occlusion: true,
                ..base
            },
        ),
        (
            "hybrid",
            FrameSettings {
                hw_threshold_px: 8.0,
                ..base
            },
        ),
    ];
    for (what, settings) in cases {
        let mut frames = Vec::new();
        for p in [HwPath::Vertex, HwPath::Mesh] {
            r.set_hw_path(p).unwrap();
            assert_eq!(r.hw_path(), p);
            // Two frames: the second culls with the first one's HZB (occlusion on).
            render(&mut r, &camera, &settings);
            frames.push(render(&mut r, &camera, &settings));
        }
        let (v, m) = (&frames[0], &frames[1]);
        let hw = v.main.counters.hw_count + v.post.counters.hw_count;
        assert_eq!(hw, m.main.counters.hw_count + m.post.counters.hw_count);
        assert!(hw > 0, "{what}: some clusters go to HW");
        let differ = (v.visbuffer.iter().zip(&m.visbuffer))
            .filter(|(a, b)| a != b)
            .count();
        eprintln!(
            "{what}: {hw} HW clusters, vertex vs mesh path: {differ} of {} pixels differ",
            v.visbuffer.len()
        );
        assert!(r.direct_visible());
        assert_eq!(differ, 0, "{what}: the mesh and vertex paths differ");
        assert_eq!(v.frame.color, m.frame.color, "{what}: images differ");
    }
    assert_no_validation_errors(&ctx);
}

/// What a visibility-buffer value resolves to: (depth bits, (instance, cluster), triangle). The
/// visible-list numbering follows the GPU's atomic order, so runs are compared through it.
fn key(f: &VgeoFrame, v: u64) -> (u32, [u32; 2], u32) {
    match f.resolve(v) {
        None => (0, [0, 0], 0),
        Some((entry, tri)) => ((v >> 32) as u32, entry, tri),
    }
}

/// An occlusion-culled frame (`on`) shows what the same frame without occlusion culling (`off`)
/// shows: the same image and depth.
fn assert_occlusion_kept_the_frame(on: &VgeoFrame, off: &VgeoFrame) {
    assert_eq!(
        on.frame.color, off.frame.color,
        "occlusion culling changed the image"
    );
    assert_eq!(
        on.frame.depth, off.frame.depth,
        "occlusion culling changed the depth"
    );
}

/// A view of [`occlusion_scene`] from `eye` towards `target` (50 degrees, near 0.1).
fn occlusion_view(eye: DVec3, target: DVec3) -> Camera {
    Camera::look_at(eye, target, Vec3::Y, 50f32.to_radians(), 0.1)
}

/// A wall in front of 20 spots (the occlusion tests' scene): meshes, placements, camera.
fn occlusion_scene() -> (Vec<BuiltMesh>, Vec<Placement>, Camera) {
    let (_, spot) = load_built(&assets().join("spot.obj"));
    let wall = build(&common::wall_mesh(16), &BuildOptions::default()).unwrap();
    let mut placements = vec![Placement {
        mesh: 1,
        transform: DMat4::from_scale(DVec3::splat(6.0)),
        color: [0.5; 3],
    }];
    for i in 0..5 {
        for j in 0..4 {
            placements.push(Placement {
                mesh: 0,
                transform: DMat4::from_translation(DVec3::new(
                    i as f64 * 1.5 - 3.0,
                    j as f64 * 1.2 - 2.0,
                    -4.0,
                )),
                color: [1.0; 3],
            });
        }
    }
    let meshes = vec![spot, wall];
    let camera = occlusion_view(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO);
    (meshes, placements, camera)
}

#[test]
fn a_timed_path_renders_the_same_frames_in_one_submission() {
    // Synchronization validation on: several frames in one command buffer, each rewriting its
    // inputs with vkCmdUpdateBuffer.
    let ctx = Context::new(&ContextOptions {
        validation: true,
        sync_validation: true,
        ..ContextOptions::from_env()
    })
    .expect("Vulkan device");
    let (meshes, placements, camera) = occlusion_scene();
    let cams: Vec<Camera> = (0..3)
        .map(|k| {
            let mut c = camera;
            c.position.x += 0.3 * k as f64;
            c
        })
        .collect();
    let settings = FrameSettings {
        error_px: 1.0,
        ..Default::default()
    };
    // One frame after another, each waited for...
    let mut seq = VgeoRenderer::new(&ctx, &meshes, &placements).unwrap();
    for c in &cams[..2] {
        render(&mut seq, c, &settings);
    }
    let want = render(&mut seq, &cams[2], &settings);
    // ... against the first two in one submission: the third frame sees the same history.
    let mut path = VgeoRenderer::new(&ctx, &meshes, &placements).unwrap();
    let times = path
        .render_path_timed(
            &cams[..2],
            W,
            H,
            &settings,
            ViewMode::Lit,
            &Light::default(),
        )
        .expect("timed path");
    assert_eq!(times.len(), 2);
    if ctx.caps().timestamp_period_ns.is_some() {
        for t in &times {
            let names: Vec<&str> = t.iter().map(|(n, _)| n.as_str()).collect();
            assert!(
                names.contains(&"cluster_cull") && names.contains(&"shade"),
                "{names:?}"
            );
            assert!(t.iter().all(|(_, ms)| ms.is_finite() && *ms >= 0.0));
        }
    }
    // Nothing reads a timed path's counters, so its cull keeps no statistics
    // (VIEW_FLAG_CULL_STATS), only what the rasterizers need; a read-back frame keeps both.
    let (m, _) = path
        .last_cull_counters()
        .expect("counters")
        .expect("a frame ran");
    assert!(m.sw_count + m.hw_count > 0, "the timed frame drew");
    assert_eq!(
        (
            m.instances_tested,
            m.nodes_visited,
            m.clusters_tested,
            m.triangles
        ),
        (0, 0, 0, 0),
        "statistics in a timed frame"
    );
    let got = render(&mut path, &cams[2], &settings);
    let c = &got.main.counters;
    assert!(
        c.instances_tested > 0 && c.clusters_tested > 0 && c.triangles > 0,
        "statistics in a read-back frame: {c:?}"
    );
    assert_eq!(
        got.main.counters.post_instance_count,
        want.main.counters.post_instance_count
    );
    assert!(
        want.main.counters.post_instance_count > 0,
        "history defers instances"
    );
    assert_eq!(
        got.visbuffer, want.visbuffer,
        "same frame after the timed path"
    );
    // The classic paths time paths the same way.
    let plain: Vec<Mesh> = meshes.iter().map(|b| b.level_mesh(0)).collect();
    let brute = Brute::new(&ctx, &plain).unwrap();
    let times = brute
        .render_path_timed(&placements, &cams, &Light::default(), W, H)
        .expect("brute path");
    assert_eq!(times.len(), 3);
    if ctx.caps().timestamp_period_ns.is_some() {
        for t in &times {
            let names: Vec<&str> = t.iter().map(|(n, _)| n.as_str()).collect();
            assert_eq!(names, ["brute", "shade"]);
        }
    }
    assert_no_validation_errors(&ctx);
}

#[test]
fn occlusion_culling_culls_hidden_instances_and_keeps_the_image() {
    // Synchronization validation on for this test: the two-phase frame has the most barriers.
    let ctx = Context::new(&ContextOptions {
        validation: true,
        sync_validation: true,
        ..ContextOptions::from_env()
    })
    .expect("Vulkan device");
    let (meshes, placements, camera) = occlusion_scene();
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).unwrap();
    let on = FrameSettings {
        error_px: 1.0,
        ..Default::default()
    };
    let first = render(&mut r, &camera, &on);
    let second = render(&mut r, &camera, &on);
    let off = render_without_occlusion(&mut r, &camera, &on);
    let (m, p) = (&second.main.counters, &second.post.counters);
    eprintln!(
        "occlusion frame 2: main deferred {} instances / {} nodes / {} clusters; post occluded {} / {} / {}; drawn {} vs {} without occlusion",
        m.post_instance_count,
        m.post_node_count,
        m.post_cluster_count,
        p.occluded_instances,
        p.occluded_nodes,
        p.occluded_clusters,
        second.visible().len(),
        off.visible().len()
    );
    assert_occlusion_kept_the_frame(&first, &off);
    assert_eq!(
        p.occluded_instances, 20,
        "all 20 instances behind the wall are culled in frame 2"
    );
    assert!(second.visible().len() < off.visible().len());
    assert_occlusion_kept_the_frame(&second, &off);
    // A camera cut: looking from behind, the old HZB is wrong; the image must still be right.
    let behind = occlusion_view(DVec3::new(0.0, 0.0, -12.0), DVec3::new(0.0, 0.0, -4.0));
    let cut = render(&mut r, &behind, &on);
    let cut_off = render_without_occlusion(&mut r, &behind, &on);
    assert_eq!(
        cut.frame.color, cut_off.frame.color,
        "wrong image after a camera cut"
    );
    assert!(cut.frame.covered() > 1000);
    assert_no_validation_errors(&ctx);
}

#[test]
fn a_frame_without_history_draws_the_nearest_instances_first() {
    // The occlusion scene with walls enough in front that their bounding spheres cover the
    // screen COLD_OCCLUDER_COVER times: the first frame (no previous HZB) draws the walls in its
    // main phase and defers the 20 spots behind them, which the post phase finds occluded.
    let ctx = gpu();
    let (meshes, mut placements, camera) = occlusion_scene();
    let walls = cold_walls(placements[0]);
    placements.extend_from_slice(&walls[1..]);
    let on = FrameSettings {
        error_px: 1.0,
        ..Default::default()
    };
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).unwrap();
    let first = render(&mut r, &camera, &on);
    assert_cold_frame_hid(&mut r, &camera, &on, &first, 20);
    // A camera cut to behind the spots: the walls' bounding spheres still reach nearer than the
    // spots, so the walls are drawn first again, but now the 20 deferred spots stand in front of
    // them: the post phase must draw every one.
    r.reset_history();
    let behind = occlusion_view(DVec3::new(0.0, 0.0, -12.0), DVec3::new(0.0, 0.0, -4.0));
    let cut = render(&mut r, &behind, &on);
    assert_eq!(cut.main.counters.post_instance_count, 20);
    assert_eq!(
        cut.post.counters.instances_visible, 20,
        "the deferred spots in front of the walls are drawn by the post phase"
    );
    let cut_off = render_without_occlusion(&mut r, &behind, &on);
    assert_occlusion_kept_the_frame(&cut, &cut_off);
    assert!(cut.frame.covered() > 1000);
    assert_no_validation_errors(&ctx);
}

#[test]
fn a_frame_without_history_selects_occluders_among_many_instances() {
    // More instances than occluder_select's workgroups take one each (OCCLUDER_SELECT_GROUPS x
    // the workgroup size): each workgroup sums several of them, and the one that adds its sums
    // last picks the cutoff. The walls come last in the instance list, so a cutoff picked before
    // their workgroup added their areas (by the first workgroup to finish, say) would draw
    // everything in the main phase.
    use vgeo::shared::{INSTANCE_CULL_WORKGROUP_SIZE, OCCLUDER_SELECT_GROUPS};
    let ctx = gpu();
    let (meshes, scene, camera) = occlusion_scene();
    let mut placements = Vec::new();
    let hidden = (OCCLUDER_SELECT_GROUPS * INSTANCE_CULL_WORKGROUP_SIZE) as usize + 4_000;
    let side = (hidden as f64).sqrt().ceil() as usize;
    for i in 0..hidden {
        let (x, y) = ((i % side) as f64, (i / side) as f64);
        placements.push(Placement {
            mesh: 0,
            transform: DMat4::from_translation(DVec3::new(
                (x / side as f64 - 0.5) * 4.0,
                (y / side as f64 - 0.5) * 3.0,
                -4.0,
            )) * DMat4::from_scale(DVec3::splat(0.02)),
            color: [1.0; 3],
        });
    }
    placements.extend(cold_walls(scene[0]));
    let on = FrameSettings {
        error_px: 1.0,
        ..Default::default()
    };
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).unwrap();
    let first = render(&mut r, &camera, &on);
    assert_cold_frame_hid(&mut r, &camera, &on, &first, hidden as u32);
    assert_eq!(
        first.main.counters.cold_groups_done, OCCLUDER_SELECT_GROUPS,
        "every occluder_select workgroup added its sums"
    );
    assert_no_validation_errors(&ctx);
}

/// `wall` and `COLD_OCCLUDER_COVER` more just in front of it: walls whose bounding-sphere
/// discs (each the whole screen) are enough for a frame without history to draw them first.
fn cold_walls(wall: Placement) -> Vec<Placement> {
    (0..=COLD_OCCLUDER_COVER.ceil() as u32)
        .map(|k| Placement {
            transform: DMat4::from_translation(DVec3::new(0.0, 0.0, 0.05 * k as f64))
                * wall.transform,
            ..wall
        })
        .collect()
}

/// `first`, a frame without history of `r`'s scene seen by `camera`, deferred its `hidden`
/// instances behind the walls to the post phase, which found them occluded, and shows what the
/// same frame without occlusion culling shows.
fn assert_cold_frame_hid(
    r: &mut VgeoRenderer,
    camera: &Camera,
    settings: &FrameSettings,
    first: &VgeoFrame,
    hidden: u32,
) {
    assert_eq!(
        first.main.counters.post_instance_count, hidden,
        "the main phase of a frame without history defers the instances behind the walls"
    );
    assert_eq!(
        first.post.counters.occluded_instances, hidden,
        "the post phase finds them behind the walls the main phase drew"
    );
    let off = render_without_occlusion(r, camera, settings);
    assert_occlusion_kept_the_frame(first, &off);
}

/// Where the screen rectangle of `corners` (world space) lies seen by `camera`: (left, right)
/// pixel columns of a `W` x `H` frame.
fn projected_columns(camera: &Camera, corners: &[DVec3]) -> (f32, f32) {
    let vp = camera.view_proj(W, H);
    let xs: Vec<f32> = corners
        .iter()
        .map(|&p| {
            vgeo::camera::project_to_pixel(&vp, (p - camera.position).as_vec3(), W, H)
                .expect("in front of the eye")[0]
        })
        .collect();
    let lo = xs.iter().copied().fold(f32::INFINITY, f32::min);
    let hi = xs.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    (lo, hi)
}

#[test]
fn an_instance_just_behind_an_edge_is_culled() {
    // Small instances behind a wall, their boxes ending 2-3 pixels inside the wall's right edge,
    // which lies inside a texel of the level a 2x2-texel window would test them at (8 pixels:
    // columns 88-95, the edge at 92). The HZB window (5x5 texels of 2 pixels here) stays on the
    // wall and culls them; the coarse window reached past the edge and let them through. One is
    // thin: tested by the cube around its sphere instead of its box, it would pass too.
    let ctx = gpu();
    let (_, spot) = load_built(&assets().join("spot.obj"));
    let wall = build(&wall_mesh(8), &BuildOptions::default()).unwrap();
    let camera = occlusion_view(DVec3::new(0.0, 0.0, 5.0), DVec3::ZERO);
    let edge_px = 92.0;
    // The wall ([-1, 1]^2 at z = 0, scaled by 2) with its right edge at column `edge_px`.
    let (e0, _) = projected_columns(&camera, &[DVec3::ZERO]);
    let (e1, _) = projected_columns(&camera, &[DVec3::X]);
    let wall_x = (edge_px - e0) as f64 / (e1 - e0) as f64 - 2.0;
    let mut placements = vec![Placement {
        mesh: 1,
        transform: DMat4::from_translation(DVec3::new(wall_x, 0.0, 0.0))
            * DMat4::from_scale(DVec3::splat(2.0)),
        color: [0.5; 3],
    }];
    // Moved along x so that the box of `mesh` (its BVH root's, what instance_cull tests) placed by
    // `place(x)` has its right side at column 89.6.
    let at_column = |mesh: &BuiltMesh, place: &dyn Fn(f64) -> DMat4| -> DMat4 {
        let root = &mesh.bvh[0];
        let (lo, hi) = (
            root.bounds_min.map(f64::from),
            root.bounds_max.map(f64::from),
        );
        let mut x = 0.0;
        for _ in 0..3 {
            let corners: Vec<DVec3> = (0..8)
                .map(|i| {
                    let c = DVec3::new(
                        if i & 1 != 0 { hi[0] } else { lo[0] },
                        if i & 2 != 0 { hi[1] } else { lo[1] },
                        if i & 4 != 0 { hi[2] } else { lo[2] },
                    );
                    place(x).transform_point3(c)
                })
                .collect();
            let (l, r) = projected_columns(&camera, &corners);
            let moved: Vec<DVec3> = corners.iter().map(|c| *c + DVec3::X).collect();
            let (_, r1) = projected_columns(&camera, &moved);
            assert!(r - l < 8.0, "the box spans {} pixels", r - l);
            x += (89.6 - r) as f64 / (r1 - r) as f64;
        }
        place(x)
    };
    // Three spots (scale 0.15) 4 units behind the wall.
    for y in [-0.6, 0.0, 0.6] {
        placements.push(Placement {
            mesh: 0,
            transform: at_column(&spot, &|x| {
                DMat4::from_translation(DVec3::new(x, y, -4.0))
                    * DMat4::from_scale(DVec3::splat(0.15))
            }),
            color: [1.0; 3],
        });
    }
    // A small square seen edge on (a thin mesh): its box is a few pixels tall and no wider than
    // a line, where the cube around its bounding sphere reaches 8 pixels past the edge.
    placements.push(Placement {
        mesh: 1,
        transform: at_column(&wall, &|x| {
            DMat4::from_translation(DVec3::new(x, -1.2, -4.0))
                * DMat4::from_rotation_y(std::f64::consts::FRAC_PI_2)
                * DMat4::from_scale(DVec3::splat(0.15))
        }),
        color: [1.0; 3],
    });
    let meshes = vec![spot, wall];
    let mut r = VgeoRenderer::new(&ctx, &meshes, &placements).unwrap();
    let on = FrameSettings {
        error_px: 1.0,
        ..Default::default()
    };
    render(&mut r, &camera, &on);
    let second = render(&mut r, &camera, &on);
    let off = render_without_occlusion(&mut r, &camera, &on);
    // The wall covers columns up to 91 where the instances are, and nothing past the edge.
    let covered = |x: u32, y: u32| off.frame.depth[(y * W + x) as usize] > 0.0;
    assert!(
        covered(91, H / 2) && !covered(92, H / 2),
        "the wall's edge is not at column 92"
    );
    assert_eq!(
        second.post.counters.occluded_instances, 4,
        "the instances behind the wall's edge are culled by their instance test"
    );
    assert_occlusion_kept_the_frame(&second, &off);
    assert_no_validation_errors(&ctx);
}

/// The camera cut of the post-phase tests: `meshes` at `placements` drawn from `front` (error
/// 0.25 px, occlusion culling on), then from behind [`occlusion_scene`]'s wall ([`cut_view`]),
/// whose frame culls first with the front view's HZB. The renderer and that frame.
fn cut_behind_the_wall(
    ctx: &Context,
    meshes: &[BuiltMesh],
    placements: &[Placement],
    front: &Camera,
) -> (VgeoRenderer, VgeoFrame) {
    let mut r = VgeoRenderer::new(ctx, meshes, placements).unwrap();
    render(&mut r, front, &cut_settings());
    let cut = render(&mut r, &cut_view(), &cut_settings());
    (r, cut)
}

/// The settings of [`cut_behind_the_wall`].
fn cut_settings() -> FrameSettings {
    FrameSettings {
        error_px: 0.25,
        ..Default::default()
    }
}

/// The view behind the wall of [`cut_behind_the_wall`].
fn cut_view() -> Camera {
    occlusion_view(DVec3::new(-1.0, 1.0, -7.0), DVec3::new(0.0, 0.0, 0.0))
}

/// `cut` (from [`cut_behind_the_wall`]) equals the same view rendered without occlusion culling.
fn assert_the_cut_is_the_frame_without_occlusion(r: &mut VgeoRenderer, cut: &VgeoFrame) {
    let off = render_without_occlusion(r, &cut_view(), &cut_settings());
    assert_occlusion_kept_the_frame(cut, &off);
}

/// The post phase takes what the main phase deferred as one index range: instances, then BVH-node
/// items, then clusters (`instance_cull`). A camera cut behind the wall of `occlusion_scene`, with
/// a big bunny standing through the wall (visible from the front, so its hidden parts are deferred
/// as clusters and a node rather than as an instance; a big cow did until session 33's root chain
/// changed its BVH), defers all three kinds at once in the main phase; the post phase must draw every one of them: the frame equals the one without
/// occlusion. Reading the clusters at the wrong offset in that range fails here (tests/cull.rs,
/// tests/views.rs and this file's other tests pass it). (The node it defers holds no cluster of
/// the cut, so a node item read at the wrong offset goes unseen here:
/// `deferred_bvh_nodes_draw_their_clusters_in_the_post_phase` defers nodes that draw.)
#[test]
fn the_post_phase_draws_deferred_instances_and_clusters_together() {
    let ctx = gpu();
    let (mut meshes, mut placements, front) = occlusion_scene();
    // A big bunny standing through the wall.
    meshes.push(load_built(&assets().join("bunny.ply")).1);
    placements.push(Placement {
        mesh: 2,
        transform: DMat4::from_translation(DVec3::new(0.3, -1.6, -0.8))
            * DMat4::from_scale(DVec3::splat(40.0)),
        color: [0.8, 0.6, 0.4],
    });
    let (mut r, cut) = cut_behind_the_wall(&ctx, &meshes, &placements, &front);
    let m = &cut.main.counters;
    eprintln!(
        "camera cut: main visited {} nodes ({} local walks, {} instances visible); deferred {} instances / {} nodes / {} clusters; post drew {} clusters",
        m.nodes_visited,
        m.local_walks,
        m.instances_visible,
        m.post_instance_count,
        m.post_node_count,
        m.post_cluster_count,
        cut.post.counters.visible_count
    );
    // Deferred nodes too: with none, the clusters' offset in the range would be right by chance.
    assert!(
        m.post_instance_count > 0 && m.post_node_count > 0 && m.post_cluster_count > 0,
        "the main phase should defer instances, nodes and clusters at once"
    );
    assert!(cut.post.counters.visible_count > 0, "the post phase draws");
    // The post phase's instance_cull runs a thread per deferred item (the main phase's cull
    // writes the indirect arguments), more threads here than a thread per instance would give:
    // the frame below is drawn with them.
    let (queue, visible) = r.capacities();
    assert_eq!(
        m.post_dispatch,
        post_dispatch_args(m, queue, visible),
        "the post phase's instance_cull arguments"
    );
    let per_instance = (placements.len() as u32).div_ceil(INSTANCE_CULL_WORKGROUP_SIZE);
    assert!(
        m.post_dispatch[0] * m.post_dispatch[1] > per_instance,
        "{:?}: more workgroups than {per_instance} (a thread per instance)",
        m.post_dispatch
    );
    assert_the_cut_is_the_frame_without_occlusion(&mut r, &cut);
    assert!(cut.frame.covered() > 1000);
    assert_no_validation_errors(&ctx);
}

/// The R64 image path and the u64 buffer path must give bit-identical visibility buffers. Runs where
/// the device has 64-bit image atomics (the H100; lavapipe has none, so there it checks only that
/// asking for the image path is a clear error).
#[test]
fn image_and_buffer_visibility_paths_agree() {
    use vgeo::passes::VisPath;
    let ctx = gpu();
    let (mesh, built) = load_built(&assets().join("spot.obj"));
    let camera = filling_camera(&mesh, 1.4);
    let placements = one(0);
    if !ctx.caps().image_int64_atomics {
        let err = VgeoRenderer::with_path(
            &ctx,
            std::slice::from_ref(&built),
            &placements,
            VisPath::Image,
        )
        .err();
        assert!(err.is_some_and(|e| e.to_string().contains("shader_image_atomic_int64")));
        eprintln!(
            "{}: no 64-bit image atomics; the image path is checked on a GPU that has them",
            ctx.caps().device_name
        );
        return;
    }
    let settings = FrameSettings {
        error_px: 1.0,
        occlusion: false,
        ..Default::default()
    };
    let mut frames = Vec::new();
    for path in [VisPath::Buffer, VisPath::Image] {
        let mut r =
            VgeoRenderer::with_path(&ctx, std::slice::from_ref(&built), &placements, path).unwrap();
        for flags in [VIEW_FLAG_FORCE_SW, VIEW_FLAG_FORCE_HW, 0] {
            frames.push((
                path,
                flags,
                render(&mut r, &camera, &FrameSettings { flags, ..settings }),
            ));
        }
    }
    for k in 0..3 {
        let (a, b) = (&frames[k].2, &frames[k + 3].2);
        let differ = a
            .visbuffer
            .iter()
            .zip(&b.visbuffer)
            .filter(|(x, y)| key(a, **x) != key(b, **y))
            .count();
        eprintln!(
            "flags {}: buffer vs image path: {differ} pixels differ (depth, instance, cluster, triangle)",
            frames[k].1
        );
        assert_eq!(
            differ, 0,
            "buffer and image paths differ (flags {})",
            frames[k].1
        );
        assert_eq!(
            a.frame.color, b.frame.color,
            "buffer and image paths give different images"
        );
    }
    assert_no_validation_errors(&ctx);
}

#[test]
fn capacity_overflows_are_reported_not_silent() {
    let ctx = gpu();
    let (mesh, built) = load_built(&assets().join("spot.obj"));
    let camera = filling_camera(&mesh, 1.4);
    let placements: Vec<Placement> = (0..4)
        .map(|i| Placement {
            mesh: 0,
            transform: DMat4::from_translation(DVec3::new(i as f64, 0.0, 0.0)),
            color: [1.0; 3],
        })
        .collect();
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &placements).unwrap();
    let settings = FrameSettings {
        error_px: 0.0,
        occlusion: false,
        ..Default::default()
    };
    r.set_capacities(1 << 16, 10);
    let f = r
        .render(
            &camera,
            W,
            H,
            &settings,
            ViewMode::Lambert,
            &Light::default(),
        )
        .expect("renders");
    let err = f
        .check()
        .expect_err("10 visible slots cannot hold threshold 0");
    assert!(err.contains("visible-cluster list overflowed"), "{err}");
    assert!(f.main.visible.len() <= 10);
    r.set_capacities(2, 1 << 16);
    let f = r
        .render(
            &camera,
            W,
            H,
            &settings,
            ViewMode::Lambert,
            &Light::default(),
        )
        .expect("renders");
    let err = f
        .check()
        .expect_err("a 2-item queue cannot hold 4 instances' BVHs");
    assert!(err.contains("queue overflowed"), "{err}");
    assert_no_validation_errors(&ctx);
}

#[test]
fn gpu_geometry_is_the_pages_bytes_and_at_most_19_bytes_per_triangle_without_uvs() {
    let ctx = gpu();
    for (file, uvs) in [
        ("scanned/bunny.ply", false),
        ("scanned/turbineblade.ply", false),
    ] {
        let (mesh, built) = load_built(&shared_assets().join(file));
        assert_eq!(mesh.has_uvs, uvs);
        let r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &one(0)).unwrap();
        let per_tri = r.scene.geometry_bytes() as f64 / mesh.triangle_count() as f64;
        eprintln!("{file}: {per_tri:.2} GPU bytes per input triangle");
        // 15.8 before pages, 21.8 (bunny) with plain-stream pages; encoded pages at the default
        // precision (16 position bits here, 12 normal bits): bunny 18.1, turbineblade 16.7.
        assert!(per_tri <= 19.0, "{file}: {per_tri:.2} B per triangle");
        // The pool holds the pages' encoded bytes exactly.
        let page_bytes: u64 = built.pages.iter().map(|p| p.bytes as u64).sum();
        assert_eq!(r.scene.pool.size(), page_bytes);
    }
    // A mesh with UVs: its pages decode to its vertices, UVs included.
    let (mesh, built) = load_built(&assets().join("spot.obj"));
    assert!(mesh.has_uvs);
    let by_page = vgeo::builder::page::clusters_by_page(&built);
    let clusters: Vec<_> = by_page[0]
        .iter()
        .map(|&c| &built.clusters[c as usize])
        .collect();
    let bytes = vgeo::builder::page::encode_page(&built, &by_page[0]);
    assert_eq!(bytes.len(), built.pages[0].bytes as usize);
    let st = vgeo::builder::page::decode_page(
        &bytes,
        &clusters,
        &built.quantization,
        true,
        built.has_material_stream(),
    )
    .expect("decodes");
    let n = built.pages[0].vertex_count as usize;
    assert_eq!(st.vertices, built.vertices[..n]);
    assert!(
        st.vertices.iter().any(|v| v.uv != 0),
        "no UVs in spot's first page"
    );
    assert_no_validation_errors(&ctx);
}

#[test]
fn the_hzb_equals_the_cpu_pyramid_of_the_visibility_buffer_at_any_size() {
    let ctx = gpu();
    let (mesh, built) = load_built(&assets().join("spot.obj"));
    let camera = filling_camera(&mesh, 1.2);
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &one(0)).unwrap();
    // One pixel; levels only in the head dispatch; a tail of several levels; a tail level larger
    // than its one workgroup (2200x1950: level 6 is 18x16 texels).
    for (w, h) in [
        (1, 1),
        (3, 2),
        (63, 65),
        (130, 67),
        (517, 301),
        (2200, 1950),
    ] {
        let f = r
            .render(
                &camera,
                w,
                h,
                &FrameSettings::default(),
                ViewMode::Lambert,
                &Light::default(),
            )
            .unwrap();
        f.check().unwrap();
        let depth: Vec<f32> = f
            .visbuffer
            .iter()
            .map(|v| f32::from_bits((v >> 32) as u32))
            .collect();
        assert!(
            w < 8 || depth.iter().filter(|d| **d > 0.0).count() > (w * h / 8) as usize,
            "{w}x{h}: the mesh covers the frame"
        );
        let gpu_hzb = r.hzb().unwrap().expect("an HZB after a frame");
        common::assert_hzb_matches_reference(&gpu_hzb, &depth, w, h);
    }
    assert_no_validation_errors(&ctx);
}

/// Renders `built`, one instance per case (name, camera, transform, whether its clusters drop
/// faces turned away), every cluster in hardware on both HW paths where there are mesh shaders,
/// and checks each frame against the same mesh's with `closed_solid` cleared: the same
/// visibility buffer and image pixel for pixel (the meshes here have no fold or depth tie where a
/// face turned away would win: on the H100 indoor has one such pixel), and with dropping, fewer
/// rasterizer writes and none more on any pixel; without, exactly the same writes.
fn closed_and_plain_frames_agree(
    ctx: &Context,
    built: &BuiltMesh,
    cases: &[(&str, Camera, DMat4, bool)],
) {
    use vgeo::HwPath;
    assert_eq!(
        built.stats.closed_solid,
        Some(true),
        "{} is a closed solid",
        built.name
    );
    let mut open = built.clone();
    open.stats.closed_solid = None;
    let settings = FrameSettings {
        error_px: 1.0,
        occlusion: false,
        flags: VIEW_FLAG_FORCE_HW | FrameSettings::COUNT_OVERDRAW,
        ..Default::default()
    };
    let mut paths = vec![HwPath::Vertex];
    if ctx.caps().mesh_shader {
        paths.push(HwPath::Mesh);
    }
    for &(what, camera, transform, culls) in cases {
        let placements = vec![Placement {
            mesh: 0,
            transform,
            color: [0.9, 0.8, 0.7],
        }];
        let mut closed = VgeoRenderer::new(ctx, std::slice::from_ref(built), &placements).unwrap();
        let mut plain = VgeoRenderer::new(ctx, std::slice::from_ref(&open), &placements).unwrap();
        for &p in &paths {
            closed.set_hw_path(p).unwrap();
            plain.set_hw_path(p).unwrap();
            let a = render(&mut closed, &camera, &settings);
            let b = render(&mut plain, &camera, &settings);
            let hw = a.main.hw.len() + a.post.hw.len();
            let dropping = a.main.hw_cull_back + a.post.hw_cull_back;
            let covered = b.visbuffer.iter().filter(|&&v| v != 0).count();
            let writes = |f: &VgeoFrame| -> u64 {
                let o = f.overdraw.as_ref().expect("overdraw counted");
                o.iter().map(|&n| n as u64).sum()
            };
            let (wa, wb) = (writes(&a), writes(&b));
            eprintln!(
                "{what} ({p:?}): {hw} HW clusters, {dropping} without faces turned away, \
                 {covered} pixels covered, {wa} fragments against {wb}"
            );
            assert!(hw > 0, "{what}: clusters go to HW");
            assert!(
                covered > b.visbuffer.len() / 20,
                "{what}: the mesh is in view"
            );
            assert_eq!(b.main.hw_cull_back + b.post.hw_cull_back, 0);
            assert_eq!(
                dropping,
                if culls { hw } else { 0 },
                "{what}: which clusters drop faces"
            );
            assert!(
                a.visbuffer == b.visbuffer,
                "{what} ({p:?}): visibility buffers differ"
            );
            assert_eq!(
                a.frame.color, b.frame.color,
                "{what} ({p:?}): images differ"
            );
            let (oa, ob) = (a.overdraw.as_ref().unwrap(), b.overdraw.as_ref().unwrap());
            assert!(
                oa.iter().zip(ob).all(|(x, y)| x <= y),
                "{what}: a pixel got more writes"
            );
            if culls {
                assert!(
                    wa * 10 < wb * 8,
                    "{what}: {wa} fragments, not fewer than {wb}"
                );
            } else {
                assert_eq!(wa, wb, "{what}: the same fragments");
            }
        }
    }
}

/// The hardware path drops the faces a closed solid turns away only where none can show: from
/// outside its box, with the near plane clear of it (`common/cull.glsl` `hw_entry_flags`). Spot
/// seen from outside (mirrored too) drops them; inside its box, or with the near plane cutting
/// into it (its inside showing through the cut), it does not.
#[test]
fn hw_drops_a_closed_solids_faces_turned_away_only_where_none_shows() {
    let ctx = gpu();
    let (mesh, built) = load_built(&assets().join("spot.obj"));
    let (lo, hi) = mesh.bounds().expect("bounds");
    let (lo, hi) = (
        DVec3::from(lo.map(f64::from)),
        DVec3::from(hi.map(f64::from)),
    );
    let (c, r) = ((lo + hi) * 0.5, (hi - lo).length() * 0.5);
    let outside = filling_camera(&mesh, 1.5);
    let inside = Camera::look_at(
        c,
        c + DVec3::X,
        Vec3::Y,
        60f32.to_radians(),
        (r * 0.01) as f32,
    );
    // A tenth of the radius in front of the box, the near plane half the radius away.
    let sliced = Camera::look_at(
        DVec3::new(c.x, c.y, hi.z + 0.1 * r),
        c,
        Vec3::Y,
        45f32.to_radians(),
        (r * 0.5) as f32,
    );
    let mirror = DMat4::from_translation(c)
        * DMat4::from_scale(DVec3::new(-1.0, 1.0, 1.0))
        * DMat4::from_translation(-c);
    let cases = [
        ("outside", outside, DMat4::IDENTITY, true),
        ("mirrored", outside, mirror, true),
        ("inside", inside, DMat4::IDENTITY, false),
        ("near plane cutting in", sliced, DMat4::IDENTITY, false),
    ];
    closed_and_plain_frames_agree(&ctx, &built, &cases);
    assert_no_validation_errors(&ctx);
}

/// A ground box seen from just above, its faces reaching behind the camera: the triangles that
/// cannot be snapped (a corner behind the near plane) decide by their clip-space determinant
/// (`common/raster.glsl` `hw_faces_away`). Near the origin, rotated and stretched; mirrored by a
/// negative scale; and ten million units out.
#[test]
fn hw_drops_a_ground_boxs_hidden_faces_across_the_near_plane() {
    let ctx = gpu();
    let mut p = Vec::new();
    for i in 0..8 {
        p.push([i & 1, (i >> 1) & 1, (i >> 2) & 1].map(|b| b as f32 - 0.5));
    }
    // Each face counter-clockwise seen from outside.
    let idx = vec![
        0, 2, 3, 0, 3, 1, // -z
        4, 5, 7, 4, 7, 6, // +z
        0, 1, 5, 0, 5, 4, // -y
        2, 6, 7, 2, 7, 3, // +y
        0, 4, 6, 0, 6, 2, // -x
        1, 3, 7, 1, 7, 5, // +x
    ];
    let built = build(&mesh_from("ground box", p, idx), &BuildOptions::default()).unwrap();
    let ground = |at: DVec3, sx: f64| {
        DMat4::from_translation(at + DVec3::new(0.0, -0.5, 0.0))
            * DMat4::from_rotation_y(30f64.to_radians())
            * DMat4::from_scale(DVec3::new(100.0 * sx, 1.0, 100.0))
    };
    let view = |at: DVec3| {
        Camera::look_at(
            at + DVec3::new(0.0, 1.5, 0.0),
            at + DVec3::new(0.0, 0.5, -10.0),
            Vec3::Y,
            70f32.to_radians(),
            0.05,
        )
    };
    let far = DVec3::new(1.0e7, 0.0, -1.0e7);
    let cases = [
        ("ground", view(DVec3::ZERO), ground(DVec3::ZERO, 1.0), true),
        (
            "mirrored ground",
            view(DVec3::ZERO),
            ground(DVec3::ZERO, -1.0),
            true,
        ),
        ("far ground", view(far), ground(far, 1.0), true),
    ];
    closed_and_plain_frames_agree(&ctx, &built, &cases);
    assert_no_validation_errors(&ctx);
}

/// The post phase's BVH-node items, read from the middle of its index range: a camera cut behind
/// the wall of [`occlusion_scene`] with a large bunny mostly behind it, whose hidden part the main
/// phase defers node by node (against the previous view's HZB: 10 nodes here), and whose nodes
/// then hold clusters of the cut. The frame equals the one without occlusion culling.
#[test]
fn deferred_bvh_nodes_draw_their_clusters_in_the_post_phase() {
    let ctx = gpu();
    let (mut meshes, mut placements, front) = occlusion_scene();
    let (_, bunny) = load_built(&assets().join("bunny.ply"));
    meshes.push(bunny);
    placements.push(Placement {
        mesh: 2,
        transform: DMat4::from_translation(DVec3::new(0.3, -1.6, -2.0))
            * DMat4::from_scale(DVec3::splat(40.0)),
        color: [0.8, 0.6, 0.4],
    });
    let (mut r, cut) = cut_behind_the_wall(&ctx, &meshes, &placements, &front);
    let (m, p) = (&cut.main.counters, &cut.post.counters);
    eprintln!(
        "camera cut: deferred {} instances / {} nodes / {} clusters; post visited {} nodes, drew {} clusters",
        m.post_instance_count,
        m.post_node_count,
        m.post_cluster_count,
        p.nodes_visited,
        p.visible_count
    );
    assert!(m.post_node_count > 1, "the main phase defers nodes");
    assert!(
        p.nodes_visited > 0 && p.visible_count > 0,
        "the post phase draws"
    );
    assert_the_cut_is_the_frame_without_occlusion(&mut r, &cut);
    assert_no_validation_errors(&ctx);
}
