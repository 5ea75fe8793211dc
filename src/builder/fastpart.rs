//! Fast, thread-safe partitioning with meshoptimizer: clusters with `meshopt_buildMeshletsFlex`
//! (triangle adjacency, spatial fallback for disconnected parts) and groups with
//! `meshopt_partitionClusters` (shared vertices, then proximity). Unlike METIS (whose random
//! generator is process-global state in GKlib, `static uint64_t mt[NN]` in `random.c`), every call
//! is deterministic and independent, so calls run in parallel without a lock.
//!
//! Adjacency is by position id (`pid`), so attribute seams (split normals / UVs / materials) do not
//! disconnect the surface; the vertex limit is re-checked on the real vertices afterwards.

use meshopt::ffi;

thread_local! {
    /// Per-thread scratch map position id -> local id (all `u32::MAX` between calls).
    static SCRATCH: std::cell::RefCell<Vec<u32>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Compacts `tris` (global vertex indices) to local ids of their position ids: returns the local
/// index buffer and, per local id, its position.
fn local_pid_mesh(
    tris: &[[u32; 3]],
    pid: &[u32],
    pid_pos: &[[f32; 3]],
) -> (Vec<u32>, Vec<[f32; 3]>) {
    SCRATCH.with(|cell| {
        let mut map = cell.borrow_mut();
        if map.len() < pid_pos.len() {
            map.resize(pid_pos.len(), u32::MAX);
        }
        let mut idx = Vec::with_capacity(tris.len() * 3);
        let mut uniq: Vec<u32> = Vec::new();
        for &v in tris.iter().flatten() {
            let p = pid[v as usize] as usize;
            if map[p] == u32::MAX {
                map[p] = uniq.len() as u32;
                uniq.push(p as u32);
            }
            idx.push(map[p]);
        }
        for &p in &uniq {
            map[p as usize] = u32::MAX;
        }
        let pos = uniq.iter().map(|&p| pid_pos[p as usize]).collect();
        (idx, pos)
    })
}

/// Unique vertices of the triangles `part` of `tris` (marks in a per-thread scratch map).
fn vertex_count(tris: &[[u32; 3]], part: &[u32]) -> usize {
    SCRATCH.with(|cell| {
        let mut seen = cell.borrow_mut();
        let mut verts: Vec<u32> = Vec::with_capacity(part.len() * 3);
        for &t in part {
            for v in tris[t as usize] {
                if seen.len() <= v as usize {
                    seen.resize(v as usize + 1, u32::MAX);
                }
                if seen[v as usize] == u32::MAX {
                    seen[v as usize] = 0;
                    verts.push(v);
                }
            }
        }
        for &v in &verts {
            seen[v as usize] = u32::MAX;
        }
        verts.len()
    })
}

/// Splits triangles (global vertex indices) into clusters of at most `max_tris` triangles and
/// `max_verts` unique vertices; returns triangle indices per cluster, in a deterministic order.
/// `clustering` picks meshoptimizer's clusterizer (see [`Clustering`]).
pub(crate) fn cluster_triangles(
    tris: &[[u32; 3]],
    pid: &[u32],
    pid_pos: &[[f32; 3]],
    max_tris: usize,
    max_verts: usize,
    clustering: Clustering,
) -> Vec<Vec<u32>> {
    if tris.is_empty() {
        return Vec::new();
    }
    let all: Vec<u32> = (0..tris.len() as u32).collect();
    if tris.len() <= max_tris && vertex_count(tris, &all) <= max_verts {
        return vec![all];
    }
    let (idx, pos) = local_pid_mesh(tris, pid, pid_pos);
    let parts = meshlets(&idx, &pos, max_tris, max_verts.min(256), clustering);
    let mut out = Vec::with_capacity(parts.len());
    for part in parts {
        if vertex_count(tris, &part) <= max_verts {
            out.push(part);
        } else {
            // Attribute seams made the real vertex count exceed the limit: split on real vertices.
            split_real(tris, part, max_tris, max_verts, &mut out);
        }
    }
    out
}

/// Greedy split of `part` (in its order, which is spatially coherent) into pieces that fit.
fn split_real(
    tris: &[[u32; 3]],
    part: Vec<u32>,
    max_tris: usize,
    max_verts: usize,
    out: &mut Vec<Vec<u32>>,
) {
    let mut cur: Vec<u32> = Vec::new();
    let mut verts: Vec<u32> = Vec::new();
    for t in part {
        let new: Vec<u32> = tris[t as usize]
            .iter()
            .copied()
            .filter(|v| !verts.contains(v))
            .collect();
        let mut nd = new.clone();
        nd.dedup();
        if !cur.is_empty() && (cur.len() >= max_tris || verts.len() + nd.len() > max_verts) {
            out.push(std::mem::take(&mut cur));
            verts.clear();
        }
        for v in tris[t as usize] {
            if !verts.contains(&v) {
                verts.push(v);
            }
        }
        cur.push(t);
    }
    if !cur.is_empty() {
        out.push(cur);
    }
}

/// Which meshoptimizer clusterizer [`cluster_triangles`] uses.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Clustering {
    /// `meshopt_buildMeshletsSpatial`: SAH splits, ~1.5x faster than `Flex`. `full`: only
    /// clusters of exactly the maximum size (but the last, and vertex-bound ones), which lets
    /// meshoptimizer test one split position per cluster instead of one per triangle; otherwise
    /// a cluster may hold down to a third of the maximum.
    Spatial { full: bool },
    /// `meshopt_buildMeshletsFlex`: adjacency-driven growth.
    Flex,
}

