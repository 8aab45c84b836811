//! An emissive analytic sphere with the radiance of its material, sampled uniformly by area.
//! Twin: `src/lights/sphere.wgsl`.

use crate::lights::area::{self, SurfacePoint};
use crate::lights::interface::{Emission, LightContext, LightKind, LightSample, ParamWords};
use crate::math::sampling::uniform_sphere;
use crate::scene::shapes::{Sphere, Triangle};
use glam::Vec3;

/// Emissive sphere `index` of `Scene::spheres`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereLight {
    /// Index into `Scene::spheres`.
    pub index: u32,
}

impl SphereLight {
    /// A uniform point of the sphere (`u[1]`, `u[2]`).
    fn point(&self, c: &LightContext, u: [f32; 3]) -> SurfacePoint {
        let s = &c.spheres[self.index as usize];
        let n = uniform_sphere(u[1], u[2]);
        SurfacePoint {
            p: s.center + s.radius * n,
            n,
            material: s.material,
            texel: area::texel(c, s.uv(n)),
        }
    }
}

impl LightKind for SphereLight {
    fn surface(&self, _triangles: &[Triangle], spheres: &[Sphere]) -> (f32, Vec<f32>) {
        let r = spheres[self.index as usize].radius;
        (4.0 * std::f32::consts::PI * r * r, Vec::new())
    }
    fn material(&self, _triangles: &[Triangle], spheres: &[Sphere]) -> Option<u32> {
        Some(spheres[self.index as usize].material)
    }
    fn emit(&self, c: &LightContext, u: [f32; 5]) -> Emission {
        area::emit(c, self.point(c, [u[0], u[1], u[2]]), u[3], u[4])
    }
    fn sample(&self, c: &LightContext, x: Vec3, _ns: Vec3, u: [f32; 3]) -> LightSample {
        area::sample(c, self.point(c, u), x)
    }
    fn anchor(&self, c: &LightContext, u: [f32; 3]) -> Option<Vec3> {
        Some(self.point(c, u).p)
    }
    fn gpu_words(&self, _c: &LightContext) -> ParamWords {
        [[self.index, 0, 0, 0], [0; 4], [0; 4], [0; 4]]
    }
}
