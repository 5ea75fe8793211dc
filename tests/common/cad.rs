//! A deterministic generator of CAD-like assemblies: thousands of small separate parts, closed
//! and open (boxes, cylinders, open tubes, plates, open boxes, brackets), flat-shaded (vertices
//! split at every sharp edge, as CAD exporters write them), with the defects real exports have:
//! duplicated parts, parts touching face to face or lying on each other, zero-area and duplicate
//! triangles, T-junctions, triangle fans of slivers, sizes from a few quantization steps to the
//! whole assembly, and a few materials.

use glam::{Mat3, Vec3};
use vgeo::mesh::{Material, Mesh};

/// SplitMix64.
pub struct Rng(pub u64);
impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e3779b97f4a7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58476d1ce4e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d049bb133111eb);
        z ^ (z >> 31)
    }
    /// Uniform in [0, 1).
    pub fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }
    /// Uniform integer in lo..=hi.
    pub fn int(&mut self, lo: u32, hi: u32) -> u32 {
        lo + (self.next() % (hi - lo + 1) as u64) as u32
    }
    pub fn chance(&mut self, p: f32) -> bool {
        self.unit() < p
    }
}

/// A rigid placement with uniform scale.
#[derive(Clone, Copy)]
struct Frame {
    rot: Mat3,
    scale: f32,
    at: Vec3,
}

impl Frame {
    fn point(&self, p: Vec3) -> Vec3 {
        self.at + self.rot * (p * self.scale)
    }
    fn normal(&self, n: Vec3) -> Vec3 {
        (self.rot * n).normalize_or_zero()
    }
}

/// The mesh being generated.
struct Out {
    positions: Vec<[f32; 3]>,
    normals: Vec<[f32; 3]>,
    indices: Vec<u32>,
    material_ids: Vec<u32>,
    /// Material of the part being generated.
    mat: u32,
}