/// `meshopt_buildMeshletsFlex` (or `Spatial`) over a compact index buffer; triangle indices per
/// meshlet.
fn meshlets(
    idx: &[u32],
    pos: &[[f32; 3]],
    max_tris: usize,
    max_verts: usize,
    clustering: Clustering,
) -> Vec<Vec<u32>> {
    let min_tris = match clustering {
        Clustering::Spatial { full: true } => max_tris,
        _ => (max_tris / 3).max(1),
    };
    // SAFETY: pure function of its arguments.
    let bound = unsafe { ffi::meshopt_buildMeshletsBound(idx.len(), max_verts, min_tris) };
    let mut ml = vec![
        ffi::meshopt_Meshlet {
            vertex_offset: 0,
            triangle_offset: 0,
            vertex_count: 0,
            triangle_count: 0,
        };
        bound
    ];
    let mut mv = vec![0u32; idx.len()];
    let mut mt = vec![0u8; idx.len()];
    // SAFETY: `ml` holds the bound computed above for these limits, `mv` and `mt` hold
    // `idx.len()` elements (the documented worst case), `pos` holds `pos.len()` float3 (stride 12)
    // and every index is < pos.len(); the limits are within 3..=256 / 1..=512, min <= max.
    let n = unsafe {
        if let Clustering::Spatial { .. } = clustering {
            ffi::meshopt_buildMeshletsSpatial(
                ml.as_mut_ptr(),
                mv.as_mut_ptr(),
                mt.as_mut_ptr(),
                idx.as_ptr(),
                idx.len(),
                pos.as_ptr().cast(),
                pos.len(),
                12,
                max_verts,
                min_tris,
                max_tris,
                0.5,
            )
        } else {
            ffi::meshopt_buildMeshletsFlex(
                ml.as_mut_ptr(),
                mv.as_mut_ptr(),
                mt.as_mut_ptr(),
                idx.as_ptr(),
                idx.len(),
                pos.as_ptr().cast(),
                pos.len(),
                12,
                max_verts,
                min_tris,
                max_tris,
                0.0,
                2.0,
            )
        }
    };
    // Map meshlet triangles back to input triangles: a triangle is identified by its three local
    // ids, rotated so that the smallest comes first (meshopt keeps the winding). Triangles are
    // bucketed by their smallest id (CSR), so each lookup scans a handful of candidates.
    let rot = |t: [u32; 3]| {
        let r = (0..3).min_by_key(|&i| t[i]).unwrap_or(0);
        [t[r], t[(r + 1) % 3], t[(r + 2) % 3]]
    };
    let keys: Vec<[u32; 3]> = idx
        .chunks_exact(3)
        .map(|c| rot([c[0], c[1], c[2]]))
        .collect();
    let mut start = vec![0u32; pos.len() + 1];
    for k in &keys {
        start[k[0] as usize + 1] += 1;
    }
    for i in 0..pos.len() {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut bucket = vec![0u32; keys.len()];
    for (t, k) in keys.iter().enumerate() {
        bucket[fill[k[0] as usize] as usize] = t as u32;
        fill[k[0] as usize] += 1;
    }
    let mut used = vec![false; keys.len()];
    let mut out = Vec::with_capacity(n);
    for m in &ml[..n.min(ml.len())] {
        let mut part = Vec::with_capacity(m.triangle_count as usize);
        for t in 0..m.triangle_count as usize {
            let at = m.triangle_offset as usize + 3 * t;
            let tri = rot(std::array::from_fn(|k| {
                mv[m.vertex_offset as usize + mt[at + k] as usize]
            }));
            let Some(&[s0, s1]) = start.get(tri[0] as usize..tri[0] as usize + 2) else {
                continue;
            };
            // Duplicates (same ids) are told apart by taking the first unused one.
            if let Some(&c) = bucket[s0 as usize..s1 as usize]
                .iter()
                .find(|&&c| !used[c as usize] && keys[c as usize] == tri)
            {
                used[c as usize] = true;
                part.push(c);
            }
        }
        if !part.is_empty() {
            out.push(part);
        }
    }
    // Anything meshopt dropped (it should not) goes into extra clusters.
    let rest: Vec<u32> = (0..keys.len() as u32)
        .filter(|&t| !used[t as usize])
        .collect();
    for c in rest.chunks(max_tris.max(1)) {
        out.push(c.to_vec());
    }
    out
}

/// Partitions clusters (their triangles in global vertex indices) into groups of about `target`
/// clusters (at most `group_max`); returns indices into `clusters` per group, each sorted, groups in
/// a deterministic order.
pub(crate) fn group_clusters(
    clusters: &[&[[u32; 3]]],
    pid: &[u32],
    pid_pos: &[[f32; 3]],
    target: usize,
    group_max: usize,
) -> Vec<Vec<u32>> {
    let n = clusters.len();
    if n <= group_max {
        return vec![(0..n as u32).collect()];
    }
    let mut idx: Vec<u32> = Vec::new();
    let mut counts: Vec<u32> = Vec::with_capacity(n);
    for c in clusters {
        counts.push((c.len() * 3) as u32);
        idx.extend(c.iter().flatten().map(|&v| pid[v as usize]));
    }
    // partitionClusters may exceed its target by a third.
    let target = target.min(group_max * 3 / 4).max(1);
    let mut dest = vec![0u32; n];
    // SAFETY: `dest` has one element per cluster, `counts` sums to `idx.len()`, every index is a
    // position id < pid_pos.len(), and `pid_pos` holds tightly packed float3 (stride 12).
    let parts = unsafe {
        ffi::meshopt_partitionClusters(
            dest.as_mut_ptr(),
            idx.as_ptr(),
            idx.len(),
            counts.as_ptr(),
            n,
            pid_pos.as_ptr().cast(),
            pid_pos.len(),
            12,
            target,
        )
    };
    let last = parts.max(1) - 1;
    let mut groups: Vec<Vec<u32>> = vec![Vec::new(); last + 1];
    for (c, &p) in dest.iter().enumerate() {
        groups[(p as usize).min(last)].push(c as u32);
    }
    let mut out = Vec::with_capacity(groups.len());
    for g in groups {
        if g.len() > group_max {
            for c in g.chunks(group_max) {
                out.push(c.to_vec());
            }
        } else if !g.is_empty() {
            out.push(g);
        }
    }
    out
}
