//! Group simplification with meshoptimizer: locked border vertices, absolute object-space error.

use super::uf_find;
use super::uf_union;

/// meshopt_SimplifyLockBorder is not used: locks are explicit per vertex.
const OPT_SPARSE_NONE: u32 = 0;
/// meshopt_SimplifyErrorAbsolute.
const OPT_ERROR_ABSOLUTE: u32 = 4;
/// meshopt_SimplifyPrune (meshoptimizer >= 0.22): removes disconnected parts that are not locked.
const OPT_PRUNE: u32 = 8;
/// meshopt_SimplifyPermissive (meshoptimizer >= 1.0): collapses may cross attribute seams.
const OPT_PERMISSIVE: u32 = 32;

/// Most attribute floats per vertex meshoptimizer takes.
pub(crate) const MAX_ATTRIBUTES: usize = 32;

/// Per-vertex attributes the simplifier weighs against position (normals, UVs): `stride` floats
/// per vertex in `values`, indexed like the positions, each float weighted by `weights[k]`.
///
/// meshoptimizer adds the squared weighted attribute deviation, scaled by the local area, to the
/// squared position deviation, so a weighted change of 1 across a distance `d` costs about as much
/// as moving the surface by `d`; the error it reports (and the builder stores) is therefore
/// `sqrt(e_pos^2 + e_attr^2)`, where `e_attr` is roughly `weight * deviation * size of the
/// collapsed region`: the attribute error converted to an object-space distance. See
/// docs/architecture.md ("Shading-aware error").
#[derive(Clone, Copy, Debug)]
pub(crate) struct Attributes<'a> {
    pub values: &'a [f32],
    pub stride: usize,
    pub weights: &'a [f32],
}

thread_local! {
    /// Per-thread scratch map global vertex -> local index (all `u32::MAX` between calls).
    static SCRATCH: std::cell::RefCell<Vec<u32>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// Per vertex of `verts` (distinct global vertices), the first of them with the same position
/// id (`pid`, indexed by global vertex): vertices with equal entries share a position.
fn first_of_position(verts: &[u32], pid: &[u32]) -> Vec<u32> {
    first_of_points(verts.iter().map(|&v| pid[v as usize]))
}

/// Per entry of `points` (a point id per vertex, in vertex order), the index of the first entry
/// with the same point id.
pub(crate) fn first_of_points(points: impl ExactSizeIterator<Item = u32>) -> Vec<u32> {
    SCRATCH.with(|cell| {
        let mut map = cell.borrow_mut();
        let mut first = Vec::with_capacity(points.len());
        let mut touched = Vec::new();
        for (local, p) in points.enumerate() {
            let p = p as usize;
            if map.len() <= p {
                map.resize(p + 1, u32::MAX);
            }
            if map[p] == u32::MAX {
                map[p] = local as u32;
                touched.push(p);
            }
            first.push(map[p]);
        }
        for p in touched {
            map[p] = u32::MAX;
        }
        first
    })
}

/// The distinct vertices of `tris` in first-use order, and `tris` as indices into them.
pub(crate) fn compact(tris: &[[u32; 3]], vertex_count: usize) -> (Vec<u32>, Vec<u32>) {
    SCRATCH.with(|cell| {
        let mut map = cell.borrow_mut();
        if map.len() < vertex_count {
            map.resize(vertex_count, u32::MAX);
        }
        let mut verts = Vec::new();
        let mut indices = Vec::with_capacity(tris.len() * 3);
        for &v in tris.iter().flatten() {
            let m = &mut map[v as usize];
            if *m == u32::MAX {
                *m = verts.len() as u32;
                verts.push(v);
            }
            indices.push(*m);
        }
        for &v in &verts {
            map[v as usize] = u32::MAX;
        }
        (verts, indices)
    })
}

/// Per vertex, the attribute floats the simplifier weighs and their weights: the normal
/// (weight `normal_weight`) and, when `uv` is given, the UV (`uv_weight`). Empty when no weight
/// is positive (position-only error). The builder and the `lod` baseline both use it, so their
/// errors mean the same.
pub(crate) fn attribute_values(
    count: usize,
    normal: &(dyn Fn(usize) -> [f32; 3] + Sync),
    uv: Option<&(dyn Fn(usize) -> [f32; 2] + Sync)>,
    normal_weight: f32,
    uv_weight: f32,
) -> (Vec<f32>, Vec<f32>) {
    use rayon::prelude::*;
    let normals = normal_weight > 0.0;
    let uv = uv.filter(|_| uv_weight > 0.0);
    let mut weights = Vec::new();
    if normals {
        weights.extend([normal_weight; 3]);
    }
    if uv.is_some() {
        weights.extend([uv_weight; 2]);
    }
    if weights.is_empty() {
        return (Vec::new(), Vec::new());
    }
    let stride = weights.len();
    let mut values = vec![0.0f32; count * stride];
    // Chunks of vertices per task: a task per vertex cost more than the copy on one thread.
    values
        .par_chunks_mut(stride * 4096)
        .enumerate()
        .for_each(|(c, chunk)| {
            for (i, out) in chunk.chunks_exact_mut(stride).enumerate() {
                let v = c * 4096 + i;
                let mut k = 0;
                if normals {
                    out[..3].copy_from_slice(&normal(v));
                    k = 3;
                }
                if let Some(f) = uv {
                    out[k..k + 2].copy_from_slice(&f(v));
                }
            }
        });
    (values, weights)
}

/// How to simplify.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Mode {
    /// Edge collapses with locked vertices.
    Locked,
    /// As `Locked`, and small disconnected parts may be removed.
    LockedPrune,
    /// As `Locked`, and collapses may cross attribute seams (normal creases, UV and material
    /// borders): for groups that cannot shrink otherwise. No pruning: the last group, with
    /// nothing locked, would be pruned away whole.
    Permissive,
    /// Vertex clustering, no locks (only valid when nothing outside the group shares vertices).
    Sloppy,
}

