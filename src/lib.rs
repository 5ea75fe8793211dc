//! vgeo: a virtualized-geometry renderer (Nanite-style cluster DAG) on raw Vulkan.
//!
//! An offline builder turns any triangle mesh into a DAG of 128-triangle clusters with monotonic
//! error; each frame, the GPU picks per cluster the coarsest detail whose error stays under a
//! pixel, culls what is hidden, and rasterizes the rest into a 64-bit visibility buffer, then
//! shades it. The items at this crate's root are its API; the modules behind them are internals
//! (hidden from these docs, reachable for tests and tools, not stable).
//!
//! # Building and loading meshes
//!
//! [`load_mesh`] imports glTF/GLB, OBJ, PLY, STL and OFF ([`ImportOptions`]: crease-angle
//! normals, node splitting); [`build`] makes the cluster DAG ([`BuildOptions`], deterministic, on
//! the CPU); [`save_vgeo`] / [`load_vgeo`] store it (`vgeo build` on the command line).
//!
//! # Embedding in an engine
//!
//! vgeo runs on the host's Vulkan device and records into the host's command buffers;
//! `examples/embed.rs` is a complete host. The steps:
//!
//! 1. Create the device with what [`requirements()`] lists, and hand it to vgeo:
//!    [`Context::from_host`] with a [`HostDevice`] (a device lacking something is refused, naming
//!    it). [`Context::new`] makes vgeo's own headless device the same way.
//! 2. Upload the scene: [`Renderer::new`] with the built meshes and [`Placement`]s. It changes at
//!    run time through `renderer.scene` ([`GpuScene`]): `add_mesh`, `add_instance`
//!    ([`InstanceDesc`]), `set_transform`, `set_color`, `remove_instance`, `remove_mesh`, with
//!    stable [`MeshHandle`]s and [`InstanceHandle`]s; buffers grow as needed
//!    ([`GpuScene::memory`]).
//! 3. One [`View`] per camera and target size ([`Renderer::create_view`]), each with its own
//!    occlusion history and `frames_in_flight` read-back slots.
//! 4. Every frame: [`Renderer::update_scene`] (the instances changed since the last frame, copied
//!    in O(changed)), then [`Renderer::record`] per view with a [`ViewFrame`]: the camera, the
//!    [`FrameSettings`] (pixel error threshold), the light and the [`HostTargets`]: the host's
//!    reverse-Z D32 depth ([`HOST_DEPTH_FORMAT`], shared both ways, so the host's draws and vgeo's
//!    geometry occlude each other), and lit colour ([`HOST_COLOR_FORMAT`]) or the GBuffer
//!    ([`HOST_GBUFFER_FORMATS`]) for the host's own lighting, or neither. Recording submits,
//!    waits and allocates nothing; layouts and stages at entry and exit are in
//!    docs/architecture.md, "Embedding".
//! 5. [`View::try_stats`] a few frames later gives the frame's counters and pass times
//!    ([`FrameStats`]) without waiting.
//!
//! ```no_run
//! # fn frame(renderer: &mut vgeo::Renderer, view: &mut vgeo::View, cb: vgeo::vk::CommandBuffer,
//! #          i: u64, depth: vgeo::HostImage, color: vgeo::HostImage,
//! #          moved: vgeo::InstanceHandle) -> Result<(), Box<dyn std::error::Error>> {
//! use glam::{DMat4, DVec3, Vec3};
//! renderer.scene.set_transform(moved, &DMat4::from_translation(DVec3::new(0.0, i as f64 * 0.01, 0.0)))?;
//! let camera = vgeo::Camera::look_at(DVec3::new(0.0, 2.0, 8.0), DVec3::ZERO, Vec3::Y, 0.8, 0.05);
//! let frame = vgeo::ViewFrame {
//!     frame: i,
//!     camera: &camera,
//!     settings: vgeo::FrameSettings::default(),
//!     light: vgeo::Light::default(),
//!     shade: vgeo::ShadeMode::Lit,
//!     targets: vgeo::HostTargets { depth: Some(depth), color: Some(color), gbuffer: None },
//! };
//! // SAFETY: `cb` is the host's command buffer, recording, outside a render pass.
//! unsafe {
//!     renderer.update_scene(cb, &mut [&mut *view])?;
//!     renderer.record(cb, view, &frame)?;
//! }
//! // ... the host ends and submits `cb`; two frames later:
//! if let Some(stats) = view.try_stats(i.saturating_sub(2))? {
//!     println!("{} triangles", stats.triangles());
//! }
//! # Ok(()) }
//! ```
//!
//! # Rendering without a host
//!
//! [`Renderer::render`] renders, submits, waits and reads back one frame ([`VgeoFrame`]) in a
//! [`ViewMode`]: the lit image or a debug view (clusters, LOD level, triangles, ...). This is what
//! `vgeo render` does; [`RenderDoc`] captures such a frame (`vgeo render --capture`).
//! [`LoadedScene`] reads a scene file (`.toml`) or a mesh, with its placements and light; the
//! baselines vgeo is measured against take the same meshes and placements and give the same
//! [`Frame`]: [`BruteRenderer`] (every triangle) and [`LodRenderer`] (discrete levels of detail).
//! [`tools`] has the command line's workflows (build, verify, info, LOD strip) as functions:
//! the `vgeo` binary and the examples use nothing but this crate root and the bench
//! (`tests/layers.rs` checks it).
//!
//! # Internals
//!
//! `mesh` imports, `builder` builds (CPU only), `format` stores, `gpu` is the only module with
//! raw Vulkan calls, `passes` are the frame's passes, `frame` records frames, `scene_gpu` holds
//! the scene on the GPU, `scene` reads scene files, `baseline` has the brute and lod renderers,
//! `bench` the benchmark, `imgerr` image error, `reference` CPU oracles for tests. Modules import
//! only from layers below them (docs/architecture.md, "Layers"; `tests/layers.rs` fails on an
//! import cycle); nothing in the library imports `bench` or the command line.

