//! A smooth conductor (Mitsuba's `conductor`): the mirror direction weighted by the
//! complex-index Fresnel reflectance times a tint, two-sided. Twin: `conductor.wgsl`.

use crate::bsdfs::interface::{back_to_side, to_front, LobeSample, Transport};
use crate::bsdfs::interface::{BsdfKind, SurfaceClass};
use crate::bsdfs::math::reflect_z;
use crate::bsdfs::microfacet::fresnel_conductor;
use crate::bsdfs::param::{GpuWords, Param};
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// The WGSL twin.
pub const WGSL: &str = include_str!("conductor.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 3;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Delta;

/// A smooth conductor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Conductor {
    /// Real part of the relative complex index of refraction, per channel.
    pub eta: Vec3,
    /// Imaginary part (absorption), per channel.
    pub k: Vec3,
    /// Tint multiplying the Fresnel reflectance (`specular_reflectance`).
    pub specular: Param,
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

impl BsdfKind for Conductor {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        Self {
            specular: self.specular.resolved(t, uv),
            ..*self
        }
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        out.rgb_u(self.eta, 0);
        out.rgb_u(self.k, 0);
        out.slot(&self.specular);
    }
    fn lobe_is_delta(&self) -> bool {
        true
    }
    fn sample_lobe(&self, wo: Vec3, _: [f32; 3], _: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
        back_to_side(
            sample_smooth(self.eta, self.k, self.specular.get(), wo),
            flipped,
        )
    }
}
