//! The build: input preparation, level-0 clusters, the group/simplify/split loop, assembly.

use std::collections::HashMap;

use rayon::prelude::*;

use super::cluster::cluster_triangles as metis_cluster_triangles;
use super::fastpart::Clustering;
use super::group::group_clusters as metis_group_clusters;
use super::quantize::{
    decode_normal, decode_position, decode_uv, encode_normal, encode_position, encode_uv,
    make_quantization,
};
use super::simplify::{Attributes, Mode, Pieces, Simplified, simplify, simplify_compacted};
use super::solid::positive_pieces;
use super::{
    BuildError, BuildOptions, BuildStats, BuiltMesh, CLUSTER_FLAG_REFS_U32, Cluster, Group,
    LevelStats, NO_GROUP, PackedVertex, Partitioner, Sphere,
};
use super::{uf_find, uf_union};
use crate::hash::FxBuild;
use crate::mesh::Mesh;
use crate::shared::{MAX_CLUSTER_LEVEL, MAX_CLUSTER_TRIANGLES, MAX_CLUSTER_VERTICES};

/// Builds the cluster DAG of `mesh`. Deterministic: the same input gives the same result whatever
/// the thread count.
pub fn build(mesh: &Mesh, opts: &BuildOptions) -> Result<BuiltMesh, BuildError> {
    build_with_progress(mesh, opts, &|_| {})
}

/// [`build`] with a progress callback, called with a short line per phase / iteration.
pub fn build_with_progress(
    mesh: &Mesh,
    opts: &BuildOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<BuiltMesh, BuildError> {
    check_options(opts)?;
    match opts.threads {
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .map_err(|e| BuildError::Threads(e.to_string()))?;
            pool.install(|| build_inner(mesh, opts, progress))
        }
        None => build_inner(mesh, opts, progress),
    }
}

fn check_options(o: &BuildOptions) -> Result<(), BuildError> {
    let bad = |s: String| Err(BuildError::InvalidOptions(s));
    if o.max_cluster_triangles < 4 || o.max_cluster_triangles > MAX_CLUSTER_TRIANGLES {
        return bad(format!(
            "max_cluster_triangles {} not in 4..={MAX_CLUSTER_TRIANGLES}",
            o.max_cluster_triangles
        ));
    }
    if o.group_min < 2 || o.group_max < o.group_min || o.group_max > 1024 {
        return bad(format!(
            "group sizes {}..{} invalid (need 2 <= min <= max <= 1024)",
            o.group_min, o.group_max
        ));
    }
    if !(o.simplify_ratio > 0.05 && o.simplify_ratio < 0.95) {
        return bad(format!(
            "simplify_ratio {} not in (0.05, 0.95)",
            o.simplify_ratio
        ));
    }
    if !(o.keep_percent > 0.0 && o.keep_percent <= 100.0) {
        return bad(format!("keep_percent {} not in (0, 100]", o.keep_percent));
    }
    for (name, w) in [
        ("normal_weight", o.normal_weight),
        ("uv_weight", o.uv_weight),
    ] {
        if !(w >= 0.0 && w.is_finite()) {
            return bad(format!("{name} {w} must be finite and >= 0"));
        }
    }
    if let Some(b) = o.position_bits
        && !(1..=super::quantize::POSITION_BITS).contains(&b)
    {
        return bad(format!(
            "position_bits {b} not in 1..={}",
            super::quantize::POSITION_BITS
        ));
    }
    if !(2..=super::quantize::NORMAL_BITS).contains(&o.normal_bits) {
        return bad(format!(
            "normal_bits {} not in 2..={}",
            o.normal_bits,
            super::quantize::NORMAL_BITS
        ));
    }
    if !(o.trim_error >= 0.0 && o.trim_error.is_finite()) {
        return bad(format!(
            "trim_error {} must be finite and >= 0",
            o.trim_error
        ));
    }
    Ok(())
}

/// `owner` of a point no working cluster uses, and of one used by several groups (locked).
const NONE: u32 = u32::MAX;
const MULTI: u32 = u32::MAX - 1;

/// Triangles per level-0 chunk clustered independently (meshoptimizer partitioner). Smaller
/// chunks cost fewer SAH levels; at 4096 the level-0 bounds were as tight in sum as at 16384
/// (lucy: 0.98x the summed squared radii, bunny 1.0x), at 2048 and 1024 looser (1.10x, 1.32x).
const LEVEL0_CHUNK: usize = 4096;

/// Working cluster during the build.
#[derive(Clone)]
struct WCluster {
    tris: Vec<[u32; 3]>,
    self_error: f32,
    /// The position-and-attribute part of `self_error` (the bound that adds up along a chain).
    pos_error: f32,
    /// The coverage part of `self_error`: the largest coverage error along its chain (at most
    /// `self_error`; what a small instance's weight leaves whole, `BuiltMesh::group_coverage`).
    coverage: f32,
    self_sphere: Sphere,
    creator: u32,
    level: u32,
    group: u32,
}

struct WGroup {
    members: Vec<u32>,
    error: f32,
    coverage: f32,
    sphere: Sphere,
    iteration: u32,
}

/// Result of one group's simplification.
struct Outcome {
    parts: Vec<Vec<[u32; 3]>>,
    error: f32,
    pos_error: f32,
    coverage: f32,
    sphere: Sphere,
    fallback: bool,
    /// Made from the root chain's source ([`ChainSource`]), not from the members.
    from_source: bool,
}

/// Records a simplified group: its members point to it, its parts become clusters of the next
/// level (created by it, with its error and sphere); returns the new clusters' indices.
fn commit_group(
    clusters: &mut Vec<WCluster>,
    groups: &mut Vec<WGroup>,
    members: Vec<u32>,
    out: Outcome,
    iteration: u32,
) -> Vec<u32> {
    let gid = groups.len() as u32;
    for &m in &members {
        clusters[m as usize].group = gid;
    }
    let mut created = Vec::with_capacity(out.parts.len());
    for part in out.parts {
        created.push(clusters.len() as u32);
        clusters.push(WCluster {
            tris: part,
            self_error: out.error,
            pos_error: out.pos_error,
            coverage: out.coverage,
            self_sphere: out.sphere,
            creator: gid,
            level: iteration + 1,
            group: NO_GROUP,
        });
    }
    groups.push(WGroup {
        members,
        error: out.error,
        coverage: out.coverage,
        sphere: out.sphere,
        iteration,
    });
    created
}

/// Input after quantization and welding.
struct Prepared {
    vertices: Vec<PackedVertex>,
    materials: Vec<u16>,
    positions: Vec<[f32; 3]>,
    pid: Vec<u32>,
    /// Position of each position id.
    pid_pos: Vec<[f32; 3]>,
    tris: Vec<[u32; 3]>,
    dropped: usize,
    duplicates: usize,
    /// The grid the DAG is built on (welding and simplification).
    quant: super::Quantization,
    /// The grid the pages store (the mesh's stated precision): `quant` or a coarser one over the
    /// same box ([`snap_to_stored_grid`]).
    stored_quant: super::Quantization,
}

/// Edge lengths of (up to 2^16 evenly spaced) input triangles: the median (0 for none) and the
/// [`super::quantize::SHORT_EDGE_QUANTILE`] quantile of the edges longer than 0 (0 for none).
fn edge_lengths(mesh: &Mesh) -> (f64, f64) {
    let tris = mesh.indices.len() / 3;
    let stride = (tris >> 16).max(1);
    let p = |i: u32| mesh.positions[i as usize].map(|x| x as f64);
    // Squared lengths, selected by their bits: for finite non-negative doubles the bit pattern
    // orders like the value, and the square root is monotonic, so the median length is the
    // root of the median square, the same value as selecting among the lengths (lucy: 5 ms
    // -> 2 ms on one thread). Non-finite lengths are left out: they become the largest word and
    // the median is taken among the others.
    let sampled = tris.div_ceil(stride);
    let mut squares = vec![0u64; 3 * sampled];
    squares
        .par_chunks_mut(3 * 4096)
        .enumerate()
        .for_each(|(c, out)| {
            for (i, sq) in out.chunks_exact_mut(3).enumerate() {
                let t = (c * 4096 + i) * stride;
                let idx = &mesh.indices[3 * t..3 * t + 3];
                for k in 0..3 {
                    let (a, b) = (p(idx[k]), p(idx[(k + 1) % 3]));
                    let l = (a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2);
                    sq[k] = if l.is_finite() { l.to_bits() } else { u64::MAX };
                }
            }
        });
    let finite = squares.iter().filter(|&&s| s != u64::MAX).count();
    if finite == 0 {
        return (0.0, 0.0);
    }
    let median = f64::from_bits(*squares.select_nth_unstable(finite / 2).1).sqrt();
    // The quantile among the lengths above 0 is the one `zeros` places further in the whole
    // order (the non-finite, the largest words, come last).
    let zeros = squares.iter().filter(|&&s| s == 0).count();
    if zeros == finite {
        return (median, 0.0);
    }
    let at = zeros + ((finite - zeros) as f64 * super::quantize::SHORT_EDGE_QUANTILE) as usize;
    let short = f64::from_bits(*squares.select_nth_unstable(at).1).sqrt();
    (median, short)
}

