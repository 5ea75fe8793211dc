//! The `.vgeo` file: one built mesh.
//!
//! Layout (little-endian): a 32-byte header (`magic`, `version`, `section_count`, `checksum`,
//! `file_length`), a section table of `section_count` entries `{id: u32, reserved: u32, offset: u64,
//! length: u64}`, then the sections, each 16-byte aligned. `checksum` is FNV-1a 64 over the whole
//! file with the checksum field taken as zero. Sections: metadata (JSON), vertex positions (grid
//! codes, 2 x u32 per vertex), vertex normals (octahedral, u32 per vertex), vertex UVs (u32 per
//! vertex; empty when the mesh has no UVs), vertex materials (u16; empty with one material),
//! clusters ([`Cluster`], 96 B), vertex references (u32 words), packed local triangle indices
//! (bit streams, see [`Cluster::triangle_offset`]), groups ([`Group`], 64 B), BVH nodes
//! ([`BvhNode`], 64 B).
//! The GPU uploads the binary sections as they are.
//!
//! [`load`] checks everything before use: magic, version, lengths, the checksum, section bounds,
//! element sizes, and every index inside the data (so a loaded mesh can be indexed without checks);
//! allocations never exceed the input's size.

use std::path::PathBuf;

use bytemuck::Pod;
use serde::{Deserialize, Serialize};

use crate::builder::{BuildStats, BuiltMesh, BvhNode, Cluster, Group, PackedVertex, Quantization};
use crate::mesh::Material;

/// File magic.
pub const MAGIC: [u8; 8] = *b"VGEO\0\r\n\x1a";
/// Current format version.
pub const VERSION: u32 = 2;
const HEADER_LEN: usize = 32;
const ENTRY_LEN: usize = 24;
const MAX_SECTIONS: u32 = 64;

/// Section ids.
pub mod section {
    pub const META: u32 = 1;
    pub const POSITIONS: u32 = 2;
    pub const VERTEX_MATERIALS: u32 = 3;
    pub const CLUSTERS: u32 = 4;
    pub const VERTEX_REFS: u32 = 5;
    pub const TRIANGLES: u32 = 6;
    pub const GROUPS: u32 = 7;
    pub const BVH: u32 = 8;
    pub const NORMALS: u32 = 9;
    pub const UVS: u32 = 10;
}

/// Why a file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum FormatError {
    #[error("not a .vgeo file (bad magic)")]
    /// Not a .vgeo file.
    BadMagic,
    #[error("unsupported .vgeo version {0} (this build reads version {VERSION})")]
    /// A format version this build does not read.
    Version(u32),
    #[error("truncated .vgeo file: {0}")]
    /// The file ends inside a section.
    Truncated(String),
    #[error(
        "corrupted .vgeo file: checksum {found:#018x} does not match the stored {stored:#018x}"
    )]
    /// The checksum does not match the content.
    Checksum {
        /// The checksum the file stores.
        stored: u64,
        /// The checksum of its content.
        found: u64,
    },
    #[error("invalid .vgeo file: {0}")]
    /// A section's content breaks an invariant.
    Invalid(String),
}

/// FNV-1a 64-bit hash.
pub fn fnv1a64(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf29ce484222325;
    for &b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x100000001b3);
    }
    h
}

#[derive(Serialize, Deserialize)]
struct MetaMaterial {
    name: String,
    base_color: [f32; 4],
    metallic: f32,
    roughness: f32,
    base_color_texture: Option<String>,
    normal_texture: Option<String>,
    /// Absent in files written before it existed.
    #[serde(default)]
    metallic_roughness_texture: Option<String>,
}

#[derive(Serialize, Deserialize)]
struct Meta {
    name: String,
    /// Bit patterns of the f64 grid origin and step (JSON numbers do not round-trip every f64).
    origin_bits: [u64; 3],
    step_bits: u64,
    uv_min: [f32; 2],
    uv_max: [f32; 2],
    has_normals: bool,
    has_uvs: bool,
    root: u32,
    materials: Vec<MetaMaterial>,
    stats: BuildStats,
}

