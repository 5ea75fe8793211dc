//! vgeo's stress scene (`src/bench/scenes.rs::stress_grid` with `assets/scenes/stress.toml`):
//! the template instance repeated on an N x N x N grid, and the camera path into it.

use bevy::math::{DMat3, DMat4, DQuat, DVec3};
use bevy::prelude::*;

use crate::Args;
use crate::mesh_io::TriMesh;

/// `assets/scenes/stress.toml`'s instance: `rotation_deg = [-90, 0, 0]` (R = Rz Ry Rx),
/// `scale = 0.1`, `color = [0.75, 0.72, 0.68]`; its light `direction = [0.4, 1.0, 0.6]`.
const ROTATION_DEG: [f64; 3] = [-90.0, 0.0, 0.0];
const SCALE: f64 = 0.1;
const COLOR: [f32; 3] = [0.75, 0.72, 0.68];
const LIGHT_DIR: [f32; 3] = [0.4, 1.0, 0.6];

pub struct StressScene {
    pub placements: Vec<Transform>,
    /// (eye, target) per frame of the path.
    pub cameras: Vec<(Vec3, Vec3)>,
    pub fov_y: f32,
    pub near: f32,
    pub far: f32,
    pub spacing: f64,
    pub color: [f32; 3],
    pub light_dir: Vec3,
    pub mesh_triangles: u64,
}

impl StressScene {
    pub fn new(mesh: &TriMesh, args: &Args) -> Self {
        let r = ROTATION_DEG;
        let rotation = DQuat::from_rotation_z(r[2].to_radians())
            * DQuat::from_rotation_y(r[1].to_radians())
            * DQuat::from_rotation_x(r[0].to_radians());
        let template =
            DMat4::from_scale_rotation_translation(DVec3::splat(SCALE), rotation, DVec3::ZERO);
        // Scene::bounds of the one instance: the object box's centre transformed, half extents
        // through |M|.
        let (blo, bhi) = mesh.bounds();
        let (blo, bhi) = (Vec3::from(blo).as_dvec3(), Vec3::from(bhi).as_dvec3());
        let centre = template.transform_point3((blo + bhi) * 0.5);
        let half = (bhi - blo) * 0.5;
        let m = DMat3::from_mat4(template);
        let ext = m.x_axis.abs() * half.x + m.y_axis.abs() * half.y + m.z_axis.abs() * half.z;
        let (lo, hi) = (centre - ext, centre + ext);
        let size = (hi - lo).max_element();
        let spacing = size * 1.3;
        let centre0 = (lo + hi) * 0.5;
        let n = args.n;
        let rot = rotation.as_quat();
        let mut placements = Vec::with_capacity((n as usize).pow(3));
        for k in 0..n {
            for j in 0..n {
                for i in 0..n {
                    let offset = DVec3::new(i as f64, j as f64, k as f64) * spacing - centre0;
                    placements.push(Transform {
                        translation: offset.as_vec3(),
                        rotation: rot,
                        scale: Vec3::splat(SCALE as f32),
                    });
                }
            }
        }
        let extent = (n - 1) as f64 * spacing + size;
        let gc = DVec3::splat((n - 1) as f64 * spacing * 0.5);
        let keys = [
            (gc + DVec3::new(0.9, 0.55, 1.6) * extent, gc),
            (
                gc + DVec3::new(0.35, 0.3, 0.75) * extent,
                gc + DVec3::new(-0.1, 0.0, 0.0) * extent,
            ),
        ];
        let cameras = interpolate_path(&keys, args.frames)
            .into_iter()
            .map(|(e, t)| (e.as_vec3(), t.as_vec3()))
            .collect();
        StressScene {
            placements,
            cameras,
            fov_y: 45f32.to_radians(),
            near: (size * 0.01) as f32,
            // vgeo's projection has no far plane; Bevy's is infinite too but culls beyond `far`.
            far: (extent * 10.0) as f32,
            spacing,
            color: COLOR,
            light_dir: Vec3::from(LIGHT_DIR).normalize(),
            mesh_triangles: (mesh.indices.len() / 3) as u64,
        }
    }
}

/// vgeo's `scene::interpolate_path`: `frames` cameras evenly along the keys' segments.
fn interpolate_path(keys: &[(DVec3, DVec3)], frames: u32) -> Vec<(DVec3, DVec3)> {
    let segments = (keys.len() - 1) as f64;
    (0..frames)
        .map(|i| {
            if frames <= 1 || segments == 0.0 {
                return keys[0];
            }
            let t = i as f64 / (frames - 1) as f64 * segments;
            let k = (t.floor() as usize).min(keys.len() - 2);
            let f = t - k as f64;
            let (a, b) = (keys[k], keys[k + 1]);
            let eye = a.0.lerp(b.0, f);
            let mut target = a.1.lerp(b.1, f);
            if target == eye {
                target = eye + (a.1 - a.0);
            }
            (eye, target)
        })
        .collect()
}