impl Out {
    fn vert(&mut self, f: &Frame, p: Vec3, n: Vec3) -> u32 {
        self.positions.push(f.point(p).to_array());
        self.normals.push(f.normal(n).to_array());
        self.positions.len() as u32 - 1
    }
    fn tri(&mut self, a: u32, b: u32, c: u32) {
        self.indices.extend_from_slice(&[a, b, c]);
        self.material_ids.push(self.mat);
    }
    /// A flat face: the parallelogram `o + s u + t v` (s, t in [0, 1]) split into `nu` x `nv`
    /// quads, facing `u x v`, with its own vertices (a seam with every other face).
    fn face(&mut self, f: &Frame, o: Vec3, u: Vec3, v: Vec3, nu: u32, nv: u32) {
        let n = u.cross(v).normalize_or_zero();
        let base = self.positions.len() as u32;
        for j in 0..=nv {
            for i in 0..=nu {
                let p = o + u * (i as f32 / nu as f32) + v * (j as f32 / nv as f32);
                self.vert(f, p, n);
            }
        }
        let id = |i: u32, j: u32| base + j * (nu + 1) + i;
        for j in 0..nv {
            for i in 0..nu {
                // Alternate the diagonal, as tessellators do.
                if (i + j) % 2 == 0 {
                    self.tri(id(i, j), id(i + 1, j), id(i + 1, j + 1));
                    self.tri(id(i, j), id(i + 1, j + 1), id(i, j + 1));
                } else {
                    self.tri(id(i, j), id(i + 1, j), id(i, j + 1));
                    self.tri(id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
                }
            }
        }
    }
    /// An axis-aligned box `[0, s]` with faces split `n[k]` times along axis k (different
    /// splits on touching boxes make T-junctions); `skip`: faces left out (open boxes), bit
    /// 2k: the face at 0 on axis k, bit 2k+1: the face at s[k].
    fn cuboid(&mut self, f: &Frame, s: Vec3, n: [u32; 3], skip: u32) {
        let ax = [Vec3::X * s.x, Vec3::Y * s.y, Vec3::Z * s.z];
        for k in 0..3 {
            let (a, b) = ((k + 1) % 3, (k + 2) % 3);
            if skip & (1 << (2 * k)) == 0 {
                // At 0, facing -k: v x u.
                self.face(f, Vec3::ZERO, ax[b], ax[a], n[b], n[a]);
            }
            if skip & (1 << (2 * k + 1)) == 0 {
                self.face(f, ax[k], ax[a], ax[b], n[a], n[b]);
            }
        }
    }
    /// A cylinder of radius 1 along z from 0 to `h` with `seg` segments; caps are triangle fans
    /// from one rim vertex (the slivers CAD tessellators make) or from a centre, or absent.
    fn cylinder(&mut self, f: &Frame, h: f32, seg: u32, rings: u32, caps: Caps, inward: bool) {
        let ring = |j: u32| {
            let a = std::f32::consts::TAU * (j % seg) as f32 / seg as f32;
            Vec3::new(a.cos(), a.sin(), 0.0)
        };
        let base = self.positions.len() as u32;
        for r in 0..=rings {
            for j in 0..seg {
                let d = ring(j);
                let n = if inward { -d } else { d };
                self.vert(f, d + Vec3::Z * (h * r as f32 / rings as f32), n);
            }
        }
        let id = |r: u32, j: u32| base + r * seg + j % seg;
        for r in 0..rings {
            for j in 0..seg {
                let (a, b, c, d) = (id(r, j), id(r, j + 1), id(r + 1, j + 1), id(r + 1, j));
                if inward {
                    self.tri(a, c, b);
                    self.tri(a, d, c);
                } else {
                    self.tri(a, b, c);
                    self.tri(a, c, d);
                }
            }
        }
        if caps == Caps::None {
            return;
        }
        for (z, up) in [(0.0, false), (h, true)] {
            let n = if up { Vec3::Z } else { -Vec3::Z };
            let rim: Vec<u32> = (0..seg)
                .map(|j| self.vert(f, ring(j) + Vec3::Z * z, n))
                .collect();
            let fan = |a: u32, b: u32, c: u32, out: &mut Out| {
                if up {
                    out.tri(a, b, c);
                } else {
                    out.tri(a, c, b);
                }
            };
            match caps {
                Caps::RimFan => {
                    for j in 1..seg - 1 {
                        fan(rim[0], rim[j as usize], rim[j as usize + 1], self);
                    }
                }
                _ => {
                    let c = self.vert(f, Vec3::Z * z, n);
                    for j in 0..seg {
                        fan(c, rim[j as usize], rim[((j + 1) % seg) as usize], self);
                    }
                }
            }
        }
    }
    /// Zero-area triangles along the segment a-b of the part: (a, m, b) with m on the segment
    /// (collinear), and (a, a', b) with a' a second vertex at a's position.
    fn slivers(&mut self, f: &Frame, a: Vec3, b: Vec3, t: f32) {
        let n = Vec3::Z;
        let (va, vm, vb) = (
            self.vert(f, a, n),
            self.vert(f, a + (b - a) * t, n),
            self.vert(f, b, n),
        );
        self.tri(va, vm, vb);
        let va2 = self.vert(f, a, -n);
        self.tri(va, va2, vb);
    }
}

#[derive(Clone, Copy, PartialEq, Eq)]
enum Caps {
    None,
    RimFan,
    CentreFan,
}

fn random_rotation(rng: &mut Rng) -> Mat3 {
    // Axis-aligned (exact coincidences) half the time.
    if rng.chance(0.5) {
        let k = rng.int(0, 3) as f32 * std::f32::consts::FRAC_PI_2;
        return Mat3::from_rotation_z(k);
    }
    let axis = Vec3::new(
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
        rng.range(-1.0, 1.0),
    )
    .normalize_or(Vec3::X);
    Mat3::from_axis_angle(axis, rng.range(0.0, std::f32::consts::TAU))
}

/// A CAD-like assembly of about `parts` parts (every part a few to a few hundred triangles; the
/// assembly about 16 units across). Deterministic in (`parts`, `seed`).
pub fn cad_assembly(parts: usize, seed: u64) -> Mesh {
    let mut rng = Rng(seed);
    let mut o = Out {
        positions: Vec::new(),
        normals: Vec::new(),
        indices: Vec::new(),
        material_ids: Vec::new(),
        mat: 0,
    };
    const MATERIALS: u32 = 6;
    let mut made = 0;
    while made < parts {
        o.mat = rng.int(0, MATERIALS - 1);
        // Log-uniform size: from about 4 grid steps (16 / 2^21 each) to several units.
        let scale = 2f32.powf(rng.range(-17.0, 1.5));
        let at = Vec3::new(
            rng.range(-8.0, 8.0),
            rng.range(-8.0, 8.0),
            rng.range(-3.0, 3.0),
        );
        // Snap some placements to a coarse grid so that parts coincide exactly.
        let at = if rng.chance(0.3) {
            (at * 4.0).round() / 4.0
        } else {
            at
        };
        let f = Frame {
            rot: random_rotation(&mut rng),
            scale,
            at,
        };
        let copies = if rng.chance(0.05) { 2 } else { 1 };
        let kind = rng.int(0, 9);
        let n3 = [rng.int(1, 3), rng.int(1, 3), rng.int(1, 3)];
        let dims = Vec3::new(
            rng.range(0.2, 1.0),
            rng.range(0.2, 1.0),
            rng.range(0.2, 1.0),
        );
        let seg = rng.int(3, 24);
        let rings = rng.int(1, 3);
        let caps = [Caps::RimFan, Caps::CentreFan][rng.int(0, 1) as usize];
        let sliver = rng.chance(0.1);
        for _ in 0..copies {
            match kind {
                0 | 1 => o.cuboid(&f, dims, n3, 0),
                // Open box (sheet metal).
                2 => o.cuboid(&f, dims, n3, 1 << rng.int(0, 5)),
                3 => o.cylinder(&f, dims.z * 3.0, seg, rings, caps, false),
                // Open tube, sometimes with a wall (inner surface, annulus-free: open).
                4 => {
                    o.cylinder(&f, dims.z * 3.0, seg, rings, Caps::None, false);
                    if rng.chance(0.5) {
                        let g = Frame {
                            scale: f.scale * 0.8,
                            ..f
                        };
                        o.cylinder(&g, dims.z * 3.0 / 0.8, seg, rings, Caps::None, true);
                    }
                }
                // Plate: one-sided, open.
                5 => o.face(
                    &f,
                    Vec3::ZERO,
                    Vec3::X * dims.x,
                    Vec3::Y * dims.y,
                    n3[0],
                    n3[1],
                ),
                // Bracket: two plates meeting at an edge (seam, positions shared).
                6 => {
                    o.face(
                        &f,
                        Vec3::ZERO,
                        Vec3::X * dims.x,
                        Vec3::Y * dims.y,
                        n3[0],
                        n3[1],
                    );
                    o.face(
                        &f,
                        Vec3::ZERO,
                        Vec3::Z * dims.z,
                        Vec3::X * dims.x,
                        n3[2],
                        n3[0],
                    );
                }
                // A stack of boxes face to face, with different face splits (T-junctions),
                // and a plate lying on the top.
                7 => {
                    let mut z = 0.0;
                    for _ in 0..rng.int(2, 4) {
                        let g = Frame {
                            at: f.point(Vec3::Z * z),
                            ..f
                        };
                        let n = [rng.int(1, 3), rng.int(1, 3), rng.int(1, 3)];
                        o.cuboid(&g, Vec3::new(1.0, 1.0, 0.5), n, 0);
                        z += 0.5;
                    }
                    let g = Frame {
                        at: f.point(Vec3::Z * z),
                        ..f
                    };
                    o.face(&g, Vec3::ZERO, Vec3::X, Vec3::Y, 1, 1);
                }
                // A bolt: a capped cylinder through a plate with the plate coincident with a
                // face of a box under it (opposite windings touching).
                8 => {
                    o.cuboid(&f, Vec3::new(2.0, 2.0, 0.5), [2, 2, 1], 0);
                    let g = Frame {
                        at: f.point(Vec3::new(0.0, 0.0, 0.5)),
                        ..f
                    };
                    o.face(&g, Vec3::ZERO, Vec3::X * 2.0, Vec3::Y * 2.0, 2, 2);
                    let b = Frame {
                        at: f.point(Vec3::new(1.0, 1.0, -0.5)),
                        scale: f.scale * 0.2,
                        ..f
                    };
                    o.cylinder(&b, 10.0, seg.max(6), 2, Caps::CentreFan, false);
                }
                // A coarse sphere (poles as fans).
                _ => {
                    let rings = rng.int(2, 8);
                    let base = o.positions.len() as u32;
                    let segs = seg.max(3);
                    for r in 0..=rings {
                        let th = std::f32::consts::PI * r as f32 / rings as f32;
                        for j in 0..segs {
                            let ph = std::f32::consts::TAU * j as f32 / segs as f32;
                            let d = Vec3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos());
                            o.vert(&f, d, d);
                        }
                    }
                    let id = |r: u32, j: u32| base + r * segs + j % segs;
                    for r in 0..rings {
                        for j in 0..segs {
                            // At the poles the ring's points coincide: degenerate triangles.
                            o.tri(id(r, j), id(r + 1, j), id(r + 1, j + 1));
                            o.tri(id(r, j), id(r + 1, j + 1), id(r, j + 1));
                        }
                    }
                }
            }
            if sliver {
                let t = rng.range(0.1, 0.9);
                o.slivers(&f, Vec3::ZERO, Vec3::X * dims.x, t);
            }
        }
        made += 1;
    }
    // Duplicate triangles: a few repeated verbatim.
    let t = o.indices.len() / 3;
    for k in 0..t / 200 {
        let i = (k * 197 + 13) % t;
        let tri = [o.indices[3 * i], o.indices[3 * i + 1], o.indices[3 * i + 2]];
        o.mat = o.material_ids[i];
        o.tri(tri[0], tri[1], tri[2]);
    }
    let n = o.positions.len();
    let t = o.indices.len() / 3;
    Mesh {
        name: format!("cad-{parts}-{seed}"),
        uvs: vec![[0.0, 0.0]; n],
        positions: o.positions,
        normals: o.normals,
        indices: o.indices,
        material_ids: {
            assert_eq!(o.material_ids.len(), t);
            o.material_ids
        },
        materials: (0..MATERIALS)
            .map(|i| Material {
                name: format!("part{i}"),
                ..Material::default()
            })
            .collect(),
        has_normals: true,
        has_uvs: false,
    }
}
