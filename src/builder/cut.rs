//! The LOD cut rule, the one definition shared by the CPU (verify, reference) and, mirrored
//! operation for operation, the GPU `cluster_cull` shader.
//!
//! Cluster `c` is drawn for threshold `tau` pixels iff
//! `lod_error_px(c.self) <= tau && lod_error_px(c.parent) > tau`. The frame applies it to an
//! instance's errors as it counts them: a small instance counts a share of each
//! ([`small_instance_weight`]) and its coverage part whole (`BuiltMesh::group_coverage`); the
//! functions here take the errors as given (whole: `verify`'s cuts), the CPU oracle of the frame
//! (`reference::cut`) weighs them first.
//!
//! **Under partial residency** (some pages absent, `res[page]` false) a group counts as refinable
//! only when all its pages are resident: the error of a group that is not counts as 0, so its
//! members (whose parent error it is) are never drawn and the clusters it produced (whose self
//! error it is) are never refined. With a closed residency set ([`super::page::close_residency`]:
//! a resident group's products' groups are resident) the errors stay monotonic along the DAG, so
//! the cut is that of the same DAG with those errors: crack-free, and drawing only resident
//! clusters.

use glam::Vec3;

use super::{BVH_FLAG_LEAF, BuiltMesh, Cluster, NO_GROUP};
use crate::shared::{
    SMALL_WEIGHT_MIN, SMALL_WEIGHT_RADIUS_PX, TINY_CUT_CLUSTERS, TINY_CUT_ENTRIES, TINY_ROW_WORDS,
};

/// Projected size in pixels of object-space `error` at the point of the sphere nearest to the
/// camera: `error * proj_scale / (distance(center, camera) - radius)`.
///
/// `proj_scale` is `viewport_height / (2 * tan(fov_y / 2))`. An error of 0 (or less) projects to 0
/// (exact geometry is fine everywhere); a camera inside (or on) the sphere gives infinity; an
/// infinite error gives infinity. Monotonic: a larger error on an enclosing sphere never projects
/// smaller. GPU mirror: the same operations in the same order, in f32.
#[inline]
pub fn lod_error_px(
    error: f32,
    sphere_center: Vec3,
    radius: f32,
    camera_pos: Vec3,
    proj_scale: f32,
) -> f32 {
    if error <= 0.0 {
        return 0.0;
    }
    let d = (sphere_center - camera_pos).length() - radius;
    if d <= 0.0 {
        return f32::INFINITY;
    }
    error * proj_scale / d
}

/// The share of its LOD errors that counts for an instance whose bounding sphere projects to a
/// radius of `radius_px` pixels: `radius_px / SMALL_WEIGHT_RADIUS_PX`, at least
/// `SMALL_WEIGHT_MIN`, and 1 from that radius up (and for an infinite or NaN radius). GPU mirror:
/// `common/lod.glsl::small_instance_weight`.
#[inline]
pub fn small_instance_weight(radius_px: f32) -> f32 {
    if radius_px < SMALL_WEIGHT_RADIUS_PX {
        (radius_px / SMALL_WEIGHT_RADIUS_PX).max(SMALL_WEIGHT_MIN)
    } else {
        1.0
    }
}

/// A LOD error as an instance of weight `weight` ([`small_instance_weight`]) counts it: the error
/// weighted, its coverage part (at most the error) whole; `error` itself at weight 1. GPU mirror:
/// `common/lod.glsl::weighted_error` (the same operations).
#[inline]
pub fn weighted_error(error: f32, coverage: f32, weight: f32) -> f32 {
    (error * weight).max(coverage)
}

/// `proj_scale` of [`lod_error_px`] for a viewport `height` pixels high and vertical field of view
/// `fov_y` radians.
pub fn proj_scale(height: f32, fov_y: f32) -> f32 {
    height / (2.0 * (fov_y * 0.5).tan())
}

fn sphere_px(s: &[f32; 4], error: f32, camera_pos: Vec3, proj_scale: f32) -> f32 {
    lod_error_px(
        error,
        Vec3::new(s[0], s[1], s[2]),
        s[3],
        camera_pos,
        proj_scale,
    )
}

/// Whether `c` is in the cut for threshold `tau`.
#[inline]
pub fn cluster_in_cut(c: &Cluster, camera_pos: Vec3, proj_scale: f32, tau: f32) -> bool {
    sphere_px(&c.self_sphere, c.self_error, camera_pos, proj_scale) <= tau
        && sphere_px(&c.parent_sphere, c.parent_error, camera_pos, proj_scale) > tau
}

/// Whether every page of group `g` is resident (`res`: per page of `m`; `None`: all are).
#[inline]
pub fn group_resident(m: &BuiltMesh, res: Option<&[bool]>, g: u32) -> bool {
    let Some(res) = res else { return true };
    let Some(g) = m.groups.get(g as usize) else {
        return false;
    };
    (g.page_first..g.page_first.saturating_add(g.page_count))
        .all(|p| res.get(p as usize).copied().unwrap_or(false))
}

