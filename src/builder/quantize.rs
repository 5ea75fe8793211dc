//! Vertex quantization: positions on a per-mesh grid ([`Quantization::position_bits`] bits per
//! axis over the mesh's largest extent, at most 21), octahedral normals
//! ([`Quantization::normal_bits`] bits per component, at most 16, stored as two i16), UVs (2 x 16
//! bits over the mesh's UV range). The precision is the mesh's stated one: every position is
//! within half a grid step of its input, and the builder works on the quantized values. Decoding
//! is deterministic (f64 math, one rounding to f32), so equal codes always decode to equal
//! positions: the cut stays crack-free.

use super::Quantization;

/// Most bits per position axis (the packed code holds 3 x 21 bits).
pub const POSITION_BITS: u32 = crate::shared::CLUSTER_COORD_BITS;
const POSITION_MAX: u64 = (1 << POSITION_BITS) - 1;
/// Fewest bits per position axis [`auto_position_bits`] chooses: a step of at most 1/16383 of
/// the mesh's largest extent, for meshes of few large triangles.
pub const AUTO_POSITION_BITS_MIN: u32 = 14;
/// [`auto_position_bits`]: grid steps per short input edge, at least.
pub const AUTO_STEPS_PER_SHORT_EDGE: f64 = 32.0;
/// The short edge of [`auto_position_bits`]: this quantile of the input's edge lengths (those
/// longer than 0).
pub const SHORT_EDGE_QUANTILE: f64 = 0.1;
/// Fewest bits per position axis of the grid the DAG is built on ([`build_position_bits`]).
pub const BUILD_POSITION_BITS_MIN: u32 = 16;
/// [`build_position_bits`]: grid steps per median input edge, at least.
pub const BUILD_STEPS_PER_EDGE: f64 = 64.0;
/// Most bits per normal component.
pub const NORMAL_BITS: u32 = 16;
/// Default normal bits per component (see docs/architecture.md, "Compact pages").
pub const DEFAULT_NORMAL_BITS: u32 = 12;

/// The grid bits per axis of a mesh of largest extent `extent` whose short edge (the
/// [`SHORT_EDGE_QUANTILE`] quantile of its edge lengths) is `short_edge`: its default stated
/// precision. At least [`AUTO_POSITION_BITS_MIN`], and a step of at most
/// 1/[`AUTO_STEPS_PER_SHORT_EDGE`] of the short edge, so that nine in ten edges are at least
/// that many steps long and their triangles keep their shape (a thin part, which makes the short
/// edges, keeps its thickness); at most [`POSITION_BITS`].
pub fn auto_position_bits(extent: f64, short_edge: f64) -> u32 {
    edge_bits(extent, short_edge, AUTO_STEPS_PER_SHORT_EDGE)
        .clamp(AUTO_POSITION_BITS_MIN, POSITION_BITS)
}

/// The bits per axis of the grid the builder welds and simplifies on when the stated precision
/// is coarser (the rule the stated precision had before session 37): a step of at most
/// 1/[`BUILD_STEPS_PER_EDGE`] of the median edge, at least [`BUILD_POSITION_BITS_MIN`] bits. The
/// DAG of a mesh then does not depend on its stated precision (at or below this): the pages
/// store its positions moved to the stated grid, by at most half a step of it. (A DAG built on a
/// coarser grid is another one: its coarse levels, which small instances draw, are another
/// simplification, and on the turbine blade a worse one; docs/architecture.md, "The stated
/// precision apart from the build grid".)
pub fn build_position_bits(extent: f64, median_edge: f64) -> u32 {
    edge_bits(extent, median_edge, BUILD_STEPS_PER_EDGE)
        .clamp(BUILD_POSITION_BITS_MIN, POSITION_BITS)
}

fn edge_bits(extent: f64, edge: f64, steps_per_edge: f64) -> u32 {
    if !(extent > 0.0 && edge > 0.0 && extent.is_finite() && edge.is_finite()) {
        return POSITION_BITS;
    }
    let steps = extent / edge * steps_per_edge;
    (steps.log2().ceil().max(0.0) as u32).min(POSITION_BITS)
}

