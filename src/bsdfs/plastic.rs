//! A diffuse base under a dielectric coating: Mitsuba's `plastic` (smooth coating, delta
//! reflection) and `roughplastic` (microfacet coating), with the base's inter-reflections in
//! closed form (linear: `kd / (1 - Fdr)`, nonlinear: `kd / (1 - kd Fdr)`).
//!
//! The diffuse part is `f_D = kd' t(cos_i) t(cos_o) / (pi eta^2)`, t the coating's
//! transmittance: `1 - F(cos)` when smooth; when rough the table Mitsuba precomputes, the
//! visible-normal integral of `G1 (1 - F)` at [`TRANSMITTANCE_RES`] cosines, looked up
//! linearly. Fdr is `fresnel_diffuse_reflectance(1/eta)` when smooth and, when rough, the
//! coating's internal reflectance integrated as Mitsuba does (`plastic_coating.rs`).
//! Two-sided: a back-side `wo` is mirrored to the front. Twin: `plastic.wgsl`.

use crate::bsdfs::interface::{back_to_side, to_front, LobeSample, Transport};
use crate::bsdfs::interface::{BsdfKind, SurfaceClass};
use crate::bsdfs::math::{cosine_hemisphere_pdf, reflect, reflect_z, square_to_cosine_hemisphere};
use crate::bsdfs::microfacet::distribution_code;
use crate::bsdfs::microfacet::{fresnel_dielectric, fresnel_diffuse_reflectance, Microfacet};
use crate::bsdfs::param::{GpuWords, Param};
pub use crate::bsdfs::plastic_coating::TRANSMITTANCE_RES;
use crate::bsdfs::plastic_coating::{coating_integral, quadrature_res, table_cos, Rule};
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// The WGSL twin.
pub const WGSL: &str = include_str!("plastic.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 4;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Shaded;

/// A plastic with its precomputed terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Plastic {
    /// Reflectance kd of the diffuse base.
    pub diffuse_reflectance: Param,
    /// Tint of the coating's reflection.
    pub specular_reflectance: Param,
    /// Relative index of the coating, interior / exterior.
    pub eta: f32,
    /// Whether the base's inter-reflections tint the colour (`kd / (1 - kd Fdr)`).
    pub nonlinear: bool,
    /// The coating's roughness (isotropic: `alpha_u` is used); `None` for a smooth coating.
    pub microfacet: Option<Microfacet>,
    /// Probability weight of the coating when sampling: `mean(ks) / (mean(kd) + mean(ks))`.
    pub specular_sampling_weight: f32,
    /// Fdr: the coating's reflectance for light diffusely arriving from inside.
    pub internal_reflectance: f32,
    /// The rough coating's transmittance at cos theta = j / (RES - 1) (zeros when smooth).
    pub external_transmittance: [f32; TRANSMITTANCE_RES],
}

impl Plastic {
    /// A plastic with the terms Mitsuba precomputes: for a rough coating the transmittance
    /// table and the internal reflectance (Mitsuba's quadrature: 64 cosines times 32^2 nodes
    /// outside and 128^2 inside, of which the symmetry in y leaves half, about 5 * 10^5
    /// integrand evaluations, about 15 ms); for a smooth one Fdr =
    /// `fresnel_diffuse_reflectance(1 / eta)`. A rough coating is made isotropic with
    /// `alpha_u` (Mitsuba refuses anisotropic ones).
    pub fn new(
        diffuse: Vec3,
        specular: Vec3,
        eta: f32,
        nonlinear: bool,
        microfacet: Option<Microfacet>,
    ) -> Self {
        let d_mean = diffuse.element_sum() / 3.0;
        let s_mean = specular.element_sum() / 3.0;
        let microfacet = microfacet.map(|mf| Microfacet::isotropic(mf.distribution, mf.alpha_u));
        let mut external_transmittance = [0.0; TRANSMITTANCE_RES];
        let internal_reflectance = match microfacet {
            None => fresnel_diffuse_reflectance(1.0 / eta),
            Some(mf) => {
                let outside = Rule::new(quadrature_res(eta), mf.distribution);
                let inside = Rule::new(quadrature_res(1.0 / eta), mf.distribution);
                let mut sum = 0.0f64;
                for (j, t) in external_transmittance.iter_mut().enumerate() {
                    let mu = table_cos(j);
                    *t = coating_integral(&mf, &outside, mu, eta, true) as f32;
                    sum += coating_integral(&mf, &inside, mu, 1.0 / eta, false) * mu as f64;
                }
                (sum / TRANSMITTANCE_RES as f64 * 2.0) as f32
            }
        };
        Self {
            diffuse_reflectance: Param::rgb(diffuse),
            specular_reflectance: Param::rgb(specular),
            eta,
            nonlinear,
            microfacet,
            specular_sampling_weight: s_mean / (d_mean + s_mean),
            internal_reflectance,
            external_transmittance,
        }
    }

