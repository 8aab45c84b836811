//! A microfacet dielectric interface (Mitsuba's `roughdielectric`, after Walter et al. 2007,
//! visible-normal sampling): reflection and transmission, `eta` interior over exterior,
//! `wo.z < 0` meaning the viewer is inside. In [`Transport::Radiance`] transmitted values
//! carry the radiance scale `(eta_o / eta_i)^2` of the crossing (Mitsuba's `eta_ti^2`); in
//! [`Transport::Importance`] they do not. Twin: `rough_dielectric.wgsl`.

use crate::bsdfs::interface::{BsdfKind, SurfaceClass};
use crate::bsdfs::interface::{LobeSample, Transport};
use crate::bsdfs::math::{mulsign, reflect, refract};
use crate::bsdfs::microfacet::{fresnel_dielectric, Microfacet, Roughness};
use crate::bsdfs::param::{GpuWords, Param};
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// The WGSL twin.
pub const WGSL: &str = include_str!("rough_dielectric.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 5;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Shaded;

/// A microfacet dielectric interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughDielectric {
    /// Relative index of refraction, interior / exterior.
    pub eta: f32,
    /// Tint of the reflected part.
    pub specular_reflectance: Param,
    /// Tint of the transmitted part.
    pub specular_transmittance: Param,
    /// The microfacet distribution and its (textureable) roughness.
    pub roughness: Roughness,
}

impl RoughDielectric {
    /// An untextured interface of distribution `mf` (its clamped roughness).
    pub fn new(eta: f32, reflectance: Vec3, transmittance: Vec3, mf: Microfacet) -> Self {
        Self {
            eta,
            specular_reflectance: Param::rgb(reflectance),
            specular_transmittance: Param::rgb(transmittance),
            roughness: Roughness::new(mf),
        }
    }

    /// The microfacet distribution of a resolved interface.
    pub fn microfacet(&self) -> Microfacet {
        self.roughness.microfacet()
    }
}

impl BsdfKind for RoughDielectric {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        Self {
            specular_reflectance: self.specular_reflectance.resolved(t, uv),
            specular_transmittance: self.specular_transmittance.resolved(t, uv),
            roughness: self.roughness.resolved(t, uv),
            ..*self
        }
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        out.raw([self.eta.to_bits(), self.roughness.code(), 0, 0]);
        out.slot(&self.specular_reflectance);
        out.slot(&self.specular_transmittance);
        self.roughness.gpu_words(out);
    }
    fn eval_lobe(&self, wi: Vec3, wo: Vec3, t: Transport) -> Vec3 {
        eval(
            &self.microfacet(),
            self.eta,
            self.specular_reflectance.get(),
            self.specular_transmittance.get(),
            wi,
            wo,
            t,
        )
    }
    fn pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        pdf(&self.microfacet(), self.eta, wi, wo)
    }
    fn lobe_transmits(&self) -> bool {
        true
    }
    fn sample_lobe(&self, wo: Vec3, u: [f32; 3], t: Transport) -> Option<LobeSample> {
        sample(
            &self.microfacet(),
            self.eta,
            self.specular_reflectance.get(),
            self.specular_transmittance.get(),
            wo,
            u,
            t,
        )
    }
}

/// The generalised half vector of `(wi, wo)` facing up, whether the pair is a reflection, and
/// `e`, the index ratio of the far side over `wo`'s side.
pub(crate) fn half_vector(eta: f32, wi: Vec3, wo: Vec3) -> (Vec3, bool, f32) {
    let reflect = wo.z * wi.z > 0.0;
    let e = if wo.z > 0.0 { eta } else { 1.0 / eta };
    let m = (wo + wi * if reflect { 1.0 } else { e }).normalize();
    (mulsign(m, m.z), reflect, e)
}

/// f(wi, wo) of the rough dielectric, reflection and transmission.
pub fn eval(
    mf: &Microfacet,
    eta: f32,
    reflectance: Vec3,
    transmittance: Vec3,
    wi: Vec3,
    wo: Vec3,
    transport: Transport,
) -> Vec3 {
    if wo.z == 0.0 || wi.z == 0.0 {
        return Vec3::ZERO;
    }
    let (m, reflect, e) = half_vector(eta, wi, wo);
    let d = mf.d(m);
    let f = fresnel_dielectric(wo.dot(m), eta).0;
    let g = mf.g(wo, wi, m);
    if reflect {
        reflectance * (f * d * g / (4.0 * wo.z.abs() * wi.z.abs()))
    } else {
        let scale = match transport {
            Transport::Radiance => 1.0 / (e * e),
            Transport::Importance => 1.0,
        };
        let (dot_o, dot_i) = (wo.dot(m), wi.dot(m));
        let denom = dot_o + e * dot_i;
        let v = scale * (1.0 - f) * d * g * e * e * dot_o * dot_i / (wo.z * denom * denom);
        transmittance * (v.abs() / wi.z.abs())
    }
}