/// The grid for positions in `[lo, hi]` with `position_bits` bits per axis (clamped to
/// 1..=[`POSITION_BITS`]), normals with `normal_bits` bits per component (clamped to
/// 2..=[`NORMAL_BITS`]) and UVs in `[uv_lo, uv_hi]`.
pub fn make_quantization(
    lo: [f32; 3],
    hi: [f32; 3],
    uv_lo: [f32; 2],
    uv_hi: [f32; 2],
    position_bits: u32,
    normal_bits: u32,
) -> Quantization {
    let position_bits = position_bits.clamp(1, POSITION_BITS);
    let extent = (0..3)
        .map(|k| hi[k] as f64 - lo[k] as f64)
        .fold(0.0f64, f64::max);
    let step = if extent > 0.0 {
        extent / ((1u64 << position_bits) - 1) as f64
    } else {
        1.0
    };
    Quantization {
        origin: [lo[0] as f64, lo[1] as f64, lo[2] as f64],
        step,
        uv_min: uv_lo,
        uv_max: uv_hi,
        position_bits,
        normal_bits: normal_bits.clamp(2, NORMAL_BITS),
    }
}

/// Grid code of a position (clamped to the grid).
pub fn encode_position(q: &Quantization, p: [f32; 3]) -> [u32; 2] {
    let mut code = 0u64;
    for (k, &pk) in p.iter().enumerate() {
        let t = ((pk as f64 - q.origin[k]) / q.step).round();
        let max = ((1u64 << q.position_bits.clamp(1, POSITION_BITS)) - 1) as f64;
        let t = if t.is_finite() {
            t.clamp(0.0, max) as u64
        } else {
            0
        };
        code |= t << (POSITION_BITS * k as u32);
    }
    [code as u32, (code >> 32) as u32]
}

/// The position code of grid coordinates (each below `2^POSITION_BITS`).
pub fn pack_coords(c: [u32; 3]) -> [u32; 2] {
    let code = c.iter().enumerate().fold(0u64, |acc, (k, &x)| {
        acc | (x as u64 & POSITION_MAX) << (POSITION_BITS * k as u32)
    });
    [code as u32, (code >> 32) as u32]
}

/// The code on grid `to` of the position with code `code` on grid `from` (the same box, `to` of
/// at most as many bits per axis): each coordinate to the nearest of `to`'s, in exact integer
/// arithmetic (both grids' step counts are odd, so there are no ties): at most half a step of
/// `to` away. Equal codes give equal codes.
pub fn regrid_position(from: &Quantization, to: &Quantization, code: [u32; 2]) -> [u32; 2] {
    let n = (1u64 << from.position_bits) - 1;
    let m = (1u64 << to.position_bits) - 1;
    pack_coords(position_coords(code).map(|x| ((x as u64 * m + n / 2) / n) as u32))
}

/// Grid coordinates of a position code.
pub fn position_coords(code: [u32; 2]) -> [u32; 3] {
    let c = code[0] as u64 | (code[1] as u64) << 32;
    [
        (c & POSITION_MAX) as u32,
        ((c >> POSITION_BITS) & POSITION_MAX) as u32,
        ((c >> (2 * POSITION_BITS)) & POSITION_MAX) as u32,
    ]
}

/// The corner of a cluster's box at grid coordinates `c`, as the GPU computes it from a page's
/// cull words (`common/cluster.glsl`, `cluster_bounds_min`): `origin + c * step` in f32 with one
/// fused multiply-add, from the mesh's f32 grid (`MeshGpu::quant_origin`, `quant_step`). The GPU
/// decodes a vertex with the same `precise` fma (`common/raster.glsl`, `decode_position`), so the
/// box of the smallest and largest coordinates holds every vertex it draws (the fma grows with
/// `c`) whatever its rounding; where the GPU's fma rounds once, as on NVIDIA and lavapipe
/// (Vulkan does not promise it), the box is also this one bit for bit.
pub fn grid_corner(q: &Quantization, c: [u32; 3]) -> [f32; 3] {
    std::array::from_fn(|k| (c[k] as f32).mul_add(q.step as f32, q.origin[k] as f32))
}

