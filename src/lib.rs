//! vgeo: a virtualized-geometry renderer (Nanite-style cluster DAG) on raw Vulkan.
//!
//! - [`mesh`] imports meshes (glTF, OBJ, PLY, STL, OFF) into a validated, welded [`mesh::Mesh`].
//! - [`builder`] turns a mesh into a DAG of clusters (CPU only, deterministic); [`format`] stores it.
//! - [`gpu`] is the only module with raw Vulkan calls; [`baseline`] holds the classic paths.
//! - [`scene`] reads scene files and is the one loader of their meshes ([`scene::load`]); [`bench`]
//!   runs the benchmark scenes in every mode; [`imgerr`] measures image error against a
//!   (supersampled) reference; [`reference`] has CPU oracles used by tests; [`build_files`] builds
//!   `.vgeo` files (what `vgeo build` does).
//!
//! Modules import only from layers below them (docs/architecture.md, "Layers"; `tests/layers.rs`
//! fails on an import cycle); nothing in the library imports [`bench`](mod@bench) or the command
//! line.
//!
//! See `docs/architecture.md` for the map of the code.

pub mod baseline;
pub mod bench;
pub mod build_files;
pub mod builder;
pub mod camera;
pub mod format;
pub mod frame;
pub mod gpu;
pub mod imgerr;
pub mod lod_strip;
pub mod material;
pub mod mesh;
pub mod passes;
pub mod reference;
pub mod render;
pub mod scene;
pub mod scene_gpu;
pub mod shared;

/// RenderDoc's in-application API: load it before creating the Vulkan instance, then capture
/// exactly one vgeo frame with `start` / `end` (what `vgeo render --capture` does).
pub use gpu::RenderDoc;
/// What vgeo requires of a host's Vulkan instance and device (and uses when present); see
/// [`gpu::HostDevice`] and [`gpu::Context::from_host`] to run vgeo on the host's device.
pub use gpu::{HostDevice, requirements};

/// SPIR-V of every shader, embedded at build time (see build.rs).
pub mod shaders {
    /// One compiled shader: its GLSL file (relative to `shaders_glsl/`), the macro its variant
    /// defines (if any) and the SPIR-V embedded at build time.
    #[derive(Clone, Copy, Debug)]
    pub struct Variant {
        pub file: &'static str,
        pub define: Option<(&'static str, &'static str)>,
        pub spirv: &'static [u8],
    }
    include!(concat!(env!("OUT_DIR"), "/shaders.rs"));
}
