//! Vertex normals for meshes that come without them: smooth within a crease angle, split at creases.
//!
//! A glTF viewer or a DCC tool shades a mesh without normals smoothly across gentle bends and flat
//! across sharp edges (a box's faces, a turbine blade's rim). Averaging every face around a vertex
//! instead bends the shading of whole faces towards their neighbours, which is wrong at full detail
//! and worse once the builder simplifies the mesh. [`crease_normals`] gives each triangle corner the
//! angle-weighted average of the faces around its position whose normal is within the crease angle
//! of the corner's own face, and splits a vertex where its corners get different normals. The
//! splits are attribute seams: the builder keeps them (meshoptimizer does not collapse across a
//! seam), so a crease stays sharp at every level of detail.

use std::collections::HashMap;

use super::Mesh;
use crate::hash::FxBuild;

/// A face around a position, as a corner's fan reads it: its normal, the angle of its corner at
/// the position (the weight) and its index.
#[derive(Clone, Copy, Default)]
struct FanFace {
    normal: [f64; 3],
    weight: f64,
    face: u32,
}

/// Default crease angle in degrees (faces meeting at a sharper angle are shaded apart).
pub const DEFAULT_CREASE_DEG: f32 = 60.0;

/// A position with more triangle corners than this is shaded flat (each corner its face's normal):
/// comparing every corner with every face around it costs the square of their number, and a
/// hostile file of one fan of 10^5 triangles took minutes. Real meshes stay far below (a UV
/// sphere's pole has as many corners as the sphere has segments).
pub const MAX_CREASE_FAN: usize = 1024;

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

/// Normalizes every usable normal; vertices without one (zero or not finite) get crease-angle
/// normals: each of their triangle corners gets the angle-weighted average of the normals of the
/// faces around the corner's *position* (any vertex there, so UV or material splits do not matter)
/// that lie within `crease_deg` degrees of the corner's own face, and a vertex whose corners get
/// different normals is split (new vertices appended, indices updated). `crease_deg >= 180` shades
/// smoothly everywhere, `0` flat per face. Positions with more than [`MAX_CREASE_FAN`] corners
/// are shaded flat. Deterministic. Returns how many vertices were added.
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
    // Face normals and the corner angles (weights).
    let mut face_n = vec![[0.0f64; 3]; tri_count];
    let mut angles = vec![[0.0f64; 3]; tri_count];
    for t in 0..tri_count {
        let idx = [
            mesh.indices[3 * t] as usize,
            mesh.indices[3 * t + 1] as usize,
            mesh.indices[3 * t + 2] as usize,
        ];
        let p = idx.map(|i| mesh.positions.get(i).copied().unwrap_or([0.0; 3]));
        face_n[t] = normalized(cross(sub(p[1], p[0]), sub(p[2], p[0]))).unwrap_or([0.0; 3]);
        for k in 0..3 {
            let a = normalized(sub(p[(k + 1) % 3], p[k]));
            let b = normalized(sub(p[(k + 2) % 3], p[k]));
            angles[t][k] = match (a, b) {
                (Some(a), Some(b)) => dot(a, b).clamp(-1.0, 1.0).acos(),
                _ => 0.0,
            };
        }
    }
    // CSR: the faces around each position, in triangle order, each with its normal and the
    // corner's angle (weight) stored in place, so that a corner's fan is read contiguously.
    let mut start = vec![0u32; npos + 1];
    for &v in &mesh.indices {
        if let Some(&p) = pid.get(v as usize) {
            start[p as usize + 1] += 1;
        }
    }
    for i in 0..npos {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut around = vec![FanFace::default(); mesh.indices.len()];
    for (c, &v) in mesh.indices.iter().enumerate() {
        if let Some(&p) = pid.get(v as usize) {
            let (t, k) = (c / 3, c % 3);
            around[fill[p as usize] as usize] = FanFace {
                normal: face_n[t],
                weight: angles[t][k],
                face: t as u32,
            };
            fill[p as usize] += 1;
        }
    }
    drop(angles);
    let cos_crease = if crease_deg >= 180.0 {
        -2.0
    } else {
        (crease_deg.max(0.0) as f64).to_radians().cos() - 1e-9
    };
    // Per corner of a vertex that needs a normal: its crease normal; vertices split per normal.
    let mut split: HashMap<(u32, [u32; 3]), u32, FxBuild> = HashMap::default();
    let mut first_normal: Vec<Option<[u32; 3]>> = vec![None; n];
    let mut added = 0usize;
    for c in 0..mesh.indices.len() {
        let v = mesh.indices[c] as usize;
        if !need.get(v).copied().unwrap_or(false) {
            continue;
        }
        let t = c / 3;
        let own = face_n[t];
        let p = pid[v] as usize;
        let mut acc = [0.0f64; 3];
        let fan = &around[start[p] as usize..start[p + 1] as usize];
        let fan = if fan.len() > MAX_CREASE_FAN {
            &[][..] // flat: `own` below
        } else {
            fan
        };
        for ff in fan {
            let nf = ff.normal;
            if ff.face as usize == t || dot(own, nf) >= cos_crease {
                let w = ff.weight;
                for i in 0..3 {
                    acc[i] += nf[i] * w;
                }
            }
        }
        let normal = normalized(acc)
            .or(normalized(own))
            .unwrap_or([0.0, 0.0, 1.0])
            .map(|x| x as f32);
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

    /// Regression: a fan of many triangles around one position cost the square of their number
    /// (80,000 took 15 s to import); past `MAX_CREASE_FAN` corners the position is shaded flat.
    #[test]
    fn a_huge_fan_is_shaded_flat() {
        let k = 20_000u32;
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
        let added = crease_normals(&mut m, 180.0);
        m.validate().expect("valid");
        // The apex is split per distinct face normal (flat), the rim shaded smoothly.
        assert!(added > k as usize / 2, "{added}");
        for tri in m.indices.chunks_exact(3) {
            let p: [[f32; 3]; 3] = std::array::from_fn(|c| m.positions[tri[c] as usize]);
            let fnormal = normalized(cross(sub(p[1], p[0]), sub(p[2], p[0]))).expect("area");
            let apex = m.normals[tri[0] as usize].map(f64::from);
            assert!(dot(apex, fnormal) > 0.9999, "{apex:?} vs {fnormal:?}");
        }
    }
}