/// What [`simplify`] made.
#[derive(Clone, Debug, Default, PartialEq)]
pub(crate) struct Simplified {
    /// The new triangles (global indices, a subset of the input vertices).
    pub tris: Vec<[u32; 3]>,
    /// meshoptimizer's absolute error (position and weighted attributes) against the input.
    pub error: f32,
    /// The coverage error against the input ([`coverage_error`]).
    pub coverage: f32,
}

impl Simplified {
    /// The error of the result against the input: the larger of the two.
    pub fn combined(&self) -> f32 {
        self.error.max(self.coverage)
    }
}

/// How [`simplify`]'s coverage error finds the connected pieces of its input.
#[derive(Clone, Copy, Debug)]
pub(crate) enum Pieces<'a> {
    /// Triangles join at shared vertices and at vertices with equal positions (compared).
    ByPosition,
    /// Triangles join at shared position ids (`pid[v]`, equal for the vertices that share a
    /// position).
    ByPid(&'a [u32]),
    /// Per compacted vertex, the first compacted vertex at its position (as
    /// `first_of_position` gives it): only for [`simplify_compacted`], whose caller has it.
    FirstOfPosition(&'a [u32]),
    /// The caller knows the input is one piece by that rule (the builder's groups learn it from
    /// their shape): the coverage error compares total areas, no union-find.
    One,
}

/// Simplifies `tris` (global vertex indices into `positions`) towards `target_tris` triangles.
/// `locked(v)` says whether global vertex `v` must keep its place; `attrs` (indexed like
/// `positions`) adds attribute deviation to the error (see [`Attributes`]); `pieces` says how the
/// coverage error finds the input's connected pieces.
#[allow(clippy::too_many_arguments)]
pub(crate) fn simplify(
    tris: &[[u32; 3]],
    positions: &[[f32; 3]],
    pieces: Pieces,
    attrs: Option<&Attributes>,
    locked: &dyn Fn(u32) -> bool,
    target_tris: usize,
    target_error: f32,
    mode: Mode,
) -> Simplified {
    // Compact vertex buffer of the group (keeps meshopt's work proportional to the group), in
    // first-use order.
    let (verts, indices) = compact(tris, positions.len());
    let r = simplify_compacted(
        &verts,
        &indices,
        positions,
        pieces,
        attrs,
        locked,
        target_tris,
        target_error,
        mode,
    );
    Simplified {
        tris: r
            .tris
            .iter()
            .map(|t| t.map(|i| verts[i as usize]))
            .collect(),
        error: r.error,
        coverage: r.coverage,
    }
}

/// [`simplify`] of triangles already compacted by [`compact`]: `verts` (distinct global vertices
/// in first-use order) and `indices` (the triangles as indices into `verts`). The result's
/// triangles index `verts` too. Callers that look at the group's triangles several times (the
/// builder's groups) compact once and stay in these small local ids, which stay in cache where
/// global ids missed it on every corner.
#[allow(clippy::too_many_arguments)]
pub(crate) fn simplify_compacted(
    verts: &[u32],
    indices: &[u32],
    positions: &[[f32; 3]],
    pieces: Pieces,
    attrs: Option<&Attributes>,
    locked: &dyn Fn(u32) -> bool,
    target_tris: usize,
    target_error: f32,
    mode: Mode,
) -> Simplified {
    let pos: Vec<[f32; 3]> = verts.iter().map(|&v| positions[v as usize]).collect();
    let lock: Vec<u8> = verts.iter().map(|&v| locked(v) as u8).collect();
    // The group's attributes, compacted like the positions; none when no weight is positive.
    let attrs = attrs.filter(|a| {
        a.stride > 0
            && a.stride <= MAX_ATTRIBUTES
            && a.weights.len() == a.stride
            && a.weights.iter().any(|&w| w > 0.0)
            && a.values.len() >= positions.len() * a.stride
    });
    let attr_values: Vec<f32> = match attrs {
        Some(a) => verts
            .iter()
            .flat_map(|&v| {
                let o = v as usize * a.stride;
                a.values[o..o + a.stride].iter().copied()
            })
            .collect(),
        None => Vec::new(),
    };
    let (attr_ptr, attr_stride, weight_ptr, attr_count) = match attrs {
        Some(a) => (
            attr_values.as_ptr(),
            a.stride * 4,
            a.weights.as_ptr(),
            a.stride,
        ),
        None => (std::ptr::null(), 0, std::ptr::null(), 0),
    };
    let mut dest = vec![0u32; indices.len()];
    let mut err = 0.0f32;
    let count = match mode {
        Mode::Locked | Mode::LockedPrune | Mode::Permissive => {
            let opts = OPT_SPARSE_NONE
                | OPT_ERROR_ABSOLUTE
                | match mode {
                    Mode::LockedPrune => OPT_PRUNE,
                    Mode::Permissive => OPT_PERMISSIVE,
                    _ => 0,
                };
            // SAFETY: every pointer covers the counts passed with it: `dest` and `indices` hold
            // `indices.len()` u32, `pos` holds `pos.len()` tightly packed float3 (stride 12), `lock`
            // has one byte per vertex, `attr_values` holds `attr_count` floats per vertex of `pos`
            // (stride `attr_count * 4` bytes) and `weights` `attr_count` floats (or both are null
            // with a count of 0), and every index is < pos.len() by construction.
            unsafe {
                meshopt::ffi::meshopt_simplifyWithAttributes(
                    dest.as_mut_ptr(),
                    indices.as_ptr(),
                    indices.len(),
                    pos.as_ptr().cast(),
                    pos.len(),
                    12,
                    attr_ptr,
                    attr_stride,
                    weight_ptr,
                    attr_count,
                    lock.as_ptr(),
                    target_tris * 3,
                    target_error,
                    opts,
                    &mut err,
                )
            }
        }
        Mode::Sloppy => {
            // SAFETY: as above, without locks.
            let n = unsafe {
                meshopt::ffi::meshopt_simplifySloppy(
                    dest.as_mut_ptr(),
                    indices.as_ptr(),
                    indices.len(),
                    pos.as_ptr().cast(),
                    pos.len(),
                    12,
                    lock.as_ptr(),
                    target_tris * 3,
                    f32::MAX,
                    &mut err,
                )
            };
            // Sloppy reports a relative error.
            // SAFETY: `pos` holds `pos.len()` float3.
            let scale =
                unsafe { meshopt::ffi::meshopt_simplifyScale(pos.as_ptr().cast(), pos.len(), 12) };
            err *= scale;
            n
        }
    };
    let count = count.min(dest.len());
    let coverage = match pieces {
        Pieces::One => one_piece_coverage_error(indices, &dest[..count], &pos),
        Pieces::ByPid(p) => {
            let first = first_of_position(verts, p);
            coverage_error(indices, &dest[..count], &pos, Some(&first))
        }
        Pieces::FirstOfPosition(first) => {
            coverage_error(indices, &dest[..count], &pos, Some(first))
        }
        Pieces::ByPosition => coverage_error(indices, &dest[..count], &pos, None),
    };
    let tris: Vec<[u32; 3]> = dest[..count]
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let finite = |e: f32| if e.is_finite() { e.max(0.0) } else { f32::MAX };
    Simplified {
        tris,
        error: finite(err),
        coverage: finite(coverage),
    }
}

/// Share of a connected piece's area it may lose before the loss counts as coverage error.
pub(crate) const COVERAGE_LOSS_SHARE: f64 = 0.25;

/// The coverage part of a simplification's error: an object-space distance.
///
/// A position bound alone lets thin geometry vanish: a grass blade of width `w` collapsed onto
/// its spine moves no point by more than about `w / 2`, yet every pixel the blade covered is
/// lost. So, per connected piece of the input (triangles joined by shared vertices or by
/// vertices at the same position), the area the simplified triangles of that piece lost is
/// measured; where a piece lost more than [`COVERAGE_LOSS_SHARE`] of its area, the error is at
/// least `sqrt(lost area)`: the side of a square of that area, so that "1 px" also means "at most
/// about one pixel of coverage gone per piece". Pieces of closed or large surfaces lose a tiny
/// share of their area to simplification and are not affected; small disconnected parts (blades,
/// leaves, rivets) are, until they are about a pixel in size. `input` and `output` are index
/// lists (triples) into `positions`; output vertices are input vertices (edge collapses and
/// vertex clustering both keep that). `first_of_position`, when given, names per vertex the
/// first vertex at its position (a vertex's own index where it is the first); else vertices at
/// equal positions are found by sorting.
pub(crate) fn coverage_error(
    input: &[u32],
    output: &[u32],
    positions: &[[f32; 3]],
    first_of_position: Option<&[u32]>,
) -> f32 {
    let n = positions.len();
    if input.is_empty() || n == 0 {
        return 0.0;
    }
    // Pieces: union-find over vertices, joined at equal positions and along triangles.
    let mut parent: Vec<u32> = match first_of_position {
        Some(f) if f.len() == n && f.iter().all(|&r| f.get(r as usize) == Some(&r)) => f.to_vec(),
        _ => {
            let mut parent: Vec<u32> = (0..n as u32).collect();
            let mut by_position: Vec<u32> = (0..n as u32).collect();
            let key = |v: u32| positions[v as usize].map(f32::to_bits);
            by_position.sort_unstable_by_key(|&v| key(v));
            for w in by_position.windows(2) {
                if key(w[0]) == key(w[1]) {
                    uf_union(&mut parent, w[0], w[1]);
                }
            }
            parent
        }
    };
    for t in input.chunks_exact(3) {
        uf_union(&mut parent, t[0], t[1]);
        uf_union(&mut parent, t[0], t[2]);
    }
    let area = |t: &[u32]| triangle_area(positions, t);
    // Area per piece before and after (indexed by the piece's root vertex).
    let mut before = vec![0.0f64; n];
    let mut after = vec![0.0f64; n];
    for t in input.chunks_exact(3) {
        let r = uf_find(&mut parent, t[0]);
        before[r as usize] += area(t);
    }
    for t in output.chunks_exact(3) {
        let r = uf_find(&mut parent, t[0]);
        after[r as usize] += area(t);
    }
    let mut lost_total = 0.0f64;
    for (b, a) in before.iter().zip(&after) {
        let lost = b - a;
        if *b > 0.0 && lost > COVERAGE_LOSS_SHARE * b {
            lost_total += lost;
        }
    }
    lost_total.sqrt() as f32
}

/// The area of triangle `t` (three indices into `positions`), in f64.
fn triangle_area(positions: &[[f32; 3]], t: &[u32]) -> f64 {
    let p = |k: usize| glam::DVec3::from(positions[t[k] as usize].map(f64::from));
    (p(1) - p(0)).cross(p(2) - p(0)).length() * 0.5
}

/// [`coverage_error`] of an input known to be one piece: the same value (one piece's loss),
/// without the union-find (most groups of a closed surface are one piece).
pub(crate) fn one_piece_coverage_error(
    input: &[u32],
    output: &[u32],
    positions: &[[f32; 3]],
) -> f32 {
    let total = |t: &[u32]| -> f64 { t.chunks_exact(3).map(|t| triangle_area(positions, t)).sum() };
    let (before, after) = (total(input), total(output));
    let lost = before - after;
    if before > 0.0 && lost > COVERAGE_LOSS_SHARE * before {
        lost.sqrt() as f32
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two unit squares (two triangles each), apart; the second's corners also appear as split
    /// copies (same positions, other indices) used by its second triangle.
    fn squares() -> (Vec<[f32; 3]>, Vec<u32>) {
        let mut p = vec![
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [1.0, 1.0, 0.0],
            [0.0, 1.0, 0.0],
            [5.0, 0.0, 0.0],
            [6.0, 0.0, 0.0],
            [6.0, 1.0, 0.0],
            [5.0, 1.0, 0.0],
        ];
        // Split copies of vertices 4 and 6 (a seam): the piece stays one piece.
        p.push([5.0, 0.0, 0.0]);
        p.push([6.0, 1.0, 0.0]);
        let idx = vec![0, 1, 2, 0, 2, 3, 4, 5, 6, 8, 9, 7];
        (p, idx)
    }

    #[test]
    fn coverage_error_counts_the_area_of_vanished_and_shrunk_pieces() {
        let (p, idx) = squares();
        // Nothing lost.
        assert_eq!(coverage_error(&idx, &idx, &p, None), 0.0);
        // The second square gone: its area (1) is lost.
        assert_eq!(coverage_error(&idx, &idx[..6], &p, None), 1.0);
        // Half of each square gone: 0.5 + 0.5 lost (more than a quarter of each piece).
        let half: Vec<u32> = [&idx[..3], &idx[6..9]].concat();
        assert!((coverage_error(&idx, &half, &p, None) - 1.0).abs() < 1e-6);
        // Half of the second square (split copies join it into one piece): 0.5 lost.
        let one: Vec<u32> = [&idx[..6], &idx[9..12]].concat();
        assert!((coverage_error(&idx, &one, &p, None) - 0.5f32.sqrt()).abs() < 1e-6);
        // Everything gone.
        assert!((coverage_error(&idx, &[], &p, None) - 2.0f32.sqrt()).abs() < 1e-6);
    }

    #[test]
    fn one_piece_coverage_error_equals_the_union_find_on_one_piece() {
        let (p, idx) = squares();
        // The second square alone (its split copies join it): one piece.
        let one = &idx[6..];
        let outs: [&[u32]; 4] = [one, &one[..3], &one[3..], &[]];
        for out in outs {
            assert_eq!(
                one_piece_coverage_error(one, out, &p),
                coverage_error(one, out, &p, None)
            );
        }
        // Half of it lost counts (more than a quarter of the piece).
        assert!((one_piece_coverage_error(one, &one[..3], &p) - 0.5f32.sqrt()).abs() < 1e-6);
    }

    #[test]
    fn coverage_error_joins_pieces_by_position_ids_as_by_positions() {
        let (p, idx) = squares();
        // Position ids: the split copies 8 and 9 share vertices 4's and 6's ids.
        let pid: Vec<u32> = vec![0, 1, 2, 3, 4, 5, 6, 7, 4, 6];
        let verts: Vec<u32> = (0..p.len() as u32).collect();
        let first = first_of_position(&verts, &pid);
        assert_eq!(first, vec![0, 1, 2, 3, 4, 5, 6, 7, 4, 6]);
        let one: Vec<u32> = [&idx[..6], &idx[9..12]].concat();
        let half: Vec<u32> = [&idx[..3], &idx[6..9]].concat();
        for out in [&idx[..], &idx[..6], &one[..], &half[..], &[][..]] {
            let by_id = coverage_error(&idx, out, &p, Some(&first));
            assert_eq!(by_id, coverage_error(&idx, out, &p, None));
        }
        // Ids that do not name first vertices are not trusted: positions decide.
        let bad: Vec<u32> = (0..p.len() as u32)
            .map(|v| (v + 1) % p.len() as u32)
            .collect();
        assert_eq!(
            coverage_error(&idx, &one, &p, Some(&bad)),
            coverage_error(&idx, &one, &p, None)
        );
    }

    #[test]
    fn coverage_error_ignores_small_losses_of_a_piece() {
        // A fan of 10 triangles around the origin; dropping one loses a tenth of the area.
        let mut p = vec![[0.0f32, 0.0, 0.0]];
        for k in 0..10 {
            let a = k as f32 / 10.0 * std::f32::consts::TAU;
            p.push([a.cos(), a.sin(), 0.0]);
        }
        let idx: Vec<u32> = (0..10u32)
            .flat_map(|k| [0, 1 + k, 1 + (k + 1) % 10])
            .collect();
        assert_eq!(coverage_error(&idx, &idx[3..], &p, None), 0.0);
        // Three of ten (30 %): counted.
        assert!(coverage_error(&idx, &idx[9..], &p, None) > 0.0);
    }
}
