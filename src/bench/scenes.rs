//! The benchmark's scenes: a scene file loaded through the run's mesh cache, thinned to the
//! suite's triangle budget, with its camera path; `stress` as an N x N x N grid of one instance.

use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use anyhow::{Context as _, Result};
use glam::{DMat4, DVec3, Vec3};

use super::BenchSettings;
use super::report::SceneInfo;
use crate::Camera;
use crate::Mesh;
use crate::scene::Scene;
use crate::scene::load::{LoadedScene, MeshCache, PreparedMesh, thin, triangles_of};
use crate::{Light, Placement};

/// A scene ready to render: meshes (prepared through the run's [`MeshCache`]), placements and
/// the cameras of its path.
pub(super) struct BenchScene {
    pub(super) info: SceneInfo,
    pub(super) meshes: Vec<Arc<PreparedMesh>>,
    pub(super) placements: Vec<Placement>,
    pub(super) cameras: Vec<Camera>,
    pub(super) light: Light,
}

impl BenchScene {
    pub(super) fn mesh_list(&self) -> Vec<&Mesh> {
        self.meshes.iter().map(|p| &p.mesh).collect()
    }
}

pub(super) fn load_scene(
    cache: &mut MeshCache,
    file: &Path,
    name: &str,
    settings: &BenchSettings,
    stress_n: Option<u32>,
) -> Result<BenchScene> {
    let t0 = Instant::now();
    let loaded = LoadedScene::load_with(cache, file)?;
    let prepare_s = t0.elapsed().as_secs_f64();
    let bounds = loaded.mesh_bounds();
    let aspect = settings.width as f32 / settings.height as f32;
    let (placements, cameras) = match stress_n {
        None => {
            let cameras = loaded.scene.path_cameras(&bounds, aspect, settings.frames);
            (loaded.placements.clone(), cameras)
        }
        Some(n) => stress_grid(&loaded.scene, &bounds, n, settings.frames)?,
    };
    let meshes = loaded.meshes();
    let instances_in_scene = placements.len() as u64;
    let placements = thin(placements, &meshes, settings.max_scene_triangles);
    let stored_triangles = meshes.iter().map(|m| m.triangle_count() as u64).sum();
    Ok(BenchScene {
        info: SceneInfo {
            name: name.to_string(),
            file: file.to_path_buf(),
            stress_n,
            instances: placements.len() as u64,
            instances_in_scene,
            scene_triangles: triangles_of(&placements, &meshes),
            stored_triangles,
            meshes: loaded.scene.meshes.iter().map(|m| m.name.clone()).collect(),
            frames: cameras.len() as u32,
            prepare_s,
            build_s: 0.0,
            reference_s: 0.0,
        },
        meshes: loaded.prepared.clone(),
        placements,
        cameras,
        light: loaded.light,
    })
}

/// The stress scene: the file's first instance repeated on an `n`^3 grid (spacing 1.3 times the
/// instance's largest extent), and a path from outside the grid's corner into it.
fn stress_grid(
    scene: &Scene,
    bounds: &[([f32; 3], [f32; 3])],
    n: u32,
    frames: u32,
) -> Result<(Vec<Placement>, Vec<Camera>)> {
    let template = scene
        .instances
        .first()
        .context("the stress scene needs an instance to repeat")?;
    let one = Scene {
        instances: vec![template.clone()],
        ..scene.clone()
    };
    let (lo, hi) = one
        .bounds(bounds)
        .context("the stress scene's mesh is empty")?;
    let size = (hi - lo).max_element();
    let spacing = size * 1.3;
    let centre0 = (lo + hi) * 0.5;
    let mut placements = Vec::with_capacity((n as usize).pow(3));
    for k in 0..n {
        for j in 0..n {
            for i in 0..n {
                let offset = DVec3::new(i as f64, j as f64, k as f64) * spacing - centre0;
                placements.push(Placement {
                    mesh: template.mesh,
                    transform: DMat4::from_translation(offset) * template.transform,
                    color: template.color,
                });
            }
        }
    }
    // The grid spans [-size/2, (n - 1) spacing + size/2] on every axis.
    let extent = (n - 1) as f64 * spacing + size;
    let centre = DVec3::splat((n - 1) as f64 * spacing * 0.5);
    let keys = [
        crate::scene::PathKey {
            eye: centre + DVec3::new(0.9, 0.55, 1.6) * extent,
            target: centre,
        },
        crate::scene::PathKey {
            eye: centre + DVec3::new(0.35, 0.3, 0.75) * extent,
            target: centre + DVec3::new(-0.1, 0.0, 0.0) * extent,
        },
    ];
    let near = (size * 0.01) as f32;
    let cameras = crate::scene::interpolate_path(&keys, frames)
        .into_iter()
        .map(|k| Camera::look_at(k.eye, k.target, Vec3::Y, 45f32.to_radians(), near))
        .collect();
    Ok((placements, cameras))
}
