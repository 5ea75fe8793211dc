//! Helpers shared by the integration tests.
#![allow(dead_code)]

use std::path::PathBuf;

use vgeo::gpu::{Context, ContextOptions};

/// The shared asset collection: `VGEO_SHARED_ASSETS`, else `../shared/assets` beside the crate (CI's
/// layout), else `/work/shared/assets`. Panics with a clear message when none exists: tests that
/// need it must not pass silently without it.
pub fn shared_assets() -> PathBuf {
    let mut candidates: Vec<PathBuf> = std::env::var("VGEO_SHARED_ASSETS")
        .ok()
        .map(PathBuf::from)
        .into_iter()
        .collect();
    candidates.push(PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/assets"
    )));
    candidates.push(PathBuf::from("/work/shared/assets"));
    candidates
        .iter()
        .find(|p| p.is_dir())
        .cloned()
        .unwrap_or_else(|| {
            panic!("shared assets folder not found (tried {candidates:?}); set VGEO_SHARED_ASSETS")
        })
}

/// The repository's own assets folder.
pub fn assets() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"))
}

/// A Vulkan context with the Khronos validation layer on (lavapipe in CI). Fails the test when no
/// device or no validation layer is available.
pub fn gpu() -> Context {
    let opts = ContextOptions {
        validation: true,
        ..ContextOptions::from_env()
    };
    Context::new(&opts).unwrap_or_else(|e| panic!("no Vulkan device for GPU tests: {e}"))
}

/// Fails the test if the validation layer reported any error.
pub fn assert_no_validation_errors(ctx: &Context) {
    let errors = ctx.validation_errors();
    assert!(
        errors.is_empty(),
        "{} Vulkan validation error(s):\n{}",
        errors.len(),
        errors.join("\n")
    );
}

/// A flat square in the xy plane, `n` x `n` quads, centred on the origin, side 2.
pub fn wall_mesh(n: u32) -> vgeo::mesh::Mesh {
    let mut m = vgeo::mesh::Mesh {
        name: "wall".into(),
        materials: vec![vgeo::mesh::Material::default()],
        ..Default::default()
    };
    for y in 0..=n {
        for x in 0..=n {
            m.positions.push([
                x as f32 / n as f32 * 2.0 - 1.0,
                y as f32 / n as f32 * 2.0 - 1.0,
                0.0,
            ]);
            m.normals.push([0.0, 0.0, 1.0]);
            m.uvs.push([0.0, 0.0]);
        }
    }
    for y in 0..n {
        for x in 0..n {
            let i = y * (n + 1) + x;
            m.indices
                .extend([i, i + 1, i + n + 1, i + 1, i + n + 2, i + n + 1]);
            m.material_ids.extend([0, 0]);
        }
    }
    m
}
