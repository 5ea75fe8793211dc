//! Camera and projection conventions, shared by the GPU passes and the CPU reference.
//!
//! - World space is right-handed, y up. The camera looks along `forward`.
//! - Positions are made camera-relative in f64 before they become f32 (scenes far from the origin).
//! - Projection: reverse-Z with an infinite far plane (`depth = near / view_distance`: 1 at the near
//!   plane, towards 0 far away), and y flipped so that NDC +y points down the image, as Vulkan's
//!   framebuffer does. Pixel (x, y) covers `[x, x+1) x [y, y+1)`; its sample is at the centre.
//! - `ndc -> pixel`: `px = (ndc.x + 1) / 2 * width`, `py = (ndc.y + 1) / 2 * height`.

use glam::{DMat4, DVec3, Mat4, Vec3, Vec4};

/// A perspective camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Eye position in world space, f64 (the frame is rendered camera-relative).
    pub position: DVec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// Up hint (need not be orthogonal to `forward`).
    pub up: Vec3,
    /// Vertical field of view in radians.
    pub fov_y: f32,
    /// Near plane distance (> 0).
    pub near: f32,
}

impl Camera {
    /// A camera at `eye` looking at `target`.
    pub fn look_at(eye: DVec3, target: DVec3, up: Vec3, fov_y: f32, near: f32) -> Self {
        let dir = (target - eye).as_vec3();
        let forward = if dir.length_squared() > 0.0 {
            dir.normalize()
        } else {
            Vec3::NEG_Z
        };
        let up = if forward.cross(up).length_squared() < 1e-12 {
            Vec3::Z
        } else {
            up
        };
        Self {
            position: eye,
            forward,
            up,
            fov_y,
            near,
        }
    }

    /// A camera that frames the box `[lo, hi]` from the front-right-above, the whole box in view.
    pub fn frame_bounds(lo: DVec3, hi: DVec3, aspect: f32) -> Self {
        let center = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-6);
        let fov_y = 45f32.to_radians();
        let fov_min = if aspect >= 1.0 {
            fov_y
        } else {
            2.0 * ((fov_y * 0.5).tan() * aspect).atan()
        };
        let dist = radius / (fov_min as f64 * 0.5).sin() * 1.02;
        let dir = DVec3::new(0.35, 0.3, 1.0).normalize();
        let near = (dist - radius).max(radius * 1e-3) as f32 * 0.5;
        Self::look_at(center + dir * dist, center, Vec3::Y, fov_y, near)
    }

    /// View rotation only: camera-relative world -> view space.
    pub fn view_rotation(&self) -> Mat4 {
        Mat4::look_to_rh(Vec3::ZERO, self.forward, self.up)
    }

    /// Reverse-Z infinite projection with y pointing down in NDC.
    pub fn projection(&self, aspect: f32) -> Mat4 {
        let mut p = Mat4::perspective_infinite_reverse_rh(self.fov_y, aspect, self.near);
        p.y_axis.y = -p.y_axis.y;
        p
    }

    /// Projection * view rotation, applied to camera-relative positions.
    pub fn view_proj(&self, width: u32, height: u32) -> Mat4 {
        self.projection(width as f32 / height.max(1) as f32) * self.view_rotation()
    }

    /// The projection of the sub-rectangle `[x0, x0 + width) x [y0, y0 + height)` (pixels) of a
    /// `full_width` x `full_height` image, onto a `width` x `height` target: the same rays as
    /// [`Camera::view_proj`] of the full image, the rectangle's pixels mapped one to one (an
    /// off-centre projection). Renders a large image in tiles; depth is unchanged.
    pub fn view_proj_window(
        &self,
        (full_width, full_height): (u32, u32),
        (x0, y0): (u32, u32),
        (width, height): (u32, u32),
    ) -> Mat4 {
        // Full-image NDC to the rectangle's NDC: ndc' = s ndc + o per axis, in clip space
        // x' = s x + o w (w unchanged, so depth is too).
        let axis = |full: u32, start: u32, size: u32| {
            let s = full as f64 / size.max(1) as f64;
            let o = (full as f64 - 2.0 * start as f64) / size.max(1) as f64 - 1.0;
            (s as f32, o as f32)
        };
        let (sx, ox) = axis(full_width, x0, width);
        let (sy, oy) = axis(full_height, y0, height);
        let window = Mat4::from_cols(
            Vec4::new(sx, 0.0, 0.0, 0.0),
            Vec4::new(0.0, sy, 0.0, 0.0),
            Vec4::new(0.0, 0.0, 1.0, 0.0),
            Vec4::new(ox, oy, 0.0, 1.0),
        );
        window * self.view_proj(full_width, full_height)
    }

    /// `model` made camera-relative (translation minus the camera position, in f64), as f32.
    pub fn relative_model(&self, model: &DMat4) -> Mat4 {
        let rel = DMat4::from_translation(-self.position) * *model;
        rel.as_mat4()
    }
}

/// Projects a camera-relative point to (pixel x, pixel y, depth, clip w); `None` behind the eye.
pub fn project_to_pixel(view_proj: &Mat4, p: Vec3, width: u32, height: u32) -> Option<[f32; 4]> {
    let c: Vec4 = *view_proj * p.extend(1.0);
    if c.w <= 0.0 {
        return None;
    }
    let ndc = c.truncate() / c.w;
    Some([
        (ndc.x + 1.0) * 0.5 * width as f32,
        (ndc.y + 1.0) * 0.5 * height as f32,
        ndc.z,
        c.w,
    ])
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A point lands in a tile's projection at its full-image pixel minus the tile's corner, with
    /// the same depth; the whole image as its own tile is the plain projection.
    #[test]
    fn window_projection_maps_pixels_of_the_rectangle() {
        let cam = Camera::look_at(
            DVec3::new(1.0, 2.0, 3.0),
            DVec3::ZERO,
            Vec3::Y,
            50f32.to_radians(),
            0.01,
        );
        let full = (640, 360);
        assert_eq!(
            cam.view_proj_window(full, (0, 0), full),
            cam.view_proj(full.0, full.1)
        );
        let vp = cam.view_proj(full.0, full.1);
        for (corner, size) in [
            ((0, 0), (256, 256)),
            ((384, 256), (256, 104)),
            ((100, 7), (33, 20)),
        ] {
            let win = cam.view_proj_window(full, corner, size);
            for p in [Vec3::new(-1.0, -2.0, -3.0), Vec3::new(-0.7, -1.5, -3.2)] {
                let a = project_to_pixel(&vp, p, full.0, full.1).unwrap();
                let b = project_to_pixel(&win, p, size.0, size.1).unwrap();
                assert!((a[0] - corner.0 as f32 - b[0]).abs() < 1e-3, "{a:?} {b:?}");
                assert!((a[1] - corner.1 as f32 - b[1]).abs() < 1e-3, "{a:?} {b:?}");
                assert!((a[2] - b[2]).abs() <= 1e-7 * a[2].abs() && a[3] == b[3]);
            }
        }
    }
}
