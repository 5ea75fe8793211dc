//! The offline cluster-DAG builder (CPU only, deterministic).
//!
//! [`build`] turns a [`Mesh`] into a [`BuiltMesh`]: level-0 clusters of at most 128 triangles and
//! 255 vertices, then repeatedly groups of about 16 (at most 32) clusters simplified to about half
//! with their borders locked and split into new clusters, until one root cluster remains. Clusters
//! and groups come from a [`Partitioner`]: meshoptimizer's spatial clusterizer and cluster
//! partitioner by default (fast, thread-safe; big inputs are clustered in parallel Morton chunks),
//! or METIS on the triangle / cluster graphs. A group simplification that would fold an edge
//! (an overlap in some cut) is retried with the fold's neighbourhood locked. Every cluster stores a
//! `self` and a `parent` (error, LOD sphere) pair as DESIGN.md's "cut rule" requires; the BVH
//! (fanout 8, leaves of up to 4 groups) fixes the order of the groups; [`verify()`] checks the
//! invariants and the cut on many views.
//!
//! Positions are snapped to a per-mesh grid at the start (21 bits per axis), normals to 16-bit
//! octahedral codes and UVs to 16 bits over the mesh's UV range, so the `.vgeo` file stores exactly
//! what the builder used and a loaded file verifies like the built one.

pub mod bvh;
pub mod cluster;
pub mod cut;
pub mod dag;
pub mod fastpart;
pub mod group;
pub mod page;
pub mod quantize;
pub mod simplify;
pub mod size;
pub mod solid;
pub mod tricode;
pub mod verify;

/// Union-find root of `x` in `parent` (with path halving): the builder's connected pieces, seam
/// components and border loops, and the coverage error's pieces.
pub(crate) fn uf_find(parent: &mut [u32], mut x: u32) -> u32 {
    while parent[x as usize] != x {
        let p = parent[parent[x as usize] as usize];
        parent[x as usize] = p;
        x = p;
    }
    x
}

/// Joins the sets of `a` and `b` under the smaller root (so a set's root is its smallest member).
pub(crate) fn uf_union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (uf_find(parent, a), uf_find(parent, b));
    parent[ra.max(rb) as usize] = ra.min(rb);
}

use bytemuck::{Pod, Zeroable};

use crate::mesh::{Material, Mesh};

pub use cut::lod_error_px;
pub use dag::{build, build_with_progress};
pub use verify::{VerifyOptions, VerifyReport, verify};

/// Options of [`build`].
#[derive(Clone, Debug, PartialEq)]
pub struct BuildOptions {
    /// Most triangles per cluster (at most [`crate::shared::MAX_CLUSTER_TRIANGLES`]).
    pub max_cluster_triangles: u32,
    /// Smallest group size the partitioner aims for (clusters).
    pub group_min: u32,
    /// Largest group size (clusters); exceeded only when the build is stuck and regroups wider.
    pub group_max: u32,
    /// Target triangle ratio of one simplification step (default 0.35; the root chain is 0.5's
    /// at any ratio, docs/architecture.md "The root chain at any ratio").
    pub simplify_ratio: f32,
    /// UE Nanite's "Keep Triangle Percent": percentage of the input triangles kept at level 0
    /// (100: all); below 100 the input is simplified first and that becomes the finest level.
    pub keep_percent: f32,
    /// UE Nanite's "Trim Relative Error": detail whose removal costs less than this error,
    /// relative to the bounding-box diagonal, is removed from the input before the build
    /// (0: none). With `keep_percent`, the stricter of the two wins.
    pub trim_error: f32,
    /// Triangle count the fallback mesh ([`BuiltMesh::fallback_mesh`]) aims for.
    pub fallback_triangles: u32,
    /// Once one cluster is left, keep simplifying it (a group of one, each step a new level with
    /// one cluster) while it has more than this many triangles and simplification still removes
    /// some: the root gets small, so a far instance (drawn as its root alone) costs a few
    /// triangles. 0 or at least `max_cluster_triangles`: stop at the first single cluster.
    pub root_triangles: u32,
    /// Weight of the vertex normal in the simplifier's error (0: position only). A normal that
    /// turns by `a` radians across a region of size `s` counts about as much as moving the surface
    /// by `normal_weight * a * s` (see docs/architecture.md, "Shading-aware error").
    pub normal_weight: f32,
    /// Weight of the UV (meshes with UVs) in the simplifier's error, as `normal_weight`.
    pub uv_weight: f32,
    /// Worker threads (`None`: rayon's default). The output does not depend on it.
    pub threads: Option<usize>,
    /// Graph partitioner for clusters and groups.
    pub partitioner: Partitioner,
    /// Bits per position axis of the grid the pages store (the mesh's stated precision: the step
    /// is the largest extent over `2^bits - 1`), 1..=21; `None`: [`quantize::auto_position_bits`]
    /// (at least 14, finer when the short edges need it). The DAG is built on a grid of at least
    /// [`quantize::build_position_bits`] whatever this says; a coarser stated grid moves only the
    /// stored positions.
    pub position_bits: Option<u32>,
    /// Bits per octahedral normal component, 2..=16.
    pub normal_bits: u32,
}

