//! The views of issue 5 on lavapipe with validation on: `groups`, `overdraw` (the rasterizers'
//! per-pixel counter), `fallback` (the DAG roots), and the LOD strip (library and CLI).

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::process::Command;

use common::{assert_no_validation_errors, assets, gpu};
use glam::{DMat4, DVec3, Vec3};
use vgeo::builder::{BuildOptions, BuiltMesh, build};
use vgeo::camera::Camera;
use vgeo::frame::{VgeoFrame, VgeoRenderer};
use vgeo::lod_strip::{LodStripOptions, panel_view, render_lod_strip};
use vgeo::mesh::Mesh;
use vgeo::passes::debug_view::ViewMode;
use vgeo::passes::view::FrameSettings;
use vgeo::render::{BACKGROUND, Light, Placement};
use vgeo::shared::{VIEW_FLAG_FORCE_HW, VIEW_FLAG_FORCE_SW};

const W: u32 = 160;
const H: u32 = 120;

fn spot() -> (Mesh, BuiltMesh) {
    common::load_built(&assets().join("spot.obj"))
}

fn at(mesh: u32, offset: DVec3) -> Placement {
    Placement {
        mesh,
        transform: DMat4::from_translation(offset),
        color: [0.9, 0.8, 0.7],
    }
}

fn render(
    r: &mut VgeoRenderer,
    camera: &Camera,
    settings: &FrameSettings,
    mode: ViewMode,
) -> VgeoFrame {
    let f = r
        .render(camera, W, H, settings, mode, &Light::default())
        .expect("frame renders");
    f.check().expect("no overflow, no watchdog");
    f
}

/// The background as the debug view writes it (sRGB-encoded, rounded).
fn background() -> [u8; 4] {
    let c = BACKGROUND.map(|v| (v.clamp(0.0, 1.0).powf(1.0 / 2.2) * 255.0).round() as u8);
    [c[0], c[1], c[2], 255]
}

fn pixel(color: &[u8], i: usize) -> [u8; 4] {
    [
        color[4 * i],
        color[4 * i + 1],
        color[4 * i + 2],
        color[4 * i + 3],
    ]
}

/// Pixels whose colour is not (within one step of rounding) the background.
fn non_background(color: &[u8]) -> usize {
    let bg = background();
    (0..color.len() / 4)
        .filter(|&i| {
            let p = pixel(color, i);
            (0..3).any(|k| p[k].abs_diff(bg[k]) > 1)
        })
        .count()
}

#[test]
fn new_views_render_without_validation_errors() {
    let ctx = gpu();
    let (mesh, built) = spot();
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &[at(0, DVec3::ZERO)])
        .expect("renderer");
    let camera = common::filling_camera(&mesh, 1.6);
    for mode in [
        ViewMode::Groups,
        ViewMode::Overdraw,
        ViewMode::Fallback,
        ViewMode::Residency,
    ] {
        let f = render(&mut r, &camera, &FrameSettings::default(), mode);
        let shown = non_background(&f.frame.color);
        let covered = f.visbuffer.iter().filter(|v| **v != 0).count();
        eprintln!(
            "{}: {shown} non-background pixels, {covered} covered",
            mode.name()
        );
        assert!(
            covered > 1000,
            "{}: spot should cover the view",
            mode.name()
        );
        // Every covered pixel is coloured (fallback's cluster borders are darkened, not erased).
        assert!(
            shown as f64 >= 0.95 * covered as f64,
            "{}: only {shown} of {covered} covered pixels differ from the background",
            mode.name()
        );
        assert_eq!(
            f.overdraw.is_some(),
            mode == ViewMode::Overdraw,
            "{}: counters read back only when counted",
            mode.name()
        );
        assert_eq!(ViewMode::parse(mode.name()), Some(mode));
        assert!(ViewMode::ALL.contains(&mode));
    }
    assert_no_validation_errors(&ctx);
}

