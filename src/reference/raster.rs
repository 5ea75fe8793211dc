//! The CPU reference rasterizer: what Vulkan's rasterizer does (lavapipe, NVIDIA), on the CPU.
//!
//! Pipeline, per triangle (positions camera-relative, see [`crate::camera`]):
//! 1. Clip space: `c = view_proj * (p, 1)` in f32, as a vertex shader computes it.
//! 2. Trivial reject when all three vertices are outside one plane of the view volume.
//! 3. Clipping (Sutherland-Hodgman) against the depth planes of Vulkan's view volume,
//!    `z <= w` (the near plane; with vgeo's projection `z` is the constant `near`, so this is
//!    `w >= near`) and `z >= 0`, and against its sides as [`SideClip`] says; then the polygon is
//!    fanned from its first vertex. Intersection points are always computed from the inside vertex
//!    towards the outside one, so an edge shared by two triangles is clipped to the same point in both.
//! 4. Perspective divide and viewport transform in f32:
//!    `x_f = ndc.x * W/2 + W/2`, `y_f = ndc.y * H/2 + H/2` (Vulkan's form; NDC +y is down).
//! 5. Snapping to fixed point with [`SUBPIXEL_BITS`] sub-pixel bits, rounding to nearest (ties to
//!    even, as `lrint` does), in i64.
//! 6. Coverage at pixel centres `(x + 0.5, y + 0.5)` with exact integer edge functions and the
//!    top-left rule (below); zero-area triangles after snapping are skipped; both windings drawn.
//! 7. Depth: `ndc.z` of the vertices interpolated linearly in screen space with the barycentrics of
//!    the snapped positions (`z/w` is affine in screen space), then rounded to f32.
//! 8. Depth test `GREATER` (reverse-Z: nearer is larger); an equal depth does not replace, so the
//!    first triangle drawn wins ties.
//!
//! **Top-left rule.** In framebuffer coordinates (y down), a triangle is first put in a fixed
//! orientation: vertices `a, b, c` such that `E_ab(c) > 0`, where
//! `E_ab(p) = (b.x - a.x) (p.y - a.y) - (b.y - a.y) (p.x - a.x)`. Then a point is inside iff all three
//! edge functions are `>= 0`. An edge `a -> b` of that oriented triangle is
//! - a *top* edge iff it is horizontal and goes right (`dy == 0 && dx > 0`): the third vertex is below,
//! - a *left* edge iff it goes up (`dy < 0`): the interior is on its right.
//!
//! A centre exactly on an edge (`E == 0`) is covered only if that edge is top or left. Two triangles
//! sharing an edge traverse it in opposite directions, so exactly one of them owns it: shared edges
//! are covered exactly once, whatever the windings.
//!
//! **Checked against lavapipe** (Mesa 25.0.7, LLVM 15, through a throwaway Vulkan program drawing the same
//! triangles with an `R32_UINT` id target and a `D32` depth test `GREATER`): with
//! [`SideClip::Viewport`] the id images were identical on jittered grids whose vertices sit exactly on
//! pixel centres or on 1/256-pixel positions (every pixel owned by exactly one triangle, so any
//! fill-rule difference shows), and differed in 1 pixel of ~40k on perspective views of a mesh
//! (f32 rounding of `view_proj * p` on the two sides). With [`SideClip::GuardBand`] a few pixels in
//! the screen's outer rows and columns differed on exact ties, because lavapipe clips at the viewport.
//! Depths of the same triangle differed by up to 6e-4 relative on the mesh views and 6e-3 on steep
//! random triangles (lavapipe sets up its own f32 depth plane): compare depths with a tolerance
//! that grows with the depth gradient, not bit for bit.

use glam::{Mat4, Vec3, Vec4};

use crate::mesh::Mesh;
use crate::shared::SUBPIXEL_BITS;

