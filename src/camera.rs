//! Pinhole camera with the reference conventions: raster (px, py) in `[0,W]x[0,H]`, row 0 at
//! the top, maps to `forward + (2px/W - 1) tan(fov/2) (W/H) right + (1 - 2py/H) tan(fov/2) up`.

use glam::Vec3;

/// A pinhole camera, stored in the form the ray generator needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The pinhole's position.
    pub eye: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// `right * tan(fov/2)` (the aspect ratio is applied per image size).
    pub right: Vec3,
    /// `true_up * tan(fov/2)`.
    pub up: Vec3,
}

impl Camera {
    /// A camera at `eye` looking at `target`; `fov_y_deg` is the full vertical field of view.
    /// Returns `None` when the frame is degenerate (eye == target or up parallel to the view).
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3, fov_y_deg: f32) -> Option<Self> {
        let forward = (target - eye).try_normalize()?;
        let right = forward.cross(up).try_normalize()?;
        let true_up = right.cross(forward);
        let t = (fov_y_deg.to_radians() * 0.5).tan();
        if !(t.is_finite() && t > 0.0) {
            return None;
        }
        Some(Self {
            eye,
            forward,
            right: right * t,
            up: true_up * t,
        })
    }

    /// Unit direction through raster position (px, py) of a `width` x `height` image.
    pub fn direction(&self, px: f32, py: f32, width: u32, height: u32) -> Vec3 {
        let sx = (2.0 * px / width as f32 - 1.0) * (width as f32 / height as f32);
        let sy = 1.0 - 2.0 * py / height as f32;
        (self.forward + sx * self.right + sy * self.up).normalize()
    }
}