/// Which partitioner makes clusters and groups.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Partitioner {
    /// meshoptimizer's spatial clusterizer (`meshopt_buildMeshletsSpatial`) and cluster
    /// partitioner: fastest, and parallel (the default).
    #[default]
    Meshopt,
    /// As `Meshopt`, but clusters after simplification grow along triangle adjacency
    /// (`meshopt_buildMeshletsFlex`): about 20% slower, slightly fewer bytes.
    MeshoptFlex,
    /// METIS on the triangle / cluster graphs: tighter borders, slower, and serialized (METIS's
    /// random generator is process-global, so calls hold a lock for determinism).
    Metis,
}

/// Default [`BuildOptions::normal_weight`].
pub const DEFAULT_NORMAL_WEIGHT: f32 = 1.0;
/// Default [`BuildOptions::uv_weight`].
pub const DEFAULT_UV_WEIGHT: f32 = 0.5;

impl Default for BuildOptions {
    fn default() -> Self {
        Self {
            max_cluster_triangles: 128,
            group_min: 8,
            group_max: 32,
            simplify_ratio: 0.35,
            keep_percent: 100.0,
            trim_error: 0.0,
            fallback_triangles: 2000,
            root_triangles: 16,
            normal_weight: DEFAULT_NORMAL_WEIGHT,
            uv_weight: DEFAULT_UV_WEIGHT,
            threads: None,
            partitioner: Partitioner::default(),
            position_bits: None,
            normal_bits: quantize::DEFAULT_NORMAL_BITS,
        }
    }
}

/// Why a build failed.
#[derive(Debug, thiserror::Error)]
pub enum BuildError {
    /// The input mesh breaks the [`Mesh`] invariants.
    #[error("mesh '{name}' is invalid: {msg}")]
    InvalidMesh {
        /// The mesh's name.
        name: String,
        /// What is wrong.
        msg: String,
    },
    /// Nothing left to build (no triangles, or all degenerate).
    #[error("mesh '{name}' has no non-degenerate triangles ({dropped} degenerate dropped)")]
    Empty {
        /// The mesh's name.
        name: String,
        /// Degenerate triangles dropped.
        dropped: usize,
    },
    /// An option is out of range.
    #[error("invalid build option: {0}")]
    InvalidOptions(String),
    /// The DAG could not be reduced to one root cluster.
    #[error(
        "mesh '{name}': the DAG got stuck at iteration {iteration} with {clusters} clusters / {triangles} triangles that cannot be simplified further"
    )]
    Stuck {
        /// The mesh's name.
        name: String,
        /// The DAG iteration it stopped at.
        iteration: u32,
        /// Clusters left.
        clusters: usize,
        /// Triangles left.
        triangles: usize,
    },
    /// The thread pool could not be created.
    #[error("cannot create a thread pool: {0}")]
    Threads(String),
}

/// A sphere `[x, y, z, radius]`.
pub type Sphere = [f32; 4];

/// Sentinel for "no group" (level-0 clusters have no creator group).
pub const NO_GROUP: u32 = crate::shared::NO_GROUP_ID;

pub use crate::shared::CLUSTER_FLAG_REFS_U32;