    /// The same plastic with base reflectance `diffuse` (a texture's value at a hit): the
    /// coating's tables do not depend on it, only the sampling weight does.
    pub fn with_diffuse(&self, diffuse: Vec3) -> Plastic {
        let d_mean = diffuse.element_sum() / 3.0;
        let s_mean = self.specular_reflectance.get().element_sum() / 3.0;
        Plastic {
            diffuse_reflectance: Param::rgb(diffuse),
            specular_sampling_weight: s_mean / (d_mean + s_mean),
            ..*self
        }
    }

    /// The coating's transmittance t(cos theta) for `cos_theta` in [0, 1].
    pub fn transmittance(&self, cos_theta: f32) -> f32 {
        if self.microfacet.is_none() {
            return 1.0 - fresnel_dielectric(cos_theta, self.eta).0;
        }
        let x = cos_theta * (TRANSMITTANCE_RES - 1) as f32;
        let i = (x.max(0.0) as usize).min(TRANSMITTANCE_RES - 2);
        let (v0, v1) = (
            self.external_transmittance[i],
            self.external_transmittance[i + 1],
        );
        v0 + (v1 - v0) * (x - i as f32)
    }

    /// `kd' t(cos_o) / eta^2`: the diffuse part's factor on the viewer's side.
    pub fn front_diffuse_out(&self, cos_o: f32) -> Vec3 {
        let kd = self.diffuse_reflectance.get();
        let ri = self.internal_reflectance;
        let denom = if self.nonlinear {
            Vec3::ONE - kd * ri
        } else {
            Vec3::splat(1.0 - ri)
        };
        kd / denom * (self.transmittance(cos_o) / (self.eta * self.eta))
    }

    /// Probability of sampling the coating for a viewer at `cos_o`.
    fn prob_specular(&self, cos_o: f32) -> f32 {
        let t = self.transmittance(cos_o);
        let ssw = self.specular_sampling_weight;
        let (ps, pd) = ((1.0 - t) * ssw, t * (1.0 - ssw));
        if ps + pd > 0.0 {
            ps / (ps + pd)
        } else {
            0.0
        }
    }

    /// The rough coating's value `ks F D G / (4 cos_o cos_i)` (zero when smooth).
    pub fn front_eval_lobe(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        let Some(mf) = self.microfacet else {
            return Vec3::ZERO;
        };
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        let h = (wi + wo).normalize();
        let f = fresnel_dielectric(wo.dot(h), self.eta).0;
        self.specular_reflectance.get() * (f * mf.d(h) * mf.g(wo, wi, h) / (4.0 * wo.z * wi.z))
    }

    /// Density of [`front_sample_lobe`](Self::front_sample_lobe): `D(h) G1(wo, h) / (4 cos_o)`.
    pub fn front_pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        let Some(mf) = self.microfacet else {
            return 0.0;
        };
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let h = (wi + wo).normalize();
        mf.d(h) * mf.smith_g1(wo, h) / (4.0 * wo.z)
    }

    /// The coating alone: smooth, the mirror direction with weight `ks F(cos_o)` (no uniforms
    /// read); rough, a visible normal from `u[1], u[2]`, weight `ks F G1(wi, m)`.
    pub fn front_sample_lobe(&self, wo: Vec3, u: [f32; 3]) -> Option<LobeSample> {
        let ks = self.specular_reflectance.get();
        let Some(mf) = self.microfacet else {
            let f = fresnel_dielectric(wo.z, self.eta).0;
            return Some(LobeSample {
                wi: reflect_z(wo),
                weight: ks * f,
                pdf: 0.0,
                delta: true,
            });
        };
        let (m, pdf_m) = mf.sample_visible(wo, Vec2::new(u[1], u[2]));
        let wi = reflect(wo, m);
        if pdf_m == 0.0 || wi.z <= 0.0 {
            return None;
        }
        let f = fresnel_dielectric(wo.dot(m), self.eta).0;
        let pdf = pdf_m / (4.0 * wi.dot(m));
        (pdf > 0.0).then_some(LobeSample {
            wi,
            weight: ks * (f * mf.smith_g1(wi, m)),
            pdf,
            delta: false,
        })
    }

    /// Density of [`front_sample`](Self::front_sample) (non-delta part): the coating's density times its
    /// probability plus the cosine-weighted base's.
    pub fn front_pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let ps = self.prob_specular(wo.z);
        let spec = if self.microfacet.is_some() {
            ps * self.front_pdf_lobe(wi, wo)
        } else {
            0.0
        };
        spec + (1.0 - ps) * cosine_hemisphere_pdf(wi)
    }

    /// Mitsuba's strategy: the coating when `u[0] < P` (P from the coating's reflectance and
    /// the sampling weight), else the base; `u[1], u[2]` give the coating's visible normal or
    /// the cosine-weighted direction.
    pub fn front_sample(&self, wo: Vec3, u: [f32; 3]) -> Option<LobeSample> {
        let ps = self.prob_specular(wo.z);
        if u[0] < ps && self.microfacet.is_none() {
            let mut s = self.front_sample_lobe(wo, u)?;
            s.weight /= ps;
            return Some(s);
        }
        let wi = if u[0] < ps {
            let mf = self.microfacet?;
            reflect(wo, mf.sample_visible(wo, Vec2::new(u[1], u[2])).0)
        } else {
            square_to_cosine_hemisphere(Vec2::new(u[1], u[2]))
        };
        let pdf = self.front_pdf(wi, wo);
        if pdf <= 0.0 {
            return None;
        }
        let diffuse = self.front_diffuse_out(wo.z) * (self.transmittance(wi.z) * FRAC_1_PI);
        let weight = (diffuse + self.front_eval_lobe(wi, wo)) * wi.z / pdf;
        Some(LobeSample {
            wi,
            weight,
            pdf,
            delta: false,
        })
    }
}

