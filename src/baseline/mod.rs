//! What a user would use instead of vgeo: `brute` (every triangle, classic draws) and `lod`
//! (discrete levels of detail per mesh, one per instance chosen by projected error).

pub mod brute;
pub mod lod;
pub mod lod_cull;