#![warn(missing_docs)]

#[doc(hidden)]
pub mod baseline;
#[doc(hidden)]
pub mod bench;
#[doc(hidden)]
pub mod build_files;
#[doc(hidden)]
pub mod builder;
#[doc(hidden)]
pub mod camera;
#[doc(hidden)]
pub mod format;
#[doc(hidden)]
pub mod frame;
#[doc(hidden)]
pub mod gpu;
mod hash;
#[doc(hidden)]
pub mod imgerr;
#[doc(hidden)]
pub mod lod_strip;
#[doc(hidden)]
pub mod material;
#[doc(hidden)]
pub mod mesh;
#[doc(hidden)]
pub mod passes;
#[doc(hidden)]
pub mod reference;
#[doc(hidden)]
pub mod render;
#[doc(hidden)]
pub mod scene;
#[doc(hidden)]
pub mod scene_gpu;
#[doc(hidden)]
pub mod shared;
#[doc(hidden)]
pub mod streaming;

/// ash's Vulkan types, as vgeo uses them (the host's handles are these).
pub use ash::vk;

pub use baseline::brute::Brute as BruteRenderer;
pub use baseline::lod::{Lod as LodRenderer, LodOptions, LodSelection, LodStats};
pub use build_files::load_input as load_meshes;
pub use builder::{BuildOptions, BuiltMesh, Partitioner, VerifyOptions, build};
pub use camera::Camera;
pub use format::{load as load_vgeo, save as save_vgeo};
pub use frame::{
    DEFAULT_FRAMES_IN_FLIGHT, FrameStats, HOST_COLOR_FORMAT, HOST_DEPTH_FORMAT,
    HOST_GBUFFER_FORMATS, HostTargets, VgeoFrame, VgeoRenderer as Renderer, View, ViewFrame,
};
pub use gpu::{
    Context, ContextOptions, DeviceFeatures, GpuError, HostDevice, HostImage, RenderDoc,
    device_extensions_for_vgeo, requirements,
};
pub use material::ShadeMode;
pub use mesh::{ImportOptions, Mesh, load as load_mesh, merge as merge_meshes};
pub use passes::debug_view::ViewMode;
pub use passes::emit_gbuffer::EmitPath;
pub use passes::raster_hw::HwPath;
pub use passes::view::FrameSettings;
pub use render::{BACKGROUND, Frame, Light, Placement};
pub use scene::generated::generated_mesh;
pub use scene::load::LoadedScene;
pub use scene_gpu::{GpuScene, InstanceDesc, InstanceHandle, MeshHandle, SceneMemory};
pub use streaming::{
    CutResidency, GeometryBudget, PageSource, StreamOptions, StreamStats, StreamedScene, Streamer,
};

/// The command line's workflows as functions, for tools built on vgeo: `vgeo build` (plan,
/// write, describe), `vgeo verify`, `vgeo info` and `vgeo render --lod-strip`. The `vgeo` binary
/// is made of these, the crate root's items and the bench (`vgeo bench`, an application beside
/// the binary: nothing in the library, this root included, imports it).
pub mod tools {
    pub use crate::build_files::{
        BuildPlan, BuildRequest, describe, info_vgeo, plan_build, read_vgeo, verify_file,
        write_vgeo,
    };
    pub use crate::builder::{VerifyReport, mesh_to_obj};
    pub use crate::format::bytes_per_input_triangle;
    pub use crate::lod_strip::{
        LodPanel, LodStrip, LodStripError, LodStripOptions, render_file as render_lod_strip,
    };
}

/// SPIR-V of every shader, embedded at build time (see build.rs).
#[doc(hidden)]
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
