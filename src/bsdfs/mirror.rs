//! A perfect mirror (TOML's `mirror`): reflected radiance = reflectance x incident radiance,
//! no Fresnel, two-sided. Photons reflect by roulette on the reflectance. Twin: `mirror.wgsl`.

use crate::bsdfs::fresnel::reflect;
use crate::bsdfs::interface::{back_to_side, to_front, LobeSample, Transport};
use crate::bsdfs::interface::{Bounce, BsdfKind, DeltaEvent, Frame, SurfaceClass};
use crate::bsdfs::math::reflect_z;
use crate::bsdfs::param::{GpuWords, Param};
use crate::bvh::hit::Hit;
use crate::error::Result;
use crate::math::geometry::Facing;
use crate::scene::locate::{check_color, Locate, Part};
use crate::settings::FresnelMode;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// The WGSL twin.
pub const WGSL: &str = include_str!("mirror.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 1;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Delta;

/// A perfect mirror.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mirror {
    /// The reflectance.
    pub reflectance: Param,
}

impl Mirror {
    /// An untextured reflectance.
    pub fn new(reflectance: Vec3) -> Self {
        Self {
            reflectance: Param::rgb(reflectance),
        }
    }
}

impl BsdfKind for Mirror {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        Self {
            reflectance: self.reflectance.resolved(t, uv),
        }
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        out.slot(&self.reflectance);
    }
    fn check(&self, at: &dyn Locate) -> Result<()> {
        check_color(
            self.reflectance.get(),
            Some(1.0),
            Part::Parameter("reflectance"),
            at,
        )
    }
    fn lobe_is_delta(&self) -> bool {
        true
    }
    fn sample_lobe(&self, wo: Vec3, _: [f32; 3], _: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
        let s = LobeSample {
            wi: reflect_z(wo),
            weight: self.reflectance.get(),
            pdf: 0.0,
            delta: true,
        };
        back_to_side(Some(s), flipped)
    }
    fn delta_event(&self, _: Frame, d: Vec3, _: &Hit, f: &Facing, _: FresnelMode) -> DeltaEvent {
        DeltaEvent::Reflect {
            dir: reflect(d, f.ns),
            weight: self.reflectance.get(),
        }
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
    fn photon_bounce(&self, _: Frame, d: Vec3, hit: &Hit, _: FresnelMode, u: [f32; 3]) -> Bounce {
        let f = Facing::new(hit.normal, hit.shading, d.dot(hit.normal) < 0.0);
        let ks = self.reflectance.get();
        let p = ks.max_element();
        if u[0] >= p {
            return Bounce::Absorb;
        }
        let dir = reflect(d, f.ns);
        if f.reflection_leaks(dir) {
            return Bounce::Absorb;
        }
        Bounce::Specular {
            dir,
            weight: ks / p,
            delta: true,
        }
    }
}
