//! Generated test meshes shared by the builder and verify tests.

use vgeo::mesh::{Material, Mesh};

/// A mesh of `positions` and `indices` with one default material (no source normals or UVs).
pub fn mesh_from(name: &str, positions: Vec<[f32; 3]>, indices: Vec<u32>) -> Mesh {
    let n = positions.len();
    let t = indices.len() / 3;
    Mesh {
        name: name.into(),
        normals: vec![[0.0, 0.0, 1.0]; n],
        uvs: positions.iter().map(|p| [p[0], p[1]]).collect(),
        positions,
        indices,
        material_ids: vec![0; t],
        materials: vec![Material::default()],
        has_normals: false,
        has_uvs: false,
    }
}

/// A `w` x `h` grid of quads in the xy plane (2 triangles each), with a height field.
pub fn grid(w: u32, h: u32, offset: [f32; 3], scale: f32) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut p = Vec::new();
    for y in 0..=h {
        for x in 0..=w {
            let z = ((x as f32 * 0.7).sin() + (y as f32 * 0.5).cos()) * 0.3;
            p.push([
                offset[0] + x as f32 * scale,
                offset[1] + y as f32 * scale,
                offset[2] + z * scale,
            ]);
        }
    }
    let mut idx = Vec::new();
    let v = |x: u32, y: u32| y * (w + 1) + x;
    for y in 0..h {
        for x in 0..w {
            idx.extend_from_slice(&[
                v(x, y),
                v(x + 1, y),
                v(x + 1, y + 1),
                v(x, y),
                v(x + 1, y + 1),
                v(x, y + 1),
            ]);
        }
    }
    (p, idx)
}

/// A closed UV sphere with `seg` segments and `rings` rings (poles as single vertices).
pub fn sphere(seg: u32, rings: u32, center: [f32; 3], r: f32) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut p = vec![[center[0], center[1], center[2] + r]];
    for i in 1..rings {
        let th = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..seg {
            let ph = std::f32::consts::TAU * j as f32 / seg as f32;
            let bump = 1.0 + 0.05 * (5.0 * ph).sin() * (3.0 * th).sin();
            p.push([
                center[0] + r * bump * th.sin() * ph.cos(),
                center[1] + r * bump * th.sin() * ph.sin(),
                center[2] + r * bump * th.cos(),
            ]);
        }
    }
    let south = p.len() as u32;
    p.push([center[0], center[1], center[2] - r]);
    let ring = |i: u32, j: u32| 1 + (i - 1) * seg + (j % seg);
    let mut idx = Vec::new();
    for j in 0..seg {
        idx.extend_from_slice(&[0, ring(1, j), ring(1, j + 1)]);
    }
    for i in 1..rings - 1 {
        for j in 0..seg {
            idx.extend_from_slice(&[ring(i, j), ring(i + 1, j), ring(i + 1, j + 1)]);
            idx.extend_from_slice(&[ring(i, j), ring(i + 1, j + 1), ring(i, j + 1)]);
        }
    }
    for j in 0..seg {
        idx.extend_from_slice(&[south, ring(rings - 1, j + 1), ring(rings - 1, j)]);
    }
    (p, idx)
}

pub fn append(dst: &mut (Vec<[f32; 3]>, Vec<u32>), src: (Vec<[f32; 3]>, Vec<u32>)) {
    let base = dst.0.len() as u32;
    dst.0.extend(src.0);
    dst.1.extend(src.1.into_iter().map(|i| i + base));
}

/// A flat `n` x `n` grid of square cells of side `side` in the xy plane (z = 0) from the origin,
/// two triangles per cell.
pub fn flat_grid(n: u32, side: f32) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut p = Vec::new();
    for y in 0..=n {
        for x in 0..=n {
            p.push([x as f32 * side, y as f32 * side, 0.0]);
        }
    }
    let v = |x: u32, y: u32| y * (n + 1) + x;
    let mut idx = Vec::new();
    for y in 0..n {
        for x in 0..n {
            idx.extend_from_slice(&[v(x, y), v(x + 1, y), v(x + 1, y + 1)]);
            idx.extend_from_slice(&[v(x, y), v(x + 1, y + 1), v(x, y + 1)]);
        }
    }
    (p, idx)
}

/// `n` separate slivers in the xy plane (z = 0) like grass blades seen from the front: each a
/// triangle of base `width` at `y = -length / 2` and apex at `y = length / 2`, the bases
/// `spacing` apart along x and centred on the origin. Area of each: `length * width / 2`.
pub fn slivers(n: u32, length: f32, width: f32, spacing: f32) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut p = Vec::new();
    let mut idx = Vec::new();
    let x0 = -(n as f32 - 1.0) * spacing / 2.0;
    for i in 0..n {
        let x = x0 + i as f32 * spacing;
        let b = p.len() as u32;
        p.push([x - width / 2.0, -length / 2.0, 0.0]);
        p.push([x + width / 2.0, -length / 2.0, 0.0]);
        p.push([x, length / 2.0, 0.0]);
        idx.extend_from_slice(&[b, b + 1, b + 2]);
    }
    (p, idx)
}

/// `n` x `n` copies of the built-in grass clump (`generated:grass`: 24 disconnected blades of 7
/// triangles and 9 vertices), 0.8 apart in x and z. Its clusters hold many vertices for their
/// triangles: at `n` = 2, level 0 to 3 have clusters of 128 to 170 vertices and of more.
pub fn grass_field(n: u32) -> Mesh {
    let clump = vgeo::scene::generated::generated_mesh("grass").expect("the generated grass");
    let mut parts = Vec::new();
    for i in 0..n {
        for j in 0..n {
            let mut m = clump.clone();
            for p in &mut m.positions {
                p[0] += 0.8 * i as f32;
                p[2] += 0.8 * j as f32;
            }
            parts.push(m);
        }
    }
    vgeo::mesh::merge(parts)
}
