//! Helpers shared by the integration tests.
#![allow(dead_code)]

pub mod cad;
pub mod shapes;

use std::path::PathBuf;

use vgeo::gpu::{Context, ContextOptions};

/// Build options at the step ratio `ratio`, the rest the defaults: for tests whose scenarios were
/// made for another ratio than the default (0.5, the default until session 37).
pub fn options_at_ratio(ratio: f32) -> vgeo::builder::BuildOptions {
    vgeo::builder::BuildOptions {
        simplify_ratio: ratio,
        ..Default::default()
    }
}

/// The shared asset collection: `VGEO_SHARED_ASSETS`, else `../shared/assets` beside the crate (CI's
/// layout), else `/work/shared/assets`. Panics with a clear message when none exists: tests that
/// need it must not pass silently without it.
pub fn shared_assets() -> PathBuf {
    let mut candidates: Vec<PathBuf> = std::env::var("VGEO_SHARED_ASSETS")
        .ok()
        .map(PathBuf::from)
        .into_iter()
        .collect();
    candidates.push(PathBuf::from(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../shared/assets"
    )));
    candidates.push(PathBuf::from("/work/shared/assets"));
    candidates
        .iter()
        .find(|p| p.is_dir())
        .cloned()
        .unwrap_or_else(|| {
            panic!("shared assets folder not found (tried {candidates:?}); set VGEO_SHARED_ASSETS")
        })
}

/// The repository's own assets folder.
pub fn assets() -> PathBuf {
    PathBuf::from(concat!(env!("CARGO_MANIFEST_DIR"), "/assets"))
}

/// A Vulkan context with the Khronos validation layer on (lavapipe in CI). Fails the test when no
/// device or no validation layer is available.
pub fn gpu() -> Context {
    let opts = ContextOptions {
        validation: true,
        ..ContextOptions::from_env()
    };
    Context::new(&opts).unwrap_or_else(|e| panic!("no Vulkan device for GPU tests: {e}"))
}

/// Fails the test if the validation layer reported any error.
pub fn assert_no_validation_errors(ctx: &Context) {
    let errors = ctx.validation_errors();
    assert!(
        errors.is_empty(),
        "{} Vulkan validation error(s):\n{}",
        errors.len(),
        errors.join("\n")
    );
}

/// Fails the test unless `gpu_hzb` (a `depth_pyramid` HZB of a `w` x `h` frame) equals, bit for
/// bit and level by level, the CPU reference built from `depth`.
pub fn assert_hzb_matches_reference(gpu_hzb: &[f32], depth: &[f32], w: u32, h: u32) {
    use vgeo::passes::depth_pyramid::{hzb_levels, hzb_reference};
    let cpu_hzb = hzb_reference(depth, w, h);
    assert_eq!(gpu_hzb.len(), cpu_hzb.len(), "{w}x{h}: HZB size");
    for (k, &(lw, lh, offset)) in hzb_levels(w, h).iter().enumerate() {
        let range = offset as usize..(offset + lw * lh) as usize;
        let differ = gpu_hzb[range.clone()]
            .iter()
            .zip(&cpu_hzb[range])
            .filter(|(a, b)| a.to_bits() != b.to_bits())
            .count();
        assert_eq!(differ, 0, "{w}x{h}: level {k} ({lw}x{lh}) differs");
    }
}

/// A flat square in the xy plane, `n` x `n` quads, centred on the origin, side 2.
pub fn wall_mesh(n: u32) -> vgeo::mesh::Mesh {
    let mut m = vgeo::mesh::Mesh {
        name: "wall".into(),
        materials: vec![vgeo::mesh::Material::default()],
        ..Default::default()
    };
    for y in 0..=n {
        for x in 0..=n {
            m.positions.push([
                x as f32 / n as f32 * 2.0 - 1.0,
                y as f32 / n as f32 * 2.0 - 1.0,
                0.0,
            ]);
            m.normals.push([0.0, 0.0, 1.0]);
            m.uvs.push([0.0, 0.0]);
        }
    }
    for y in 0..n {
        for x in 0..n {
            let i = y * (n + 1) + x;
            m.indices
                .extend([i, i + 1, i + n + 1, i + 1, i + n + 2, i + n + 1]);
            m.material_ids.extend([0, 0]);
        }
    }
    m
}

/// Imports a mesh and builds its DAG with default options (panics on failure: test input).
pub fn load_built(path: &std::path::Path) -> (vgeo::mesh::Mesh, vgeo::builder::BuiltMesh) {
    let (mesh, _) = vgeo::mesh::load_mesh(path).expect("mesh loads");
    let built =
        vgeo::builder::build(&mesh, &vgeo::builder::BuildOptions::default()).expect("mesh builds");
    (mesh, built)
}

/// A camera `dist_scale` bounding radii from the mesh's centre, looking at it from the front.
pub fn filling_camera(m: &vgeo::mesh::Mesh, dist_scale: f64) -> vgeo::camera::Camera {
    use glam::DVec3;
    let (lo, hi) = m.bounds().expect("bounds");
    let lo = DVec3::from(lo.map(f64::from));
    let hi = DVec3::from(hi.map(f64::from));
    let c = (lo + hi) * 0.5;
    let r = (hi - lo).length() * 0.5;
    vgeo::camera::Camera::look_at(
        c + DVec3::new(0.2, 0.1, 1.0).normalize() * r * dist_scale,
        c,
        glam::Vec3::Y,
        45f32.to_radians(),
        (r * 0.05) as f32,
    )
}

/// For each cluster, (fewest, most) drawn clusters on its paths up to the root (a cluster's
/// parents are the clusters its group produced): a cut is sound when every level-0 cluster has
/// (1, 1).
pub fn path_crossings(m: &vgeo::builder::BuiltMesh, cut: &[u32]) -> Vec<(u32, u32)> {
    let mut drawn = vec![0u32; m.clusters.len()];
    for &c in cut {
        drawn[c as usize] = 1;
    }
    let mut parents: Vec<Vec<u32>> = vec![Vec::new(); m.groups.len()];
    for (ci, c) in m.clusters.iter().enumerate() {
        if c.creator != vgeo::builder::NO_GROUP {
            parents[c.creator as usize].push(ci as u32);
        }
    }
    let mut order: Vec<u32> = (0..m.clusters.len() as u32).collect();
    order.sort_by_key(|&c| std::cmp::Reverse(m.clusters[c as usize].level));
    let mut up = vec![(0u32, 0u32); m.clusters.len()];
    for c in order {
        let d = drawn[c as usize];
        let ps = &parents[m.clusters[c as usize].group as usize];
        up[c as usize] = if ps.is_empty() {
            (d, d)
        } else {
            let mn = ps.iter().map(|&p| up[p as usize].0).min().unwrap_or(0);
            let mx = ps.iter().map(|&p| up[p as usize].1).max().unwrap_or(0);
            (d + mn, d + mx)
        };
    }
    up
}
