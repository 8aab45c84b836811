//! The BSDFs of Mitsuba 3.9.1 (`diffuse`, `conductor`, `roughconductor`, `dielectric`,
//! `roughdielectric`, `thindielectric`, `plastic`, `roughplastic`) as pure f32 math, with
//! their values, densities and samplers, and the split the photon mapper uses: a
//! Lambertian-like DIFFUSE part estimated from photon density plus a LOBE part (delta or
//! glossy) traced by rays.
//!
//! Conventions: directions are unit vectors in the local shading frame, z the shading normal
//! on the front side. `wo` points towards the viewer (for a photon: where it came from), `wi`
//! towards the light (for a photon: where it goes next), both away from the surface. Mitsuba
//! names them the other way round (its `si.wi` is our `wo`). [`Bsdf::eval`] is f(wi, wo)
//! without the cosine; [`Bsdf::eval_cos`] is Mitsuba's `eval`, f |cos theta_i|.
//!
//! The reflective kinds (diffuse, conductors, plastics) are two-sided like Mitsuba's
//! `twosided` adapter: a `wo` below the surface mirrors both directions' z to the front.
//! Dielectrics are one interface: `wo.z < 0` means the viewer is inside.
//!
//! Random numbers: every sampler takes three uniforms in [0, 1). `u[0]` picks a component
//! (reflection or transmission, coating or base) and `u[1]`, `u[2]` pick the direction;
//! each kind's sampler documents which it reads.

pub mod classic;
pub mod material;
pub mod shading;

mod conductor;
mod dielectric;
mod diffuse;
mod gltf;
mod ior;
pub mod math;
pub mod microfacet;
mod plastic;

pub use gltf::{schlick_mean, schlick_mean_table, MetallicRoughness, SCHLICK_MEAN_RES};
pub use microfacet::{
    fresnel_conductor, fresnel_dielectric, fresnel_diffuse_reflectance, named_conductor,
    Distribution, Microfacet, METAL_NAMES,
};
pub use plastic::{Plastic, TRANSMITTANCE_RES};

use glam::Vec3;

/// Which quantity a path carries; only transmission through a dielectric tells them apart
/// (radiance is scaled by 1/eta^2 of the crossing, importance is not).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Transport {
    /// Camera paths: radiance flows from `wi` to `wo`.
    Radiance,
    /// Photon paths: power flows from `wo` to `wi`.
    Importance,
}

/// What one scattering from a sampled lobe gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeSample {
    /// The sampled direction (towards the light; for a photon the direction it leaves in).
    pub wi: Vec3,
    /// `f |cos theta_i| / pdf`; for a delta lobe the weight of the delta (Fresnel and tint).
    pub weight: Vec3,
    /// Solid-angle density of `wi` under the sampler that produced it; 0 for a delta lobe.
    pub pdf: f32,
    /// Whether the sampled lobe is a delta (mirror, smooth refraction, pass-through).
    pub delta: bool,
}

/// A BSDF with all parameters resolved (textures already looked up by the caller).
///
/// Plain `Copy` data (the plastic carries its 64-entry transmittance table inline, so the enum
/// is about 300 bytes); no allocation anywhere.
#[derive(Clone, Copy, Debug, PartialEq)]
#[allow(clippy::large_enum_variant)] // Copy and allocation-free matter more than the size
pub enum Bsdf {
    /// Lambertian reflection (`diffuse`): f = albedo / pi.
    Diffuse {
        /// Reflectance.
        albedo: Vec3,
    },
    /// A conductor (`conductor` when `microfacet` is `None`, else `roughconductor`).
    Conductor {
        /// Real part of the relative complex index of refraction, per channel.
        eta: Vec3,
        /// Imaginary part (absorption), per channel.
        k: Vec3,
        /// Tint multiplying the Fresnel reflectance (`specular_reflectance`).
        specular: Vec3,
        /// Roughness; `None` for a smooth (delta) mirror.
        microfacet: Option<Microfacet>,
    },
    /// A dielectric interface (`dielectric` when `microfacet` is `None`, else
    /// `roughdielectric`).
    Dielectric {
        /// Relative index of refraction, interior / exterior.
        eta: f32,
        /// Tint of the reflected part.
        specular_reflectance: Vec3,
        /// Tint of the transmitted part.
        specular_transmittance: Vec3,
        /// Roughness; `None` for a smooth (delta) interface.
        microfacet: Option<Microfacet>,
    },
    /// A thin dielectric sheet (`thindielectric`): delta reflection with the inter-reflected
    /// Fresnel `R' = 2R / (1 + R)` and straight pass-through with `1 - R'`.
    ThinDielectric {
        /// Relative index of refraction of the sheet, interior / exterior.
        eta: f32,
        /// Tint of the reflected part.
        specular_reflectance: Vec3,
        /// Tint of the transmitted part.
        specular_transmittance: Vec3,
    },
    /// A diffuse base under a dielectric coating (`plastic` and `roughplastic`).
    Plastic(Plastic),
    /// glTF 2.0's metallic-roughness material (Appendix B, thin-walled transmission).
    MetallicRoughness(MetallicRoughness),
}

