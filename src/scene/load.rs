//! The one way a scene's meshes are loaded and built. `vgeo render`, `vgeo bench`, `vgeo build`
//! (of a scene file) and the tests all go through [`MeshCache`] and [`LoadedScene`], so every scene
//! option (`materials = N`, generated meshes, `.vgeo` files) applies to every path alike.
//!
//! A [`MeshCache`] holds [`PreparedMesh`]es keyed by [`MeshKey`]: the mesh's path and the scene
//! options that change it. Its import and build options are fixed at creation, so the key and the
//! cache together determine the mesh and its cluster DAG. Scenes loaded through one cache share
//! their meshes (the benchmark loads every scene through one).

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::{Arc, OnceLock};
use std::time::Instant;

use anyhow::{Context as _, Result};

use crate::builder::{BuildOptions, BuiltMesh};
use crate::camera::Camera;
use crate::mesh::{ImportOptions, Mesh};
use crate::render::{Light, Placement};
use crate::scene::{GENERATED_PREFIX, Scene, SceneMesh, generated};

/// What makes two scene meshes one prepared mesh: the file (or `generated:NAME`) and every scene
/// option that changes the mesh.
#[derive(Clone, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct MeshKey {
    /// As in [`SceneMesh::path`].
    pub path: PathBuf,
    /// [`SceneMesh::materials`]: the mesh's materials replaced by this many generated patches.
    pub materials: Option<u32>,
}

impl MeshKey {
    /// The key of a scene's mesh entry.
    pub fn of(m: &SceneMesh) -> Self {
        Self {
            path: m.path.clone(),
            materials: m.materials,
        }
    }
}

/// A scene mesh imported (or generated, or read from a `.vgeo` file) with the scene's options
/// applied, and its cluster DAG once built.
pub struct PreparedMesh {
    /// What it was made from.
    pub key: MeshKey,
    /// The full-detail mesh (of a `.vgeo` file: its level 0).
    pub mesh: Mesh,
    /// Import warnings, each naming its file.
    pub warnings: Vec<String>,
    build: BuildOptions,
    built: OnceLock<BuiltMesh>,
}

impl PreparedMesh {
    /// Imports, generates or reads the mesh of `key` and applies its options.
    pub fn prepare(key: &MeshKey, import: &ImportOptions, build: &BuildOptions) -> Result<Self> {
        let path = &key.path;
        let text = path.to_string_lossy();
        let built = OnceLock::new();
        let mut warnings = Vec::new();
        let mut mesh = if let Some(name) = text.strip_prefix(GENERATED_PREFIX) {
            generated::generated_mesh(name).with_context(|| {
                format!(
                    "unknown generated mesh `{text}` (available: {})",
                    generated::NAMES
                        .map(|n| format!("{GENERATED_PREFIX}{n}"))
                        .join(", ")
                )
            })?
        } else if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("vgeo"))
        {
            let bytes =
                std::fs::read(path).with_context(|| format!("cannot read {}", path.display()))?;
            let b = crate::format::load(&bytes)
                .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
            let mesh = b.level_mesh(0);
            let _ = built.set(b);
            mesh
        } else {
            let import = crate::mesh::load(path, import)?;
            // The importer's warnings already name the file.
            warnings = import.report.warnings;
            crate::mesh::merge(import.meshes)
        };
        if let Some(n) = key.materials {
            if built.get().is_some() {
                anyhow::bail!(
                    "{}: materials = {n} needs the source mesh (a .vgeo file keeps its built materials)",
                    path.display()
                );
            }
            crate::mesh::assign_patch_materials(&mut mesh, n);
        }
        mesh.validate()
            .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
        Ok(Self {
            key: key.clone(),
            mesh,
            warnings,
            build: build.clone(),
            built,
        })
    }

    /// The cluster DAG if it is there already (read from a `.vgeo` file, or built).
    pub fn built_if_ready(&self) -> Option<&BuiltMesh> {
        self.built.get()
    }

    /// The cluster DAG: read from the `.vgeo` file, or built now with the cache's options (once;
    /// later calls return the same). `progress` gets the builder's phase lines.
    pub fn built_with(&self, progress: &(dyn Fn(&str) + Sync)) -> Result<&BuiltMesh> {
        if let Some(b) = self.built.get() {
            return Ok(b);
        }
        let b = crate::builder::build_with_progress(&self.mesh, &self.build, progress)
            .map_err(|e| anyhow::anyhow!("{}: {e}", self.key.path.display()))?;
        // Another thread may have built it meanwhile: both results are equal (deterministic).
        Ok(self.built.get_or_init(|| b))
    }

    /// [`PreparedMesh::built_with`] without progress.
    pub fn built(&self) -> Result<&BuiltMesh> {
        self.built_with(&|_| {})
    }
}