fn prepare(mesh: &Mesh, opts: &BuildOptions) -> Result<Prepared, BuildError> {
    mesh.validate().map_err(|msg| BuildError::InvalidMesh {
        name: mesh.name.clone(),
        msg,
    })?;
    // Position ids index edge keys of 31 bits per point (`undirected`).
    if mesh.positions.len() >= 1 << 31 {
        return Err(BuildError::InvalidMesh {
            name: mesh.name.clone(),
            msg: format!("{} vertices (at most 2^31 - 1)", mesh.positions.len()),
        });
    }
    if mesh.materials.len() > u16::MAX as usize {
        return Err(BuildError::InvalidMesh {
            name: mesh.name.clone(),
            msg: format!("{} materials (at most {})", mesh.materials.len(), u16::MAX),
        });
    }
    let (lo, hi) = mesh.bounds().ok_or_else(|| BuildError::Empty {
        name: mesh.name.clone(),
        dropped: 0,
    })?;
    let mut uv_lo = [f32::MAX; 2];
    let mut uv_hi = [f32::MIN; 2];
    for t in &mesh.uvs {
        for k in 0..2 {
            if t[k].is_finite() {
                uv_lo[k] = uv_lo[k].min(t[k]);
                uv_hi[k] = uv_hi[k].max(t[k]);
            }
        }
    }
    for k in 0..2 {
        if uv_lo[k] > uv_hi[k] {
            uv_lo[k] = 0.0;
            uv_hi[k] = 0.0;
        }
    }
    let extent = (0..3)
        .map(|k| hi[k] as f64 - lo[k] as f64)
        .fold(0.0f64, f64::max);
    // The stated precision (what the pages store), and the grid the DAG is built on: the
    // finer of it and the build grid (`quantize::build_position_bits`), so that a coarser
    // stated precision leaves the DAG as it is and only moves the stored positions.
    let (median, short) = edge_lengths(mesh);
    let stored_bits = opts
        .position_bits
        .unwrap_or_else(|| super::quantize::auto_position_bits(extent, short))
        .clamp(1, super::quantize::POSITION_BITS);
    let build_bits = super::quantize::build_position_bits(extent, median).max(stored_bits);
    let quant = make_quantization(lo, hi, uv_lo, uv_hi, build_bits, opts.normal_bits);
    let stored_quant = make_quantization(lo, hi, uv_lo, uv_hi, stored_bits, opts.normal_bits);
    let nv = mesh.positions.len();
    let mut key_to_vertex: HashMap<(PackedVertex, u16), u32, FxBuild> =
        HashMap::with_capacity_and_hasher(nv, FxBuild::default());
    let mut pos_to_pid: HashMap<[u32; 2], u32, FxBuild> =
        HashMap::with_capacity_and_hasher(nv, FxBuild::default());
    let mut vertices = Vec::new();
    let mut materials = Vec::new();
    let mut pid = Vec::new();
    let mut tris = Vec::with_capacity(mesh.triangle_count());
    let mut dropped = 0;
    let mut duplicates = 0;
    // Input vertices are encoded once (a vertex is used by ~6 corners).
    let encoded: Vec<PackedVertex> = mesh
        .positions
        .par_iter()
        .enumerate()
        .map(|(v, &p)| PackedVertex {
            position: encode_position(&quant, p),
            normal: encode_normal(mesh.normals[v], quant.normal_bits),
            uv: if mesh.has_uvs {
                encode_uv(&quant, mesh.uvs[v])
            } else {
                0
            },
        })
        .collect();
    // Per input vertex, the last (material, id) it was welded to: most corners hit it, so the
    // hash map is consulted about once per vertex, not once per corner. When every vertex has a
    // single material (the common case), the welding is done by sorting instead and the cache
    // answers every corner.
    let mut cache: Vec<(u16, u32)> = vec![(u16::MAX, 0); mesh.positions.len()];
    let mut welded = false;
    // The sort parallelizes; on one thread the hash map is cheaper (lucy x16: 3.4 -> 3.2 s).
    let by_sort = rayon::current_num_threads() > 1;
    if let Some(w) = by_sort.then(|| weld_by_sort(mesh, &encoded)).flatten() {
        vertices = w.vertices;
        materials = w.materials;
        pid = w.pid;
        cache = w.cache;
        welded = true;
    }
    // A triangle's points (position ids), `None` when two coincide (degenerate: dropped).
    let points = |tri: [u32; 3], pid: &[u32]| {
        let p = tri.map(|v| pid[v as usize]);
        (p[0] != p[1] && p[1] != p[2] && p[0] != p[2]).then_some(p)
    };
    if welded {
        // Every corner's vertex is in the cache: the triangles are mapped in parallel (the same
        // ids as the loop below would give, in the same order).
        let mapped: Vec<Option<[u32; 3]>> = mesh
            .indices
            .par_chunks_exact(3)
            .map(|idx| {
                let tri = [0, 1, 2].map(|k| cache[idx[k] as usize].1);
                points(tri, &pid).map(|_| tri)
            })
            .collect();
        dropped = mapped.par_iter().filter(|t| t.is_none()).count();
        // (`filter_map`, not `flatten`: rayon's flatten drives every Option as its own parallel
        // iterator, a small allocation per triangle.)
        tris = mapped.into_par_iter().filter_map(|t| t).collect();
    } else {
        for (t, idx) in mesh.indices.chunks_exact(3).enumerate() {
            let mat = mesh.material_ids[t] as u16;
            let mut tri = [0u32; 3];
            for k in 0..3 {
                let v = idx[k] as usize;
                if cache[v].0 == mat {
                    tri[k] = cache[v].1;
                    continue;
                }
                let pv = encoded[v];
                let next = vertices.len() as u32;
                let id = *key_to_vertex.entry((pv, mat)).or_insert(next);
                if id == next {
                    vertices.push(pv);
                    materials.push(mat);
                    let np = pos_to_pid.len() as u32;
                    pid.push(*pos_to_pid.entry(pv.position).or_insert(np));
                }
                cache[v] = (mat, id);
                tri[k] = id;
            }
            if points(tri, &pid).is_some() {
                tris.push(tri);
            } else {
                dropped += 1;
            }
        }
    }
    drop(cache);
    // Exact duplicates (same three points, same winding) are dropped, the first one kept: they
    // add nothing to the surface and make coincident layers that simplification cannot keep
    // consistent. A triangle's key is its point triple rotated to start at the smallest.
    let key = |tri: &[u32; 3]| {
        let p = tri.map(|v| pid[v as usize]);
        let r = (0..3).min_by_key(|&i| p[i]).unwrap_or(0);
        [p[r], p[(r + 1) % 3], p[(r + 2) % 3]]
    };
    let keys: Vec<[u32; 3]> = tris.par_iter().map(key).collect();
    let npid = pid.iter().max().map_or(0, |&m| m as usize + 1);
    let keep = first_occurrences(&keys, npid);
    drop(keys);
    duplicates += keep.iter().filter(|&&k| !k).count();
    if duplicates > 0 {
        let mut i = 0;
        tris.retain(|_| {
            i += 1;
            keep[i - 1]
        });
    }
    let positions: Vec<[f32; 3]> = vertices
        .par_iter()
        .map(|v| decode_position(&quant, v.position))
        .collect();
    let mut pid_pos = vec![[0.0f32; 3]; npid];
    for (v, &p) in pid.iter().enumerate() {
        pid_pos[p as usize] = positions[v];
    }
    Ok(Prepared {
        pid_pos,
        vertices,
        materials,
        positions,
        pid,
        tris,
        dropped,
        duplicates,
        quant,
        stored_quant,
    })
}

/// The partitioner chosen in the options, with the mesh data it needs.
#[derive(Clone, Copy)]
struct Parter<'a> {
    kind: Partitioner,
    pid: &'a [u32],
    positions: &'a [[f32; 3]],
    pid_pos: &'a [[f32; 3]],
}

impl Parter<'_> {
    /// Clusters of `tris`; `level0`: the input's clusters.
    fn clusters(
        &self,
        tris: &[[u32; 3]],
        max_tris: usize,
        max_verts: usize,
        level0: bool,
    ) -> Vec<Vec<u32>> {
        match self.kind {
            Partitioner::Meshopt | Partitioner::MeshoptFlex => super::fastpart::cluster_triangles(
                tris,
                self.pid,
                self.pid_pos,
                max_tris,
                max_verts,
                self.clustering(level0),
            ),
            Partitioner::Metis => {
                metis_cluster_triangles(tris, self.pid, self.positions, max_tris, max_verts)
            }
        }
    }

    /// meshoptimizer's clusterizer for the input's clusters (`level0`) or a group's.
    fn clustering(&self, level0: bool) -> Clustering {
        if level0 || self.kind == Partitioner::Meshopt {
            // A group's clusters are split into full clusters only (SAH at multiples of the
            // cluster size): meshoptimizer then tests a split per cluster instead of per
            // triangle, and the coarse levels get fewer clusters with tighter bounds in sum
            // (measured on lucy and bunny). Level 0 keeps the freer split: its bounds were looser
            // with full clusters only.
            Clustering::Spatial { full: !level0 }
        } else {
            Clustering::Flex
        }
    }

    /// Clusters of a group's simplified triangles `tris`, given in the group's local ids
    /// ([`Local`]): the same partition as [`Parter::clusters`] of their global form (meshoptimizer's
    /// partitioners compact by point in first-use order either way), read from the group's small
    /// arrays instead of the mesh's.
    fn group_clusters(
        &self,
        local: &Local,
        tris: &[[u32; 3]],
        max_tris: usize,
        max_verts: usize,
    ) -> Vec<Vec<u32>> {
        if self.kind == Partitioner::Metis {
            return self.clusters(&local.global(tris), max_tris, max_verts, false);
        }
        let point_pos: Vec<[f32; 3]> = local
            .points
            .iter()
            .map(|&p| self.pid_pos[p as usize])
            .collect();
        super::fastpart::cluster_triangles(
            tris,
            &local.lp,
            &point_pos,
            max_tris,
            max_verts,
            self.clustering(false),
        )
    }

    fn groups(
        &self,
        clusters: &[&[[u32; 3]]],
        centers: &dyn Fn() -> Vec<[f32; 3]>,
        target: usize,
        gmax: usize,
    ) -> Vec<Vec<u32>> {
        match self.kind {
            Partitioner::Meshopt | Partitioner::MeshoptFlex => {
                super::fastpart::group_clusters(clusters, self.pid, self.pid_pos, target, gmax)
            }
            Partitioner::Metis => {
                metis_group_clusters(clusters, &centers(), self.pid, target, gmax)
            }
        }
    }
}

/// Welding by sorting (see [`weld_by_sort`]).
struct Welded {
    vertices: Vec<PackedVertex>,
    materials: Vec<u16>,
    pid: Vec<u32>,
    /// Per input vertex: (material, welded id); `u16::MAX` material for unreferenced vertices.
    cache: Vec<(u16, u32)>,
}

/// Welds equal (encoded vertex, material) pairs by sorting, when every input vertex is used with
/// a single material (else `None`). Ids are assigned in order of first use by the corners, and
/// position ids in order of vertex creation: exactly what the hash-map path produces.
fn weld_by_sort(mesh: &Mesh, encoded: &[PackedVertex]) -> Option<Welded> {
    let nv = encoded.len();
    // Corner indices are kept as u32 below (the hash-map path takes larger meshes).
    if mesh.indices.len() > u32::MAX as usize {
        return None;
    }
    // The used vertices in order of first use, with their material (the same for every corner,
    // else `None`): one serial pass over the corners, cheaper on few threads than the parallel
    // pass with atomics and the sort by first corner it replaced.
    let mut vm = vec![u16::MAX; nv];
    let mut first: Vec<u32> = Vec::with_capacity(nv);
    for (t, idx) in mesh.indices.chunks_exact(3).enumerate() {
        let m = mesh.material_ids[t] as u16;
        for &v in idx {
            let seen = &mut vm[v as usize];
            if *seen == u16::MAX {
                *seen = m;
                first.push(v);
            } else if *seen != m {
                return None;
            }
        }
    }
    // Rank = order of first use; equal keys take the smallest rank's id.
    let mut keyed: Vec<(PackedVertex, u16, u32)> = first
        .iter()
        .enumerate()
        .map(|(r, &v)| (encoded[v as usize], vm[v as usize], r as u32))
        .collect();
    // The key orders as the tuple's derived order (position, normal, uv, material, rank), packed
    // into three u64 so that `sort_total` can radix-sort it.
    sort_total(&mut keyed, |(v, m, r)| {
        (
            (v.position[0] as u64) << 32 | v.position[1] as u64,
            (v.normal as u64) << 32 | v.uv as u64,
            (*m as u64) << 32 | *r as u64,
        )
    });
    let mut rep = vec![0u32; first.len()];
    let reps: Vec<(u32, u32)> = keyed
        .par_chunk_by(|a, b| a.0 == b.0 && a.1 == b.1)
        .flat_map_iter(|same| same.iter().map(move |e| (e.2, same[0].2)))
        .collect();
    drop(keyed);
    for (r, to) in reps {
        rep[r as usize] = to;
    }
    let mut id_of_rank = vec![0u32; first.len()];
    let mut vertices = Vec::new();
    let mut materials = Vec::new();
    for r in 0..first.len() {
        if rep[r] == r as u32 {
            id_of_rank[r] = vertices.len() as u32;
            let v = first[r] as usize;
            vertices.push(encoded[v]);
            materials.push(vm[v]);
        } else {
            id_of_rank[r] = id_of_rank[rep[r] as usize];
        }
    }
    // Position ids in order of vertex creation.
    let mut by_pos: Vec<([u32; 2], u32)> = vertices
        .iter()
        .enumerate()
        .map(|(i, v)| (v.position, i as u32))
        .collect();
    sort_total(&mut by_pos, |k| (k.0[0], k.0[1], k.1));
    let mut first_of = vec![0u32; vertices.len()];
    let mut i = 0;
    while i < by_pos.len() {
        let mut j = i + 1;
        while j < by_pos.len() && by_pos[j].0 == by_pos[i].0 {
            j += 1;
        }
        for e in &by_pos[i..j] {
            first_of[e.1 as usize] = by_pos[i].1;
        }
        i = j;
    }
    drop(by_pos);
    let mut pid = vec![0u32; vertices.len()];
    let mut next = 0u32;
    for i in 0..vertices.len() {
        if first_of[i] == i as u32 {
            pid[i] = next;
            next += 1;
        } else {
            pid[i] = pid[first_of[i] as usize];
        }
    }
    let mut cache = vec![(u16::MAX, 0u32); nv];
    for (r, &v) in first.iter().enumerate() {
        cache[v as usize] = (vm[v as usize], id_of_rank[r]);
    }
    Some(Welded {
        vertices,
        materials,
        pid,
        cache,
    })
}

