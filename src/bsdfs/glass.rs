//! A smooth dielectric interface (Mitsuba's `dielectric`, TOML's `glass`): index `eta`
//! inside over outside, exact (or Schlick's, `--fresnel`) unpolarised Fresnel. Camera paths
//! split at it below a depth ([`DeltaEvent::Split`]); photons choose by the reflectance. In
//! the local frame it is Mitsuba's smooth dielectric with its tints; a scene's glass is
//! untinted (the builder refuses tints, which the camera paths' splits do not carry yet).
//! Twin: `glass.wgsl`.

use crate::bsdfs::fresnel::dielectric_shading;
use crate::bsdfs::interface::{Bounce, BsdfKind, DeltaEvent, Frame, SurfaceClass};
use crate::bsdfs::interface::{LobeSample, Transport};
use crate::bsdfs::math::reflect_z;
use crate::bsdfs::microfacet::fresnel_dielectric;
use crate::bsdfs::param::{GpuWords, Param};
use crate::bvh::hit::Hit;
use crate::error::Result;
use crate::math::geometry::Facing;
use crate::scene::locate::{Locate, Part};
use crate::settings::FresnelMode;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// The WGSL twin.
pub const WGSL: &str = include_str!("glass.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 3;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Delta;

/// A smooth dielectric interface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Glass {
    /// Index of refraction inside over outside.
    pub eta: f32,
    /// Tint of the reflected part (Mitsuba's `specular_reflectance`).
    pub specular_reflectance: Param,
    /// Tint of the transmitted part.
    pub specular_transmittance: Param,
}

impl Glass {
    /// Untinted glass of index `eta`.
    pub fn new(eta: f32) -> Self {
        Self::tinted(eta, Vec3::ONE, Vec3::ONE)
    }

    /// Glass of index `eta` with Mitsuba's tints.
    pub fn tinted(eta: f32, reflectance: Vec3, transmittance: Vec3) -> Self {
        Self {
            eta,
            specular_reflectance: Param::rgb(reflectance),
            specular_transmittance: Param::rgb(transmittance),
        }
    }
}

/// Mitsuba's smooth dielectric: reflect when `u[0] <= F(cos_o)` (weight: the reflectance
/// tint), else refract (weight: the transmittance tint, times `eta_ti^2` for radiance). Only
/// `u[0]` read.
pub fn sample_smooth(
    eta: f32,
    reflectance: Vec3,
    transmittance: Vec3,
    wo: Vec3,
    u: [f32; 3],
    transport: Transport,
) -> Option<LobeSample> {
    let (r, cos_t, _, eta_ti) = fresnel_dielectric(wo.z, eta);
    let (wi, weight) = if u[0] <= r {
        (reflect_z(wo), reflectance)
    } else {
        let factor = match transport {
            Transport::Radiance => eta_ti * eta_ti,
            Transport::Importance => 1.0,
        };
        (
            Vec3::new(-eta_ti * wo.x, -eta_ti * wo.y, cos_t),
            transmittance * factor,
        )
    };
    Some(LobeSample {
        wi,
        weight,
        pdf: 0.0,
        delta: true,
    })
}

impl BsdfKind for Glass {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        Self {
            eta: self.eta,
            specular_reflectance: self.specular_reflectance.resolved(t, uv),
            specular_transmittance: self.specular_transmittance.resolved(t, uv),
        }
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        out.floats([self.eta, 0.0, 0.0, 0.0]);
        out.slot(&self.specular_reflectance);
        out.slot(&self.specular_transmittance);
    }
    fn check(&self, at: &dyn Locate) -> Result<()> {
        let untinted = |p: &Param| !p.is_textured() && p.get() == Vec3::ONE;
        if !untinted(&self.specular_reflectance) || !untinted(&self.specular_transmittance) {
            let message = "a tinted smooth dielectric is not supported yet";
            return Err(at.error(Part::Parameter("specular_reflectance"), message.into()));
        }
        match self.eta {
            ior if ior.is_finite() && ior > 0.0 => Ok(()),
            _ => Err(at.error(Part::Parameter("ior"), "must be positive and finite".into())),
        }
    }
    fn lobe_is_delta(&self) -> bool {
        true
    }
    fn sample_lobe(&self, wo: Vec3, u: [f32; 3], t: Transport) -> Option<LobeSample> {
        let (r, tr) = (
            self.specular_reflectance.get(),
            self.specular_transmittance.get(),
        );
        sample_smooth(self.eta, r, tr, wo, u, t)
    }
    fn splits(&self) -> bool {
        true
    }
    fn delta_event(
        &self,
        _: Frame,
        d: Vec3,
        hit: &Hit,
        _: &Facing,
        fresnel: FresnelMode,
    ) -> DeltaEvent {
        DeltaEvent::Split(dielectric_shading(
            d,
            hit.normal,
            hit.shading,
            self.eta,
            fresnel,
        ))
    }
    fn surface_diffuse_albedo(&self, _: Frame, _: Vec3) -> Vec3 {
        Vec3::ZERO
    }
    fn surface_store_weight(&self, _: Frame, _: Vec3) -> Option<f32> {
        None
    }
    fn surface_eval_diffuse(&self, _: Frame, _: Vec3, _: Vec3) -> Vec3 {
        Vec3::ZERO
    }
    fn photon_bounce(
        &self,
        _: Frame,
        d: Vec3,
        hit: &Hit,
        fresnel: FresnelMode,
        u: [f32; 3],
    ) -> Bounce {
        let f = Facing::new(hit.normal, hit.shading, d.dot(hit.normal) < 0.0);
        let g = dielectric_shading(d, hit.normal, hit.shading, self.eta, fresnel);
        match g.refracted {
            Some(t) if u[0] >= g.reflectance => {
                if f.refraction_leaks(t) {
                    return Bounce::Absorb;
                }
                Bounce::Specular {
                    dir: t,
                    weight: Vec3::ONE,
                    delta: true,
                }
            }
            _ => {
                if f.reflection_leaks(g.reflected) {
                    return Bounce::Absorb;
                }
                Bounce::Specular {
                    dir: g.reflected,
                    weight: Vec3::ONE,
                    delta: true,
                }
            }
        }
    }
}
