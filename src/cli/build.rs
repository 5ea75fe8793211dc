//! `vgeo build`, `vgeo verify`: the arguments, progress and printing around
//! [`vgeo::tools`], which does the work.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use clap::Args;
use vgeo::tools::{self as build_files, BuildRequest, describe};
use vgeo::{BuildOptions, ImportOptions, Partitioner, VerifyOptions};

/// `vgeo build IN -o OUT.vgeo`: builds the cluster DAG of a mesh, or of every mesh of a scene.
#[derive(Args, Debug, Clone)]
pub struct BuildArgs {
    /// Input mesh (glTF/GLB, OBJ, PLY, STL, OFF), or a scene file (.toml): every mesh of the
    /// scene is built with the scene's options (e.g. `materials = 64`), as `vgeo render` and
    /// `vgeo bench` load them, into OUT/NAME.vgeo.
    pub input: PathBuf,
    /// Output `.vgeo` file (default: the input with extension `.vgeo`); for a scene file, the
    /// output folder (default: SCENE-vgeo beside the scene file).
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
    /// Triangle ratio of one simplification step. The default 0.35 stores about a quarter fewer
    /// bytes than 0.5, and the levels kept resident above a drawn region weigh about half of it
    /// instead of as much (a cold camera cut holds 1.7x the page bytes it draws instead of
    /// 2.3x); a cut lands further below the threshold, so mid-sized instances draw a few percent
    /// more triangles. A ratio other than 0.5 keeps 0.5's root chain (the coarse levels small
    /// instances draw; its source is found by making the levels at 0.5 too, from the same level
    /// 0, so the build takes about 1.5x as long as at 0.5). At 0.35 against 0.5 on the H100
    /// (the bench's 16-frame paths): image error at 1 px within 0.05 dB (the smallest instances
    /// the same), frame times -2.4 % to +1.3 % (stress N=20 +1.2 %, outdoor +1.3 %, foliage
    /// -2.4 %), 13-23 % fewer bytes (docs/architecture.md, "The DAG's step", "The root chain at
    /// any ratio" and "The stated precision apart from the build grid, and 0.35 as the
    /// default").
    #[arg(long = "ratio", default_value_t = BuildOptions::default().simplify_ratio)]
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
    /// Crease angle (degrees) of the normals generated for meshes that have none: faces meeting
    /// at a sharper angle are shaded flat apart (their vertices split, and the split kept at every
    /// level of detail); 180 shades smoothly everywhere.
    #[arg(long = "crease-deg", default_value_t = ImportOptions::default().crease_deg)]
    pub crease_deg: f32,
    /// Weight of the vertex normal in the simplification error (0: position only): a normal
    /// turning by A radians across a region of size S counts like moving the surface by
    /// WEIGHT * A * S, so shading that would visibly change is refined like geometry.
    #[arg(long = "normal-weight", default_value_t = BuildOptions::default().normal_weight)]
    pub normal_weight: f32,
    /// Weight of the UV in the simplification error (meshes with UVs; 0: ignore UVs).
    #[arg(long = "uv-weight", default_value_t = BuildOptions::default().uv_weight)]
    pub uv_weight: f32,
    /// Worker threads of the whole command: import (crease normals), build and the file's page
    /// encoding (default: all cores). The output does not depend on it.
    #[arg(long = "threads")]
    pub threads: Option<usize>,
    /// The mesh's position precision: bits per axis of the grid its pages store (1-21; the step
    /// is its largest extent over 2^BITS - 1). Default: at least 14, finer when a step would
    /// exceed 1/32 of its short edges (the shortest tenth). Fewer bits make smaller pages;
    /// positions move by at most half a step. The DAG is built on a grid of at least 16 bits
    /// whatever this says (finer when the median edge needs it), so a coarser precision moves the
    /// stored positions and leaves the levels as they are.
    #[arg(long = "position-bits")]
    pub position_bits: Option<u32>,
    /// Bits per octahedral normal component (2-16). Fewer bits make smaller pages.
    #[arg(long = "normal-bits", default_value_t = BuildOptions::default().normal_bits)]
    pub normal_bits: u32,
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

/// Runs `vgeo build`.
pub fn run_build(a: &BuildArgs) -> anyhow::Result<()> {
    // The import and the file's writing run on rayon's global pool; the build on its own pool of
    // the same size. (The global pool can be set up once per process: a later call keeps it.)
    if let Some(n) = a.threads {
        let _ = rayon::ThreadPoolBuilder::new()
            .num_threads(n.max(1))
            .build_global();
    }
    let build = BuildOptions {
        max_cluster_triangles: a.max_triangles,
        group_min: a.group_min,
        group_max: a.group_max,
        simplify_ratio: a.ratio,
        keep_percent: a.keep_percent,
        trim_error: a.trim_error,
        fallback_triangles: a.fallback_triangles,
        root_triangles: a.root_triangles,
        normal_weight: a.normal_weight,
        uv_weight: a.uv_weight,
        threads: a.threads,
        position_bits: a.position_bits,
        normal_bits: a.normal_bits,
        partitioner: match a.partitioner.as_str() {
            "metis" => Partitioner::Metis,
            "meshopt-flex" => Partitioner::MeshoptFlex,
            _ => Partitioner::Meshopt,
        },
    };
    let req = BuildRequest {
        input: a.input.clone(),
        out: a.out.clone(),
        import: ImportOptions {
            split_nodes: a.split_nodes,
            crease_deg: a.crease_deg,
        },
        build,
    };
    let plan = build_files::plan_build(&req)?;
    for w in &plan.warnings {
        eprintln!("warning: {w}");
    }
    for p in &plan.skipped {
        eprintln!("{}: built already, skipped", p.display());
    }
    let jobs = &plan.jobs;
    if a.fallback_out.is_some() && jobs.len() > 1 {
        anyhow::bail!(
            "--fallback-out takes one mesh; this input has {}",
            jobs.len()
        );
    }
    let mut reports = Vec::new();
    let mut failed = Vec::new();
    for job in jobs {
        let bar = indicatif::ProgressBar::new_spinner();
        let progress = |msg: &str| bar.set_message(msg.to_string());
        let t0 = Instant::now();
        let built = job.build(&req.build, &progress);
        let secs = t0.elapsed().as_secs_f64();
        bar.finish_and_clear();
        let built = match built {
            Ok(b) => b,
            // A scene's other meshes are still built; the command fails at the end.
            Err(e) if jobs.len() > 1 && plan.scene => {
                eprintln!("error: {e:#}");
                failed.push(job.input.display().to_string());
                continue;
            }
            Err(e) => return Err(e),
        };
        let out = &job.out;
        let len = build_files::write_vgeo(&built, out)?;
        if let Some(obj) = &a.fallback_out {
            let fb = built.fallback_mesh(a.fallback_triangles);
            std::fs::write(obj, build_files::mesh_to_obj(&fb))
                .with_context(|| format!("writing {}", obj.display()))?;
        }
        let tps = built.stats.input_triangles as f64 / secs.max(1e-9);
        if a.json {
            reports.push(serde_json::json!({
                "input": job.input, "output": out, "seconds": secs, "triangles_per_second": tps,
                "bytes": len,
                "bytes_per_input_triangle": build_files::bytes_per_input_triangle(len, &built),
                "stats": built.stats,
            }));
        } else {
            println!("{}", describe(&built, len));
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
    if !failed.is_empty() {
        anyhow::bail!(
            "{} of {} meshes failed to build: {}",
            failed.len(),
            jobs.len(),
            failed.join(", ")
        );
    }
    Ok(())
}

/// Runs `vgeo verify`; true when the file passes.
pub fn run_verify(a: &VerifyArgs) -> anyhow::Result<bool> {
    let opts = VerifyOptions {
        views: a.views,
        seed: a.seed,
        ..Default::default()
    };
    let report = build_files::verify_file(&a.file, &opts, a.reference)?;
    println!("{}: {report}", a.file.display());
    Ok(report.ok())
}
