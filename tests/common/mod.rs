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
