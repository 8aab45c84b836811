//! An emissive mesh: triangles `first..first + count` of the scene (one emissive shape) with
//! the radiance of their material, sampled by area through their CDF. Twin:
//! `src/lights/triangles.wgsl`.

use crate::lights::area::{self, SurfacePoint};
use crate::lights::interface::{Emission, LightContext, LightKind, LightSample, ParamWords};
use crate::math::sampling::uniform_triangle;
use crate::scene::shapes::{Sphere, Triangle};
use glam::Vec3;

/// Emissive triangles `first..first + count` of `Scene::triangles`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangles {
    /// Index of the first triangle.
    pub first: u32,
    /// Number of triangles.
    pub count: u32,
}

impl Triangles {
    /// Picks a triangle with probability proportional to its area: the first whose CDF value
    /// exceeds `u` (the last for `u` at or past the end).
    pub fn pick(&self, c: &LightContext, u: f32) -> usize {
        let i = c
            .cdf
            .partition_point(|&v| v <= u)
            .min(self.count as usize - 1);
        self.first as usize + i
    }

    /// A uniform point of the surface: a triangle by area (`u[0]`), a uniform point on it.
    fn point(&self, c: &LightContext, u: [f32; 3]) -> SurfacePoint {
        let t = self.pick(c, u[0]);
        let tri = &c.triangles[t];
        let (b1, b2) = uniform_triangle(u[1], u[2]);
        SurfacePoint {
            p: tri.point(b1, b2),
            n: tri.normal(),
            material: tri.material,
            texel: area::texel(c, area::triangle_uv(c.uvs, t, b1, b2)),
        }
    }
}

impl LightKind for Triangles {
    fn surface(&self, triangles: &[Triangle], _spheres: &[Sphere]) -> (f32, Vec<f32>) {
        let tris = &triangles[self.first as usize..(self.first + self.count) as usize];
        let mut acc = 0.0f64;
        let mut cdf = Vec::with_capacity(tris.len());
        for tri in tris {
            acc += tri.area() as f64;
            cdf.push(acc as f32);
        }
        for v in &mut cdf {
            *v = if acc > 0.0 {
                (*v as f64 / acc) as f32
            } else {
                1.0
            };
        }
        (acc as f32, cdf)
    }
    fn material(&self, triangles: &[Triangle], _spheres: &[Sphere]) -> Option<u32> {
        Some(triangles[self.first as usize].material)
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
    fn gpu_words(&self, c: &LightContext) -> ParamWords {
        [
            [self.first, self.count, c.cdf_start, 0],
            [0; 4],
            [0; 4],
            [0; 4],
        ]
    }
}
