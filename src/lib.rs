//! vgeo: a virtualized-geometry renderer (Nanite-style cluster DAG) on raw Vulkan.
//!
//! See `docs/architecture.md` for the map of the code.

pub mod camera;
pub mod mesh;
pub mod reference;
pub mod scene;
pub mod shared;
