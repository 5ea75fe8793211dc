//! Pages: the unit of geometry that is stored, read and streamed.
//!
//! After the DAG is assembled, [`paginate`] puts its clusters into pages of at most
//! [`PAGE_BYTES`] encoded bytes. A page holds whole groups (the members of a group share a page;
//! a group too large for one page spans consecutive pages) and is self-contained.
//!
//! **Two views of a page.** In memory ([`BuiltMesh`]) a page is a range of the mesh's logical
//! streams: its vertices (each distinct vertex once per page, in order of first use by the page's
//! clusters), u16 vertex references from the page's first vertex, and packed triangles, so the
//! whole-mesh view ([`BuiltMesh::vertex_ref`], the verifier, the CPU oracles) reads it directly.
//! Stored (a `.vgeo` file's page) and on the GPU (a slot of the geometry pool) a page is its
//! *encoded* bytes ([`encode_page`]): for each of its clusters, in index order, starting at word
//! [`super::Cluster::data_offset`]:
//!
//! - a header of [`header_words`] u32 words: first what culling reads ([`CULL_WORDS`]: the
//!   cluster's box on the mesh's grid, its smallest coordinates (3 words; x's bits above
//!   [`crate::shared::CLUSTER_COORD_BITS`] hold the triangle code's header, [`super::tricode`],
//!   and above it the normals' y width)
//!   and its extents (2 words, [`join_box`]), which the GPU turns into its bounds as it decodes a
//!   vertex ([`super::quantize::grid_corner`]); `vertex_count | triangle_count << 8 | level << 16
//!   | size_code << 24`; its group; its creator group), then the rest of its code: the bit widths
//!   `x | y << 5 | z << 10 | normal x << 15 | uv << 20 | material << 25` (the normals' y
//!   components' width rides in the smallest x coordinate's high bits, above the triangle code's
//!   header: a normal's two components have a width each since format 9), the smallest
//!   octahedral normal components (two i16), the smallest UV components (two u16, meshes with
//!   UVs) and the smallest material (meshes with a material stream);
//! - its vertices, each `vertex_bits` bits (the widths summed, UV components twice)
//!   of offsets from those minimums, as one little-endian bit stream (vertex `i` at bit
//!   `i * vertex_bits`; fields x, y, z, normal x, normal y, u, v, material);
//! - its triangles in the max-delta code of [`super::tricode`] (about 11 bits a triangle), after
//!   the builder's canonical triangle order.
//!
//! After the last cluster a page has one spare zero word, so that a reader may always fetch the
//! word after a field's first (the GPU reads every field as two words, without a branch).
//!
//! The cull words make a page carry its clusters whole: on the GPU a cluster is found by a small
//! resident locator (its page and word offset) and everything else about it is read from its page
//! (its LOD pairs are its groups', in the resident group table), so the per-cluster records need
//! not stay resident for geometry that is not (`docs/architecture.md`, "Streaming").
//!
//! A vertex is stored once per cluster that uses it, with no reference indirection, in as few
//! bits as the cluster's range needs; the codes are those of the mesh's grid, so the decoded
//! values equal the logical ones bit for bit (the GPU's decoding is `shaders_glsl/common/raster.glsl`).
//! [`decode_page`] turns the encoded bytes back into the logical streams.
//!
//! Pages are ordered from the DAG's root down (groups by decreasing build iteration): the first
//! [`BuiltMesh::resident_pages`] pages hold every group simplified at or after the fallback level
//! and nothing else, the always-resident part from which the mesh can always be drawn (it ends at
//! a page boundary: every mesh keeps it, in view or not). A page that cannot take the next group
//! is first filled with the largest groups of the same iteration among the next
//! [`FILL_WINDOW`] that fit, so that pages (and the slots holding them, each the size of the
//! largest page) are nearly full while neighbours in the stored (spatial) order share a page.

use std::collections::HashMap;

use bytemuck::{Pod, Zeroable};

use super::quantize::{POSITION_BITS, pack_coords, position_coords};
use super::{BuiltMesh, CLUSTER_FLAG_REFS_U32, Cluster, PackedVertex};
use crate::hash::FxBuild;

pub use crate::shared::PAGE_BYTES;

/// A page: its ranges in the mesh's logical streams ([`BuiltMesh::vertices`] and
/// `vertex_materials`, [`BuiltMesh::vertex_refs`], [`BuiltMesh::triangles`]), its clusters and
/// the length of its encoded bytes. Pages cover each stream in order, without gaps.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Pod, Zeroable)]
pub struct Page {
    pub vertex_first: u32,
    pub vertex_count: u32,
    /// In u32 words.
    pub ref_first: u32,
    pub ref_words: u32,
    /// In bytes (multiples of 4).
    pub triangle_first: u32,
    pub triangle_bytes: u32,
    /// Clusters whose data the page holds ([`super::Cluster::page`]).
    pub cluster_count: u32,
    /// Length of the page's encoded bytes ([`encode_page`], a multiple of 4).
    pub bytes: u32,
}
const _: () = assert!(size_of::<Page>() == 32);

/// Words of a cluster's header that culling reads: its box on the grid (5), counts, level and
/// size code, group, creator.
pub const CULL_WORDS: u32 = crate::shared::CLUSTER_CULL_WORDS;

/// Words of a cluster's header in an encoded page.
pub fn header_words(has_uvs: bool, has_materials: bool) -> u32 {
    CULL_WORDS + 2 + has_uvs as u32 + has_materials as u32
}