/// One pixel in fixed point.
const ONE: i64 = 1 << SUBPIXEL_BITS;
/// Half a pixel in fixed point: pixel centres are at `x * ONE + HALF`.
const HALF: i64 = ONE / 2;
/// Largest width or height of a target; keeps every fixed-point product within i64.
pub const MAX_TARGET_SIZE: u32 = 1 << 16;
/// Extent of the guard band in pixels from the viewport's centre (see the module docs).
const GUARD_BAND_PIXELS: f32 = (1 << 20) as f32;

/// How triangles are clipped against the sides (`-w <= x, y <= w`) of the view volume. Only pixels
/// exactly on an edge of a triangle that crosses the screen's border can differ between the two.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SideClip {
    /// At the viewport's edges, as the Vulkan spec's clip volume says; lavapipe does this. The
    /// clipped polygon's new vertices are snapped like the others, which can move an edge by a
    /// fraction of a sub-pixel step where it is cut.
    #[default]
    Viewport,
    /// Only at a guard band about a million pixels out (which keeps the fixed-point math in range):
    /// what GPUs with a guard band do (NVIDIA) and what a compute rasterizer that merely bounds its
    /// loops to the screen does.
    GuardBand,
}

/// A depth and id buffer for the reference rasterizer.
#[derive(Clone, Debug, PartialEq)]
pub struct RasterTarget {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// Row-major depth per pixel; `0.0` = empty (reverse-Z: far away is 0).
    pub depth: Vec<f32>,
    /// Row-major id per pixel: `u32::MAX` = empty, else the id of the triangle that wrote it.
    pub id: Vec<u32>,
}

impl RasterTarget {
    /// An empty target. Panics if a side is over [`MAX_TARGET_SIZE`].
    pub fn new(width: u32, height: u32) -> Self {
        assert!(
            width <= MAX_TARGET_SIZE && height <= MAX_TARGET_SIZE,
            "reference raster target {width}x{height} is larger than {MAX_TARGET_SIZE}"
        );
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            depth: vec![0.0; n],
            id: vec![u32::MAX; n],
        }
    }

    /// Number of pixels written by some triangle.
    pub fn covered(&self) -> usize {
        self.id.iter().filter(|&&i| i != u32::MAX).count()
    }

    /// Index of pixel `(x, y)` in `depth` and `id`.
    pub fn index(&self, x: u32, y: u32) -> usize {
        y as usize * self.width as usize + x as usize
    }
}

/// One covered pixel of one triangle, before the depth test.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fragment {
    /// Pixel column, from the left.
    pub x: u32,
    /// Pixel row, from the top.
    pub y: u32,
    /// Interpolated `ndc.z` (reverse-Z: 1 at the near plane, towards 0 far away).
    pub depth: f32,
    /// The id given with the triangle.
    pub id: u32,
}

/// Rasterizes triangles given in camera-relative space (already transformed by the model matrix)
/// into `target`, with depth test `GREATER` (first drawn wins ties) and [`SideClip::Viewport`].
/// See the module docs.
pub fn rasterize(
    target: &mut RasterTarget,
    view_proj: &Mat4,
    tris: impl IntoIterator<Item = ([Vec3; 3], u32)>,
) {
    rasterize_with(target, view_proj, SideClip::Viewport, tris);
}

/// [`rasterize`] with a choice of side clipping.
pub fn rasterize_with(
    target: &mut RasterTarget,
    view_proj: &Mat4,
    side_clip: SideClip,
    tris: impl IntoIterator<Item = ([Vec3; 3], u32)>,
) {
    let (width, height) = (target.width, target.height);
    let (depth, id) = (&mut target.depth, &mut target.id);
    for_each_fragment(width, height, view_proj, side_clip, tris, |f| {
        let i = f.y as usize * width as usize + f.x as usize;
        if f.depth > depth[i] {
            depth[i] = f.depth;
            id[i] = f.id;
        }
    });
}

