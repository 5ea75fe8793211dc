//! Image error against a reference (DESIGN.md, "Measures"): box downsampling, PSNR of the lit
//! image, and the share of pixels whose visible surface differs, against a supersampled reference
//! (`vgeo bench`'s, made by [`crate::baseline::brute::Brute::render_reference`]) or a plain frame.
//!
//! **The reference.** A [`Reference`] pixel holds what `n x n` samples of the truth (brute at
//! `n` times the resolution, samples on a regular grid inside the pixel) saw there: the box
//! filter of their colours (the mean of the encoded 8-bit values, rounded, as the issue's
//! measurements and `tests/faithful.rs` do; not of linear light), how many of them hit geometry,
//! and the smallest and largest of their depths (reverse-Z, so larger is nearer).
//!
//! **Surface difference against it.** A 1-sample test pixel shows one surface, the one at its
//! centre. It shows "a surface the reference sees" when:
//! - it is empty and at least one sample of the reference is empty too, or
//! - it is covered, at least one sample is covered, and its depth lies within the samples' depth
//!   range widened by [`DEPTH_TOLERANCE`] (relative): `d_min (1 - t) <= d <= d_max / (1 - t)`.
//!
//! Otherwise the pixel counts as a surface difference (and as a coverage difference when the
//! reason is coverage alone). Reverse-Z depth is affine in screen space across a plane, so a plane
//! covering the pixel has its centre depth inside the range of its symmetric samples: brute at one
//! sample per pixel is ~0 % away, apart from triangles smaller than the sample spacing and
//! curved surfaces; the floor is measured, not assumed. With one sample per pixel the rule is the
//! old one: coverage differs, or depths differ by more than the tolerance. The cost of the range
//! rule: a wrong surface whose depth happens to fall between the depths of two surfaces the
//! reference sees in that pixel (at a silhouette) is not counted.
//!
//! **Depth error**: over pixels covered in the test and in at least one reference sample, the
//! relative distance from the test depth to the samples' depth range (0 inside it).

use anyhow::{Result, bail};
use serde::Serialize;

use crate::render::Frame;

/// Relative depth difference above which two depths show different surfaces.
pub const DEPTH_TOLERANCE: f32 = 1e-3;

/// Averages `factor` x `factor` blocks of an RGBA8 image `width` x `height` (row-major, top row
/// first): each channel of the `(width / factor) x (height / factor)` result is the rounded mean
/// of its block's encoded values. Panics unless `width` and `height` are multiples of `factor`
/// (> 0) and `rgba` holds `4 width height` bytes.
pub fn box_downsample(rgba: &[u8], width: u32, height: u32, factor: u32) -> Vec<u8> {
    assert!(
        factor > 0 && width.is_multiple_of(factor) && height.is_multiple_of(factor),
        "{width}x{height} is not a multiple of {factor}"
    );
    assert_eq!(rgba.len(), 4 * width as usize * height as usize);
    let (w, f) = (width as usize, factor as usize);
    let (ow, oh) = (w / f, height as usize / f);
    let n = (f * f) as u32;
    let mut out = vec![0u8; ow * oh * 4];
    for y in 0..oh {
        for x in 0..ow {
            let mut sum = [0u32; 4];
            for dy in 0..f {
                let row = ((y * f + dy) * w + x * f) * 4;
                for px in rgba[row..row + 4 * f].chunks_exact(4) {
                    for k in 0..4 {
                        sum[k] += px[k] as u32;
                    }
                }
            }
            for k in 0..4 {
                out[(y * ow + x) * 4 + k] = ((sum[k] + n / 2) / n) as u8;
            }
        }
    }
    out
}

/// Mean squared error of the RGB channels of two RGBA8 images of the same size (8-bit units).
/// Panics when the lengths differ.
pub fn mse_rgb(a: &[u8], b: &[u8]) -> f64 {
    assert_eq!(a.len(), b.len(), "images of different sizes");
    let mut sq = 0.0f64;
    for (pa, pb) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        for k in 0..3 {
            let d = pa[k] as f64 - pb[k] as f64;
            sq += d * d;
        }
    }
    sq / (3 * (a.len() / 4).max(1)) as f64
}

/// PSNR in dB of 8-bit images with mean squared error `mse` (infinite when 0).
pub fn psnr(mse: f64) -> f64 {
    if mse <= 0.0 {
        f64::INFINITY
    } else {
        10.0 * (255.0f64 * 255.0 / mse).log10()
    }
}