#[test]
fn groups_view_colours_by_instance_and_dag_group() {
    let ctx = gpu();
    let (mesh, built) = spot();
    // Two instances side by side at full detail: level 0 of spot spans several groups.
    let placements = [
        at(0, DVec3::new(-0.6, 0.0, 0.0)),
        at(0, DVec3::new(0.6, 0.0, 0.0)),
    ];
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &placements).unwrap();
    let camera = common::filling_camera(&mesh, 2.4);
    let settings = FrameSettings {
        error_px: 0.0,
        occlusion: false,
        ..Default::default()
    };
    let f = render(&mut r, &camera, &settings, ViewMode::Groups);
    // (instance, group) of each covered pixel, from the visibility buffer and the cluster table.
    let key: Vec<Option<(u32, u32)>> = f
        .visbuffer
        .iter()
        .map(|&v| {
            f.resolve(v)
                .map(|([inst, c], _)| (inst, built.clusters[c as usize].group))
        })
        .collect();
    let mut colours: BTreeMap<(u32, u32), BTreeSet<[u8; 4]>> = BTreeMap::new();
    let mut clusters_of: BTreeMap<(u32, u32), BTreeSet<u32>> = BTreeMap::new();
    for (i, k) in key.iter().enumerate() {
        if let Some(k) = k {
            colours
                .entry(*k)
                .or_default()
                .insert(pixel(&f.frame.color, i));
            let (entry, _) = f.resolve(f.visbuffer[i]).unwrap();
            clusters_of.entry(*k).or_default().insert(entry[1]);
        }
    }
    eprintln!(
        "groups view: {} (instance, group) pairs on screen, clusters per pair {:?}",
        colours.len(),
        clusters_of.values().map(|s| s.len()).collect::<Vec<_>>()
    );
    assert!(
        colours.len() >= 4,
        "two instances of a multi-group cut: {} groups on screen",
        colours.len()
    );
    assert!(
        clusters_of.values().any(|s| s.len() >= 2),
        "some group shows several clusters"
    );
    for (k, c) in &colours {
        assert_eq!(
            c.len(),
            1,
            "(instance, group) {k:?}: its clusters' pixels have {} colours",
            c.len()
        );
    }
    let distinct: BTreeSet<[u8; 4]> = colours.values().flatten().copied().collect();
    assert_eq!(
        distinct.len(),
        colours.len(),
        "every (instance, group) on screen has its own colour"
    );
    // Neighbouring groups are told apart: adjacent pixels of different groups differ clearly.
    let mut boundaries = BTreeMap::new();
    for y in 0..H as usize {
        for x in 0..W as usize {
            let i = y * W as usize + x;
            for j in [i + 1, i + W as usize] {
                if (j == i + 1 && x + 1 == W as usize) || j >= key.len() {
                    continue;
                }
                if let (Some(a), Some(b)) = (key[i], key[j])
                    && a != b
                {
                    let (pa, pb) = (pixel(&f.frame.color, i), pixel(&f.frame.color, j));
                    let d: u32 = (0..3).map(|k| pa[k].abs_diff(pb[k]) as u32).sum();
                    boundaries.insert((a.min(b), a.max(b)), d);
                }
            }
        }
    }
    eprintln!("neighbouring group pairs and colour distances: {boundaries:?}");
    assert!(!boundaries.is_empty());
    let close = boundaries.values().filter(|d| **d < 60).count();
    assert_eq!(
        close, 0,
        "{close} neighbouring group pairs have nearly the same colour"
    );
    assert_no_validation_errors(&ctx);
}