/// Calls `visit` for every pixel covered by every triangle, in draw order, with no depth test
/// (for overdraw counts and custom tests). Same rules as [`rasterize`].
/// Panics if a side is over [`MAX_TARGET_SIZE`].
pub fn for_each_fragment(
    width: u32,
    height: u32,
    view_proj: &Mat4,
    side_clip: SideClip,
    tris: impl IntoIterator<Item = ([Vec3; 3], u32)>,
    mut visit: impl FnMut(Fragment),
) {
    assert!(
        width <= MAX_TARGET_SIZE && height <= MAX_TARGET_SIZE,
        "target too large"
    );
    if width == 0 || height == 0 {
        return;
    }
    let vp = Viewport::new(width, height, side_clip);
    for (p, id) in tris {
        let clip = p.map(|v| *view_proj * v.extend(1.0));
        rasterize_clip(&vp, clip, &mut |x, y, depth| {
            visit(Fragment { x, y, depth, id })
        });
    }
}

/// The triangles of `mesh` in camera-relative space, for [`rasterize`]: positions transformed by
/// `relative_model` (see [`crate::camera::Camera::relative_model`]), ids `first_id + triangle index`.
pub fn mesh_triangles<'a>(
    mesh: &'a Mesh,
    relative_model: &Mat4,
    first_id: u32,
) -> impl Iterator<Item = ([Vec3; 3], u32)> + 'a {
    let m = *relative_model;
    mesh.indices
        .chunks_exact(3)
        .enumerate()
        .map(move |(t, tri)| {
            let p = |k: usize| m.transform_point3(Vec3::from(mesh.positions[tri[k] as usize]));
            ([p(0), p(1), p(2)], first_id.wrapping_add(t as u32))
        })
}

/// Viewport constants.
struct Viewport {
    width: u32,
    height: u32,
    half_w: f32,
    half_h: f32,
    /// Side clip planes' half-extents in NDC units (1 = the viewport's edges).
    guard_x: f32,
    guard_y: f32,
}

impl Viewport {
    fn new(width: u32, height: u32, side_clip: SideClip) -> Self {
        let half_w = width as f32 * 0.5;
        let half_h = height as f32 * 0.5;
        let (guard_x, guard_y) = match side_clip {
            SideClip::Viewport => (1.0, 1.0),
            SideClip::GuardBand => (
                (GUARD_BAND_PIXELS / half_w).max(1.0),
                (GUARD_BAND_PIXELS / half_h).max(1.0),
            ),
        };
        Self {
            width,
            height,
            half_w,
            half_h,
            guard_x,
            guard_y,
        }
    }
}

/// A convex polygon in clip space (a triangle clipped by up to 6 planes has at most 9 vertices).
struct Poly {
    v: [Vec4; 12],
    n: usize,
}

impl Poly {
    fn push(&mut self, p: Vec4) {
        self.v[self.n] = p;
        self.n += 1;
    }

    /// Keeps the part where `plane . v >= 0` (Sutherland-Hodgman).
    fn clip(&self, plane: Vec4) -> Poly {
        let mut out = Poly {
            v: [Vec4::ZERO; 12],
            n: 0,
        };
        for i in 0..self.n {
            let a = self.v[i];
            let b = self.v[(i + 1) % self.n];
            let (da, db) = (plane.dot(a), plane.dot(b));
            if da >= 0.0 {
                out.push(a);
            }
            if (da >= 0.0) != (db >= 0.0) {
                // Always from the inside vertex, so that a shared edge gives the same point.
                let (pin, din, pout, dout) = if da >= 0.0 {
                    (a, da, b, db)
                } else {
                    (b, db, a, da)
                };
                let t = din / (din - dout);
                out.push(pin + (pout - pin) * t);
            }
        }
        out
    }
}