/// Bounding sphere of points (box centre, farthest point).
fn points_sphere(points: impl Iterator<Item = [f32; 3]> + Clone) -> Sphere {
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for p in points.clone() {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    let c: [f32; 3] = std::array::from_fn(|k| (lo[k] + hi[k]) * 0.5);
    let mut r = 0.0f32;
    for p in points {
        r = r.max(dist(c, p));
    }
    pad_sphere(c, r)
}

fn dist(a: [f32; 3], b: [f32; 3]) -> f32 {
    (((a[0] - b[0]) as f64).powi(2)
        + ((a[1] - b[1]) as f64).powi(2)
        + ((a[2] - b[2]) as f64).powi(2))
    .sqrt() as f32
}

/// Inflates a radius so that float rounding in [`super::lod_error_px`] cannot make an enclosed sphere
/// project larger than its encloser.
fn pad_sphere(c: [f32; 3], r: f32) -> Sphere {
    let mag = c[0].abs().max(c[1].abs()).max(c[2].abs());
    let r = r * (1.0 + 1e-5) + (mag + r) * 4e-7 + f32::MIN_POSITIVE;
    [c[0], c[1], c[2], r]
}

/// A sphere enclosing all `spheres`.
fn merge_spheres(spheres: &[Sphere]) -> Sphere {
    let mut lo = [f32::MAX; 3];
    let mut hi = [f32::MIN; 3];
    for s in spheres {
        for k in 0..3 {
            lo[k] = lo[k].min(s[k] - s[3]);
            hi[k] = hi[k].max(s[k] + s[3]);
        }
    }
    let c: [f32; 3] = std::array::from_fn(|k| (lo[k] + hi[k]) * 0.5);
    let mut r = 0.0f32;
    for s in spheres {
        r = r.max(dist(c, [s[0], s[1], s[2]]) + s[3]);
    }
    pad_sphere(c, r)
}

/// Error of a group against the original surface, and its position-and-attribute part.
///
/// The part is the simplification's error (measured against the members' triangles) plus the
/// members' own part (theirs against the original): the triangle inequality's bound, as the
/// `lod` baseline's levels measure theirs against the full mesh. The error is at least that, at
/// least the simplification's coverage error (area lost against the members' triangles; not
/// summed along the chain: square roots of areas do not add up) and at least the members'
/// errors (monotonic); strictly positive, with a margin against rounding.
fn group_error(
    simplify_error: f32,
    coverage: f32,
    members_pos: f32,
    members_max: f32,
    min_error: f32,
) -> (f32, f32) {
    let pos = simplify_error + members_pos;
    let error = (pos.max(coverage).max(members_max) * (1.0 + 1.0 / 1024.0)).max(min_error);
    (error, pos)
}

/// Edges (by position id) of some triangles with their use counts each way: entries
/// `(min << 32 | max, uses min -> max, uses max -> min)`, sorted by key. Keeping both directions
/// in one entry lets every check read an edge's balance without a second lookup.
struct Edges(Vec<(u64, u32, u32)>);

impl Edges {
    /// The edges of a group's triangles in its local ids ([`Local`]): `lp` names each local
    /// vertex's point, an index into `points` (the group's position ids, ascending). Points are
    /// numbered in the order of their ids, so the edges sort like their global keys by a counting
    /// sort over the smaller point and a small sort of each point's entries, in linear time (a
    /// comparison sort of 64-bit keys was a tenth of the build, a radix sort of 32-bit keys 2 %);
    /// a group of more than 2^15 points takes the 64-bit keys.
    fn of(tris: &[[u32; 3]], lp: &[u32], points: &[u32]) -> Edges {
        let k = points.len();
        if k <= 1 << 15 {
            // A counting sort by the smaller point, then each point's few entries (its larger
            // point << 1 | forward) sorted in place (`bucket_edges`, as `Level0` does for the
            // whole mesh): the order of `(min, max, direction)`.
            let (start, mut entries) = bucket_uses(tris, |v| lp[v as usize], k);
            let mut out: Vec<(u64, u32, u32)> = Vec::with_capacity(entries.len());
            for p in 0..k {
                let a = (points[p] as u64) << 32;
                let bucket = &mut entries[start[p] as usize..start[p + 1] as usize];
                bucket_edges(bucket, |b, f, r| {
                    out.push((a | points[b as usize] as u64, f, r))
                });
            }
            Edges(out)
        } else {
            let point = |v: u32| points[lp[v as usize] as usize];
            let mut keys: Vec<u64> = Vec::with_capacity(tris.len() * 3);
            for t in tris {
                for e in 0..3 {
                    keys.push(undirected(point(t[e]), point(t[(e + 1) % 3])));
                }
            }
            Edges::from_keys(keys)
        }
    }

    /// Counts of directed edges given as `undirected(a, b)` keys.
    fn from_keys(mut keys: Vec<u64>) -> Edges {
        keys.sort_unstable();
        Edges::from_sorted(&keys)
    }

    fn from_sorted(keys: &[u64]) -> Edges {
        let mut out: Vec<(u64, u32, u32)> = Vec::with_capacity(keys.len());
        for &k in keys {
            let (key, forward) = (k >> 1, k & 1 == 1);
            if out.last().is_none_or(|l| l.0 != key) {
                out.push((key, 0, 0));
            }
            let l = out.last_mut().expect("pushed above");
            if forward {
                l.1 += 1;
            } else {
                l.2 += 1;
            }
        }
        Edges(out)
    }

    /// Uses of a -> b and of b -> a.
    fn pair(&self, a: u32, b: u32) -> (u32, u32) {
        let k = (a.min(b) as u64) << 32 | a.max(b) as u64;
        match self.0.binary_search_by_key(&k, |e| e.0) {
            Ok(i) if a <= b => (self.0[i].1, self.0[i].2),
            Ok(i) => (self.0[i].2, self.0[i].1),
            Err(_) => (0, 0),
        }
    }
}

/// The edges at one point from its bucket of directed edge uses (`other point << 1 | (the use
/// runs from the smaller point to the larger)`, the point being the smaller): sorted in place,
/// then per other point, in ascending order, `edge(other, uses min -> max, uses max -> min)`.
/// The bucketing of [`Edges::of`] and [`Level0::new`].
fn bucket_edges(bucket: &mut [u32], mut edge: impl FnMut(u32, u32, u32)) {
    bucket.sort_unstable();
    for same in bucket.chunk_by(|x, y| x >> 1 == y >> 1) {
        let f = same.iter().filter(|&&x| x & 1 == 1).count() as u32;
        edge(same[0] >> 1, f, same.len() as u32 - f);
    }
}

/// A directed edge use a -> b in the bucket of its smaller point: `larger << 1 | (a < b)`.
fn bucket_entry(a: u32, b: u32) -> u32 {
    a.max(b) << 1 | (a < b) as u32
}

/// The directed edge uses of `tris` (vertex `v` at point `point(v) < points`), bucketed by their
/// smaller point with a counting sort: point p's uses ([`bucket_entry`], in triangle order) are
/// `uses[start[p]..start[p + 1]]`. What [`Edges::of`] and [`Level0::new`] (on one thread or a
/// small mesh) sort per bucket ([`bucket_edges`]).
fn bucket_uses(
    tris: &[[u32; 3]],
    point: impl Fn(u32) -> u32,
    points: usize,
) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; points + 1];
    for t in tris {
        let p = t.map(&point);
        for e in 0..3 {
            start[p[e].min(p[(e + 1) % 3]) as usize + 1] += 1;
        }
    }
    for i in 0..points {
        start[i + 1] += start[i];
    }
    let mut cursor = start[..points].to_vec();
    let mut uses = vec![0u32; start[points] as usize];
    for t in tris {
        let p = t.map(&point);
        for e in 0..3 {
            let (a, b) = (p[e], p[(e + 1) % 3]);
            let at = &mut cursor[a.min(b) as usize];
            uses[*at as usize] = bucket_entry(a, b);
            *at += 1;
        }
    }
    (start, uses)
}

/// Sort key of the directed edge a -> b: the undirected key `min << 32 | max` shifted left
/// by one, with the low bit set when a < b (the forward direction). Position ids are below
/// 2^31 (`prepare` checks), so the key fits.
fn undirected(a: u32, b: u32) -> u64 {
    ((a.min(b) as u64) << 32 | a.max(b) as u64) << 1 | (a < b) as u64
}

/// Whether every edge of `tris` (by position id, `npid` of them) is used once in each direction:
/// no irregular edge of [`Level0`] (the closed-solid test of `builder::solid::closed_solid`).
pub(crate) fn regular_edges(tris: &[[u32; 3]], pid: &[u32], npid: usize) -> bool {
    Level0::new(tris, pid, npid).irregular.is_empty()
}

/// What the cut test compares against (verify's rules), from the level-0 triangles: the edges
/// whose directed use counts are not (1, 1) ("irregular": open borders, non-manifold and
/// duplicated edges), the points on them ("border" points) and their components.
struct Level0 {
    /// (undirected key `min << 32 | max`, uses min -> max, uses max -> min), sorted by key.
    irregular: Vec<(u64, u32, u32)>,
    border: Vec<bool>,
    /// Union-find root of each border point over the irregular edges.
    comp: Vec<u32>,
}

impl Level0 {
    fn new(tris: &[[u32; 3]], pid: &[u32], npid: usize) -> Level0 {
        use std::sync::atomic::{AtomicU32, Ordering::Relaxed};
        // The directed edge uses, bucketed by their smaller point (counting sort: one count and
        // one fill pass, in parallel), each use stored as `larger point << 1 | (from < to)`.
        // Position ids are below 2^31 (`prepare` checks), so the entry fits.
        let edges = |t: &[u32; 3]| {
            let p = t.map(|v| pid[v as usize]);
            [(p[0], p[1]), (p[1], p[2]), (p[2], p[0])]
        };
        let (start, mut uses) = if rayon::current_num_threads() == 1 || tris.len() < 1 << 18 {
            // Plain counters on one thread or a small mesh: the atomic form cost lucy (100 K
            // triangles) 7.4 ms of a 208 ms one-thread build on the device host.
            bucket_uses(tris, |v| pid[v as usize], npid)
        } else {
            let counts: Vec<AtomicU32> = (0..npid).map(|_| AtomicU32::new(0)).collect();
            tris.par_iter().for_each(|t| {
                for (a, b) in edges(t) {
                    counts[a.min(b) as usize].fetch_add(1, Relaxed);
                }
            });
            let mut start = Vec::with_capacity(npid + 1);
            let mut total = 0u32;
            start.push(0);
            for c in &counts {
                total += c.load(Relaxed);
                start.push(total);
            }
            let cursor: Vec<AtomicU32> = start[..npid].iter().map(|&s| AtomicU32::new(s)).collect();
            drop(counts);
            let slots: Vec<AtomicU32> = (0..total).map(|_| AtomicU32::new(0)).collect();
            tris.par_iter().for_each(|t| {
                for (a, b) in edges(t) {
                    let at = cursor[a.min(b) as usize].fetch_add(1, Relaxed);
                    slots[at as usize].store(bucket_entry(a, b), Relaxed);
                }
            });
            (
                start,
                slots.into_iter().map(AtomicU32::into_inner).collect(),
            )
        };
        // Per bucket (in parallel over runs of points), sorted: the uses of one undirected edge
        // are adjacent, buckets in point order, so the irregular edges come out sorted by key.
        let runs = (rayon::current_num_threads() * 8).clamp(1, npid.max(1));
        let mut pieces: Vec<(usize, &mut [u32])> = Vec::with_capacity(runs);
        let mut rest: &mut [u32] = &mut uses;
        let mut first = 0usize;
        for k in 1..=runs {
            let end = npid * k / runs;
            let len = (start[end] - start[first]) as usize;
            let (head, tail) = rest.split_at_mut(len);
            pieces.push((first, head));
            rest = tail;
            first = end;
        }
        let irregular: Vec<(u64, u32, u32)> = pieces
            .into_par_iter()
            .enumerate()
            .flat_map_iter(|(k, (first, piece))| {
                let end = npid * (k + 1) / runs;
                let base = start[first] as usize;
                let mut out = Vec::new();
                for a in first..end {
                    let bucket = &mut piece[start[a] as usize - base..start[a + 1] as usize - base];
                    bucket_edges(bucket, |b, f, r| {
                        if (f, r) != (1, 1) {
                            out.push(((a as u64) << 32 | b as u64, f, r));
                        }
                    });
                }
                out
            })
            .collect();
        drop(uses);
        let mut border = vec![false; npid];
        let mut comp: Vec<u32> = (0..npid as u32).collect();
        for &(k, _, _) in &irregular {
            let (a, b) = ((k >> 32) as u32, k as u32);
            border[a as usize] = true;
            border[b as usize] = true;
            uf_union(&mut comp, a, b);
        }
        for x in 0..npid as u32 {
            comp[x as usize] = uf_find(&mut comp, x);
        }
        Level0 {
            irregular,
            border,
            comp,
        }
    }