#[test]
fn overdraw_counts_every_rasterizer_write() {
    let ctx = gpu();
    let wall = build(&common::wall_mesh(6), &BuildOptions::default()).expect("wall builds");
    // Front-on, the wall covers the middle of the view and nothing overlaps: exactly 1 per pixel.
    let camera = Camera::look_at(
        DVec3::new(0.0, 0.0, 3.5),
        DVec3::ZERO,
        Vec3::Y,
        45f32.to_radians(),
        0.1,
    );
    let settings = FrameSettings {
        error_px: 0.0,
        occlusion: false,
        ..Default::default()
    };
    let mut one = VgeoRenderer::new(&ctx, std::slice::from_ref(&wall), &[at(0, DVec3::ZERO)])
        .expect("renderer");
    // The counter path off: nothing is allocated, nothing read back.
    let lit = render(&mut one, &camera, &settings, ViewMode::Lambert);
    assert!(lit.overdraw.is_none());
    assert!(
        one.overdraw_counts().unwrap().is_none(),
        "no counter before a frame counts"
    );
    let mut first_counts = None;
    for flags in [0, VIEW_FLAG_FORCE_SW, VIEW_FLAG_FORCE_HW] {
        let f = render(
            &mut one,
            &camera,
            &FrameSettings { flags, ..settings },
            ViewMode::Overdraw,
        );
        let counts = f.overdraw.clone().expect("overdraw view reads counts back");
        assert_eq!(counts.len(), (W * H) as usize);
        let covered = f.visbuffer.iter().filter(|v| **v != 0).count();
        assert!(covered > 3000, "the wall covers {covered} pixels");
        for (i, (&n, &v)) in counts.iter().zip(&f.visbuffer).enumerate() {
            let expect = (v != 0) as u32;
            assert_eq!(
                n,
                expect,
                "flags {flags}: pixel {i} written {n} times (covered: {})",
                v != 0
            );
        }
        // The image: background exactly where the count is 0, one colour for count 1.
        let bg = pixel(&lit.frame.color, 0);
        let ones: BTreeSet<[u8; 4]> = (0..counts.len())
            .filter(|&i| counts[i] == 1)
            .map(|i| pixel(&f.frame.color, i))
            .collect();
        assert_eq!(ones.len(), 1, "count 1 has one colour");
        assert!(!ones.contains(&bg));
        assert!((0..counts.len()).all(|i| (counts[i] == 0) == (pixel(&f.frame.color, i) == bg)));
        first_counts.get_or_insert(counts);
    }
    // Counting off after a counting frame: the counters are neither cleared nor written, even for
    // a view that covers other pixels.
    let moved = Camera::look_at(
        DVec3::new(0.7, 0.2, 2.5),
        DVec3::ZERO,
        Vec3::Y,
        45f32.to_radians(),
        0.1,
    );
    let before = one.overdraw_counts().unwrap().expect("allocated");
    let f = render(&mut one, &moved, &settings, ViewMode::Clusters);
    assert!(f.overdraw.is_none());
    assert_eq!(
        one.overdraw_counts().unwrap().expect("still allocated"),
        before,
        "a frame without the overdraw flag touched the counters"
    );
    let recount = render(&mut one, &moved, &settings, ViewMode::Overdraw)
        .overdraw
        .unwrap();
    assert_ne!(recount, before, "the moved view covers other pixels");

    // Two instances at the same place: every covered pixel is written twice.
    let mut two = VgeoRenderer::new(
        &ctx,
        std::slice::from_ref(&wall),
        &[at(0, DVec3::ZERO), at(0, DVec3::ZERO)],
    )
    .expect("renderer");
    for flags in [VIEW_FLAG_FORCE_SW, VIEW_FLAG_FORCE_HW] {
        let f = render(
            &mut two,
            &camera,
            &FrameSettings { flags, ..settings },
            ViewMode::Overdraw,
        );
        let counts = f.overdraw.unwrap();
        let covered: Vec<usize> = (0..counts.len()).filter(|&i| f.visbuffer[i] != 0).collect();
        assert_eq!(
            covered,
            (0..counts.len())
                .filter(|&i| counts[i] > 0)
                .collect::<Vec<_>>()
        );
        assert!(
            covered.iter().all(|&i| counts[i] == 2),
            "flags {flags}: two coincident instances must give 2 everywhere they cover"
        );
        let two_colour: BTreeSet<[u8; 4]> =
            covered.iter().map(|&i| pixel(&f.frame.color, i)).collect();
        assert_eq!(two_colour.len(), 1);
    }
    assert_no_validation_errors(&ctx);
}

