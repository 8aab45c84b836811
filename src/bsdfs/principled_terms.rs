//! The principled family's shared terms: Mitsuba's Schlick Fresnel and tint, Disney's diffuse,
//! the clearcoat's GTR1 distribution and Smith masking, the microfacet side check. Both
//! `principled` and `principledthin` build their lobes from them, so neither BSDF's file holds
//! them. Twins: their `pr_` namesakes in `principled.wgsl` (`mean`'s is `gltf_mean`).

use crate::bsdfs::math::{mulsign, safe_sqrt};
use crate::bsdfs::metallic_roughness::schlick_weight;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// Mitsuba's RGB luminance.
#[inline]
pub(crate) fn luminance(c: Vec3) -> f32 {
    0.212_671 * c.x + 0.715_160 * c.y + 0.072_169 * c.z
}

/// The mean of the three channels.
#[inline]
pub(crate) fn mean(v: Vec3) -> f32 {
    (v.x + v.y + v.z) / 3.0
}

/// Schlick's approximation with reflectance `r0` at `cos_i` (Mitsuba's `calc_schlick`: the
/// transmitted cosine when the index seen from `cos_i`'s side is below 1).
pub(crate) fn calc_schlick(r0: Vec3, cos_i: f32, eta: f32) -> Vec3 {
    let outside = cos_i >= 0.0;
    let (eta_it, eta_ti) = if outside {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    let cos_t = safe_sqrt(1.0 - (1.0 - cos_i * cos_i) * (eta_ti * eta_ti));
    let w = if eta_it > 1.0 {
        schlick_weight(cos_i.abs())
    } else {
        schlick_weight(cos_t)
    };
    Vec3::splat(w) + (Vec3::ONE - Vec3::splat(w)) * r0
}

/// `base` over its luminance (one where the luminance is zero): the tint of the sheen and of
/// the tinted specular.
pub(crate) fn tint(base: Vec3) -> Vec3 {
    let lum = luminance(base);
    if lum > 0.0 {
        base / lum
    } else {
        Vec3::ONE
    }
}

/// Disney's diffuse response at the cosines `cos_o`, `cos_i` (both positive) and `cos_d` (the
/// half vector's with a direction), split as the photon mapper splits it: the separable
/// `(1 - flatness) f_diff` and the rest, `(1 - flatness) f_retro + flatness f_ss`.
pub(crate) fn disney_diffuse(
    cos_o: f32,
    cos_i: f32,
    cos_d: f32,
    roughness: f32,
    flatness: f32,
) -> (f32, f32) {
    let (fo, fi) = (schlick_weight(cos_o), schlick_weight(cos_i));
    let f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo);
    let rr = 2.0 * roughness * cos_d * cos_d;
    let f_retro = rr * (fo + fi + fo * fi * (rr - 1.0));
    let fss90 = rr / 2.0;
    let fss = (1.0 + (fss90 - 1.0) * fo) * (1.0 + (fss90 - 1.0) * fi);
    let f_ss = 1.25 * (fss * (1.0 / (cos_o + cos_i) - 0.5) + 0.5);
    (
        (1.0 - flatness) * f_diff,
        (1.0 - flatness) * f_retro + flatness * f_ss,
    )
}

/// GTR1's distribution of normals (clearcoat) of roughness `alpha`.
pub(crate) fn gtr1_d(alpha: f32, m: Vec3) -> f32 {
    let a2 = alpha * alpha;
    let r = (a2 - 1.0) / (PI * a2.ln() * (1.0 + (a2 - 1.0) * m.z * m.z));
    if r * m.z > 1e-20 {
        r
    } else {
        0.0
    }
}

/// GTR1's sampled normal from `u` (density `cos_m D(m)`).
pub(crate) fn gtr1_sample(alpha: f32, u: Vec2) -> Vec3 {
    let (sin_phi, cos_phi) = (2.0 * PI * u.x).sin_cos();
    let a2 = alpha * alpha;
    let cos2 = (1.0 - a2.powf(1.0 - u.y)) / (1.0 - a2);
    let sin_t = (1.0 - cos2).max(0.0).sqrt();
    Vec3::new(cos_phi * sin_t, sin_phi * sin_t, cos2.max(0.0).sqrt())
}

/// The separable GGX masking term of the clearcoat (alpha 0.25) for one direction.
pub(crate) fn smith_ggx1(v: Vec3, m: Vec3, alpha: f32) -> f32 {
    if v.dot(m) * v.z <= 0.0 {
        return 0.0;
    }
    if v.z == 1.0 {
        return 1.0;
    }
    let c2 = v.z * v.z;
    let tan2 = (1.0 - c2) / c2;
    2.0 / (1.0 + (1.0 + alpha * alpha * tan2).sqrt())
}

/// Whether `m` (flipped to `wo`'s side) is seen from the front by `wo` and, for a
/// reflection, by `wi`, for a transmission from behind (Mitsuba's `mac_mic_compatibility`).
pub(crate) fn compatible(m: Vec3, wo: Vec3, wi: Vec3, reflection: bool) -> bool {
    let ms = mulsign(m, wo.z);
    wo.dot(ms) > 0.0
        && if reflection {
            wi.dot(ms) > 0.0
        } else {
            wi.dot(ms) < 0.0
        }
}