    /// Uses of a -> b and b -> a in the level-0 triangles, when not (1, 1); `None` for a regular
    /// edge (used once each way) or an absent one, both balanced.
    fn counts(&self, a: u32, b: u32) -> Option<(u32, u32)> {
        let k = (a.min(b) as u64) << 32 | a.max(b) as u64;
        let i = self.irregular.binary_search_by_key(&k, |e| e.0).ok()?;
        let (_, f, r) = self.irregular[i];
        Some(if a < b { (f, r) } else { (r, f) })
    }

    /// Whether a cut may use a -> b `f` times and b -> a `r` times (verify's rule): balanced,
    /// as in the input, or once between two points of one open border.
    fn allows(&self, a: u32, b: u32, f: u32, r: u32) -> bool {
        f == r
            || self.counts(a, b) == Some((f, r))
            || (f + r == 1
                && self.border[a as usize]
                && self.border[b as usize]
                && self.comp[a as usize] == self.comp[b as usize])
    }
}

/// A group's triangles in local ids, made once per group so that every later pass (shape, edges,
/// simplification, degenerate triangles) reads small arrays that stay in cache, instead of
/// looking up each corner's global vertex and position id in mesh-sized maps (those misses
/// were about a tenth of a one-thread build).
struct Local {
    /// The distinct global vertices, in first-use order ([`super::simplify::compact`]).
    verts: Vec<u32>,
    /// The triangles as indices into `verts`, flat.
    indices: Vec<u32>,
    /// The group's position ids, ascending.
    points: Vec<u32>,
    /// Per local vertex, its point (an index into `points`).
    lp: Vec<u32>,
}

impl Local {
    fn new(tris: &[[u32; 3]], pid: &[u32], nverts: usize) -> Local {
        let (verts, indices) = super::simplify::compact(tris, nverts);
        let vpid: Vec<u32> = verts.iter().map(|&v| pid[v as usize]).collect();
        let mut points = vpid.clone();
        radsort::sort(&mut points);
        points.dedup();
        let lp = vpid
            .iter()
            .map(|p| points.binary_search(p).expect("a point of the group") as u32)
            .collect();
        Local {
            verts,
            indices,
            points,
            lp,
        }
    }

    fn tris(&self) -> &[[u32; 3]] {
        bytemuck::cast_slice(&self.indices)
    }

    /// Whether some point has several vertices (an attribute seam), and whether the triangles
    /// form more than one connected piece (through shared points): a union-find over the
    /// triangles, each point recording the first triangle that uses it.
    fn shape(&self) -> (bool, bool) {
        let seam = self.verts.len() != self.points.len();
        let tris = self.tris();
        let mut parent: Vec<u32> = (0..tris.len() as u32).collect();
        let mut owner = vec![NONE; self.points.len()];
        for (ti, t) in tris.iter().enumerate() {
            for &v in t {
                let o = &mut owner[self.lp[v as usize] as usize];
                if *o == NONE {
                    *o = ti as u32;
                } else {
                    let first = *o;
                    uf_union(&mut parent, first, ti as u32);
                }
            }
        }
        let pieces = (0..tris.len() as u32)
            .filter(|&t| uf_find(&mut parent, t) == t)
            .count();
        (seam, pieces > 1)
    }

    /// Per local vertex, the first local vertex at its point (see `Pieces::FirstOfPosition`).
    fn first_of_position(&self) -> Vec<u32> {
        super::simplify::first_of_points(self.lp.iter().copied())
    }

    /// `tris` (local ids) in global vertex indices.
    fn global(&self, tris: &[[u32; 3]]) -> Vec<[u32; 3]> {
        tris.iter()
            .map(|t| t.map(|v| self.verts[v as usize]))
            .collect()
    }
}

/// Sorts `v` by `key`, which orders it totally (or equal keys are equal elements): a radix sort
/// on one thread (a fraction of a comparison sort's instructions), rayon's parallel sort on more
/// (the radix sort is serial: on two threads it left one idle, lucy x16 built in x1.32 of the
/// issue-11 base's time against x1.16 with the parallel sort, H100 host, session 15). The same
/// order either way, so the build does not depend on the thread count.
fn sort_total<T: Send + Copy, K: radsort::Key + Ord>(v: &mut [T], key: impl Fn(&T) -> K + Sync) {
    if rayon::current_num_threads() == 1 {
        radsort::sort_by_key(v, key);
    } else {
        v.par_sort_unstable_by_key(key);
    }
}

/// Sorts `v`, which is already in order of what `full` adds to `prefix`, by `full` (a total
/// order, as [`sort_total`]): on one thread a stable radix sort by `prefix` alone, fewer passes
/// for the same order; on more, rayon's parallel sort by `full`.
fn sort_by_prefix<T: Send + Copy, P: radsort::Key, K: Ord>(
    v: &mut [T],
    prefix: impl Fn(&T) -> P,
    full: impl Fn(&T) -> K + Sync,
) {
    if rayon::current_num_threads() == 1 {
        radsort::sort_by_key(v, prefix);
    } else {
        v.par_sort_unstable_by_key(full);
    }
}

/// `tris` without the triangles that have two corners at one point (`pid`: a vertex's point; the
/// mesh's position ids, or a group's `Local::lp`).
fn drop_degenerate(tris: &mut Vec<[u32; 3]>, pid: &[u32]) {
    tris.retain(|t| {
        let p = [pid[t[0] as usize], pid[t[1] as usize], pid[t[2] as usize]];
        p[0] != p[1] && p[1] != p[2] && p[0] != p[2]
    });
}

fn build_inner(
    mesh: &Mesh,
    opts: &BuildOptions,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<BuiltMesh, BuildError> {
    let prep = prepare(mesh, opts)?;
    let Prepared {
        vertices,
        materials: vmat,
        positions,
        pid,
        pid_pos,
        mut tris,
        dropped,
        duplicates,
        quant,
        stored_quant,
    } = prep;
    let input_triangles = mesh.triangle_count();
    if tris.is_empty() {
        return Err(BuildError::Empty {
            name: mesh.name.clone(),
            dropped,
        });
    }
    let extent = (quant.step * ((1u64 << quant.position_bits) - 1) as f64) as f32;
    let min_error = (extent * 1e-6).max(1e-30);
    let max_tris = opts.max_cluster_triangles as usize;
    let max_verts = MAX_CLUSTER_VERTICES as usize;
    // The attributes the simplifier weighs (decoded from what the file stores): the normal, and
    // the UV when the mesh has UVs.
    let decode_uv_of = |v: usize| decode_uv(&quant, vertices[v].uv);
    let (attr_values, attr_weights) = super::simplify::attribute_values(
        vertices.len(),
        &|v| decode_normal(vertices[v].normal, quant.normal_bits),
        mesh.has_uvs
            .then_some(&decode_uv_of as &(dyn Fn(usize) -> [f32; 2] + Sync)),
        opts.normal_weight,
        opts.uv_weight,
    );
    let attrs = Attributes {
        values: &attr_values,
        stride: attr_weights.len(),
        weights: &attr_weights,
    };
    let attrs = Some(&attrs);

    // Optional trimming of the input (UE Nanite's "Trim Relative Error" and "Keep Triangle
    // Percent"): first every detail whose removal costs less than `trim_error` x the bounding-box
    // diagonal, then, if more than `keep_percent` of the triangles remain, down to that count.
    // Both reduce: the result satisfies the stricter of the two.
    let mut trimmed_error = 0.0f32;
    if opts.trim_error > 0.0 {
        let (lo, hi) = mesh.bounds().unwrap_or(([0.0; 3], [0.0; 3]));
        let diag = dist(lo, hi);
        let r = simplify(
            &tris,
            &positions,
            Pieces::ByPid(&pid),
            attrs,
            &|_| false,
            0,
            opts.trim_error * diag,
            Mode::Locked,
        );
        let e = r.combined();
        let mut t = r.tris;
        drop_degenerate(&mut t, &pid);
        if !t.is_empty() && t.len() < tris.len() {
            tris = t;
            trimmed_error = e;
        }
    }
    if opts.keep_percent < 100.0 {
        let target =
            ((input_triangles as f64 * opts.keep_percent as f64 / 100.0).round() as usize).max(1);
        if tris.len() > target {
            let r = simplify(
                &tris,
                &positions,
                Pieces::ByPid(&pid),
                attrs,
                &|_| false,
                target,
                f32::MAX,
                Mode::Locked,
            );
            let e = r.combined();
            let mut t = r.tris;
            drop_degenerate(&mut t, &pid);
            if !t.is_empty() && t.len() < tris.len() {
                tris = t;
                trimmed_error = trimmed_error.max(e);
            }
        }
    }
    let level0_triangles = tris.len();
    let npid = pid.iter().copied().max().map_or(0, |m| m as usize + 1);
    let level0 = Level0::new(&tris, &pid, npid);
    let closed_solid = level0.irregular.is_empty() && positive_pieces(&tris, &pid, &pid_pos);
    progress(&format!(
        "{}: {} triangles, clustering level 0",
        mesh.name,
        tris.len()
    ));

    let parter = Parter {
        kind: opts.partitioner,
        pid: &pid,
        positions: &positions,
        pid_pos: &pid_pos,
    };
    // Level-0 clusters. With meshoptimizer, big inputs are cut into spatially compact chunks
    // (runs of the Morton order of triangle centroids) clustered in parallel; the chunking
    // depends on the input only, so the result does not depend on the thread count.
    let chunks: Vec<Vec<u32>> =
        if opts.partitioner != Partitioner::Metis && tris.len() > 2 * LEVEL0_CHUNK {
            let centroids: Vec<[f32; 3]> = tris
                .par_iter()
                .map(|t| {
                    let (a, b, c) = (
                        positions[t[0] as usize],
                        positions[t[1] as usize],
                        positions[t[2] as usize],
                    );
                    std::array::from_fn(|k| (a[k] + b[k] + c[k]) / 3.0)
                })
                .collect();
            let codes = super::cluster::morton_codes(&centroids);
            // (code, index) pairs sort without an indirection per comparison; the order is that
            // of (code, index), as before.
            let mut keyed: Vec<(u64, u32)> = codes
                .par_iter()
                .enumerate()
                .map(|(i, &c)| (c, i as u32))
                .collect();
            drop(codes);
            sort_by_prefix(&mut keyed, |k| k.0, |&k| k);
            let order: Vec<u32> = keyed.par_iter().map(|k| k.1).collect();
            drop(keyed);
            let n = order.len().div_ceil(LEVEL0_CHUNK);
            (0..n)
                .map(|k| order[k * order.len() / n..(k + 1) * order.len() / n].to_vec())
                .collect()
        } else {
            vec![(0..tris.len() as u32).collect()]
        };
    let clusters: Vec<WCluster> = chunks
        .par_iter()
        .map(|chunk| {
            let ct: Vec<[u32; 3]> = chunk.iter().map(|&i| tris[i as usize]).collect();
            parter
                .clusters(&ct, max_tris, max_verts, true)
                .into_iter()
                .map(|part| {
                    let t: Vec<[u32; 3]> = part.iter().map(|&i| ct[i as usize]).collect();
                    let sphere = points_sphere(t.iter().flatten().map(|&v| positions[v as usize]));
                    WCluster {
                        tris: t,
                        self_error: 0.0,
                        pos_error: 0.0,
                        coverage: 0.0,
                        self_sphere: sphere,
                        creator: NO_GROUP,
                        level: 0,
                        group: NO_GROUP,
                    }
                })
                .collect::<Vec<_>>()
        })
        .collect::<Vec<_>>()
        .into_iter()
        .flatten()
        .collect();
    drop(tris);
    progress(&format!(
        "{}: level 0: {} clusters",
        mesh.name,
        clusters.len()
    ));

    let lc = LevelCtx {
        mesh,
        parter,
        positions: &positions,
        attrs,
        pid: &pid,
        npid,
        min_error,
        level0: &level0,
    };
    // A step ratio other than CHAIN_STEP_RATIO takes that ratio's root chain: its source, and the
    // sizes of the levels made from it, come from the levels at CHAIN_STEP_RATIO, made from the
    // same level 0 (docs/architecture.md, "The root chain at any ratio").
    let preset = if opts.simplify_ratio != CHAIN_STEP_RATIO {
        let shadow = BuildOptions {
            simplify_ratio: CHAIN_STEP_RATIO,
            ..opts.clone()
        };
        progress(&format!(
            "{}: the root chain's source at step ratio {CHAIN_STEP_RATIO}",
            mesh.name
        ));
        // Should the levels at that ratio fail (a group stuck where the build's own ratio is
        // not), the build makes its own chain, as before session 36.
        match run_levels(&lc, clusters.clone(), &shadow, None, &|_| {}) {
            // A mesh of at most CHAIN_SOURCE_TRIANGLES is its own source at every ratio (its
            // whole-mesh levels keep the DAG's step): nothing to take.
            Ok(l) => l.chain_source.filter(|s| !s.is_input),
            Err(e) => {
                progress(&format!(
                    "{}: no root chain source at step ratio {CHAIN_STEP_RATIO} ({e}): the \
                     build's own",
                    mesh.name
                ));
                None
            }
        }
    } else {
        None
    };
    let Levels {
        mut clusters,
        mut groups,
        working,
        levels,
        widened,
        fallback_groups,
        ..
    } = run_levels(&lc, clusters, opts, preset, progress)?;
    let root = working[0];
    // The root's pseudo-group: parent error infinite.
    let root_sphere = clusters[root as usize].self_sphere;
    clusters[root as usize].group = groups.len() as u32;
    groups.push(WGroup {
        members: vec![root],
        error: f32::INFINITY,
        coverage: f32::INFINITY,
        sphere: root_sphere,
        iteration: u32::MAX,
    });

    let stats = BuildStats {
        input_triangles,
        degenerate_dropped: dropped,
        duplicates_dropped: duplicates,
        level0_triangles,
        level0_error: trimmed_error,
        closed_solid: Some(closed_solid),
        vertices: vertices.len(),
        levels,
        widened_iterations: widened,
        fallback_groups,
        ..Default::default()
    };
    // Positions moved to a coarser stored grid may make two vertices equal (near-coincident
    // ones, which the build grid kept apart): the pages then tell vertices apart by value, as
    // the loader's decoding does (by index, such a page decoded to fewer vertices than its
    // record said, and the file was refused).
    let snapped = stored_quant.position_bits < quant.position_bits;
    let (mut built, sizes) = assemble(
        mesh,
        quant,
        stored_quant,
        vertices,
        vmat,
        &positions,
        clusters,
        groups,
        stats,
    );
    progress("paging");
    let resident_level = built.fallback_level(opts.fallback_triangles);
    super::page::paginate_sized(
        &mut built,
        super::page::PAGE_BYTES as usize,
        resident_level,
        &sizes,
        !snapped,
    );
    Ok(built)
}

/// The mesh data the levels are made from (shared by the runs at two ratios).
#[derive(Clone, Copy)]
struct LevelCtx<'a> {
    mesh: &'a Mesh,
    parter: Parter<'a>,
    positions: &'a [[f32; 3]],
    attrs: Option<&'a Attributes<'a>>,
    pid: &'a [u32],
    npid: usize,
    min_error: f32,
    level0: &'a Level0,
}

