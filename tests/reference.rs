//! The CPU reference rasterizer through its public API, against independent oracles: ray casting
//! for coverage and depth, exact counts for fill-rule cases, parity of a closed mesh.

mod common;

use std::time::Instant;

use common::shared_assets;
use glam::{DMat4, DVec3, DVec4, Mat4, Vec3};
use vgeo::camera::Camera;
use vgeo::reference::{RasterTarget, SideClip, for_each_fragment, rasterize};

/// xorshift64* for test inputs.
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
    }
    fn unit(&mut self) -> f32 {
        (self.next() >> 40) as f32 / (1u64 << 24) as f32
    }
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * self.unit()
    }
}

fn camera_at_origin(near: f32) -> Camera {
    Camera::look_at(DVec3::ZERO, DVec3::NEG_Z, Vec3::Y, 60f32.to_radians(), near)
}

/// Fragment count per pixel.
fn counts(w: u32, h: u32, vp: &Mat4, tris: &[([Vec3; 3], u32)]) -> Vec<u32> {
    let mut c = vec![0u32; (w * h) as usize];
    for_each_fragment(w, h, vp, SideClip::Viewport, tris.iter().copied(), |f| {
        c[(f.y * w + f.x) as usize] += 1
    });
    c
}

/// Ray-casting oracle: whether the ray through viewport point `(px, py)` hits the part of the
/// triangle at or beyond the near plane, and the expected depth there.
struct Oracle {
    inv: DMat4,
    w: f64,
    h: f64,
}

impl Oracle {
    fn new(vp: &Mat4, w: u32, h: u32) -> Self {
        Self {
            inv: vp.as_dmat4().inverse(),
            w: w as f64,
            h: h as f64,
        }
    }

    fn hit(&self, tri: &[Vec3; 3], px: f64, py: f64) -> Option<f64> {
        let ndc = DVec4::new(px / self.w * 2.0 - 1.0, py / self.h * 2.0 - 1.0, 1.0, 1.0);
        let q = self.inv * ndc;
        let dir = q.truncate() / q.w; // on the near plane: t = 1 is the near plane
        let [a, b, c] = tri.map(|v| v.as_dvec3());
        let (e1, e2) = (b - a, c - a);
        let pv = dir.cross(e2);
        let det = e1.dot(pv);
        if det.abs() < 1e-300 {
            return None;
        }
        let tv = -a;
        let u = tv.dot(pv) / det;
        let qv = tv.cross(e1);
        let v = dir.dot(qv) / det;
        let t = e2.dot(qv) / det;
        (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t >= 1.0).then_some(1.0 / t)
    }

    /// `Some(depth)` / `None` if the five samples around the pixel centre agree, else ambiguous.
    fn pixel(&self, tri: &[Vec3; 3], x: u32, y: u32, eps: f64) -> Result<Option<f64>, ()> {
        let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
        let centre = self.hit(tri, cx, cy);
        for (dx, dy) in [(eps, 0.0), (-eps, 0.0), (0.0, eps), (0.0, -eps)] {
            if self.hit(tri, cx + dx, cy + dy).is_some() != centre.is_some() {
                return Err(());
            }
        }
        Ok(centre)
    }
}

/// Compares one triangle's fragments with the oracle; returns (covered, checked pixels).
fn check_against_oracle(
    tri: [Vec3; 3],
    vp: &Mat4,
    w: u32,
    h: u32,
    eps: f64,
    side_clip: SideClip,
) -> (usize, usize) {
    let oracle = Oracle::new(vp, w, h);
    let mut depth = vec![f32::NAN; (w * h) as usize];
    let mut n = 0;
    for_each_fragment(w, h, vp, side_clip, [(tri, 0)], |f| {
        let i = (f.y * w + f.x) as usize;
        assert!(
            depth[i].is_nan(),
            "pixel {},{} covered twice by one triangle",
            f.x,
            f.y
        );
        depth[i] = f.depth;
        n += 1;
    });
    let mut checked = 0;
    for y in 0..h {
        for x in 0..w {
            let Ok(want) = oracle.pixel(&tri, x, y, eps) else {
                continue;
            };
            checked += 1;
            let got = depth[(y * w + x) as usize];
            match want {
                None => assert!(
                    got.is_nan(),
                    "pixel {x},{y} covered, oracle misses; tri {tri:?}"
                ),
                Some(d) => {
                    assert!(
                        !got.is_nan(),
                        "pixel {x},{y} missed, oracle hits; tri {tri:?}"
                    );
                    // Snapping moves vertices by up to 1/512 pixel: allow the depth change over
                    // 1/128 pixel (depth is affine in screen space), plus f32 rounding.
                    let (cx, cy) = (x as f64 + 0.5, y as f64 + 0.5);
                    let delta = 1.0 / 128.0;
                    let slack = [(delta, 0.0), (0.0, delta), (-delta, 0.0), (0.0, -delta)]
                        .iter()
                        .filter_map(|&(dx, dy)| oracle.hit(&tri, cx + dx, cy + dy))
                        .map(|dn| (dn - d).abs())
                        .fold(0.0, f64::max);
                    assert!(
                        (got as f64 - d).abs() <= d * 1e-5 + slack,
                        "pixel {x},{y}: depth {got} vs {d} (slack {slack}); tri {tri:?}"
                    );
                    assert!(got <= 1.0 + 1e-6, "depth {got} in front of the near plane");
                }
            }
        }
    }
    (n, checked)
}