/// `c`'s (self, parent) errors under residency `res` (see the module's documentation): each the
/// group's error, or 0 when the group is not wholly resident.
#[inline]
pub fn resident_errors(m: &BuiltMesh, c: &Cluster, res: Option<&[bool]>) -> (f32, f32) {
    let own = |g: u32, e: f32| if group_resident(m, res, g) { e } else { 0.0 };
    let self_error = if c.creator == NO_GROUP {
        c.self_error
    } else {
        own(c.creator, c.self_error)
    };
    (self_error, own(c.group, c.parent_error))
}

/// Whether `c` is in the cut for threshold `tau` under residency `res`.
#[inline]
pub fn cluster_in_resident_cut(
    m: &BuiltMesh,
    c: &Cluster,
    res: Option<&[bool]>,
    camera_pos: Vec3,
    proj_scale: f32,
    tau: f32,
) -> bool {
    if res.is_none() {
        return cluster_in_cut(c, camera_pos, proj_scale, tau);
    }
    let (se, pe) = resident_errors(m, c, res);
    sphere_px(&c.self_sphere, se, camera_pos, proj_scale) <= tau
        && sphere_px(&c.parent_sphere, pe, camera_pos, proj_scale) > tau
}

/// The cut by testing every cluster (the oracle), under residency `res` (`None`: every page).
pub fn cut_brute(
    m: &BuiltMesh,
    camera_pos: Vec3,
    proj_scale: f32,
    tau: f32,
    res: Option<&[bool]>,
) -> Vec<u32> {
    (0..m.clusters.len() as u32)
        .filter(|&i| {
            cluster_in_resident_cut(m, &m.clusters[i as usize], res, camera_pos, proj_scale, tau)
        })
        .collect()
}

/// The cut through the BVH (what the GPU does, minus frustum and occlusion culling): a subtree is
/// skipped when its largest parent error is already fine (errors under residency are never
/// larger). Sorted cluster indices; `None` if the BVH references something out of range or has a
/// cycle (more visits than nodes).
pub fn cut_bvh(
    m: &BuiltMesh,
    camera_pos: Vec3,
    proj_scale: f32,
    tau: f32,
    res: Option<&[bool]>,
) -> Option<Vec<u32>> {
    let mut out = Vec::new();
    if m.bvh.is_empty() {
        return Some(out);
    }
    let mut stack = vec![0u32];
    let mut visits = 0usize;
    while let Some(n) = stack.pop() {
        visits += 1;
        if visits > m.bvh.len() {
            return None;
        }
        let node = m.bvh.get(n as usize)?;
        if sphere_px(
            &node.lod_sphere,
            node.max_parent_error,
            camera_pos,
            proj_scale,
        ) <= tau
        {
            continue;
        }
        if node.flags & BVH_FLAG_LEAF != 0 {
            for g in node.first..node.first.checked_add(node.count)? {
                let g = m.groups.get(g as usize)?;
                for ci in g.first_cluster..g.first_cluster.checked_add(g.cluster_count)? {
                    let c = m.clusters.get(ci as usize)?;
                    if cluster_in_resident_cut(m, c, res, camera_pos, proj_scale, tau) {
                        out.push(ci);
                    }
                }
            }
        } else {
            for ch in node.first..node.first.checked_add(node.count)? {
                stack.push(ch);
            }
        }
    }
    out.sort_unstable();
    Some(out)
}

/// One cut of a small instance ([`TinyCuts`]): the clusters `first .. first + count` of
/// [`TinyCuts::clusters`]. It is the instance's cut when its error (`error`, the next group error
/// to refine, weighted with `coverage` as the instance counts it: `common/lod.glsl`'s
/// `weighted_error`) projects to at most the threshold on the mesh's LOD bound and the previous
/// row's does not.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TinyRow {
    /// The row's threshold: every cluster's self error is at most it.
    pub error: f32,
    pub first: u32,
    pub count: u32,
    /// The largest coverage part of its clusters' self errors (`BuiltMesh::group_coverage_of`),
    /// at least every finer row's: with `error`, what a small instance weighs the row by.
    pub coverage: f32,
}

