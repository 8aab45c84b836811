//! Textured emission (glTF `emissiveTexture`, Mitsuba's area emitter with a textured
//! `radiance`): the emitted radiance at a point is the material's `emission` times the
//! texture's colour there. Lights are sampled uniformly by area, so each sample is weighed
//! by the texel it lands on; a light's power, which shares the photon budget, includes the
//! texture's mean over its surface ([`texture_mean`]), and a photon leaving a point carries
//! that texel over the same mean, so the photons' total is unbiased whatever the mean's
//! accuracy. A spot's or projector's projected image is its emission texture in the same way
//! (each kind's mean: `Spot::projected_mean`, `Projector::texture_mean`).

use crate::lights::area::triangle_uv;
use crate::lights::interface::LightKind;
use crate::lights::LightShape;
use crate::math::sampling::uniform_triangle;
use crate::scene::{Scene, NO_TEXTURE};
use glam::Vec3;

/// Stratified samples per triangle (a 4 x 4 grid of the unit square, mapped uniformly).
const PER_TRIANGLE: u32 = 4;
/// At most this many texture lookups per light; larger meshes take one per triangle.
const MAX_LOOKUPS: usize = 1 << 20;

/// The emission texture of light `l`'s material or the image it projects, or [`NO_TEXTURE`].
pub fn texture_of(scene: &Scene, l: usize) -> u32 {
    match scene.lights[l].shape {
        LightShape::Spot(s) => return s.projection.map_or(NO_TEXTURE, |p| p.texture),
        LightShape::Projector(p) => return p.texture.unwrap_or(NO_TEXTURE),
        _ => {}
    }
    match scene.lights[l]
        .shape
        .material(&scene.triangles, &scene.spheres)
    {
        Some(m) => scene.materials[m as usize].emission_texture,
        None => NO_TEXTURE,
    }
}

/// The area-weighted mean of light `l`'s emission texture over its surface (one when it has
/// none), by stratified samples.
pub fn texture_mean(scene: &Scene, l: usize) -> Vec3 {
    let t = texture_of(scene, l);
    if t == NO_TEXTURE {
        return Vec3::ONE;
    }
    let tex = &scene.textures[t as usize];
    let k = PER_TRIANGLE;
    let grid = |k: u32| {
        (0..k * k)
            .map(move |i| ((i % k) as f32 + 0.5, (i / k) as f32 + 0.5))
            .map(move |(x, y)| (x / k as f32, y / k as f32))
    };
    let (mut sum, mut weight) = (Vec3::ZERO, 0.0f32);
    match scene.lights[l].shape {
        LightShape::Triangles(t) => {
            let (first, count) = (t.first, t.count);
            let k = if count as usize * (k * k) as usize > MAX_LOOKUPS {
                1
            } else {
                k
            };
            for i in first..first + count {
                let area = scene.triangles[i as usize].area();
                let mut s = Vec3::ZERO;
                for (u1, u2) in grid(k) {
                    let (b1, b2) = uniform_triangle(u1, u2);
                    s += tex.eval(triangle_uv(&scene.uvs, i as usize, b1, b2));
                }
                sum += s * (area / (k * k) as f32);
                weight += area;
            }
        }
        LightShape::Sphere(_) => {
            // Uniform in (cos theta, phi): equal areas of the sphere.
            for (u1, u2) in grid(32) {
                let z = 1.0 - 2.0 * u1;
                let r = (1.0 - z * z).max(0.0).sqrt();
                let phi = 2.0 * std::f32::consts::PI * u2;
                let n = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                sum += tex.eval(crate::textures::uv::sphere(n));
                weight += 1.0;
            }
        }
        LightShape::Spot(s) => return s.projected_mean(tex),
        LightShape::Projector(_) => return crate::lights::projector::Projector::texture_mean(tex),
        _ => return Vec3::ONE,
    }
    if weight > 0.0 {
        sum / weight
    } else {
        Vec3::ONE
    }
}
