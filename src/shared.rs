//! The single source of constants and `#[repr(C)]` GPU structs shared by Rust and GLSL.
//!
//! build.rs reads every `pub const NAME: u32|i32|f32 = literal;` line between the two marker comments
//! below and passes it to shaderc as a macro, so GLSL sees the same values by the same names.
//! GPU structs are `Pod` and their sizes are asserted here; the GLSL side declares them in
//! `shaders_glsl/common/shared.glsl` with the same layout (scalar block layout).

use bytemuck::{Pod, Zeroable};

// BEGIN SHADER CONSTANTS
/// Sub-pixel precision of rasterization (fixed point), the same in HW, SW and the CPU reference.
pub const SUBPIXEL_BITS: u32 = 8;
/// Most triangles in one cluster.
pub const MAX_CLUSTER_TRIANGLES: u32 = 128;
/// Most vertices in one cluster (indices are stored as u8).
pub const MAX_CLUSTER_VERTICES: u32 = 255;
/// Visibility buffer low word: visible-cluster index << TRIANGLE_BITS | triangle.
pub const VISBUFFER_TRIANGLE_BITS: u32 = 7;
/// Bits of the visible-cluster index in the visibility buffer's low word.
pub const VISBUFFER_CLUSTER_BITS: u32 = 25;
/// Workgroup size of simple 2D image passes.
pub const TILE_WORKGROUP_SIZE: u32 = 8;
// END SHADER CONSTANTS

/// Per-frame uniforms of the classic (brute) path. All positions are camera-relative.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct FrameUniforms {
    /// Projection * view rotation (the camera sits at the origin of the camera-relative space).
    pub view_proj: [[f32; 4]; 4],
    /// Direction towards the light, world space, w unused.
    pub light_dir: [f32; 4],
    /// Width, height, 1/width, 1/height.
    pub viewport: [f32; 4],
}
const _: () = assert!(size_of::<FrameUniforms>() == 96);

/// One instance of the classic path: camera-relative model matrix and its normal matrix.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct InstanceGpu {
    pub model: [[f32; 4]; 4],
    /// Inverse-transpose of the model's 3x3 part, as three columns (w unused).
    pub normal_matrix: [[f32; 4]; 3],
    /// Base colour tint (rgb) and material index (w, as float bits are not needed: small ints).
    pub color: [f32; 4],
}
const _: () = assert!(size_of::<InstanceGpu>() == 128);

/// Vertex of the classic path: position and normal (uv kept for the material pass later).
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct VertexGpu {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
}
const _: () = assert!(size_of::<VertexGpu>() == 32);
