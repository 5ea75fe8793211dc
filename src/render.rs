//! What a render produces, independent of the path that made it.

use std::path::Path;

use glam::{DMat4, Vec3};

/// One placed copy of a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Index into the mesh list.
    pub mesh: u32,
    /// Object -> world, in f64 (made camera-relative before it becomes f32).
    pub transform: DMat4,
    /// Albedo tint.
    pub color: [f32; 3],
}

/// Lighting of a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Direction towards the light (world space).
    pub direction: Vec3,
}

impl Default for Light {
    fn default() -> Self {
        Self {
            direction: Vec3::new(0.4, 1.0, 0.6).normalize(),
        }
    }
}

/// Background colour of every path (linear RGBA, before the output encoding).
pub const BACKGROUND: [f32; 4] = [0.02, 0.02, 0.03, 1.0];

/// A rendered frame read back to the CPU.
#[derive(Clone, Debug)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    /// RGBA8, row-major, top row first.
    pub color: Vec<u8>,
    /// Reverse-Z depth per pixel; 0.0 where nothing was drawn.
    pub depth: Vec<f32>,
    /// GPU milliseconds per pass (empty without timestamp support).
    pub gpu_ms: Vec<(String, f64)>,
    /// Triangles submitted for drawing.
    pub triangles: u64,
}

impl Frame {
    /// Total GPU time of all passes.
    pub fn gpu_total_ms(&self) -> f64 {
        self.gpu_ms.iter().map(|(_, ms)| ms).sum()
    }

    /// Pixels where something was drawn.
    pub fn covered(&self) -> usize {
        self.depth.iter().filter(|d| **d > 0.0).count()
    }

    /// Writes the colour image as PNG.
    pub fn save_png(&self, path: &Path) -> anyhow::Result<()> {
        let img = image::RgbaImage::from_raw(self.width, self.height, self.color.clone())
            .ok_or_else(|| anyhow::anyhow!("frame buffer has the wrong size"))?;
        img.save(path)
            .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))
    }
}

/// A scene with its meshes imported, ready for any rendering path.
pub struct LoadedScene {
    pub scene: crate::scene::Scene,
    /// `meshes[i]` is `scene.meshes[i]`, imported (all parts merged).
    pub meshes: Vec<crate::mesh::Mesh>,
    /// Cluster DAGs of the meshes loaded from `.vgeo` files (`None`: built by
    /// [`LoadedScene::built_meshes`], which moves them all out).
    pub built: Vec<Option<crate::builder::BuiltMesh>>,
    pub placements: Vec<Placement>,
    pub light: Light,
    /// Import warnings (each names its file).
    pub warnings: Vec<String>,
}

impl LoadedScene {
    /// Loads a scene file (`.toml`) or a single mesh file (auto-framed).
    pub fn load(path: &Path) -> anyhow::Result<Self> {
        let is_scene = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
        let scene = if is_scene {
            crate::scene::Scene::load(path)?
        } else {
            crate::scene::Scene::single_mesh(path)
        };
        let mut meshes = Vec::with_capacity(scene.meshes.len());
        let mut built = Vec::with_capacity(scene.meshes.len());
        let mut warnings = Vec::new();
        for m in &scene.meshes {
            let before = meshes.len();
            let generated = m
                .path
                .to_str()
                .and_then(|p| p.strip_prefix(crate::scene::GENERATED_PREFIX));
            if let Some(name) = generated {
                let mesh = crate::bench::generated_mesh(name).ok_or_else(|| {
                    anyhow::anyhow!(
                        "mesh `{}`: unknown generated mesh `{name}` (available: grass, box)",
                        m.name
                    )
                })?;
                meshes.push(mesh);
                built.push(None);
            } else if m
                .path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("vgeo"))
            {
                let bytes = std::fs::read(&m.path)
                    .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", m.path.display()))?;
                let b = crate::format::load(&bytes)
                    .map_err(|e| anyhow::anyhow!("{}: {e}", m.path.display()))?;
                meshes.push(b.level_mesh(0));
                built.push(Some(b));
            } else {
                let (mesh, report) = crate::mesh::load_mesh(&m.path)?;
                // The importer's warnings already name the file.
                warnings.extend(report.warnings);
                meshes.push(mesh);
                built.push(None);
            }
            if let (Some(n), Some(mesh)) = (m.materials, meshes.get_mut(before)) {
                crate::mesh::assign_patch_materials(mesh, n);
            }
        }
        let placements = scene
            .instances
            .iter()
            .map(|i| Placement {
                mesh: i.mesh,
                transform: i.transform,
                color: i.color,
            })
            .collect();
        let light = Light {
            direction: scene.light_dir,
        };
        Ok(Self {
            scene,
            meshes,
            built,
            placements,
            light,
            warnings,
        })
    }

    /// The cluster DAG of every mesh, moved out of the scene: loaded `.vgeo` files as they are, the
    /// others built now (in parallel, default options; `progress` receives one line per mesh
    /// built). Afterwards `built` is empty; nothing is copied.
    pub fn built_meshes(
        &mut self,
        progress: &(dyn Fn(&str) + Sync),
    ) -> anyhow::Result<Vec<crate::builder::BuiltMesh>> {
        use rayon::prelude::*;
        let opts = crate::builder::BuildOptions::default();
        if self.built.len() != self.meshes.len() {
            anyhow::bail!("the scene's cluster DAGs were already taken");
        }
        let built = std::mem::take(&mut self.built);
        built
            .into_par_iter()
            .zip(self.meshes.par_iter())
            .zip(self.scene.meshes.par_iter())
            .map(|((b, mesh), sm)| match b {
                Some(b) => Ok(b),
                None => {
                    let t = std::time::Instant::now();
                    let b = crate::builder::build(mesh, &opts)
                        .map_err(|e| anyhow::anyhow!("{}: {e}", sm.path.display()))?;
                    progress(&format!(
                        "built {} ({} triangles, {} clusters, {} levels) in {:.2} s",
                        sm.name,
                        mesh.triangle_count(),
                        b.clusters.len(),
                        b.stats.levels.len(),
                        t.elapsed().as_secs_f64()
                    ));
                    Ok(b)
                }
            })
            .collect()
    }

    /// The scene's camera for an image of `width` x `height`.
    pub fn camera(&self, width: u32, height: u32) -> crate::camera::Camera {
        let bounds: Vec<_> = self
            .meshes
            .iter()
            .map(|m| m.bounds().unwrap_or(([0.0; 3], [0.0; 3])))
            .collect();
        self.scene
            .camera(&bounds, width as f32 / height.max(1) as f32)
    }

    /// Triangles in the scene (instanced).
    pub fn scene_triangles(&self) -> u64 {
        self.placements
            .iter()
            .map(|p| self.meshes[p.mesh as usize].triangle_count() as u64)
            .sum()
    }
}