/// One cluster as stored on the GPU (and in the file).
///
/// `self_*` is the pair of the simplification that produced the cluster (level 0: error 0 and its own
/// bounds), shared by all clusters produced together; `parent_*` is the pair of the simplification of
/// the group it is a member of (the root: `f32::INFINITY`), shared by all members of that group.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Cluster {
    pub self_sphere: Sphere,
    pub parent_sphere: Sphere,
    /// Tight bounds of the cluster's own vertices (for frustum / occlusion culling).
    pub bounds_min: [f32; 3],
    pub self_error: f32,
    pub bounds_max: [f32; 3],
    pub parent_error: f32,
    /// Offset (in u32 words) of the cluster's vertex references in [`BuiltMesh::vertex_refs`].
    pub vertex_ref_offset: u32,
    /// Word offset of the cluster's encoded data in its page's bytes (see [`page`]); 0 before
    /// [`page::paginate`].
    pub data_offset: u32,
    /// Offset (in bytes, a multiple of 4) of the cluster's packed local triangle indices in
    /// [`BuiltMesh::triangles`]: `3 * triangle_count` indices of [`index_bits`]`(vertex_count)`
    /// bits each, as a little-endian bit stream (index `k` starts at bit `k * bits`).
    pub triangle_offset: u32,
    /// `vertex_count | triangle_count << 8 | flags << 16 | size_code << 24` (flags: 8 bits; the
    /// size code of its triangles: [`size`]).
    pub counts: u32,
    /// The group the cluster is a member of (its `parent` pair); the root's own pseudo-group.
    pub group: u32,
    /// The group whose simplification produced the cluster ([`NO_GROUP`] at level 0).
    pub creator: u32,
    /// DAG level: 0 for input clusters, else the creator group's iteration + 1 (at most
    /// [`crate::shared::MAX_CLUSTER_LEVEL`]).
    pub level: u32,
    /// The page holding the cluster's vertices, references and triangles ([`BuiltMesh::pages`]).
    pub page: u32,
}
const _: () = assert!(size_of::<Cluster>() == 96);

impl Cluster {
    /// Number of unique vertices (<= 255).
    pub fn vertex_count(&self) -> u32 {
        self.counts & 0xff
    }
    /// Number of triangles (<= 128).
    pub fn triangle_count(&self) -> u32 {
        (self.counts >> 8) & 0xff
    }
    /// Flags ([`CLUSTER_FLAG_REFS_U32`]).
    pub fn flags(&self) -> u32 {
        (self.counts >> 16) & 0xff
    }
    /// The size code of its triangles (see [`size`]): their edge-length equivalent is at most
    /// [`size::size_ratio`]`(code)` times its bounds' diagonal.
    pub fn size_code(&self) -> u32 {
        self.counts >> 24
    }
    /// The edge-length equivalent of its triangles that its size code stands for (object space;
    /// at most 4.4 % above the measure, see [`size`]).
    pub fn triangle_size(&self) -> f64 {
        size::size_ratio(self.size_code())
            * size::diagonal_squared(self.bounds_min, self.bounds_max).sqrt()
    }
    /// Number of u32 words its vertex references take.
    pub fn vertex_ref_words(&self) -> u32 {
        if self.flags() & CLUSTER_FLAG_REFS_U32 != 0 {
            self.vertex_count()
        } else {
            self.vertex_count().div_ceil(2)
        }
    }
}

/// Bits per packed local triangle index of a cluster with `vertex_count` vertices (1..=8).
pub fn index_bits(vertex_count: u32) -> u32 {
    (32 - vertex_count.saturating_sub(1).leading_zeros()).max(1)
}

/// The concatenation of `part(p)` over `parts`, in order, each part copied to its place in
/// parallel (the builder's per-cluster and per-page streams; a serial copy was a tenth of the
/// packing's time on two threads).
pub(crate) fn concat<P: Sync, T: Copy + Send + Sync>(
    parts: &[P],
    part: impl Fn(&P) -> &[T] + Sync,
) -> Vec<T> {
    use rayon::prelude::*;
    let total: usize = parts.iter().map(|p| part(p).len()).sum();
    let mut out: Vec<T> = Vec::with_capacity(total);
    let mut rest = &mut out.spare_capacity_mut()[..total];
    let mut places = Vec::with_capacity(parts.len());
    for p in parts {
        let (head, tail) = rest.split_at_mut(part(p).len());
        places.push(head);
        rest = tail;
    }
    places
        .into_par_iter()
        .zip(parts.par_iter())
        .for_each(|(place, p)| {
            for (d, s) in place.iter_mut().zip(part(p)) {
                d.write(*s);
            }
        });
    // SAFETY: the places split `out`'s first `total` spare elements among the parts, whose
    // lengths sum to `total`, and every element of every place was written above.
    unsafe { out.set_len(total) };
    out
}

