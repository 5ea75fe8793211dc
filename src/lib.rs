//! vgeo: a virtualized-geometry renderer (Nanite-style cluster DAG) on raw Vulkan.
//!
//! See `docs/architecture.md` for the map of the code.

pub mod builder;
pub mod camera;
pub mod cmd_build;
pub mod format;
pub mod mesh;
pub mod shared;
