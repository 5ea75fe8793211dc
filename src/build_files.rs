//! Building `.vgeo` files: what `vgeo build`, `vgeo verify` and `vgeo info FILE.vgeo` do, as
//! library calls with no command line (the CLI, `src/cli/build.rs`, parses arguments, shows
//! progress and prints). A plan ([`plan_build`]) lists the outputs of an input (a mesh file, a
//! glTF's nodes, or every mesh of a scene with the scene's options, through the scene loader);
//! each [`BuildJob`] builds its mesh and [`write_vgeo`] stores it.

use std::ops::Deref;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::Context;

use crate::builder::{self, BuildOptions, BuiltMesh, VerifyOptions, VerifyReport};
use crate::mesh::{ImportOptions, Mesh};
use crate::scene::Scene;
use crate::scene::load::{LoadedScene, MeshCache, PreparedMesh};

/// Loads the meshes of `path` with the importer: one per glTF node with `split_nodes`, else one.
/// Import warnings are printed to stderr.
pub fn load_input(path: &Path, opts: &ImportOptions) -> anyhow::Result<Vec<Mesh>> {
    if !(opts.crease_deg >= 0.0 && opts.crease_deg <= 180.0) {
        anyhow::bail!("--crease-deg {} is not in 0..=180", opts.crease_deg);
    }
    let import = crate::mesh::load(path, opts)?;
    for w in &import.report.warnings {
        eprintln!("warning: {w}");
    }
    Ok(import.meshes)
}

/// What one output is made from.
enum Source {
    /// A glTF node's mesh (`split_nodes`).
    Node(Mesh),
    /// A mesh file, or a scene's mesh with the scene's options, through the scene loader
    /// ([`crate::scene::load`]: the path `vgeo render` and `vgeo bench` take).
    Prepared(Arc<PreparedMesh>),
}

/// One output of a build: a mesh and the `.vgeo` file it goes to.
pub struct BuildJob {
    /// The input named in messages.
    pub input: PathBuf,
    /// The `.vgeo` file to write.
    pub out: PathBuf,
    source: Source,
}

/// A built mesh: owned (a glTF node's) or the scene loader's (built once, shared).
pub enum Built<'a> {
    /// Built for this job.
    Owned(Box<BuiltMesh>),
    /// The scene loader's copy.
    Shared(&'a BuiltMesh),
}

impl Deref for Built<'_> {
    type Target = BuiltMesh;
    fn deref(&self) -> &BuiltMesh {
        match self {
            Built::Owned(m) => m,
            Built::Shared(m) => m,
        }
    }
}

impl BuildJob {
    /// Builds the job's mesh with `opts` (a scene's meshes were given their options by
    /// [`plan_build`]), reporting progress lines to `progress`.
    pub fn build(
        &self,
        opts: &BuildOptions,
        progress: &(dyn Fn(&str) + Sync),
    ) -> anyhow::Result<Built<'_>> {
        match &self.source {
            Source::Node(mesh) => builder::build_with_progress(mesh, opts, progress)
                .map(|m| Built::Owned(Box::new(m)))
                .map_err(|e| anyhow::anyhow!("{e:#}"))
                .with_context(|| format!("building {}", self.input.display())),
            Source::Prepared(p) => p
                .built_with(progress)
                .map(Built::Shared)
                .with_context(|| format!("building {}", self.input.display())),
        }
    }
}

/// What to build: [`plan_build`]'s input.
#[derive(Clone, Debug)]
pub struct BuildRequest {
    /// A mesh file (glTF/GLB, OBJ, PLY, STL, OFF) or a scene file (`.toml`).
    pub input: PathBuf,
    /// The output `.vgeo` (default: the input with extension `.vgeo`); for a scene, the output
    /// folder (default: `SCENE-vgeo` beside the scene file).
    pub out: Option<PathBuf>,
    /// Import options (`split_nodes`: each glTF node its own output, `OUT` a prefix).
    pub import: ImportOptions,
    /// Build options.
    pub build: BuildOptions,
}

/// The outputs of a [`BuildRequest`].
pub struct BuildPlan {
    /// One per output, in order.
    pub jobs: Vec<BuildJob>,
    /// Whether the input is a scene file.
    pub scene: bool,
    /// Import and scene warnings.
    pub warnings: Vec<String>,
    /// A scene's meshes given as `.vgeo` files (built already, no job).
    pub skipped: Vec<PathBuf>,
}

/// Whether `path` is a scene file (`.toml`).
pub fn is_scene_file(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("toml"))
}