/// Bytes of a cluster's packed triangle indices, padded to a multiple of 4.
pub fn packed_triangle_bytes(vertex_count: u32, triangle_count: u32) -> usize {
    ((3 * triangle_count as usize * index_bits(vertex_count) as usize).div_ceil(32)) * 4
}

/// Appends the packed form of `local` (indices `< vertex_count`) to `out` (see
/// [`Cluster::triangle_offset`]).
pub fn pack_indices(local: &[u8], vertex_count: u32, out: &mut Vec<u8>) {
    let bits = index_bits(vertex_count);
    let mut acc = 0u64;
    let mut n = 0u32;
    let start = out.len();
    for &l in local {
        acc |= (l as u64) << n;
        n += bits;
        while n >= 8 {
            out.push(acc as u8);
            acc >>= 8;
            n -= 8;
        }
    }
    if n > 0 {
        out.push(acc as u8);
    }
    let len = (out.len() - start).div_ceil(4) * 4;
    out.resize(start + len, 0);
}

/// Local index `k` of a packed stream starting at `bytes[0]` with `bits` per index; `None` when it
/// lies outside `bytes`.
pub fn unpack_index(bytes: &[u8], bits: u32, k: usize) -> Option<u32> {
    let bit = k * bits as usize;
    let lo = *bytes.get(bit / 8)? as u32;
    let hi = if (bit % 8) + bits as usize > 8 {
        *bytes.get(bit / 8 + 1)? as u32
    } else {
        0
    };
    Some(((lo | hi << 8) >> (bit % 8)) & ((1 << bits) - 1))
}

/// A group: clusters simplified together. Its members are the clusters
/// `first_cluster .. first_cluster + cluster_count` and all share the group's (error, sphere) as
/// their `parent` pair.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct Group {
    /// LOD sphere of the group's simplification (the members' parent sphere).
    pub lod_sphere: Sphere,
    /// Union of the members' bounds.
    pub bounds_min: [f32; 3],
    /// Error of the group's simplification (the members' parent error; the root's: infinity).
    pub error: f32,
    pub bounds_max: [f32; 3],
    pub first_cluster: u32,
    pub cluster_count: u32,
    /// Build iteration at which the group was simplified (`u32::MAX` for the root pseudo-group).
    pub iteration: u32,
    /// The pages holding the members' data: `page_first .. page_first + page_count` (one page
    /// unless the group is larger than a page).
    pub page_first: u32,
    pub page_count: u32,
}
const _: () = assert!(size_of::<Group>() == 64);

pub use crate::shared::BVH_FLAG_LEAF;

/// A BVH node (fanout <= 8) over groups.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Pod, Zeroable)]
pub struct BvhNode {
    pub bounds_min: [f32; 3],
    /// Largest parent error in the subtree: when it projects under the threshold on `lod_sphere`,
    /// no cluster below can be drawn.
    pub max_parent_error: f32,
    pub bounds_max: [f32; 3],
    pub flags: u32,
    /// Encloses every parent sphere in the subtree.
    pub lod_sphere: Sphere,
    /// Inner node: first child node; leaf: first group.
    pub first: u32,
    /// Inner node: child count; leaf: group count.
    pub count: u32,
    /// Largest coverage part of a parent error in the subtree (`BuiltMesh::group_coverage`): with
    /// `max_parent_error`, what bounds a small instance's weighted parent errors below.
    pub max_parent_coverage: f32,
    pub _pad: u32,
}
const _: () = assert!(size_of::<BvhNode>() == 64);

/// A vertex: position on the mesh grid (21 bits per axis in 63 bits), octahedral normal
/// (2 x 16 bits), UV (2 x 16 bits over the mesh's UV range; 0 when the mesh has no UVs). The file
/// stores these as separate streams (positions 8 B, normals 4 B, UVs 4 B only when the mesh has
/// UVs), see [`crate::format`].
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Pod, Zeroable)]
pub struct PackedVertex {
    /// Low and high words of `x | y << 21 | z << 42`.
    pub position: [u32; 2],
    pub normal: u32,
    pub uv: u32,
}
const _: () = assert!(size_of::<PackedVertex>() == 16);

