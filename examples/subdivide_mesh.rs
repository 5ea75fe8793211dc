//! Makes large test meshes deterministically from a real scan, for timing `vgeo build` and
//! `vgeo verify` at sizes we have no scan of:
//!
//! `cargo run --release --example subdivide_mesh -- IN OUT.ply [--levels N] [--copies K] [--seed S]`
//!
//! Each level splits every triangle into 4 at its edge midpoints (4^N times the triangles); a
//! midpoint moves along the mean normal of its edge's ends by up to 2 % of the edge length (a hash of
//! the two vertex indices picks how far), so that the new detail is not flat and simplifies like
//! scanned detail. `--copies K` then places K copies side by side along x (disconnected parts).
//! Midpoints are shared by both triangles of an edge, so the surface stays welded. Written as a
//! binary little-endian PLY (positions and triangles only); same input, same bytes. `--seed S`
//! changes how far each midpoint moves: meshes of different seeds are different geometry of the
//! same size (a scene of unique meshes, for streaming).

use std::collections::HashMap;
use std::io::Write;

fn hash(a: u32, b: u32, seed: u64) -> f32 {
    // SplitMix64 of the edge and the seed: a value in [-1, 1].
    let mut z = ((a as u64) << 32 | b as u64)
        .wrapping_add(0x9e3779b97f4a7c15u64.wrapping_mul(seed.wrapping_add(1)));
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d049bb133111eb);
    z ^= z >> 31;
    (z >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
}

fn sub(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f32; 3], b: [f32; 3]) -> [f32; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn len(a: [f32; 3]) -> f32 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// One 1:4 split of every triangle with displaced midpoints.
pub fn subdivide(p: &mut Vec<[f32; 3]>, idx: &[u32], seed: u64) -> Vec<u32> {
    let mut normal = vec![[0f32; 3]; p.len()];
    for t in idx.chunks_exact(3) {
        let n = cross(
            sub(p[t[1] as usize], p[t[0] as usize]),
            sub(p[t[2] as usize], p[t[0] as usize]),
        );
        for &v in t {
            for k in 0..3 {
                normal[v as usize][k] += n[k];
            }
        }
    }
    for n in &mut normal {
        let l = len(*n).max(1e-30);
        for x in n.iter_mut() {
            *x /= l;
        }
    }
    let mut mid: HashMap<(u32, u32), u32> = HashMap::with_capacity(idx.len() * 3 / 2);
    let mut out = Vec::with_capacity(idx.len() * 4);
    for t in idx.chunks_exact(3) {
        let mut m = [0u32; 3];
        for e in 0..3 {
            let (a, b) = (t[e], t[(e + 1) % 3]);
            let key = (a.min(b), a.max(b));
            m[e] = *mid.entry(key).or_insert_with(|| {
                let (pa, pb) = (p[key.0 as usize], p[key.1 as usize]);
                let (na, nb) = (normal[key.0 as usize], normal[key.1 as usize]);
                let h = 0.02 * len(sub(pa, pb)) * hash(key.0, key.1, seed);
                let np = std::array::from_fn(|k| (pa[k] + pb[k]) * 0.5 + (na[k] + nb[k]) * 0.5 * h);
                p.push(np);
                p.len() as u32 - 1
            });
        }
        out.extend_from_slice(&[
            t[0], m[0], m[2], m[0], t[1], m[1], m[2], m[1], t[2], m[0], m[1], m[2],
        ]);
    }
    out
}

fn main() -> anyhow::Result<()> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: subdivide_mesh IN OUT.ply [--levels N] [--copies K] [--seed S]";
    let mut files = Vec::new();
    let (mut levels, mut copies, mut seed) = (1u32, 1u32, 0u64);
    let mut it = args.iter();
    while let Some(a) = it.next() {
        match a.as_str() {
            "--levels" => levels = it.next().ok_or(anyhow::anyhow!(usage))?.parse()?,
            "--copies" => copies = it.next().ok_or(anyhow::anyhow!(usage))?.parse()?,
            "--seed" => seed = it.next().ok_or(anyhow::anyhow!(usage))?.parse()?,
            _ => files.push(a.clone()),
        }
    }
    let [input, output] = files.as_slice() else {
        anyhow::bail!(usage);
    };
    let (v, t) = write_subdivided(
        std::path::Path::new(input),
        std::path::Path::new(output),
        levels,
        copies,
        seed,
    )?;
    eprintln!("{output}: {v} vertices, {t} triangles");
    Ok(())
}

/// `input` subdivided `levels` times with `seed`, `copies` times side by side, written to
/// `output` as binary PLY; its vertex and triangle counts.
pub fn write_subdivided(
    input: &std::path::Path,
    output: &std::path::Path,
    levels: u32,
    copies: u32,
    seed: u64,
) -> anyhow::Result<(usize, usize)> {
    // No crease splitting (180 degrees): a vertex split at a crease would get two different
    // midpoints on its edges, opening cracks.
    let import = vgeo::ImportOptions {
        crease_deg: 180.0,
        ..Default::default()
    };
    let meshes = vgeo::load_meshes(input, &import)?;
    let mesh = vgeo::merge_meshes(meshes);
    let mut p = mesh.positions.clone();
    let mut idx = mesh.indices.clone();
    for _ in 0..levels {
        idx = subdivide(&mut p, &idx, seed);
    }
    let (lo, hi) = mesh
        .bounds()
        .ok_or_else(|| anyhow::anyhow!("{}: empty mesh", input.display()))?;
    let step = (hi[0] - lo[0]) * 1.1;
    let nv = p.len();
    let mut f = std::io::BufWriter::new(std::fs::File::create(output)?);
    write!(
        f,
        "ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\nproperty float z\nelement face {}\nproperty list uchar int vertex_indices\nend_header\n",
        nv * copies as usize,
        idx.len() / 3 * copies as usize
    )?;
    for c in 0..copies {
        for q in &p {
            let q = [q[0] + step * c as f32, q[1], q[2]];
            for x in q {
                f.write_all(&x.to_le_bytes())?;
            }
        }
    }
    for c in 0..copies {
        for t in idx.chunks_exact(3) {
            f.write_all(&[3u8])?;
            for &v in t {
                f.write_all(&((v as usize + nv * c as usize) as i32).to_le_bytes())?;
            }
        }
    }
    f.flush()?;
    Ok((nv * copies as usize, idx.len() / 3 * copies as usize))
}
