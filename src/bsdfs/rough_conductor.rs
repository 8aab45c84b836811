//! A microfacet conductor (Mitsuba's `roughconductor`): `F(wo . h) D(h) G / (4 cos_o cos_i)`
//! times a tint, visible-normal sampling, anisotropic Beckmann or GGX, two-sided. Twin:
//! `rough_conductor.wgsl`.

use crate::bsdfs::interface::{back_to_side, to_front, LobeSample, Transport};
use crate::bsdfs::interface::{BsdfKind, SurfaceClass};
use crate::bsdfs::math::reflect;
use crate::bsdfs::microfacet::{fresnel_conductor, Microfacet, Roughness};
use crate::bsdfs::param::{GpuWords, Param};
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// The WGSL twin.
pub const WGSL: &str = include_str!("rough_conductor.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 5;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Shaded;

/// A microfacet conductor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoughConductor {
    /// Real part of the relative complex index of refraction, per channel.
    pub eta: Vec3,
    /// Imaginary part (absorption), per channel.
    pub k: Vec3,
    /// Tint multiplying the Fresnel reflectance (`specular_reflectance`).
    pub specular: Param,
    /// The microfacet distribution and its (textureable) roughness.
    pub roughness: Roughness,
}

/// f(wi, wo): `F(wo . h) D(h) G(wi, wo, h) / (4 cos_o cos_i)` times the tint, h the half vector
/// (zero unless both directions are above the surface).
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

impl RoughConductor {
    /// An untextured conductor of distribution `mf` (its clamped roughness).
    pub fn new(eta: Vec3, k: Vec3, specular: Vec3, mf: Microfacet) -> Self {
        Self {
            eta,
            k,
            specular: Param::rgb(specular),
            roughness: Roughness::new(mf),
        }
    }

    /// The microfacet distribution of a resolved conductor.
    pub fn microfacet(&self) -> Microfacet {
        self.roughness.microfacet()
    }
}

impl BsdfKind for RoughConductor {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        Self {
            specular: self.specular.resolved(t, uv),
            roughness: self.roughness.resolved(t, uv),
            ..*self
        }
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        out.rgb_u(self.eta, self.roughness.code());
        out.rgb_u(self.k, 0);
        out.slot(&self.specular);
        self.roughness.gpu_words(out);
    }
    fn eval_lobe(&self, wi: Vec3, wo: Vec3, _: Transport) -> Vec3 {
        to_front(wi, wo).map_or(Vec3::ZERO, |(wi, wo, _)| {
            eval(
                &self.microfacet(),
                self.eta,
                self.k,
                self.specular.get(),
                wi,
                wo,
            )
        })
    }
    fn pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        to_front(wi, wo).map_or(0.0, |(wi, wo, _)| pdf(&self.microfacet(), wi, wo))
    }
    fn sample_lobe(&self, wo: Vec3, u: [f32; 3], _: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
        let s = sample(
            &self.microfacet(),
            self.eta,
            self.k,
            self.specular.get(),
            wo,
            u,
        );
        back_to_side(s, flipped)
    }
}