/// Per-mesh quantization grid.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Quantization {
    /// Position of grid point (0, 0, 0).
    pub origin: [f64; 3],
    /// Grid step (the same on every axis).
    pub step: f64,
    /// UV range: code 0 is `uv_min`, code 65535 is `uv_max`.
    pub uv_min: [f32; 2],
    pub uv_max: [f32; 2],
    /// Bits per position axis: `step` is the largest extent over `2^position_bits - 1`.
    pub position_bits: u32,
    /// Bits per octahedral normal component ([`quantize::normal_scale`]).
    pub normal_bits: u32,
}

/// Statistics of one complete level of the DAG (the working set after an iteration).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct LevelStats {
    /// DAG level (0: the input triangles).
    pub level: u32,
    /// Clusters at this level.
    pub clusters: usize,
    /// Triangles at this level.
    pub triangles: usize,
    /// Triangles relative to the previous level.
    pub ratio: f32,
    /// Largest `self` error of its clusters.
    pub max_error: f32,
    /// Groups simplified at this iteration, and how many of them could not shrink (carried over).
    pub groups: usize,
    /// Groups that could not be simplified enough (kept for the next iteration).
    pub stuck_groups: usize,
}

/// Build statistics (deterministic; timing is reported separately by the CLI).
#[derive(Clone, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct BuildStats {
    /// Triangles of the input mesh.
    pub input_triangles: usize,
    /// Triangles dropped as degenerate (after snapping to the grid).
    pub degenerate_dropped: usize,
    /// Exact duplicate triangles dropped (same points, same winding).
    pub duplicates_dropped: usize,
    /// Level-0 triangles (after degenerate removal, `trim_error` and `keep_percent`).
    pub level0_triangles: usize,
    /// Object-space error of trimming the input to level 0 (0 without trimming).
    #[serde(default)]
    pub level0_error: f32,
    /// Stored vertices.
    pub vertices: usize,
    /// Clusters, every level.
    pub clusters: usize,
    /// DAG groups.
    pub groups: usize,
    /// BVH nodes over the clusters.
    pub bvh_nodes: usize,
    /// Triangles over all levels.
    pub stored_triangles: usize,
    /// Per DAG level.
    pub levels: Vec<LevelStats>,
    /// Iterations at which the group size had to be widened beyond `group_max` (stuck).
    pub widened_iterations: Vec<u32>,
    /// Groups that needed pruning, sloppy simplification or merging to make progress.
    pub fallback_groups: usize,
    /// Pages the clusters' data is stored in ([`page`]).
    #[serde(default)]
    pub pages: usize,
    /// Level 0 is a closed solid: every edge is used once in each direction and every
    /// edge-connected piece encloses a positive volume (its faces turned outwards). From a camera
    /// outside it, no face turned away is ever the nearest, so the hardware rasterizer drops
    /// those faces (`common/cull.glsl` `hw_entry_flags`). `None` in files written before this
    /// existed: not known, so no face is dropped (rebuild the file to have them dropped).
    #[serde(default)]
    pub closed_solid: Option<bool>,
}

/// A built mesh: the cluster DAG, its BVH and vertex data. What `.vgeo` stores.
#[derive(Clone, Debug, PartialEq)]
pub struct BuiltMesh {
    /// The mesh's name.
    pub name: String,
    /// How positions and UVs are quantized.
    pub quantization: Quantization,
    /// Whether the source had normals (else crease-angle normals were made).
    pub has_normals: bool,
    /// Whether the vertices carry UVs.
    pub has_uvs: bool,
    /// The mesh's materials (clusters index them).
    pub materials: Vec<Material>,
    /// Packed vertices of every cluster.
    pub vertices: Vec<PackedVertex>,
    /// Material per vertex (vertices are split per material, so a triangle's material is its first
    /// vertex's).
    pub vertex_materials: Vec<u16>,
    /// Clusters of every level, with their error and bounding spheres.
    pub clusters: Vec<Cluster>,
    /// Vertex references of all clusters (u16 pairs or u32 words, see [`Cluster`]).
    pub vertex_refs: Vec<u32>,
    /// Packed local triangle indices of all clusters (see [`Cluster::triangle_offset`]).
    pub triangles: Vec<u8>,
    /// DAG groups.
    pub groups: Vec<Group>,
    /// Per group, the coverage part of its error (at most `error`): the largest coverage error
    /// along its chain, which a small instance counts whole while it weighs the rest
    /// (`cut::small_instance_weight`). Empty for a file written before it existed: every error
    /// then counts whole ([`BuiltMesh::group_coverage_of`]).
    pub group_coverage: Vec<f32>,
    /// BVH over the clusters, for the GPU's culling walk.
    pub bvh: Vec<BvhNode>,
    /// Index of the root cluster.
    pub root: u32,
    /// The pages the clusters' data is stored in, from the root down ([`page`]).
    pub pages: Vec<page::Page>,
    /// The first `resident_pages` pages hold every group simplified at or after the fallback
    /// level: the always-resident part.
    pub resident_pages: u32,
    /// What the build did (levels, counts, dropped input).
    pub stats: BuildStats,
}

