//! Every scene file in assets/scenes renders in every mode (brute, lod, vgeo) on lavapipe with the
//! validation layer on, loaded through the scene loader `vgeo render` and `vgeo bench` use
//! (`vgeo::scene::load`, every scene option applied), at 64x48. Scenes above [`MAX_TRIANGLES`]
//! (foliage's million grass clumps) keep every k-th instance, as the quick bench suite does: brute
//! drawing all 168 M triangles on lavapipe took 47 s of the test's 97.

mod common;

use std::path::PathBuf;
use std::time::Instant;

use vgeo::baseline::brute::Brute;
use vgeo::baseline::lod::{Lod, LodOptions};
use vgeo::frame::VgeoRenderer;
use vgeo::imgerr::{Reference, image_error};
use vgeo::passes::debug_view::ViewMode;
use vgeo::passes::view::FrameSettings;
use vgeo::render::Frame;
use vgeo::scene::load::{LoadedScene, MeshCache, thin, triangles_of};

const W: u32 = 64;
const H: u32 = 48;
/// Full-detail triangles a scene is thinned to (every k-th instance).
const MAX_TRIANGLES: u64 = 20_000_000;

/// Something was drawn: covered pixels, and more than one colour.
fn check_image(what: &str, f: &Frame) -> Result<(), String> {
    let first = &f.color[..4];
    let varied = f.color.chunks_exact(4).any(|p| p[..3] != first[..3]);
    if f.width != W || f.height != H || f.covered() == 0 || !varied || f.triangles == 0 {
        return Err(format!(
            "{what}: {}x{}, {} covered pixels, {} triangles, varied colours: {varied}",
            f.width,
            f.height,
            f.covered(),
            f.triangles
        ));
    }
    Ok(())
}

#[test]
fn every_scene_renders_in_every_mode() {
    let ctx = common::gpu();
    let shared = common::shared_assets();
    assert!(shared.join("scanned/lucy.ply").exists(), "{shared:?}");
    let dir = common::assets().join("scenes");
    let mut files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("scenes folder")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    let names: Vec<String> = files
        .iter()
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    for s in vgeo::bench::SCENES
        .iter()
        .chain(&["stress", "demo", "herd"])
    {
        assert!(names.iter().any(|n| n == s), "{s} missing from {names:?}");
    }
    // One cache, as the benchmark has: meshes shared by scenes are imported and built once.
    let mut cache = MeshCache::default();
    let mut failures = Vec::new();
    let mut timings = Vec::new();
    for (file, name) in files.iter().zip(&names) {
        let t = Instant::now();
        let loaded =
            LoadedScene::load_with(&mut cache, file).unwrap_or_else(|e| panic!("{name}: {e:#}"));
        // Every scene option applied: `materials = N` replaced the mesh's materials by (up to N,
        // as many as equal patches of the triangles make) generated ones.
        for (m, mesh) in loaded.scene.meshes.iter().zip(loaded.meshes()) {
            if let Some(n) = m.materials {
                let k = mesh.materials.len();
                assert!(
                    k > n as usize / 2 && k <= n as usize,
                    "{name}: {}: {k} materials",
                    m.name
                );
                assert!(mesh.materials.iter().all(|x| x.name.starts_with("patch")));
            }
        }
        let load_s = t.elapsed().as_secs_f64();
        let camera = loaded.camera(W, H);
        let meshes = loaded.meshes();
        let placements = thin(loaded.placements.clone(), &meshes, Some(MAX_TRIANGLES));
        let (placements, light) = (&placements, &loaded.light);

        let t = Instant::now();
        let brute = Brute::new(&ctx, &meshes).expect("brute renderer");
        let b = brute
            .render(placements, &camera, light, W, H)
            .unwrap_or_else(|e| panic!("{name} brute: {e}"));
        drop(brute);
        let brute_s = t.elapsed().as_secs_f64();
        let reference = Reference::from_frame(&b).expect("reference");
        if let Err(e) = check_image(&format!("{name} brute"), &b) {
            failures.push(e);
        }

        let t = Instant::now();
        let lod = Lod::new(&ctx, &meshes, &LodOptions::default()).expect("lod renderer");
        let l = lod
            .render(placements, &camera, light, W, H, 1.0)
            .unwrap_or_else(|e| panic!("{name} lod: {e}"));
        drop(lod);
        let lod_s = t.elapsed().as_secs_f64();
        let lod_err = image_error(&reference, &l).expect("same size");
        if let Err(e) = check_image(&format!("{name} lod"), &l) {
            failures.push(e);
        }

        let t = Instant::now();
        let vgeo = match loaded.built_meshes(&|_| {}) {
            Err(e) => Err(format!("{name} vgeo: build failed: {e:#}")),
            Ok(built) => {
                let build_s = t.elapsed().as_secs_f64();
                let mut r = VgeoRenderer::new(&ctx, &built, placements).expect("vgeo renderer");
                let settings = FrameSettings {
                    error_px: 1.0,
                    ..FrameSettings::default()
                };
                let vf = r
                    .render(&camera, W, H, &settings, ViewMode::Lit, light)
                    .unwrap_or_else(|e| panic!("{name} vgeo: {e}"));
                match vf.check() {
                    Err(e) => Err(format!("{name} vgeo: incomplete frame: {e}")),
                    Ok(()) => Ok((vf.frame, build_s)),
                }
            }
        };
        let vgeo_s = t.elapsed().as_secs_f64();
        common::assert_no_validation_errors(&ctx);
        let line = match vgeo {
            Err(e) => {
                failures.push(e.clone());
                e
            }
            Ok((v, build_s)) => {
                let vgeo_err = image_error(&reference, &v).expect("same size");
                if let Err(e) = check_image(&format!("{name} vgeo"), &v) {
                    failures.push(e);
                }
                // The three modes show the same scene: coverage agrees with brute's nearly
                // everywhere (different surfaces at 1 px are allowed, different coverage barely).
                for (mode, e) in [("lod", &lod_err), ("vgeo", &vgeo_err)] {
                    if e.coverage_diff > 0.05 {
                        failures.push(format!(
                            "{name} {mode}: coverage differs from brute's on {:.1} % of the pixels",
                            e.coverage_diff * 100.0
                        ));
                    }
                }
                format!(
                    "vgeo {:.1} s (build {build_s:.1} s; {} triangles, coverage diff {:.2} %, PSNR {:.1} dB)",
                    vgeo_s,
                    v.triangles,
                    vgeo_err.coverage_diff * 100.0,
                    vgeo_err.psnr_db
                )
            }
        };
        let summary = format!(
            "{name}: {} of {} instances, {} triangles; load {load_s:.1} s; brute {brute_s:.1} s ({} triangles); lod {lod_s:.1} s ({} triangles, coverage diff {:.2} %, PSNR {:.1} dB); {line}",
            placements.len(),
            loaded.placements.len(),
            triangles_of(placements, &meshes),
            b.triangles,
            l.triangles,
            lod_err.coverage_diff * 100.0,
            lod_err.psnr_db,
        );
        eprintln!("{summary}");
        timings.push(summary);
    }
    assert!(
        failures.is_empty(),
        "{} failure(s):\n{}\n\ntimings:\n{}",
        failures.len(),
        failures.join("\n"),
        timings.join("\n")
    );
}
