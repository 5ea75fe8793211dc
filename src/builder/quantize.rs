//! Vertex quantization: positions on a per-mesh grid (21 bits per axis), octahedral normals
//! (2 x 16 bits), UVs (2 x 16 bits over the mesh's UV range). Decoding is deterministic (f64 math,
//! one rounding to f32), so equal codes always decode to equal positions: the cut stays crack-free.

use super::Quantization;

/// Bits per position axis.
pub const POSITION_BITS: u32 = 21;
const POSITION_MAX: u64 = (1 << POSITION_BITS) - 1;

/// The grid for positions in `[lo, hi]` and UVs in `[uv_lo, uv_hi]`.
pub fn make_quantization(
    lo: [f32; 3],
    hi: [f32; 3],
    uv_lo: [f32; 2],
    uv_hi: [f32; 2],
) -> Quantization {
    let extent = (0..3)
        .map(|k| hi[k] as f64 - lo[k] as f64)
        .fold(0.0f64, f64::max);
    let step = if extent > 0.0 {
        extent / POSITION_MAX as f64
    } else {
        1.0
    };
    Quantization {
        origin: [lo[0] as f64, lo[1] as f64, lo[2] as f64],
        step,
        uv_min: uv_lo,
        uv_max: uv_hi,
    }
}

/// Grid code of a position (clamped to the grid).
pub fn encode_position(q: &Quantization, p: [f32; 3]) -> [u32; 2] {
    let mut code = 0u64;
    for (k, &pk) in p.iter().enumerate() {
        let t = ((pk as f64 - q.origin[k]) / q.step).round();
        let t = if t.is_finite() {
            t.clamp(0.0, POSITION_MAX as f64) as u64
        } else {
            0
        };
        code |= t << (POSITION_BITS * k as u32);
    }
    [code as u32, (code >> 32) as u32]
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

/// Position of a grid code.
pub fn decode_position(q: &Quantization, code: [u32; 2]) -> [f32; 3] {
    let c = position_coords(code);
    [
        (q.origin[0] + c[0] as f64 * q.step) as f32,
        (q.origin[1] + c[1] as f64 * q.step) as f32,
        (q.origin[2] + c[2] as f64 * q.step) as f32,
    ]
}

fn snorm16(v: f32) -> u32 {
    ((v.clamp(-1.0, 1.0) * 32767.0).round() as i32 as i16) as u16 as u32
}

fn unsnorm16(c: u32) -> f32 {
    (c as u16 as i16) as f32 / 32767.0
}

/// Octahedral code of a normal (any length; zero or non-finite gives +Z).
pub fn encode_normal(n: [f32; 3]) -> u32 {
    let l = n[0].abs() + n[1].abs() + n[2].abs();
    if !(l.is_finite() && l > 0.0) {
        return snorm16(0.0) | snorm16(0.0) << 16;
    }
    let (mut x, mut y, z) = (n[0] / l, n[1] / l, n[2] / l);
    if z < 0.0 {
        let (ox, oy) = (x, y);
        x = (1.0 - oy.abs()) * if ox >= 0.0 { 1.0 } else { -1.0 };
        y = (1.0 - ox.abs()) * if oy >= 0.0 { 1.0 } else { -1.0 };
    }
    snorm16(x) | snorm16(y) << 16
}

/// Unit normal of an octahedral code.
pub fn decode_normal(code: u32) -> [f32; 3] {
    let x = unsnorm16(code & 0xffff);
    let y = unsnorm16(code >> 16);
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
