//! CPU oracle of the GPU cut: which `(instance, cluster)` pairs `cluster_cull` must draw for a view
//! with frustum culling off, computed with the same f32 operations as the shaders
//! (`shaders_glsl/common/cull.glsl`) and the one `lod_error_px` of `builder::cut`.

use glam::Vec3;

use crate::builder::cut::{TinyCuts, TinyRow, small_instance_weight, weighted_error};
use crate::builder::{BuiltMesh, lod_error_px};
use crate::camera::Camera;
use crate::render::Placement;
use crate::scene_gpu::instance_gpu;
use crate::shared::{
    InstanceVgeo, TINY_CUT_RADIUS_PX, ViewGpu, WALK_CLUSTERS, WALK_WIDE_INSTANCES,
};

/// One cluster of the CPU cut.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CutEntry {
    pub instance: u32,
    /// Global cluster index (mesh's first cluster + local index), as the GPU reports it.
    pub cluster: u32,
}

/// Camera-relative position, as `relative_position` in cull.glsl.
pub fn relative_position(inst: &InstanceVgeo, view: &ViewGpu, p: Vec3) -> Vec3 {
    let th = Vec3::from(inst.translation_hi);
    let tl = Vec3::from(inst.translation_lo);
    let ch = Vec3::from_slice(&view.camera_hi[..3]);
    let cl = Vec3::from_slice(&view.camera_lo[..3]);
    let t = (th - ch) + (tl - cl);
    let c0 = Vec3::from_slice(&inst.linear[0][..3]);
    let c1 = Vec3::from_slice(&inst.linear[1][..3]);
    let c2 = Vec3::from_slice(&inst.linear[2][..3]);
    let l = c0 * p.x + c1 * p.y + c2 * p.z;
    t + l
}

/// Pixels of projected error of (error, sphere) of an instance, and whether it is within
/// `rel_margin` of `tau` (a borderline value whose side may differ by float rounding on a GPU).
fn projected(inst: &InstanceVgeo, view: &ViewGpu, sphere: [f32; 4], error: f32) -> f32 {
    projected_weighted(inst, view, sphere, (error, error), 1.0)
}

/// [`projected`] of an error with coverage part `(error, coverage)` as an instance of weight
/// `weight` counts it (`common/lod.glsl`'s `weighted_error`, in the same order:
/// `max(error * weight, coverage) * scale`).
fn projected_weighted(
    inst: &InstanceVgeo,
    view: &ViewGpu,
    sphere: [f32; 4],
    (error, coverage): (f32, f32),
    weight: f32,
) -> f32 {
    let c = relative_position(inst, view, Vec3::new(sphere[0], sphere[1], sphere[2]));
    lod_error_px(
        weighted_error(error, coverage, weight) * inst.max_scale,
        c,
        sphere[3] * inst.max_scale,
        Vec3::ZERO,
        view.proj_scale,
    )
}

/// The share of its LOD errors instance `inst` of mesh `m` counts in `view`
/// ([`small_instance_weight`] of its bounding sphere's projected radius: `common/lod.glsl`'s
/// `instance_weight`).
pub fn instance_weight(m: &BuiltMesh, inst: &InstanceVgeo, view: &ViewGpu) -> f32 {
    let (bc, br) = crate::scene_gpu::mesh_sphere(m);
    small_instance_weight(projected(inst, view, [bc[0], bc[1], bc[2], br], br))
}

/// Pixels of group `g`'s error (on its LOD sphere) as instance `inst` of mesh `m` counts it with
/// weight `weight` ([`instance_weight`]): the error weighted, its coverage part whole, as the
/// cull's tests project it.
pub fn group_error_px(
    m: &BuiltMesh,
    inst: &InstanceVgeo,
    view: &ViewGpu,
    g: u32,
    weight: f32,
) -> f32 {
    let grp = &m.groups[g as usize];
    let e = (grp.error, m.group_coverage_of(g));
    projected_weighted(inst, view, grp.lod_sphere, e, weight)
}

