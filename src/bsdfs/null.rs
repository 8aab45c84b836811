//! An index-matched boundary (Mitsuba's `null`): rays and photons pass straight through,
//! unscattered and not counted as a bounce; it only bounds media (`Material::media`). Its WGSL
//! twin holds the answers that differ from the defaults.

use crate::bsdfs::interface::{Bounce, BsdfKind, Frame, SurfaceClass};
use crate::bsdfs::param::GpuWords;
use crate::bvh::hit::Hit;
use crate::settings::FresnelMode;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// Its WGSL twin: the answers that differ from the defaults.
pub const WGSL: &str = include_str!("null.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 0;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Null;

/// Passes everything straight through.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Null;

impl BsdfKind for Null {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, _: &[SceneTexture], _: Vec2) -> Self {
        *self
    }
    fn gpu_words(&self, _: &mut GpuWords) {}
    fn has_lobe(&self) -> bool {
        false
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
    fn photon_bounce(&self, _: Frame, _: Vec3, _: &Hit, _: FresnelMode, _: [f32; 3]) -> Bounce {
        Bounce::Absorb
    }
}