/// A cluster's cull words ([`CULL_WORDS`]), from its code and record: its box on the mesh's grid
/// (the smallest coordinates, x's high bits the triangle code's header `tri_head` and the
/// normals' y width, then the extents, [`join_box`]), `vertex_count | triangle_count << 8 | level << 16 | size_code << 24`
/// (the level has 8 bits: [`crate::shared::MAX_CLUSTER_LEVEL`], which the builder and the
/// loader's checks keep), group, creator. The record's bounds are that box's corners
/// ([`super::quantize::grid_corner`]; [`decode_page`] checks it).
pub fn cull_words(c: &Cluster, code: &ClusterCode, tri_head: u32) -> [u32; CULL_WORDS as usize] {
    let head = tri_head | code.normal_y_width << crate::shared::TRIANGLE_HEAD_BITS;
    let b = join_box(code.position_min, code.position_extent, head);
    [
        b[0],
        b[1],
        b[2],
        b[3],
        b[4],
        c.vertex_count()
            | c.triangle_count() << 8
            | c.level.min(crate::shared::MAX_CLUSTER_LEVEL) << 16
            | c.size_code() << 24,
        c.group,
        c.creator,
    ]
}

/// Bits needed for values `0 ..= range`.
fn width(range: u32) -> u32 {
    32 - range.leading_zeros()
}

/// A cluster's encoding parameters: per field the minimum and the bit width.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct ClusterCode {
    pub position_min: [u32; 3],
    /// Largest minus smallest grid coordinate per axis (the box the cull reads).
    pub position_extent: [u32; 3],
    /// Bit widths `x | y << 5 | z << 10 | normal x << 15 | uv << 20 | material << 25`.
    pub widths: u32,
    /// Bit width of the normals' y components (stored above the triangle code's header in the
    /// cull words' smallest x coordinate, [`join_box`]).
    pub normal_y_width: u32,
    pub normal_min: u32,
    pub uv_min: u32,
    pub material_min: u32,
}

impl ClusterCode {
    /// Bit widths: x, y, z, normal x, normal y, uv (per component), material.
    pub fn field_widths(&self) -> [u32; 7] {
        let w = |k: u32| (self.widths >> (5 * k)) & 31;
        [w(0), w(1), w(2), w(3), self.normal_y_width, w(4), w(5)]
    }

    /// Bits per vertex.
    pub fn vertex_bits(&self) -> u32 {
        let [x, y, z, nx, ny, uv, m] = self.field_widths();
        x + y + z + nx + ny + 2 * uv + m
    }

    /// The code of a cluster's vertices (with their materials; `has_uvs`, `has_materials` say
    /// which fields the mesh stores).
    pub fn of(vertices: &[(PackedVertex, u16)], has_uvs: bool, has_materials: bool) -> Self {
        let mut lo = [u32::MAX; 3];
        let mut hi = [0u32; 3];
        let mut nlo = [i32::MAX; 2];
        let mut nhi = [i32::MIN; 2];
        let mut ulo = [u32::MAX; 2];
        let mut uhi = [0u32; 2];
        let (mut mlo, mut mhi) = (u32::MAX, 0u32);
        for (v, m) in vertices {
            let c = position_coords(v.position);
            for k in 0..3 {
                lo[k] = lo[k].min(c[k]);
                hi[k] = hi[k].max(c[k]);
            }
            let n = normal_parts(v.normal);
            let u = [v.uv & 0xffff, v.uv >> 16];
            for k in 0..2 {
                nlo[k] = nlo[k].min(n[k]);
                nhi[k] = nhi[k].max(n[k]);
                ulo[k] = ulo[k].min(u[k]);
                uhi[k] = uhi[k].max(u[k]);
            }
            mlo = mlo.min(*m as u32);
            mhi = mhi.max(*m as u32);
        }
        if vertices.is_empty() {
            return Self::default();
        }
        let nw = [0, 1].map(|k| width((nhi[k] - nlo[k]) as u32));
        let uw = if has_uvs {
            width((uhi[0] - ulo[0]).max(uhi[1] - ulo[1]))
        } else {
            0
        };
        let mw = if has_materials { width(mhi - mlo) } else { 0 };
        let widths = [
            width(hi[0] - lo[0]),
            width(hi[1] - lo[1]),
            width(hi[2] - lo[2]),
            nw[0],
            uw,
            mw,
        ]
        .iter()
        .enumerate()
        .fold(0u32, |acc, (k, &w)| acc | w << (5 * k));
        ClusterCode {
            position_min: lo,
            position_extent: std::array::from_fn(|k| hi[k] - lo[k]),
            widths,
            normal_y_width: nw[1],
            normal_min: (nlo[0] as u16 as u32) | (nlo[1] as u16 as u32) << 16,
            uv_min: if has_uvs { ulo[0] | ulo[1] << 16 } else { 0 },
            material_min: if has_materials { mlo } else { 0 },
        }
    }
}

/// The two octahedral components of a normal code as signed values.
fn normal_parts(code: u32) -> [i32; 2] {
    [code as u16 as i16 as i32, (code >> 16) as u16 as i16 as i32]
}

/// Encoded words of a cluster of `vertex_count` vertices under `code` whose triangles take
/// `triangle_words` ([`super::tricode::encode`]).
pub fn cluster_words(
    code: &ClusterCode,
    vertex_count: u32,
    triangle_words: usize,
    has_uvs: bool,
    has_materials: bool,
) -> usize {
    header_words(has_uvs, has_materials) as usize
        + (vertex_count as usize * code.vertex_bits() as usize).div_ceil(32)
        + triangle_words
}