/// Clips, projects, snaps and rasterizes one clip-space triangle.
fn rasterize_clip(vp: &Viewport, c: [Vec4; 3], visit: &mut impl FnMut(u32, u32, f32)) {
    if !c.iter().all(|v| v.is_finite()) {
        return;
    }
    let (gx, gy) = (vp.guard_x, vp.guard_y);
    // Planes as `plane . v >= 0`: near (z <= w), far (z >= 0), then the sides.
    let depth_planes = [
        Vec4::new(0.0, 0.0, -1.0, 1.0),
        Vec4::new(0.0, 0.0, 1.0, 0.0),
    ];
    let guard_planes = [
        Vec4::new(-1.0, 0.0, 0.0, gx),
        Vec4::new(1.0, 0.0, 0.0, gx),
        Vec4::new(0.0, -1.0, 0.0, gy),
        Vec4::new(0.0, 1.0, 0.0, gy),
    ];
    // Trivial reject: all outside one plane of the view volume (sides at the screen's edges).
    let reject_planes = [
        depth_planes[0],
        depth_planes[1],
        Vec4::new(-1.0, 0.0, 0.0, 1.0),
        Vec4::new(1.0, 0.0, 0.0, 1.0),
        Vec4::new(0.0, -1.0, 0.0, 1.0),
        Vec4::new(0.0, 1.0, 0.0, 1.0),
    ];
    if reject_planes
        .iter()
        .any(|pl| c.iter().all(|v| pl.dot(*v) < 0.0))
    {
        return;
    }
    let mut poly = Poly {
        v: [Vec4::ZERO; 12],
        n: 3,
    };
    poly.v[..3].copy_from_slice(&c);
    for plane in depth_planes.iter().chain(&guard_planes) {
        if poly.v[..poly.n].iter().any(|v| plane.dot(*v) < 0.0) {
            poly = poly.clip(*plane);
            if poly.n < 3 {
                return;
            }
        }
    }
    // Project and snap every polygon vertex once, then fan.
    let mut fixed = [[0i64; 2]; 12];
    let mut depth = [0f32; 12];
    for i in 0..poly.n {
        let v = poly.v[i];
        if v.w <= 0.0 {
            return;
        }
        let ndc = v.truncate() / v.w;
        let xf = ndc.x * vp.half_w + vp.half_w;
        let yf = ndc.y * vp.half_h + vp.half_h;
        fixed[i] = [snap(xf), snap(yf)];
        depth[i] = ndc.z;
    }
    for i in 1..poly.n - 1 {
        raster_fixed(
            [fixed[0], fixed[i], fixed[i + 1]],
            [depth[0], depth[i], depth[i + 1]],
            vp.width,
            vp.height,
            visit,
        );
    }
}

/// A viewport coordinate in fixed point, rounded to nearest (ties to even).
fn snap(v: f32) -> i64 {
    (v as f64 * ONE as f64).round_ties_even() as i64
}

/// `E_ab(p)`: positive when `p` is on the interior side of `a -> b` for a positively oriented triangle.
fn edge(a: [i64; 2], b: [i64; 2], p: [i64; 2]) -> i64 {
    (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0])
}

/// Floor division by a positive divisor.
fn floor_div(a: i64, b: i64) -> i64 {
    a.div_euclid(b)
}

