//! Vertex normals for meshes that come without them: smooth within a crease angle, split at creases.
//!
//! A glTF viewer or a DCC tool shades a mesh without normals smoothly across gentle bends and flat
//! across sharp edges (a box's faces, a turbine blade's rim). Averaging every face around a vertex
//! instead bends the shading of whole faces towards their neighbours, which is wrong at full detail
//! and worse once the builder simplifies the mesh. [`crease_normals`] marks an edge *sharp* where
//! its two faces meet at more than the crease angle, splits the faces around each position into
//! *smooth fans* (faces joined across edges that are not sharp, as Blender's auto-smooth does), and
//! gives every corner the angle-weighted average normal of its fan. A vertex is split only where
//! sharp edges cut its fan apart, so a curved surface without creases keeps one vertex per position
//! however coarse its triangles. The splits are attribute seams: the builder keeps them
//! (meshoptimizer does not collapse across a seam), so a crease stays sharp at every level of detail.
//!
//! (Comparing each corner's face with every face around it instead, as some viewers do, is not
//! transitive: on a coarse curved scan the faces around a vertex differ by more than the crease
//! angle from end to end, every corner got a slightly different normal, and Lucy's 50 K vertices
//! became 151 K seam vertices that the simplifier must keep.)

use std::collections::HashMap;

use super::Mesh;
use crate::hash::FxBuild;

/// Default crease angle in degrees (faces meeting at a sharper angle are shaded apart).
pub const DEFAULT_CREASE_DEG: f32 = 60.0;

fn sub(a: [f32; 3], b: [f32; 3]) -> [f64; 3] {
    [
        a[0] as f64 - b[0] as f64,
        a[1] as f64 - b[1] as f64,
        a[2] as f64 - b[2] as f64,
    ]
}

fn cross(u: [f64; 3], w: [f64; 3]) -> [f64; 3] {
    [
        u[1] * w[2] - u[2] * w[1],
        u[2] * w[0] - u[0] * w[2],
        u[0] * w[1] - u[1] * w[0],
    ]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalized(a: [f64; 3]) -> Option<[f64; 3]> {
    let len = dot(a, a).sqrt();
    (len.is_finite() && len > 1e-300).then(|| [a[0] / len, a[1] / len, a[2] / len])
}

/// Whether a stored normal is usable (finite, not zero).
fn usable(n: [f32; 3]) -> bool {
    let len = (n[0] as f64).hypot(n[1] as f64).hypot(n[2] as f64);
    len.is_finite() && len > 1e-20
}

/// Root of `i` in a union-find, halving paths as it goes.
fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let up = parent[parent[i as usize] as usize];
        parent[i as usize] = up;
        i = up;
    }
    i
}

/// Joins the sets of `a` and `b` (the smaller root becomes the root).
fn union(parent: &mut [u32], a: u32, b: u32) {
    let (ra, rb) = (find(parent, a), find(parent, b));
    if ra != rb {
        parent[ra.max(rb) as usize] = ra.min(rb);
    }
}