/// Density of [`sample`]: the visible-normal density of m times the chosen side's Fresnel
/// probability times the Jacobian of the reflection or refraction mapping.
pub fn pdf(mf: &Microfacet, eta: f32, wi: Vec3, wo: Vec3) -> f32 {
    if wo.z == 0.0 {
        return 0.0;
    }
    let (m, reflect, e) = half_vector(eta, wi, wo);
    let (dot_o, dot_i) = (wo.dot(m), wi.dot(m));
    if dot_o * wo.z <= 0.0 || dot_i * wi.z <= 0.0 {
        return 0.0;
    }
    let dwh_dwi = if reflect {
        1.0 / (4.0 * dot_i)
    } else {
        e * e * dot_i / (dot_o + e * dot_i).powi(2)
    };
    let f = fresnel_dielectric(dot_o, eta).0;
    let prob = mf.pdf_visible(mulsign(wo, wo.z), m) * if reflect { f } else { 1.0 - f };
    prob * dwh_dwi.abs()
}

/// Visible normal m from `u[1], u[2]` (seen from `wo`'s side); reflect when `u[0] <= F(wo . m)`,
/// else refract. Weight = `G1(wi, m)` times the tint (and the radiance scale when refracting).
/// `None` when the direction lands on the wrong side of the surface (no energy).
pub fn sample(
    mf: &Microfacet,
    eta: f32,
    reflectance: Vec3,
    transmittance: Vec3,
    wo: Vec3,
    u: [f32; 3],
    transport: Transport,
) -> Option<LobeSample> {
    if wo.z == 0.0 {
        return None;
    }
    let (m, pdf_m) = mf.sample_visible(mulsign(wo, wo.z), Vec2::new(u[1], u[2]));
    if pdf_m == 0.0 {
        return None;
    }
    let dot_o = wo.dot(m);
    let (f, cos_t, eta_it, eta_ti) = fresnel_dielectric(dot_o, eta);
    let (wi, mut weight, pdf) = if u[0] <= f {
        let wi = reflect(wo, m);
        (wi, reflectance, pdf_m * f / (4.0 * wi.dot(m)).abs())
    } else {
        let wi = refract(wo, m, cos_t, eta_ti);
        let factor = match transport {
            Transport::Radiance => eta_ti * eta_ti,
            Transport::Importance => 1.0,
        };
        let dot_i = wi.dot(m);
        let dwh = eta_it * eta_it * dot_i / (dot_o + eta_it * dot_i).powi(2);
        (wi, transmittance * factor, pdf_m * (1.0 - f) * dwh.abs())
    };
    weight *= mf.smith_g1(wi, m);
    let right_side = if u[0] <= f {
        wi.z * wo.z > 0.0
    } else {
        wi.z * wo.z < 0.0
    };
    (right_side && pdf > 0.0).then_some(LobeSample {
        wi,
        weight,
        pdf,
        delta: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdfs::interface::Frame;
    use crate::bsdfs::microfacet::Distribution;
    use crate::math::geometry::Facing;
    use crate::math::rng::{Rng, Stream};

    /// On a smooth triangle (shading normal tilted off the geometric one) the lobe's rays
    /// are the shading frame's alone, as Mitsuba spawns them: the same directions and weights
    /// as with the geometric normal equal to the shading one, including rays that end on the
    /// other side of the geometric surface than the lobe chose (a reflection below it, a
    /// refraction above it), which the test requires to occur.
    #[test]
    fn lobe_rays_go_on_past_the_geometric_surface() {
        let rd = RoughDielectric::new(
            1.3,
            Vec3::ONE,
            Vec3::ONE,
            Microfacet::new(Distribution::Beckmann, 0.3, 0.3),
        );
        let ng = Vec3::Z;
        let mut r = Rng::new(7, Stream::Camera, 0, 0);
        let (mut kept, mut across) = (0, 0);
        for i in 0..20_000u32 {
            // Shading normal up to ~40 degrees off ng, a viewer above both surfaces.
            let ns = (ng + Vec3::new(r.next() - 0.5, r.next() - 0.5, 0.0) * 1.6).normalize();
            let v = Vec3::new(2.0 * r.next() - 1.0, 2.0 * r.next() - 1.0, r.next()).normalize();
            if v.dot(ng) <= 0.0 || v.dot(ns) <= 0.0 {
                continue;
            }
            let frame = Frame::new(ns, Vec3::X);
            let mut a = Rng::new(7, Stream::Camera, 1, i);
            let mut b = a;
            let smooth = rd.surface_sample_lobe(frame, -v, &Facing::new(ng, ns, true), &mut a);
            let flat = rd.surface_sample_lobe(frame, -v, &Facing::new(ns, ns, true), &mut b);
            assert_eq!(
                smooth.map(|l| (l.dir, l.weight)),
                flat.map(|l| (l.dir, l.weight))
            );
            if let Some(l) = smooth {
                kept += 1;
                let reflects = l.dir.dot(ns) > 0.0;
                across += usize::from(reflects != (l.dir.dot(ng) > 0.0));
            }
        }
        assert!(kept > 5_000, "{kept} rays");
        assert!(
            across > 50,
            "{across} of {kept} rays end across the geometric surface"
        );
    }
}
