//! Environment lights: radiance arriving from infinitely far away along every ray that
//! leaves the scene. A constant one (Mitsuba's `constant`, TOML `radiance`) or a lat-long
//! image (Mitsuba's `envmap`), looked up as Mitsuba 3 looks it up: `u = atan2(x, -z) / 2 pi`,
//! `v = acos(y) / pi` in the map's frame, texel column `i` centred at `u = (i + 0.5) / W`
//! (periodic), row `j` at `v = j / (H - 1)`, bilinear. A scene has at most one; the builder
//! makes it the last light ([`Scene::environment`]). Its power is the flux through a disc of
//! the bounding sphere's radius R facing each direction: `pi R^2` times the integral of the
//! radiance over the sphere of directions (`4 pi^2 R^2 L` for a constant L).

use crate::textures::{SceneTexture, Texture, NO_TEXTURE};
use glam::{Mat3, Vec2, Vec3};
use std::f32::consts::PI;

/// Luminance of linear RGB (Rec. 709 weights, Mitsuba's `luminance`).
pub fn luminance(c: Vec3) -> f32 {
    0.212_671 * c.x + 0.715_160 * c.y + 0.072_169 * c.z
}

/// An environment light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Environment {
    /// A constant environment's radiance; an image's scale on its texels.
    pub radiance: Vec3,
    /// Index into [`Scene::textures`] of the lat-long image, or [`NO_TEXTURE`] (constant).
    pub texture: u32,
    /// The map's frame to world (the rotation of Mitsuba's `to_world`).
    pub to_world: Mat3,
}

impl Environment {
    /// A constant environment of radiance `radiance`.
    pub fn constant(radiance: Vec3) -> Self {
        Environment {
            radiance,
            texture: NO_TEXTURE,
            to_world: Mat3::IDENTITY,
        }
    }

    /// Radiance arriving from unit direction `dir` (the direction of a ray leaving the scene).
    pub fn eval(&self, textures: &[SceneTexture], dir: Vec3) -> Vec3 {
        match self.texture {
            NO_TEXTURE => self.radiance,
            t => {
                let SceneTexture::Bitmap(image) = &textures[t as usize] else {
                    return Vec3::ZERO;
                };
                self.radiance * latlong_lookup(image, latlong_uv(self.to_world.transpose() * dir))
            }
        }
    }
}

/// Mitsuba's `direction_to_uv` of a unit direction in the map's frame.
pub fn latlong_uv(d: Vec3) -> Vec2 {
    let u = d.x.atan2(-d.z) * (0.5 / PI);
    let v = d.y.clamp(-1.0, 1.0).acos() * (1.0 / PI);
    Vec2::new(u, v)
}

/// Mitsuba's `uv_to_direction`: the unit direction in the map's frame at `uv`.
pub fn latlong_dir(uv: Vec2) -> Vec3 {
    let (sin_t, cos_t) = (uv.y * PI).sin_cos();
    let (sin_p, cos_p) = (uv.x * 2.0 * PI).sin_cos();
    Vec3::new(sin_p * sin_t, cos_t, -cos_p * sin_t)
}

/// The image at `uv` as Mitsuba's `envmap` filters it: `u` wraps with column `i` centred at
/// `(i + 0.5) / W`, `v` clamps with row `j` at `j / (H - 1)`, bilinear.
pub fn latlong_lookup(t: &Texture, uv: Vec2) -> Vec3 {
    let (w, h) = (t.width as i64, t.height as i64);
    let x = (uv.x - uv.x.floor()) * w as f32 - 0.5;
    let y = uv.y.clamp(0.0, 1.0) * (h - 1).max(0) as f32;
    let (fx, fy) = (x.floor(), y.floor());
    let (tx, ty) = (x - fx, y - fy);
    let (x0, y0) = (fx as i64, fy as i64);
    let fetch = |i: i64, j: i64| {
        let i = i.rem_euclid(w) as u32;
        let j = j.clamp(0, h - 1) as u32;
        t.texel(i, j).truncate()
    };
    let row0 = fetch(x0, y0) * (1.0 - tx) + fetch(x0 + 1, y0) * tx;
    let row1 = fetch(x0, y0 + 1) * (1.0 - tx) + fetch(x0 + 1, y0 + 1) * tx;
    row0 * (1.0 - ty) + row1 * ty
}

/// The integral of an image environment's texels over the sphere of directions (before its
/// scale): the midpoint rule on a grid twice the image's resolution.
pub fn image_integral(t: &Texture) -> Vec3 {
    let (nu, nv) = (2 * t.width.max(1), 2 * t.height.max(1));
    let mut sum = glam::DVec3::ZERO;
    for j in 0..nv {
        let v = (j as f32 + 0.5) / nv as f32;
        let sin_t = (v * PI).sin() as f64;
        for i in 0..nu {
            let u = (i as f32 + 0.5) / nu as f32;
            sum += latlong_lookup(t, Vec2::new(u, v)).as_dvec3() * sin_t;
        }
    }
    // dw = 2 pi^2 sin(theta) du dv.
    (sum * (2.0 * std::f64::consts::PI.powi(2) / (nu as f64 * nv as f64))).as_vec3()
}

mod kind;
pub mod sampling;
pub mod setup;