/// Rasterizes a triangle given in snapped fixed-point viewport coordinates (any winding), calling
/// `visit(x, y, depth)` for each covered pixel inside `[0, width) x [0, height)`.
pub(crate) fn raster_fixed(
    mut v: [[i64; 2]; 3],
    mut z: [f32; 3],
    width: u32,
    height: u32,
    visit: &mut impl FnMut(u32, u32, f32),
) {
    let mut area = edge(v[0], v[1], v[2]);
    if area == 0 {
        return;
    }
    if area < 0 {
        v.swap(1, 2);
        z.swap(1, 2);
        area = -area;
    }
    let min_x = v[0][0].min(v[1][0]).min(v[2][0]);
    let max_x = v[0][0].max(v[1][0]).max(v[2][0]);
    let min_y = v[0][1].min(v[1][1]).min(v[2][1]);
    let max_y = v[0][1].max(v[1][1]).max(v[2][1]);
    // Pixels whose centre lies in the box, clamped to the screen.
    let x0 = (floor_div(min_x - HALF + ONE - 1, ONE)).max(0);
    let x1 = (floor_div(max_x - HALF, ONE)).min(width as i64 - 1);
    let y0 = (floor_div(min_y - HALF + ONE - 1, ONE)).max(0);
    let y1 = (floor_div(max_y - HALF, ONE)).min(height as i64 - 1);
    if x0 > x1 || y0 > y1 {
        return;
    }
    let start = [x0 * ONE + HALF, y0 * ONE + HALF];
    // Edge k is opposite vertex k, so its value is vertex k's barycentric weight times `area`.
    let mut row = [0i64; 3];
    let mut step_x = [0i64; 3];
    let mut step_y = [0i64; 3];
    let mut bias = [0i64; 3];
    for k in 0..3 {
        let a = v[(k + 1) % 3];
        let b = v[(k + 2) % 3];
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let top_left = (dy == 0 && dx > 0) || dy < 0;
        bias[k] = if top_left { 0 } else { -1 };
        row[k] = edge(a, b, start);
        step_x[k] = -dy * ONE;
        step_y[k] = dx * ONE;
    }
    let inv_area = 1.0 / area as f64;
    let zf = z.map(f64::from);
    for y in y0..=y1 {
        let mut e = row;
        for x in x0..=x1 {
            if ((e[0] + bias[0]) | (e[1] + bias[1]) | (e[2] + bias[2])) >= 0 {
                let d =
                    (e[0] as f64 * zf[0] + e[1] as f64 * zf[1] + e[2] as f64 * zf[2]) * inv_area;
                visit(x as u32, y as u32, d as f32);
            }
            for k in 0..3 {
                e[k] += step_x[k];
            }
        }
        for k in 0..3 {
            row[k] += step_y[k];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// xorshift64* for test inputs.
    struct Rng(u64);
    impl Rng {
        fn next(&mut self) -> u64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            self.0.wrapping_mul(0x2545_f491_4f6c_dd1d)
        }
        fn range(&mut self, lo: i64, hi: i64) -> i64 {
            lo + (self.next() % (hi - lo) as u64) as i64
        }
    }

    /// Coverage count per pixel of a list of fixed-point triangles.
    fn counts(tris: &[[[i64; 2]; 3]], w: u32, h: u32) -> Vec<u32> {
        let mut c = vec![0u32; (w * h) as usize];
        for t in tris {
            raster_fixed(*t, [0.5; 3], w, h, &mut |x, y, _| {
                c[(y * w + x) as usize] += 1
            });
        }
        c
    }

    /// Pixel centre `(x + 0.5, y + 0.5)` in fixed point.
    fn centre(x: i64, y: i64) -> [i64; 2] {
        [x * ONE + HALF, y * ONE + HALF]
    }

    #[test]
    fn shared_edges_cover_each_pixel_once() {
        let (w, h) = (24u32, 24u32);
        let mut rng = Rng(0x9e37_79b9_7f4a_7c15);
        let mut shared_centres = 0;
        for case in 0..3000 {
            // Edge endpoints: on pixel centres for half the cases (centres along the edge lie on it
            // exactly), anywhere in sub-pixel units otherwise; some axis-aligned edges.
            let pick = |rng: &mut Rng| -> [i64; 2] {
                if case % 2 == 0 {
                    centre(rng.range(-4, w as i64 + 4), rng.range(-4, h as i64 + 4))
                } else {
                    [
                        rng.range(-600, w as i64 * ONE + 600),
                        rng.range(-600, h as i64 * ONE + 600),
                    ]
                }
            };
            let a = pick(&mut rng);
            let mut b = pick(&mut rng);
            match case % 5 {
                0 => b[0] = a[0],
                1 => b[1] = a[1],
                _ => {}
            }
            // Third vertices on either side of the line a-b.
            let (mut c, mut d) = (pick(&mut rng), pick(&mut rng));
            let mut tries = 0;
            while !(edge(a, b, c) > 0 && edge(a, b, d) < 0) && tries < 100 {
                c = pick(&mut rng);
                d = pick(&mut rng);
                tries += 1;
            }
            if edge(a, b, c) <= 0 || edge(a, b, d) >= 0 {
                continue;
            }
            // Random windings for both triangles.
            let t1 = if rng.next() & 1 == 0 {
                [a, b, c]
            } else {
                [b, a, c]
            };
            let t2 = if rng.next() & 1 == 0 {
                [a, b, d]
            } else {
                [d, b, a]
            };
            let cnt = counts(&[t1, t2], w, h);
            assert!(
                cnt.iter().all(|&n| n <= 1),
                "case {case}: pixel covered twice: {t1:?} {t2:?}"
            );
            // Every centre strictly inside the union quad or on the shared edge's interior is covered.
            for y in 0..h as i64 {
                for x in 0..w as i64 {
                    let p = centre(x, y);
                    let (eab, ebc, eca) = (edge(a, b, p), edge(b, c, p), edge(c, a, p));
                    let (ebd, eda) = (edge(b, d, p), edge(d, a, p));
                    let in1 = eab > 0 && ebc > 0 && eca > 0;
                    let in2 = eab < 0 && ebd < 0 && eda < 0;
                    let on_shared = eab == 0 && ebc > 0 && eca > 0 && ebd < 0 && eda < 0;
                    if on_shared {
                        shared_centres += 1;
                    }
                    if in1 || in2 || on_shared {
                        assert_eq!(
                            cnt[(y * w as i64 + x) as usize],
                            1,
                            "case {case} pixel {x},{y}"
                        );
                    }
                }
            }
        }
        // The test exercised exact ties on the shared edge.
        assert!(
            shared_centres > 500,
            "only {shared_centres} centres on shared edges"
        );
    }

    #[test]
    fn fan_around_a_point_covers_once() {
        // A closed fan of triangles around a pixel centre: no gap, no double cover inside.
        let (w, h) = (32u32, 32u32);
        let c = centre(16, 16);
        let ring: Vec<[i64; 2]> = (0..16)
            .map(|i| {
                let a = i as f64 / 16.0 * std::f64::consts::TAU;
                [
                    c[0] + (a.cos() * 14.0 * ONE as f64) as i64,
                    c[1] + (a.sin() * 14.0 * ONE as f64) as i64,
                ]
            })
            .collect();
        let tris: Vec<_> = (0..16)
            .map(|i| {
                if i % 2 == 0 {
                    [c, ring[i], ring[(i + 1) % 16]]
                } else {
                    [ring[(i + 1) % 16], ring[i], c]
                }
            })
            .collect();
        let cnt = counts(&tris, w, h);
        assert!(cnt.iter().all(|&n| n <= 1));
        for dy in -9..=9 {
            for dx in -9..=9 {
                assert_eq!(
                    cnt[((16 + dy) * 32 + 16 + dx) as usize],
                    1,
                    "pixel {dx},{dy} from centre"
                );
            }
        }
    }

    #[test]
    fn top_left_rule_on_a_right_triangle() {
        // Corners on pixel centres (2,2), (6,2), (2,6): the top edge y=2 and the left edge x=2 are in,
        // the hypotenuse x+y=8 is out; the complementary triangle takes the hypotenuse.
        let (a, b, c, d) = (centre(2, 2), centre(6, 2), centre(2, 6), centre(6, 6));
        for t in [[a, b, c], [a, c, b]] {
            let cnt = counts(&[t], 8, 8);
            for y in 0..8 {
                for x in 0..8 {
                    let want = x >= 2 && y >= 2 && x + y < 8;
                    assert_eq!(cnt[(y * 8 + x) as usize] == 1, want, "pixel {x},{y}");
                }
            }
        }
        for t in [[b, d, c], [b, c, d]] {
            let cnt = counts(&[t], 8, 8);
            for y in 0..8 {
                for x in 0..8 {
                    let want = x <= 5 && y <= 5 && x + y >= 8;
                    assert_eq!(cnt[(y * 8 + x) as usize] == 1, want, "pixel {x},{y}");
                }
            }
        }
    }

    #[test]
    fn zero_area_after_snapping_is_skipped() {
        let a = centre(1, 1);
        let cnt = counts(
            &[[a, [a[0] + 1000, a[1] + 1000], [a[0] + 2000, a[1] + 2000]]],
            8,
            8,
        );
        assert!(cnt.iter().all(|&n| n == 0));
    }

    #[test]
    fn side_clipping_keeps_shared_edges_exact() {
        // A huge quad (far beyond the guard band) split along a diagonal: every pixel once, in both
        // modes; and quads crossing the screen's edges, split either way.
        let vp = Mat4::IDENTITY;
        let big = 1.0e5;
        let mut quads = vec![[
            Vec3::new(-big, -big * 0.7, 0.5),
            Vec3::new(big * 0.9, -big, 0.5),
            Vec3::new(big, big, 0.5),
            Vec3::new(-big * 0.8, big, 0.5),
        ]];
        let mut rng = Rng(5);
        let mut r =
            |lo: f32, hi: f32| lo + (hi - lo) * (rng.next() >> 40) as f32 / (1u64 << 24) as f32;
        for _ in 0..200 {
            // Convex: four points on an ellipse around a point on screen, one per quarter turn.
            let (cx, cy, rx, ry) = (r(-0.9, 0.9), r(-0.9, 0.9), r(0.2, 2.0), r(0.2, 2.0));
            let corner = |k: f32, a: f32| {
                let t = (k + a) * std::f32::consts::FRAC_PI_2;
                Vec3::new(cx + rx * t.cos(), cy + ry * t.sin(), 0.5)
            };
            quads.push([
                corner(0.0, r(0.0, 1.0)),
                corner(1.0, r(0.0, 1.0)),
                corner(2.0, r(0.0, 1.0)),
                corner(3.0, r(0.0, 1.0)),
            ]);
        }
        for side_clip in [SideClip::Viewport, SideClip::GuardBand] {
            for (n, q) in quads.iter().enumerate() {
                let (t1, t2) = if n % 2 == 0 {
                    ([q[0], q[1], q[2]], [q[0], q[3], q[2]])
                } else {
                    ([q[1], q[2], q[3]], [q[3], q[0], q[1]])
                };
                let mut cnt = vec![0u32; 64 * 48];
                for_each_fragment(64, 48, &vp, side_clip, [(t1, 0), (t2, 1)], |f| {
                    cnt[(f.y * 64 + f.x) as usize] += 1
                });
                let bad: Vec<(usize, usize)> = (0..cnt.len())
                    .filter(|&i| cnt[i] > 1)
                    .map(|i| (i % 64, i / 64))
                    .collect();
                assert!(
                    bad.is_empty(),
                    "{side_clip:?} quad {n}: double cover at {bad:?}, {q:?}"
                );
                // Centres inside the quad by more than 1/16 pixel are covered.
                for (i, &c) in cnt.iter().enumerate() {
                    let (px, py) = ((i % 64) as f32 + 0.5, (i / 64) as f32 + 0.5);
                    let p = [px / 32.0 - 1.0, py / 24.0 - 1.0];
                    let inside = (0..4).all(|k| {
                        let (a, b) = (q[k], q[(k + 1) % 4]);
                        let (ex, ey) = ((b.x - a.x) * 32.0, (b.y - a.y) * 24.0);
                        let cross = ex * (p[1] - a.y) * 24.0 - ey * (p[0] - a.x) * 32.0;
                        cross > (ex * ex + ey * ey).sqrt() / 16.0
                    });
                    if inside {
                        assert_eq!(c, 1, "{side_clip:?} quad {n}: hole at {px},{py}");
                    }
                }
                if n == 0 {
                    assert!(
                        cnt.iter().all(|&c| c == 1),
                        "{side_clip:?}: hole in the huge quad"
                    );
                }
            }
        }
    }
}