#[test]
fn full_screen_quads_cover_every_pixel_once() {
    let (w, h) = (61, 37);
    // Exactly the viewport (edges on pixel borders), through an identity projection.
    let q = [
        Vec3::new(-1.0, -1.0, 0.5),
        Vec3::new(1.0, -1.0, 0.5),
        Vec3::new(1.0, 1.0, 0.5),
        Vec3::new(-1.0, 1.0, 0.5),
    ];
    let tris = [([q[0], q[1], q[2]], 0), ([q[2], q[3], q[0]], 1)];
    assert!(counts(w, h, &Mat4::IDENTITY, &tris).iter().all(|&n| n == 1));
    // A plane larger than the view, through a camera.
    let cam = camera_at_origin(0.1);
    let vp = cam.view_proj(w, h);
    let q = [
        Vec3::new(-50.0, -50.0, -5.0),
        Vec3::new(50.0, -50.0, -5.0),
        Vec3::new(50.0, 50.0, -5.0),
        Vec3::new(-50.0, 50.0, -5.0),
    ];
    let tris = [([q[0], q[1], q[2]], 0), ([q[0], q[3], q[2]], 1)];
    assert!(counts(w, h, &vp, &tris).iter().all(|&n| n == 1));
    let mut t = RasterTarget::new(w, h);
    rasterize(&mut t, &vp, tris);
    assert_eq!(t.covered(), (w * h) as usize);
}

#[test]
fn behind_the_camera_draws_nothing() {
    let cam = camera_at_origin(0.1);
    let vp = cam.view_proj(64, 64);
    let mut t = RasterTarget::new(64, 64);
    let tris = [
        // Entirely behind.
        (
            [
                Vec3::new(-1.0, -1.0, 2.0),
                Vec3::new(1.0, -1.0, 2.0),
                Vec3::new(0.0, 1.0, 3.0),
            ],
            0,
        ),
        // Around the eye but between it and the near plane.
        (
            [
                Vec3::new(-1.0, -1.0, -0.05),
                Vec3::new(1.0, -1.0, -0.05),
                Vec3::new(0.0, 1.0, -0.05),
            ],
            1,
        ),
        // A large triangle behind: its unclipped projection would cover the screen.
        (
            [
                Vec3::new(-100.0, -100.0, 1.0),
                Vec3::new(100.0, -100.0, 1.0),
                Vec3::new(0.0, 100.0, 1.0),
            ],
            2,
        ),
    ];
    rasterize(&mut t, &vp, tris);
    assert_eq!(t.covered(), 0);
    assert!(t.depth.iter().all(|&d| d == 0.0));
}

#[test]
fn near_plane_crossing_draws_only_the_visible_part() {
    let (w, h) = (96, 64);
    let cam = camera_at_origin(0.5);
    let vp = cam.view_proj(w, h);
    // A floor-like triangle from behind the eye to far ahead, and one crossing the near plane sideways.
    let tris = [
        [
            Vec3::new(-3.0, -1.0, 4.0),
            Vec3::new(3.0, -1.0, 4.0),
            Vec3::new(0.0, -1.0, -20.0),
        ],
        [
            Vec3::new(-2.0, 0.5, -0.2),
            Vec3::new(2.0, -0.3, -6.0),
            Vec3::new(-1.0, -1.0, -3.0),
        ],
        [
            Vec3::new(0.3, 0.0, 0.3),
            Vec3::new(0.6, 0.4, -1.5),
            Vec3::new(0.1, -0.4, -0.9),
        ],
    ];
    for (tri, side_clip) in tris
        .iter()
        .flat_map(|t| [(*t, SideClip::Viewport), (*t, SideClip::GuardBand)])
    {
        let (covered, checked) = check_against_oracle(tri, &vp, w, h, 1.0 / 16.0, side_clip);
        assert!(
            covered > 100 && covered < (w * h) as usize,
            "covered {covered}"
        );
        assert!(
            checked > (w * h) as usize * 9 / 10,
            "only {checked} pixels unambiguous"
        );
    }
}