impl BuiltMesh {
    /// The coverage part of group `g`'s error ([`BuiltMesh::group_coverage`]); the whole error
    /// where it is not known.
    pub fn group_coverage_of(&self, g: u32) -> f32 {
        match self.group_coverage.get(g as usize) {
            Some(&c) => c,
            None => self.groups.get(g as usize).map_or(0.0, |g| g.error),
        }
    }

    /// Decoded position of vertex `v`.
    pub fn position(&self, v: u32) -> [f32; 3] {
        quantize::decode_position(&self.quantization, self.vertices[v as usize].position)
    }

    /// All decoded positions.
    pub fn positions(&self) -> Vec<[f32; 3]> {
        self.vertices
            .iter()
            .map(|v| quantize::decode_position(&self.quantization, v.position))
            .collect()
    }

    /// Global index of cluster `c`'s local vertex `i`. Panics on out-of-range input (the file loader
    /// checks every reference).
    pub fn vertex_ref(&self, c: &Cluster, i: u32) -> u32 {
        if c.flags() & CLUSTER_FLAG_REFS_U32 != 0 {
            self.vertex_refs[(c.vertex_ref_offset + i) as usize]
        } else {
            let w = self.vertex_refs[(c.vertex_ref_offset + i / 2) as usize];
            self.pages[c.page as usize].vertex_first + ((w >> (16 * (i & 1))) & 0xffff)
        }
    }

    /// Triangles of cluster `c` as its local vertex indices.
    pub fn cluster_local_triangles(&self, c: &Cluster) -> Vec<[u32; 3]> {
        let bytes = &self.triangles[c.triangle_offset as usize..];
        let bits = index_bits(c.vertex_count());
        (0..c.triangle_count() as usize)
            .map(|t| std::array::from_fn(|k| unpack_index(bytes, bits, 3 * t + k).unwrap_or(0)))
            .collect()
    }

    /// Triangles of cluster `ci` as global vertex indices.
    pub fn cluster_triangles(&self, ci: usize) -> Vec<[u32; 3]> {
        let c = &self.clusters[ci];
        self.cluster_local_triangles(c)
            .into_iter()
            .map(|t| t.map(|l| self.vertex_ref(c, l)))
            .collect()
    }

    /// Number of complete levels (working sets) recorded in the stats.
    pub fn level_count(&self) -> usize {
        self.stats.levels.len()
    }

    /// Clusters forming complete level `k`: created at iteration <= k and simplified (as a group
    /// member) at iteration >= k, or never (the root).
    pub fn level_clusters(&self, k: u32) -> Vec<u32> {
        (0..self.clusters.len() as u32)
            .filter(|&ci| {
                let c = &self.clusters[ci as usize];
                let g = &self.groups[c.group as usize];
                c.level <= k && g.iteration >= k
            })
            .collect()
    }

    /// The complete level whose triangle count is closest to `target` (the finer on a tie).
    pub fn fallback_level(&self, target: u32) -> u32 {
        let mut best = 0u32;
        let mut best_d = u64::MAX;
        for l in &self.stats.levels {
            let d = (l.triangles as i64 - target as i64).unsigned_abs();
            if d < best_d {
                best_d = d;
                best = l.level;
            }
        }
        best
    }

