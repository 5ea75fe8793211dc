//! CLI glue for `vgeo build`, `vgeo verify` and `vgeo info FILE.vgeo`.

use std::path::{Path, PathBuf};
use std::time::Instant;

use anyhow::{Context, bail};
use clap::Args;

use crate::builder::{self, BuildOptions, VerifyOptions};
use crate::mesh::{Material, Mesh};

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
    /// Percentage of input triangles kept at level 0.
    #[arg(long = "keep-percent", default_value_t = 100.0)]
    pub keep_percent: f32,
    /// Object-space error below which input detail is trimmed (0: none).
    #[arg(long = "trim-error", default_value_t = 0.0)]
    pub trim_error: f32,
    /// Triangle count the fallback mesh aims for.
    #[arg(long = "fallback-triangles", default_value_t = 2000)]
    pub fallback_triangles: u32,
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
}

/// Reads a mesh file. PLY and OBJ are read here until the importers of `crate::mesh` land; the
/// lead replaces this with `crate::mesh::load_mesh`.
pub fn load_input(path: &Path) -> anyhow::Result<Vec<Mesh>> {
    let ext = path
        .extension()
        .and_then(|e| e.to_str())
        .unwrap_or("")
        .to_ascii_lowercase();
    let name = path
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or("mesh")
        .to_string();
    match ext.as_str() {
        "ply" => Ok(vec![load_ply(path, name)?]),
        "obj" => load_obj(path),
        _ => bail!(
            "{}: unsupported input format '{ext}' (this build reads .ply and .obj)",
            path.display()
        ),
    }
}

fn finish(mut m: Mesh) -> anyhow::Result<Mesh> {
    let n = m.positions.len();
    m.normals = vec![[0.0; 3]; n];
    for t in m.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|i| glam::Vec3::from_array(m.positions[i as usize]));
        let fnorm = (b - a).cross(c - a);
        for &i in t {
            let s = &mut m.normals[i as usize];
            *s = (glam::Vec3::from_array(*s) + fnorm).to_array();
        }
    }
    for s in &mut m.normals {
        *s = glam::Vec3::from_array(*s)
            .normalize_or(glam::Vec3::Z)
            .to_array();
    }
    m.uvs = vec![[0.0; 2]; n];
    m.material_ids = vec![0; m.indices.len() / 3];
    m.materials = vec![Material::default()];
    m.validate()
        .map_err(|e| anyhow::anyhow!("{}: {e}", m.name))?;
    Ok(m)
}

fn load_ply(path: &Path, name: String) -> anyhow::Result<Mesh> {
    use ply_rs::ply::Property;
    let f = std::fs::File::open(path).with_context(|| format!("opening {}", path.display()))?;
    let mut r = std::io::BufReader::new(f);
    let ply = ply_rs::parser::Parser::<ply_rs::ply::DefaultElement>::new()
        .read_ply(&mut r)
        .with_context(|| format!("parsing {}", path.display()))?;
    let num = |p: Option<&Property>| -> Option<f64> {
        Some(match p? {
            Property::Float(x) => *x as f64,
            Property::Double(x) => *x,
            Property::Int(x) => *x as f64,
            Property::UInt(x) => *x as f64,
            Property::Short(x) => *x as f64,
            Property::UShort(x) => *x as f64,
            Property::Char(x) => *x as f64,
            Property::UChar(x) => *x as f64,
            _ => return None,
        })
    };
    let mut m = Mesh {
        name,
        ..Default::default()
    };
    let verts = ply
        .payload
        .get("vertex")
        .map(|v| v.as_slice())
        .unwrap_or(&[]);
    for (i, v) in verts.iter().enumerate() {
        let p = ["x", "y", "z"].map(|k| num(v.get(k)));
        let [Some(x), Some(y), Some(z)] = p else {
            bail!("{}: vertex {i} lacks x/y/z", path.display())
        };
        let p = [x as f32, y as f32, z as f32];
        if !p.iter().all(|c| c.is_finite()) {
            bail!("{}: vertex {i} is not finite", path.display());
        }
        m.positions.push(p);
    }
    let faces = ply.payload.get("face").map(|v| v.as_slice()).unwrap_or(&[]);
    for (fi, f) in faces.iter().enumerate() {
        let list = f.get("vertex_indices").or_else(|| f.get("vertex_index"));
        let idx: Vec<i64> = match list {
            Some(Property::ListInt(l)) => l.iter().map(|&x| x as i64).collect(),
            Some(Property::ListUInt(l)) => l.iter().map(|&x| x as i64).collect(),
            Some(Property::ListUChar(l)) => l.iter().map(|&x| x as i64).collect(),
            Some(Property::ListShort(l)) => l.iter().map(|&x| x as i64).collect(),
            Some(Property::ListUShort(l)) => l.iter().map(|&x| x as i64).collect(),
            _ => bail!("{}: face {fi} has no vertex index list", path.display()),
        };
        if let Some(bad) = idx
            .iter()
            .find(|&&x| x < 0 || x as usize >= m.positions.len())
        {
            bail!("{}: face {fi} index {bad} out of range", path.display());
        }
        for k in 1..idx.len().saturating_sub(1) {
            m.indices
                .extend_from_slice(&[idx[0] as u32, idx[k] as u32, idx[k + 1] as u32]);
        }
    }
    finish(m)
}