#[test]
fn fallback_view_draws_exactly_the_fallback_level() {
    let ctx = gpu();
    let (mesh, built) = spot();
    // The fallback level: the complete DAG level nearest the builder's fallback target.
    let level = built.fallback_level(vgeo::builder::BuildOptions::default().fallback_triangles);
    assert!(level > 0, "spot's fallback is coarser than the input");
    let roots: Vec<u32> = built.level_clusters(level);
    let root_tris: u64 = roots
        .iter()
        .map(|&c| built.clusters[c as usize].triangle_count() as u64)
        .sum();
    assert!(!roots.is_empty() && root_tris > 0);
    let placements = [
        at(0, DVec3::new(-0.8, 0.0, 0.0)),
        at(0, DVec3::new(0.0, 0.0, -0.5)),
        at(0, DVec3::new(0.8, 0.0, 0.0)),
    ];
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &placements).unwrap();
    let camera = common::filling_camera(&mesh, 3.0);
    // Occlusion off: a root partly hidden behind another instance still counts as drawn.
    let settings = FrameSettings {
        error_px: 0.5,
        occlusion: false,
        ..Default::default()
    };
    let full = FrameSettings {
        error_px: 0.0,
        ..settings
    };
    let detailed = render(&mut r, &camera, &full, ViewMode::Lambert);
    let f = render(&mut r, &camera, &settings, ViewMode::Fallback);
    let visible_instances = f.main.counters.instances_visible + f.post.counters.instances_visible;
    eprintln!(
        "fallback (level {level}): {} clusters ({root_tris} triangles) per instance, {} visible instances, {} triangles drawn (detailed view: {})",
        roots.len(),
        visible_instances,
        f.frame.triangles,
        detailed.frame.triangles
    );
    assert_eq!(visible_instances, 3, "all three instances in view");
    assert_eq!(
        f.frame.triangles,
        visible_instances as u64 * root_tris,
        "fallback draws the fallback level's triangles for every visible instance"
    );
    let mut drawn = f.visible();
    drawn.sort_unstable();
    let expected: Vec<[u32; 2]> = (0..3u32)
        .flat_map(|i| roots.iter().map(move |&c| [i, c]))
        .collect();
    assert_eq!(
        drawn, expected,
        "the drawn clusters are the fallback level's"
    );
    assert!(
        detailed.frame.triangles > 2 * f.frame.triangles,
        "the fallback is coarser than the normal cut ({} vs {})",
        f.frame.triangles,
        detailed.frame.triangles
    );
    assert!(non_background(&f.frame.color) > 1000);
    assert_no_validation_errors(&ctx);
}