/// The cuts of a small instance, from the root down to [`TINY_CUT_CLUSTERS`] clusters: what
/// `instance_cull` draws (each cluster still tested for the frustum and the HZB) without walking
/// the BVH (docs/architecture.md, "Small instances: a cut from a table").
///
/// An instance far from the camera compared to its size projects every group's error at about
/// the same distance. Measuring all of them at the point of the mesh's LOD bound (a sphere around
/// the mesh's centre enclosing every group's LOD sphere: `MeshGpu::walk_radius`) nearest to the
/// camera makes each projection at least as large as at its own sphere, so the cut is as fine
/// or finer everywhere (never coarser than the threshold allows). With one distance for all, the
/// cut depends only on which group errors project over the threshold: as the threshold falls it
/// refines the groups in decreasing order of error, so there is one cut per distinct group error,
/// and the coarse ones, up to [`TINY_CUT_CLUSTERS`] clusters, fit a small table. Each is a cut
/// of the DAG with monotonic errors (crack-free): a cluster is in row `k`'s cut iff its parent
/// error is larger than the row's `error` and its self error is at most that. A small instance
/// weighs the rows' errors (keeping their coverage part whole) and takes the first that is fine:
/// a cut as fine as or finer than the per-group rule with those weighted errors.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TinyCuts {
    /// Coarsest first; `error` decreasing.
    pub rows: Vec<TinyRow>,
    /// The rows' clusters (mesh-local indices), row after row.
    pub clusters: Vec<u32>,
}

impl TinyCuts {
    /// The table of `m`'s small-instance cuts: rows while a cut has at most
    /// [`TINY_CUT_CLUSTERS`] clusters and all rows together at most [`TINY_CUT_ENTRIES`].
    pub fn of(m: &BuiltMesh) -> Self {
        let mut out = TinyCuts::default();
        if m.clusters.is_empty() {
            return out;
        }
        // The thresholds: every distinct finite group error, decreasing, then 0 (below every
        // positive error: the cut of the whole first level).
        let mut errors: Vec<f32> = m
            .clusters
            .iter()
            .map(|c| c.parent_error)
            .filter(|e| e.is_finite())
            .map(|e| e.max(0.0))
            .collect();
        errors.sort_unstable_by(|a, b| b.total_cmp(a));
        errors.dedup();
        if errors.last().is_none_or(|&e| e > 0.0) {
            errors.push(0.0);
        }
        // Clusters by decreasing parent error: a row's cut lies in the prefix whose parent error
        // is above its threshold, which grows as the threshold falls.
        let mut order: Vec<u32> = (0..m.clusters.len() as u32).collect();
        order.sort_by(|&a, &b| {
            let (a, b) = (&m.clusters[a as usize], &m.clusters[b as usize]);
            b.parent_error.total_cmp(&a.parent_error)
        });
        let mut prefix = 0;
        for &e in &errors {
            while prefix < order.len() && m.clusters[order[prefix] as usize].parent_error > e {
                prefix += 1;
            }
            let first = out.clusters.len();
            for &ci in &order[..prefix] {
                if m.clusters[ci as usize].self_error <= e {
                    out.clusters.push(ci);
                }
            }
            let count = out.clusters.len() - first;
            if count > TINY_CUT_CLUSTERS as usize || out.clusters.len() > TINY_CUT_ENTRIES as usize
            {
                out.clusters.truncate(first);
                break;
            }
            out.clusters[first..].sort_unstable();
            let coverage = out.clusters[first..]
                .iter()
                .map(|&ci| match m.clusters[ci as usize].creator {
                    NO_GROUP => 0.0,
                    g => m.group_coverage_of(g),
                })
                .fold(0.0, f32::max);
            out.rows.push(TinyRow {
                error: e,
                first: first as u32,
                count: count as u32,
                coverage,
            });
        }
        // Coarser rows hold at least the coverage of finer ones, so a weighted row error falls
        // row by row as the unweighted one does (the GPU's binary search needs it).
        let mut below = 0.0f32;
        for r in out.rows.iter_mut().rev() {
            r.coverage = r.coverage.max(below);
            below = r.coverage;
        }
        out
    }

    /// The table as `instance_cull` reads it (u32 words): the row count; per row
    /// ([`TINY_ROW_WORDS`]) its error's bits, the word where its clusters start (relative to the
    /// table's first word), its cluster count and its coverage's bits; then the clusters.
    pub fn words(&self) -> Vec<u32> {
        let head = 1 + TINY_ROW_WORDS * self.rows.len() as u32;
        let mut w = Vec::with_capacity(head as usize + self.clusters.len());
        w.push(self.rows.len() as u32);
        for r in &self.rows {
            w.extend([
                r.error.to_bits(),
                head + r.first,
                r.count,
                r.coverage.to_bits(),
            ]);
        }
        w.extend_from_slice(&self.clusters);
        w
    }

    /// The row a cut for threshold `tau` takes, where `px(row)` projects a row's (weighted)
    /// error onto the mesh's LOD bound: the first whose error projects to at most `tau`, if any
    /// (`None`: the instance needs a finer cut than the table holds). `px` must not grow from
    /// a row to the next.
    pub fn row_for(&self, tau: f32, px: impl Fn(&TinyRow) -> f32) -> Option<&TinyRow> {
        let last = self.rows.last()?;
        if px(last) > tau {
            return None;
        }
        let k = self.rows.partition_point(|r| px(r) > tau);
        self.rows.get(k)
    }
}