/// Position of a grid code.
pub fn decode_position(q: &Quantization, code: [u32; 2]) -> [f32; 3] {
    let c = position_coords(code);
    [
        (q.origin[0] + c[0] as f64 * q.step) as f32,
        (q.origin[1] + c[1] as f64 * q.step) as f32,
        (q.origin[2] + c[2] as f64 * q.step) as f32,
    ]
}

/// The largest magnitude of a normal component code with `bits` bits.
pub fn normal_scale(bits: u32) -> f32 {
    ((1u32 << (bits.clamp(2, NORMAL_BITS) - 1)) - 1) as f32
}

fn snorm(v: f32, scale: f32) -> u32 {
    ((v.clamp(-1.0, 1.0) * scale).round() as i32 as i16) as u16 as u32
}

fn unsnorm(c: u32, scale: f32) -> f32 {
    (c as u16 as i16) as f32 / scale
}

/// Octahedral code of a normal with `bits` bits per component (any length; zero or non-finite
/// gives +Z): two i16 of magnitude at most [`normal_scale`]`(bits)`.
pub fn encode_normal(n: [f32; 3], bits: u32) -> u32 {
    let scale = normal_scale(bits);
    let l = n[0].abs() + n[1].abs() + n[2].abs();
    if !(l.is_finite() && l > 0.0) {
        return snorm(0.0, scale) | snorm(0.0, scale) << 16;
    }
    let (mut x, mut y, z) = (n[0] / l, n[1] / l, n[2] / l);
    if z < 0.0 {
        let (ox, oy) = (x, y);
        x = (1.0 - oy.abs()) * if ox >= 0.0 { 1.0 } else { -1.0 };
        y = (1.0 - ox.abs()) * if oy >= 0.0 { 1.0 } else { -1.0 };
    }
    snorm(x, scale) | snorm(y, scale) << 16
}

/// Unit normal of an octahedral code of `bits` bits per component (as
/// `shaders_glsl/common/raster.glsl` decodes it).
pub fn decode_normal(code: u32, bits: u32) -> [f32; 3] {
    let scale = normal_scale(bits);
    let x = unsnorm(code & 0xffff, scale);
    let y = unsnorm(code >> 16, scale);
    let z = 1.0 - x.abs() - y.abs();
    let t = (-z).max(0.0);
    let x = x + if x >= 0.0 { -t } else { t };
    let y = y + if y >= 0.0 { -t } else { t };
    let l = (x * x + y * y + z * z).sqrt();
    if l > 0.0 {
        [x / l, y / l, z / l]
    } else {
        [0.0, 0.0, 1.0]
    }
}

/// 16-bit code of a UV over the mesh's UV range.
pub fn encode_uv(q: &Quantization, uv: [f32; 2]) -> u32 {
    let mut code = 0u32;
    for (k, &uvk) in uv.iter().enumerate() {
        let range = q.uv_max[k] as f64 - q.uv_min[k] as f64;
        let t = if range > 0.0 {
            ((uvk as f64 - q.uv_min[k] as f64) / range * 65535.0).round()
        } else {
            0.0
        };
        let t = if t.is_finite() {
            t.clamp(0.0, 65535.0) as u32
        } else {
            0
        };
        code |= t << (16 * k);
    }
    code
}

/// UV of a 16-bit code.
pub fn decode_uv(q: &Quantization, code: u32) -> [f32; 2] {
    let mut uv = [0.0f32; 2];
    for (k, out) in uv.iter_mut().enumerate() {
        let range = q.uv_max[k] as f64 - q.uv_min[k] as f64;
        let t = ((code >> (16 * k)) & 0xffff) as f64 / 65535.0;
        *out = (q.uv_min[k] as f64 + t * range) as f32;
    }
    uv
}