/// PSNR in dB of the RGB channels of two RGBA8 images of the same size (infinite when equal).
pub fn psnr_rgb(a: &[u8], b: &[u8]) -> f64 {
    psnr(mse_rgb(a, b))
}

/// A reference image: per pixel what `samples_per_axis`^2 samples saw (see the module
/// documentation). Row-major, top row first.
#[derive(Clone, Debug, PartialEq)]
pub struct Reference {
    pub width: u32,
    pub height: u32,
    /// `n`: the samples of a pixel are an `n x n` grid.
    pub samples_per_axis: u32,
    /// RGBA8, the box filter of the samples' colours.
    pub color: Vec<u8>,
    /// Smallest and largest reverse-Z depth of the covered samples (0 where none is covered).
    pub depth_min: Vec<f32>,
    pub depth_max: Vec<f32>,
    /// Covered samples per pixel (`0..=n*n`).
    pub covered: Vec<u16>,
}

impl Reference {
    /// A reference of `width` x `height` pixels of `n x n` samples, still empty (black, nothing
    /// covered): fill it with [`Reference::add_tile`]. Panics when `n` is 0 or above 255.
    pub fn new(width: u32, height: u32, samples_per_axis: u32) -> Self {
        assert!((1..=255).contains(&samples_per_axis));
        let n = width as usize * height as usize;
        Self {
            width,
            height,
            samples_per_axis,
            color: vec![0; 4 * n],
            depth_min: vec![0.0; n],
            depth_max: vec![0.0; n],
            covered: vec![0; n],
        }
    }

    /// Samples per pixel.
    pub fn spp(&self) -> u32 {
        self.samples_per_axis * self.samples_per_axis
    }

    /// A frame as a one-sample-per-pixel reference.
    pub fn from_frame(frame: &Frame) -> Result<Self> {
        Self::from_supersampled(frame, 1)
    }

    /// The reference of a frame rendered at `n` times the resolution (`n x n` samples per pixel).
    pub fn from_supersampled(frame: &Frame, samples_per_axis: u32) -> Result<Self> {
        let n = samples_per_axis.max(1);
        if !frame.width.is_multiple_of(n) || !frame.height.is_multiple_of(n) {
            bail!(
                "a {}x{} frame is not {n}x{n} samples per pixel",
                frame.width,
                frame.height
            );
        }
        let mut r = Self::new(frame.width / n, frame.height / n, n);
        r.add_tile(0, 0, frame)?;
        Ok(r)
    }

    /// Fills the pixels `[x0, x0 + w) x [y0, y0 + h)` from `tile`, a frame of `w n x h n` samples
    /// (the same camera's projection of that sub-rectangle at `n` times the resolution; see
    /// [`crate::camera::Camera::view_proj_window`]).
    pub fn add_tile(&mut self, x0: u32, y0: u32, tile: &Frame) -> Result<()> {
        let n = self.samples_per_axis;
        let samples = tile.width as usize * tile.height as usize;
        if !tile.width.is_multiple_of(n)
            || !tile.height.is_multiple_of(n)
            || x0 + tile.width / n > self.width
            || y0 + tile.height / n > self.height
            || tile.color.len() != 4 * samples
            || tile.depth.len() != samples
        {
            bail!(
                "a {}x{} tile of {n}x{n} samples per pixel does not fit at ({x0}, {y0}) in a {}x{} reference",
                tile.width,
                tile.height,
                self.width,
                self.height
            );
        }
        let (tw, th) = (tile.width / n, tile.height / n);
        let color = box_downsample(&tile.color, tile.width, tile.height, n);
        let sw = tile.width as usize;
        for y in 0..th as usize {
            for x in 0..tw as usize {
                let (mut lo, mut hi, mut count) = (f32::INFINITY, 0.0f32, 0u16);
                for dy in 0..n as usize {
                    let row = (y * n as usize + dy) * sw + x * n as usize;
                    for &d in &tile.depth[row..row + n as usize] {
                        if d > 0.0 {
                            lo = lo.min(d);
                            hi = hi.max(d);
                            count += 1;
                        }
                    }
                }
                let o = (y0 as usize + y) * self.width as usize + x0 as usize + x;
                let s = y * tw as usize + x;
                self.color[4 * o..4 * o + 4].copy_from_slice(&color[4 * s..4 * s + 4]);
                self.covered[o] = count;
                self.depth_min[o] = if count > 0 { lo } else { 0.0 };
                self.depth_max[o] = hi;
            }
        }
        Ok(())
    }

