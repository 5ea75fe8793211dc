//! Polygon triangulation: ear clipping on the polygon's best-fit plane.
//!
//! A fan is wrong for concave polygons (triangles outside the polygon, overlaps), so every face with
//! more than three corners goes through [`triangulate`]: convex faces take a fan (fast path), others
//! are ear-clipped in 2D after projecting onto the plane of the Newell normal. Weakly simple
//! polygons such as "keyhole" faces (a hole joined to the outline by a doubled bridge edge) work:
//! corners that coincide with an ear's corner are not counted as inside it, and an ear's diagonal
//! must not cross any remaining edge. Always emits exactly `n - 2` triangles with the polygon's
//! winding; if no proper ear exists (self-intersecting input), the most convex corner is clipped.
//! The work is bounded (see [`ear_clip_budget`]): past it (a self-intersecting polygon, whose
//! forced clips cost O(n^3) in all, or a concave one of many thousands of corners) the remaining
//! corners are fanned, so that a hostile file cannot make the import take hours.

/// Least and most ear-clipping work per corner (see [`ear_clip_budget`]).
const EAR_CLIP_WORK_PER_CORNER: (usize, usize) = (2048, 8192);

/// Ear-clipping work (corners visited by ear tests) allowed for an n-gon: `n * 4n`, between
/// 2,048 and 8,192 per corner. A simple polygon needs about `1.5 n^2` (a concave spiral band of
/// 4,000 corners: 24 M), so simple polygons of up to about 5,000 corners are clipped in full; a
/// self-intersecting one (a 2,000-corner star took 9 s before the bound) stops there, at a cost
/// linear in the file's size.
pub fn ear_clip_budget(n: usize) -> usize {
    let (least, most) = EAR_CLIP_WORK_PER_CORNER;
    n.saturating_mul(n.saturating_mul(4).clamp(least, most))
}

/// Triangulates polygon `poly` (indices into `positions`), appending `n - 2` triangles to `out`.
/// Fewer than three corners append nothing. Indices out of range of `positions` are treated as
/// being at the origin (callers validate indices first). Returns `false` when the ear clipping ran
/// out of work ([`ear_clip_budget`]) and fanned the corners left (callers warn).
pub fn triangulate(positions: &[[f32; 3]], poly: &[u32], out: &mut Vec<[u32; 3]>) -> bool {
    let n = poly.len();
    if n < 3 {
        return true;
    }
    if n == 3 {
        out.push([poly[0], poly[1], poly[2]]);
        return true;
    }
    let pos = |i: u32| -> [f64; 3] {
        let p = positions.get(i as usize).copied().unwrap_or([0.0; 3]);
        [p[0] as f64, p[1] as f64, p[2] as f64]
    };
    let p3: Vec<[f64; 3]> = poly.iter().map(|&i| pos(i)).collect();
    let normal = newell_normal(&p3);
    let len = (normal[0] * normal[0] + normal[1] * normal[1] + normal[2] * normal[2]).sqrt();
    if !(len.is_finite() && len > 0.0) {
        // Zero-area polygon: any triangulation is degenerate; keep the count right with a fan.
        fan(poly, out);
        return true;
    }
    let nz = [normal[0] / len, normal[1] / len, normal[2] / len];
    let (u, v) = plane_basis(nz);
    // Projected onto (u, v) with (u, v, n) right-handed, the polygon is counter-clockwise.
    let p2: Vec<[f64; 2]> = p3.iter().map(|p| [dot(*p, u), dot(*p, v)]).collect();
    if is_convex(&p2) {
        fan(poly, out);
        return true;
    }
    ear_clip(&p2, poly, out)
}

/// The warning for `faces` polygons that [`triangulate`] fanned in part, if any.
pub fn warn_fanned(faces: usize, path: &std::path::Path, warnings: &mut Vec<String>) {
    if faces > 0 {
        warnings.push(format!(
            "{}: {faces} polygon(s) too costly to ear-clip (self-intersecting, or concave with \
             thousands of corners) were triangulated in part as a fan",
            path.display()
        ));
    }
}

