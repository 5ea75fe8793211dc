//! The brute-force renderer on the GPU (lavapipe in CI) against the CPU reference rasterizer, with
//! the validation layer on.

mod common;

use common::{assert_no_validation_errors, assets, gpu, shared_assets};
use vgeo::baseline::brute::Brute;
use vgeo::reference::{RasterTarget, mesh_triangles, rasterize};
use vgeo::render::Frame;
use vgeo::scene::load::LoadedScene;

/// Renders `scene` with brute on the GPU and with the reference on the CPU; returns (coverage
/// agreement, depth agreement among pixels both cover, covered pixels).
fn compare_with_reference(path: &std::path::Path, w: u32, h: u32) -> (f64, f64, usize, Frame) {
    let scene = LoadedScene::load(path).expect("scene loads");
    let camera = scene.camera(w, h);
    let ctx = gpu();
    let brute = Brute::new(&ctx, &scene.meshes()).expect("brute renderer");
    let frame = brute
        .render(&scene.placements, &camera, &scene.light, w, h)
        .expect("render");
    assert_no_validation_errors(&ctx);

    let vp = camera.view_proj(w, h);
    let mut target = RasterTarget::new(w, h);
    for (i, p) in scene.placements.iter().enumerate() {
        let model = camera.relative_model(&p.transform);
        let tris = mesh_triangles(scene.mesh(p.mesh), &model, (i as u32) << 20);
        rasterize(&mut target, &vp, tris);
    }
    let n = (w * h) as usize;
    let mut same_cover = 0;
    let mut both = 0;
    let mut depth_ok = 0;
    for i in 0..n {
        let g = frame.depth[i];
        let r = target.depth[i];
        if (g > 0.0) == (r > 0.0) {
            same_cover += 1;
        }
        if g > 0.0 && r > 0.0 {
            both += 1;
            if (g - r).abs() <= 1e-3 * r.max(g) {
                depth_ok += 1;
            }
        }
    }
    let (c, d) = (
        same_cover as f64 / n as f64,
        depth_ok as f64 / both.max(1) as f64,
    );
    eprintln!(
        "{}: coverage agreement {c:.5}, depth agreement {d:.5}, {both} pixels covered by both",
        path.display()
    );
    (c, d, both, frame)
}

#[test]
fn bunny_matches_reference_rasterizer() {
    let path = shared_assets().join("scanned/bunny.ply");
    let (coverage, depth, covered, frame) = compare_with_reference(&path, 256, 192);
    assert!(
        covered > 5_000,
        "the bunny should fill a good part of the frame, covered {covered}"
    );
    assert!(
        coverage >= 0.995,
        "coverage agreement {coverage:.5} < 99.5%"
    );
    assert!(depth >= 0.995, "depth agreement {depth:.5} < 99.5%");
    assert_eq!(frame.triangles, 69_451);
    // The shaded image is not flat: lit pixels differ from the background.
    let distinct: std::collections::BTreeSet<_> = frame.color.chunks(4).map(|c| c[0]).collect();
    assert!(
        distinct.len() > 20,
        "shading looks flat: {} distinct red values",
        distinct.len()
    );
}

#[test]
fn flight_helmet_multi_node_gltf_matches_reference_rasterizer() {
    let path = shared_assets().join("gltf/FlightHelmet/FlightHelmet.gltf");
    let (coverage, depth, covered, frame) = compare_with_reference(&path, 160, 224);
    assert!(
        covered > 3_000,
        "the helmet should fill a good part of the frame, covered {covered}"
    );
    assert!(
        coverage >= 0.995,
        "coverage agreement {coverage:.5} < 99.5%"
    );
    assert!(depth >= 0.995, "depth agreement {depth:.5} < 99.5%");
    assert_eq!(frame.triangles, 94_722);
}

#[test]
fn herd_scene_renders_and_matches_reference() {
    let path = assets().join("scenes/herd.toml");
    let (coverage, depth, covered, frame) = compare_with_reference(&path, 240, 135);
    assert!(covered > 2_000, "covered {covered}");
    assert!(coverage >= 0.995, "coverage agreement {coverage:.5}");
    assert!(depth >= 0.995, "depth agreement {depth:.5}");
    assert!(frame.triangles > 400_000);
}

