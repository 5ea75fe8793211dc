//! The per-frame view of the vgeo path ([`ViewGpu`]) from a camera and the LOD settings.

use glam::{Mat4, Vec4};

use crate::builder::cut::proj_scale;
use crate::camera::Camera;
use crate::scene_gpu::split_f64;
use crate::shared::ViewGpu;

/// Settings of one vgeo frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrameSettings {
    /// LOD threshold: the largest projected error allowed, in pixels.
    pub error_px: f32,
    /// The SW/HW split: a cluster goes to the HW rasterizer when the edge-length equivalent of
    /// its triangles (`sqrt(2 * sum(A^2) / sum(A))` over their areas, i.e. the side of a square
    /// grid cell of their area-weighted mean area: `builder::size`), projected at the cluster's
    /// nearest point, exceeds this many pixels. 0: every cluster to HW; a huge value: every
    /// cluster not reaching the near plane to SW. Negative ([`FrameSettings::AUTO_HW_THRESHOLD`],
    /// the default): chosen by the renderer from the GPU times of the frames it drew
    /// (`frame::split`): the renderer's own for [`crate::frame::VgeoRenderer::render`], each
    /// view's for a host's frames.
    pub hw_threshold_px: f32,
    /// Zero or more of [`FrameSettings::FORCE_SW`], [`FrameSettings::FORCE_HW`],
    /// [`FrameSettings::NO_FRUSTUM`], [`FrameSettings::COUNT_OVERDRAW`].
    pub flags: u32,
    /// Two-pass occlusion culling against the hierarchical depth buffer.
    pub occlusion: bool,
}

impl FrameSettings {
    /// [`FrameSettings::flags`]: every cluster to the software rasterizer.
    pub const FORCE_SW: u32 = crate::shared::VIEW_FLAG_FORCE_SW;
    /// [`FrameSettings::flags`]: every cluster to the hardware rasterizer.
    pub const FORCE_HW: u32 = crate::shared::VIEW_FLAG_FORCE_HW;
    /// [`FrameSettings::flags`]: no frustum culling (the pure LOD cut).
    pub const NO_FRUSTUM: u32 = crate::shared::VIEW_FLAG_NO_FRUSTUM;
    /// [`FrameSettings::flags`]: count rasterizer writes per pixel (the overdraw view).
    pub const COUNT_OVERDRAW: u32 = crate::shared::VIEW_FLAG_COUNT_OVERDRAW;
    /// The fixed split where none is measured: where the automatic one starts, and what it keeps
    /// on a device without timestamps (pixels).
    pub const DEFAULT_HW_THRESHOLD_PX: f32 = crate::shared::DEFAULT_HW_THRESHOLD_PX;
    /// [`FrameSettings::hw_threshold_px`]: the split chosen by measured cost (the default).
    pub const AUTO_HW_THRESHOLD: f32 = -1.0;

    /// Whether the split is chosen by measured cost ([`FrameSettings::AUTO_HW_THRESHOLD`]).
    pub fn auto_split(&self) -> bool {
        self.hw_threshold_px < 0.0
    }

    /// `hw_threshold_px` where nothing is timed to choose by: a fixed split as given, the
    /// automatic one as the fixed default ([`FrameSettings::DEFAULT_HW_THRESHOLD_PX`], where
    /// the automatic one starts).
    pub fn fixed_split(hw_threshold_px: f32) -> f32 {
        if hw_threshold_px < 0.0 {
            Self::DEFAULT_HW_THRESHOLD_PX
        } else {
            hw_threshold_px
        }
    }

    /// A split as the command line gives it: `auto` ([`FrameSettings::AUTO_HW_THRESHOLD`]) or a
    /// number of pixels, at least 0.
    pub fn parse_hw_threshold(s: &str) -> Result<f32, String> {
        if s == "auto" {
            return Ok(Self::AUTO_HW_THRESHOLD);
        }
        match s.parse::<f32>() {
            Ok(v) if v >= 0.0 => Ok(v),
            _ => Err(format!("`{s}`: `auto` or a number of pixels >= 0")),
        }
    }
}

impl Default for FrameSettings {
    fn default() -> Self {
        Self {
            error_px: 1.0,
            hw_threshold_px: Self::AUTO_HW_THRESHOLD,
            flags: 0,
            occlusion: true,
        }
    }
}

/// Frustum planes of a camera-relative view-projection (inside: `dot(n, p) + d >= 0`), normalized:
/// left, right, top, bottom, near. The far plane is at infinity.
pub fn frustum_planes(vp: &Mat4) -> [Vec4; 5] {
    let r0 = vp.row(0);
    let r1 = vp.row(1);
    let r2 = vp.row(2);
    let r3 = vp.row(3);
    // Reverse-Z infinite: depth = z/w in [0, 1] means z <= w (near plane) and z >= 0 (always).
    [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r3 - r2].map(|p| p / p.truncate().length().max(1e-30))
}

/// The [`ViewGpu`] of `camera` for a `width` x `height` image.
pub fn view_gpu(
    camera: &Camera,
    width: u32,
    height: u32,
    settings: &FrameSettings,
    instance_count: u32,
    queue_capacity: u32,
    visible_capacity: u32,
) -> ViewGpu {
    let vp = camera.view_proj(width, height);
    let (hx, lx) = split_f64(camera.position.x);
    let (hy, ly) = split_f64(camera.position.y);
    let (hz, lz) = split_f64(camera.position.z);
    ViewGpu {
        view_proj: vp.to_cols_array_2d(),
        frustum: frustum_planes(&vp).map(|p| p.to_array()),
        camera_hi: [hx, hy, hz, 0.0],
        camera_lo: [lx, ly, lz, 0.0],
        viewport: [
            width as f32,
            height as f32,
            1.0 / width as f32,
            1.0 / height as f32,
        ],
        proj_scale: proj_scale(height as f32, camera.fov_y),
        error_px: settings.error_px,
        hw_threshold_px: settings.hw_threshold_px,
        near: camera.near,
        instance_count,
        flags: settings.flags,
        queue_capacity,
        visible_capacity,
    }
}

/// The material passes' view (mirrors `MaterialViewGpu` in shaders_glsl/common/material.glsl);
/// `material_classify`, `emit_gbuffer` and `shade` read it.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, bytemuck::Pod, bytemuck::Zeroable)]
pub struct MaterialViewGpu {
    /// Inverse of the camera-relative `view_proj`.
    pub inv_view_proj: [[f32; 4]; 4],
    /// Towards the light (world space), normalized.
    pub light_dir: [f32; 4],
    /// sRGB-encoded background.
    pub background: [f32; 4],
    /// Width, height, 1/width, 1/height.
    pub viewport: [f32; 4],
    pub tiles_x: u32,
    pub tiles_y: u32,
    /// Materials in the scene's table.
    pub material_count: u32,
    /// Capacity of the visible-cluster list (larger indices are ignored).
    pub visible_capacity: u32,
    /// `shade`'s output: 0 shaded, 1 albedo, 2 normals, 3 materials.
    pub mode: u32,
    /// Non-zero: `emit_gbuffer` counts its fragments per material.
    pub count_fragments: u32,
    /// `SHADE_FLAG_*` (`crate::shared::SHADE_FLAG_COVERED_ONLY`).
    pub flags: u32,
    pub _pad: u32,
}
const _: () = assert!(size_of::<MaterialViewGpu>() == 144);