impl BsdfKind for Plastic {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        let specular = self.specular_reflectance.resolved(t, uv);
        let p = Plastic {
            specular_reflectance: specular,
            ..*self
        };
        // The coating's tables do not depend on the textures, the sampling weight does.
        if self.diffuse_reflectance.is_textured() || self.specular_reflectance.is_textured() {
            p.with_diffuse(self.diffuse_reflectance.eval(t, uv))
        } else {
            p
        }
    }
    fn base_colour_mut(&mut self) -> Option<&mut Param> {
        Some(&mut self.diffuse_reflectance)
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        out.slot(&self.diffuse_reflectance);
        out.slot(&self.specular_reflectance);
        // The table's offset (word 2's z) is written by the packer.
        out.raw([
            self.eta.to_bits(),
            self.nonlinear as u32,
            0,
            self.specular_sampling_weight.to_bits(),
        ]);
        let (distribution, alpha) = match self.microfacet {
            Some(mf) => (distribution_code(mf.distribution), mf.alpha_u),
            None => (NO_MICROFACET, 0.0),
        };
        out.raw([
            self.internal_reflectance.to_bits(),
            distribution,
            alpha.to_bits(),
            0,
        ]);
        if self.microfacet.is_some() {
            out.table = self.external_transmittance.to_vec();
            out.table_at = Some((2, 2));
        }
    }
    fn diffuse_out(&self, wo: Vec3) -> Vec3 {
        if wo.z != 0.0 {
            self.front_diffuse_out(wo.z.abs())
        } else {
            Vec3::ZERO
        }
    }
    fn store_weight(&self, wi: Vec3) -> f32 {
        if wi.z != 0.0 {
            self.transmittance(wi.z.abs())
        } else {
            0.0
        }
    }
    fn eval_lobe(&self, wi: Vec3, wo: Vec3, _: Transport) -> Vec3 {
        to_front(wi, wo).map_or(Vec3::ZERO, |(wi, wo, _)| self.front_eval_lobe(wi, wo))
    }
    fn pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        to_front(wi, wo).map_or(0.0, |(wi, wo, _)| self.front_pdf_lobe(wi, wo))
    }
    fn sample_lobe(&self, wo: Vec3, u: [f32; 3], _: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
        back_to_side(self.front_sample_lobe(wo, u), flipped)
    }
    fn has_diffuse(&self) -> bool {
        true
    }
    fn lobe_is_delta(&self) -> bool {
        self.microfacet.is_none()
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        to_front(wi, wo).map_or(0.0, |(wi, wo, _)| self.front_pdf(wi, wo))
    }
    fn sample(&self, wo: Vec3, u: [f32; 3], _: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
        back_to_side(self.front_sample(wo, u), flipped)
    }
}

/// The GPU's distribution code of a smooth coating.
pub const NO_MICROFACET: u32 = u32::MAX;

/// The WGSL constants the twin reads: the table's length and the smooth coating's code.
pub fn wgsl_consts() -> String {
    format!(
        "const BSDF_TABLE_RES: u32 = {TRANSMITTANCE_RES}u;\nconst PLASTIC_NO_MICROFACET: u32 = {NO_MICROFACET}u;\n"
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smooth_plastic_terms() {
        let p = Plastic::new(Vec3::splat(0.5), Vec3::ONE, 1.5, false, None);
        assert_eq!(
            p.internal_reflectance,
            fresnel_diffuse_reflectance(1.0 / 1.5)
        );
        assert!((p.transmittance(1.0) - 0.96).abs() < 1e-6);
        assert!((p.specular_sampling_weight - 1.0 / 1.5).abs() < 1e-6);
    }
}
