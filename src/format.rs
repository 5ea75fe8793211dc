//! The `.vgeo` file: one built mesh, its geometry in pages that can be read one at a time.
//!
//! Layout (little-endian): a 32-byte header (`magic`, `version`, `section_count`, `checksum`,
//! `file_length`), a section table of `section_count` entries `{id: u32, reserved: u32, offset: u64,
//! length: u64}`, then the sections, each 16-byte aligned, the page data last. Sections: metadata
//! (JSON), clusters ([`Cluster`], 96 B), groups ([`Group`], 64 B), BVH nodes ([`BvhNode`], 64 B),
//! the page table (one [`PageEntry`] of 64 B per page: the builder's [`Page`], where its bytes lie
//! in the file, their length and FNV-1a 64 checksum), optionally the groups' coverage parts (one
//! f32 per group, `BuiltMesh::group_coverage`; a file without them counts every error whole, its
//! BVH nodes' `max_parent_coverage` taken as their `max_parent_error`) and the page data (every
//! page's bytes, `builder::page::encode_page`, each 16-byte aligned, in page order).
//!
//! `checksum` is FNV-1a 64 over the file up to the page data, with the checksum field taken as
//! zero: opening a file ([`VgeoFile::open`]) reads and checks only that head; each page is checked
//! by its own checksum when it is read ([`VgeoFile::read_page`]). Older files are refused with a
//! hint to rebuild: version 2 (vertex streams in whole-mesh sections) predates pages, version 3
//! stored pages as plain streams (shared vertices with references) rather than encoded clusters,
//! version 4's cluster headers lacked the cull words (bounds, counts, level, groups) that let the
//! GPU read a cluster from its page alone, version 5's clusters lacked the size code of their
//! triangles (`builder::size`, bits 24-31 of the counts and of the cull words' info word, where
//! the level now has 8 bits) by which the frame splits them between the rasterizers, and
//! version 6 stored a cluster's triangles as plain packed indices rather than the max-delta code
//! (`builder::tricode`) with its canonical triangle order, and version 7 stored a cluster's
//! bounds in its cull words as six floats rather than its box on the mesh's grid (16 bytes more
//! per cluster), and version 8 gave both components of a cluster's normals one bit width (the
//! wider one's) where version 9 gives each its own.
//!
//! [`load`] and [`VgeoFile`] check everything before use: magic, version, lengths, checksums,
//! section bounds, element sizes, and every index inside the data (so a loaded mesh can be indexed
//! without checks, and a page read can go to the GPU as it is); allocations never exceed the
//! input's size.

use std::os::unix::fs::FileExt;
use std::path::{Path, PathBuf};

use bytemuck::{Pod, Zeroable};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};

use crate::builder::page::{Page, clusters_by_page, decode_page, encode_page};
use crate::builder::{BuildStats, BuiltMesh, BvhNode, Cluster, Group, Quantization};
use crate::mesh::Material;

/// File magic.
pub const MAGIC: [u8; 8] = *b"VGEO\0\r\n\x1a";
/// Current format version.
pub const VERSION: u32 = 9;
const HEADER_LEN: usize = 32;
const ENTRY_LEN: usize = 24;
const MAX_SECTIONS: u32 = 64;

/// Section ids (2, 3, 5, 6, 9 and 10 were version 2's vertex streams).
pub mod section {
    pub const META: u32 = 1;
    pub const CLUSTERS: u32 = 4;
    pub const GROUPS: u32 = 7;
    pub const BVH: u32 = 8;
    pub const PAGE_TABLE: u32 = 11;
    pub const PAGE_DATA: u32 = 12;
    /// Optional: per group, the coverage part of its error (`BuiltMesh::group_coverage`, f32).
    pub const GROUP_COVERAGE: u32 = 13;
}

/// One page of the page table: the builder's [`Page`] and where its bytes lie in the file.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct PageEntry {
    pub page: Page,
    /// File offset and length of the page's bytes.
    pub offset: u64,
    pub length: u64,
    /// FNV-1a 64 of the page's bytes.
    pub checksum: u64,
    pub _reserved: u64,
}
const _: () = assert!(size_of::<PageEntry>() == 64);

