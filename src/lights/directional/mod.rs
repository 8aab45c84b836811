//! A directional (distant) light: parallel light travelling along a direction, delivering its
//! irradiance to a surface facing it; invisible to the camera. Its photons start on a disc of
//! the radius of the scene's bounding sphere across the direction, two radii back from the
//! sphere's centre, so that every photon starts outside the scene. Twin:
//! `src/lights/directional/directional.wgsl`; the scene builder's call is in `build.rs`.

mod build;

use crate::lights::interface::{word, Emission, LightContext, LightKind, LightSample, ParamWords};
use glam::Vec3;

/// Parallel light along `direction`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Directional {
    /// Unit direction the light travels in.
    pub direction: Vec3,
    /// Irradiance on a surface facing the light, W/m^2 per channel.
    pub irradiance: Vec3,
}

impl LightKind for Directional {
    fn is_delta(&self) -> bool {
        true
    }
    fn emit(&self, c: &LightContext, u: [f32; 5]) -> Emission {
        let (centre, r) = c.bounds;
        Emission {
            origin: centre - 2.0 * r * self.direction + c.disc(self.direction, [u[1], u[2]]),
            dir: self.direction,
            normal: Vec3::ZERO,
            scale: Vec3::ONE,
        }
    }
    fn sample(&self, _c: &LightContext, x: Vec3, _ns: Vec3, _u: [f32; 3]) -> LightSample {
        LightSample::delta(x - self.direction, self.irradiance, true)
    }
    fn anchor(&self, _c: &LightContext, _u: [f32; 3]) -> Option<Vec3> {
        None
    }
    fn gpu_words(&self, c: &LightContext) -> ParamWords {
        let (centre, r) = c.bounds;
        [
            word(centre, r.to_bits()),
            word(self.direction, 0),
            word(self.irradiance, 0),
            [0; 4],
        ]
    }
}