/// Serializes a built mesh.
pub fn save(m: &BuiltMesh) -> Vec<u8> {
    let q = &m.quantization;
    let meta = Meta {
        name: m.name.clone(),
        origin_bits: q.origin.map(f64::to_bits),
        step_bits: q.step.to_bits(),
        uv_min: q.uv_min,
        uv_max: q.uv_max,
        has_normals: m.has_normals,
        has_uvs: m.has_uvs,
        root: m.root,
        materials: m
            .materials
            .iter()
            .map(|x| MetaMaterial {
                name: x.name.clone(),
                base_color: x.base_color,
                metallic: x.metallic,
                roughness: x.roughness,
                base_color_texture: x
                    .base_color_texture
                    .as_ref()
                    .map(|p| p.to_string_lossy().into_owned()),
                normal_texture: x
                    .normal_texture
                    .as_ref()
                    .map(|p| p.to_string_lossy().into_owned()),
                metallic_roughness_texture: x
                    .metallic_roughness_texture
                    .as_ref()
                    .map(|p| p.to_string_lossy().into_owned()),
            })
            .collect(),
        stats: m.stats.clone(),
    };
    let meta_json = serde_json::to_vec(&meta).unwrap_or_default();
    let positions: Vec<[u32; 2]> = m.vertices.iter().map(|v| v.position).collect();
    let normals: Vec<u32> = m.vertices.iter().map(|v| v.normal).collect();
    let uvs: Vec<u32> = if m.has_uvs {
        m.vertices.iter().map(|v| v.uv).collect()
    } else {
        Vec::new()
    };
    let sections: Vec<(u32, &[u8])> = vec![
        (section::META, &meta_json),
        (section::POSITIONS, bytemuck::cast_slice(&positions)),
        (section::NORMALS, bytemuck::cast_slice(&normals)),
        (section::UVS, bytemuck::cast_slice(&uvs)),
        (
            section::VERTEX_MATERIALS,
            bytemuck::cast_slice(&m.vertex_materials),
        ),
        (section::CLUSTERS, bytemuck::cast_slice(&m.clusters)),
        (section::VERTEX_REFS, bytemuck::cast_slice(&m.vertex_refs)),
        (section::TRIANGLES, &m.triangles),
        (section::GROUPS, bytemuck::cast_slice(&m.groups)),
        (section::BVH, bytemuck::cast_slice(&m.bvh)),
    ];
    let align = |x: usize| x.div_ceil(16) * 16;
    let mut offset = align(HEADER_LEN + ENTRY_LEN * sections.len());
    let mut table = Vec::new();
    for (id, data) in &sections {
        table.push((*id, offset as u64, data.len() as u64));
        offset = align(offset + data.len());
    }
    let mut out = Vec::with_capacity(offset);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&(sections.len() as u32).to_le_bytes());
    out.extend_from_slice(&0u64.to_le_bytes()); // checksum, patched below
    out.extend_from_slice(&(offset as u64).to_le_bytes());
    for (id, off, len) in &table {
        out.extend_from_slice(&id.to_le_bytes());
        out.extend_from_slice(&0u32.to_le_bytes());
        out.extend_from_slice(&off.to_le_bytes());
        out.extend_from_slice(&len.to_le_bytes());
    }
    for ((_, data), (_, off, _)) in sections.iter().zip(&table) {
        out.resize(*off as usize, 0);
        out.extend_from_slice(data);
    }
    out.resize(offset, 0);
    let sum = fnv1a64(&out);
    out[16..24].copy_from_slice(&sum.to_le_bytes());
    out
}

fn u32_at(b: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(
        b.get(at..at.checked_add(4)?)?.try_into().ok()?,
    ))
}

fn u64_at(b: &[u8], at: usize) -> Option<u64> {
    Some(u64::from_le_bytes(
        b.get(at..at.checked_add(8)?)?.try_into().ok()?,
    ))
}

fn pod_vec<T: Pod>(data: &[u8], what: &str) -> Result<Vec<T>, FormatError> {
    let size = size_of::<T>();
    if !data.len().is_multiple_of(size) {
        return Err(FormatError::Invalid(format!(
            "section {what}: {} bytes is not a multiple of the {size}-byte element",
            data.len()
        )));
    }
    Ok(bytemuck::pod_collect_to_vec(data))
}

