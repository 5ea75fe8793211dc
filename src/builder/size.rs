//! The size of a cluster's triangles: what the frame's SW/HW split compares with
//! `hw_threshold_px` (`common/cull.glsl::emit_cluster`).
//!
//! The measure is an **edge-length equivalent**: `sqrt(2 * sum(A^2) / sum(A))` over the cluster's
//! triangle areas `A`, i.e. the legs of the right isosceles triangle whose area is the
//! cluster's area-weighted mean triangle area (a grid of squares of side `s`, each split into two
//! triangles, measures `s`). Area, not extent: the compute rasterizer runs a thread per triangle
//! and walks its pixels one after another (and its rows, for larger triangles), so its cost
//! follows the pixels each triangle covers, while a long thin blade with a large bounding sphere
//! but a small area is cheap there and slow in hardware. Weighted by area, so that the large
//! triangles of a cluster with mixed sizes, whose pixels the workgroup waits for, count as much as
//! the pixels they cover (the mean over triangles would let 127 small ones hide one big one).
//!
//! Stored per cluster as an 8-bit code relative to the cluster's bounds diagonal `d` (the measure
//! is at most about `0.81 d`: the largest triangle inside a ball of diameter `d`), in steps of
//! 1/16 octave, rounded up: `size <= d * 2^((code - 255) / 16)`, at most 4.4 % above the measure
//! (down to `d / 2^15.9`, far below a pixel for any cluster on screen). The code is computed with
//! `+ - * /` and `sqrt` only (exactly rounded everywhere), so the same input gives the same byte on
//! every platform and `verify` can recompute it exactly.

use crate::shared::{CLUSTER_SIZE_CODE_MAX, CLUSTER_SIZE_STEPS};

// The encoding takes `(size / d)^16` by squaring `(size / d)^2` three times.
const _: () = assert!(CLUSTER_SIZE_STEPS == 16 && CLUSTER_SIZE_CODE_MAX == 255);

/// The squared edge-length equivalent of `triangles` (corner positions): `2 * sum(A^2) / sum(A)`;
/// 0 when every triangle has zero area. Sums in the given order (deterministic).
pub fn size_squared(triangles: impl IntoIterator<Item = [[f32; 3]; 3]>) -> f64 {
    let (mut s1, mut s2) = (0.0f64, 0.0f64);
    for [a, b, c] in triangles {
        let u: [f64; 3] = std::array::from_fn(|k| b[k] as f64 - a[k] as f64);
        let v: [f64; 3] = std::array::from_fn(|k| c[k] as f64 - a[k] as f64);
        let n = [
            u[1] * v[2] - u[2] * v[1],
            u[2] * v[0] - u[0] * v[2],
            u[0] * v[1] - u[1] * v[0],
        ];
        let area = 0.5 * (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        s1 += area;
        s2 += area * area;
    }
    if s1 > 0.0 { 2.0 * s2 / s1 } else { 0.0 }
}

/// The squared length of the diagonal of bounds `lo`..`hi` (as the GPU takes it: the cluster's
/// stored f32 bounds).
pub fn diagonal_squared(lo: [f32; 3], hi: [f32; 3]) -> f64 {
    (0..3)
        .map(|k| {
            let d = hi[k] as f64 - lo[k] as f64;
            d * d
        })
        .sum()
}

/// The size code of a cluster whose triangles measure `size_sq` (squared, [`size_squared`]) with
/// bounds of squared diagonal `diagonal_sq`: the smallest code `c` with
/// `d * 2^((c - 255) / 16) >= size`, clamped to 0..=255 (0 for an empty measure).
pub fn size_code(size_sq: f64, diagonal_sq: f64) -> u32 {
    if size_sq.is_nan() || size_sq <= 0.0 || diagonal_sq.is_nan() || diagonal_sq <= 0.0 {
        return 0;
    }
    let q = size_sq / diagonal_sq;
    if q >= 1.0 {
        return CLUSTER_SIZE_CODE_MAX;
    }
    // x = (size / d)^16; the code is 255 + ceil(log2 x).
    let mut x = q;
    for _ in 0..3 {
        x *= x;
    }
    // Below 2^-255 (and subnormal or zero): code 0.
    if x < f64::from_bits((1023u64 - 255) << 52) {
        return 0;
    }
    let bits = x.to_bits();
    let exponent = ((bits >> 52) & 0x7ff) as i64 - 1023;
    let ceil_log2 = if bits & ((1u64 << 52) - 1) == 0 {
        exponent
    } else {
        exponent + 1
    };
    (CLUSTER_SIZE_CODE_MAX as i64 + ceil_log2).clamp(0, CLUSTER_SIZE_CODE_MAX as i64) as u32
}

/// What a code stands for: the largest edge-length equivalent it admits, as a share of the bounds
/// diagonal (`common/cluster.glsl::cluster_size_ratio` computes the same in f32).
pub fn size_ratio(code: u32) -> f64 {
    ((code.min(CLUSTER_SIZE_CODE_MAX) as f64 - CLUSTER_SIZE_CODE_MAX as f64)
        / CLUSTER_SIZE_STEPS as f64)
        .exp2()
}

/// The size code of the triangles `triangles` in bounds `lo`..`hi`.
pub fn cluster_size_code(
    triangles: impl IntoIterator<Item = [[f32; 3]; 3]>,
    lo: [f32; 3],
    hi: [f32; 3],
) -> u32 {
    size_code(size_squared(triangles), diagonal_squared(lo, hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn code_is_the_smallest_that_covers_the_size() {
        for k in 0..=255u32 {
            // Just below a code's ratio: that code.
            let r = size_ratio(k);
            let down = r * (1.0 - 1e-9);
            assert_eq!(size_code(down * down, 1.0), k, "below code {k}");
            // Just above it: the next code (255 stays 255).
            let up = r * (1.0 + 1e-9);
            assert_eq!(size_code(up * up, 1.0), (k + 1).min(255), "above code {k}");
        }
        assert_eq!(size_code(0.0, 1.0), 0);
        assert_eq!(size_code(1e-30, 1.0), 0);
        assert_eq!(size_code(4.0, 1.0), 255);
        assert_eq!(size_code(1.0, 0.0), 0);
        assert_eq!(size_code(f64::NAN, 1.0), 0);
        // Relative to the diagonal: the same code at any scale (by powers of two exactly).
        assert_eq!(size_code(0.09, 1.0), size_code(0.09 * 1024.0, 1024.0));
    }

    #[test]
    fn square_grid_measures_its_side() {
        // Two triangles of a square of side 3: areas 4.5 each.
        let t = [
            [[0.0, 0.0, 0.0], [3.0, 0.0, 0.0], [3.0, 3.0, 0.0]],
            [[0.0, 0.0, 0.0], [3.0, 3.0, 0.0], [0.0, 3.0, 0.0]],
        ];
        assert_eq!(size_squared(t), 9.0);
        // One big triangle among small ones dominates by its area.
        let big = [[0.0, 0.0, 0.0], [100.0, 0.0, 0.0], [0.0, 100.0, 0.0]];
        let small = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let mixed: Vec<_> = std::iter::once(big)
            .chain(std::iter::repeat_n(small, 127))
            .collect();
        let s = size_squared(mixed).sqrt();
        assert!(s > 98.0 && s < 100.0, "{s}");
    }
}