#[test]
fn random_triangles_match_ray_casting() {
    let (w, h) = (48, 40);
    let cam = Camera::look_at(
        DVec3::ZERO,
        DVec3::new(0.2, -0.1, -1.0),
        Vec3::Y,
        50f32.to_radians(),
        0.3,
    );
    let vp = cam.view_proj(w, h);
    let mut rng = Rng(12345);
    let mut total = 0;
    for _ in 0..300 {
        let c = Vec3::new(
            rng.range(-3.0, 3.0),
            rng.range(-3.0, 3.0),
            rng.range(-8.0, 1.0),
        );
        let s = rng.range(0.05, 4.0);
        let tri =
            [0, 1, 2].map(|_| c + Vec3::new(rng.range(-s, s), rng.range(-s, s), rng.range(-s, s)));
        let a = check_against_oracle(tri, &vp, w, h, 1.0 / 32.0, SideClip::Viewport).0;
        let b = check_against_oracle(tri, &vp, w, h, 1.0 / 32.0, SideClip::GuardBand).0;
        assert!(
            a.abs_diff(b) <= 2,
            "side clipping changed {a} covered pixels to {b}"
        );
        total += a;
    }
    assert!(
        total > 10_000,
        "the random triangles covered only {total} pixels"
    );
}

#[test]
fn depth_of_a_facing_plane_is_near_over_distance() {
    let (w, h) = (80, 60);
    for (near, d) in [(0.1f32, 5.0f32), (0.01, 1234.5), (1.0, 1.5)] {
        let cam = camera_at_origin(near);
        let vp = cam.view_proj(w, h);
        let s = d * 2.0;
        let q = [
            Vec3::new(-s, -s, -d),
            Vec3::new(s, -s, -d),
            Vec3::new(s, s, -d),
            Vec3::new(-s, s, -d),
        ];
        let mut t = RasterTarget::new(w, h);
        rasterize(
            &mut t,
            &vp,
            [([q[0], q[1], q[2]], 7), ([q[0], q[2], q[3]], 8)],
        );
        assert_eq!(t.covered(), (w * h) as usize);
        let want = near as f64 / d as f64;
        for &z in &t.depth {
            assert!(
                ((z as f64 - want) / want).abs() < 1e-6,
                "near {near} d {d}: depth {z} vs {want}"
            );
        }
    }
}

#[test]
fn closer_triangle_wins_and_ties_keep_the_first() {
    let (w, h) = (32, 32);
    let cam = camera_at_origin(0.1);
    let vp = cam.view_proj(w, h);
    let tri = |z: f32| {
        [
            Vec3::new(-z, -z, z),
            Vec3::new(z, -z, z),
            Vec3::new(0.0, z, z),
        ]
    };
    let (near_t, far_t) = ((tri(-2.0), 1), (tri(-3.0), 2));
    for order in [[near_t, far_t], [far_t, near_t]] {
        let mut t = RasterTarget::new(w, h);
        rasterize(&mut t, &vp, order);
        let mut both = 0;
        let mut f = vec![0u32; (w * h) as usize];
        for_each_fragment(w, h, &vp, SideClip::Viewport, [far_t], |fr| {
            f[(fr.y * w + fr.x) as usize] += 1
        });
        for_each_fragment(w, h, &vp, SideClip::Viewport, [near_t], |fr| {
            let i = (fr.y * w + fr.x) as usize;
            assert_eq!(t.id[i], 1, "pixel {},{}", fr.x, fr.y);
            assert_eq!(t.depth[i], fr.depth);
            both += f[i];
        });
        assert!(both > 50, "the triangles overlap on {both} pixels only");
    }
    // Same depth: the first drawn stays.
    for first in [3u32, 4] {
        let mut t = RasterTarget::new(w, h);
        rasterize(&mut t, &vp, [(tri(-2.0), first), (tri(-2.0), 7 - first)]);
        assert!(t.covered() > 50);
        assert!(t.id.iter().all(|&i| i == u32::MAX || i == first));
    }
}