/// Parses and checks a `.vgeo` file.
pub fn load(bytes: &[u8]) -> Result<BuiltMesh, FormatError> {
    if bytes.len() < 8 || bytes[..8] != MAGIC {
        return Err(if bytes.len() < 8 && MAGIC.starts_with(bytes) {
            FormatError::Truncated(format!("{} bytes", bytes.len()))
        } else {
            FormatError::BadMagic
        });
    }
    let trunc = || FormatError::Truncated(format!("{} bytes, header incomplete", bytes.len()));
    let version = u32_at(bytes, 8).ok_or_else(trunc)?;
    if version != VERSION {
        return Err(FormatError::Version(version));
    }
    let count = u32_at(bytes, 12).ok_or_else(trunc)?;
    let stored = u64_at(bytes, 16).ok_or_else(trunc)?;
    let length = u64_at(bytes, 24).ok_or_else(trunc)?;
    if length != bytes.len() as u64 {
        return Err(if length > bytes.len() as u64 {
            FormatError::Truncated(format!("{} bytes of {length}", bytes.len()))
        } else {
            FormatError::Invalid(format!(
                "{} bytes but the header says {length}",
                bytes.len()
            ))
        });
    }
    if count > MAX_SECTIONS {
        return Err(FormatError::Invalid(format!(
            "{count} sections (at most {MAX_SECTIONS})"
        )));
    }
    let mut zeroed = bytes.to_vec();
    zeroed[16..24].fill(0);
    let found = fnv1a64(&zeroed);
    drop(zeroed);
    if found != stored {
        return Err(FormatError::Checksum { stored, found });
    }
    let table_end = HEADER_LEN + ENTRY_LEN * count as usize;
    if table_end > bytes.len() {
        return Err(FormatError::Invalid(format!(
            "section table of {count} entries exceeds the file"
        )));
    }
    let mut found_sections: Vec<(u32, &[u8])> = Vec::new();
    for i in 0..count as usize {
        let e = HEADER_LEN + ENTRY_LEN * i;
        let id = u32_at(bytes, e).ok_or_else(trunc)?;
        let off = u64_at(bytes, e + 8).ok_or_else(trunc)?;
        let len = u64_at(bytes, e + 16).ok_or_else(trunc)?;
        let end = off
            .checked_add(len)
            .filter(|&end| end <= bytes.len() as u64 && off >= table_end as u64);
        let Some(end) = end else {
            return Err(FormatError::Invalid(format!(
                "section {id} ({off}+{len}) lies outside the file"
            )));
        };
        if found_sections.iter().any(|(x, _)| *x == id) {
            return Err(FormatError::Invalid(format!("section {id} appears twice")));
        }
        found_sections.push((id, &bytes[off as usize..end as usize]));
    }
    let get = |id: u32, name: &str| {
        found_sections
            .iter()
            .find(|(x, _)| *x == id)
            .map(|(_, d)| *d)
            .ok_or_else(|| FormatError::Invalid(format!("section {name} (id {id}) is missing")))
    };
    let meta: Meta = serde_json::from_slice(get(section::META, "meta")?)
        .map_err(|e| FormatError::Invalid(format!("section meta: {e}")))?;
    let origin = meta.origin_bits.map(f64::from_bits);
    let step = f64::from_bits(meta.step_bits);
    if !(step.is_finite() && step > 0.0 && origin.iter().all(|x| x.is_finite())) {
        return Err(FormatError::Invalid(
            "section meta: quantization grid is not finite and positive".into(),
        ));
    }
    let positions = pod_vec::<[u32; 2]>(get(section::POSITIONS, "positions")?, "positions")?;
    let normals = pod_vec::<u32>(get(section::NORMALS, "normals")?, "normals")?;
    let uvs = pod_vec::<u32>(get(section::UVS, "uvs")?, "uvs")?;
    if normals.len() != positions.len()
        || uvs.len() != if meta.has_uvs { positions.len() } else { 0 }
    {
        return Err(FormatError::Invalid(format!(
            "{} positions, {} normals, {} UVs (has UVs: {})",
            positions.len(),
            normals.len(),
            uvs.len(),
            meta.has_uvs
        )));
    }
    let vertices = positions
        .iter()
        .enumerate()
        .map(|(i, &position)| PackedVertex {
            position,
            normal: normals[i],
            uv: uvs.get(i).copied().unwrap_or(0),
        })
        .collect();
    let m = BuiltMesh {
        name: meta.name,
        quantization: Quantization {
            origin,
            step,
            uv_min: meta.uv_min,
            uv_max: meta.uv_max,
        },
        has_normals: meta.has_normals,
        has_uvs: meta.has_uvs,
        materials: meta
            .materials
            .into_iter()
            .map(|x| Material {
                name: x.name,
                base_color: x.base_color,
                metallic: x.metallic,
                roughness: x.roughness,
                base_color_texture: x.base_color_texture.map(PathBuf::from),
                normal_texture: x.normal_texture.map(PathBuf::from),
                metallic_roughness_texture: x.metallic_roughness_texture.map(PathBuf::from),
            })
            .collect(),
        vertices,
        vertex_materials: pod_vec::<u16>(
            get(section::VERTEX_MATERIALS, "vertex materials")?,
            "vertex materials",
        )?,
        clusters: pod_vec::<Cluster>(get(section::CLUSTERS, "clusters")?, "clusters")?,
        vertex_refs: pod_vec::<u32>(
            get(section::VERTEX_REFS, "vertex references")?,
            "vertex references",
        )?,
        triangles: get(section::TRIANGLES, "triangles")?.to_vec(),
        groups: pod_vec::<Group>(get(section::GROUPS, "groups")?, "groups")?,
        bvh: pod_vec::<BvhNode>(get(section::BVH, "bvh")?, "bvh")?,
        root: meta.root,
        stats: meta.stats,
    };
    let errors = crate::builder::verify::structure_errors(&m);
    if let Some(first) = errors.first() {
        return Err(FormatError::Invalid(format!(
            "{first} ({} problems)",
            errors.len()
        )));
    }
    if let Some(v) = m
        .vertex_materials
        .iter()
        .find(|&&v| v as usize >= m.materials.len().max(1))
    {
        return Err(FormatError::Invalid(format!(
            "vertex material {v} out of range ({} materials)",
            m.materials.len()
        )));
    }
    Ok(m)
}

/// Bytes of `file` per input triangle of the mesh it holds.
pub fn bytes_per_input_triangle(file_len: usize, m: &BuiltMesh) -> f64 {
    file_len as f64 / m.stats.input_triangles.max(1) as f64
}