    /// The reference as a frame (its colour; depth: the nearest sample's), e.g. to save as PNG.
    pub fn to_frame(&self) -> Frame {
        Frame {
            width: self.width,
            height: self.height,
            color: self.color.clone(),
            depth: self.depth_max.clone(),
            gpu_ms: Vec::new(),
            triangles: 0,
        }
    }
}

/// Image error of a frame against a [`Reference`] (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct ImageError {
    /// Share of pixels whose visible surface is none the reference sees there.
    pub surface_diff: f64,
    /// Share of pixels that differ by coverage alone: covered where no sample is, or empty where
    /// every sample is covered.
    pub coverage_diff: f64,
    /// Relative distance of the depth to the reference's depth range, over pixels both cover:
    /// mean and max.
    pub depth_err_mean: f64,
    pub depth_err_max: f64,
    /// Mean squared error of the lit RGB image against the reference's colour (8-bit units).
    pub mse: f64,
    /// PSNR of the lit RGB image in dB; infinite (`null` in JSON) only when the images are equal.
    #[serde(serialize_with = "finite_or_null")]
    pub psnr_db: f64,
}

fn finite_or_null<S: serde::Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    if v.is_finite() {
        s.serialize_f64(*v)
    } else {
        s.serialize_none()
    }
}

/// Compares `test` (one sample per pixel) with `reference` (same size in pixels): see
/// [`ImageError`]. Depth 0 is "nothing drawn" (reverse-Z).
pub fn image_error(reference: &Reference, test: &Frame) -> Result<ImageError> {
    let n = reference.width as usize * reference.height as usize;
    if test.width != reference.width
        || test.height != reference.height
        || test.depth.len() != n
        || test.color.len() != 4 * n
        || reference.color.len() != 4 * n
    {
        bail!(
            "cannot compare a {}x{} frame with a {}x{} reference",
            test.width,
            test.height,
            reference.width,
            reference.height
        );
    }
    let all = reference.spp() as u16;
    let keep = 1.0 - DEPTH_TOLERANCE;
    let (mut surface, mut coverage, mut both) = (0usize, 0usize, 0usize);
    let (mut dsum, mut dmax) = (0.0f64, 0.0f64);
    for (i, &d) in test.depth.iter().enumerate() {
        let count = reference.covered[i];
        if d <= 0.0 {
            if count == all {
                coverage += 1;
                surface += 1;
            }
            continue;
        }
        if count == 0 {
            coverage += 1;
            surface += 1;
            continue;
        }
        both += 1;
        let (lo, hi) = (reference.depth_min[i], reference.depth_max[i]);
        let rel = if d < lo {
            (lo - d) / lo
        } else if d > hi {
            (d - hi) / hi
        } else {
            0.0
        } as f64;
        dsum += rel;
        dmax = dmax.max(rel);
        if d < lo * keep || d * keep > hi {
            surface += 1;
        }
    }
    let mse = mse_rgb(&reference.color, &test.color);
    let pixels = n.max(1) as f64;
    Ok(ImageError {
        surface_diff: surface as f64 / pixels,
        coverage_diff: coverage as f64 / pixels,
        depth_err_mean: if both > 0 { dsum / both as f64 } else { 0.0 },
        depth_err_max: dmax,
        mse,
        psnr_db: psnr(mse),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frame(width: u32, depth: Vec<f32>, color: Vec<u8>) -> Frame {
        Frame {
            width,
            height: depth.len() as u32 / width,
            color,
            depth,
            gpu_ms: Vec::new(),
            triangles: 0,
        }
    }

    #[test]
    fn one_sample_reference_counts_coverage_depth_and_psnr() {
        let a = frame(4, vec![0.5, 0.5, 0.0, 0.2], vec![10; 16]);
        let ra = Reference::from_frame(&a).unwrap();
        assert_eq!(image_error(&ra, &a).unwrap().psnr_db, f64::INFINITY);
        assert_eq!(image_error(&ra, &a).unwrap().surface_diff, 0.0);
        let mut c = vec![10u8; 16];
        c[0] = 20; // one channel off by 10: mse = 100 / 12
        let b = frame(4, vec![0.5, 0.5004, 0.3, 0.21], c);
        let e = image_error(&ra, &b).unwrap();
        // Pixel 1: within 1e-3 relative; pixel 2: coverage; pixel 3: 5 % off.
        assert_eq!(e.coverage_diff, 0.25);
        assert_eq!(e.surface_diff, 0.5);
        assert!((e.depth_err_max - 0.05).abs() < 1e-5, "{}", e.depth_err_max);
        assert!((e.mse - 100.0 / 12.0).abs() < 1e-9);
        assert!((e.psnr_db - psnr(100.0 / 12.0)).abs() < 1e-9 && e.psnr_db.is_finite());
        let small = frame(1, vec![0.5], vec![0; 4]);
        assert!(image_error(&ra, &small).is_err());
    }

    #[test]
    fn box_downsample_averages_blocks() {
        // 4x2 -> 2x1: blocks of 2x2.
        let mut img = vec![0u8; 4 * 8];
        for (i, px) in img.chunks_exact_mut(4).enumerate() {
            px.copy_from_slice(&[i as u8 * 10, 255, 0, (i % 2) as u8]);
        }
        // Left block: pixels 0, 1, 4, 5; right: 2, 3, 6, 7.
        let out = box_downsample(&img, 4, 2, 2);
        assert_eq!(out, vec![25, 255, 0, 1, 45, 255, 0, 1]);
        assert_eq!(box_downsample(&img, 4, 2, 1), img);
        assert_eq!(psnr_rgb(&out, &out), f64::INFINITY);
        let mut off = out.clone();
        off[0] += 3; // mse = 9 / 6
        assert!((psnr_rgb(&out, &off) - psnr(1.5)).abs() < 1e-12);
    }

    #[test]
    fn supersampled_reference_accepts_any_surface_it_sees() {
        // One pixel of 2x2 samples: two on a near surface (0.5), one on a far one (0.1), one empty.
        let ss = frame(2, vec![0.5, 0.1, 0.0, 0.5], vec![100; 16]);
        let r = Reference::from_supersampled(&ss, 2).unwrap();
        assert_eq!((r.width, r.height, r.spp()), (1, 1, 4));
        assert_eq!(r.covered, vec![3]);
        assert_eq!((r.depth_min[0], r.depth_max[0]), (0.1, 0.5));
        let test = |d: f32| image_error(&r, &frame(1, vec![d], vec![100; 4])).unwrap();
        // Near, far, in between (the range rule), empty: all seen by some sample.
        for d in [0.5, 0.1, 0.3, 0.0] {
            assert_eq!(test(d).surface_diff, 0.0, "depth {d}");
        }
        // Nearer than every sample, or farther: a surface the reference does not see there.
        assert_eq!(test(0.6).surface_diff, 1.0);
        assert_eq!(test(0.6).coverage_diff, 0.0);
        assert!((test(0.6).depth_err_max - 0.2).abs() < 1e-6);
        assert_eq!(test(0.05).surface_diff, 1.0);
        // A fully covered pixel shown empty, and an empty one shown covered, differ by coverage.
        let full = Reference::from_supersampled(&frame(2, vec![0.5; 4], vec![0; 16]), 2).unwrap();
        let e = image_error(&full, &frame(1, vec![0.0], vec![0; 4])).unwrap();
        assert_eq!((e.surface_diff, e.coverage_diff), (1.0, 1.0));
        let empty = Reference::from_supersampled(&frame(2, vec![0.0; 4], vec![0; 16]), 2).unwrap();
        let e = image_error(&empty, &frame(1, vec![0.2], vec![0; 4])).unwrap();
        assert_eq!((e.surface_diff, e.coverage_diff), (1.0, 1.0));
        // The colour is the block's mean.
        assert_eq!(r.color, vec![100; 4]);
    }

    #[test]
    fn tiles_fill_their_rectangle() {
        // A 2x1-pixel reference of 2x2 samples from two 2x2-sample tiles.
        let mut r = Reference::new(2, 1, 2);
        r.add_tile(1, 0, &frame(2, vec![0.4; 4], vec![200; 16]))
            .unwrap();
        r.add_tile(0, 0, &frame(2, vec![0.0, 0.2, 0.0, 0.0], vec![40; 16]))
            .unwrap();
        assert_eq!(r.covered, vec![1, 4]);
        assert_eq!(r.depth_max, vec![0.2, 0.4]);
        assert_eq!(&r.color[..4], &[40; 4]);
        assert_eq!(&r.color[4..], &[200; 4]);
        // Out of bounds, or not a whole number of pixels.
        assert!(
            r.add_tile(1, 1, &frame(2, vec![0.4; 4], vec![0; 16]))
                .is_err()
        );
        assert!(
            r.add_tile(0, 0, &frame(3, vec![0.4; 3], vec![0; 12]))
                .is_err()
        );
        assert_eq!(r.to_frame().depth, vec![0.2, 0.4]);
    }
}