/// The cut of every instance for `view` (error threshold `view.error_px`), and the entries whose
/// decision is within `rel_margin` of the threshold (borderline: either side is acceptable).
pub fn reference_cut(
    built: &[BuiltMesh],
    placements: &[Placement],
    view: &ViewGpu,
    rel_margin: f32,
) -> (Vec<CutEntry>, Vec<CutEntry>) {
    reference_cut_resident(
        built,
        &vec![None; built.len()],
        placements,
        view,
        rel_margin,
    )
}

/// [`reference_cut`] under page residency: `residency[mesh]` is the mesh's resident pages
/// (`None`: all), the cut rule of `builder::cut` (a group not wholly resident counts error 0).
/// Small instances, in a view of many instances, take `instance_cull`'s cut from the mesh's table
/// ([`TinyCuts`]): every error projected on the mesh's LOD bound; under partial residency the
/// finest row at most as fine as that whose clusters' pages are all resident
/// ([`resident_row`]). Every instance counts [`small_instance_weight`] of each error (of its
/// bounding sphere's projected radius) and its coverage part whole (`common/lod.glsl`'s
/// `instance_weight` and `weighted_error`).
pub fn reference_cut_resident(
    built: &[BuiltMesh],
    residency: &[Option<&[bool]>],
    placements: &[Placement],
    view: &ViewGpu,
    rel_margin: f32,
) -> (Vec<CutEntry>, Vec<CutEntry>) {
    let mut offsets = Vec::with_capacity(built.len());
    let mut total = 0u32;
    for m in built {
        offsets.push(total);
        total += m.clusters.len() as u32;
    }
    let tau = view.error_px;
    let near = |v: f32| {
        (v - tau).abs() <= rel_margin * tau.max(1e-6) || (v.is_infinite() && tau.is_infinite())
    };
    // Per mesh: its small-instance cuts and the LOD bound they are projected on (as the GPU's
    // MeshGpu holds them).
    let tiny: Vec<(TinyCuts, Vec3, f32)> = built
        .iter()
        .map(|m| {
            let (center, _) = crate::scene_gpu::mesh_sphere(m);
            let (_, _, radius) = crate::scene_gpu::walk_bound(m, center);
            (TinyCuts::of(m), Vec3::from(center), radius)
        })
        .collect();
    let mut cut = Vec::new();
    let mut borderline = Vec::new();
    for (i, p) in placements.iter().enumerate() {
        let inst = instance_gpu(p);
        let m = &built[p.mesh as usize];
        let res = residency.get(p.mesh as usize).copied().flatten();
        let partial = res.is_some_and(|r| r.iter().any(|&x| !x));
        // `instance_cull`'s small-instance path (`emit_tiny_cut`): every error projected on the
        // mesh's LOD bound. Its cut is the first row whose error projects to at most tau, the
        // per-cluster rule with that one projection (builder::cut::TinyCuts; `by_bound` below
        // marks the borderline clusters by it).
        let (table, center, radius) = &tiny[p.mesh as usize];
        let bound = [center.x, center.y, center.z, *radius];
        // The instance's bounding sphere's projected radius (the same projection, its radius as
        // the "error"), and the share of its errors that counts at that size.
        let (bc, br) = crate::scene_gpu::mesh_sphere(m);
        let size = projected(&inst, view, [bc[0], bc[1], bc[2], br], br);
        let weight = small_instance_weight(size);
        let uniform = |e: (f32, f32)| projected_weighted(&inst, view, bound, e, weight);
        let row_px = |r: &TinyRow| uniform((r.error, r.coverage));
        let last = table.rows.last().map(row_px);
        // Only in a view of many instances (`emit_tiny_cut`; the view's instance count is the
        // scene's).
        let wide = placements.len() >= WALK_WIDE_INSTANCES as usize;
        // A mesh of at most WALK_CLUSTERS clusters takes its table at any size.
        let any_size = m.clusters.len() <= WALK_CLUSTERS as usize;
        let small =
            wide && (any_size || size <= TINY_CUT_RADIUS_PX) && last.is_some_and(|px| px <= tau);
        // A small instance's cut is the table's row (`emit_tiny_cut`'s binary search), under
        // partial residency the finest resident row at most as fine.
        let row_clusters =
            |r: &TinyRow| &table.clusters[r.first as usize..(r.first + r.count) as usize];
        let pick = |k: usize| resident_row(m, table, k, res).map(|k| row_clusters(&table.rows[k]));
        let wanted = table.rows.partition_point(|r| row_px(r) > tau);
        let picked = pick(wanted);
        // With no resident row (not while the top is always resident) the GPU walks it.
        let small = small && picked.is_some();
        let row: &[u32] = picked.filter(|_| small).unwrap_or(&[]);
        // A row whose weighted error is at the threshold may be taken or passed over by the
        // GPU's rounding: the clusters in which the rows beside it differ are borderline (a
        // row's coverage may come from clusters other than those that change).
        let mut row_edge: Vec<u32> = Vec::new();
        if small {
            let mut alt = Vec::new();
            if table.rows.get(wanted).is_some_and(|r| near(row_px(r))) {
                alt.extend(pick(wanted + 1));
            }
            if wanted > 0 && near(row_px(&table.rows[wanted - 1])) {
                alt.extend(pick(wanted - 1));
            }
            for a in alt {
                row_edge.extend(a.iter().filter(|c| row.binary_search(c).is_err()));
                row_edge.extend(row.iter().filter(|c| a.binary_search(c).is_err()));
            }
            row_edge.sort_unstable();
        }
        // Near the table's edges (its size limit, a row's error at the threshold) the GPU may
        // take either path: clusters the two cuts disagree on are borderline.
        let size_edge =
            !any_size && (size - TINY_CUT_RADIUS_PX).abs() <= rel_margin * TINY_CUT_RADIUS_PX;
        let either = wide && (size_edge || last.is_some_and(near));
        for (ci, c) in m.clusters.iter().enumerate() {
            let (se, pe) = crate::builder::cut::resident_errors(m, c, res);
            // With their coverage parts (0 with the error, where a group is not resident).
            let part = |g: u32, e: f32| {
                (
                    e,
                    if e == 0.0 {
                        0.0
                    } else {
                        m.group_coverage_of(g)
                    },
                )
            };
            let (se, pe) = (part(c.creator, se), part(c.group, pe));
            let s = projected_weighted(&inst, view, c.self_sphere, se, weight);
            let q = projected_weighted(&inst, view, c.parent_sphere, pe, weight);
            let (us, uq) = (uniform(se), uniform(pe));
            let e = CutEntry {
                instance: i as u32,
                cluster: offsets[p.mesh as usize] + ci as u32,
            };
            let by_group = s <= tau && q > tau;
            let by_bound = us <= tau && uq > tau;
            let in_cut = if small {
                row.binary_search(&(ci as u32)).is_ok()
            } else {
                by_group
            };
            if in_cut {
                cut.push(e);
            }
            let edge = if small {
                near(us) || near(uq) || row_edge.binary_search(&(ci as u32)).is_ok()
            } else {
                near(s) || near(q)
            };
            // Under partial residency the table's row may be coarser than `by_bound`'s.
            let by_row = partial && picked.is_some_and(|r| r.binary_search(&(ci as u32)).is_ok());
            if edge || (either && (by_group != by_bound || (partial && by_group != by_row))) {
                borderline.push(e);
            }
        }
    }
    (cut, borderline)
}

/// The row a small instance of `m` draws when its table's row `wanted` is the one fine enough
/// (`emit_tiny_cut`): under `res` (resident pages; `None`: all) the finest row at most as fine
/// whose clusters' pages are all resident; `None` when the table has no such row (the instance
/// is walked).
pub fn resident_row(
    m: &BuiltMesh,
    table: &TinyCuts,
    wanted: usize,
    res: Option<&[bool]>,
) -> Option<usize> {
    let resident = |k: usize| {
        let r = &table.rows[k];
        table.clusters[r.first as usize..(r.first + r.count) as usize]
            .iter()
            .all(|&c| res.is_none_or(|res| res[m.clusters[c as usize].page as usize]))
    };
    if wanted >= table.rows.len() {
        return None;
    }
    (0..=wanted).rev().find(|&k| resident(k))
}

/// Convenience: the [`ViewGpu`] the GPU would use, for [`reference_cut`].
pub fn view_for(
    camera: &Camera,
    width: u32,
    height: u32,
    settings: &crate::passes::view::FrameSettings,
) -> ViewGpu {
    crate::passes::view::view_gpu(camera, width, height, settings, 0, 0, 0)
}
