//! What a render produces, independent of the path that made it.

use std::path::Path;

use glam::{DMat4, Vec3};

/// One placed copy of a mesh.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Placement {
    /// Index into the mesh list.
    pub mesh: u32,
    /// Object -> world, in f64 (made camera-relative before it becomes f32).
    pub transform: DMat4,
    /// Albedo tint.
    pub color: [f32; 3],
}

/// How much an object-space length (a LOD error, a bounding radius) can grow under `transform`:
/// the largest length of its linear part's axes, computed in f32 from the f32 axes the GPU gets.
/// The one scale factor of every pixel-error test: vgeo's culls (`InstanceVgeo::max_scale`) and
/// lod's level selection, so that "N px" means the same in both.
pub fn max_axis_scale(transform: &DMat4) -> f32 {
    let axis = |v: glam::DVec4| v.truncate().as_vec3().length();
    axis(transform.x_axis)
        .max(axis(transform.y_axis))
        .max(axis(transform.z_axis))
}

/// Lighting of a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Light {
    /// Direction towards the light (world space).
    pub direction: Vec3,
}

impl Default for Light {
    fn default() -> Self {
        Self {
            direction: Vec3::new(0.4, 1.0, 0.6).normalize(),
        }
    }
}

/// Background colour of every path (linear RGBA, before the output encoding).
pub const BACKGROUND: [f32; 4] = [0.02, 0.02, 0.03, 1.0];

/// A rendered frame read back to the CPU.
#[derive(Clone, Debug)]
pub struct Frame {
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
    /// RGBA8, row-major, top row first.
    pub color: Vec<u8>,
    /// Reverse-Z depth per pixel; 0.0 where nothing was drawn.
    pub depth: Vec<f32>,
    /// GPU milliseconds per pass (empty without timestamp support).
    pub gpu_ms: Vec<(String, f64)>,
    /// Triangles submitted for drawing.
    pub triangles: u64,
}

impl Frame {
    /// Total GPU time of all passes.
    pub fn gpu_total_ms(&self) -> f64 {
        self.gpu_ms.iter().map(|(_, ms)| ms).sum()
    }

    /// Pixels where something was drawn.
    pub fn covered(&self) -> usize {
        self.depth.iter().filter(|d| **d > 0.0).count()
    }

    /// Writes the colour image as PNG.
    pub fn save_png(&self, path: &Path) -> anyhow::Result<()> {
        let img = image::RgbaImage::from_raw(self.width, self.height, self.color.clone())
            .ok_or_else(|| anyhow::anyhow!("frame buffer has the wrong size"))?;
        img.save(path)
            .map_err(|e| anyhow::anyhow!("cannot write {}: {e}", path.display()))
    }
}
