//! The 64-bit visibility buffer of [`FrameBuffers`]: clearing it before the rasterizers and reading
//! it back, on both storage paths ([`VisBuffer::Buffer`], [`VisBuffer::Image`]).
//!
//! Each pixel is `depth bits << 32 | visible index << VISBUFFER_TRIANGLE_BITS | triangle`, 0 = empty
//! (see [`unpack`]). Rows are top to bottom, `width` pixels each, on both paths.

use crate::gpu::{Cmd, GpuError, GpuResult};
use crate::passes::{FrameBuffers, VisBuffer};
use crate::shared::VISBUFFER_TRIANGLE_BITS;

/// Clears the visibility buffer to 0 (empty). The image path leaves the image in `GENERAL` layout.
/// The caller orders this before the rasterizers with a transfer -> shader barrier.
pub fn clear(cmd: &mut Cmd, fb: &FrameBuffers) {
    match &fb.visbuffer {
        VisBuffer::Buffer(b) => cmd.fill_buffer(b, 0),
        VisBuffer::Image(i) => cmd.clear_image_zero(i),
    }
}

/// Reads the visibility buffer back (after the frame's submission completed): `width * height`
/// values, row-major.
pub fn download(fb: &FrameBuffers) -> GpuResult<Vec<u64>> {
    let bytes = match &fb.visbuffer {
        VisBuffer::Buffer(b) => b.download()?,
        VisBuffer::Image(i) => i.download()?,
    };
    let n = fb.width as usize * fb.height as usize;
    if bytes.len() < 8 * n {
        return Err(GpuError::Other(format!(
            "visibility buffer readback has {} bytes, expected {}",
            bytes.len(),
            8 * n
        )));
    }
    Ok(bytes[..8 * n]
        .chunks_exact(8)
        .map(|c| u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]))
        .collect())
}

/// One visibility-buffer value taken apart: `None` when empty, else (depth, visible index, triangle).
pub fn unpack(value: u64) -> Option<(f32, u32, u32)> {
    if value == 0 {
        return None;
    }
    let lo = value as u32;
    Some((
        f32::from_bits((value >> 32) as u32),
        lo >> VISBUFFER_TRIANGLE_BITS,
        lo & ((1 << VISBUFFER_TRIANGLE_BITS) - 1),
    ))
}
