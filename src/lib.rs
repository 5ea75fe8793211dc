//! vgeo: a virtualized-geometry renderer (Nanite-style cluster DAG) on raw Vulkan.
//!
//! See `docs/architecture.md` for the map of the code.

pub mod camera;
pub mod gpu;
pub mod mesh;
pub mod shared;

/// SPIR-V of every shader, embedded at build time (see build.rs).
pub mod shaders {
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}
pub mod baseline;
pub mod render;
