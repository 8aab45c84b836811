//! Mitsuba's `blendbsdf`: a material that is one of two others, `first` with probability
//! `1 - w` and `second` with probability `w` (`w` a [`Param`], constant or textured), which in
//! expectation is the blend `(1 - w) f_first + w f_second` (pbrt-v4's `MixMaterial` makes the
//! same choice). The choice is made once per hit and ray direction by a hash of their bits
//! ([`blend_u`]), so every question asked of one hit gets the same component, on both backends
//! alike; [`choose`] is the one place it is made, called by `crate::bsdfs::shading::bsdf_at`.
//! Twin: `blend.wgsl`.
//!
//! The photon-mapping split: a blend stores photons where any component stores them (the
//! photon map estimates the light arriving, whichever component a photon then bounces off),
//! and an estimate is weighed by the chosen component's diffuse albedo, so both halves of the
//! estimate are unbiased for the blend. A component's coating weight on stored photons
//! (`store_weight`, a plastic's) is the one chosen at the photon's hit.

pub use crate::bsdfs::material::Blend;
use crate::bsdfs::material::Material;
use crate::math::rng::pcg_hash;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// The most blends nested in one another that [`choose`] follows (the scene builder refuses
/// deeper nests).
pub const MAX_BLEND_DEPTH: u32 = 8;

/// The uniform number in [0, 1) of a blend's choice at the hit `p` for a ray along `d`: a
/// hash of their bits, the same for every question asked of that hit.
#[inline]
pub fn blend_u(p: Vec3, d: Vec3) -> f32 {
    let mut h = 0x9e37_79b9u32;
    for v in [p.x, p.y, p.z, d.x, d.y, d.z] {
        h = pcg_hash(h ^ v.to_bits());
    }
    (h >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// The index of the material a hit at `p` (texture coordinates `uv`) on material `index`,
/// seen along `d`, is: `index` itself unless it is a blend, else the component chosen by
/// [`blend_u`], following nested blends up to [`MAX_BLEND_DEPTH`].
#[inline]
pub fn choose(
    materials: &[Material],
    textures: &[SceneTexture],
    index: u32,
    p: Vec3,
    d: Vec3,
    uv: Vec2,
) -> u32 {
    let mut i = index;
    let Some(_) = materials[i as usize].blend else {
        return i;
    };
    let mut u = blend_u(p, d);
    for _ in 0..MAX_BLEND_DEPTH {
        let Some(b) = materials[i as usize].blend else {
            break;
        };
        let w = b.weight.eval(textures, uv).x.clamp(0.0, 1.0);
        // The same uniform, rescaled, chooses inside the component chosen.
        if u < w {
            i = b.second;
            u /= w;
        } else {
            i = b.first;
            u = (u - w) / (1.0 - w);
        }
        u = u.min(ONE_BELOW);
    }
    i
}

/// The largest f32 below 1 (a rescaled choice's uniform stays below it).
pub const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;
