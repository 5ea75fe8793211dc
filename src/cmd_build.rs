//! CLI glue for `vgeo build`, `vgeo verify` and `vgeo info FILE.vgeo`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::Context;
use clap::Args;

use crate::builder::{self, BuildOptions, VerifyOptions};
use crate::mesh::Mesh;

/// `vgeo build IN -o OUT.vgeo`: builds the cluster DAG of a mesh.
#[derive(Args, Debug, Clone)]
pub struct BuildArgs {
    /// Input mesh (glTF/GLB, OBJ, PLY, STL, OFF).
    pub input: PathBuf,
    /// Output `.vgeo` file (default: the input with extension `.vgeo`).
    #[arg(short = 'o', long = "out")]
    pub out: Option<PathBuf>,
    /// Most triangles per cluster.
    #[arg(long = "max-triangles", default_value_t = 128)]
    pub max_triangles: u32,
    /// Smallest group size (clusters).
    #[arg(long = "group-min", default_value_t = 8)]
    pub group_min: u32,
    /// Largest group size (clusters).
    #[arg(long = "group-max", default_value_t = 32)]
    pub group_max: u32,
    /// Triangle ratio of one simplification step.
    #[arg(long = "ratio", default_value_t = 0.5)]
    pub ratio: f32,
    /// Percentage of input triangles kept at level 0 (UE Nanite's "Keep Triangle Percent").
    #[arg(long = "keep-percent", default_value_t = 100.0)]
    pub keep_percent: f32,
    /// Error, relative to the bounding-box diagonal, below which input detail is trimmed
    /// (UE Nanite's "Trim Relative Error"; 0: none).
    #[arg(long = "trim-error", default_value_t = 0.0)]
    pub trim_error: f32,
    /// Triangle count the fallback mesh aims for.
    #[arg(long = "fallback-triangles", default_value_t = 2000)]
    pub fallback_triangles: u32,
    /// Keep simplifying the single top cluster while it has more than this many triangles (small
    /// roots make far instances cheap; 0: stop at the first single cluster).
    #[arg(long = "root-triangles", default_value_t = 16)]
    pub root_triangles: u32,
    /// Write the fallback mesh as OBJ.
    #[arg(long = "fallback-out")]
    pub fallback_out: Option<PathBuf>,
    /// Build each node / mesh of a multi-mesh file separately (`OUT` becomes a prefix).
    #[arg(long = "split-nodes")]
    pub split_nodes: bool,
    /// Worker threads (default: all cores). The output does not depend on it.
    #[arg(long = "threads")]
    pub threads: Option<usize>,
    /// Print the statistics as JSON.
    #[arg(long = "json")]
    pub json: bool,
    /// Partitioner for clusters and groups: `meshopt` (spatial clusters, fastest), `meshopt-flex`
    /// (adjacency-grown clusters after simplification) or `metis` (slower, serialized).
    #[arg(long = "partitioner", default_value = "meshopt", value_parser = ["meshopt", "meshopt-flex", "metis"])]
    pub partitioner: String,
}

/// `vgeo verify FILE.vgeo`: checks a built mesh (invariants and the cut on random views).
#[derive(Args, Debug, Clone)]
pub struct VerifyArgs {
    /// The `.vgeo` file.
    pub file: PathBuf,
    /// Random views for the cut test.
    #[arg(long = "views", default_value_t = 64)]
    pub views: usize,
    /// Seed of the views.
    #[arg(long = "seed", default_value_t = 1)]
    pub seed: u64,
    /// Check with the slow reference verifier (the oracle the fast one is tested against; same
    /// report, for comparisons and timing).
    #[arg(long = "reference", hide = true)]
    pub reference: bool,
}

/// Loads the meshes of `path` with the importer: one per glTF node with `split_nodes`, else one.
/// Import warnings are printed to stderr.
pub fn load_input(path: &Path, split_nodes: bool) -> anyhow::Result<Vec<Mesh>> {
    let import = crate::mesh::load(path, &crate::mesh::ImportOptions { split_nodes })?;
    for w in &import.report.warnings {
        eprintln!("warning: {w}");
    }
    Ok(import.meshes)
}