#[test]
fn timestamps_report_the_brute_pass() {
    let ctx = gpu();
    let scene = LoadedScene::load(&assets().join("spot.obj")).expect("spot loads");
    let brute = Brute::new(&ctx, &scene.meshes()).expect("brute");
    let frame = brute
        .render(
            &scene.placements,
            &scene.camera(64, 64),
            &scene.light,
            64,
            64,
        )
        .expect("render");
    if ctx.caps().timestamp_period_ns.is_some() {
        let names: Vec<&str> = frame.gpu_ms.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["brute", "shade"]);
        assert!(
            frame
                .gpu_ms
                .iter()
                .all(|(_, ms)| *ms > 0.0 && ms.is_finite())
        );
    }
    assert_no_validation_errors(&ctx);
}

#[test]
fn validation_errors_are_caught() {
    let ctx = gpu();
    assert!(ctx.validation_errors().is_empty());
    ctx.provoke_validation_error();
    let errors = ctx.validation_errors();
    assert!(
        !errors.is_empty(),
        "a zero-sized buffer must be reported by the validation layer"
    );
}

/// The supersampled reference: one sample per pixel is brute's frame exactly; rendered in uneven
/// tiles (off-centre projections of the same camera) it is the reference rendered in one piece,
/// but for samples on triangle edges that float rounding moves across.
#[test]
fn supersampled_reference_in_tiles_matches_one_piece() {
    use vgeo::imgerr::{Reference, image_error};
    let scene = LoadedScene::load(&assets().join("scenes/herd.toml")).expect("herd loads");
    let (w, h, n) = (40, 30, 3);
    let camera = scene.camera(w, h);
    let ctx = gpu();
    let brute = Brute::new(&ctx, &scene.meshes()).expect("brute");
    let (p, l) = (&scene.placements, &scene.light);
    let one = brute.render(p, &camera, l, w, h).expect("frame");
    let r1 = brute
        .render_reference(p, &camera, l, (w, h), 1)
        .expect("1 spp");
    assert_eq!(r1, Reference::from_frame(&one).unwrap());
    // Brute's frame measured against itself: no error.
    let e = image_error(&r1, &one).unwrap();
    assert_eq!((e.surface_diff, e.psnr_db), (0.0, f64::INFINITY));

    let whole = brute
        .render_reference_tiled(p, &camera, l, (w, h), n, 10_000)
        .expect("one tile");
    // Tiles of 7 x 7 pixels (21 samples a side): 6 x 5 tiles, the last column and row narrower.
    let tiled = brute
        .render_reference_tiled(p, &camera, l, (w, h), n, 7 * n)
        .expect("tiles");
    // The one-piece reference is the box filter of brute at 3x the resolution.
    let big = brute.render(p, &camera, l, w * n, h * n).expect("big");
    assert_eq!(whole, Reference::from_supersampled(&big, n).unwrap());
    let covered = whole.covered.iter().filter(|&&c| c > 0).count();
    assert!(covered > 100, "covered {covered}");
    let same_cover = (whole.covered.iter().zip(&tiled.covered))
        .filter(|(a, b)| a == b)
        .count();
    assert!(
        same_cover as f64 >= 0.97 * (w * h) as f64,
        "{same_cover} of {} pixels cover as many samples",
        w * h
    );
    let db = vgeo::imgerr::psnr_rgb(&whole.color, &tiled.color);
    assert!(db > 40.0, "tiled vs one piece: {db:.1} dB");
    // Brute at one sample per pixel against the 3x3 reference: not equal (the floor; 23.5 dB
    // here, a 40x30 image of sub-pixel detail), the same surfaces.
    let floor = image_error(&tiled, &one).unwrap();
    assert!(
        floor.psnr_db.is_finite() && floor.psnr_db > 15.0 && floor.coverage_diff < 0.02,
        "{floor:?}"
    );
    assert_no_validation_errors(&ctx);
}
