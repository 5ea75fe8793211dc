//! RenderDoc capture of one vgeo frame (Debian's renderdoc 1.24 on lavapipe, installed by
//! `.ci/setup.sh`): run directly with `--capture` and launched by `renderdoccmd`, converted to XML,
//! the capture names every pass of the frame and the main objects.

mod common;

use std::path::{Path, PathBuf};
use std::process::Command;

fn tmp(name: &str) -> PathBuf {
    let p = Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_file(&p);
    p
}

fn render_args(png: &Path, rdc: &Path) -> Vec<String> {
    let bunny = common::assets().join("bunny.ply");
    [
        "render",
        bunny.to_str().unwrap(),
        "--mode",
        "vgeo",
        "--width",
        "96",
        "--height",
        "96",
        "-o",
        png.to_str().unwrap(),
        "--capture",
        rdc.to_str().unwrap(),
    ]
    .map(String::from)
    .to_vec()
}

/// The capture as RenderDoc's XML.
fn convert(rdc: &Path) -> String {
    let xml = rdc.with_extension("zip.xml");
    let o = Command::new("renderdoccmd")
        .args(["convert", "-c", "zip.xml", "-f"])
        .arg(rdc)
        .arg("-o")
        .arg(&xml)
        .output()
        .expect("renderdoccmd runs (install renderdoc: bash .ci/setup.sh)");
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    std::fs::read_to_string(&xml).expect("converted capture")
}

/// Values of `<string name="NAME" ...>value</string>` in the XML.
fn strings(xml: &str, name: &str) -> Vec<String> {
    let key = format!("<string name=\"{name}\"");
    xml.lines()
        .filter_map(|l| {
            let at = l.find(&key)?;
            let rest = &l[at..];
            let start = rest.find('>')? + 1;
            let end = rest.find("</string>")?;
            Some(rest[start..end].to_string())
        })
        .collect()
}

fn check_capture(rdc: &Path) {
    let xml = convert(rdc);
    let labels = strings(&xml, "pLabelName");
    for pass in [
        "instance_cull",
        "cluster_cull",
        "raster_sw",
        "raster_hw",
        "depth_pyramid",
        "instance_cull (post)",
        "cluster_cull (post)",
        "raster_sw (post)",
        "raster_hw (post)",
        "material_classify",
        "emit_gbuffer",
        "shade",
    ] {
        assert!(
            labels.iter().any(|l| l == pass),
            "pass label `{pass}` not in the capture: {labels:?}"
        );
    }
    let names = strings(&xml, "ObjectName");
    for object in [
        "scene cluster locators",
        "scene instances",
        "scene bvh",
        "cull queue",
        "visible clusters",
        "visbuffer",
        "hzb",
        "view",
        "instance_cull",
        "shade",
        "main queue",
    ] {
        assert!(
            names.iter().any(|n| n == object),
            "object name `{object}` not in the capture"
        );
    }
}

#[test]
fn capture_run_directly_names_every_pass() {
    let (png, rdc) = (tmp("capture_direct.png"), tmp("capture_direct.rdc"));
    let o = Command::new(env!("CARGO_BIN_EXE_vgeo"))
        .args(render_args(&png, &rdc))
        .env("VGEO_VALIDATION", "1")
        .output()
        .expect("vgeo runs");
    let err = String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("captured one frame to"), "{err}");
    // RenderDoc reports itself, and vgeo says what it falls back to under it.
    assert!(err.contains("note: running under RenderDoc"), "{err}");
    assert!(png.exists(), "no image written");
    check_capture(&rdc);
}

#[test]
fn capture_launched_by_renderdoc_names_every_pass() {
    let (png, rdc) = (tmp("capture_launched.png"), tmp("capture_launched.rdc"));
    let o = Command::new("renderdoccmd")
        .args(["capture", "-w", "-d", env!("CARGO_MANIFEST_DIR"), "-c"])
        .arg(tmp("capture_launched_template"))
        .arg(env!("CARGO_BIN_EXE_vgeo"))
        .args(render_args(&png, &rdc))
        .output()
        .expect("renderdoccmd runs (install renderdoc: bash .ci/setup.sh)");
    let out = String::from_utf8_lossy(&o.stdout).into_owned() + &String::from_utf8_lossy(&o.stderr);
    assert!(o.status.success(), "{out}");
    assert!(rdc.exists(), "no capture at {}:\n{out}", rdc.display());
    check_capture(&rdc);
}