/// Encoded bytes of a cluster with `vertices` (in reference order, with their materials) and
/// local triangles `tris` (in the canonical order): what [`paginate`] places in a page.
pub(crate) fn cluster_bytes(
    vertices: &[(PackedVertex, u16)],
    tris: &[[u32; 3]],
    has_uvs: bool,
    has_materials: bool,
) -> usize {
    let code = ClusterCode::of(vertices, has_uvs, has_materials);
    let n = vertices.len() as u32;
    4 * cluster_words(
        &code,
        n,
        super::tricode::encoded_words(tris, n),
        has_uvs,
        has_materials,
    )
}

/// Appends bits to a u32 stream, from word `start` of `out` on (it may leave one spare word
/// after the last bit written).
pub(super) struct BitWriter<'a> {
    pub out: &'a mut Vec<u32>,
    pub start: usize,
    pub bit: usize,
}

impl BitWriter<'_> {
    pub fn put(&mut self, value: u32, bits: u32) {
        if bits == 0 {
            return;
        }
        let w = self.start + self.bit / 32;
        let sh = (self.bit % 32) as u32;
        while self.out.len() <= w + 1 {
            self.out.push(0);
        }
        let v = value as u64 & ((1u64 << bits) - 1);
        self.out[w] |= (v << sh) as u32;
        self.out[w + 1] |= ((v << sh) >> 32) as u32;
        self.bit += bits as usize;
    }
}

/// Reads bits from a u32 stream (`None` past its end).
pub(super) fn get_bits(words: &[u32], bit: usize, bits: u32) -> Option<u32> {
    if bits == 0 {
        return Some(0);
    }
    let w = bit / 32;
    let sh = (bit % 32) as u32;
    let lo = *words.get(w)? as u64;
    let hi = if sh + bits > 32 {
        *words.get(w + 1)? as u64
    } else {
        0
    };
    Some((((lo | hi << 32) >> sh) & ((1u64 << bits) - 1)) as u32)
}

/// The vertices (with materials) and packed triangles of cluster `c` of `m`, from the logical
/// streams.
fn cluster_vertices(m: &BuiltMesh, c: &Cluster) -> Vec<(PackedVertex, u16)> {
    let mats = m.has_material_stream();
    (0..c.vertex_count())
        .map(|i| {
            let v = m.vertex_ref(c, i) as usize;
            (m.vertices[v], if mats { m.vertex_materials[v] } else { 0 })
        })
        .collect()
}

/// Appends cluster `c`'s encoded words (see the module's documentation) to `out`.
fn encode_cluster(m: &BuiltMesh, c: &Cluster, out: &mut Vec<u32>) {
    let (has_uvs, has_mats) = (m.has_uvs, m.has_material_stream());
    let verts = cluster_vertices(m, c);
    let code = ClusterCode::of(&verts, has_uvs, has_mats);
    let (tri_head, tri_words) =
        super::tricode::encode(&m.cluster_local_triangles(c), c.vertex_count());
    // (The loader refuses other values; `shared.rs` asserts that these fit the spare bits.)
    debug_assert!(tri_head <= 8 && code.normal_y_width <= 16);
    out.extend_from_slice(&cull_words(c, &code, tri_head));
    out.push(code.widths);
    out.push(code.normal_min);
    if has_uvs {
        out.push(code.uv_min);
    }
    if has_mats {
        out.push(code.material_min);
    }
    let [wx, wy, wz, wnx, wny, wu, wm] = code.field_widths();
    let start = out.len();
    let vertex_words = (verts.len() * code.vertex_bits() as usize).div_ceil(32);
    let mut w = BitWriter { out, start, bit: 0 };
    let nmin = normal_parts(code.normal_min);
    for (v, mat) in &verts {
        let p = position_coords(v.position);
        w.put(p[0] - code.position_min[0], wx);
        w.put(p[1] - code.position_min[1], wy);
        w.put(p[2] - code.position_min[2], wz);
        let n = normal_parts(v.normal);
        w.put((n[0] - nmin[0]) as u32, wnx);
        w.put((n[1] - nmin[1]) as u32, wny);
        w.put((v.uv & 0xffff) - (code.uv_min & 0xffff), wu);
        w.put((v.uv >> 16) - (code.uv_min >> 16), wu);
        w.put(*mat as u32 - code.material_min, wm);
    }
    out.resize(start + vertex_words, 0);
    out.extend(tri_words);
}

/// A cluster's box on the grid as the first five cull words: the smallest coordinates (x's spare
/// high bits, above [`crate::shared::CLUSTER_COORD_BITS`], `head`: the triangle code's header in
/// [`crate::shared::TRIANGLE_HEAD_BITS`], the normals' y width above), then the
/// three extents of [`crate::shared::CLUSTER_COORD_BITS`] bits each in two words (x in bits 0-20
/// of the first, y in its bits 21-31 and bits 0-9 of the second, z in bits 10-30 of the second;
/// `common/cluster.glsl` reads them).
fn join_box(min: [u32; 3], extent: [u32; 3], head: u32) -> [u32; 5] {
    let b = crate::shared::CLUSTER_COORD_BITS;
    [
        min[0] | head << b,
        min[1],
        min[2],
        extent[0] | extent[1] << b,
        extent[1] >> (32 - b) | extent[2] << (2 * b - 32),
    ]
}

/// The inverse of [`join_box`]: smallest coordinates, extents, `head` (high bits of y
/// and z and of the extents' last word are left for the checks to refuse).
fn split_box(words: &[u32]) -> ([u32; 3], [u32; 3], u32) {
    let b = crate::shared::CLUSTER_COORD_BITS;
    let mask = (1u32 << b) - 1;
    (
        [words[0] & mask, words[1], words[2]],
        [
            words[3] & mask,
            words[3] >> b | (words[4] << (32 - b)) & mask,
            words[4] >> (2 * b - 32),
        ],
        words[0] >> b,
    )
}

