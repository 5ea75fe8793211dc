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

/// A face around a position, as a corner's fan reads it: its normal, the angle of its corner at
/// the position (the weight), the corner's index, and the two other positions of the face.
#[derive(Clone, Copy, Default)]
struct FanFace {
    normal: [f64; 3],
    weight: f64,
    corner: u32,
    others: [u32; 2],
}

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

/// Root of `i` in a small union-find, halving paths as it goes.
fn find(parent: &mut [u32], mut i: u32) -> u32 {
    while parent[i as usize] != i {
        let up = parent[parent[i as usize] as usize];
        parent[i as usize] = up;
        i = up;
    }
    i
}

/// Splits one position's fan into smooth fans and writes each corner's normal (the
/// angle-weighted average of its smooth fan; its own face's where that is degenerate).
/// `parent` and `edges` are scratch.
fn fan_normals(
    fan: &[FanFace],
    cos_crease: f64,
    parent: &mut Vec<u32>,
    edges: &mut Vec<(u32, u32)>,
    acc: &mut Vec<[f64; 3]>,
    out: &mut [[f32; 3]],
) {
    let k = fan.len();
    parent.clear();
    parent.extend(0..k as u32);
    // Faces sharing an edge of this position share the edge's other position: sort the
    // (other position, face) pairs and join the faces of one edge that meet smoothly.
    edges.clear();
    for (i, ff) in fan.iter().enumerate() {
        edges.push((ff.others[0], i as u32));
        if ff.others[1] != ff.others[0] {
            edges.push((ff.others[1], i as u32));
        }
    }
    edges.sort_unstable();
    let mut run = 0;
    while run < edges.len() {
        let mut end = run + 1;
        while end < edges.len() && edges[end].0 == edges[run].0 {
            end += 1;
        }
        // Usually two faces per edge; a non-manifold edge joins every smooth pair.
        for a in run..end {
            for b in a + 1..end {
                let (fa, fb) = (edges[a].1, edges[b].1);
                if dot(fan[fa as usize].normal, fan[fb as usize].normal) >= cos_crease {
                    let (ra, rb) = (find(parent, fa), find(parent, fb));
                    if ra != rb {
                        parent[ra.max(rb) as usize] = ra.min(rb);
                    }
                }
            }
        }
        run = end;
    }
    acc.clear();
    acc.resize(k, [0.0; 3]);
    for (i, ff) in fan.iter().enumerate() {
        let r = find(parent, i as u32) as usize;
        for (a, n) in acc[r].iter_mut().zip(ff.normal) {
            *a += n * ff.weight;
        }
    }
    for (i, ff) in fan.iter().enumerate() {
        let r = find(parent, i as u32) as usize;
        let normal = normalized(acc[r])
            .or(normalized(ff.normal))
            .unwrap_or([0.0, 0.0, 1.0]);
        out[ff.corner as usize] = normal.map(|x| x as f32);
    }
}

/// Normalizes every usable normal; vertices without one (zero or not finite) get crease-angle
/// normals: an edge is sharp where its faces' normals differ by more than `crease_deg` degrees,
/// the faces around a *position* (any vertex there, so UV or material splits do not matter) fall
/// into smooth fans joined across edges that are not sharp, and each triangle corner gets the
/// angle-weighted average normal of its fan. A vertex whose corners get different normals is split
/// (new vertices appended, indices updated). `crease_deg >= 180` shades smoothly everywhere, `0`
/// flat per face. Linear in the corners (a sort per position). Deterministic. Returns how many
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
    // CSR: the faces around each position, in triangle order, each with its normal, the corner's
    // angle (weight) and the face's other two positions, so that a fan is read contiguously.
    let mut start = vec![0u32; npos + 2];
    for c in 0..tri_count * 3 {
        start[corner_pid(c) as usize + 1] += 1;
    }
    for i in 0..=npos {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut around = vec![FanFace::default(); tri_count * 3];
    for t in 0..tri_count {
        let idx = [
            mesh.indices[3 * t] as usize,
            mesh.indices[3 * t + 1] as usize,
            mesh.indices[3 * t + 2] as usize,
        ];
        let p = idx.map(|i| mesh.positions.get(i).copied().unwrap_or([0.0; 3]));
        let face_n = normalized(cross(sub(p[1], p[0]), sub(p[2], p[0]))).unwrap_or([0.0; 3]);
        let q = [0, 1, 2].map(|k| corner_pid(3 * t + k));
        for k in 0..3 {
            let a = normalized(sub(p[(k + 1) % 3], p[k]));
            let b = normalized(sub(p[(k + 2) % 3], p[k]));
            let weight = match (a, b) {
                (Some(a), Some(b)) => dot(a, b).clamp(-1.0, 1.0).acos(),
                _ => 0.0,
            };
            let slot = &mut fill[q[k] as usize];
            around[*slot as usize] = FanFace {
                normal: face_n,
                weight,
                corner: (3 * t + k) as u32,
                others: [q[(k + 1) % 3], q[(k + 2) % 3]],
            };
            *slot += 1;
        }
    }
    drop(fill);
    let cos_crease = if crease_deg >= 180.0 {
        -2.0
    } else {
        (crease_deg.max(0.0) as f64).to_radians().cos() - 1e-9
    };
    // Every corner's normal, fan by fan (only fans with a corner that needs one).
    let mut corner_normal = vec![[0.0f32; 3]; tri_count * 3];
    let (mut parent, mut edges, mut acc) = (Vec::new(), Vec::new(), Vec::new());
    for p in 0..npos {
        let fan = &around[start[p] as usize..start[p + 1] as usize];
        let needed = fan.iter().any(|ff| {
            need.get(mesh.indices[ff.corner as usize] as usize)
                .copied()
                .unwrap_or(false)
        });
        if needed {
            fan_normals(
                fan,
                cos_crease,
                &mut parent,
                &mut edges,
                &mut acc,
                &mut corner_normal,
            );
        }
    }
    drop(around);
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
