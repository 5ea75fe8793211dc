//! Pages: the unit of geometry that is stored, read and (later) streamed.
//!
//! After the DAG is assembled, [`paginate`] puts its clusters into pages of at most
//! [`PAGE_BYTES`] bytes of vertex data, vertex references and packed triangles. A page holds whole
//! groups (the members of a group share a page; a group too large for one page spans consecutive
//! pages) and is self-contained: its clusters reference only the page's own vertices (a vertex used
//! by two pages is stored in both), through u16 references from the page's first vertex. The
//! mesh's vertex, reference and triangle streams are the pages' ranges concatenated in page order,
//! so the whole-mesh view ([`BuiltMesh::vertex_ref`], the verifier, the CPU oracles) is unchanged.
//!
//! Pages are ordered from the DAG's root down (groups by decreasing build iteration): the first
//! [`BuiltMesh::resident_pages`] pages hold every group simplified at or after the fallback level,
//! the always-resident part from which the mesh can always be drawn.
//!
//! A page's bytes ([`page_bytes`], what a `.vgeo` file stores per page and the GPU's geometry pool
//! holds per page slot) are its streams one after another, each 4-byte aligned: positions
//! (2 x u32 per vertex), normals (u32), UVs (u32, meshes with UVs), materials (u16, meshes with
//! per-vertex materials, padded to 4 bytes), vertex references (u32 words), packed triangles.

use bytemuck::{Pod, Zeroable};

use super::{BuiltMesh, CLUSTER_FLAG_REFS_U32, PackedVertex};

pub use crate::shared::PAGE_BYTES;

/// A page: its ranges in the mesh's streams ([`BuiltMesh::vertices`] and `vertex_materials`,
/// [`BuiltMesh::vertex_refs`], [`BuiltMesh::triangles`]). Pages cover each stream in order,
/// without gaps.
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
    pub _pad: u32,
}
const _: () = assert!(size_of::<Page>() == 32);

/// Byte offsets of a page's streams in its bytes ([`page_bytes`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct PageLayout {
    pub positions: usize,
    pub normals: usize,
    /// Equal to `materials` when the mesh has no UVs.
    pub uvs: usize,
    /// Equal to `refs` when the mesh has no per-vertex materials.
    pub materials: usize,
    pub refs: usize,
    pub triangles: usize,
    /// Total bytes.
    pub len: usize,
}

/// The layout of a page of `vertex_count` vertices, `ref_words` reference words and
/// `triangle_bytes` triangle bytes.
pub fn layout(
    vertex_count: usize,
    ref_words: usize,
    triangle_bytes: usize,
    has_uvs: bool,
    has_materials: bool,
) -> PageLayout {
    let positions = 0;
    let normals = positions + 8 * vertex_count;
    let uvs = normals + 4 * vertex_count;
    let materials = uvs + if has_uvs { 4 * vertex_count } else { 0 };
    let refs = materials
        + if has_materials {
            (2 * vertex_count).next_multiple_of(4)
        } else {
            0
        };
    let triangles = refs + 4 * ref_words;
    PageLayout {
        positions,
        normals,
        uvs,
        materials,
        refs,
        triangles,
        len: triangles + triangle_bytes,
    }
}

impl Page {
    /// The layout of the page's bytes for a mesh with or without UVs and per-vertex materials.
    pub fn layout(&self, has_uvs: bool, has_materials: bool) -> PageLayout {
        layout(
            self.vertex_count as usize,
            self.ref_words as usize,
            self.triangle_bytes as usize,
            has_uvs,
            has_materials,
        )
    }
}

impl BuiltMesh {
    /// Whether the pages hold a material per vertex: the mesh has more than one material
    /// (`vertex_materials` then has one entry per vertex, else none).
    pub fn has_material_stream(&self) -> bool {
        self.materials.len() > 1
    }

    /// The layout of page `p`'s bytes.
    pub fn page_layout(&self, p: &Page) -> PageLayout {
        p.layout(self.has_uvs, self.has_material_stream())
    }
}

/// Page `p`'s bytes (see the module's documentation). Panics when the page's ranges lie outside
/// the mesh's streams (a loaded or built mesh's never do: the structure check covers them).
pub fn page_bytes(m: &BuiltMesh, p: &Page) -> Vec<u8> {
    let l = m.page_layout(p);
    let mut out = Vec::with_capacity(l.len);
    let vs = &m.vertices[p.vertex_first as usize..(p.vertex_first + p.vertex_count) as usize];
    for v in vs {
        out.extend_from_slice(bytemuck::bytes_of(&v.position));
    }
    for v in vs {
        out.extend_from_slice(&v.normal.to_le_bytes());
    }
    if m.has_uvs {
        for v in vs {
            out.extend_from_slice(&v.uv.to_le_bytes());
        }
    }
    if m.has_material_stream() {
        let mats = &m.vertex_materials
            [p.vertex_first as usize..(p.vertex_first + p.vertex_count) as usize];
        out.extend_from_slice(bytemuck::cast_slice(mats));
        out.resize(l.refs, 0);
    }
    let refs = &m.vertex_refs[p.ref_first as usize..(p.ref_first + p.ref_words) as usize];
    out.extend_from_slice(bytemuck::cast_slice(refs));
    out.extend_from_slice(
        &m.triangles[p.triangle_first as usize..(p.triangle_first + p.triangle_bytes) as usize],
    );
    debug_assert_eq!(out.len(), l.len);
    out
}

