//! The camera with the reference conventions: raster (px, py) in `[0,W]x[0,H]`, row 0 at the
//! top, maps to `forward + (2px/W - 1) tan(fov/2) (W/H) right + (1 - 2py/H) tan(fov/2) up`.
//! A pinhole by default; with an aperture, a thin lens (Mitsuba's `thinlens`) focused on the
//! plane `focus_distance` along `forward`. An orthographic camera's rays all travel along
//! `forward`, from `eye + (2px/W - 1) (W/H) right + (1 - 2py/H) up` (`right` and `up` then
//! being the view's half-height in scene units, along each axis). Its pixel filter says where
//! in (and around) the pixel samples fall ([`crate::camera::pixel_filter`]). Twin:
//! `src/camera/camera.wgsl`.

pub mod pixel_filter;

use crate::camera::pixel_filter::{concentric_disc, PixelFilter};
use glam::Vec3;

/// A camera, stored in the form the ray generator needs.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// The pinhole's position (the lens centre).
    pub eye: Vec3,
    /// Unit view direction.
    pub forward: Vec3,
    /// `right * tan(fov/2)` (the aspect ratio is applied per image size).
    pub right: Vec3,
    /// `true_up * tan(fov/2)`.
    pub up: Vec3,
    /// The thin lens's aperture radius, scene units (0: a pinhole).
    pub aperture_radius: f32,
    /// Distance from the lens to the plane in focus, along `forward` (scene units).
    pub focus_distance: f32,
    /// The reconstruction filter the pixel jitter follows.
    pub filter: PixelFilter,
    /// Parallel rays along `forward` (no lens), `right` and `up` the view's half-height.
    pub orthographic: bool,
}

impl Camera {
    /// A pinhole camera at `eye` looking at `target` (focused there) with a box filter;
    /// `fov_y_deg` is the full vertical field of view. Returns `None` when the frame is degenerate (eye ==
    /// target or up parallel to the view).
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
            aperture_radius: 0.0,
            focus_distance: (target - eye).length(),
            filter: PixelFilter::Box,
            orthographic: false,
        })
    }

    /// An orthographic camera at `eye` looking at `target` whose view is `half_height` scene
    /// units from its centre to its top edge (the width follows the image's aspect). `None`
    /// when the frame is degenerate or `half_height` is not positive and finite.
    pub fn orthographic(eye: Vec3, target: Vec3, up: Vec3, half_height: f32) -> Option<Self> {
        if !(half_height.is_finite() && half_height > 0.0) {
            return None;
        }
        let forward = (target - eye).try_normalize()?;
        let right = forward.cross(up).try_normalize()?;
        Some(Self {
            right: right * half_height,
            up: right.cross(forward) * half_height,
            orthographic: true,
            ..Self::look_at(eye, target, up, 90.0)?
        })
    }

    /// Unit direction through raster position (px, py) of a `width` x `height` image (from
    /// the lens centre).
    pub fn direction(&self, px: f32, py: f32, width: u32, height: u32) -> Vec3 {
        self.film_direction(px, py, width, height).normalize()
    }

    /// The unnormalised direction through (px, py): its `forward` component is 1.
    fn film_direction(&self, px: f32, py: f32, width: u32, height: u32) -> Vec3 {
        let (sx, sy) = film_xy(px, py, width, height);
        self.forward + sx * self.right + sy * self.up
    }

    /// Whether the camera has a lens (and so draws a lens sample per camera ray).
    pub fn is_thin_lens(&self) -> bool {
        self.aperture_radius > 0.0
    }

    /// The camera ray `(origin, unit direction)` through raster position (px, py); `lens` in
    /// [0, 1)^2 picks the point on the aperture (unused by a pinhole). A thin lens's rays
    /// through (px, py) all meet at the pinhole ray's point at depth `focus_distance`.
    pub fn ray(&self, px: f32, py: f32, width: u32, height: u32, lens: (f32, f32)) -> (Vec3, Vec3) {
        if self.orthographic {
            let (sx, sy) = film_xy(px, py, width, height);
            return (self.eye + sx * self.right + sy * self.up, self.forward);
        }
        if !self.is_thin_lens() {
            return (self.eye, self.direction(px, py, width, height));
        }
        let focus = self.focus_distance * self.film_direction(px, py, width, height);
        let (a, b) = concentric_disc(lens.0, lens.1);
        let on_lens = self.aperture_radius * (a * self.right.normalize() + b * self.up.normalize());
        (self.eye + on_lens, (focus - on_lens).normalize())
    }
}

/// Raster (px, py) of a `width` x `height` image as film coordinates: x in `[-W/H, W/H]`
/// rightwards, y in `[-1, 1]` upwards.
fn film_xy(px: f32, py: f32, width: u32, height: u32) -> (f32, f32) {
    let sx = (2.0 * px / width as f32 - 1.0) * (width as f32 / height as f32);
    (sx, 1.0 - 2.0 * py / height as f32)
}

/// The vertical field of view, degrees, of the default view of a scene without a camera: the
/// Khronos glTF-Sample-Viewer's default `yfov` (45 degrees).
pub const DEFAULT_FOV_Y: f32 = 45.0;

/// The Khronos glTF-Sample-Viewer's default view of the bounds `min..max` (its
/// `UserCamera.fitViewToScene`) for an image of `aspect` = width / height, as
/// `(eye, target)`: looking down -z, up +y, at the box's centre from distance
/// `d = max(s / 2 / tan(yfov / 2), s / 2 / tan(yfov aspect / 2))` along +z, `s` the larger of
/// the box's x and y extents (its depth is not counted, as in the viewer: a box's plane
/// through its centre fills the image's larger side; nearer parts may overflow). A box with
/// no x or y extent uses its z extent, or 1.
pub fn fit_view(min: Vec3, max: Vec3, aspect: f32) -> (Vec3, Vec3) {
    let size = max - min;
    let mut s = size.x.max(size.y);
    if s <= 0.0 {
        s = if size.z > 0.0 { size.z } else { 1.0 };
    }
    let yfov = DEFAULT_FOV_Y.to_radians();
    let zoom = |fov: f32| s / 2.0 / (fov / 2.0).tan();
    let (y_zoom, x_zoom) = (zoom(yfov), zoom(yfov * aspect));
    // A horizontal fov past 180 degrees (tan < 0) never limits the distance.
    let d = if x_zoom > 0.0 {
        y_zoom.max(x_zoom)
    } else {
        y_zoom
    };
    let target = (min + max) / 2.0;
    (target + Vec3::new(0.0, 0.0, d), target)
}