/// Why a file could not be loaded.
#[derive(Debug, thiserror::Error)]
pub enum FormatError {
    #[error("not a .vgeo file (bad magic)")]
    /// Not a .vgeo file.
    BadMagic,
    #[error(
        "unsupported .vgeo version {0} (this build reads version {VERSION}; files of version 8 and \
         older code their clusters' vertices in another layout (version 7 and older also their \
         boxes, version 6 and older their triangles, version 5 and older lack the clusters' \
         triangle size that splits the rasterizers): rebuild them with `vgeo build`)"
    )]
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
    #[error(
        "corrupted .vgeo page {page}: checksum {found:#018x} does not match the stored {stored:#018x}"
    )]
    /// A page's bytes do not match its checksum.
    PageChecksum {
        /// The page.
        page: u32,
        /// The checksum the page table stores.
        stored: u64,
        /// The checksum of the page's bytes.
        found: u64,
    },
    #[error("cannot read .vgeo file: {0}")]
    /// The file could not be read.
    Io(String),
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
    position_bits: u32,
    normal_bits: u32,
    has_normals: bool,
    has_uvs: bool,
    root: u32,
    resident_pages: u32,
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
        position_bits: q.position_bits,
        normal_bits: q.normal_bits,
        has_normals: m.has_normals,
        has_uvs: m.has_uvs,
        root: m.root,
        resident_pages: m.resident_pages,
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
    let align = |x: usize| x.div_ceil(16) * 16;
    // The page data, each page 16-aligned (offsets relative to the section for now).
    let mut data = Vec::new();
    let mut entries: Vec<PageEntry> = Vec::with_capacity(m.pages.len());
    // Pages are encoded and checksummed in parallel (each on its own), then laid out in order.
    let by_page = clusters_by_page(m);
    let encoded: Vec<(Vec<u8>, u64)> = by_page
        .par_iter()
        .map(|clusters| {
            let bytes = encode_page(m, clusters);
            let checksum = fnv1a64(&bytes);
            (bytes, checksum)
        })
        .collect();
    for (p, (bytes, checksum)) in m.pages.iter().zip(encoded) {
        data.resize(align(data.len()), 0);
        entries.push(PageEntry {
            page: *p,
            offset: data.len() as u64,
            length: bytes.len() as u64,
            checksum,
            _reserved: 0,
        });
        data.extend_from_slice(&bytes);
    }
    // The head's sections (the group coverage only where it is known) and their lengths.
    let coverage = !m.group_coverage.is_empty();
    let mut head_sections: Vec<(u32, usize)> = vec![
        (section::META, meta_json.len()),
        (
            section::CLUSTERS,
            std::mem::size_of_val(m.clusters.as_slice()),
        ),
        (section::GROUPS, std::mem::size_of_val(m.groups.as_slice())),
        (section::BVH, std::mem::size_of_val(m.bvh.as_slice())),
        (
            section::PAGE_TABLE,
            std::mem::size_of_val(entries.as_slice()),
        ),
    ];
    if coverage {
        head_sections.push((
            section::GROUP_COVERAGE,
            std::mem::size_of_val(m.group_coverage.as_slice()),
        ));
    }
    let count = head_sections.len() + 1;
    let mut offset = align(HEADER_LEN + ENTRY_LEN * count);
    let mut table = Vec::new();
    for (id, len) in head_sections {
        table.push((id, offset as u64, len as u64));
        offset = align(offset + len);
    }
    let data_off = offset;
    for e in &mut entries {
        e.offset += data_off as u64;
    }
    table.push((section::PAGE_DATA, data_off as u64, data.len() as u64));
    let file_len = data_off + data.len();
    let mut out = Vec::with_capacity(file_len);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&VERSION.to_le_bytes());
    out.extend_from_slice(&(count as u32).to_le_bytes());
    out.extend_from_slice(&0u64.to_le_bytes()); // checksum, patched below
    out.extend_from_slice(&(file_len as u64).to_le_bytes());
    for (id, off, len) in &table {
        out.extend_from_slice(&id.to_le_bytes());
        out.extend_from_slice(&0u32.to_le_bytes());
        out.extend_from_slice(&off.to_le_bytes());
        out.extend_from_slice(&len.to_le_bytes());
    }
    let mut contents: Vec<&[u8]> = vec![
        &meta_json,
        bytemuck::cast_slice(&m.clusters),
        bytemuck::cast_slice(&m.groups),
        bytemuck::cast_slice(&m.bvh),
        bytemuck::cast_slice(&entries),
    ];
    if coverage {
        contents.push(bytemuck::cast_slice(&m.group_coverage));
    }
    for (c, (_, off, _)) in contents.iter().zip(&table) {
        out.resize(*off as usize, 0);
        out.extend_from_slice(c);
    }
    out.resize(data_off, 0);
    let sum = fnv1a64(&out);
    out[16..24].copy_from_slice(&sum.to_le_bytes());
    out.extend_from_slice(&data);
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