/// What [`run_levels`] made.
struct Levels {
    clusters: Vec<WCluster>,
    groups: Vec<WGroup>,
    /// The root (one cluster).
    working: Vec<u32>,
    levels: Vec<LevelStats>,
    widened: Vec<u32>,
    fallback_groups: usize,
    /// The root chain's source; made by this run (no `preset`), with [`ChainSource::steps`].
    chain_source: Option<ChainSource>,
}

/// The levels above level 0 (`clusters`) at `opts`' step ratio, to the root: groups simplified
/// level by level, then the root chain; `preset`: the root chain's source, given from a run at
/// [`CHAIN_STEP_RATIO`].
fn run_levels(
    lc: &LevelCtx,
    mut clusters: Vec<WCluster>,
    opts: &BuildOptions,
    preset: Option<ChainSource>,
    progress: &(dyn Fn(&str) + Sync),
) -> Result<Levels, BuildError> {
    let LevelCtx {
        mesh,
        parter,
        positions,
        attrs,
        pid,
        npid,
        min_error,
        level0,
    } = *lc;
    let own_source = preset.is_none();
    let mut groups: Vec<WGroup> = Vec::new();
    let mut working: Vec<u32> = (0..clusters.len() as u32).collect();
    let mut chain_source: Option<ChainSource> = preset;
    // Without a preset: the triangles of the source's level and of each level made from the
    // source after it, while they are (`ChainSource::steps`); `None` before the source.
    let mut steps: Option<Vec<usize>> = None;
    let mut steps_open = true;
    let mut levels = vec![level_stats(0, &working, &clusters, 0, 0, 0)];
    let mut widened = Vec::new();
    let mut fallback_groups = 0;
    let mut iteration = 0u32;
    let mut widen = 1usize;
    let group_target =
        ((opts.group_min as usize) * 2).clamp(opts.group_min as usize, opts.group_max as usize);

    while working.len() > 1 {
        // A level has 8 bits in the cull words (MAX_CLUSTER_LEVEL); the next would be iteration + 1.
        if iteration >= MAX_CLUSTER_LEVEL {
            return Err(stuck(mesh, iteration, &working, &clusters));
        }
        let gmax = (opts.group_max as usize).saturating_mul(widen);
        let member_groups: Vec<Vec<u32>> = {
            let tri_refs: Vec<&[[u32; 3]]> = working
                .iter()
                .map(|&c| clusters[c as usize].tris.as_slice())
                .collect();
            let centers = || -> Vec<[f32; 3]> {
                working
                    .iter()
                    .map(|&c| {
                        let s = clusters[c as usize].self_sphere;
                        let t = &clusters[c as usize].tris;
                        let n = (t.len() * 3) as f32;
                        let mut m = [0.0f32; 3];
                        for &v in t.iter().flatten() {
                            for k in 0..3 {
                                m[k] += positions[v as usize][k] / n;
                            }
                        }
                        if m.iter().all(|x| x.is_finite()) {
                            m
                        } else {
                            [s[0], s[1], s[2]]
                        }
                    })
                    .collect()
            };
            parter
                .groups(&tri_refs, &centers, group_target * widen, gmax)
                .into_iter()
                .map(|g| g.into_iter().map(|i| working[i as usize]).collect())
                .collect()
        };
        let single = member_groups.len() == 1;
        // Locks: position ids used by more than one group. In parallel over the groups: a
        // point ends as its one group or MULTI whatever the order of the writes.
        let owner: Vec<u32> = {
            use std::sync::atomic::{AtomicU32, Ordering::Relaxed};
            let owner: Vec<AtomicU32> = (0..npid).map(|_| AtomicU32::new(NONE)).collect();
            member_groups.par_iter().enumerate().for_each(|(gi, g)| {
                let gi = gi as u32;
                for &c in g {
                    for &v in clusters[c as usize].tris.iter().flatten() {
                        let o = &owner[pid[v as usize] as usize];
                        let mut cur = o.load(Relaxed);
                        while cur != gi && cur != MULTI {
                            let new = if cur == NONE { gi } else { MULTI };
                            match o.compare_exchange_weak(cur, new, Relaxed, Relaxed) {
                                Ok(_) => break,
                                Err(now) => cur = now,
                            }
                        }
                    }
                }
            });
            owner.into_iter().map(AtomicU32::into_inner).collect()
        };
        // Use counts of the edges between two locked points (see `unsafe_changes`).
        let shared = {
            let mut keys: Vec<u64> = working
                .par_iter()
                .flat_map_iter(|&c| {
                    let (owner, pid) = (&owner, &pid);
                    clusters[c as usize].tris.iter().flat_map(move |t| {
                        let p = t.map(|v| pid[v as usize]);
                        (0..3).filter_map(move |e| {
                            let (a, b) = (p[e], p[(e + 1) % 3]);
                            (owner[a as usize] == MULTI && owner[b as usize] == MULTI)
                                .then(|| undirected(a, b))
                        })
                    })
                })
                .collect();
            sort_total(&mut keys, |&k| k);
            Edges::from_sorted(&keys)
        };
        // The first level of at most CHAIN_SOURCE_TRIANGLES: the root chain's source.
        if chain_source.is_none() {
            chain_source = ChainSource::of(&working, &clusters, iteration);
            steps = chain_source.as_ref().map(|s| vec![s.tris.len()]);
        }
        let level_tris = triangle_count(&working, &clusters);
        let ctx = GroupCtx {
            // A level of one group (the whole mesh) simplifies the source too, as the root chain,
            // when the source is coarser than the input (a small mesh keeps the DAG's step) and
            // not far coarser than the DAG's own step would make (a source given from the default
            // ratio: at most half of that, so that no level drops much more than a step).
            source: chain_source.as_ref().filter(|s| {
                single
                    && !s.is_input
                    && s.tris.len() as f32 >= 0.5 * opts.simplify_ratio * level_tris as f32
            }),
            parter,
            clusters: &clusters,
            positions,
            attrs,
            pid,
            owner: &owner,
            opts,
            min_error,
            single,
            speculate: rayon::current_num_threads() / member_groups.len().max(1),
            level0,
            shared: &shared,
        };
        let outcomes: Vec<Option<Outcome>> = member_groups
            .par_iter()
            .map(|g| ctx.simplify_group(g))
            .collect();
        let from_source = outcomes
            .iter()
            .all(|o| o.as_ref().is_some_and(|o| o.from_source));
        let mut next = Vec::new();
        let mut progressed = false;
        let mut stuck_groups = 0;
        let level = iteration + 1;
        for (g, out) in member_groups.into_iter().zip(outcomes) {
            match out {
                Some(out) => {
                    progressed = true;
                    fallback_groups += out.fallback as usize;
                    next.extend(commit_group(&mut clusters, &mut groups, g, out, iteration));
                }
                None => {
                    stuck_groups += 1;
                    next.extend(g);
                }
            }
        }
        let ngroups = groups.iter().filter(|g| g.iteration == iteration).count() + stuck_groups;
        if !progressed {
            if single {
                return Err(stuck(mesh, iteration, &working, &clusters));
            }
            widened.push(iteration);
            widen *= 2;
        } else {
            widen = 1;
        }
        let prev = levels.last().map_or(0, |l| l.triangles);
        let mut st = level_stats(level, &next, &clusters, prev, ngroups, stuck_groups);
        st.level = level;
        progress(&format!(
            "{}: level {level}: {} clusters, {} triangles ({} groups, {} stuck)",
            mesh.name, st.clusters, st.triangles, ngroups, stuck_groups
        ));
        record_step(&mut steps, &mut steps_open, from_source, st.triangles);
        levels.push(st);
        working = next;
        iteration += 1;
    }
    // Root chain: simplify the single cluster further (a group of one, nothing to lock) while it
    // is above `root_triangles` and simplification still removes triangles into one cluster.
    let owner = vec![NONE; npid];
    let shared = Edges(Vec::new());
    if chain_source.is_none() {
        chain_source = ChainSource::of(&working, &clusters, iteration);
        steps = chain_source.as_ref().map(|s| vec![s.tris.len()]);
    }
    while (opts.root_triangles as usize) > 0
        && clusters[working[0] as usize].tris.len() > opts.root_triangles as usize
        && iteration < MAX_CLUSTER_LEVEL
    {
        let top = working[0];
        let ctx = GroupCtx {
            source: chain_source.as_ref(),
            parter,
            clusters: &clusters,
            positions,
            attrs,
            pid,
            owner: &owner,
            opts,
            min_error,
            single: true,
            speculate: rayon::current_num_threads(),
            level0,
            shared: &shared,
        };
        let Some(out) = ctx.simplify_group(&[top]) else {
            break;
        };
        let n = clusters[top as usize].tris.len();
        let [part] = out.parts.as_slice() else {
            break;
        };
        if part.is_empty() || part.len() >= n {
            break;
        }
        fallback_groups += out.fallback as usize;
        let from_source = out.from_source;
        let level = iteration + 1;
        working = commit_group(&mut clusters, &mut groups, vec![top], out, iteration);
        let prev = levels.last().map_or(0, |l| l.triangles);
        let mut st = level_stats(level, &working, &clusters, prev, 1, 0);
        st.level = level;
        progress(&format!(
            "{}: level {level}: root chain, {} triangles",
            mesh.name, st.triangles
        ));
        record_step(&mut steps, &mut steps_open, from_source, st.triangles);
        levels.push(st);
        iteration += 1;
    }
    if own_source && let Some(s) = chain_source.as_mut() {
        // The source's level and those made from it: the chain another ratio steps onto.
        s.steps = steps.unwrap_or_default();
    }
    Ok(Levels {
        clusters,
        groups,
        working,
        levels,
        widened,
        fallback_groups,
        chain_source,
    })
}