#[test]
fn top_left_rule_through_the_public_api() {
    // Identity projection on 8x8: NDC = pixel / 4 - 1. Corners on the centres of pixels (2,2),
    // (6,2), (2,6): the top edge (y = 2) and left edge (x = 2) are in, the hypotenuse is out.
    let p = |x: f32, y: f32| Vec3::new((x + 0.5) / 4.0 - 1.0, (y + 0.5) / 4.0 - 1.0, 0.5);
    let (a, b, c, d) = (p(2.0, 2.0), p(6.0, 2.0), p(2.0, 6.0), p(6.0, 6.0));
    for (tri, inside) in [
        (
            [a, b, c],
            (|x, y| x >= 2 && y >= 2 && x + y < 8) as fn(u32, u32) -> bool,
        ),
        ([c, b, a], |x, y| x >= 2 && y >= 2 && x + y < 8),
        ([b, d, c], |x, y| x <= 5 && y <= 5 && x + y >= 8),
        ([c, d, b], |x, y| x <= 5 && y <= 5 && x + y >= 8),
    ] {
        let cnt = counts(8, 8, &Mat4::IDENTITY, &[(tri, 0)]);
        for y in 0..8 {
            for x in 0..8 {
                assert_eq!(
                    cnt[(y * 8 + x) as usize] == 1,
                    inside(x, y),
                    "pixel {x},{y} of {tri:?}"
                );
            }
        }
    }
}

#[test]
fn closed_mesh_is_crossed_an_even_number_of_times() {
    // Every ray from a camera outside a closed mesh enters and leaves it: with shared edges covered
    // exactly once, every pixel gets an even number of fragments (no crack, no double cover).
    let path = shared_assets().join("scanned/spot.obj");
    let opts = tobj::LoadOptions {
        triangulate: true,
        single_index: false,
        ..Default::default()
    };
    let (models, _) =
        tobj::load_obj(&path, &opts).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let mut tris = Vec::new();
    for m in &models {
        let pos = &m.mesh.positions;
        let v = |i: u32| {
            Vec3::new(
                pos[i as usize * 3],
                pos[i as usize * 3 + 1],
                pos[i as usize * 3 + 2],
            )
        };
        for t in m.mesh.indices.chunks_exact(3) {
            tris.push([v(t[0]), v(t[1]), v(t[2])]);
        }
    }
    assert_eq!(tris.len(), 5856);
    let (w, h) = (160, 120);
    for eye in [
        DVec3::new(2.0, 1.0, 2.5),
        DVec3::new(-0.3, -2.5, 0.4),
        DVec3::new(0.0, 0.2, -3.0),
    ] {
        let cam = Camera::look_at(
            eye,
            DVec3::new(0.0, 0.0, 0.3),
            Vec3::Y,
            40f32.to_radians(),
            0.05,
        );
        let vp = cam.view_proj(w, h);
        let rel = cam.relative_model(&DMat4::IDENTITY);
        let moved: Vec<([Vec3; 3], u32)> = tris
            .iter()
            .enumerate()
            .map(|(i, t)| (t.map(|p| rel.transform_point3(p)), i as u32))
            .collect();
        let cnt = counts(w, h, &vp, &moved);
        let covered = cnt.iter().filter(|&&n| n > 0).count();
        assert!(covered > 1000, "spot covers {covered} pixels");
        let odd: Vec<usize> = (0..cnt.len()).filter(|&i| cnt[i] % 2 == 1).collect();
        assert!(
            odd.is_empty(),
            "eye {eye}: {} pixels with an odd count, e.g. {:?}",
            odd.len(),
            &odd[..odd.len().min(5)]
        );
    }
}

#[test]
fn hundred_thousand_triangles_are_fast() {
    let (w, h) = (256, 256);
    let cam = camera_at_origin(0.1);
    let vp = cam.view_proj(w, h);
    let mut rng = Rng(99);
    let tris: Vec<([Vec3; 3], u32)> = (0..100_000u32)
        .map(|i| {
            let c = Vec3::new(
                rng.range(-2.0, 2.0),
                rng.range(-2.0, 2.0),
                rng.range(-6.0, -3.0),
            );
            let s = 0.03;
            (
                [0, 1, 2]
                    .map(|_| c + Vec3::new(rng.range(-s, s), rng.range(-s, s), rng.range(-s, s))),
                i,
            )
        })
        .collect();
    let start = Instant::now();
    let mut t = RasterTarget::new(w, h);
    rasterize(&mut t, &vp, tris.iter().copied());
    let secs = start.elapsed().as_secs_f64();
    eprintln!(
        "100k triangles at 256x256: {:.3} s, {} pixels covered",
        secs,
        t.covered()
    );
    assert!(t.covered() > (w * h) as usize / 2);
    // Generous for a loaded 2-core CI machine; typically well under a tenth of this.
    assert!(secs < 3.0, "took {secs} s");
}
