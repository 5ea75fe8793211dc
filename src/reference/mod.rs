//! CPU oracles for the GPU passes.
//!
//! - [`raster`]: a rasterizer with the same rules as Vulkan's (fixed-point snapping with
//!   [`SUBPIXEL_BITS`](crate::shared::SUBPIXEL_BITS) sub-pixel bits, top-left fill rule, near-plane
//!   clipping, reverse-Z depth test `GREATER`), so GPU readbacks can be compared pixel by pixel.

pub mod cut;
pub mod raster;

pub use raster::{
    Fragment, RasterTarget, SideClip, for_each_fragment, mesh_triangles, rasterize, rasterize_with,
};