/// Records a new level of `triangles` in the root chain's `steps` (see [`run_levels`]) while
/// every level after the source's was made from the source.
fn record_step(
    steps: &mut Option<Vec<usize>>,
    open: &mut bool,
    from_source: bool,
    triangles: usize,
) {
    if let Some(v) = steps.as_mut().filter(|_| *open) {
        if from_source {
            v.push(triangles);
        } else {
            *open = false;
        }
    }
}

/// Per key (a triangle's point triple, rotated to start at its smallest point id, all below
/// `npid`), whether no earlier key equals it. Keys are bucketed by their first point (a counting
/// sort, stable in key order) and compared within a bucket: linear time, and far fewer cache
/// misses than a hash set of all keys (which took 4 % of a one-thread build of 1.6 M triangles).
fn first_occurrences(keys: &[[u32; 3]], npid: usize) -> Vec<bool> {
    let mut start = vec![0u32; npid + 1];
    for k in keys {
        start[k[0] as usize + 1] += 1;
    }
    for i in 0..npid {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut order = vec![0u32; keys.len()];
    for (i, k) in keys.iter().enumerate() {
        let f = &mut fill[k[0] as usize];
        order[*f as usize] = i as u32;
        *f += 1;
    }
    drop(fill);
    let mut keep = vec![true; keys.len()];
    let mut big: Vec<([u32; 3], u32)> = Vec::new();
    for b in 0..npid {
        let bucket = &order[start[b] as usize..start[b + 1] as usize];
        if bucket.len() <= 16 {
            // Small buckets (almost all): each key against the earlier ones.
            for j in 1..bucket.len() {
                let kj = keys[bucket[j] as usize];
                if bucket[..j].iter().any(|&i| keys[i as usize] == kj) {
                    keep[bucket[j] as usize] = false;
                }
            }
        } else {
            // A point of high valence: sort its keys (then their order) and compare neighbours.
            big.clear();
            big.extend(bucket.iter().map(|&i| (keys[i as usize], i)));
            big.sort_unstable();
            for w in big.windows(2) {
                if w[0].0 == w[1].0 {
                    keep[w[1].1 as usize] = false;
                }
            }
        }
    }
    keep
}

fn stuck(mesh: &Mesh, iteration: u32, working: &[u32], clusters: &[WCluster]) -> BuildError {
    BuildError::Stuck {
        name: mesh.name.clone(),
        iteration,
        clusters: working.len(),
        triangles: triangle_count(working, clusters),
    }
}

/// The triangles of clusters `ids`.
fn triangle_count(ids: &[u32], clusters: &[WCluster]) -> usize {
    ids.iter().map(|&c| clusters[c as usize].tris.len()).sum()
}

/// The triangles of clusters `ids`, in order.
fn triangles_of(ids: &[u32], clusters: &[WCluster]) -> Vec<[u32; 3]> {
    ids.iter()
        .flat_map(|&c| clusters[c as usize].tris.iter().copied())
        .collect()
}

/// The largest position error of clusters `ids`.
fn max_pos_error(ids: &[u32], clusters: &[WCluster]) -> f32 {
    ids_max(ids, clusters, |c| c.pos_error)
}

/// The largest `f` of clusters `ids` (0 for none).
fn ids_max(ids: &[u32], clusters: &[WCluster], f: impl Fn(&WCluster) -> f32) -> f32 {
    ids.iter()
        .map(|&c| f(&clusters[c as usize]))
        .fold(0.0, f32::max)
}

fn level_stats(
    level: u32,
    working: &[u32],
    clusters: &[WCluster],
    prev: usize,
    groups: usize,
    stuck: usize,
) -> LevelStats {
    let triangles = triangle_count(working, clusters);
    LevelStats {
        level,
        clusters: working.len(),
        triangles,
        ratio: if prev > 0 {
            triangles as f32 / prev as f32
        } else {
            1.0
        },
        max_error: working
            .iter()
            .map(|&c| clusters[c as usize].self_error)
            .fold(0.0, f32::max),
        groups,
        stuck_groups: stuck,
    }
}

struct GroupCtx<'a> {
    /// The root chain's source ([`ChainSource`]): a chain step, and a whole-mesh level of a mesh
    /// whose source is not its input (and not far coarser than the DAG's own step would make,
    /// `run_levels`), simplifies it, not its members.
    source: Option<&'a ChainSource>,
    parter: Parter<'a>,
    clusters: &'a [WCluster],
    positions: &'a [[f32; 3]],
    attrs: Option<&'a Attributes<'a>>,
    pid: &'a [u32],
    owner: &'a [u32],
    opts: &'a BuildOptions,
    min_error: f32,
    single: bool,
    /// How many of a group's first attempts it may simplify at once, in parallel, before the
    /// usual sequence (the threads per group this iteration; below 2, none). More than the
    /// spare threads made a one-group level slower: on two threads, nine attempts where the
    /// first one was taken cost 3 ms of bunny's 75.
    speculate: usize,
    level0: &'a Level0,
    /// Use counts of the working set's edges between two shared points.
    shared: &'a Edges,
}

impl GroupCtx<'_> {
    /// Points of the edges whose use counts this group's result changes in a way that some cut
    /// could not match (verify's rule: in every cut, each edge is used as often each way, or as
    /// in the input, or once between two points of one open border). A cut's count of an edge
    /// is its input count plus the changes of the groups applied in it. An edge with a point
    /// that only this group uses (at this iteration) is used by this group alone: its new count
    /// must pass the rule. An edge between two shared points may be used and changed by several
    /// groups, in any combination: it may change only by as many uses each way, and only while
    /// the working set uses it as often each way, so that every combination stays balanced.
    /// (A balanced change of an edge that another group uses unbalanced, e.g. the open border
    /// of a part touching this group's part at two points, shows in a cut as an edge used
    /// once one way and twice the other.)
    fn unsafe_changes(&self, in_e: &Edges, out_e: &Edges) -> Vec<u32> {
        let multi = |p: u32| self.owner[p as usize] == MULTI;
        let mut bad = Vec::new();
        let (a, b) = (&in_e.0, &out_e.0);
        let (mut i, mut j) = (0, 0);
        while i < a.len() || j < b.len() {
            let k = match (a.get(i), b.get(j)) {
                (Some(x), Some(y)) => x.0.min(y.0),
                (Some(x), None) => x.0,
                (None, Some(y)) => y.0,
                (None, None) => break,
            };
            let take = |v: &[(u64, u32, u32)], at: &mut usize| match v.get(*at) {
                Some(e) if e.0 == k => {
                    *at += 1;
                    (e.1, e.2)
                }
                _ => (0, 0),
            };
            let ((fi, ri), (fo, ro)) = (take(a, &mut i), take(b, &mut j));
            if (fi, ri) == (fo, ro) {
                continue;
            }
            // Both rules read the same with the edge's ends swapped, so one check covers both
            // directions.
            let (x, y) = ((k >> 32) as u32, k as u32);
            let ok = if multi(x) && multi(y) {
                let (sf, sr) = self.shared.pair(x, y);
                sf == sr && fo as i64 - fi as i64 == ro as i64 - ri as i64
            } else {
                self.level0.allows(x, y, fo, ro)
            };
            if !ok {
                bad.push(x);
                bad.push(y);
            }
        }
        bad
    }

    /// The group `members` simplified: from the source when there is one ([`Self::source`]);
    /// a whole-mesh level (several members) that cannot be made from it takes the DAG's step
    /// from its members instead, with its last resort (a root chain step has none: it ends).
    fn simplify_group(&self, members: &[u32]) -> Option<Outcome> {
        self.simplify_from(members, self.source).or_else(|| {
            (self.source.is_some() && members.len() > 1)
                .then(|| self.simplify_from(members, None))
                .flatten()
        })
    }

    fn simplify_from(&self, members: &[u32], source: Option<&ChainSource>) -> Option<Outcome> {
        // `n`: the members' triangles, which a result must have fewer of; from a source (the
        // whole mesh, at a finer level or given from CHAIN_STEP_RATIO's levels) the target is
        // `ChainSource::target`: CHAIN_RATIO of them, or the next of the given levels.
        let n = triangle_count(members, self.clusters);
        let (tris, target): (Vec<[u32; 3]>, usize) = match source {
            Some(src) => (src.tris.clone(), src.target(n)),
            None => (
                triangles_of(members, self.clusters),
                ((n as f32 * self.opts.simplify_ratio) as usize).max(1),
            ),
        };
        let locked = |v: u32| self.owner[self.pid[v as usize] as usize] == MULTI;
        let members_max = members
            .iter()
            .map(|&m| self.clusters[m as usize].self_error)
            .fold(0.0, f32::max);
        let spheres: Vec<Sphere> = members
            .iter()
            .map(|&m| self.clusters[m as usize].self_sphere)
            .collect();
        let sphere = merge_spheres(&spheres);
        let max_tris = self.opts.max_cluster_triangles as usize;
        let max_verts = MAX_CLUSTER_VERTICES as usize;
        // An attempt is taken when it removes at least 15 % of the triangles. The last group
        // (nothing to regroup with) takes any reduction, but only when no attempt (before
        // sloppy) reaches 15 %: the first such result is kept as a candidate, so that a group
        // that barely shrinks with its seams kept collapses across them instead of adding a
        // level of nearly the same triangles.
        let strict = |t: &Vec<[u32; 3]>| !t.is_empty() && (t.len() as f32) <= n as f32 * 0.85;
        let lenient = |t: &Vec<[u32; 3]>| self.single && !t.is_empty() && t.len() < n;
        let mut candidate = None;
        // Attempts in order; the second locks the group's open borders too (non-manifold and
        // open-border input can otherwise fold a border edge onto another).
        // The last group (nothing to regroup with) also tries gentler targets before sloppy.
        let local = Local::new(&tris, self.pid, self.positions.len());
        let (seams, pieces) = local.shape();
        let mut attempts = vec![(Mode::Locked, false, target), (Mode::Locked, true, target)];
        // Pruning removes whole connected pieces: of a group in one piece it leaves nothing.
        if pieces {
            attempts.push((Mode::LockedPrune, true, target));
        }
        // A group that cannot shrink with its attribute seams kept (material borders: the
        // coarse levels of a mesh with many materials are little else) may collapse across
        // them; only where the group has seams (a point with several vertices), else the
        // attempts would repeat the ones above.
        if seams {
            attempts.push((Mode::Permissive, false, target));
            attempts.push((Mode::Permissive, true, target));
        }
        if self.single {
            attempts.push((Mode::Locked, true, n * 3 / 4));
            attempts.push((Mode::Locked, true, n * 9 / 10));
            // Sloppy with the open borders locked first: holes and open parts keep their
            // borders, so the result stays crack-free where an unlocked one would not.
            attempts.push((Mode::Sloppy, true, target));
            attempts.push((Mode::Sloppy, false, target));
        }
        let in_edges = Edges::of(local.tris(), &local.lp, &local.points);
        // Open-border / non-manifold points of the group (computed when first needed).
        // Open-border / non-manifold points of the group.
        let border: Vec<u32> = {
            let mut b = Vec::new();
            for &(k, f, r) in &in_edges.0 {
                if f != r {
                    b.push((k >> 32) as u32);
                    b.push(k as u32);
                }
            }
            b.sort_unstable();
            b.dedup();
            b
        };
        let locked_border = |v: u32| border.binary_search(&self.pid[v as usize]).is_ok();
        // With threads to spare (few groups this iteration), the first `speculate` attempts are
        // simplified at once, before any fold has locked more points; the sequence below takes
        // these results while no fold has (the same inputs give the same result), so the output
        // is the same as without, in the time of the slowest attempt rather than their sum.
        let first_of_position = if pieces {
            local.first_of_position()
        } else {
            Vec::new()
        };
        // One attempt: the group's locks, the open borders when asked, and `extra` points. Its
        // triangles are in the group's local ids.
        let run = |mode: Mode, lock_border: bool, goal: usize, extra: &[u32]| {
            let lock = |v: u32| {
                locked(v)
                    || (lock_border && locked_border(v))
                    || extra.binary_search(&self.pid[v as usize]).is_ok()
            };
            simplify_compacted(
                &local.verts,
                &local.indices,
                self.positions,
                if pieces {
                    Pieces::FirstOfPosition(&first_of_position)
                } else {
                    Pieces::One
                },
                self.attrs,
                &lock,
                goal,
                f32::MAX,
                mode,
            )
        };
        let mut speculated: Vec<Option<Simplified>> = vec![None; attempts.len()];
        if self.speculate >= 2 {
            let k = self.speculate.min(attempts.len());
            attempts[..k]
                .par_iter()
                .map(|&(mode, lock_border, goal)| Some(run(mode, lock_border, goal, &[])))
                .collect_into_vec(&mut speculated);
            speculated.resize(attempts.len(), None);
        }
        let mut result = None;
        // Position ids locked because an attempt folded edges at them (grows per round).
        let mut extra: Vec<u32> = Vec::new();
        let mut rounds = 0;
        let mut attempt_rounds = 0;
        let mut i = 0;
        while i < attempts.len() {
            let (mode, lock_border, goal) = attempts[i];
            if mode == Mode::Sloppy && candidate.is_some() {
                break;
            }
            if mode == Mode::Sloppy && attempt_rounds == 0 {
                // Vertex clustering starts from the group's own locks: the points locked by the
                // edge-collapse attempts' folds would leave it nothing to cluster.
                extra.clear();
            }
            let r = match speculated[i].take() {
                Some(r) if extra.is_empty() => r,
                _ => run(mode, lock_border, goal, &extra),
            };
            let (mut t, e) = (r.tris, (r.error, r.coverage));
            drop_degenerate(&mut t, &local.lp);
            if !(strict(&t) || candidate.is_none() && lenient(&t)) {
                // Too little reduction to be taken, folds or not; locking a fold's points for
                // another round would only reduce less, and so would the same attempt with the
                // open borders locked too.
                i += 1;
                attempt_rounds = 0;
                if !lock_border && attempts.get(i) == Some(&(mode, true, goal)) {
                    i += 1;
                }
                continue;
            }
            // No overlap (verify's rule): an edge used more than once in one direction must be
            // balanced by the other direction or be used exactly as in the input; otherwise it
            // is a fold, visible in every cut that shows it.
            let out_edges = Edges::of(&t, &local.lp, &local.points);
            let mut folded: Vec<u32> = out_edges
                .0
                .iter()
                .filter(|&&(k, f, r)| {
                    (f > 1 || r > 1)
                        && f != r
                        && (f, r) != in_edges.pair((k >> 32) as u32, k as u32)
                })
                .flat_map(|&(k, _, _)| [(k >> 32) as u32, k as u32])
                .collect();
            if folded.is_empty() {
                folded = self.unsafe_changes(&in_edges, &out_edges);
            }
            if folded.is_empty() {
                if strict(&t) {
                    result = Some((t, e, i > 0 || rounds > 0));
                    break;
                }
                if candidate.is_none() && lenient(&t) {
                    candidate = Some((t, e, i > 0 || rounds > 0));
                }
            } else if attempt_rounds < 8 {
                // Lock the fold's vertices and their input neighbours, and retry.
                folded.sort_unstable();
                folded.dedup();
                for tri in local.tris() {
                    let p = tri.map(|v| local.points[local.lp[v as usize] as usize]);
                    if p.iter().any(|x| folded.binary_search(x).is_ok()) {
                        extra.extend_from_slice(&p);
                    }
                }
                extra.extend(folded);
                extra.sort_unstable();
                extra.dedup();
                rounds += 1;
                attempt_rounds += 1;
                continue;
            }
            i += 1;
            attempt_rounds = 0;
        }
        if result.is_none() {
            result = candidate;
        }
        if result.is_none() && self.single {
            // Last resort: everything fits in one cluster; merge without simplifying.
            let fits = source.is_none() && n <= max_tris && {
                let mut v: Vec<u32> = tris.iter().flatten().copied().collect();
                v.sort_unstable();
                v.dedup();
                v.len() <= max_verts
            };
            if fits && members.len() > 1 {
                result = Some((local.tris().to_vec(), (0.0, 0.0), true));
            }
        }
        let (t, e, fallback) = result?;
        // The error is measured against what was simplified: the source, when there is one.
        let members_pos = match source {
            Some(src) => src.pos_error,
            None => max_pos_error(members, self.clusters),
        };
        let (error, pos_error) = group_error(e.0, e.1, members_pos, members_max, self.min_error);
        // A level made from the source is at least the source's level in error and coverage (a
        // source given from CHAIN_STEP_RATIO's levels: the errors there; made from the build's
        // own source level, its members, these change nothing).
        let (error, members_coverage) = match source {
            Some(src) => (error.max(src.error), src.coverage),
            None => (error, 0.0),
        };
        // The coverage part: not summed (see group_error), the members' at least.
        let coverage = members
            .iter()
            .map(|&m| self.clusters[m as usize].coverage)
            .fold(e.1.max(members_coverage), f32::max)
            .min(error);
        let parts = self
            .parter
            .group_clusters(&local, &t, max_tris, max_verts)
            .into_iter()
            .map(|p| {
                p.iter()
                    .map(|&i| t[i as usize].map(|v| local.verts[v as usize]))
                    .collect()
            })
            .collect();
        Some(Outcome {
            parts,
            error,
            pos_error,
            coverage,
            sphere,
            fallback,
            from_source: source.is_some(),
        })
    }
}