/// The jobs of `req`: a mesh file gives one job (or one per glTF node with `split_nodes`:
/// `OUT_i.vgeo` when there are several); a scene file gives one per distinct (path, options) of
/// its meshes, to `OUT/NAME.vgeo` (creating the folder), skipping meshes given as `.vgeo`.
pub fn plan_build(req: &BuildRequest) -> anyhow::Result<BuildPlan> {
    if !(req.import.crease_deg >= 0.0 && req.import.crease_deg <= 180.0) {
        anyhow::bail!("--crease-deg {} is not in 0..=180", req.import.crease_deg);
    }
    if is_scene_file(&req.input) {
        return scene_plan(req);
    }
    if req
        .input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("vgeo"))
    {
        anyhow::bail!("{} is built already", req.input.display());
    }
    let out_base = req
        .out
        .clone()
        .unwrap_or_else(|| req.input.with_extension("vgeo"));
    let mut warnings = Vec::new();
    let jobs = if req.import.split_nodes {
        let meshes = load_input(&req.input, &req.import)?;
        let count = meshes.len();
        let stem = out_base
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("out")
            .to_string();
        meshes
            .into_iter()
            .enumerate()
            .map(|(i, mesh)| BuildJob {
                input: req.input.clone(),
                source: Source::Node(mesh),
                out: if count > 1 {
                    out_base.with_file_name(format!("{stem}_{i}.vgeo"))
                } else {
                    out_base.clone()
                },
            })
            .collect()
    } else {
        let mut cache = MeshCache::new(req.import.clone(), req.build.clone());
        let loaded = LoadedScene::from_scene(&mut cache, Scene::single_mesh(&req.input))?;
        warnings.extend(loaded.warnings.iter().cloned());
        vec![BuildJob {
            input: req.input.clone(),
            source: Source::Prepared(loaded.prepared[0].clone()),
            out: out_base,
        }]
    };
    Ok(BuildPlan {
        jobs,
        scene: false,
        warnings,
        skipped: Vec::new(),
    })
}

/// [`plan_build`] of a scene file.
fn scene_plan(req: &BuildRequest) -> anyhow::Result<BuildPlan> {
    if req.import.split_nodes {
        anyhow::bail!("--split-nodes applies to a mesh file, not a scene");
    }
    let dir = req.out.clone().unwrap_or_else(|| {
        let stem = req
            .input
            .file_stem()
            .map_or("scene".into(), |s| s.to_string_lossy());
        req.input.with_file_name(format!("{stem}-vgeo"))
    });
    let mut cache = MeshCache::new(req.import.clone(), req.build.clone());
    let loaded = LoadedScene::load_with(&mut cache, &req.input)?;
    std::fs::create_dir_all(&dir).with_context(|| format!("creating {}", dir.display()))?;
    let mut jobs: Vec<BuildJob> = Vec::new();
    let mut skipped = Vec::new();
    for (m, p) in loaded.scene.meshes.iter().zip(&loaded.prepared) {
        if p.built_if_ready().is_some() {
            skipped.push(m.path.clone());
            continue;
        }
        if jobs
            .iter()
            .any(|j| matches!(&j.source, Source::Prepared(q) if Arc::ptr_eq(p, q)))
        {
            continue;
        }
        jobs.push(BuildJob {
            input: m.path.clone(),
            source: Source::Prepared(p.clone()),
            out: dir.join(format!("{}.vgeo", m.name)),
        });
    }
    Ok(BuildPlan {
        jobs,
        scene: true,
        warnings: loaded.warnings.clone(),
        skipped,
    })
}

/// Writes `built` as a `.vgeo` file to `out`; returns the file's size in bytes.
pub fn write_vgeo(built: &BuiltMesh, out: &Path) -> anyhow::Result<usize> {
    let bytes = crate::format::save(built);
    std::fs::write(out, &bytes).with_context(|| format!("writing {}", out.display()))?;
    Ok(bytes.len())
}

/// `m`'s encoded pages (what streams and what the GPU holds of its geometry) per input triangle,
/// part by part, with the bits a stored vertex and a triangle take.
fn describe_pages(m: &BuiltMesh) -> String {
    let b = crate::builder::page::page_bytes_breakdown(m);
    let per_tri = |bytes: u64| bytes as f64 / m.stats.input_triangles.max(1) as f64;
    let per_vertex = |bits: u64| bits as f64 / b.stored_vertices.max(1) as f64;
    let mut fields = format!(
        "position {:.1}, normal {:.1}",
        per_vertex(b.position_bits),
        per_vertex(b.normal_bits)
    );
    if m.has_uvs {
        fields += &format!(", uv {:.1}", per_vertex(b.uv_bits));
    }
    if m.has_material_stream() {
        fields += &format!(", material {:.1}", per_vertex(b.material_bits));
    }
    format!(
        "pages: {} bytes, {:.2} per input triangle: vertices {:.2} ({:.2} stored per triangle, \
         {:.1} bits each: {fields}), triangles {:.2} ({:.1} bits each), cluster headers {:.2}, \
         page ends {:.2}",
        b.total(),
        per_tri(b.total()),
        per_tri(b.vertices),
        b.stored_vertices as f64 / b.stored_triangles.max(1) as f64,
        per_vertex(b.position_bits + b.normal_bits + b.uv_bits + b.material_bits),
        per_tri(b.triangles),
        8.0 * b.triangles as f64 / b.stored_triangles.max(1) as f64,
        per_tri(b.headers),
        per_tri(b.page_ends),
    )
}

