//! What the area lights (emissive triangles, [`crate::lights::triangles`], and spheres,
//! [`crate::lights::sphere`]) share: a point of their surface with its material and emission
//! texel, photons leaving it by the cosine (from either face of a two-sided emitter), and
//! shadow rays towards it, uniform by area. Twin: `src/lights/area.wgsl`.

use crate::lights::interface::{Emission, LightContext, LightSample};
use crate::math::sampling::{cosine_hemisphere, uniform_sphere};
use crate::textures::NO_TEXTURE;
use glam::{Vec2, Vec3};

/// A point of an area light's surface.
#[derive(Clone, Copy, Debug)]
pub struct SurfacePoint {
    /// Where it is.
    pub p: Vec3,
    /// The surface's unit front normal there.
    pub n: Vec3,
    /// The emitting material.
    pub material: u32,
    /// The emission texture's value there (one without a texture; `crate::lights::emission`).
    pub texel: Vec3,
}

/// The light's emission texture at `uv` (one without a texture).
pub fn texel(c: &LightContext, uv: Vec2) -> Vec3 {
    match c.emission_texture {
        NO_TEXTURE => Vec3::ONE,
        t => c.textures[t as usize].eval(uv),
    }
}

/// The uv of point `(b1, b2)` (barycentrics of v1 and v2) of triangle `t`; zero without uvs.
pub fn triangle_uv(uvs: &[[Vec2; 3]], t: usize, b1: f32, b2: f32) -> Vec2 {
    match uvs.get(t) {
        Some(c) => (1.0 - b1 - b2) * c[0] + b1 * c[1] + b2 * c[2],
        None => Vec2::ZERO,
    }
}

/// A photon leaving `sp` by the cosine about its normal, `u3` and `u4` uniform (a two-sided
/// emitter's lower half of `u3` picks the front face, its upper half the back), carrying the
/// texel over the texture's mean.
pub fn emit(c: &LightContext, sp: SurfacePoint, u3: f32, u4: f32) -> Emission {
    let mut n = sp.n;
    if n == Vec3::ZERO {
        // A degenerate triangle: no face to leave by.
        return Emission {
            origin: sp.p,
            dir: uniform_sphere(u3, u4),
            normal: n,
            scale: Vec3::ONE,
        };
    }
    let mean = c.texture_mean;
    let scale = Vec3::select(mean.cmpgt(Vec3::ZERO), sp.texel / mean, Vec3::ZERO);
    let mut u3 = u3;
    if c.materials[sp.material as usize].two_sided_emission {
        if u3 >= 0.5 {
            n = -n;
            u3 = u3 * 2.0 - 1.0;
        } else {
            u3 *= 2.0;
        }
    }
    Emission {
        origin: sp.p,
        dir: cosine_hemisphere(n, u3, u4),
        normal: n,
        scale,
    }
}

/// The shadow-ray target `sp` seen from `x`: `Le cos_l area / d^2` (both faces of a
/// two-sided emitter), zero when `x` is behind it or on it.
pub fn sample(c: &LightContext, sp: SurfacePoint, x: Vec3) -> LightSample {
    let m = &c.materials[sp.material as usize];
    let to_x = x - sp.p;
    let d2 = to_x.length_squared();
    let dark = LightSample {
        point: sp.p,
        weight: Vec3::ZERO,
        normal: sp.n,
        distant: false,
    };
    if d2 <= 0.0 {
        return dark;
    }
    let mut cos_l = sp.n.dot(to_x) / d2.sqrt();
    if m.two_sided_emission {
        cos_l = cos_l.abs();
    }
    if cos_l <= 0.0 {
        return dark;
    }
    LightSample {
        point: sp.p,
        weight: m.emission * sp.texel * (cos_l * c.area / d2),
        normal: sp.n,
        distant: false,
    }
}

/// The solid-angle density with which an area light of area `area` is sampled at `point`
/// (normal `normal`) as seen from `x`: uniform over its area, `d^2 / (|cos_l| area)`; 0 for a
/// point seen edge-on.
pub fn solid_angle_pdf(area: f32, x: Vec3, point: Vec3, normal: Vec3) -> f32 {
    let to_x = x - point;
    let d2 = to_x.length_squared();
    let cos_l = normal.dot(to_x).abs() / d2.sqrt();
    if cos_l > 0.0 && area > 0.0 {
        d2 / (cos_l * area)
    } else {
        0.0
    }
}