/// The root chain (a single cluster simplified further, each step a level of one cluster) steps
/// by this ratio, finer than the DAG's: a small instance's cut lies on the chain, and finer steps
/// give it a cut nearer the threshold (docs/architecture.md, "The root chain").
const CHAIN_RATIO: f32 = 0.7;
/// The root chain simplifies the first level of at most this many triangles ([`ChainSource`]).
const CHAIN_SOURCE_TRIANGLES: usize = 2048;
/// The step ratio whose levels give the root chain its source, whatever the build's own ratio
/// (docs/architecture.md, "The root chain at any ratio").
const CHAIN_STEP_RATIO: f32 = 0.5;

/// The root chain's source: the whole mesh at the first level of at most
/// [`CHAIN_SOURCE_TRIANGLES`] triangles, and its position error. Each chain step simplifies it
/// (not the chain's last cluster), so a step's position error is the source's plus that one
/// simplification's, not the sum of every step's along the chain: the sum grew with the number
/// of steps and made finer steps draw more triangles at the same error (session 33). A build at
/// a step ratio other than [`CHAIN_STEP_RATIO`] takes the source of a build at that ratio
/// (`build_inner`), so that its chain is that build's (session 36).
struct ChainSource {
    tris: Vec<[u32; 3]>,
    pos_error: f32,
    /// The source level's largest error and coverage error (its clusters' `self_error` and
    /// `coverage`): a level made from the source has at least these.
    error: f32,
    coverage: f32,
    /// Whether the source is the mesh's input (level 0).
    is_input: bool,
    /// Given from [`CHAIN_STEP_RATIO`]'s levels: the triangles of the source's level and of each
    /// level after it that was made from the source, while they were; empty for the build's own
    /// source.
    steps: Vec<usize>,
}

impl ChainSource {
    /// The triangle target of a level made from the source after a level of `n` triangles:
    /// CHAIN_RATIO of them; with `steps`, the next of them that is at most 0.85 `n` (a step
    /// must remove 15 %, `simplify_from`): its target is CHAIN_RATIO of the one before it (the
    /// source itself when it is the first), so that simplifying the source to it makes the very
    /// level that build made (the same source and target), and the levels after it follow that
    /// build's as far as `steps` goes; past them, CHAIN_RATIO of `n`.
    fn target(&self, n: usize) -> usize {
        let step = |m: usize| ((m as f32 * CHAIN_RATIO) as usize).max(1);
        match self.steps.iter().position(|&c| c as f32 <= 0.85 * n as f32) {
            Some(0) => self.tris.len(),
            Some(k) => step(self.steps[k - 1]),
            None => step(n),
        }
    }

    /// The source, when the level `working` (the whole mesh) has at most
    /// [`CHAIN_SOURCE_TRIANGLES`] triangles.
    fn of(working: &[u32], clusters: &[WCluster], level: u32) -> Option<Self> {
        (triangle_count(working, clusters) <= CHAIN_SOURCE_TRIANGLES).then(|| ChainSource {
            tris: triangles_of(working, clusters),
            pos_error: max_pos_error(working, clusters),
            error: ids_max(working, clusters, |c| c.self_error),
            coverage: ids_max(working, clusters, |c| c.coverage),
            is_input: level == 0,
            steps: Vec::new(),
        })
    }
}

/// The box of the positions with grid codes `codes`, its corners as the GPU computes them from a
/// page's cull words ([`super::quantize::grid_corner`]): it holds every vertex the GPU decodes,
/// and a page stores it exactly as the smallest coordinates and the extents.
fn grid_box(
    quant: &super::Quantization,
    codes: impl Iterator<Item = [u32; 2]>,
) -> ([f32; 3], [f32; 3]) {
    let mut lo = [u32::MAX; 3];
    let mut hi = [0u32; 3];
    for code in codes {
        let c = super::quantize::position_coords(code);
        for k in 0..3 {
            lo[k] = lo[k].min(c[k]);
            hi[k] = hi[k].max(c[k]);
        }
    }
    (
        super::quantize::grid_corner(quant, lo),
        super::quantize::grid_corner(quant, hi),
    )
}

/// Moves `vertices` from the build grid `from` to the stored grid `to` (the same box, at most as
/// many bits per axis; [`super::quantize::regrid_position`]): a position moves by at most half a
/// step of `to`. Equal codes stay equal, so a vertex clusters share stays shared (the cut stays
/// crack-free), and the DAG built on `from` is kept. Returns the moved positions, decoded (`None`
/// when the grids are the same).
fn snap_to_stored_grid(
    from: &super::Quantization,
    to: &super::Quantization,
    vertices: &mut [PackedVertex],
) -> Option<Vec<[f32; 3]>> {
    if to.position_bits >= from.position_bits {
        return None;
    }
    vertices
        .par_iter_mut()
        .for_each(|v| v.position = super::quantize::regrid_position(from, to, v.position));
    Some(
        vertices
            .par_iter()
            .map(|v| super::quantize::decode_position(to, v.position))
            .collect(),
    )
}