    /// The complete level whose triangle count is closest to `target`, as a plain mesh.
    pub fn fallback_mesh(&self, target: u32) -> Mesh {
        self.level_mesh(self.fallback_level(target))
    }

    /// Complete level `k` as a plain mesh (vertices compacted, attributes decoded). Vertices equal
    /// in every attribute are one (pages store a vertex shared by two pages in both).
    pub fn level_mesh(&self, k: u32) -> Mesh {
        let mut remap = vec![u32::MAX; self.vertices.len()];
        let mut by_value: std::collections::HashMap<(PackedVertex, u16), u32> =
            std::collections::HashMap::new();
        let mut mesh = Mesh {
            name: format!("{} (level {k})", self.name),
            materials: if self.materials.is_empty() {
                vec![Material::default()]
            } else {
                self.materials.clone()
            },
            has_normals: self.has_normals,
            has_uvs: self.has_uvs,
            ..Default::default()
        };
        for ci in self.level_clusters(k) {
            for tri in self.cluster_triangles(ci as usize) {
                for &v in &tri {
                    if remap[v as usize] == u32::MAX {
                        let pv = &self.vertices[v as usize];
                        let key = (
                            *pv,
                            self.vertex_materials.get(v as usize).copied().unwrap_or(0),
                        );
                        let next = mesh.positions.len() as u32;
                        let id = *by_value.entry(key).or_insert(next);
                        remap[v as usize] = id;
                        if id != next {
                            mesh.indices.push(id);
                            continue;
                        }
                        mesh.positions
                            .push(quantize::decode_position(&self.quantization, pv.position));
                        mesh.normals.push(quantize::decode_normal(
                            pv.normal,
                            self.quantization.normal_bits,
                        ));
                        mesh.uvs
                            .push(quantize::decode_uv(&self.quantization, pv.uv));
                    }
                    mesh.indices.push(remap[v as usize]);
                }
                let m = self
                    .vertex_materials
                    .get(tri[0] as usize)
                    .copied()
                    .unwrap_or(0) as u32;
                mesh.material_ids
                    .push(m.min(mesh.materials.len() as u32 - 1));
            }
        }
        mesh
    }
}

/// Writes `mesh` as Wavefront OBJ text (positions, normals, UVs, one `usemtl` per material run).
pub fn mesh_to_obj(mesh: &Mesh) -> String {
    use std::fmt::Write;
    let mut s = String::new();
    let _ = writeln!(
        s,
        "# {} ({} triangles), written by vgeo",
        mesh.name,
        mesh.triangle_count()
    );
    for p in &mesh.positions {
        let _ = writeln!(s, "v {} {} {}", p[0], p[1], p[2]);
    }
    for n in &mesh.normals {
        let _ = writeln!(s, "vn {} {} {}", n[0], n[1], n[2]);
    }
    for t in &mesh.uvs {
        let _ = writeln!(s, "vt {} {}", t[0], t[1]);
    }
    let mut cur = u32::MAX;
    for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
        let m = mesh.material_ids.get(t).copied().unwrap_or(0);
        if m != cur {
            cur = m;
            let name = mesh
                .materials
                .get(m as usize)
                .map(|m| m.name.as_str())
                .unwrap_or("default");
            let _ = writeln!(s, "usemtl {name}");
        }
        let _ = writeln!(
            s,
            "f {a}/{a}/{a} {b}/{b}/{b} {c}/{c}/{c}",
            a = tri[0] + 1,
            b = tri[1] + 1,
            c = tri[2] + 1
        );
    }
    s
}

#[cfg(test)]
mod tests {
    /// `concat` keeps the parts' order and every element, with empty parts anywhere and more
    /// parts than threads.
    #[test]
    fn concat_is_the_parts_in_order() {
        let parts: Vec<Vec<u32>> = (0..200u32)
            .map(|p| (0..(p * 7) % 13).map(|i| p * 1000 + i).collect())
            .collect();
        let flat: Vec<u32> = parts.iter().flatten().copied().collect();
        assert_eq!(super::concat(&parts, |p| p.as_slice()), flat);
        let none: Vec<Vec<u8>> = vec![Vec::new(); 3];
        assert!(super::concat(&none, |p| p.as_slice()).is_empty());
        assert!(super::concat::<Vec<u8>, u8>(&[], |p| p.as_slice()).is_empty());
    }
}