/// Normalizes every usable normal; vertices without one (zero or not finite) get crease-angle
/// normals: an edge is sharp where its faces' normals differ by more than `crease_deg` degrees,
/// the faces around a *position* (any vertex there, so UV or material splits do not matter) fall
/// into smooth fans joined across edges that are not sharp, and each triangle corner gets the
/// angle-weighted average normal of its fan. A vertex whose corners get different normals is split
/// (new vertices appended, indices updated). `crease_deg >= 180` shades smoothly everywhere, `0`
/// flat per face. Linear in the corners (one radix sort of the edges). Deterministic. Returns how many
/// vertices were added.
pub fn crease_normals(mesh: &mut Mesh, crease_deg: f32) -> usize {
    let n = mesh.positions.len();
    mesh.normals.resize(n, [0.0; 3]);
    let mut need = vec![false; n];
    for (v, nn) in mesh.normals.iter_mut().enumerate() {
        if usable(*nn) {
            let len = (nn[0] as f64).hypot(nn[1] as f64).hypot(nn[2] as f64);
            *nn = nn.map(|c| (c as f64 / len) as f32);
        } else {
            need[v] = true;
        }
    }
    if !need.iter().any(|&x| x) {
        return 0;
    }
    let tri_count = mesh.indices.len() / 3;
    // Position ids (bit-equal positions share one) and, per position, the triangles around it.
    let mut pos_id: HashMap<[u32; 3], u32, FxBuild> =
        HashMap::with_capacity_and_hasher(n, FxBuild::default());
    let pid: Vec<u32> = mesh
        .positions
        .iter()
        .map(|p| {
            let next = pos_id.len() as u32;
            *pos_id.entry(p.map(f32::to_bits)).or_insert(next)
        })
        .collect();
    let npos = pos_id.len();
    drop(pos_id);
    // A corner's position id (an index out of range reads as a position of its own, `npos`).
    let corner_pid = |c: usize| -> u32 {
        pid.get(mesh.indices[c] as usize)
            .copied()
            .unwrap_or(npos as u32)
    };
    // Per corner its position id; per face its unit normal (zero where degenerate), per corner
    // its angle (the weight). A corner's two edge directions are the face's unit edge vectors,
    // one of them negated (exactly the normalized difference taken the other way).
    use rayon::prelude::*;
    let cpid: Vec<u32> = (0..tri_count * 3).into_par_iter().map(corner_pid).collect();
    let mut face_normal = vec![[0.0f64; 3]; tri_count];
    let mut weight = vec![0.0f64; tri_count * 3];
    let (indices, positions) = (&mesh.indices, &mesh.positions);
    face_normal
        .par_iter_mut()
        .zip(weight.par_chunks_mut(3))
        .enumerate()
        .with_min_len(4096)
        .for_each(|(t, (normal, w))| {
            let p: [[f32; 3]; 3] = std::array::from_fn(|k| {
                let i = indices[3 * t + k] as usize;
                positions.get(i).copied().unwrap_or([0.0; 3])
            });
            *normal = normalized(cross(sub(p[1], p[0]), sub(p[2], p[0]))).unwrap_or([0.0; 3]);
            // Edge k runs from corner k to corner k + 1.
            let e: [Option<[f64; 3]>; 3] =
                std::array::from_fn(|k| normalized(sub(p[(k + 1) % 3], p[k])));
            for k in 0..3 {
                let (a, b) = (e[k], e[(k + 2) % 3].map(|v| v.map(|x| -x)));
                w[k] = match (a, b) {
                    (Some(a), Some(b)) => dot(a, b).clamp(-1.0, 1.0).acos(),
                    _ => 0.0,
                };
            }
        });
    let cos_crease = if crease_deg >= 180.0 {
        -2.0
    } else {
        (crease_deg.max(0.0) as f64).to_radians().cos() - 1e-9
    };
    let smooth = |a: u32, b: u32| {
        dot(face_normal[a as usize / 3], face_normal[b as usize / 3]) >= cos_crease
    };
    // The corner after `c` in its triangle: edge `c` runs from corner `c` to it.
    let next = |c: u32| c - c % 3 + (c + 1) % 3;
    // Every edge by its two positions (smaller first), each edge's entries in corner order: a
    // counting sort into buckets by the smaller position, then each bucket (a handful of
    // entries) sorted on its own, in parallel.
    let ends_of = |c: usize| {
        let (a, b) = (cpid[c], cpid[next(c as u32) as usize]);
        (a.min(b), a.max(b))
    };
    let mut start = vec![0u32; npos + 2];
    for c in 0..tri_count * 3 {
        start[ends_of(c).0 as usize + 1] += 1;
    }
    for i in 0..=npos {
        start[i + 1] += start[i];
    }
    let mut edges: Vec<(u64, u32)> = vec![(0, 0); tri_count * 3];
    for c in 0..tri_count * 3 {
        let (lo, hi) = ends_of(c);
        let slot = &mut start[lo as usize];
        edges[*slot as usize] = ((lo as u64) << 32 | hi as u64, c as u32);
        *slot += 1;
    }
    drop(start);
    edges
        .par_chunk_by_mut(|a, b| a.0 >> 32 == b.0 >> 32)
        .for_each(|bucket| bucket.sort_unstable());
    // Smooth fans: union-find over corners. Two faces that share an edge and meet smoothly join
    // their corners at each end of it (a non-manifold edge joins every smooth pair). A
    // degenerate face's edge between two corners at one position joins them, and the other such
    // edges' corners there, as a fan around that position would (their normals are zero, so
    // only at a crease of 90 degrees or more).
    let mut parent: Vec<u32> = (0..tri_count as u32 * 3).collect();
    let mut run = 0;
    while run < edges.len() {
        let key = edges[run].0;
        let mut end = run + 1;
        while end < edges.len() && edges[end].0 == key {
            end += 1;
        }
        let lo = (key >> 32) as u32;
        if lo == key as u32 {
            if 0.0 >= cos_crease {
                for &(_, c) in &edges[run..end] {
                    union(&mut parent, c, next(c));
                    union(&mut parent, c, edges[run].1);
                }
            }
        } else {
            // Each entry's corners at the edge's smaller and larger position.
            let ends = |c: u32| {
                if cpid[c as usize] == lo {
                    (c, next(c))
                } else {
                    (next(c), c)
                }
            };
            for i in run..end {
                for j in i + 1..end {
                    let (a, b) = (edges[i].1, edges[j].1);
                    if smooth(a, b) {
                        let ((a0, a1), (b0, b1)) = (ends(a), ends(b));
                        union(&mut parent, a0, b0);
                        union(&mut parent, a1, b1);
                    }
                }
            }
        }
        run = end;
    }
    drop(edges);
    // Each fan's angle-weighted normal, summed in corner order; each corner takes its fan's
    // (its own face's where the sum vanishes). Fans never span positions, so the corners are
    // grouped by position (counting sort), each position's sorted by (fan, corner), and the fans
    // summed in parallel.
    let root_of = |mut c: u32| {
        while parent[c as usize] != c {
            c = parent[c as usize];
        }
        c
    };
    let roots: Vec<u32> = (0..tri_count as u32 * 3)
        .into_par_iter()
        .with_min_len(4096)
        .map(root_of)
        .collect();
    let mut start = vec![0u32; npos + 2];
    for &p in &cpid {
        start[p as usize + 1] += 1;
    }
    for i in 0..=npos {
        start[i + 1] += start[i];
    }
    // (position, fan, corner)
    let mut fans: Vec<(u32, u32, u32)> = vec![(0, 0, 0); tri_count * 3];
    for (c, &p) in cpid.iter().enumerate() {
        let slot = &mut start[p as usize];
        fans[*slot as usize] = (p, roots[c], c as u32);
        *slot += 1;
    }
    drop((start, roots, parent));
    fans.par_chunk_by_mut(|a, b| a.0 == b.0)
        .for_each(|at| at.sort_unstable());
    let (face_normal, weight) = (&face_normal, &weight);
    let normals: Vec<[f32; 3]> = fans
        .par_chunk_by(|a, b| a.0 == b.0 && a.1 == b.1)
        .flat_map_iter(|fan| {
            let mut acc = [0.0f64; 3];
            for &(_, _, c) in fan {
                let n = face_normal[c as usize / 3];
                for (a, n) in acc.iter_mut().zip(n) {
                    *a += n * weight[c as usize];
                }
            }
            let fan_normal = normalized(acc);
            fan.iter().map(move |&(_, _, c)| {
                fan_normal
                    .or(normalized(face_normal[c as usize / 3]))
                    .unwrap_or([0.0, 0.0, 1.0])
                    .map(|x| x as f32)
            })
        })
        .collect();
    let mut corner_normal = vec![[0.0f32; 3]; tri_count * 3];
    for (&(_, _, c), n) in fans.iter().zip(normals) {
        corner_normal[c as usize] = n;
    }
    drop((fans, cpid));
    // Vertices split per distinct normal, in corner order.
    let mut split: HashMap<(u32, [u32; 3]), u32, FxBuild> = HashMap::default();
    let mut first_normal: Vec<Option<[u32; 3]>> = vec![None; n];
    let mut added = 0usize;
    for (c, &normal) in corner_normal.iter().enumerate() {
        let v = mesh.indices[c] as usize;
        if !need.get(v).copied().unwrap_or(false) {
            continue;
        }
        let bits = normal.map(f32::to_bits);
        match first_normal[v] {
            None => {
                first_normal[v] = Some(bits);
                mesh.normals[v] = normal;
            }
            Some(b) if b == bits => {}
            Some(_) => {
                let id = *split.entry((v as u32, bits)).or_insert_with(|| {
                    mesh.positions.push(mesh.positions[v]);
                    mesh.normals.push(normal);
                    let uv = mesh.uvs.get(v).copied().unwrap_or([0.0; 2]);
                    mesh.uvs.push(uv);
                    added += 1;
                    (mesh.positions.len() - 1) as u32
                });
                mesh.indices[c] = id;
            }
        }
    }
    added
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit cube with 8 shared corners and no normals.
    fn cube() -> Mesh {
        let mut m = Mesh {
            name: "cube".into(),
            materials: vec![super::super::Material::default()],
            ..Default::default()
        };
        for i in 0..8u32 {
            m.positions
                .push([(i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32]);
        }
        let quads = [
            [0, 2, 3, 1],
            [4, 5, 7, 6],
            [0, 1, 5, 4],
            [2, 6, 7, 3],
            [0, 4, 6, 2],
            [1, 3, 7, 5],
        ];
        for q in quads {
            m.indices.extend([q[0], q[1], q[2], q[0], q[2], q[3]]);
            m.material_ids.extend([0, 0]);
        }
        m.normals = vec![[0.0; 3]; 8];
        m.uvs = vec![[0.0; 2]; 8];
        m
    }

    #[test]
    fn a_cube_is_shaded_flat_below_90_degrees_and_smooth_above() {
        let mut flat = cube();
        let added = crease_normals(&mut flat, 60.0);
        // Each corner is shared by 3 faces at 90 degrees: 3 vertices per corner.
        assert_eq!(added, 16);
        assert_eq!(flat.positions.len(), 24);
        flat.validate().expect("valid");
        // Every corner's normal is its face's normal.
        for tri in flat.indices.chunks_exact(3) {
            let p: [[f32; 3]; 3] = std::array::from_fn(|k| flat.positions[tri[k] as usize]);
            let fnormal = normalized(cross(sub(p[1], p[0]), sub(p[2], p[0]))).expect("area");
            for &i in tri {
                let nn = flat.normals[i as usize].map(f64::from);
                assert!(dot(nn, fnormal) > 0.9999, "{nn:?} vs {fnormal:?}");
            }
        }
        let mut smooth = cube();
        assert_eq!(crease_normals(&mut smooth, 120.0), 0);
        // Corner (0,0,0) points away from the centre along the diagonal.
        let n0 = smooth.normals[0].map(f64::from);
        let d = normalized([-1.0, -1.0, -1.0]).expect("diag");
        assert!(dot(n0, d) > 0.999, "{n0:?}");
    }

    #[test]
    fn existing_normals_are_kept_and_normalized() {
        let mut m = cube();
        m.normals = vec![[0.0, 0.0, 2.0]; 8];
        assert_eq!(crease_normals(&mut m, 60.0), 0);
        assert!(m.normals.iter().all(|n| *n == [0.0, 0.0, 1.0]));
    }

    /// A cone of `k` faces around an apex, without normals.
    fn cone(k: u32) -> Mesh {
        let mut m = Mesh {
            name: "cone".into(),
            materials: vec![super::super::Material::default()],
            ..Default::default()
        };
        m.positions.push([0.0, 0.0, 1.0]);
        for i in 0..k {
            let a = std::f32::consts::TAU * i as f32 / k as f32;
            m.positions.push([a.cos(), a.sin(), 0.0]);
        }
        for i in 0..k {
            m.indices.extend([0, 1 + i, 1 + (i + 1) % k]);
            m.material_ids.push(0);
        }
        m.normals = vec![[0.0; 3]; m.positions.len()];
        m.uvs = vec![[0.0; 2]; m.positions.len()];
        m
    }

    /// Regression: a fan of many triangles around one position cost the square of their number
    /// (80,000 took 15 s to import). Smooth fans are found by a sort, so a huge fan is cheap and
    /// shaded like any other: smoothly at 180 degrees (one apex normal, straight up).
    #[test]
    fn a_huge_fan_is_cheap_and_smooth() {
        let mut m = cone(80_000);
        let t0 = std::time::Instant::now();
        let added = crease_normals(&mut m, 180.0);
        m.validate().expect("valid");
        assert_eq!(added, 0);
        let apex = m.normals[0].map(f64::from);
        assert!(apex[2] > 0.9999, "{apex:?}");
        // Generous: the quadratic version took 15 s in release; this one takes milliseconds.
        assert!(t0.elapsed().as_secs_f64() < 5.0, "{:?}", t0.elapsed());
    }

    /// A smooth curved surface whose faces around a vertex differ by more than the crease angle
    /// from end to end, but by little across each edge, keeps one vertex per position: only
    /// sharp edges split. (Comparing each corner's face with every face around it split every
    /// corner of such a vertex.)
    #[test]
    fn a_coarse_smooth_cone_is_not_split() {
        // 12 faces around a steep apex: neighbours differ by ~29 degrees, opposite faces by ~160.
        let mut m = cone(12);
        for p in m.positions.iter_mut().skip(1) {
            p[0] *= 0.1;
            p[1] *= 0.1;
        }
        let added = crease_normals(&mut m, 60.0);
        assert_eq!(added, 0, "no edge is sharper than 60 degrees");
        let apex = m.normals[0].map(f64::from);
        assert!(apex[2] > 0.99, "{apex:?}");
        // With a crease below the neighbour angle every edge is sharp: flat, each apex corner apart.
        let mut flat = cone(12);
        for p in flat.positions.iter_mut().skip(1) {
            p[0] *= 0.1;
            p[1] *= 0.1;
        }
        assert!(crease_normals(&mut flat, 20.0) > 0);
    }
}