/// Stores triangulated faces as the mesh's triangles (material 0; the vector becomes the index
/// list without a copy) and warns about the `skipped` faces that had fewer than 3 vertices (OFF
/// and PLY polygon lists).
pub fn set_triangles(
    mesh: &mut super::Mesh,
    tris: Vec<[u32; 3]>,
    skipped: usize,
    path: &std::path::Path,
    warnings: &mut Vec<String>,
) {
    if skipped > 0 {
        warnings.push(format!(
            "{}: skipped {skipped} faces with fewer than 3 vertices",
            path.display()
        ));
    }
    mesh.material_ids = vec![0; tris.len()];
    mesh.indices = tris.into_flattened();
}

/// Twice the signed area of polygon `p` (2D shoelace): positive when counter-clockwise.
pub fn signed_area2(p: &[[f64; 2]]) -> f64 {
    let n = p.len();
    (0..n)
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % n]);
            a[0] * b[1] - b[0] * a[1]
        })
        .sum()
}

/// Newell's normal of a 3D polygon: its length is twice the (vector) area.
pub fn newell_normal(p: &[[f64; 3]]) -> [f64; 3] {
    let n = p.len();
    let mut r = [0.0; 3];
    for i in 0..n {
        let (a, b) = (p[i], p[(i + 1) % n]);
        r[0] += (a[1] - b[1]) * (a[2] + b[2]);
        r[1] += (a[2] - b[2]) * (a[0] + b[0]);
        r[2] += (a[0] - b[0]) * (a[1] + b[1]);
    }
    r
}

