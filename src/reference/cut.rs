//! CPU oracle of the GPU cut: which `(instance, cluster)` pairs `cluster_cull` must draw for a view
//! with frustum culling off, computed with the same f32 operations as the shaders
//! (`shaders_glsl/common/cull.glsl`) and the one `lod_error_px` of `builder::cut`.

use glam::Vec3;

use crate::builder::{BuiltMesh, lod_error_px};
use crate::camera::Camera;
use crate::render::Placement;
use crate::scene_gpu::instance_gpu;
use crate::shared::{InstanceVgeo, ViewGpu};

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
    let c = relative_position(inst, view, Vec3::new(sphere[0], sphere[1], sphere[2]));
    lod_error_px(
        error * inst.max_scale,
        c,
        sphere[3] * inst.max_scale,
        Vec3::ZERO,
        view.proj_scale,
    )
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
    let mut cut = Vec::new();
    let mut borderline = Vec::new();
    for (i, p) in placements.iter().enumerate() {
        let inst = instance_gpu(p);
        let m = &built[p.mesh as usize];
        for (ci, c) in m.clusters.iter().enumerate() {
            let res = residency.get(p.mesh as usize).copied().flatten();
            let (se, pe) = crate::builder::cut::resident_errors(m, c, res);
            let s = projected(&inst, view, c.self_sphere, se);
            let q = projected(&inst, view, c.parent_sphere, pe);
            let e = CutEntry {
                instance: i as u32,
                cluster: offsets[p.mesh as usize] + ci as u32,
            };
            if s <= tau && q > tau {
                cut.push(e);
            }
            if near(s) || near(q) {
                borderline.push(e);
            }
        }
    }
    (cut, borderline)
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
