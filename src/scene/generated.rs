//! Meshes made in code, named in scene files as `generated:NAME` (see [`crate::scene`]): the
//! benchmark scenes' ground boxes and grass clumps.

use glam::{DVec3, Vec3};

use crate::mesh::{Material, Mesh};

/// The names [`generated_mesh`] knows.
pub const NAMES: [&str; 2] = ["grass", "box"];

/// A mesh made in code, named in scene files as `generated:NAME`: `grass` (a clump of 24 thin
/// disconnected blades, 168 triangles, about 1 unit tall and wide, base at y = 0) or `box` (a
/// unit cube centred at the origin, flat normals).
pub fn generated_mesh(name: &str) -> Option<Mesh> {
    let mut mesh = match name {
        "grass" => grass_clump(24, 4, 7),
        "box" => unit_box(),
        _ => return None,
    };
    mesh.name = name.to_string();
    mesh.material_ids = vec![0; mesh.indices.len() / 3];
    mesh.materials = vec![Material::default()];
    mesh.uvs = vec![[0.0; 2]; mesh.positions.len()];
    mesh.has_uvs = false;
    Some(mesh)
}

/// A grass clump: `blades` blades of `segments` quads and a tip triangle each.
fn grass_clump(blades: u32, segments: u32, seed: u64) -> Mesh {
    let mut rng = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut unit = move || {
        // xorshift64*: deterministic, good enough for placement.
        rng ^= rng >> 12;
        rng ^= rng << 25;
        rng ^= rng >> 27;
        (rng.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    };
    let mut m = Mesh::default();
    for _ in 0..blades {
        let angle = unit() * std::f64::consts::TAU;
        let r = unit().sqrt() * 0.3;
        let base = DVec3::new(r * angle.cos(), 0.0, r * angle.sin());
        let facing = unit() * std::f64::consts::TAU;
        let side = DVec3::new(facing.cos(), 0.0, facing.sin());
        let lean = DVec3::new(-facing.sin(), 0.0, facing.cos()) * (0.2 + 0.4 * unit());
        let height = 0.6 + 0.4 * unit();
        let width = 0.04 + 0.03 * unit();
        let first = m.positions.len() as u32;
        for s in 0..segments {
            let t = s as f64 / segments as f64;
            let centre = base + DVec3::Y * (height * t) + lean * (t * t);
            let w = width * (1.0 - t * 0.8);
            for sign in [-1.0, 1.0] {
                m.positions
                    .push((centre + side * (w * 0.5 * sign)).as_vec3().into());
            }
        }
        let tip = base + DVec3::Y * height + lean;
        m.positions.push(tip.as_vec3().into());
        for s in 0..segments - 1 {
            let (a, b) = (first + 2 * s, first + 2 * s + 1);
            m.indices.extend_from_slice(&[a, b, a + 2, b, b + 2, a + 2]);
        }
        let last = first + 2 * (segments - 1);
        m.indices.extend_from_slice(&[last, last + 1, last + 2]);
    }
    m.normals = vec![[0.0; 3]; m.positions.len()];
    crate::mesh::fill_missing_normals(&mut m);
    m.has_normals = false;
    m
}

/// A unit cube centred at the origin, 24 vertices (flat normals), 12 triangles.
fn unit_box() -> Mesh {
    let mut m = Mesh::default();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut n = Vec3::ZERO;
            n[axis] = sign;
            let u = n.any_orthonormal_pair().0;
            let v = n.cross(u);
            let first = m.positions.len() as u32;
            for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                m.positions.push((0.5 * (n + u * a + v * b)).into());
                m.normals.push(n.into());
            }
            m.indices.extend_from_slice(&[
                first,
                first + 1,
                first + 2,
                first,
                first + 2,
                first + 3,
            ]);
        }
    }
    m.has_normals = true;
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn generated_meshes_are_valid() {
        let g = generated_mesh("grass").unwrap();
        g.validate().unwrap();
        assert_eq!(g.triangle_count(), 24 * 7);
        let (lo, hi) = g.bounds().unwrap();
        assert!(lo[1] >= 0.0 && hi[1] > 0.5 && hi[1] < 1.5, "{lo:?} {hi:?}");
        let b = generated_mesh("box").unwrap();
        b.validate().unwrap();
        assert_eq!(b.triangle_count(), 12);
        assert_eq!(b.bounds().unwrap(), ([-0.5; 3], [0.5; 3]));
        // Outward winding: each triangle's normal agrees with its vertices' normals.
        for t in b.indices.chunks_exact(3) {
            let p = |i: u32| Vec3::from(b.positions[i as usize]);
            let n = (p(t[1]) - p(t[0])).cross(p(t[2]) - p(t[0]));
            assert!(n.dot(Vec3::from(b.normals[t[0] as usize])) > 0.0);
        }
        assert!(generated_mesh("nope").is_none());
        for name in NAMES {
            assert!(generated_mesh(name).is_some(), "{name}");
        }
    }
}