fn fan(poly: &[u32], out: &mut Vec<[u32; 3]>) {
    for k in 1..poly.len() - 1 {
        out.push([poly[0], poly[k], poly[k + 1]]);
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross3(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Orthonormal `(u, v)` with `u x v = n`.
fn plane_basis(n: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let helper = if n[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = cross3(helper, n);
    let l = dot(u, u).sqrt();
    let u = [u[0] / l, u[1] / l, u[2] / l];
    let v = cross3(n, u);
    (u, v)
}

/// Twice the signed area of triangle `abc` (positive: counter-clockwise).
fn orient(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Counter-clockwise, every turn left (or straight), and turning once around in total.
fn is_convex(p: &[[f64; 2]]) -> bool {
    let n = p.len();
    let mut total_angle = 0.0;
    for i in 0..n {
        let (a, b, c) = (p[(i + n - 1) % n], p[i], p[(i + 1) % n]);
        if orient(a, b, c) < 0.0 {
            return false;
        }
        let d1 = [b[0] - a[0], b[1] - a[1]];
        let d2 = [c[0] - b[0], c[1] - b[1]];
        total_angle += (d1[0] * d2[1] - d1[1] * d2[0]).atan2(d1[0] * d2[0] + d1[1] * d2[1]);
    }
    // A convex polygon turns by exactly 2*pi; a star polygon with all left turns by more.
    (total_angle - std::f64::consts::TAU).abs() < 1e-6
}

/// Whether segments `ab` and `cd` cross at a point interior to both (touching does not count).
fn segments_cross(a: [f64; 2], b: [f64; 2], c: [f64; 2], d: [f64; 2]) -> bool {
    let (d1, d2) = (orient(a, b, c), orient(a, b, d));
    let (d3, d4) = (orient(c, d, a), orient(c, d, b));
    ((d1 > 0.0 && d2 < 0.0) || (d1 < 0.0 && d2 > 0.0))
        && ((d3 > 0.0 && d4 < 0.0) || (d3 < 0.0 && d4 > 0.0))
}

/// Ear clipping over a doubly linked ring of the corners of a counter-clockwise polygon; `false`
/// if it ran out of work and fanned the corners left.
fn ear_clip(p: &[[f64; 2]], poly: &[u32], out: &mut Vec<[u32; 3]>) -> bool {
    let n = p.len();
    let budget = ear_clip_budget(n);
    let mut work = 0usize;
    let mut prev: Vec<usize> = (0..n).map(|i| (i + n - 1) % n).collect();
    let mut next: Vec<usize> = (0..n).map(|i| (i + 1) % n).collect();
    let mut remaining = n;
    let mut cur = 0;
    let mut misses = 0;
    // Strictness: 0 = proper ear, 1 = allow a straight corner (zero-area ear), 2 = forced.
    let mut level = 0;
    while remaining > 3 {
        if work > budget {
            // The ring from `cur` as a fan: n - 2 triangles in all, the winding kept.
            let mut k = next[cur];
            while next[k] != cur {
                out.push([poly[cur], poly[k], poly[next[k]]]);
                k = next[k];
            }
            return false;
        }
        let (a, b, c) = (prev[cur], cur, next[cur]);
        // An ear test walks the remaining ring twice.
        work += if level < 2 { 2 * remaining } else { 1 };
        let ok = match level {
            0 => orient(p[a], p[b], p[c]) > 0.0 && is_ear(p, &next, a, b, c),
            1 => orient(p[a], p[b], p[c]) >= 0.0 && is_ear(p, &next, a, b, c),
            _ => true,
        };
        if ok {
            out.push([poly[a], poly[b], poly[c]]);
            next[a] = c;
            prev[c] = a;
            remaining -= 1;
            cur = a;
            misses = 0;
            level = 0;
            continue;
        }
        cur = next[cur];
        misses += 1;
        if misses > remaining {
            misses = 0;
            level += 1;
            if level >= 2 {
                // No ear at all: clip the most convex corner so that we always terminate.
                let mut best = cur;
                let mut best_o = f64::NEG_INFINITY;
                let mut k = cur;
                work += remaining;
                for _ in 0..remaining {
                    let o = orient(p[prev[k]], p[k], p[next[k]]);
                    if o > best_o {
                        best_o = o;
                        best = k;
                    }
                    k = next[k];
                }
                cur = best;
            }
        }
    }
    let (a, b, c) = (prev[cur], cur, next[cur]);
    out.push([poly[a], poly[b], poly[c]]);
    true
}

/// No other remaining corner inside (or on) triangle `abc`, and diagonal `ac` crosses no edge.
fn is_ear(p: &[[f64; 2]], next: &[usize], a: usize, b: usize, c: usize) -> bool {
    let (pa, pb, pc) = (p[a], p[b], p[c]);
    let mut k = next[c];
    while k != a {
        let q = p[k];
        let coincident = q == pa || q == pb || q == pc;
        if !coincident
            && orient(pa, pb, q) >= 0.0
            && orient(pb, pc, q) >= 0.0
            && orient(pc, pa, q) >= 0.0
        {
            return false;
        }
        k = next[k];
    }
    // Edges of the rest of the ring: c -> ... -> a.
    let mut k = c;
    while k != a {
        let k2 = next[k];
        let (q1, q2) = (p[k], p[k2]);
        let touches = q1 == pa || q1 == pc || q2 == pa || q2 == pc;
        if !touches && segments_cross(pa, pc, q1, q2) {
            return false;
        }
        k = k2;
    }
    true
}

#[cfg(test)]
mod tests {
    use super::*;

    fn area(positions: &[[f32; 3]], tris: &[[u32; 3]]) -> f64 {
        tris.iter()
            .map(|t| {
                let p = |i: u32| {
                    let q = positions[i as usize];
                    [q[0] as f64, q[1] as f64, q[2] as f64]
                };
                let (a, b, c) = (p(t[0]), p(t[1]), p(t[2]));
                let cr = cross3(
                    [b[0] - a[0], b[1] - a[1], b[2] - a[2]],
                    [c[0] - a[0], c[1] - a[1], c[2] - a[2]],
                );
                dot(cr, cr).sqrt() / 2.0
            })
            .sum()
    }

    #[test]
    fn concave_l_shape_covers_its_area() {
        // L shape (area 3) in the plane z = 2, clockwise when seen from +z.
        let pts2 = [
            [0.0, 0.0],
            [0.0, 2.0],
            [1.0, 2.0],
            [1.0, 1.0],
            [2.0, 1.0],
            [2.0, 0.0],
        ];
        let positions: Vec<[f32; 3]> = pts2.iter().map(|p| [p[0], p[1], 2.0]).collect();
        let poly: Vec<u32> = (0..6).collect();
        let mut out = Vec::new();
        triangulate(&positions, &poly, &mut out);
        assert_eq!(out.len(), 4);
        assert!(
            (area(&positions, &out) - 3.0).abs() < 1e-9,
            "area {}",
            area(&positions, &out)
        );
        // Winding kept: every triangle's normal points like the polygon's (-z here).
        for t in &out {
            let (a, b, c) = (
                positions[t[0] as usize],
                positions[t[1] as usize],
                positions[t[2] as usize],
            );
            let z = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
            assert!(z < 0.0, "triangle {t:?} flipped");
        }
    }

    #[test]
    fn keyhole_polygon_with_bridge() {
        // Square 4x4 with a 2x2 square hole joined by a doubled bridge edge: area 12.
        let positions: Vec<[f32; 3]> = [
            [0.0, 0.0],
            [4.0, 0.0],
            [4.0, 4.0],
            [0.0, 4.0],
            [1.0, 1.0],
            [1.0, 3.0],
            [3.0, 3.0],
            [3.0, 1.0],
        ]
        .iter()
        .map(|p| [p[0], 0.0, p[1]])
        .collect();
        let poly = [0u32, 1, 2, 3, 0, 4, 5, 6, 7, 4];
        let mut out = Vec::new();
        triangulate(&positions, &poly, &mut out);
        assert_eq!(out.len(), 8);
        assert!(
            (area(&positions, &out) - 12.0).abs() < 1e-9,
            "area {}",
            area(&positions, &out)
        );
    }

    #[test]
    fn self_intersecting_terminates_with_n_minus_2() {
        let positions: Vec<[f32; 3]> = [[0.0, 0.0], [2.0, 2.0], [2.0, 0.0], [0.0, 2.0], [1.0, 5.0]]
            .iter()
            .map(|p| [p[0], p[1], 0.0])
            .collect();
        let mut out = Vec::new();
        triangulate(&positions, &[0, 1, 2, 3, 4], &mut out);
        assert_eq!(out.len(), 3);
    }

    /// A star polygon `{n/k}` with jittered radii: self-intersecting everywhere.
    fn star(n: usize) -> Vec<[f32; 3]> {
        let k = n / 2 - 1;
        (0..n)
            .map(|i| {
                let j = (i * k) % n;
                let a = std::f32::consts::TAU * j as f32 / n as f32;
                let r = 1.0 + 0.3 * (j % 3) as f32;
                [r * a.cos(), r * a.sin(), 0.0]
            })
            .collect()
    }

    /// Regression: forced clips of a self-intersecting polygon cost O(n^3) (a 2,000-corner star
    /// took 9 s, 20,000 corners would take hours); the work is now bounded and the rest fanned.
    #[test]
    fn self_intersecting_polygon_work_is_bounded() {
        let n = 3001; // odd: {n/k} visits every corner
        let positions = star(n);
        let poly: Vec<u32> = (0..n as u32).collect();
        let mut out = Vec::new();
        // `false`: the work budget ran out and the rest was fanned (deterministic, not timed).
        assert!(!triangulate(&positions, &poly, &mut out), "ran out of work");
        assert_eq!(out.len(), n - 2);
        // Every corner used, each triangle from the polygon's corners.
        let mut used = vec![false; n];
        out.iter().flatten().for_each(|&i| used[i as usize] = true);
        assert!(used.iter().all(|&u| u));
    }

    /// A simple concave polygon of 4,000 corners (a spiral band) is still ear-clipped in full.
    #[test]
    fn large_simple_concave_polygon_is_ear_clipped_in_full() {
        let m = 2000;
        let arm = |i: usize, r: f32| {
            let a = 0.02 * i as f32;
            [(r + 0.1 * a) * a.cos(), (r + 0.1 * a) * a.sin(), 0.0]
        };
        let mut positions: Vec<[f32; 3]> = (0..m).map(|i| arm(i, 1.0)).collect();
        positions.extend((0..m).rev().map(|i| arm(i, 1.05)));
        let poly: Vec<u32> = (0..2 * m as u32).collect();
        let mut out = Vec::new();
        assert!(triangulate(&positions, &poly, &mut out));
        assert_eq!(out.len(), 2 * m - 2);
    }
}
