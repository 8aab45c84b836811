//! An isotropic point light: radiant intensity in W/sr per channel, invisible to the camera;
//! photons leave uniformly over the sphere. Twin: `src/lights/point/point.wgsl`; the scene
//! builder's call is in `build.rs`.

mod build;

use crate::lights::interface::{word, Emission, LightContext, LightKind, LightSample, ParamWords};
use crate::math::sampling::uniform_sphere;
use glam::Vec3;

/// An isotropic point source.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    /// Where it is.
    pub position: Vec3,
    /// Radiant intensity, W/sr per channel.
    pub intensity: Vec3,
}

impl LightKind for Point {
    fn is_delta(&self) -> bool {
        true
    }
    fn emit(&self, _c: &LightContext, u: [f32; 5]) -> Emission {
        Emission {
            origin: self.position,
            dir: uniform_sphere(u[3], u[4]),
            normal: Vec3::ZERO,
            scale: Vec3::ONE,
        }
    }
    fn sample(&self, _c: &LightContext, x: Vec3, _ns: Vec3, _u: [f32; 3]) -> LightSample {
        let d2 = (self.position - x).length_squared().max(1e-20);
        LightSample::delta(self.position, self.intensity / d2, false)
    }
    fn anchor(&self, _c: &LightContext, _u: [f32; 3]) -> Option<Vec3> {
        Some(self.position)
    }
    fn gpu_words(&self, _c: &LightContext) -> ParamWords {
        [
            word(self.position, 0),
            word(self.intensity, 0),
            [0; 4],
            [0; 4],
        ]
    }
}
