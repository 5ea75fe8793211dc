//! The `vgeo` command line as a user runs it (validation on).

mod common;

use std::process::Command;

use common::{assets, shared_assets};

fn vgeo() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_vgeo"));
    c.env("VGEO_VALIDATION", "1");
    c
}

fn run(c: &mut Command) -> (bool, String, String) {
    let out = c.output().expect("vgeo runs");
    (
        out.status.success(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

#[test]
fn info_prints_device_and_features() {
    let (ok, out, err) = run(vgeo().arg("info"));
    assert!(ok, "vgeo info failed: {err}");
    for key in [
        "device:",
        "driver:",
        "shaderInt64:",
        "64-bit buffer atomics:",
        "64-bit image atomics:",
        "multiDrawIndirect:",
        "drawIndirectCount:",
        "timestamps:",
        "subgroup size:",
        "device-local memory:",
        "mesh shaders:",
        "raster_hw path:",
    ] {
        assert!(out.contains(key), "`{key}` missing from:\n{out}");
    }
}

#[test]
fn render_mesh_writes_png() {
    let dir = std::env::temp_dir().join(format!("vgeo-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("bunny.png");
    let bunny = shared_assets().join("scanned/bunny.ply");
    let (ok, out, err) = run(vgeo()
        .args([
            "render", "--mode", "brute", "--width", "96", "--height", "64", "--out",
        ])
        .arg(&png)
        .arg(&bunny));
    assert!(ok, "render failed: {err}");
    assert!(
        out.contains("triangles:  69451 drawn (100.0 % of the scene)"),
        "{out}"
    );
    let img = image::open(&png).expect("a readable PNG").to_rgba8();
    assert_eq!(img.dimensions(), (96, 64));
    let bg = img.get_pixel(0, 0);
    let lit = img.pixels().filter(|p| *p != bg).count();
    assert!(lit > 500, "the bunny covers only {lit} pixels");
    assert!(!err.contains("validation error"), "{err}");
}

#[test]
fn render_lod_on_the_gpu_and_the_cpu_gives_one_image() {
    let dir = std::env::temp_dir().join(format!("vgeo-cli-lod-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let spot = assets().join("spot.obj");
    let mut images = Vec::new();
    for mode in ["lod", "lod-cpu"] {
        let png = dir.join(format!("{mode}.png"));
        let (ok, out, err) = run(vgeo()
            .args(["render", "--mode", mode, "--width", "64", "--height", "48"])
            .arg("--out")
            .arg(&png)
            .arg(&spot));
        assert!(ok, "{mode} failed: {err}");
        assert!(out.contains("triangles:"), "{mode}: {out}");
        assert!(!err.contains("validation error"), "{mode}: {err}");
        images.push(image::open(&png).expect("a readable PNG").to_rgba8());
    }
    assert!(images[0] == images[1], "lod and lod-cpu images differ");
    let bg = images[0].get_pixel(0, 0);
    assert!(images[0].pixels().filter(|p| *p != bg).count() > 200);
}

#[test]
fn bad_input_is_a_clear_error_not_a_panic() {
    let invalid = shared_assets().join("invalid/BoxWithInfinites.glb");
    let cases: Vec<(Vec<std::ffi::OsString>, &str)> = vec![
        (
            vec!["render".into(), invalid.clone().into()],
            "BoxWithInfinites.glb",
        ),
        (
            vec!["render".into(), "/nonexistent/mesh.ply".into()],
            "mesh.ply",
        ),
        (
            vec!["render".into(), assets().join("ATTRIBUTION.md").into()],
            "ATTRIBUTION.md",
        ),
        (
            vec![
                "render".into(),
                "--width".into(),
                "0".into(),
                assets().join("spot.obj").into(),
            ],
            "--width",
        ),
        (
            vec![
                "render".into(),
                "--mode".into(),
                "magic".into(),
                assets().join("spot.obj").into(),
            ],
            "magic",
        ),
        (
            vec![
                "render".into(),
                "--hw-path".into(),
                "geometry".into(),
                assets().join("spot.obj").into(),
            ],
            "--hw-path `geometry`",
        ),
    ];
    for (args, needle) in cases {
        let (ok, _out, err) = run(vgeo().args(&args));
        assert!(!ok, "{args:?} should fail");
        assert!(err.contains("error"), "{args:?}: {err}");
        assert!(
            err.contains(needle),
            "{args:?}: error should name `{needle}`: {err}"
        );
        assert!(!err.contains("panicked"), "{args:?} panicked: {err}");
    }
}

/// `--hw-path`: every cluster to the hardware rasterizer (`--hw-threshold 0`) gives one image on
/// the vertex and the mesh path (where the device has mesh shaders; elsewhere `mesh` is a clear
/// error), and `--stats` says which path drew.
#[test]
fn render_hw_paths_give_one_image() {
    let dir = std::env::temp_dir().join(format!("vgeo-cli-hw-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (ok, info, err) = run(vgeo().arg("info"));
    assert!(ok, "{err}");
    let has_mesh = info.contains("mesh shaders:          yes");
    let mut images = Vec::new();
    for path in ["vertex", "mesh"] {
        let png = dir.join(format!("{path}.png"));
        let (ok, out, err) = run(vgeo()
            .args(["render", "--width", "96", "--height", "64", "--stats"])
            .args(["--hw-threshold", "0", "--hw-path", path, "--out"])
            .arg(&png)
            .arg(assets().join("spot.obj")));
        if path == "mesh" && !has_mesh {
            assert!(!ok, "--hw-path mesh without mesh shaders should fail");
            assert!(err.contains("VK_EXT_mesh_shader"), "{err}");
            assert!(!err.contains("panicked"), "{err}");
            return;
        }
        assert!(ok, "--hw-path {path} failed: {err}");
        assert!(
            out.contains(&format!("raster_hw: {path} path (--hw-path {path})")),
            "{out}"
        );
        assert!(!err.contains("validation error"), "{path}: {err}");
        images.push(image::open(&png).expect("a readable PNG").to_rgba8());
    }
    assert!(
        images[0] == images[1],
        "the vertex and mesh paths' images differ"
    );
    let bg = images[0].get_pixel(0, 0);
    assert!(images[0].pixels().filter(|p| *p != bg).count() > 200);
}

#[test]
fn build_verify_and_info_of_a_vgeo_file() {
    let dir = std::env::temp_dir().join(format!("vgeo-cli-build-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let out_file = dir.join("spot.vgeo");
    let (ok, _, err) = run(vgeo()
        .arg("build")
        .arg(assets().join("spot.obj"))
        .arg("-o")
        .arg(&out_file));
    assert!(ok, "build failed: {err}");
    let (ok, out, err) = run(vgeo().arg("verify").arg(&out_file));
    assert!(ok, "verify failed: {out}{err}");
    let (ok, out, err) = run(vgeo().arg("info").arg(&out_file));
    assert!(ok, "info failed: {err}");
    assert!(
        out.contains("5856"),
        "info should state the input triangles: {out}"
    );
    assert!(
        out.contains("closed solid: seen from outside"),
        "info should say spot is a closed solid: {out}"
    );
    assert!(
        out.contains("pages: ") && out.contains("bits each: position ") && out.contains(", uv "),
        "info should say where the page bytes go (spot has UVs): {out}"
    );
    assert!(
        out.contains("precision: 14 position bits per axis")
            && out.contains("12 normal bits per component"),
        "info should state the stated precision (spot: 14 bits by its short edges): {out}"
    );
    assert!(
        out.contains("small instances: under 16 px an error counts a share"),
        "info should say how small instances count the errors: {out}"
    );
    // A file from before the coverage part: info says its errors count whole.
    let mut old = vgeo::format::load(&std::fs::read(&out_file).unwrap()).expect("loads");
    old.group_coverage.clear();
    let old_file = dir.join("old.vgeo");
    std::fs::write(&old_file, vgeo::format::save(&old)).unwrap();
    let (ok, out, err) = run(vgeo().arg("info").arg(&old_file));
    assert!(ok, "info failed: {err}");
    assert!(
        out.contains("small instances: every error counts whole"),
        "info should say an older file's errors count whole: {out}"
    );
    let (ok, out, err) = run(vgeo()
        .arg("build")
        .arg(assets().join("bunny.ply"))
        .arg("-o")
        .arg(dir.join("bunny.vgeo")));
    assert!(ok, "build failed: {err}");
    assert!(
        out.contains("not a closed solid"),
        "build should say the bunny (with holes) is not a closed solid: {out}"
    );
    // A truncated file is an error, not a panic.
    let bytes = std::fs::read(&out_file).unwrap();
    let cut = dir.join("cut.vgeo");
    std::fs::write(&cut, &bytes[..bytes.len() / 2]).unwrap();
    let (ok, _, err) = run(vgeo().arg("verify").arg(&cut));
    assert!(!ok && !err.contains("panicked"), "{err}");
}

/// `vgeo build SCENE.toml` builds every mesh of the scene through the scene loader, with the
/// scene's options applied (`materials = N`, generated meshes), one file per mesh.
#[test]
fn build_of_a_scene_applies_its_options() {
    let dir = std::env::temp_dir().join(format!("vgeo-cli-scene-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("scene.toml");
    let spot = assets().join("spot.obj");
    std::fs::write(
        &scene,
        format!(
            "[[mesh]]\nname = \"ground\"\npath = \"generated:box\"\n\
             [[mesh]]\nname = \"spot\"\npath = {:?}\nmaterials = 8\n\
             [[mesh]]\nname = \"spot_again\"\npath = {:?}\nmaterials = 8\n\
             [[instance]]\nmesh = \"ground\"\n[[instance]]\nmesh = \"spot\"\n",
            spot.display().to_string(),
            spot.display().to_string()
        ),
    )
    .unwrap();
    let out = dir.join("built");
    let (ok, stdout, err) = run(vgeo().arg("build").arg(&scene).arg("-o").arg(&out));
    assert!(ok, "build failed: {stdout}{err}");
    let load = |name: &str| {
        let bytes = std::fs::read(out.join(format!("{name}.vgeo")))
            .unwrap_or_else(|e| panic!("{name}.vgeo: {e}"));
        vgeo::format::load(&bytes).unwrap_or_else(|e| panic!("{name}.vgeo: {e}"))
    };
    assert_eq!(load("ground").stats.input_triangles, 12);
    let spot = load("spot");
    assert_eq!(spot.stats.input_triangles, 5856);
    assert_eq!(spot.materials.len(), 8, "materials = 8 applied");
    // The same mesh with the same options is built once.
    assert!(!out.join("spot_again.vgeo").exists());
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn help_explains_commands() {
    let (ok, out, _) = run(vgeo().arg("--help"));
    assert!(ok);
    for cmd in ["render", "build", "bench", "verify", "info"] {
        assert!(out.contains(cmd), "--help lacks `{cmd}`:\n{out}");
    }
    // The benchmark's reference and equal-error options are explained.
    let (ok, out, _) = run(vgeo().args(["bench", "--help"]));
    assert!(ok);
    for opt in ["--reference-spp", "--psnr-margin", "4x4", "floor"] {
        assert!(out.contains(opt), "bench --help lacks `{opt}`:\n{out}");
    }
    // The SW/HW split's default is the renderer's (measured: `auto`), in both commands' help.
    assert!(
        out.contains("Default `auto`"),
        "bench --help lacks the automatic split:\n{out}"
    );
    let (ok, out, _) = run(vgeo().args(["render", "--help"]));
    assert!(ok);
    assert!(
        out.contains("[default: auto]"),
        "render --help lacks the automatic split:\n{out}"
    );
    // A split that is neither `auto` nor a number of pixels is refused, saying what it takes.
    for bad in ["--hw-threshold=-3", "--hw-threshold=fast"] {
        let (ok, _, err) = run(vgeo().args(["render", "x.ply", bad]));
        assert!(!ok, "--hw-threshold {bad} was taken");
        assert!(err.contains("`auto` or a number of pixels"), "{err}");
    }
}

/// `vgeo` with no arguments: the demo (a field of bunnies, over 100 M instanced triangles) in vgeo
/// mode, the image and its clusters view, scene triangles against triangles drawn.
#[test]
fn no_arguments_render_the_demo_in_vgeo_mode() {
    let dir = std::env::temp_dir().join(format!("vgeo-demo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let (ok, out, err) = run(vgeo().current_dir(&dir));
    assert!(ok, "vgeo failed: {err}");
    assert!(out.contains("(vgeo mode)"), "{out}");
    let number = |key: &str| -> u64 {
        let line = out
            .lines()
            .find(|l| l.starts_with(key))
            .unwrap_or_else(|| panic!("{key} in {out}"));
        line.split(|c: char| !c.is_ascii_digit())
            .filter(|w| !w.is_empty())
            .map(|w| w.parse().unwrap())
            .collect::<Vec<u64>>()[if key == "scene:" { 2 } else { 0 }]
    };
    let scene = number("scene:");
    let drawn = number("triangles:");
    let clusters = number("clusters:");
    assert!(scene >= 100_000_000, "the demo has {scene} triangles");
    assert!(drawn > 0 && drawn * 10 < scene, "drew {drawn} of {scene}");
    assert!(
        clusters > 0 && clusters * 128 >= drawn,
        "{clusters} clusters for {drawn}"
    );
    for png in ["vgeo.png", "vgeo_clusters.png"] {
        let img = image::open(dir.join(png))
            .expect("a readable PNG")
            .to_rgba8();
        assert_eq!(img.dimensions(), (1280, 720));
    }
    assert!(!err.contains("validation error"), "{err}");
}

/// `vgeo render FILE.vgeo --geometry-budget`: the file is opened head-only and read page by page
/// as the view asks. With its finest page corrupted, a small far view (which never needs that
/// page) renders without a word, while loading the whole file fails on that page; the intact
/// file streamed settles to the image of the whole file.
#[test]
fn render_streams_a_vgeo_file_reading_only_the_pages_the_view_needs() {
    let dir = std::env::temp_dir().join(format!("vgeo-cli-stream-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bunny.vgeo");
    let (ok, _, err) = run(vgeo()
        .args(["build", "--threads", "1", "-o"])
        .arg(&file)
        .arg(assets().join("bunny.ply")));
    assert!(ok, "build failed: {err}");
    let render = |out: &str, streamed: bool| {
        let mut c = vgeo();
        c.args([
            "render", "--width", "64", "--height", "48", "--frames", "12", "--out",
        ])
        .arg(dir.join(out))
        .arg(&file);
        if streamed {
            c.args(["--geometry-budget", "8", "--stream-mib-per-frame", "1"]);
        }
        run(&mut c)
    };
    let (ok, _, err) = render("whole.png", false);
    assert!(ok, "{err}");
    let (ok, out, err) = render("streamed.png", true);
    assert!(ok && !err.contains("warning"), "{out}\n{err}");
    assert_eq!(
        std::fs::read(dir.join("whole.png")).unwrap(),
        std::fs::read(dir.join("streamed.png")).unwrap(),
        "the streamed frame settles to the whole file's"
    );
    // Corrupt the last page (the finest level's).
    let f = vgeo::format::VgeoFile::open(&file).expect("opens");
    let e = *f.page_entry(f.page_count() - 1).unwrap();
    drop(f);
    let mut bytes = std::fs::read(&file).unwrap();
    bytes[(e.offset + e.length / 2) as usize] ^= 0x5a;
    std::fs::write(&file, &bytes).unwrap();
    let (ok, _, err) = render("whole2.png", false);
    assert!(!ok && err.contains("corrupted .vgeo page"), "{err}");
    let (ok, out, err) = render("streamed2.png", true);
    assert!(ok && !err.contains("warning"), "{out}\n{err}");
    assert_eq!(
        std::fs::read(dir.join("streamed.png")).unwrap(),
        std::fs::read(dir.join("streamed2.png")).unwrap(),
        "the far view never needed the corrupted page"
    );
}

/// `vgeo render --path`: the camera follows the scene's path over `--frames`, with a line per
/// frame under `--stats` (and the residency with `--geometry-budget`); other modes refuse it.
#[test]
fn render_path_reports_every_frame() {
    let dir = std::env::temp_dir().join(format!("vgeo-cli-path-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = assets().join("scenes/herd.toml");
    let args = |budget: bool| {
        let mut c = vgeo();
        c.args([
            "render", "--path", "--frames", "3", "--stats", "--width", "64", "--height", "48",
            "--out",
        ])
        .arg(dir.join("path.png"))
        .arg(&scene);
        if budget {
            c.args(["--geometry-budget", "16"]);
        }
        c
    };
    let (ok, out, err) = run(&mut args(false));
    assert!(ok, "{err}");
    for f in 1..=3 {
        assert!(
            out.contains(&format!("  frame {f}: ")),
            "frame {f} missing:\n{out}"
        );
    }
    let (ok, out, err) = run(&mut args(true));
    assert!(ok, "{err}");
    assert!(
        out.contains("  frame 3: ") && out.contains("pages resident") && out.contains("used "),
        "{out}"
    );
    let (ok, _, err) = run(args(false).args(["--mode", "brute"]));
    assert!(!ok && err.contains("--path"), "{err}");
    // --time: the last view timed back to back, with the automatic split settled first and
    // said.
    let (ok, out, err) = run(args(true).args(["--time", "4"]));
    assert!(
        ok && out.contains("timed:") && out.contains("mean of 4 frames"),
        "{out}\n{err}"
    );
    assert!(out.contains("split:      auto: "), "{out}");
}

/// `--geometry-budget` alone (or `auto`) streams under a quarter of the device-local heap, said at
/// the start; the `residency` view renders with it; a budget that is no number of MiB is refused
/// with what is accepted.
#[test]
fn geometry_budget_auto_and_the_residency_view() {
    let dir = std::env::temp_dir().join(format!("vgeo-cli-auto-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let png = dir.join("residency.png");
    let bunny = assets().join("bunny.ply");
    // Three frames: the pages the first frame asks for are drawn by the third (the always-resident
    // pages hold the fallback level alone, so the first two show its clusters wanting detail).
    let mut c = vgeo();
    c.arg("render")
        .arg(&bunny)
        .args(["--width", "64", "--height", "48", "--frames", "3"])
        .args(["--view", "residency", "--geometry-budget", "--out"])
        .arg(&png);
    let (ok, out, err) = run(&mut c);
    assert!(ok, "{out}\n{err}");
    assert!(
        err.contains("geometry budget: ") && err.contains("(auto: a quarter of the"),
        "{err}"
    );
    let img = image::open(&png).expect("a readable PNG").to_rgba8();
    let green = vgeo::shared::RESIDENCY_COLOR_RESIDENT.to_le_bytes();
    let dark = vgeo::shared::RESIDENCY_COLOR_NOT_NEEDED.to_le_bytes();
    let drawn = img
        .pixels()
        .filter(|p| p.0[..3] == green[..3] || p.0[..3] == dark[..3])
        .count();
    assert!(drawn > 50, "{drawn} pixels resident or not needed");
    let (ok, _, err) = run(vgeo()
        .arg("render")
        .arg(&bunny)
        .args(["--geometry-budget", "lots", "--out"])
        .arg(dir.join("x.png")));
    assert!(
        !ok && err.contains("--geometry-budget") && err.contains("auto"),
        "{err}"
    );
    std::fs::remove_dir_all(&dir).ok();
}