/// What the fixed part of a file says: its length and where the page data lies.
struct Header {
    length: u64,
    stored: u64,
    /// (id, offset, length) per section.
    sections: Vec<(u32, u64, u64)>,
    /// Offset and length of the page data section.
    data: (u64, u64),
}

/// Parses the header and section table from the first bytes of a file (`head` may be shorter than
/// the file: it must hold the table).
fn parse_header(head: &[u8]) -> Result<Header, FormatError> {
    if head.len() < 8 || head[..8] != MAGIC {
        return Err(if head.len() < 8 && MAGIC.starts_with(head) {
            FormatError::Truncated(format!("{} bytes", head.len()))
        } else {
            FormatError::BadMagic
        });
    }
    let trunc = || FormatError::Truncated(format!("{} bytes, header incomplete", head.len()));
    let version = u32_at(head, 8).ok_or_else(trunc)?;
    if version != VERSION {
        return Err(FormatError::Version(version));
    }
    let count = u32_at(head, 12).ok_or_else(trunc)?;
    let stored = u64_at(head, 16).ok_or_else(trunc)?;
    let length = u64_at(head, 24).ok_or_else(trunc)?;
    if count > MAX_SECTIONS {
        return Err(FormatError::Invalid(format!(
            "{count} sections (at most {MAX_SECTIONS})"
        )));
    }
    let table_end = (HEADER_LEN + ENTRY_LEN * count as usize) as u64;
    if table_end > length {
        return Err(FormatError::Invalid(format!(
            "section table of {count} entries exceeds the file"
        )));
    }
    let mut sections: Vec<(u32, u64, u64)> = Vec::new();
    for i in 0..count as usize {
        let e = HEADER_LEN + ENTRY_LEN * i;
        let id = u32_at(head, e).ok_or_else(trunc)?;
        let off = u64_at(head, e + 8).ok_or_else(trunc)?;
        let len = u64_at(head, e + 16).ok_or_else(trunc)?;
        if off
            .checked_add(len)
            .is_none_or(|end| end > length || off < table_end)
        {
            return Err(FormatError::Invalid(format!(
                "section {id} ({off}+{len}) lies outside the file"
            )));
        }
        if sections.iter().any(|(x, _, _)| *x == id) {
            return Err(FormatError::Invalid(format!("section {id} appears twice")));
        }
        sections.push((id, off, len));
    }
    let (_, doff, dlen) = *sections
        .iter()
        .find(|(id, _, _)| *id == section::PAGE_DATA)
        .ok_or_else(|| FormatError::Invalid("section page data (id 12) is missing".into()))?;
    if doff + dlen != length {
        return Err(FormatError::Invalid(
            "the page data is not the file's last section".into(),
        ));
    }
    if let Some((id, ..)) = sections
        .iter()
        .find(|(id, off, len)| *id != section::PAGE_DATA && off + len > doff)
    {
        return Err(FormatError::Invalid(format!(
            "section {id} overlaps the page data"
        )));
    }
    Ok(Header {
        length,
        stored,
        sections,
        data: (doff, dlen),
    })
}

