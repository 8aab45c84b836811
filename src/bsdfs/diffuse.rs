//! Lambertian reflection (Mitsuba's `diffuse`, TOML's `diffuse`): f = albedo / pi, two-sided,
//! sampled with the cosine-weighted hemisphere. Photons bounce by the classic roulette on the
//! albedo ([`crate::bsdfs::phong::classic_bounce`]). Twin: `diffuse.wgsl`.

use crate::bsdfs::interface::{back_to_side, to_front, LobeSample, Transport};
use crate::bsdfs::interface::{Bounce, BsdfKind, Frame, SurfaceClass};
use crate::bsdfs::math::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::bsdfs::param::{GpuWords, Param};
use crate::bsdfs::phong::classic_bounce;
use crate::bvh::hit::Hit;
use crate::error::Result;
use crate::scene::locate::{check_color, Locate, Part};
use crate::settings::FresnelMode;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The WGSL twin.
pub const WGSL: &str = include_str!("diffuse.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 1;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Shaded;

/// Lambertian reflection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Diffuse {
    /// The albedo.
    pub reflectance: Param,
}

impl Diffuse {
    /// An untextured albedo.
    pub fn new(albedo: Vec3) -> Self {
        Self {
            reflectance: Param::rgb(albedo),
        }
    }
}

/// Density of the cosine-weighted sample: cos theta_i / pi on the front side (`wo.z > 0`).
pub fn pdf(wi: Vec3, wo: Vec3) -> f32 {
    if wi.z > 0.0 && wo.z > 0.0 {
        cosine_hemisphere_pdf(wi)
    } else {
        0.0
    }
}

impl BsdfKind for Diffuse {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        Self {
            reflectance: self.reflectance.resolved(t, uv),
        }
    }
    fn base_colour_mut(&mut self) -> Option<&mut Param> {
        Some(&mut self.reflectance)
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        out.slot(&self.reflectance);
    }
    fn check(&self, at: &dyn Locate) -> Result<()> {
        check_color(
            self.reflectance.get(),
            Some(1.0),
            Part::Parameter("albedo"),
            at,
        )
    }
    fn diffuse_out(&self, wo: Vec3) -> Vec3 {
        if wo.z != 0.0 {
            self.reflectance.get()
        } else {
            Vec3::ZERO
        }
    }
    fn store_weight(&self, wi: Vec3) -> f32 {
        if wi.z != 0.0 {
            1.0
        } else {
            0.0
        }
    }
    fn has_diffuse(&self) -> bool {
        true
    }
    fn has_lobe(&self) -> bool {
        false
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        to_front(wi, wo).map_or(0.0, |(wi, wo, _)| pdf(wi, wo))
    }
    /// A cosine-weighted `wi` from `u[1], u[2]` (`u[0]` unused); weight = albedo.
    fn sample(&self, wo: Vec3, u: [f32; 3], _: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
        let wi = square_to_cosine_hemisphere(Vec2::new(u[1], u[2]));
        let pdf = pdf(wi, wo);
        let s = (pdf > 0.0).then_some(LobeSample {
            wi,
            weight: self.reflectance.get(),
            pdf,
            delta: false,
        });
        back_to_side(s, flipped)
    }
    fn surface_diffuse_albedo(&self, _: Frame, _: Vec3) -> Vec3 {
        self.reflectance.get()
    }
    fn surface_store_weight(&self, _: Frame, _: Vec3) -> Option<f32> {
        None
    }
    fn surface_eval_diffuse(&self, _: Frame, _: Vec3, _: Vec3) -> Vec3 {
        self.reflectance.get() / PI
    }
    fn surface_eval(&self, _: Frame, _: Vec3, _: Vec3, _: Vec3) -> Vec3 {
        self.reflectance.get() / PI
    }
    fn photon_bounce(&self, _: Frame, d: Vec3, hit: &Hit, _: FresnelMode, u: [f32; 3]) -> Bounce {
        classic_bounce(self.reflectance.get(), Vec3::ZERO, 0.0, d, hit, u)
    }
}
