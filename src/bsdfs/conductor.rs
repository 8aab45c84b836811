//! Conductors: the smooth mirror (Mitsuba's `conductor`) and the microfacet model
//! (`roughconductor`, visible-normal sampling), both with the complex-index Fresnel
//! reflectance times a tint. Front side only (`wo.z > 0`); callers mirror a back-side `wo`.

use crate::bsdfs::math::{reflect, reflect_z};
use crate::bsdfs::microfacet::{fresnel_conductor, Microfacet};
use crate::bsdfs::LobeSample;
use glam::{Vec2, Vec3};

/// f(wi, wo) of the rough conductor: `F(wo . h) D(h) G(wi, wo, h) / (4 cos_o cos_i)` times
/// the tint, h the half vector (zero unless both directions are above the surface).
pub fn eval(mf: &Microfacet, eta: Vec3, k: Vec3, specular: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return Vec3::ZERO;
    }
    let h = (wi + wo).normalize();
    let d = mf.d(h);
    if d == 0.0 {
        return Vec3::ZERO;
    }
    let value = d * mf.g(wo, wi, h) / (4.0 * wo.z * wi.z);
    fresnel_conductor(wo.dot(h), eta, k) * specular * value
}

/// Density of [`sample`]: `D(h) G1(wo, h) / (4 cos_o)` where both directions face h.
pub fn pdf(mf: &Microfacet, wi: Vec3, wo: Vec3) -> f32 {
    let h = (wi + wo).normalize();
    if wi.z <= 0.0 || wo.z <= 0.0 || wo.dot(h) <= 0.0 || wi.dot(h) <= 0.0 {
        return 0.0;
    }
    mf.d(h) * mf.smith_g1(wo, h) / (4.0 * wo.z)
}

/// Visible normal from `u[1], u[2]` (`u[0]` unused), mirror `wo` about it; weight =
/// `F G1(wi, m)` times the tint. `None` below the horizon.
pub fn sample(
    mf: &Microfacet,
    eta: Vec3,
    k: Vec3,
    specular: Vec3,
    wo: Vec3,
    u: [f32; 3],
) -> Option<LobeSample> {
    let (m, pdf_m) = mf.sample_visible(wo, Vec2::new(u[1], u[2]));
    let wi = reflect(wo, m);
    if pdf_m == 0.0 || wi.z <= 0.0 {
        return None;
    }
    let pdf = pdf_m / (4.0 * wi.dot(m));
    let weight = fresnel_conductor(wo.dot(m), eta, k) * specular * mf.smith_g1(wi, m);
    (pdf > 0.0).then_some(LobeSample {
        wi,
        weight,
        pdf,
        delta: false,
    })
}

/// The mirror direction (no uniforms read); weight = `F(cos_o)` times the tint.
pub fn sample_smooth(eta: Vec3, k: Vec3, specular: Vec3, wo: Vec3) -> Option<LobeSample> {
    let weight = fresnel_conductor(wo.z, eta, k) * specular;
    Some(LobeSample {
        wi: reflect_z(wo),
        weight,
        pdf: 0.0,
        delta: true,
    })
}