/// Runs `vgeo build`.
pub fn run_build(a: &BuildArgs) -> anyhow::Result<()> {
    let meshes = load_input(&a.input, a.split_nodes)?;
    let mut meshes = if a.split_nodes {
        meshes
    } else {
        vec![crate::mesh::merge(meshes)]
    };
    let opts = BuildOptions {
        max_cluster_triangles: a.max_triangles,
        group_min: a.group_min,
        group_max: a.group_max,
        simplify_ratio: a.ratio,
        keep_percent: a.keep_percent,
        trim_error: a.trim_error,
        fallback_triangles: a.fallback_triangles,
        root_triangles: a.root_triangles,
        threads: a.threads,
        partitioner: match a.partitioner.as_str() {
            "metis" => builder::Partitioner::Metis,
            "meshopt-flex" => builder::Partitioner::MeshoptFlex,
            _ => builder::Partitioner::Meshopt,
        },
    };
    let out_base = a
        .out
        .clone()
        .unwrap_or_else(|| a.input.with_extension("vgeo"));
    let count = meshes.len();
    let mut reports = Vec::new();
    for (i, mesh) in meshes.drain(..).enumerate() {
        let out = if count > 1 {
            let stem = out_base
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("out");
            out_base.with_file_name(format!("{stem}_{i}.vgeo"))
        } else {
            out_base.clone()
        };
        let bar = indicatif::ProgressBar::new_spinner();
        let t0 = Instant::now();
        let built =
            builder::build_with_progress(&mesh, &opts, &|msg| bar.set_message(msg.to_string()))
                .with_context(|| format!("building {}", a.input.display()))?;
        let secs = t0.elapsed().as_secs_f64();
        bar.finish_and_clear();
        let bytes = crate::format::save(&built);
        std::fs::write(&out, &bytes).with_context(|| format!("writing {}", out.display()))?;
        if let Some(obj) = &a.fallback_out {
            let fb = built.fallback_mesh(a.fallback_triangles);
            std::fs::write(obj, builder::mesh_to_obj(&fb))
                .with_context(|| format!("writing {}", obj.display()))?;
        }
        let tps = built.stats.input_triangles as f64 / secs.max(1e-9);
        if a.json {
            reports.push(serde_json::json!({
                "input": a.input, "output": out, "seconds": secs, "triangles_per_second": tps,
                "bytes": bytes.len(),
                "bytes_per_input_triangle": crate::format::bytes_per_input_triangle(bytes.len(), &built),
                "stats": built.stats,
            }));
        } else {
            println!("{}", describe(&built, bytes.len()));
            println!(
                "built in {secs:.2} s ({:.0} input triangles/s) -> {}",
                tps,
                out.display()
            );
        }
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&reports)?);
    }
    Ok(())
}

/// Human-readable statistics of a built mesh.
pub fn describe(m: &builder::BuiltMesh, file_len: usize) -> String {
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

/// Runs `vgeo verify`; true when the file passes.
pub fn run_verify(a: &VerifyArgs) -> anyhow::Result<bool> {
    let bytes = std::fs::read(&a.file).with_context(|| format!("reading {}", a.file.display()))?;
    let m = crate::format::load(&bytes).with_context(|| format!("loading {}", a.file.display()))?;
    let opts = VerifyOptions {
        views: a.views,
        seed: a.seed,
        ..Default::default()
    };
    let report = if a.reference {
        builder::verify::verify_reference(&m, &opts)
    } else {
        builder::verify(&m, &opts)
    };
    println!("{}: {report}", a.file.display());
    Ok(report.ok())
}

/// Statistics of a `.vgeo` file for `vgeo info`.
pub fn info_vgeo(path: &Path) -> anyhow::Result<String> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let m = crate::format::load(&bytes).with_context(|| format!("loading {}", path.display()))?;
    Ok(describe(&m, bytes.len()))
}