/// Two-sided kinds: both directions' z mirrored to the front when `wo` is below, or `None`
/// when `wo` lies in the surface.
#[inline]
fn to_front(wi: Vec3, wo: Vec3) -> Option<(Vec3, Vec3, bool)> {
    if wo.z > 0.0 {
        Some((wi, wo, false))
    } else if wo.z < 0.0 {
        Some((flip_z(wi), flip_z(wo), true))
    } else {
        None
    }
}

#[inline]
fn flip_z(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

/// Mirrors a front-side sample back to the side `wo` was on.
#[inline]
fn back_to_side(s: Option<LobeSample>, flipped: bool) -> Option<LobeSample> {
    s.map(|mut s| {
        if flipped {
            s.wi = flip_z(s.wi);
        }
        s
    })
}

impl Bsdf {
    /// The non-delta BSDF value f(wi, wo), without the cosine.
    pub fn eval(&self, wi: Vec3, wo: Vec3, transport: Transport) -> Vec3 {
        self.diffuse_value(wi, wo) + self.eval_lobe(wi, wo, transport)
    }

    /// `eval * |wi.z|`: the value Mitsuba's `BSDF::eval` returns.
    pub fn eval_cos(&self, wi: Vec3, wo: Vec3, transport: Transport) -> Vec3 {
        self.eval(wi, wo, transport) * wi.z.abs()
    }

    /// Solid-angle density with which [`sample`](Self::sample) produces a non-delta `wi`.
    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        match self {
            Bsdf::Diffuse { .. } => {
                to_front(wi, wo).map_or(0.0, |(wi, wo, _)| diffuse::pdf(wi, wo))
            }
            Bsdf::Plastic(p) => to_front(wi, wo).map_or(0.0, |(wi, wo, _)| p.pdf(wi, wo)),
            Bsdf::MetallicRoughness(g) => to_front(wi, wo).map_or(0.0, |(wi, wo, _)| g.pdf(wi, wo)),
            _ => self.pdf_lobe(wi, wo),
        }
    }

    /// Samples the whole BSDF (Mitsuba's strategies). `None` when the sample carries nothing
    /// (below the horizon, zero density). See each kind for its use of `u`: diffuse reads
    /// `u[1], u[2]`; conductors read `u[1], u[2]` (rough) or nothing (smooth); dielectrics
    /// read `u[0]` (reflect if `u[0] <= F`) and `u[1], u[2]` (rough: the microfacet); the
    /// thin dielectric reads `u[0]`; plastics read `u[0]` (coating if below the coating's
    /// probability) and `u[1], u[2]` (the coating's microfacet or the cosine-weighted base).
    pub fn sample(&self, wo: Vec3, u: [f32; 3], transport: Transport) -> Option<LobeSample> {
        match self {
            Bsdf::Diffuse { albedo } => {
                let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
                back_to_side(diffuse::sample(*albedo, wo, u), flipped)
            }
            Bsdf::Plastic(p) => {
                let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
                back_to_side(p.sample(wo, u), flipped)
            }
            Bsdf::MetallicRoughness(g) => {
                let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
                back_to_side(g.sample(wo, u), flipped)
            }
            _ => self.sample_lobe(wo, u, transport),
        }
    }

    /// The diffuse part's factor on the viewer's side: f_D(wi, wo) =
    /// `diffuse_out(wo) * store_weight(wi) / pi` for `wi`, `wo` on the same side (f_D is zero
    /// across the surface; a gather only uses photons from the viewer's side).
    /// Diffuse: the albedo. Plastic: `kd' t(wo) / eta^2` with kd' = kd / (1 - Fdr_int)
    /// (nonlinear: kd / (1 - kd Fdr_int)) and t the coating's transmittance. Others: zero.
    pub fn diffuse_out(&self, wo: Vec3) -> Vec3 {
        match self {
            Bsdf::Diffuse { albedo } if wo.z != 0.0 => *albedo,
            Bsdf::Plastic(p) if wo.z != 0.0 => p.diffuse_out(wo.z.abs()),
            Bsdf::MetallicRoughness(g) if wo.z != 0.0 => g.diffuse_out(wo.z.abs()),
            _ => Vec3::ZERO,
        }
    }

    /// The diffuse part's factor on the light's side, applied when a photon arriving along
    /// `wi` is stored: 1 for Diffuse, the coating's transmittance t(wi) for Plastic, 0 else.
    pub fn store_weight(&self, wi: Vec3) -> f32 {
        match self {
            Bsdf::Diffuse { .. } if wi.z != 0.0 => 1.0,
            Bsdf::Plastic(p) if wi.z != 0.0 => p.transmittance(wi.z.abs()),
            Bsdf::MetallicRoughness(g) if wi.z != 0.0 && g.has_diffuse() => 1.0,
            _ => 0.0,
        }
    }

    /// The diffuse part f_D(wi, wo) itself (zero across the surface).
    fn diffuse_value(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        if !self.has_diffuse() || wi.z * wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.diffuse_out(wo) * (self.store_weight(wi) * std::f32::consts::FRAC_1_PI)
    }

    /// The lobe part's non-delta value (Plastic: its rough coating; Diffuse: zero), so that
    /// `eval = f_D + eval_lobe`.
    pub fn eval_lobe(&self, wi: Vec3, wo: Vec3, transport: Transport) -> Vec3 {
        match *self {
            Bsdf::Diffuse { .. } | Bsdf::ThinDielectric { .. } => Vec3::ZERO,
            Bsdf::Conductor {
                eta,
                k,
                specular,
                microfacet: Some(mf),
            } => to_front(wi, wo).map_or(Vec3::ZERO, |(wi, wo, _)| {
                conductor::eval(&mf, eta, k, specular, wi, wo)
            }),
            Bsdf::Conductor {
                microfacet: None, ..
            } => Vec3::ZERO,
            Bsdf::Dielectric {
                eta,
                specular_reflectance,
                specular_transmittance,
                microfacet,
            } => match microfacet {
                Some(mf) => dielectric::eval(
                    &mf,
                    eta,
                    specular_reflectance,
                    specular_transmittance,
                    wi,
                    wo,
                    transport,
                ),
                None => Vec3::ZERO,
            },
            Bsdf::Plastic(ref p) => {
                to_front(wi, wo).map_or(Vec3::ZERO, |(wi, wo, _)| p.eval_lobe(wi, wo))
            }
            Bsdf::MetallicRoughness(ref g) => {
                to_front(wi, wo).map_or(Vec3::ZERO, |(wi, wo, _)| g.eval_lobe(wi, wo))
            }
        }
    }

    /// Solid-angle density with which [`sample_lobe`](Self::sample_lobe) produces a
    /// non-delta `wi` (zero for delta lobes and for Diffuse).
    pub fn pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        match *self {
            Bsdf::Conductor {
                microfacet: Some(mf),
                ..
            } => to_front(wi, wo).map_or(0.0, |(wi, wo, _)| conductor::pdf(&mf, wi, wo)),
            Bsdf::Dielectric {
                eta,
                microfacet: Some(mf),
                ..
            } => dielectric::pdf(&mf, eta, wi, wo),
            Bsdf::Plastic(ref p) => to_front(wi, wo).map_or(0.0, |(wi, wo, _)| p.pdf_lobe(wi, wo)),
            Bsdf::MetallicRoughness(ref g) => {
                to_front(wi, wo).map_or(0.0, |(wi, wo, _)| g.pdf_lobe(wi, wo))
            }
            _ => 0.0,
        }
    }

    /// Samples the lobe part alone (Plastic: the coating; conductors and dielectrics: all of
    /// it; Diffuse: `None`). Uniforms as for [`sample`](Self::sample), except that the
    /// plastic's coating reads only `u[1], u[2]` (rough) or nothing (smooth).
    pub fn sample_lobe(&self, wo: Vec3, u: [f32; 3], transport: Transport) -> Option<LobeSample> {
        match *self {
            Bsdf::Diffuse { .. } => None,
            Bsdf::Conductor {
                eta,
                k,
                specular,
                microfacet,
            } => {
                let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
                let s = match microfacet {
                    Some(mf) => conductor::sample(&mf, eta, k, specular, wo, u),
                    None => conductor::sample_smooth(eta, k, specular, wo),
                };
                back_to_side(s, flipped)
            }
            Bsdf::Dielectric {
                eta,
                specular_reflectance,
                specular_transmittance,
                microfacet,
            } => match microfacet {
                Some(mf) => dielectric::sample(
                    &mf,
                    eta,
                    specular_reflectance,
                    specular_transmittance,
                    wo,
                    u,
                    transport,
                ),
                None => dielectric::sample_smooth(
                    eta,
                    specular_reflectance,
                    specular_transmittance,
                    wo,
                    u,
                    transport,
                ),
            },
            Bsdf::ThinDielectric {
                eta,
                specular_reflectance,
                specular_transmittance,
            } => dielectric::sample_thin(eta, specular_reflectance, specular_transmittance, wo, u),
            Bsdf::Plastic(ref p) => {
                let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
                back_to_side(p.sample_lobe(wo, u), flipped)
            }
            Bsdf::MetallicRoughness(ref g) => {
                let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
                back_to_side(g.sample_lobe(wo, u), flipped)
            }
        }
    }

    /// The probability with which a photon seen from `wo` follows the lobe part rather than
    /// the diffuse part (kinds with both): a plastic's coating reflectance `1 - t(wo)`, a
    /// metallic-roughness material's lobe albedo against its base's; both kept inside
    /// [0.05, 0.95] so that neither part goes unsampled.
    pub fn lobe_probability(&self, wo: Vec3) -> f32 {
        match self {
            Bsdf::MetallicRoughness(g) => g.lobe_probability(wo.z.abs()),
            _ => (1.0 - self.store_weight(wo)).clamp(0.05, 0.95),
        }
    }

    /// Whether the BSDF has a diffuse part (Diffuse, Plastic, a metallic-roughness
    /// material that is not all metal or transmission).
    pub fn has_diffuse(&self) -> bool {
        match self {
            Bsdf::MetallicRoughness(g) => g.has_diffuse(),
            b => matches!(b, Bsdf::Diffuse { .. } | Bsdf::Plastic(_)),
        }
    }

    /// Whether the BSDF has a lobe part (every kind but Diffuse).
    pub fn has_lobe(&self) -> bool {
        !matches!(self, Bsdf::Diffuse { .. })
    }

    /// Whether the lobe part is a delta (smooth conductor, smooth dielectric, thin
    /// dielectric, smooth plastic); false without a lobe.
    pub fn lobe_is_delta(&self) -> bool {
        match self {
            Bsdf::Diffuse { .. } => false,
            Bsdf::Conductor { microfacet, .. } | Bsdf::Dielectric { microfacet, .. } => {
                microfacet.is_none()
            }
            Bsdf::ThinDielectric { .. } => true,
            Bsdf::Plastic(p) => p.microfacet.is_none(),
            Bsdf::MetallicRoughness(_) => false,
        }
    }
}
