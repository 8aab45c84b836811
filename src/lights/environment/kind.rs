//! The environment as a light kind: photons from the disc of the scene's bounding sphere two
//! radii out towards their direction (uniform for a constant environment, by the map's
//! distribution for an image, weighed `L pi R^2 / (pdf power)`), shadow rays by
//! [`sampling::sample_direction`] to a distant target. Twin: `environment_*` in
//! `src/lights/environment/environment.wgsl`.

use crate::lights::environment::sampling;
use crate::lights::environment::Environment;
use crate::lights::interface::{word, Emission, LightContext, LightKind, LightSample, ParamWords};
use glam::Vec3;

impl LightKind for Environment {
    fn emit(&self, c: &LightContext, u: [f32; 5]) -> Emission {
        let (w, pdf) = sampling::emit_direction(self, c.env, [u[0], u[3], u[4]]);
        let (centre, r) = c.bounds;
        let scale = match c.env {
            None => Vec3::ONE,
            Some(_) if pdf <= 0.0 => Vec3::ZERO,
            Some(_) => {
                let flux = self.eval(c.textures, w) * (std::f32::consts::PI * r * r / pdf);
                Vec3::select(c.power.cmpgt(Vec3::ZERO), flux / c.power, Vec3::ZERO)
            }
        };
        Emission {
            origin: centre + 2.0 * r * w + c.disc(-w, [u[1], u[2]]),
            dir: -w,
            normal: Vec3::ZERO,
            scale,
        }
    }
    fn sample(&self, c: &LightContext, x: Vec3, ns: Vec3, u: [f32; 3]) -> LightSample {
        let (dir, pdf) = sampling::sample_direction(self, c.env, ns, u);
        let weight = if pdf > 0.0 {
            self.eval(c.textures, dir) / pdf
        } else {
            Vec3::ZERO
        };
        LightSample::delta(x + dir, weight, true)
    }
    fn anchor(&self, _c: &LightContext, _u: [f32; 3]) -> Option<Vec3> {
        None
    }
    fn direction_pdf(&self, c: &LightContext, ns: Vec3, dir: Vec3) -> f32 {
        sampling::direction_pdf(self, c.env, ns, dir)
    }
    /// Its distribution follows the triangle CDFs in `light_cdf` (from `cdf_start`); the
    /// third word holds `power / (pi R^2)`, so that a photon's scale is `L / (pdf mean)`.
    fn gpu_words(&self, c: &LightContext) -> ParamWords {
        let (centre, r) = c.bounds;
        let disc = std::f32::consts::PI * r * r;
        [
            word(centre, r.to_bits()),
            word(self.radiance, c.cdf_start),
            word(c.power / disc, self.texture),
            [0; 4],
        ]
    }
}
