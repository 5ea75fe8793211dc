//! `--shader-dir`: a pass's GLSL edited in a folder takes effect without a rebuild; a broken
//! shader or a changed interface block is a clear error, never a panic (validation on).

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn vgeo() -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_vgeo"));
    c.env("VGEO_VALIDATION", "1").env_remove("VGEO_SHADER_DIR");
    c
}

/// A fresh folder under the target dir for one test.
fn folder(name: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join(format!("shader_dir_{name}"));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(d.join("common")).unwrap();
    d
}

fn source(rel: &str) -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("shaders_glsl")
            .join(rel),
    )
    .unwrap()
}

/// Renders the bunny small in vgeo mode, lit; (success, stderr, image when written).
fn render(dir: Option<&Path>, out: &str) -> (bool, String, Option<image::RgbaImage>) {
    let png = Path::new(env!("CARGO_TARGET_TMPDIR")).join(out);
    let _ = std::fs::remove_file(&png);
    let mut c = vgeo();
    c.args([
        "render", "--mode", "vgeo", "--width", "48", "--height", "48", "-o",
    ])
    .arg(&png)
    .arg(common::assets().join("bunny.ply"));
    if let Some(d) = dir {
        c.arg("--shader-dir").arg(d);
    }
    let o = c.output().expect("vgeo runs");
    let err = String::from_utf8_lossy(&o.stderr).into_owned();
    assert!(!err.contains("panicked"), "vgeo panicked:\n{err}");
    let img = image::open(&png).ok().map(|i| i.to_rgba8());
    (o.status.success(), err, img)
}

#[test]
fn an_edited_pass_changes_the_image() {
    let d = folder("edited");
    let text = source("shade.comp.glsl");
    let store = "imageStore(out_image, px, vec4(color, 1.0));";
    assert!(
        text.contains(store),
        "shade.comp.glsl no longer ends in {store}"
    );
    std::fs::write(
        d.join("shade.comp.glsl"),
        text.replace(
            store,
            "imageStore(out_image, px, vec4(1.0, 0.0, 1.0, 1.0));",
        ),
    )
    .unwrap();
    let (ok, err, img) = render(None, "shader_dir_before.png");
    assert!(ok, "{err}");
    let before = img.unwrap();
    let magenta = |p: &image::Rgba<u8>| p.0 == [255, 0, 255, 255];
    assert!(
        !before.pixels().any(magenta),
        "the built-in image has magenta"
    );
    let (ok, err, img) = render(Some(&d), "shader_dir_after.png");
    assert!(ok, "{err}");
    assert!(
        err.contains("shaders from") && err.contains("shade.comp.glsl"),
        "{err}"
    );
    let after = img.unwrap();
    assert!(
        after.pixels().all(magenta),
        "the edited shade pass did not run"
    );
}

#[test]
fn an_edited_include_recompiles_its_users() {
    let d = folder("include");
    std::fs::write(d.join("common/shading.glsl"), source("common/shading.glsl")).unwrap();
    let (ok, err, img) = render(Some(&d), "shader_dir_include.png");
    assert!(ok, "{err}");
    // The same text gives the same image; every shader including it was compiled again.
    assert!(err.contains("shade.comp.glsl"), "{err}");
    let (_, _, reference) = render(None, "shader_dir_include_ref.png");
    assert_eq!(img.unwrap(), reference.unwrap());
}

#[test]
fn a_broken_shader_names_file_and_line() {
    let d = folder("broken");
    let mut lines: Vec<String> = source("shade.comp.glsl")
        .lines()
        .map(String::from)
        .collect();
    // The first statement of main (a line in a comment would stay valid GLSL).
    let at = lines
        .iter()
        .position(|l| l.starts_with("void main()"))
        .expect("shade.comp.glsl has main")
        + 1;
    assert!(lines[at].trim_end().ends_with(';'), "{}", lines[at]);
    lines[at].push_str(" this is not glsl;");
    std::fs::write(d.join("shade.comp.glsl"), lines.join("\n")).unwrap();
    let (ok, err, img) = render(Some(&d), "shader_dir_broken.png");
    assert!(!ok && img.is_none(), "a broken shader rendered");
    let want = format!("{}:{}: error", d.join("shade.comp.glsl").display(), at + 1);
    assert!(err.contains(&want), "`{want}` missing from:\n{err}");
}

#[test]
fn a_changed_block_size_is_refused() {
    let d = folder("block");
    let text = source("common/cull_bindings.glsl");
    let pc = "uniform Phase { uint phase; } pc;";
    assert!(
        text.contains(pc),
        "cull_bindings.glsl no longer declares {pc}"
    );
    std::fs::write(
        d.join("common/cull_bindings.glsl"),
        text.replace(pc, "uniform Phase { uint phase; uint extra; } pc;"),
    )
    .unwrap();
    let (ok, err, _) = render(Some(&d), "shader_dir_block.png");
    assert!(!ok, "a changed push-constant block was accepted");
    assert!(
        err.contains("interface blocks changed size") && err.contains("push constants is 8 bytes"),
        "{err}"
    );
}

#[test]
fn unknown_files_and_missing_folders_are_errors() {
    let d = folder("unknown");
    std::fs::write(d.join("shading.comp.glsl"), "void main() {}").unwrap();
    let (ok, err, _) = render(Some(&d), "shader_dir_unknown.png");
    assert!(!ok && err.contains("not a vgeo shader source"), "{err}");
    let (ok, err, _) = render(Some(&d.join("nope")), "shader_dir_missing.png");
    assert!(!ok && err.contains("does not exist"), "{err}");
}