#[test]
fn lod_strip_cut_coarsens_with_distance_and_matches_the_unmagnified_view() {
    let ctx = gpu();
    let (mesh, built) = spot();
    let mut r = VgeoRenderer::new(&ctx, std::slice::from_ref(&built), &[at(0, DVec3::ZERO)])
        .expect("renderer");
    let base = common::filling_camera(&mesh, 1.5);
    let (lo, hi) = mesh.bounds().unwrap();
    let centre = (DVec3::from(lo.map(f64::from)) + DVec3::from(hi.map(f64::from))) * 0.5;
    let d0 = (centre - base.position).length();
    let opts = LodStripOptions {
        panels: 4,
        width: W,
        height: H,
        error_px: 0.5,
        ..Default::default()
    };
    let strip = render_lod_strip(&mut r, &base, d0, &Light::default(), &opts).expect("strip");
    for l in strip.report() {
        eprintln!("{l}");
    }
    assert_eq!((strip.frame.width, strip.frame.height), (4 * W, H));
    assert_eq!(strip.frame.color.len(), (4 * W * H * 4) as usize);
    assert_eq!(strip.panels.len(), 4);
    let tris: Vec<u64> = strip.panels.iter().map(|p| p.triangles).collect();
    assert!(
        tris.windows(2).all(|w| w[1] <= w[0]),
        "triangles must not grow with distance: {tris:?}"
    );
    assert!(
        tris[3] < tris[0],
        "16x farther must draw fewer triangles: {tris:?}"
    );
    // Every panel shows the mesh at about the same apparent size.
    let sizes: Vec<usize> = (0..4)
        .map(|p| {
            (0..(W * H) as usize)
                .filter(|&i| {
                    let (x, y) = (i % W as usize, i / W as usize);
                    strip.frame.depth[y * 4 * W as usize + p * W as usize + x] > 0.0
                })
                .count()
        })
        .collect();
    eprintln!("covered pixels per panel: {sizes:?}");
    for s in &sizes {
        assert!(
            (*s as f64 - sizes[0] as f64).abs() <= 0.25 * sizes[0] as f64,
            "panels differ in apparent size: {sizes:?}"
        );
    }
    // Honesty: panel 2's cut is the one the unmagnified camera at its distance draws.
    let (narrow, _) = panel_view(&base, d0, 2, opts.error_px);
    let wide = Camera {
        fov_y: base.fov_y,
        near: base.near,
        ..narrow
    };
    let f = render(
        &mut r,
        &wide,
        &FrameSettings {
            error_px: opts.error_px,
            occlusion: false,
            ..Default::default()
        },
        ViewMode::Clusters,
    );
    let mut unmagnified = f.visible();
    unmagnified.sort_unstable();
    assert_eq!(
        strip.panels[2].visible, unmagnified,
        "the magnified panel must draw the unmagnified view's cut"
    );
    assert!((strip.panels[2].distance - 4.0 * d0).abs() < 1e-9 * d0);
    // A narrowed view without the threshold scaling would draw the near cut instead.
    let telephoto = render(
        &mut r,
        &narrow,
        &FrameSettings {
            error_px: opts.error_px,
            occlusion: false,
            ..Default::default()
        },
        ViewMode::Clusters,
    );
    assert!(telephoto.frame.triangles > strip.panels[2].triangles);
    assert_no_validation_errors(&ctx);
}

fn vgeo() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_vgeo"));
    c.env("VGEO_VALIDATION", "1");
    c
}

#[test]
fn cli_renders_the_new_views_and_a_lod_strip() {
    let dir = std::env::temp_dir().join(format!("vgeo-views-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let spot = assets().join("spot.obj");
    let png = dir.join("strip.png");
    let out = vgeo()
        .args([
            "render",
            "--lod-strip",
            "--panels",
            "3",
            "--width",
            "80",
            "--height",
            "60",
            "--out",
        ])
        .arg(&png)
        .arg(&spot)
        .output()
        .expect("vgeo runs");
    let (stdout, stderr) = (
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr),
    );
    assert!(out.status.success(), "lod strip failed: {stderr}");
    for k in 0..3 {
        assert!(stdout.contains(&format!("panel {k}: distance")), "{stdout}");
    }
    assert!(!stdout.contains("panel 3:"), "{stdout}");
    let img = image::open(&png).expect("a readable PNG").to_rgba8();
    assert_eq!(img.dimensions(), (240, 60));
    for view in ["groups", "overdraw", "fallback"] {
        let png = dir.join(format!("{view}.png"));
        let out = vgeo()
            .args([
                "render", "--mode", "vgeo", "--view", view, "--width", "64", "--height", "48",
                "--out",
            ])
            .arg(&png)
            .arg(&spot)
            .output()
            .expect("vgeo runs");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(out.status.success(), "--view {view} failed: {stderr}");
        let img = image::open(&png).expect("a readable PNG").to_rgba8();
        assert_eq!(img.dimensions(), (64, 48));
        assert!(non_background(img.as_raw()) > 100, "--view {view}: empty");
    }
    // Bad strip options are clear errors, not panics.
    let out = vgeo()
        .args(["render", "--lod-strip", "--panels", "17"])
        .arg(&spot)
        .output()
        .expect("vgeo runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("panels"),
        "{stderr}"
    );
    assert!(!stderr.contains("panicked"), "{stderr}");
    let out = vgeo()
        .args(["render", "--lod-strip", "--strip-view", "fallback"])
        .arg(&spot)
        .output()
        .expect("vgeo runs");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success() && stderr.contains("fallback"),
        "{stderr}"
    );
}
