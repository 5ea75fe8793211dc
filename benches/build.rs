//! Build benchmark: `cargo bench --bench build [-- FILTER]` builds bunny, lucy, turbineblade (from the
//! shared assets) and a generated 2M-triangle subdivided surface (`-- torus10M`: a 10M-triangle
//! one, only when named), with 1 thread and with all threads, and prints per mesh: input
//! triangles/s (and per core), peak memory (VmHWM, reset before each build through
//! /proc/self/clear_refs), bytes per input triangle of the .vgeo file, levels.
//! `VGEO_PARTITIONER=metis|meshopt-flex` picks another partitioner; `VGEO_PHASES=1` prints the
//! time of each build phase.

use std::time::Instant;

use vgeo::builder::{self, BuildOptions};
use vgeo::mesh::{Material, Mesh};

/// Peak resident memory of the process in KiB (VmHWM), if readable.
fn vm_hwm_kib() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// Current resident memory in KiB (VmRSS).
fn vm_rss_kib() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmRSS:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// CPU time (user + system) of the process in seconds, from /proc/self/stat (clock ticks of
/// 1/100 s, the Linux default USER_HZ).
fn cpu_seconds() -> f64 {
    let Ok(s) = std::fs::read_to_string("/proc/self/stat") else {
        return 0.0;
    };
    // Fields after the parenthesized command name; utime and stime are fields 14 and 15.
    let rest = s.rsplit_once(')').map_or("", |x| x.1);
    let f: Vec<u64> = rest
        .split_whitespace()
        .map(|x| x.parse().unwrap_or(0))
        .collect();
    (f.get(11).copied().unwrap_or(0) + f.get(12).copied().unwrap_or(0)) as f64 / 100.0
}

/// Resets VmHWM to the current RSS (Linux >= 4.0); false if not possible.
fn reset_hwm() -> bool {
    std::fs::write("/proc/self/clear_refs", "5").is_ok()
}

/// A torus of `n` x `n` quads (2n^2 triangles) with a bumpy displacement: a closed, smooth,
/// uniformly subdivided surface.
fn generated_torus(n: u32) -> Mesh {
    let (big, small) = (1.0f32, 0.35f32);
    let mut positions = Vec::with_capacity((n * n) as usize);
    for i in 0..n {
        let u = i as f32 / n as f32 * std::f32::consts::TAU;
        for j in 0..n {
            let v = j as f32 / n as f32 * std::f32::consts::TAU;
            let r = small
                * (1.0
                    + 0.08 * (7.0 * u).sin() * (5.0 * v).cos()
                    + 0.02 * (41.0 * u + 29.0 * v).sin());
            positions.push([
                (big + r * v.cos()) * u.cos(),
                (big + r * v.cos()) * u.sin(),
                r * v.sin(),
            ]);
        }
    }
    let mut indices = Vec::with_capacity((n * n * 6) as usize);
    for i in 0..n {
        for j in 0..n {
            let a = i * n + j;
            let b = ((i + 1) % n) * n + j;
            let c = ((i + 1) % n) * n + (j + 1) % n;
            let d = i * n + (j + 1) % n;
            indices.extend_from_slice(&[a, b, c, a, c, d]);
        }
    }
    let t = indices.len() / 3;
    let mut mesh = Mesh {
        name: format!("torus{}", 2 * n * n),
        normals: vec![[0.0; 3]; positions.len()],
        uvs: vec![[0.0; 2]; positions.len()],
        positions,
        indices,
        material_ids: vec![0; t],
        materials: vec![Material::default()],
        has_normals: false,
        has_uvs: false,
    };
    vgeo::mesh::fill_missing_normals(&mut mesh);
    mesh
}

fn main() {
    let filter: Option<String> = std::env::args().skip(1).find(|a| !a.starts_with('-'));
    let dir = std::env::var("VGEO_SHARED_ASSETS").unwrap_or_else(|_| "/work/shared/assets".into());
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    // `torus10M` (issue 14: scaling to 16 threads on a 10 M-triangle mesh) only when asked for by
    // name: it takes minutes on one thread.
    let names = [
        "bunny.ply",
        "lucy.ply",
        "turbineblade.ply",
        "torus2M",
        "torus10M",
    ];
    println!(
        "| mesh | input tris | threads | wall s | CPU s | tris/s (wall) | tris/CPU-s | peak MiB (VmHWM) | B/input tri | levels |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for name in names {
        if filter.as_ref().is_some_and(|f| !name.contains(f.as_str()))
            || (name == "torus10M" && filter.as_deref() != Some("torus10M"))
        {
            continue;
        }
        let mesh = if name == "torus2M" {
            generated_torus(1000)
        } else if name == "torus10M" {
            generated_torus(2236)
        } else {
            let path = std::path::Path::new(&dir).join("scanned").join(name);
            match vgeo::build_files::load_input(&path, &Default::default()) {
                Ok(m) => vgeo::mesh::merge(m),
                Err(e) => {
                    eprintln!("{}: {e:#}", path.display());
                    std::process::exit(1);
                }
            }
        };
        for threads in [1, cores] {
            let opts = BuildOptions {
                threads: Some(threads),
                partitioner: match std::env::var("VGEO_PARTITIONER").as_deref() {
                    Ok("metis") => builder::Partitioner::Metis,
                    Ok("meshopt-flex") => builder::Partitioner::MeshoptFlex,
                    _ => builder::Partitioner::Meshopt,
                },
                ..Default::default()
            };
            let base = vm_rss_kib().unwrap_or(0);
            let reset = reset_hwm();
            let c0 = cpu_seconds();
            let t0 = Instant::now();
            let phases = std::env::var("VGEO_PHASES").is_ok();
            let progress = |m: &str| {
                if phases {
                    eprintln!("{:8.3}s {m}", t0.elapsed().as_secs_f64());
                }
            };
            let built = match builder::build_with_progress(&mesh, &opts, &progress) {
                Ok(b) => b,
                Err(e) => {
                    eprintln!("{name}: {e}");
                    std::process::exit(1);
                }
            };
            let secs = t0.elapsed().as_secs_f64();
            let cpu = cpu_seconds() - c0;
            let peak = vm_hwm_kib().unwrap_or(0);
            let bytes = vgeo::format::save(&built).len();
            if phases {
                let wide = built
                    .clusters
                    .iter()
                    .filter(|c| c.flags() & builder::CLUSTER_FLAG_REFS_U32 != 0)
                    .count();
                eprintln!(
                    "clusters with u32 references: {wide} of {}; refs {} B, triangles {} B, vertices {}",
                    built.clusters.len(),
                    built.vertex_refs.len() * 4,
                    built.triangles.len(),
                    built.vertices.len()
                );
            }
            let n = mesh.triangle_count() as f64;
            println!(
                "| {} | {} | {threads} | {secs:.3} | {cpu:.2} | {:.0} | {:.0} | {:.0}{} (mesh loaded: {:.0}) | {:.2} | {} |",
                mesh.name,
                mesh.triangle_count(),
                n / secs,
                n / cpu.max(0.01),
                peak as f64 / 1024.0,
                if reset { "" } else { " (not reset)" },
                base as f64 / 1024.0,
                bytes as f64 / n,
                built.stats.levels.len(),
            );
        }
    }
}
