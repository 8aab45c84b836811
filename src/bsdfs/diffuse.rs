//! Lambertian reflection (Mitsuba's `diffuse`): f = albedo / pi on the front side, sampled
//! with the cosine-weighted hemisphere. Callers mirror a back-side `wo` to the front first.

use crate::bsdfs::math::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::bsdfs::LobeSample;
use glam::{Vec2, Vec3};

/// Density of [`sample`]: cos theta_i / pi on the front side (`wo.z > 0`).
pub fn pdf(wi: Vec3, wo: Vec3) -> f32 {
    if wi.z > 0.0 && wo.z > 0.0 {
        cosine_hemisphere_pdf(wi)
    } else {
        0.0
    }
}

/// Cosine-weighted `wi` from `u[1], u[2]` (`u[0]` unused); weight = albedo.
pub fn sample(albedo: Vec3, wo: Vec3, u: [f32; 3]) -> Option<LobeSample> {
    let wi = square_to_cosine_hemisphere(Vec2::new(u[1], u[2]));
    let pdf = pdf(wi, wo);
    (pdf > 0.0).then_some(LobeSample {
        wi,
        weight: albedo,
        pdf,
        delta: false,
    })
}
