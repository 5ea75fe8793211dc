//! The LOD cut rule, the one definition shared by the CPU (verify, reference) and, mirrored
//! operation for operation, the GPU `cluster_cull` shader.
//!
//! Cluster `c` is drawn for threshold `tau` pixels iff
//! `lod_error_px(c.self) <= tau && lod_error_px(c.parent) > tau`.
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
