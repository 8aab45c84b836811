//! A thin dielectric sheet (Mitsuba's `thindielectric`): delta reflection with the
//! inter-reflected Fresnel `R' = 2R / (1 + R)` and straight pass-through with `1 - R'`, either
//! side alike. Camera paths split at it as at glass. Twin: `thin_dielectric.wgsl`.

use crate::bsdfs::fresnel::reflect as reflect_world;
use crate::bsdfs::interface::{BsdfKind, DeltaEvent, Dielectric, Frame, SurfaceClass};
use crate::bsdfs::interface::{LobeSample, Transport};
use crate::bsdfs::math::reflect_z;
use crate::bsdfs::microfacet::fresnel_dielectric;
use crate::bsdfs::param::{GpuWords, Param};
use crate::bvh::hit::Hit;
use crate::math::geometry::Facing;
use crate::settings::FresnelMode;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// The WGSL twin.
pub const WGSL: &str = include_str!("thin_dielectric.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 3;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Delta;

/// A thin dielectric sheet.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThinDielectric {
    /// Relative index of refraction of the sheet, interior / exterior.
    pub eta: f32,
    /// Tint of the reflected part.
    pub specular_reflectance: Param,
    /// Tint of the transmitted part.
    pub specular_transmittance: Param,
}

impl ThinDielectric {
    /// An untextured sheet.
    pub fn new(eta: f32, reflectance: Vec3, transmittance: Vec3) -> Self {
        Self {
            eta,
            specular_reflectance: Param::rgb(reflectance),
            specular_transmittance: Param::rgb(transmittance),
        }
    }
}

impl BsdfKind for ThinDielectric {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        Self {
            specular_reflectance: self.specular_reflectance.resolved(t, uv),
            specular_transmittance: self.specular_transmittance.resolved(t, uv),
            ..*self
        }
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        out.floats([self.eta, 0.0, 0.0, 0.0]);
        out.slot(&self.specular_reflectance);
        out.slot(&self.specular_transmittance);
    }
    fn lobe_is_delta(&self) -> bool {
        true
    }
    fn sample_lobe(&self, wo: Vec3, u: [f32; 3], _: Transport) -> Option<LobeSample> {
        sample_thin(
            self.eta,
            self.specular_reflectance.get(),
            self.specular_transmittance.get(),
            wo,
            u,
        )
    }
    fn splits(&self) -> bool {
        true
    }
    fn passes_null(&self) -> bool {
        true
    }
    /// `1 - R'` of the inter-reflected Fresnel reflectance, times the transmittance tint.
    fn null_transmission(&self, wo: Vec3) -> Vec3 {
        let r = fresnel_dielectric(wo.z.abs(), self.eta).0;
        let r = if r < 1.0 { 2.0 * r / (1.0 + r) } else { 1.0 };
        self.specular_transmittance.get() * (1.0 - r)
    }
    fn delta_event(&self, _: Frame, d: Vec3, _: &Hit, f: &Facing, _: FresnelMode) -> DeltaEvent {
        let r = fresnel_dielectric(d.dot(f.ns).abs(), self.eta).0;
        DeltaEvent::Split(Dielectric {
            reflected: reflect_world(d, f.ns),
            refracted: Some(d),
            reflectance: if r < 1.0 { 2.0 * r / (1.0 + r) } else { 1.0 },
            eta: 1.0,
        })
    }
}

/// The thin sheet: reflect when `u[0] <= R'` with `R' = 2R / (1 + R)` the inter-reflected
/// Fresnel reflectance (weight: the reflectance tint), else pass straight through to `-wo`
/// (weight: the transmittance tint). Only `u[0]` read; either side alike.
pub fn sample_thin(
    eta: f32,
    reflectance: Vec3,
    transmittance: Vec3,
    wo: Vec3,
    u: [f32; 3],
) -> Option<LobeSample> {
    let r = fresnel_dielectric(wo.z.abs(), eta).0;
    let r = r * 2.0 / (1.0 + r);
    let (wi, weight) = if u[0] <= r {
        (reflect_z(wo), reflectance)
    } else {
        (-wo, transmittance)
    };
    Some(LobeSample {
        wi,
        weight,
        pdf: 0.0,
        delta: true,
    })
}
