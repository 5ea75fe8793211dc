//! What a user would use instead of vgeo: `brute` (every triangle, classic draws). The discrete-LOD
//! baseline (`lod`) comes with the benchmark work.

pub mod brute;