/// Human-readable statistics of a built mesh.
pub fn describe(m: &BuiltMesh, file_len: usize) -> String {
    use std::fmt::Write;
    let s = &m.stats;
    let mut o = String::new();
    let _ = writeln!(
        o,
        "{}: {} input triangles ({} degenerate, {} duplicate dropped), {} vertices",
        m.name, s.input_triangles, s.degenerate_dropped, s.duplicates_dropped, s.vertices
    );
    let _ = writeln!(
        o,
        "{} clusters, {} groups, {} BVH nodes, {} triangles over all levels ({:.2}x)",
        s.clusters,
        s.groups,
        s.bvh_nodes,
        s.stored_triangles,
        s.stored_triangles as f64 / s.level0_triangles.max(1) as f64
    );
    let _ = writeln!(
        o,
        "file: {} bytes, {:.2} bytes per input triangle",
        file_len,
        crate::format::bytes_per_input_triangle(file_len, m)
    );
    let q = &m.quantization;
    let _ = writeln!(
        o,
        "precision: {} position bits per axis (a step of {:.3e}), {} normal bits per component",
        q.position_bits, q.step, q.normal_bits
    );
    let _ = writeln!(o, "{}", describe_pages(m));
    let _ = writeln!(
        o,
        "{}",
        match s.closed_solid {
            Some(true) =>
                "closed solid: seen from outside, its faces turned away are not rasterized",
            Some(false) => {
                "not a closed solid (an open edge, a non-manifold edge, or a piece turned inwards \
                 or flat): every face is rasterized"
            }
            None => {
                "closed solid or not: unknown (a file from before vgeo told them apart; rebuild it \
                 to have a closed solid's faces turned away dropped): every face is rasterized"
            }
        }
    );
    if m.group_coverage.is_empty() {
        let _ = writeln!(
            o,
            "small instances: every error counts whole (a file from before vgeo kept the coverage \
             part of its errors; rebuild it to have instances under {} px weigh theirs)",
            crate::shared::SMALL_WEIGHT_RADIUS_PX
        );
    } else {
        // Groups whose error is its coverage part (thin parts losing area): a small instance
        // counts those whole, so the weight does not lighten them.
        let (n, covered) = m
            .groups
            .iter()
            .zip(&m.group_coverage)
            .filter(|(g, _)| g.error.is_finite())
            .fold((0, 0), |(n, c), (g, &cov)| {
                (n + 1, c + (cov >= g.error) as usize)
            });
        let _ = writeln!(
            o,
            "small instances: under {} px an error counts a share, its coverage part whole; {} of \
             {} groups' errors are all coverage",
            crate::shared::SMALL_WEIGHT_RADIUS_PX,
            covered,
            n
        );
    }
    let _ = writeln!(
        o,
        "level  clusters  triangles  ratio  max error  groups  stuck"
    );
    for l in &s.levels {
        let _ = writeln!(
            o,
            "{:5}  {:8}  {:9}  {:5.3}  {:9.3e}  {:6}  {:5}",
            l.level, l.clusters, l.triangles, l.ratio, l.max_error, l.groups, l.stuck_groups
        );
    }
    if !s.widened_iterations.is_empty() || s.fallback_groups > 0 {
        let _ = writeln!(
            o,
            "stuck: widened groups at iterations {:?}; {} groups needed pruning/sloppy/merge",
            s.widened_iterations, s.fallback_groups
        );
    }
    o
}

/// Reads and loads a `.vgeo` file.
pub fn read_vgeo(path: &Path) -> anyhow::Result<(BuiltMesh, usize)> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let m = crate::format::load(&bytes).with_context(|| format!("loading {}", path.display()))?;
    Ok((m, bytes.len()))
}

/// Checks a `.vgeo` file: DAG invariants and crack-free cuts for `opts.views` random views (with
/// the slow reference verifier when `reference`).
pub fn verify_file(
    path: &Path,
    opts: &VerifyOptions,
    reference: bool,
) -> anyhow::Result<VerifyReport> {
    let (m, _) = read_vgeo(path)?;
    Ok(if reference {
        builder::verify::verify_reference(&m, opts)
    } else {
        builder::verify(&m, opts)
    })
}

/// Statistics of a `.vgeo` file (`vgeo info FILE.vgeo`).
pub fn info_vgeo(path: &Path) -> anyhow::Result<String> {
    let (m, len) = read_vgeo(path)?;
    Ok(describe(&m, len))
}
