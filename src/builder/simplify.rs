//! Group simplification with meshoptimizer: locked border vertices, absolute object-space error.

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
    let values = (0..count)
        .into_par_iter()
        .flat_map_iter(|v| {
            let n = normals.then(|| normal(v)).into_iter().flatten();
            n.chain(uv.map(|f| f(v)).into_iter().flatten())
        })
        .collect();
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

/// Simplifies `tris` (global vertex indices into `positions`) towards `target_tris` triangles.
/// `locked(v)` says whether global vertex `v` must keep its place; `attrs` (indexed like
/// `positions`) adds attribute deviation to the error (see [`Attributes`]). Returns the new
/// triangles (global indices, a subset of the input vertices) and the absolute error.
pub(crate) fn simplify(
    tris: &[[u32; 3]],
    positions: &[[f32; 3]],
    attrs: Option<&Attributes>,
    locked: &dyn Fn(u32) -> bool,
    target_tris: usize,
    target_error: f32,
    mode: Mode,
) -> (Vec<[u32; 3]>, f32) {
    // Compact vertex buffer of the group (keeps meshopt's work proportional to the group), in
    // first-use order.
    let (verts, indices) = compact(tris, positions.len());
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
    let out: Vec<[u32; 3]> = dest[..count]
        .chunks_exact(3)
        .map(|t| {
            [
                verts[t[0] as usize],
                verts[t[1] as usize],
                verts[t[2] as usize],
            ]
        })
        .collect();
    (
        out,
        if err.is_finite() {
            err.max(0.0)
        } else {
            f32::MAX
        },
    )
}