fn load_obj(path: &Path) -> anyhow::Result<Vec<Mesh>> {
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ..Default::default()
    };
    let (models, _) =
        tobj::load_obj(path, &opts).with_context(|| format!("parsing {}", path.display()))?;
    let mut m = Mesh {
        name: path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("mesh")
            .into(),
        ..Default::default()
    };
    for model in models {
        let base = m.positions.len() as u32;
        m.positions.extend(
            model
                .mesh
                .positions
                .chunks_exact(3)
                .map(|p| [p[0], p[1], p[2]]),
        );
        m.indices
            .extend(model.mesh.indices.iter().map(|&i| i + base));
    }
    if let Some(bad) = m.indices.iter().find(|&&i| i as usize >= m.positions.len()) {
        bail!("{}: index {bad} out of range", path.display());
    }
    Ok(vec![finish(m)?])
}

/// Runs `vgeo build`.
pub fn run_build(a: &BuildArgs) -> anyhow::Result<()> {
    let meshes = load_input(&a.input)?;
    let mut meshes = if a.split_nodes {
        meshes
    } else {
        vec![merge_meshes(meshes, &a.input)]
    };
    let opts = BuildOptions {
        max_cluster_triangles: a.max_triangles,
        group_min: a.group_min,
        group_max: a.group_max,
        simplify_ratio: a.ratio,
        keep_percent: a.keep_percent,
        trim_error: a.trim_error,
        fallback_triangles: a.fallback_triangles,
        threads: a.threads,
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

fn merge_meshes(meshes: Vec<Mesh>, path: &Path) -> Mesh {
    let mut out = Mesh {
        name: path
            .file_stem()
            .and_then(|s| s.to_str())
            .unwrap_or("mesh")
            .into(),
        ..Default::default()
    };
    for m in meshes {
        let base = out.positions.len() as u32;
        let mbase = out.materials.len() as u32;
        out.positions.extend(m.positions);
        out.normals.extend(m.normals);
        out.uvs.extend(m.uvs);
        out.indices.extend(m.indices.iter().map(|&i| i + base));
        out.material_ids
            .extend(m.material_ids.iter().map(|&i| i + mbase));
        out.materials.extend(m.materials);
        out.has_normals |= m.has_normals;
        out.has_uvs |= m.has_uvs;
    }
    out
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
    let report = builder::verify(
        &m,
        &VerifyOptions {
            views: a.views,
            seed: a.seed,
            ..Default::default()
        },
    );
    println!("{}: {report}", a.file.display());
    Ok(report.ok())
}

/// Statistics of a `.vgeo` file for `vgeo info`.
pub fn info_vgeo(path: &Path) -> anyhow::Result<String> {
    let bytes = std::fs::read(path).with_context(|| format!("reading {}", path.display()))?;
    let m = crate::format::load(&bytes).with_context(|| format!("loading {}", path.display()))?;
    Ok(describe(&m, bytes.len()))
}
