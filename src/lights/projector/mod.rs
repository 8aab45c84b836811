//! A projector (Mitsuba 3's `projector` emitter): a pinhole that projects an image, the
//! reciprocal of a perspective camera. In its local frame (z along the axis, x and y across)
//! the direction through point `(a, b)` of the image plane at unit distance,
//! `a, b in [-1, 1]` in units of `tan(fov_x / 2)` and `tan(fov_y / 2)`, reads the image at
//! `uv = ((1 - a) / 2, (1 - b) / 2)` (Mitsuba's camera: u grows against local x, v against
//! local y). `irradiance` (a colour, times the image's texel) is what Mitsuba calls the
//! irradiance on that plane: the radiant intensity in a direction at angle `theta` to the
//! axis is `pi E / cos^3 theta`, so a white Lambertian plane across the axis at any distance
//! `z` has radiance `E / z^2` (Mitsuba's `sample_direction`: `pi E / (z^2 cos theta)` per
//! unit of the receiver's cosine). The power is `pi E A` per channel, `A = 4 tan(fov_x / 2)
//! tan(fov_y / 2)` the image plane's area, times the image's mean over the plane
//! (`crate::lights::emission`, multiplied in when the scene is finished).
//!
//! Photons of a projector without an image leave through a uniform point of the image plane
//! (`u[3]`, `u[4]` its uv), so they land uniformly on any plane across the axis. With an
//! image they pass it in proportion to the image (`distribution.rs`: `u[0]` picks a cell,
//! `u[3]`, `u[4]` the point in it), each carrying its texel over the image's mean and the
//! density there. Twin: `projector.wgsl` beside it; the scene builder's call is in `build.rs`.

mod build;
pub mod distribution;

pub use build::ProjectorLight;

use crate::lights::area::texel;
use crate::lights::interface::{word, Emission, LightContext, LightKind, LightSample, ParamWords};
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// A projector: a point source through an image plane (module docs); invisible to the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projector {
    /// Where it is (the pinhole).
    pub position: Vec3,
    /// Half the image plane's width at unit distance along the local x axis:
    /// `tan(fov_x / 2)` times the unit x axis.
    pub x_half: Vec3,
    /// Half its height along the local y axis: `tan(fov_y / 2)` times the unit y axis.
    pub y_half: Vec3,
    /// The unit axis it shines along (local z).
    pub axis: Vec3,
    /// The irradiance on the image plane at unit distance, W/m^2 per channel, before the
    /// image's texel (Mitsuba's `irradiance` times its `scale`).
    pub irradiance: Vec3,
    /// The image it projects (its index in the scene's textures), if any; it is the light's
    /// emission texture (`crate::lights::emission::texture_of`).
    pub texture: Option<u32>,
}

impl Projector {
    /// The image plane's uv of the direction through `p - position` (module docs) and that
    /// vector's component along the axis; `None` behind the projector or outside the image.
    pub fn uv(&self, to_x: Vec3) -> Option<(Vec2, f32)> {
        let z = to_x.dot(self.axis);
        let a = to_x.dot(self.x_half) / (self.x_half.length_squared() * z);
        let b = to_x.dot(self.y_half) / (self.y_half.length_squared() * z);
        let uv = Vec2::new(0.5 - 0.5 * a, 0.5 - 0.5 * b);
        let inside = z > 0.0 && uv.cmpge(Vec2::ZERO).all() && uv.cmple(Vec2::ONE).all();
        inside.then_some((uv, z))
    }

    /// The image plane's area at unit distance, `4 tan(fov_x / 2) tan(fov_y / 2)`.
    pub fn plane_area(&self) -> f32 {
        4.0 * self.x_half.length() * self.y_half.length()
    }

    /// The mean of `texture` over the image (its uv square), by the midpoints of a 256 x 256
    /// grid: the mean the photons' texels are divided by.
    pub fn texture_mean(texture: &SceneTexture) -> Vec3 {
        let n = 256;
        let mut sum = glam::DVec3::ZERO;
        for j in 0..n {
            for i in 0..n {
                let uv = Vec2::new((i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32);
                sum += texture.eval(uv).as_dvec3();
            }
        }
        (sum / (n * n) as f64).as_vec3()
    }
}

impl LightKind for Projector {
    fn is_delta(&self) -> bool {
        true
    }
    /// A photon through the image plane's point of uv `(u[3], u[4])` without an image, else
    /// through a point of the cell `u[0]` picks (module docs), carrying the texel there over
    /// the image's mean and the density.
    fn emit(&self, c: &LightContext, u: [f32; 5]) -> Emission {
        let (uv, pdf) = match self.texture {
            Some(_) => {
                let (corner, size, pdf) = distribution::pick(c.cdf, u[0]);
                let uv = Vec2::new(corner[0] + u[3] * size[0], corner[1] + u[4] * size[1]);
                (uv, pdf)
            }
            None => (Vec2::new(u[3], u[4]), 1.0),
        };
        let (a, b) = (1.0 - 2.0 * uv.x, 1.0 - 2.0 * uv.y);
        let dir = (self.axis + a * self.x_half + b * self.y_half).normalize();
        let mean = c.texture_mean * pdf;
        let t = texel(c, uv);
        Emission {
            origin: self.position,
            dir,
            normal: Vec3::ZERO,
            scale: Vec3::select(mean.cmpgt(Vec3::ZERO), t / mean, Vec3::ZERO),
        }
    }
    /// Its image's distribution (`distribution.rs`; none without an image).
    fn distribution(&self, textures: &[SceneTexture]) -> Vec<f32> {
        match self.texture {
            Some(t) => distribution::image_distribution(&textures[t as usize]),
            None => Vec::new(),
        }
    }
    /// `pi E |to_x| / z^3` (module docs), black outside the image.
    fn sample(&self, c: &LightContext, x: Vec3, _ns: Vec3, _u: [f32; 3]) -> LightSample {
        let to_x = x - self.position;
        let weight = match self.uv(to_x) {
            Some((uv, z)) => {
                let k = std::f32::consts::PI * to_x.length() / (z * z * z);
                self.irradiance * texel(c, uv) * k
            }
            None => Vec3::ZERO,
        };
        LightSample::delta(self.position, weight, false)
    }
    fn anchor(&self, _c: &LightContext, _u: [f32; 3]) -> Option<Vec3> {
        Some(self.position)
    }
    /// p0 = (position, start of its distribution in `light_cdf`), p1..p3 = the half extents
    /// and the axis, their fourth words the irradiance's channels.
    fn gpu_words(&self, c: &LightContext) -> ParamWords {
        let e = self.irradiance;
        [
            word(self.position, c.cdf_start),
            word(self.x_half, e.x.to_bits()),
            word(self.y_half, e.y.to_bits()),
            word(self.axis, e.z.to_bits()),
        ]
    }
}