/// One page's streams, decoded from its bytes.
pub struct PageStreams {
    pub vertices: Vec<PackedVertex>,
    /// Empty when the mesh has no per-vertex materials.
    pub materials: Vec<u16>,
    pub refs: Vec<u32>,
    pub triangles: Vec<u8>,
}

/// Decodes page `p`'s bytes (the inverse of [`page_bytes`]); `None` when `bytes` does not have
/// the page's length.
pub fn decode_page(
    bytes: &[u8],
    p: &Page,
    has_uvs: bool,
    has_materials: bool,
) -> Option<PageStreams> {
    let n = p.vertex_count as usize;
    let l = p.layout(has_uvs, has_materials);
    if bytes.len() != l.len {
        return None;
    }
    let word =
        |at: usize| u32::from_le_bytes([bytes[at], bytes[at + 1], bytes[at + 2], bytes[at + 3]]);
    let vertices = (0..n)
        .map(|i| PackedVertex {
            position: [word(l.positions + 8 * i), word(l.positions + 8 * i + 4)],
            normal: word(l.normals + 4 * i),
            uv: if has_uvs { word(l.uvs + 4 * i) } else { 0 },
        })
        .collect();
    let materials = if has_materials {
        (0..n)
            .map(|i| {
                u16::from_le_bytes([bytes[l.materials + 2 * i], bytes[l.materials + 2 * i + 1]])
            })
            .collect()
    } else {
        Vec::new()
    };
    let refs = (0..p.ref_words as usize)
        .map(|i| word(l.refs + 4 * i))
        .collect();
    Some(PageStreams {
        vertices,
        materials,
        refs,
        triangles: bytes[l.triangles..].to_vec(),
    })
}

/// Bytes a page needs per vertex (positions, normals, UVs, materials before padding).
fn vertex_bytes(has_uvs: bool, has_materials: bool) -> usize {
    12 + if has_uvs { 4 } else { 0 } + if has_materials { 2 } else { 0 }
}

/// Most vertices one page may hold (its references are u16 offsets from its first vertex).
const MAX_PAGE_VERTICES: usize = 1 << 16;