/// The mesh without its pages' content (the streams empty), and the page table, from a file's
/// head (`head`: its bytes up to the page data), checked: the head checksum, every section, the
/// page table against the page data's extent, and the structure without the pages' content.
fn parse_head(h: &Header, head: &[u8]) -> Result<(BuiltMesh, Vec<PageEntry>), FormatError> {
    let mut zeroed = head.to_vec();
    zeroed[16..24].fill(0);
    let found = fnv1a64(&zeroed);
    drop(zeroed);
    if found != h.stored {
        return Err(FormatError::Checksum {
            stored: h.stored,
            found,
        });
    }
    let get = |id: u32, name: &str| -> Result<&[u8], FormatError> {
        let (_, off, len) = h
            .sections
            .iter()
            .find(|(x, _, _)| *x == id)
            .ok_or_else(|| FormatError::Invalid(format!("section {name} (id {id}) is missing")))?;
        head.get(*off as usize..(*off + *len) as usize)
            .ok_or_else(|| FormatError::Invalid(format!("section {name} lies outside the head")))
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
    use crate::builder::quantize::{NORMAL_BITS, POSITION_BITS};
    if !(1..=POSITION_BITS).contains(&meta.position_bits)
        || !(2..=NORMAL_BITS).contains(&meta.normal_bits)
    {
        return Err(FormatError::Invalid(format!(
            "section meta: {} position bits / {} normal bits (at most {POSITION_BITS} / {NORMAL_BITS})",
            meta.position_bits, meta.normal_bits
        )));
    }
    let entries = pod_vec::<PageEntry>(get(section::PAGE_TABLE, "page table")?, "page table")?;
    // Optional (a file from before it has none).
    let has_coverage = h
        .sections
        .iter()
        .any(|(x, _, _)| *x == section::GROUP_COVERAGE);
    let m = BuiltMesh {
        name: meta.name,
        quantization: Quantization {
            origin,
            step,
            uv_min: meta.uv_min,
            uv_max: meta.uv_max,
            position_bits: meta.position_bits,
            normal_bits: meta.normal_bits,
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
        vertices: Vec::new(),
        vertex_materials: Vec::new(),
        clusters: pod_vec::<Cluster>(get(section::CLUSTERS, "clusters")?, "clusters")?,
        vertex_refs: Vec::new(),
        triangles: Vec::new(),
        groups: pod_vec::<Group>(get(section::GROUPS, "groups")?, "groups")?,
        group_coverage: match has_coverage {
            true => pod_vec::<f32>(
                get(section::GROUP_COVERAGE, "group coverage")?,
                "group coverage",
            )?,
            false => Vec::new(),
        },
        bvh: pod_vec::<BvhNode>(get(section::BVH, "bvh")?, "bvh")?,
        root: meta.root,
        pages: entries.iter().map(|e| e.page).collect(),
        resident_pages: meta.resident_pages,
        stats: meta.stats,
    };
    let (doff, dlen) = h.data;
    for (i, e) in entries.iter().enumerate() {
        let want = e.page.bytes as u64;
        if e.length != want
            || e.offset < doff
            || e.offset
                .checked_add(e.length)
                .is_none_or(|end| end > doff + dlen)
        {
            return Err(FormatError::Invalid(format!(
                "page {i}: {}+{} bytes, its page record says {want} inside the page data ({doff}+{dlen})",
                e.offset, e.length
            )));
        }
    }
    let mut m = m;
    if has_coverage && m.group_coverage.len() != m.groups.len() {
        return Err(FormatError::Invalid(format!(
            "section group coverage: {} values for {} groups",
            m.group_coverage.len(),
            m.groups.len()
        )));
    }
    if m.group_coverage.is_empty() {
        // A file from before the coverage part: every error counts whole, the BVH's bound too.
        for n in &mut m.bvh {
            n.max_parent_coverage = n.max_parent_error;
        }
    } else {
        // The BVH's bound is the groups' (checked below), not trusted from the file: the GPU
        // prunes small instances' subtrees by it.
        crate::builder::bvh::set_max_parent_coverage(&mut m.bvh, &m.group_coverage);
    }
    let errors = crate::builder::verify::head_errors(&m);
    if let Some(first) = errors.first() {
        return Err(FormatError::Invalid(format!(
            "{first} ({} problems)",
            errors.len()
        )));
    }
    Ok((m, entries))
}

/// Checks page `i`'s bytes (its checksum, then every cluster stored in it decoded: see
/// [`decode_page`]; its logical streams must match the page's and clusters' records) and decodes
/// them.
fn check_page(
    m: &BuiltMesh,
    e: &PageEntry,
    i: u32,
    clusters: &[u32],
    bytes: &[u8],
) -> Result<crate::builder::page::PageStreams, FormatError> {
    let found = fnv1a64(bytes);
    if found != e.checksum {
        return Err(FormatError::PageChecksum {
            page: i,
            stored: e.checksum,
            found,
        });
    }
    let p = &e.page;
    let bad = |what: String| FormatError::Invalid(format!("page {i}: {what}"));
    let cs: Vec<&Cluster> = clusters.iter().map(|&c| &m.clusters[c as usize]).collect();
    let st = decode_page(
        bytes,
        &cs,
        &m.quantization,
        m.has_uvs,
        m.has_material_stream(),
    )
    .map_err(bad)?;
    for (&ci, &(r, t)) in clusters.iter().zip(&st.cluster_starts) {
        let c = &m.clusters[ci as usize];
        if c.vertex_ref_offset as u64 != p.ref_first as u64 + r as u64
            || c.triangle_offset as u64 != p.triangle_first as u64 + t as u64
        {
            return Err(bad(format!(
                "cluster {ci}: references at {} and triangles at {}, its page decodes them at {} and {}",
                c.vertex_ref_offset,
                c.triangle_offset,
                p.ref_first as u64 + r as u64,
                p.triangle_first as u64 + t as u64
            )));
        }
    }
    if (st.vertices.len(), st.refs.len(), st.triangles.len())
        != (
            p.vertex_count as usize,
            p.ref_words as usize,
            p.triangle_bytes as usize,
        )
    {
        return Err(bad(format!(
            "decodes to {} vertices, {} reference words and {} triangle bytes, its record says {}, {} and {}",
            st.vertices.len(),
            st.refs.len(),
            st.triangles.len(),
            p.vertex_count,
            p.ref_words,
            p.triangle_bytes
        )));
    }
    if let Some(v) = st
        .materials
        .iter()
        .find(|&&v| v as usize >= m.materials.len().max(1))
    {
        return Err(bad(format!(
            "vertex material {v} out of range ({} materials)",
            m.materials.len()
        )));
    }
    Ok(st)
}

/// Makes `bytes`'s stored length and checksums (the head's and every page's the page table can
/// locate) match its content, where its header can be parsed: what a fuzzer applies to a mutated
/// file so that the checks behind the checksums are reached. Not for use on real files.
pub fn fix_checksums(bytes: &mut [u8]) {
    if bytes.len() < HEADER_LEN || !bytes.starts_with(&MAGIC) {
        return;
    }
    let len = bytes.len() as u64;
    bytes[24..32].copy_from_slice(&len.to_le_bytes());
    let Ok(h) = parse_header(bytes) else { return };
    if let Some(&(_, off, n)) = h
        .sections
        .iter()
        .find(|(id, _, _)| *id == section::PAGE_TABLE)
    {
        let esz = size_of::<PageEntry>() as u64;
        for k in 0..n / esz {
            let at = (off + k * esz) as usize;
            let (Some(o), Some(l)) = (u64_at(bytes, at + 32), u64_at(bytes, at + 40)) else {
                continue;
            };
            let Some(end) = o.checked_add(l).filter(|&e| e <= len) else {
                continue;
            };
            let sum = fnv1a64(&bytes[o as usize..end as usize]);
            if at + 56 <= h.data.0 as usize {
                bytes[at + 48..at + 56].copy_from_slice(&sum.to_le_bytes());
            }
        }
    }
    let head = h.data.0 as usize;
    bytes[16..24].fill(0);
    let sum = fnv1a64(&bytes[..head]);
    bytes[16..24].copy_from_slice(&sum.to_le_bytes());
}

/// Parses and checks a whole `.vgeo` file.
pub fn load(bytes: &[u8]) -> Result<BuiltMesh, FormatError> {
    let h = parse_header(bytes)?;
    if h.length != bytes.len() as u64 {
        return Err(if h.length > bytes.len() as u64 {
            FormatError::Truncated(format!("{} bytes of {}", bytes.len(), h.length))
        } else {
            FormatError::Invalid(format!(
                "{} bytes but the header says {}",
                bytes.len(),
                h.length
            ))
        });
    }
    let (mut m, entries) = parse_head(&h, &bytes[..h.data.0 as usize])?;
    let by = clusters_by_page(&m);
    for (i, e) in entries.iter().enumerate() {
        let page = &bytes[e.offset as usize..(e.offset + e.length) as usize];
        let st = check_page(&m, e, i as u32, &by[i], page)?;
        m.vertices.extend(st.vertices);
        m.vertex_materials.extend(st.materials);
        m.vertex_refs.extend(st.refs);
        m.triangles.extend(st.triangles);
    }
    let errors = crate::builder::verify::structure_errors(&m);
    if let Some(first) = errors.first() {
        return Err(FormatError::Invalid(format!(
            "{first} ({} problems)",
            errors.len()
        )));
    }
    Ok(m)
}

/// A `.vgeo` file opened for reading page by page: [`VgeoFile::open`] reads and checks its head
/// (metadata, clusters, groups, BVH, page table; no page content), [`VgeoFile::read_page`] one
/// page, checked, ready for the GPU.
pub struct VgeoFile {
    file: std::fs::File,
    path: PathBuf,
    head: BuiltMesh,
    entries: Vec<PageEntry>,
    by_page: Vec<Vec<u32>>,
}

impl VgeoFile {
    /// Opens `path` and checks its head.
    pub fn open(path: &Path) -> Result<Self, FormatError> {
        let io = |e: std::io::Error| FormatError::Io(format!("{}: {e}", path.display()));
        let file = std::fs::File::open(path).map_err(io)?;
        let len = file.metadata().map_err(io)?.len();
        let read = |off: u64, n: u64| -> Result<Vec<u8>, FormatError> {
            let n = n.min(len.saturating_sub(off));
            let mut buf = vec![0u8; n as usize];
            file.read_exact_at(&mut buf, off).map_err(io)?;
            Ok(buf)
        };
        let first = read(0, HEADER_LEN as u64)?;
        let count = u32_at(&first, 12).unwrap_or(0).min(MAX_SECTIONS);
        let table = read(0, (HEADER_LEN + ENTRY_LEN * count as usize) as u64)?;
        let h = parse_header(&table)?;
        if h.length != len {
            return Err(if h.length > len {
                FormatError::Truncated(format!("{len} bytes of {}", h.length))
            } else {
                FormatError::Invalid(format!("{len} bytes but the header says {}", h.length))
            });
        }
        let head_bytes = read(0, h.data.0)?;
        let (head, entries) = parse_head(&h, &head_bytes)?;
        let by_page = clusters_by_page(&head);
        Ok(Self {
            file,
            path: path.to_path_buf(),
            head,
            entries,
            by_page,
        })
    }

    /// The mesh without its pages' content: metadata, clusters, groups, BVH and pages (the
    /// vertex, reference, triangle and material streams are empty).
    pub fn head(&self) -> &BuiltMesh {
        &self.head
    }

    /// Pages in the file.
    pub fn page_count(&self) -> u32 {
        self.entries.len() as u32
    }

    /// The page table's entry of page `i`.
    pub fn page_entry(&self, i: u32) -> Option<&PageEntry> {
        self.entries.get(i as usize)
    }

    /// Page `i`'s encoded bytes (`builder::page::encode_page`), read alone and checked (checksum,
    /// and every cluster in it decoded: its data where its record says, coordinates on the grid,
    /// local indices below its vertex count, materials in range).
    pub fn read_page(&self, i: u32) -> Result<Vec<u8>, FormatError> {
        let e = self
            .entries
            .get(i as usize)
            .ok_or_else(|| FormatError::Invalid(format!("page {i} out of range")))?;
        let mut buf = vec![0u8; e.length as usize];
        self.file
            .read_exact_at(&mut buf, e.offset)
            .map_err(|err| FormatError::Io(format!("{}: page {i}: {err}", self.path.display())))?;
        check_page(&self.head, e, i, &self.by_page[i as usize], &buf)?;
        Ok(buf)
    }
}

/// Bytes of `file` per input triangle of the mesh it holds.
pub fn bytes_per_input_triangle(file_len: usize, m: &BuiltMesh) -> f64 {
    file_len as f64 / m.stats.input_triangles.max(1) as f64
}