/// Prepared meshes by [`MeshKey`], made with one set of import and build options.
pub struct MeshCache {
    import: ImportOptions,
    build: BuildOptions,
    entries: HashMap<MeshKey, Arc<PreparedMesh>>,
}

impl Default for MeshCache {
    /// Default import and build options (what `vgeo render` and `vgeo bench` use).
    fn default() -> Self {
        Self::new(ImportOptions::default(), BuildOptions::default())
    }
}

impl MeshCache {
    /// An empty cache whose meshes are imported with `import` and built with `build`.
    pub fn new(import: ImportOptions, build: BuildOptions) -> Self {
        Self {
            import,
            build,
            entries: HashMap::new(),
        }
    }

    /// The options meshes are built with.
    pub fn build_options(&self) -> &BuildOptions {
        &self.build
    }

    /// Meshes held.
    pub fn len(&self) -> usize {
        self.entries.len()
    }

    /// Whether the cache holds no mesh.
    pub fn is_empty(&self) -> bool {
        self.entries.is_empty()
    }

    /// The prepared mesh of every entry of `scene.meshes`, in order: those cached are shared, the
    /// others imported now (in parallel).
    pub fn prepare(&mut self, scene: &Scene) -> Result<Vec<Arc<PreparedMesh>>> {
        use rayon::prelude::*;
        let mut missing: Vec<MeshKey> = scene
            .meshes
            .iter()
            .map(MeshKey::of)
            .filter(|k| !self.entries.contains_key(k))
            .collect();
        missing.sort();
        missing.dedup();
        let (import, build) = (&self.import, &self.build);
        let made: Vec<Result<PreparedMesh>> = missing
            .par_iter()
            .map(|k| PreparedMesh::prepare(k, import, build))
            .collect();
        for p in made {
            let p = p?;
            self.entries.insert(p.key.clone(), Arc::new(p));
        }
        scene
            .meshes
            .iter()
            .map(|m| {
                self.entries
                    .get(&MeshKey::of(m))
                    .cloned()
                    .with_context(|| format!("{}: not prepared", m.path.display()))
            })
            .collect()
    }
}

/// A scene with its meshes prepared, ready for any rendering path.
pub struct LoadedScene {
    /// The scene as its file describes it (a single mesh file becomes a scene of one instance).
    pub scene: Scene,
    /// `prepared[i]` is `scene.meshes[i]` with its options applied (shared with the cache and
    /// with other entries of the same [`MeshKey`]).
    pub prepared: Vec<Arc<PreparedMesh>>,
    /// Every instance: which of `prepared` and where.
    pub placements: Vec<Placement>,
    /// The scene's light.
    pub light: Light,
    /// Import warnings of the scene's meshes (each names its file).
    pub warnings: Vec<String>,
}

impl LoadedScene {
    /// Loads a scene file (`.toml`) or a single mesh file (auto-framed) with a cache of its own.
    pub fn load(path: &Path) -> Result<Self> {
        Self::load_with(&mut MeshCache::default(), path)
    }

    /// Loads a scene file (`.toml`) or a single mesh file through `cache`.
    pub fn load_with(cache: &mut MeshCache, path: &Path) -> Result<Self> {
        let is_scene = path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("toml"));
        let scene = if is_scene {
            Scene::load(path)?
        } else {
            Scene::single_mesh(path)
        };
        Self::from_scene(cache, scene)
    }

    /// Prepares the meshes of `scene` through `cache`.
    pub fn from_scene(cache: &mut MeshCache, scene: Scene) -> Result<Self> {
        let prepared = cache.prepare(&scene)?;
        let mut warnings = Vec::new();
        for (i, p) in prepared.iter().enumerate() {
            if !prepared[..i].iter().any(|q| Arc::ptr_eq(p, q)) {
                warnings.extend(p.warnings.iter().cloned());
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
            prepared,
            placements,
            light,
            warnings,
        })
    }

    /// The full-detail meshes, `meshes()[i]` for `scene.meshes[i]`.
    pub fn meshes(&self) -> Vec<&Mesh> {
        self.prepared.iter().map(|p| &p.mesh).collect()
    }

    /// Mesh `i` (an index into `scene.meshes`; panics when out of range).
    pub fn mesh(&self, i: u32) -> &Mesh {
        &self.prepared[i as usize].mesh
    }

    /// The cluster DAG of every mesh: read from `.vgeo` files or built before, the others built now
    /// (in parallel; `progress` receives one line per mesh built).
    pub fn built_meshes(&self, progress: &(dyn Fn(&str) + Sync)) -> Result<Vec<&BuiltMesh>> {
        use rayon::prelude::*;
        // Each mesh once, even when several entries share it.
        let mut todo: Vec<(usize, &Arc<PreparedMesh>)> = Vec::new();
        for (i, p) in self.prepared.iter().enumerate() {
            if p.built_if_ready().is_none() && !todo.iter().any(|(_, q)| Arc::ptr_eq(p, q)) {
                todo.push((i, p));
            }
        }
        todo.par_iter()
            .map(|(i, p)| {
                let t = Instant::now();
                let b = p.built()?;
                progress(&format!(
                    "built {} ({} triangles, {} clusters, {} levels) in {:.2} s",
                    self.scene.meshes[*i].name,
                    p.mesh.triangle_count(),
                    b.clusters.len(),
                    b.stats.levels.len(),
                    t.elapsed().as_secs_f64()
                ));
                Ok(())
            })
            .collect::<Result<Vec<()>>>()?;
        self.prepared.iter().map(|p| p.built()).collect()
    }

    /// Object-space bounds of each mesh (zero for an empty one).
    pub fn mesh_bounds(&self) -> Vec<([f32; 3], [f32; 3])> {
        self.prepared
            .iter()
            .map(|p| p.mesh.bounds().unwrap_or(([0.0; 3], [0.0; 3])))
            .collect()
    }

    /// The scene's camera for an image of `width` x `height`.
    pub fn camera(&self, width: u32, height: u32) -> Camera {
        self.scene
            .camera(&self.mesh_bounds(), width as f32 / height.max(1) as f32)
    }

    /// Triangles in the scene (instanced, full detail).
    pub fn scene_triangles(&self) -> u64 {
        triangles_of(&self.placements, &self.meshes())
    }
}