/// The encoded bytes of the page holding `clusters` (its clusters in index order, as
/// [`clusters_by_page`] lists them); the clusters' `data_offset`s must be those [`paginate`]
/// gave them.
pub fn encode_page(m: &BuiltMesh, clusters: &[u32]) -> Vec<u8> {
    let mut words: Vec<u32> = Vec::new();
    for &ci in clusters {
        let c = &m.clusters[ci as usize];
        debug_assert_eq!(c.data_offset as usize, words.len());
        encode_cluster(m, c, &mut words);
    }
    words.push(0);
    bytemuck::cast_slice(&words).to_vec()
}

/// Where a mesh's encoded page bytes go ([`page_bytes_breakdown`]; `vgeo build` / `vgeo info`
/// print it): the parts sum to the pages' bytes.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PageBytes {
    /// Cluster headers ([`header_words`] each).
    pub headers: u64,
    /// Vertex bit streams, each rounded up to whole words.
    pub vertices: u64,
    /// Triangle codes ([`super::tricode`]).
    pub triangles: u64,
    /// The spare word after each page's last cluster.
    pub page_ends: u64,
    /// Vertices stored (once per cluster that uses one) and triangles over all levels.
    pub stored_vertices: u64,
    pub stored_triangles: u64,
    /// Bits of the stored vertices' fields, summed: positions (x, y, z), normals (both
    /// octahedral components), UVs (both) and materials.
    pub position_bits: u64,
    pub normal_bits: u64,
    pub uv_bits: u64,
    pub material_bits: u64,
}

impl PageBytes {
    /// Every part together: the pages' encoded bytes.
    pub fn total(&self) -> u64 {
        self.headers + self.vertices + self.triangles + self.page_ends
    }
}

/// Where `m`'s encoded page bytes go, cluster by cluster, as [`encode_page`] lays them out.
pub fn page_bytes_breakdown(m: &BuiltMesh) -> PageBytes {
    let (has_uvs, has_mats) = (m.has_uvs, m.has_material_stream());
    let mut b = PageBytes {
        page_ends: 4 * m.pages.len() as u64,
        ..Default::default()
    };
    for c in &m.clusters {
        let verts = cluster_vertices(m, c);
        let code = ClusterCode::of(&verts, has_uvs, has_mats);
        let n = verts.len() as u64;
        let [x, y, z, nxw, nyw, uw, mw] = code.field_widths().map(u64::from);
        b.headers += 4 * header_words(has_uvs, has_mats) as u64;
        b.vertices += 4 * (n * code.vertex_bits() as u64).div_ceil(32);
        b.triangles +=
            4 * super::tricode::encoded_words(&m.cluster_local_triangles(c), c.vertex_count())
                as u64;
        b.stored_vertices += n;
        b.stored_triangles += c.triangle_count() as u64;
        b.position_bits += n * (x + y + z);
        b.normal_bits += n * (nxw + nyw);
        b.uv_bits += n * 2 * uw;
        b.material_bits += n * mw;
    }
    b
}

/// Page `page`'s encoded bytes (finds its clusters by a pass over all clusters: for one page at a
/// time; [`encode_page`] with [`clusters_by_page`] for many).
pub fn page_bytes(m: &BuiltMesh, page: u32) -> Vec<u8> {
    let clusters: Vec<u32> = (0..m.clusters.len() as u32)
        .filter(|&c| m.clusters[c as usize].page == page)
        .collect();
    encode_page(m, &clusters)
}

/// Per page, the clusters stored in it (in index order).
pub fn clusters_by_page(m: &BuiltMesh) -> Vec<Vec<u32>> {
    let mut by = vec![Vec::new(); m.pages.len()];
    for (ci, c) in m.clusters.iter().enumerate() {
        if let Some(b) = by.get_mut(c.page as usize) {
            b.push(ci as u32);
        }
    }
    by
}

/// One page's logical streams, decoded from its encoded bytes.
pub struct PageStreams {
    pub vertices: Vec<PackedVertex>,
    /// Empty when the mesh has no per-vertex materials.
    pub materials: Vec<u16>,
    pub refs: Vec<u32>,
    pub triangles: Vec<u8>,
    /// Per cluster of the page (in the order given): its first reference word and its first
    /// triangle byte, relative to the page's.
    pub cluster_starts: Vec<(u32, u32)>,
}