#[allow(clippy::too_many_arguments)]
fn assemble(
    mesh: &Mesh,
    build_quant: super::Quantization,
    quant: super::Quantization,
    mut vertices: Vec<PackedVertex>,
    vmat: Vec<u16>,
    positions: &[[f32; 3]],
    wclusters: Vec<WCluster>,
    wgroups: Vec<WGroup>,
    mut stats: BuildStats,
) -> (BuiltMesh, Vec<usize>) {
    // From here on the mesh is at its stated precision: bounds, boxes and pages come from the
    // stored positions.
    let stored_positions = snap_to_stored_grid(&build_quant, &quant, &mut vertices);
    let positions = stored_positions.as_deref().unwrap_or(positions);
    // Group bounds, then the BVH, which fixes the order of the groups (each leaf's groups
    // contiguous); clusters are stored by member group so that a group's members are contiguous.
    let pre: Vec<Group> = wgroups
        .par_iter()
        .map(|g| {
            let (lo, hi) = grid_box(
                &quant,
                g.members
                    .iter()
                    .flat_map(|&m| wclusters[m as usize].tris.iter().flatten())
                    .map(|&v| vertices[v as usize].position),
            );
            Group {
                lod_sphere: g.sphere,
                bounds_min: lo,
                error: g.error,
                bounds_max: hi,
                first_cluster: 0,
                cluster_count: g.members.len() as u32,
                iteration: g.iteration,
                page_first: 0,
                page_count: 0,
            }
        })
        .collect();
    let (bvh, gorder) = super::bvh::build_bvh(&pre);
    let mut new_gid = vec![0u32; wgroups.len()];
    for (ni, &og) in gorder.iter().enumerate() {
        new_gid[og as usize] = ni as u32;
    }
    let mut new_index = vec![0u32; wclusters.len()];
    let mut order = Vec::with_capacity(wclusters.len());
    let mut groups = Vec::with_capacity(wgroups.len());
    let mut group_coverage = Vec::with_capacity(wgroups.len());
    for &og in &gorder {
        let first = order.len() as u32;
        for &m in &wgroups[og as usize].members {
            new_index[m as usize] = order.len() as u32;
            order.push(m);
        }
        let mut g = pre[og as usize];
        g.first_cluster = first;
        groups.push(g);
        group_coverage.push(wgroups[og as usize].coverage);
    }
    let mut bvh = bvh;
    super::bvh::set_max_parent_coverage(&mut bvh, &group_coverage);
    // Per cluster (in parallel): local vertices in first-use order, packed local indices,
    // vertex references, bounds; then concatenated in order.
    let nverts = vertices.len();
    let one_material = mesh.materials.len() <= 1;
    // (`BuiltMesh::has_material_stream`: a material per vertex only with several materials.)
    let has_mats = !one_material;
    let packed: Vec<(Cluster, Vec<u32>, Vec<u8>, usize)> = order
        .par_iter()
        .map(|&ci| {
            let w = &wclusters[ci as usize];
            // The local vertices and the canonical triangle order the page's triangle code
            // needs, in the order that codes the triangles in the fewest words.
            // (A triangle whose corners have several materials keeps its first corner, whose
            // material is the triangle's.)
            // (With one material, every triangle may rotate.)
            let material = |v: u32| vmat.get(v as usize).copied();
            let (local, local_tris) = super::tricode::stored_order(&w.tris, nverts, &|t| {
                one_material || material(t[0]) == material(t[1]) && material(t[0]) == material(t[2])
            });
            let (lo, hi) = grid_box(&quant, local.iter().map(|&v| vertices[v as usize].position));
            let local_idx: Vec<u8> = local_tris.iter().flatten().map(|&l| l as u8).collect();
            // Its encoded bytes in a page (`page::paginate`'s sizes, from what is at hand here).
            let coded: Vec<(PackedVertex, u16)> = local
                .iter()
                .map(|&v| {
                    let m = if has_mats { vmat[v as usize] } else { 0 };
                    (vertices[v as usize], m)
                })
                .collect();
            let bytes = super::page::cluster_bytes(&coded, &local_tris, mesh.has_uvs, has_mats);
            let mut tri_bytes = Vec::new();
            super::pack_indices(&local_idx, local.len() as u32, &mut tri_bytes);
            // Full u32 references until `page::paginate` gives each page its own u16 ones.
            let refs = local.clone();
            let flags = CLUSTER_FLAG_REFS_U32;
            let size = super::size::cluster_size_code(
                w.tris.iter().map(|t| t.map(|v| positions[v as usize])),
                lo,
                hi,
            );
            let g = &wgroups[w.group as usize];
            let cluster = Cluster {
                self_sphere: w.self_sphere,
                parent_sphere: g.sphere,
                bounds_min: lo,
                self_error: w.self_error,
                bounds_max: hi,
                parent_error: g.error,
                vertex_ref_offset: 0,
                data_offset: 0,
                triangle_offset: 0,
                counts: local.len() as u32 | (w.tris.len() as u32) << 8 | flags << 16 | size << 24,
                group: new_gid[w.group as usize],
                creator: if w.creator == NO_GROUP {
                    NO_GROUP
                } else {
                    new_gid[w.creator as usize]
                },
                level: w.level,
                page: 0,
            };
            (cluster, refs, tri_bytes, bytes)
        })
        .collect();
    let mut clusters = Vec::with_capacity(order.len());
    let mut sizes = Vec::with_capacity(order.len());
    let (mut ref_at, mut tri_at) = (0u32, 0u32);
    let mut stored = 0;
    for (c, r, t, bytes) in &packed {
        let mut c = *c;
        c.vertex_ref_offset = ref_at;
        c.triangle_offset = tri_at;
        ref_at += r.len() as u32;
        tri_at += t.len() as u32;
        stored += c.triangle_count() as usize;
        clusters.push(c);
        sizes.push(*bytes);
    }
    let refs = super::concat(&packed, |p| &p.1);
    let triangles = super::concat(&packed, |p| &p.2);
    let root = wgroups
        .iter()
        .find(|g| g.iteration == u32::MAX)
        .and_then(|g| g.members.first())
        .map_or(0, |&r| new_index[r as usize]);
    stats.clusters = clusters.len();
    stats.groups = groups.len();
    stats.bvh_nodes = bvh.len();
    stats.stored_triangles = stored;
    let single_material = mesh.materials.len() <= 1;
    let built = BuiltMesh {
        name: mesh.name.clone(),
        quantization: quant,
        has_normals: mesh.has_normals,
        has_uvs: mesh.has_uvs,
        materials: mesh.materials.clone(),
        vertices,
        vertex_materials: if single_material { Vec::new() } else { vmat },
        clusters,
        vertex_refs: refs,
        triangles,
        groups,
        group_coverage,
        bvh,
        root,
        pages: Vec::new(),
        resident_pages: 0,
        stats,
    };
    (built, sizes)
}

#[cfg(test)]
mod tests {
    use super::{Edges, Level0, edge_lengths, first_occurrences, group_error, undirected};

    /// The median edge and the short edge (selected among squared lengths by their bits)
    /// against the median and the quantile of the lengths themselves (the quantile among those
    /// longer than 0), on edges of many lengths, equal ones, zero-length ones and non-finite
    /// ones (which are left out), with an odd and an even count, and on a mesh big enough to be
    /// sampled.
    #[test]
    fn edge_lengths_are_the_median_and_the_quantile() {
        let mut rng = crate::builder::verify::Rng(11);
        let mut next = || (rng.next() % 1000) as f32 * 0.37 - 150.0;
        let mut positions: Vec<[f32; 3]> = (0..300).map(|_| [next(), next(), next()]).collect();
        positions[7] = [f32::NAN, 0.0, 0.0];
        positions[11] = [f32::INFINITY, 1.0, 0.0];
        positions[12] = positions[13];
        // (Zero-length edges: triangles 1 and 2 start at points 22 and 29, 44 and 51.)
        positions[29] = positions[22];
        positions[51] = positions[44];
        // (240 of the 300 points on one: about 64 % of the edges are zero-length, so the short
        // edge lies above the median.)
        let mut collapsed = positions.clone();
        for q in collapsed.iter_mut().take(240) {
            *q = [1.0, 2.0, 3.0];
        }
        // (140 K triangles: every second one is sampled.)
        for (positions, tris) in [
            (&positions, 301usize),
            (&positions, 300),
            (&positions, 140_001),
            (&collapsed, 301),
        ] {
            let indices: Vec<u32> = (0..3 * tris as u32)
                .map(|i| (i * 7 + i / 3) % 300)
                .collect();
            // (Only the positions and the triangles count.)
            let mesh = crate::mesh::Mesh {
                positions: positions.clone(),
                indices: indices.clone(),
                ..Default::default()
            };
            let stride = (tris >> 16).max(1);
            let mut lens: Vec<f64> = indices
                .chunks_exact(3)
                .step_by(stride)
                .flat_map(|t| {
                    (0..3).map(|k| {
                        let (a, b) = (positions[t[k] as usize], positions[t[(k + 1) % 3] as usize]);
                        (0..3)
                            .map(|c| (a[c] as f64 - b[c] as f64).powi(2))
                            .sum::<f64>()
                            .sqrt()
                    })
                })
                .filter(|l| l.is_finite())
                .collect();
            let mid = lens.len() / 2;
            let want = *lens.select_nth_unstable_by(mid, f64::total_cmp).1;
            let mut nonzero: Vec<f64> = lens.iter().copied().filter(|&l| l > 0.0).collect();
            let zeros = lens.len() - nonzero.len();
            assert!(zeros > 0, "{tris} triangles: the case of zero-length edges");
            if positions[0] == [1.0, 2.0, 3.0] {
                assert!(2 * zeros > lens.len(), "the case of a zero median");
            }
            let at =
                (nonzero.len() as f64 * crate::builder::quantize::SHORT_EDGE_QUANTILE) as usize;
            let short = *nonzero.select_nth_unstable_by(at, f64::total_cmp).1;
            let (median, got_short) = edge_lengths(&mesh);
            assert_eq!(median.to_bits(), want.to_bits(), "{tris} triangles");
            assert_eq!(got_short.to_bits(), short.to_bits(), "{tris} triangles");
        }
    }

    /// `Edges::of` (counting sort by the smaller point, a sort per point) against the 64-bit
    /// keys' plain sort, on triangles with repeated, reversed and degenerate edges and a fan of
    /// 32 edges at one point.
    /// `Level0` counts the edge uses with plain counters on one thread and for small meshes,
    /// with atomics in parallel for large ones: both give the same irregular edges, border points
    /// and components, on a mesh past the switch with open borders, non-manifold and duplicated
    /// edges (random triangles over few points).
    #[test]
    fn level0_is_the_same_serial_and_parallel() {
        let mut rng = crate::builder::verify::Rng(5);
        let npid = 40_000usize;
        let tris: Vec<[u32; 3]> = (0..(1 << 18) + 1000)
            .map(|_| {
                let a = (rng.next() % npid as u64) as u32;
                let b = (a + 1 + (rng.next() % 8) as u32) % npid as u32;
                let c = (b + 1 + (rng.next() % 8) as u32) % npid as u32;
                [a, b, c]
            })
            .collect();
        let pid: Vec<u32> = (0..npid as u32).collect();
        let on = |threads: usize, tris: &[[u32; 3]]| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let l = pool.install(|| Level0::new(tris, &pid, npid));
            (l.irregular, l.border, l.comp)
        };
        let serial = on(1, &tris);
        assert!(!serial.0.is_empty() && serial.1.iter().any(|&b| b));
        assert_eq!(on(3, &tris), serial);
        // A small mesh takes the serial path on any thread count.
        let small = &tris[..5000];
        assert_eq!(on(3, small), on(1, small));
    }

    #[test]
    fn edges_of_counts_each_direction_in_key_order() {
        // Points are the group's position ids, ascending; local vertex v is at point lp[v].
        let points: Vec<u32> = (0..40).map(|i| 1000 + 7 * i).collect();
        let lp: Vec<u32> = (0..60).map(|v| v % 40).collect();
        let mut tris: Vec<[u32; 3]> = (1..30).map(|i| [0, i, i + 1]).collect();
        tris.extend([
            [3, 2, 1],
            [1, 2, 3],
            [5, 5, 6],
            [41, 42, 2],
            [10, 50, 11],
            [39, 38, 0],
        ]);
        let got = Edges::of(&tris, &lp, &points);
        let point = |v: u32| points[lp[v as usize] as usize];
        let keys: Vec<u64> = tris
            .iter()
            .flat_map(|t| (0..3).map(move |e| undirected(point(t[e]), point(t[(e + 1) % 3]))))
            .collect();
        let want = Edges::from_keys(keys);
        assert_eq!(got.0, want.0);
        assert!(got.0.windows(2).all(|w| w[0].0 < w[1].0));
        // Point 1000 (the fan's centre) is the smaller point of 32 distinct edges: to the fan's
        // points 1-30 and to points 38 and 39.
        assert_eq!(got.0.iter().filter(|e| e.0 >> 32 == 1000).count(), 32);
    }

    #[test]
    fn first_occurrences_keeps_the_first_of_equal_keys() {
        // A few small buckets, and one point of high valence (a big bucket) with repeats in it.
        let mut keys = vec![
            [0, 1, 2],
            [0, 2, 1],
            [1, 2, 3],
            [0, 1, 2],
            [1, 2, 3],
            [2, 3, 4],
        ];
        for k in 0..40u32 {
            keys.push([5, 6 + k % 25, 100 + k % 25]);
        }
        let keep = first_occurrences(&keys, 200);
        let mut seen = std::collections::HashSet::new();
        let expected: Vec<bool> = keys.iter().map(|k| seen.insert(*k)).collect();
        assert_eq!(keep, expected);
        assert_eq!(keep.iter().filter(|&&k| !k).count(), 2 + 15);
    }

    #[test]
    fn group_error_bounds_the_distance_to_the_original_surface() {
        let m = 1.0 + 1.0 / 1024.0;
        // Position-and-attribute errors add up along the chain: 0.1 against the members, whose
        // own part is 0.2 against the original.
        let (e, pos) = group_error(0.1, 0.0, 0.2, 0.2, 0.0);
        assert!((pos - 0.3).abs() < 1e-6 && (e - 0.3 * m).abs() < 1e-6);
        // The coverage error is not summed: the larger of it and the chain's bound.
        let (e, pos) = group_error(0.1, 0.5, 0.2, 0.45, 0.0);
        assert!((pos - 0.3).abs() < 1e-6 && (e - 0.5 * m).abs() < 1e-6);
        // Never below a member's error (monotonic), never zero.
        let (e, _) = group_error(0.0, 0.0, 0.0, 0.7, 0.0);
        assert!((e - 0.7 * m).abs() < 1e-6);
        assert_eq!(group_error(0.0, 0.0, 0.0, 0.0, 1e-9).0, 1e-9);
    }
}