/// Full-detail triangles of `placements` of `meshes` (instanced).
pub fn triangles_of(placements: &[Placement], meshes: &[&Mesh]) -> u64 {
    placements
        .iter()
        .map(|p| meshes[p.mesh as usize].triangle_count() as u64)
        .sum()
}

/// Keeps every k-th of `placements` (the smallest k) so that at most `cap` full-detail triangles
/// remain (all of them when `cap` is `None`, and always at least one placement): how the quick
/// benchmark suite and the tests make large scenes small while keeping their spread.
pub fn thin(placements: Vec<Placement>, meshes: &[&Mesh], cap: Option<u64>) -> Vec<Placement> {
    let Some(cap) = cap else { return placements };
    let tris = triangles_of(&placements, meshes);
    if tris <= cap || placements.len() <= 1 {
        return placements;
    }
    let k = tris.div_ceil(cap.max(1)) as usize;
    placements.into_iter().step_by(k).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scene(text: &str) -> Scene {
        Scene::parse(text, Path::new("/nowhere/scene.toml")).expect("scene parses")
    }

    #[test]
    fn cache_keys_by_path_and_options() {
        let s = scene(
            "[[mesh]]\nname = \"a\"\npath = \"generated:box\"\n\
             [[mesh]]\nname = \"b\"\npath = \"generated:box\"\n\
             [[mesh]]\nname = \"c\"\npath = \"generated:box\"\nmaterials = 3\n\
             [[instance]]\nmesh = \"a\"\n[[instance]]\nmesh = \"c\"\n",
        );
        let mut cache = MeshCache::default();
        let loaded = LoadedScene::from_scene(&mut cache, s.clone()).unwrap();
        assert_eq!(cache.len(), 2, "one entry per (path, options)");
        assert!(Arc::ptr_eq(&loaded.prepared[0], &loaded.prepared[1]));
        assert!(!Arc::ptr_eq(&loaded.prepared[0], &loaded.prepared[2]));
        // The scene's option is applied: the box's 12 triangles over 3 patch materials.
        assert_eq!(loaded.mesh(0).materials.len(), 1);
        assert_eq!(loaded.mesh(2).materials.len(), 3);
        assert_eq!(loaded.scene_triangles(), 24);
        // Loading again shares what is cached, and builds each DAG once.
        let again = LoadedScene::from_scene(&mut cache, s).unwrap();
        assert_eq!(cache.len(), 2);
        assert!(Arc::ptr_eq(&loaded.prepared[2], &again.prepared[2]));
        let lines = std::sync::Mutex::new(Vec::new());
        let built = again
            .built_meshes(&|l| lines.lock().unwrap().push(l.to_string()))
            .unwrap();
        assert_eq!(built.len(), 3);
        assert!(std::ptr::eq(built[0], built[1]));
        assert_eq!(
            lines.lock().unwrap().len(),
            2,
            "{:?}",
            lines.lock().unwrap()
        );
        assert!(std::ptr::eq(
            loaded.prepared[2].built_if_ready().unwrap(),
            built[2]
        ));
    }

    #[test]
    fn unknown_generated_mesh_is_an_error() {
        let s = scene(
            "[[mesh]]\nname = \"a\"\npath = \"generated:cone\"\n[[instance]]\nmesh = \"a\"\n",
        );
        let e = LoadedScene::from_scene(&mut MeshCache::default(), s)
            .err()
            .expect("fails")
            .to_string();
        assert!(
            e.contains("generated:cone") && e.contains("generated:grass"),
            "{e}"
        );
    }
}