/// Decodes a page's encoded bytes (the inverse of [`encode_page`]) into its logical streams:
/// `clusters` are the page's clusters in index order. An error says what does not fit: a cluster
/// whose data does not start where the previous ended, data past the end or bytes left over, a
/// coordinate off the mesh's grid, a code that is not the minimal one of its vertices or of its
/// triangles ([`super::tricode`]), a local index not below the cluster's vertex count.
pub fn decode_page(
    bytes: &[u8],
    clusters: &[&Cluster],
    quant: &super::Quantization,
    has_uvs: bool,
    has_materials: bool,
) -> Result<PageStreams, String> {
    if !bytes.len().is_multiple_of(4) {
        return Err(format!("{} bytes, not whole words", bytes.len()));
    }
    let words: Vec<u32> = bytes
        .chunks_exact(4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    let hw = header_words(has_uvs, has_materials) as usize;
    let mut st = PageStreams {
        vertices: Vec::new(),
        materials: Vec::new(),
        refs: Vec::new(),
        triangles: Vec::new(),
        cluster_starts: Vec::with_capacity(clusters.len()),
    };
    let mut slot: HashMap<(PackedVertex, u16), u32, FxBuild> = HashMap::default();
    let mut at = 0usize;
    let coord_max = (1u64 << POSITION_BITS) - 1;
    for (k, c) in clusters.iter().enumerate() {
        let bad = |what: String| format!("cluster {k} of the page: {what}");
        if c.data_offset as usize != at {
            return Err(bad(format!(
                "its data starts at word {}, the previous cluster's ended at {at}",
                c.data_offset
            )));
        }
        let head = words
            .get(at..at + hw)
            .ok_or_else(|| bad("header past the page's end".into()))?;
        let (cull, head) = head.split_at(CULL_WORDS as usize);
        let (position_min, position_extent, box_head) = split_box(cull);
        let tri_bits = crate::shared::TRIANGLE_HEAD_BITS;
        let tri_head = box_head & ((1 << tri_bits) - 1);
        let mut code = ClusterCode {
            position_min,
            position_extent,
            widths: head[0],
            normal_y_width: box_head >> tri_bits,
            normal_min: head[1],
            uv_min: 0,
            material_min: 0,
        };
        if cull != cull_words(c, &code, tri_head) {
            return Err(bad(
                "its cull words (box, counts, level, size code, group, creator) differ from its \
                 record"
                    .into(),
            ));
        }
        // The bounds the CPU's cut and the checks use are the box the GPU reads.
        let hi: [u64; 3] =
            std::array::from_fn(|a| position_min[a] as u64 + position_extent[a] as u64);
        if hi.iter().any(|&x| x > coord_max) {
            return Err(bad(format!(
                "its box {position_min:?} + {position_extent:?} leaves the grid"
            )));
        }
        let hi = hi.map(|x| x as u32);
        let (lo_f, hi_f) = (
            super::quantize::grid_corner(quant, position_min),
            super::quantize::grid_corner(quant, hi),
        );
        if lo_f.map(f32::to_bits) != c.bounds_min.map(f32::to_bits)
            || hi_f.map(f32::to_bits) != c.bounds_max.map(f32::to_bits)
        {
            return Err(bad("its box on the grid is not its record's bounds".into()));
        }
        let mut h = 2;
        if has_uvs {
            code.uv_min = head[h];
            h += 1;
        }
        if has_materials {
            code.material_min = head[h];
        }
        let [wx, wy, wz, wnx, wny, wu, wm] = code.field_widths();
        if code.widths >> 30 != 0
            || wnx > 16
            || wny > 16
            || wu > 16
            || wm > 16
            || (!has_uvs && (wu != 0 || code.uv_min != 0))
            || (!has_materials && (wm != 0 || code.material_min != 0))
        {
            return Err(bad(format!(
                "bad field widths {:#x} (normals' y width {})",
                code.widths, code.normal_y_width
            )));
        }
        let (vc, tc) = (c.vertex_count(), c.triangle_count());
        let vbits = code.vertex_bits() as usize;
        let vstart = at + hw;
        let vwords = (vc as usize * vbits).div_ceil(32);
        if vstart + vwords > words.len() {
            return Err(bad(format!(
                "{} words past the page's end",
                vstart + vwords - words.len()
            )));
        }
        let vw = &words[vstart..vstart + vwords];
        let nmin = normal_parts(code.normal_min);
        let mut refs_local = Vec::with_capacity(vc as usize);
        let mut decoded = Vec::with_capacity(vc as usize);
        for i in 0..vc as usize {
            let mut bit = i * vbits;
            let mut get = |w: u32| {
                let v = get_bits(vw, bit, w).unwrap_or(0);
                bit += w as usize;
                v
            };
            let off = [get(wx), get(wy), get(wz)];
            let mut p = [0u32; 3];
            for a in 0..3 {
                let v = code.position_min[a] as u64 + off[a] as u64;
                if v > coord_max {
                    return Err(bad(format!("vertex {i}: coordinate {v} off the grid")));
                }
                p[a] = v as u32;
            }
            let n = [
                (nmin[0] + get(wnx) as i32) as u16 as u32,
                (nmin[1] + get(wny) as i32) as u16 as u32,
            ];
            let u = (code.uv_min & 0xffff) + get(wu);
            let v = (code.uv_min >> 16) + get(wu);
            let mat = code.material_min + get(wm);
            if u > 0xffff || v > 0xffff || mat > 0xffff {
                return Err(bad(format!("vertex {i}: UV or material out of range")));
            }
            let pv = PackedVertex {
                position: pack_coords(p),
                normal: n[0] | n[1] << 16,
                uv: u | v << 16,
            };
            let key = (pv, mat as u16);
            decoded.push(key);
            let next = st.vertices.len() as u32;
            let s = *slot.entry(key).or_insert(next);
            if s == next {
                st.vertices.push(pv);
                if has_materials {
                    st.materials.push(mat as u16);
                }
            }
            refs_local.push(s);
        }
        if st.vertices.len() > MAX_PAGE_VERTICES {
            return Err(format!("more than {MAX_PAGE_VERTICES} vertices"));
        }
        // One encoding per cluster: the header must be the one its vertices give (minimums and
        // the fewest bits), so that a loaded page saves to the same bytes and lengths.
        if ClusterCode::of(&decoded, has_uvs, has_materials) != code {
            return Err(bad(
                "its header is not the minimal code of its vertices".into()
            ));
        }
        let (tris, twords) =
            super::tricode::decode(tri_head, &words[vstart + vwords..], tc, vc).map_err(&bad)?;
        let end = vstart + vwords + twords;
        let local: Vec<u8> = tris.iter().flatten().map(|&l| l as u8).collect();
        let mut tri = Vec::new();
        super::pack_indices(&local, vc, &mut tri);
        st.cluster_starts
            .push((st.refs.len() as u32, st.triangles.len() as u32));
        for pair in refs_local.chunks(2) {
            st.refs
                .push(pair[0] | pair.get(1).copied().unwrap_or(0) << 16);
        }
        st.triangles.extend_from_slice(&tri);
        at = end;
    }
    if words.len() != at + 1 || words[at] != 0 {
        return Err(format!(
            "{} words after its last cluster (one spare zero word expected)",
            words.len() - at
        ));
    }
    Ok(st)
}

/// How many groups ahead [`paginate`] looks for one that fills the rest of a page.
pub const FILL_WINDOW: usize = 16;

/// Most vertices one page may hold (its logical references are u16 offsets from its first
/// vertex).
const MAX_PAGE_VERTICES: usize = 1 << 16;

impl BuiltMesh {
    /// Whether the pages hold a material per vertex: the mesh has more than one material
    /// (`vertex_materials` then has one entry per vertex, else none).
    pub fn has_material_stream(&self) -> bool {
        self.materials.len() > 1
    }
}

/// The key that merges equal vertices within a page.
type VertexKey = ([u32; 2], u32, u32, u16);

fn vertex_key(v: &PackedVertex, material: u16) -> VertexKey {
    (v.position, v.normal, v.uv, material)
}

/// Lays `m`'s clusters out in pages of at most `page_bytes` encoded bytes (see the module's
/// documentation), rewriting the logical vertex, reference and triangle streams page by page and
/// setting each cluster's `page` and `data_offset`; the clusters, groups and BVH keep their order
/// and meaning. Groups simplified at or after iteration `resident_level` come first, alone in the
/// always-resident pages. Deterministic.
pub fn paginate(m: &mut BuiltMesh, page_bytes: usize, resident_level: u32) {
    use rayon::prelude::*;
    let (has_uvs, has_mats) = (m.has_uvs, m.has_material_stream());
    // Each cluster's encoded bytes (they do not depend on the page it lands in).
    let sizes: Vec<usize> = {
        let mm = &*m;
        mm.clusters
            .par_iter()
            .map(|c| {
                let tris = mm.cluster_local_triangles(c);
                cluster_bytes(&cluster_vertices(mm, c), &tris, has_uvs, has_mats)
            })
            .collect()
    };
    paginate_sized(m, page_bytes, resident_level, &sizes, false);
}

thread_local! {
    /// Per-thread map vertex index -> slot in the page being laid out (all `u32::MAX` between
    /// pages); see [`paginate_sized`].
    static PAGE_SLOTS: std::cell::RefCell<Vec<u32>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// [`paginate`] given each cluster's encoded bytes ([`cluster_bytes`]), which the builder
/// computes while it packs the clusters. `unique_vertices`: no two of `m`'s vertices are equal
/// (with their materials), as the builder's welding leaves them, so a page's vertices are told
/// apart by index (a hash of each vertex's value took most of the layout's time otherwise).
pub(crate) fn paginate_sized(
    m: &mut BuiltMesh,
    page_bytes: usize,
    resident_level: u32,
    sizes: &[usize],
    unique_vertices: bool,
) {
    use rayon::prelude::*;
    let has_mats = m.has_material_stream();
    debug_assert_eq!(sizes.len(), m.clusters.len());
    // Groups from the root down; ties in stored (BVH) order.
    let mut order: Vec<u32> = (0..m.groups.len() as u32).collect();
    order.sort_by_key(|&g| (std::cmp::Reverse(m.groups[g as usize].iteration), g));

    let mut page_of = vec![0u32; m.clusters.len()];
    let mut pages: Vec<Vec<u32>> = vec![Vec::new()];
    // Bytes and (at most) logical vertices of the current page.
    let mut used = (0usize, 0usize);
    let mut resident_pages = 0usize;
    let cost = |members: &[u32]| {
        members.iter().fold((0usize, 0usize), |(b, v), &c| {
            (
                b + sizes[c as usize],
                v + m.clusters[c as usize].vertex_count() as usize,
            )
        })
    };
    // (The page's spare word counts too.)
    let fits = |used: (usize, usize), add: (usize, usize)| {
        used.0 + add.0 + 4 <= page_bytes && used.1 + add.1 <= MAX_PAGE_VERTICES
    };
    let members_of = |g: u32| {
        let grp = &m.groups[g as usize];
        (grp.first_cluster..grp.first_cluster + grp.cluster_count).collect::<Vec<u32>>()
    };
    // Groups placed ahead of their turn to fill a page (see below).
    let mut taken = vec![false; m.groups.len()];
    let mut in_prefix = true;
    for (k, &g) in order.iter().enumerate() {
        if taken[g as usize] {
            continue;
        }
        let grp = &m.groups[g as usize];
        // The always-resident prefix holds the groups at or above `resident_level` and nothing
        // else: its last page ends with them (a streamed group there would stay resident for
        // good, and every mesh pays its prefix, in view or not).
        if in_prefix && k > 0 && grp.iteration < resident_level {
            in_prefix = false;
            if !pages.last().is_some_and(|p| p.is_empty()) {
                pages.push(Vec::new());
                used = (0, 0);
            }
            resident_pages = pages.len() - 1;
        }
        let members = members_of(g);
        let add = cost(&members);
        // A page that cannot take this group is first filled with the largest groups of the
        // same iteration among the next few that still fit (so that pages, and the slots that
        // hold them, are nearly full; the groups stay near in the stored, spatial order).
        if !fits(used, add) && fits((0, 0), add) && !pages.last().is_some_and(|p| p.is_empty()) {
            loop {
                let best = order[k + 1..order.len().min(k + 1 + FILL_WINDOW)]
                    .iter()
                    .copied()
                    .filter(|&h| {
                        !taken[h as usize] && m.groups[h as usize].iteration == grp.iteration
                    })
                    .map(|h| (cost(&members_of(h)), h))
                    .filter(|&(c, _)| fits(used, c))
                    .max_by_key(|&(c, h)| (c.0, std::cmp::Reverse(h)));
                let Some((c, h)) = best else { break };
                taken[h as usize] = true;
                used = (used.0 + c.0, used.1 + c.1);
                let page = pages.len() as u32 - 1;
                let hm = members_of(h);
                for &ci in &hm {
                    page_of[ci as usize] = page;
                }
                pages.last_mut().expect("a page").extend_from_slice(&hm);
            }
        }
        let chunks: Vec<Vec<u32>> = if fits(used, add) || fits((0, 0), add) {
            vec![members]
        } else {
            members.iter().map(|&c| vec![c]).collect()
        };
        for chunk in chunks {
            let add = cost(&chunk);
            if !fits(used, add) && !pages.last().is_some_and(|p| p.is_empty()) {
                pages.push(Vec::new());
                used = (0, 0);
            }
            used = (used.0 + add.0, used.1 + add.1);
            let page = pages.len() as u32 - 1;
            for &ci in &chunk {
                page_of[ci as usize] = page;
            }
            pages.last_mut().expect("a page").extend_from_slice(&chunk);
        }
    }
    if in_prefix {
        resident_pages = pages.len();
    }

    // The logical streams, page by page; clusters in index order within a page, each distinct
    // vertex once per page in order of first use. Pages are laid out independently (in
    // parallel), then concatenated in order.
    struct Laid {
        vertices: Vec<PackedVertex>,
        vmat: Vec<u16>,
        refs: Vec<u32>,
        triangles: Vec<u8>,
        /// Per member: (triangle offset, vertex reference offset, data word), page-relative.
        at: Vec<(u32, u32, u32)>,
        words: u32,
    }
    for members in pages.iter_mut() {
        members.sort_unstable();
    }
    let laid: Vec<Laid> = {
        let mm = &*m;
        pages
            .par_iter()
            .map(|members| {
                let mut l = Laid {
                    vertices: Vec::new(),
                    vmat: Vec::new(),
                    refs: Vec::new(),
                    triangles: Vec::new(),
                    at: Vec::with_capacity(members.len()),
                    words: 0,
                };
                // A page's slot of each distinct vertex: by value in a hash map sized for every
                // member vertex up front, or, where equal vertices have one index, by index in a
                // per-thread map (reset to `u32::MAX` after the page).
                let mut by_key: HashMap<VertexKey, u32, FxBuild> = if unique_vertices {
                    HashMap::default()
                } else {
                    HashMap::with_capacity_and_hasher(
                        members
                            .iter()
                            .map(|&ci| mm.clusters[ci as usize].vertex_count() as usize)
                            .sum(),
                        FxBuild::default(),
                    )
                };
                PAGE_SLOTS.with(|cell| {
                    let mut by_index = cell.borrow_mut();
                    if unique_vertices && by_index.len() < mm.vertices.len() {
                        by_index.resize(mm.vertices.len(), u32::MAX);
                    }
                    let mut placed: Vec<u32> = Vec::new();
                    for &ci in members {
                        let c = &mm.clusters[ci as usize];
                        let local: Vec<u32> = (0..c.vertex_count())
                            .map(|i| {
                                let g = mm.vertex_ref(c, i) as usize;
                                let v = mm.vertices[g];
                                let mat = if has_mats { mm.vertex_materials[g] } else { 0 };
                                let next = l.vertices.len() as u32;
                                let s = if unique_vertices {
                                    let e = &mut by_index[g];
                                    if *e == u32::MAX {
                                        *e = next;
                                        placed.push(g as u32);
                                    }
                                    *e
                                } else {
                                    *by_key.entry(vertex_key(&v, mat)).or_insert(next)
                                };
                                if s == next {
                                    l.vertices.push(v);
                                    if has_mats {
                                        l.vmat.push(mat);
                                    }
                                }
                                s
                            })
                            .collect();
                        let src = c.triangle_offset as usize;
                        let len =
                            super::packed_triangle_bytes(c.vertex_count(), c.triangle_count());
                        l.at.push((l.triangles.len() as u32, l.refs.len() as u32, l.words));
                        l.triangles.extend_from_slice(&mm.triangles[src..src + len]);
                        l.words += (sizes[ci as usize] / 4) as u32;
                        for pair in local.chunks(2) {
                            l.refs
                                .push(pair[0] | pair.get(1).copied().unwrap_or(0) << 16);
                        }
                    }
                    for g in placed {
                        by_index[g as usize] = u32::MAX;
                    }
                });
                l
            })
            .collect()
    };
    // Offsets first (serial, one step per page), then the streams copied page by page in
    // parallel.
    let mut out_pages = Vec::with_capacity(pages.len());
    let mut at = (0u32, 0u32, 0u32);
    for (pi, (members, l)) in pages.iter().zip(&laid).enumerate() {
        let page = Page {
            vertex_first: at.0,
            vertex_count: l.vertices.len() as u32,
            ref_first: at.1,
            ref_words: l.refs.len() as u32,
            triangle_first: at.2,
            triangle_bytes: l.triangles.len() as u32,
            cluster_count: members.len() as u32,
            bytes: 4 * (l.words + 1),
        };
        at = (
            at.0 + page.vertex_count,
            at.1 + page.ref_words,
            at.2 + page.triangle_bytes,
        );
        for (&ci, &(t, r, w)) in members.iter().zip(&l.at) {
            let cm = &mut m.clusters[ci as usize];
            cm.triangle_offset = page.triangle_first + t;
            cm.vertex_ref_offset = page.ref_first + r;
            cm.data_offset = w;
            cm.counts &= !(CLUSTER_FLAG_REFS_U32 << 16);
            cm.page = pi as u32;
        }
        out_pages.push(page);
    }
    let vertices = super::concat(&laid, |l| &l.vertices);
    let vmat = super::concat(&laid, |l| &l.vmat);
    let refs = super::concat(&laid, |l| &l.refs);
    let triangles = super::concat(&laid, |l| &l.triangles);
    // Groups: the pages of their members (consecutive by construction).
    for g in m.groups.iter_mut() {
        let members = g.first_cluster as usize..(g.first_cluster + g.cluster_count) as usize;
        let lo = members.clone().map(|c| page_of[c]).min().unwrap_or(0);
        let hi = members.map(|c| page_of[c]).max().unwrap_or(0);
        g.page_first = lo;
        g.page_count = hi - lo + 1;
    }
    m.vertices = vertices;
    m.vertex_materials = vmat;
    m.vertex_refs = refs;
    m.triangles = triangles;
    m.stats.vertices = m.vertices.len();
    m.stats.pages = out_pages.len();
    m.pages = out_pages;
    m.resident_pages = resident_pages.max(1) as u32;
}
/// Per group, the pages that must be resident whenever all of the group's pages are (sorted):
/// those of the groups of the clusters it produced (their parents' siblings), so that a resident
/// group's products can be drawn and refined into it.
pub fn group_needs(m: &BuiltMesh) -> Vec<Vec<u32>> {
    let mut needs: Vec<Vec<u32>> = vec![Vec::new(); m.groups.len()];
    for c in &m.clusters {
        if let Some(n) = needs.get_mut(c.creator as usize)
            && let Some(g) = m.groups.get(c.group as usize)
        {
            n.extend(g.page_first..g.page_first + g.page_count);
        }
    }
    for n in &mut needs {
        n.sort_unstable();
        n.dedup();
    }
    needs
}

/// Grows `resident` (per page of `m`) to the smallest closed set containing it and the
/// always-resident pages: every group whose pages are all resident has its [`group_needs`]
/// resident. Under a closed set the cut ([`super::cut`]) is crack-free.
pub fn close_residency(m: &BuiltMesh, needs: &[Vec<u32>], resident: &mut [bool]) {
    for r in resident.iter_mut().take(m.resident_pages as usize) {
        *r = true;
    }
    loop {
        let mut grew = false;
        for (g, n) in m.groups.iter().zip(needs) {
            let whole = (g.page_first..g.page_first + g.page_count)
                .all(|p| resident.get(p as usize).copied().unwrap_or(false));
            if whole {
                for &p in n {
                    if let Some(r) = resident.get_mut(p as usize)
                        && !*r
                    {
                        *r = true;
                        grew = true;
                    }
                }
            }
        }
        if !grew {
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bits_round_trip_across_words() {
        let mut out = vec![7u32];
        let mut w = BitWriter {
            out: &mut out,
            start: 1,
            bit: 0,
        };
        let fields = [
            (5u32, 3u32),
            (0x1fffff, 21),
            (0, 0),
            (0xabcd, 16),
            (1, 1),
            (0x7fff, 15),
        ];
        for &(v, b) in &fields {
            w.put(v, b);
        }
        assert_eq!(out[0], 7, "the writer touched a word before its start");
        let mut bit = 0;
        for &(v, b) in &fields {
            assert_eq!(get_bits(&out[1..], bit, b), Some(v));
            bit += b as usize;
        }
        let end = 32 * (out.len() - 1);
        assert_eq!(get_bits(&out[1..], end, 8), None);
        assert_eq!(get_bits(&out[1..], end - 4, 8), None);
    }

    #[test]
    fn cluster_code_spans_signed_normals_and_materials() {
        let v = |x: u32, n: [i16; 2], uv: u32| PackedVertex {
            position: pack_coords([x, 5, (1 << POSITION_BITS) - 1]),
            normal: n[0] as u16 as u32 | (n[1] as u16 as u32) << 16,
            uv,
        };
        let verts = [
            (v(10, [-32767, 3], 0x0001_0002), 4u16),
            (v(13, [32767, 3], 0x0009_0002), 6u16),
        ];
        let c = ClusterCode::of(&verts, true, true);
        assert_eq!(c.position_min, [10, 5, (1 << POSITION_BITS) - 1]);
        // x spans 3 (2 bits), y and z nothing, normal x 65534 (16 bits), normal y nothing,
        // UVs 8 (4 bits), materials 2 (2 bits).
        assert_eq!(c.field_widths(), [2, 0, 0, 16, 0, 4, 2]);
        assert_eq!(c.vertex_bits(), 2 + 16 + 8 + 2);
        assert_eq!(normal_parts(c.normal_min), [-32767, 3]);
        assert_eq!((c.uv_min, c.material_min), (0x0001_0002, 4));
        let plain = ClusterCode::of(&verts, false, false);
        assert_eq!(plain.field_widths()[5..], [0, 0]);
    }
}