/// Lays `m`'s clusters out in pages of at most `page_bytes` bytes (see the module's
/// documentation), rewriting the vertex, reference and triangle streams; the clusters, groups and
/// BVH keep their order and meaning (only where a cluster's data lies changes). Groups simplified
/// at or after iteration `resident_level` come first, in the always-resident pages. Deterministic.
pub fn paginate(m: &mut BuiltMesh, page_bytes: usize, resident_level: u32) {
    let has_materials = m.has_material_stream();
    let vbytes = vertex_bytes(m.has_uvs, has_materials);
    // Each cluster's global vertices, in local order.
    let locals: Vec<Vec<u32>> = m
        .clusters
        .iter()
        .map(|c| (0..c.vertex_count()).map(|i| m.vertex_ref(c, i)).collect())
        .collect();
    let tri_bytes = |ci: usize| {
        let c = &m.clusters[ci];
        super::packed_triangle_bytes(c.vertex_count(), c.triangle_count())
    };
    // Groups from the root down; ties in stored (BVH) order.
    let mut order: Vec<u32> = (0..m.groups.len() as u32).collect();
    order.sort_by_key(|&g| (std::cmp::Reverse(m.groups[g as usize].iteration), g));

    // Page assignment: `mark[v]` is the page (+1) that already holds vertex v.
    let nv = m.vertices.len();
    let mut mark = vec![0u32; nv];
    let mut trial = vec![0u32; nv];
    let mut trial_id = 0u32;
    let mut page_of = vec![0u32; m.clusters.len()];
    let mut pages: Vec<Vec<u32>> = vec![Vec::new()];
    let mut used = 0usize; // bytes of the current page (vertex bytes unpadded)
    let mut used_vertices = 0usize;
    let mut resident_pages = 0usize;
    // Bytes and new vertices `members` would add to the current page.
    let cost = |members: &[u32], mark: &[u32], trial: &mut [u32], trial_id: u32, page: u32| {
        let mut new_v = 0usize;
        let mut bytes = 0usize;
        for &ci in members {
            let c = &m.clusters[ci as usize];
            bytes += 4 * c.vertex_count().div_ceil(2) as usize + tri_bytes(ci as usize);
            for &v in &locals[ci as usize] {
                if mark[v as usize] != page + 1 && trial[v as usize] != trial_id {
                    trial[v as usize] = trial_id;
                    new_v += 1;
                }
            }
        }
        (bytes + new_v * vbytes, new_v)
    };
    for (k, &g) in order.iter().enumerate() {
        let grp = &m.groups[g as usize];
        let members: Vec<u32> =
            (grp.first_cluster..grp.first_cluster + grp.cluster_count).collect();
        let mut page = pages.len() as u32 - 1;
        trial_id += 1;
        let (add, new_v) = cost(&members, &mark, &mut trial, trial_id, page);
        let fits = |used: usize, uv: usize, add: usize, nv: usize| {
            used + add + 2 * (uv + nv) % 4 <= page_bytes && uv + nv <= MAX_PAGE_VERTICES
        };
        let chunks: Vec<Vec<u32>> = if fits(used, used_vertices, add, new_v) {
            vec![members]
        } else {
            if !pages[page as usize].is_empty() {
                pages.push(Vec::new());
                page += 1;
                used = 0;
                used_vertices = 0;
            }
            trial_id += 1;
            let (add, new_v) = cost(&members, &mark, &mut trial, trial_id, page);
            if fits(0, 0, add, new_v) {
                vec![members]
            } else {
                members.iter().map(|&c| vec![c]).collect()
            }
        };
        for chunk in chunks {
            trial_id += 1;
            let (add, new_v) = cost(&chunk, &mark, &mut trial, trial_id, page);
            if !fits(used, used_vertices, add, new_v) && !pages[page as usize].is_empty() {
                pages.push(Vec::new());
                page += 1;
                used = 0;
                used_vertices = 0;
            }
            trial_id += 1;
            let (add, new_v) = cost(&chunk, &mark, &mut trial, trial_id, page);
            used += add;
            used_vertices += new_v;
            for &ci in &chunk {
                page_of[ci as usize] = page;
                pages[page as usize].push(ci);
                for &v in &locals[ci as usize] {
                    mark[v as usize] = page + 1;
                }
            }
        }
        // The always-resident prefix ends with the last page holding a group at or above
        // `resident_level` (groups come in decreasing iteration).
        if grp.iteration >= resident_level || k == 0 {
            resident_pages = pages.len();
        }
    }
    drop(mark);
    drop(trial);

    // The new streams, page by page; clusters in index order within a page.
    let mut vertices = Vec::with_capacity(nv);
    let mut vmat = Vec::new();
    let mut refs = Vec::with_capacity(m.vertex_refs.len());
    let mut triangles = Vec::with_capacity(m.triangles.len());
    let mut out_pages = Vec::with_capacity(pages.len());
    let mut slot = vec![u32::MAX; nv];
    for (pi, members) in pages.iter_mut().enumerate() {
        members.sort_unstable();
        let page = Page {
            vertex_first: vertices.len() as u32,
            ref_first: refs.len() as u32,
            triangle_first: triangles.len() as u32,
            cluster_count: members.len() as u32,
            ..Default::default()
        };
        let mut local_vertices: Vec<u32> = Vec::new();
        for &ci in members.iter() {
            let c = &mut m.clusters[ci as usize];
            let src = c.triangle_offset as usize;
            let len = super::packed_triangle_bytes(c.vertex_count(), c.triangle_count());
            c.triangle_offset = triangles.len() as u32;
            triangles.extend_from_slice(&m.triangles[src..src + len]);
            c.vertex_ref_offset = refs.len() as u32;
            c.vertex_base = page.vertex_first;
            c.counts &= !(CLUSTER_FLAG_REFS_U32 << 16);
            c.page = pi as u32;
            let local: Vec<u32> = locals[ci as usize]
                .iter()
                .map(|&v| {
                    if slot[v as usize] == u32::MAX {
                        slot[v as usize] = local_vertices.len() as u32;
                        local_vertices.push(v);
                    }
                    slot[v as usize]
                })
                .collect();
            for pair in local.chunks(2) {
                refs.push(pair[0] | pair.get(1).copied().unwrap_or(0) << 16);
            }
        }
        for &v in &local_vertices {
            slot[v as usize] = u32::MAX;
            vertices.push(m.vertices[v as usize]);
            if has_materials {
                vmat.push(m.vertex_materials[v as usize]);
            }
        }
        out_pages.push(Page {
            vertex_count: local_vertices.len() as u32,
            ref_words: refs.len() as u32 - page.ref_first,
            triangle_bytes: triangles.len() as u32 - page.triangle_first,
            ..page
        });
    }
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
    fn layout_aligns_every_stream() {
        let l = layout(3, 2, 8, true, true);
        assert_eq!((l.normals, l.uvs, l.materials, l.refs), (24, 36, 48, 56));
        assert_eq!((l.triangles, l.len), (64, 72));
        let l = layout(3, 2, 8, false, false);
        assert_eq!((l.uvs, l.materials, l.refs, l.triangles), (36, 36, 36, 44));
    }
}
