//! The BSDFs: one union of every scattering model ([`Bsdf`]), each kind one file of this
//! folder with its WGSL twin beside it, all implementing the one interface
//! [`BsdfKind`](interface::BsdfKind). The list of kinds below is the only place the set is
//! named: it makes the union, its dispatch, the kinds' GPU codes and the generated WGSL
//! dispatch (`gpu.rs`). Adding a kind is its file, its WGSL file and one line of the list
//! (docs/architecture.md, "Adding a BSDF").
//!
//! The kinds: Mitsuba 3.9.1's BSDFs (`diffuse`, `conductor`, `roughconductor`, `dielectric`,
//! `roughdielectric`, `thindielectric`, `plastic`, `roughplastic`) and glTF 2.0's
//! metallic-roughness material as pure f32 math, the classic Phong lobe and mirror, and the
//! surfaces that reflect nothing or let everything pass (`null`). Their wrappers are the
//! material's: two-sided reflective kinds (as Mitsuba's `twosided`), a mask (`Alpha`), a
//! normal map ([`material::Material`]).
//!
//! Conventions: directions are unit vectors in the local shading frame, z the shading normal
//! on the front side. `wo` points towards the viewer (for a photon: where it came from), `wi`
//! towards the light (for a photon: where it goes next), both away from the surface. Mitsuba
//! names them the other way round (its `si.wi` is our `wo`). `eval` is f(wi, wo) without the
//! cosine; [`Bsdf::eval_cos`] is Mitsuba's `eval`, f |cos theta_i|. The reflective kinds are
//! two-sided: a `wo` below the surface mirrors both directions' z to the front. Dielectrics
//! are one interface: `wo.z < 0` means the viewer is inside.
//!
//! Random numbers: every sampler takes three uniforms in [0, 1). `u[0]` picks a component
//! (reflection or transmission, coating or base) and `u[1]`, `u[2]` pick the direction;
//! each kind's sampler documents which it reads.

pub mod blend;
pub mod fresnel;
pub mod gpu;
pub mod interface;
pub mod material;
pub mod math;
pub mod microfacet;
pub mod param;
pub mod shading;

mod ior;
mod plastic_coating;
mod principled_terms;

pub mod black;
pub mod conductor;
pub mod diffuse;
pub mod glass;
pub mod metallic_roughness;
pub mod mirror;
pub mod null;
pub mod phong;
pub mod plastic;
pub mod principled;
pub mod principled_thin;
pub mod rough_conductor;
pub mod rough_dielectric;
pub mod thin_dielectric;

pub use interface::{BsdfKind, LobeSample, SurfaceClass, Transport};
pub use metallic_roughness::{
    schlick_mean, schlick_mean_table, MetallicRoughness, SCHLICK_MEAN_RES,
};
pub use microfacet::{
    fresnel_conductor, fresnel_dielectric, fresnel_diffuse_reflectance, named_conductor,
    Distribution, Microfacet, METAL_NAMES,
};
pub use param::{Channel, Param};
pub use plastic::{Plastic, TRANSMITTANCE_RES};
pub use principled::Principled;
pub use principled_thin::PrincipledThin;

use crate::bsdfs::interface::{Bounce, DeltaEvent, Frame, LobeRay};
use crate::bsdfs::param::GpuWords;
use crate::bvh::hit::Hit;
use crate::math::geometry::Facing;
use crate::math::rng::Rng;
use crate::settings::FresnelMode;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// One kind of the list, as the GPU's generated dispatch needs it.
#[derive(Clone, Copy, Debug)]
pub struct KindInfo {
    /// The variant's name (`MetallicRoughness`).
    pub name: &'static str,
    /// Its module, the prefix of its WGSL functions (`rough_conductor_eval_lobe`).
    pub prefix: &'static str,
    /// Its WGSL file, or "" when the WGSL defaults (`shading.wgsl`) and the generated
    /// properties say all it does.
    pub wgsl: &'static str,
    /// Its class ([`SurfaceClass`]).
    pub class: SurfaceClass,
    /// The 16-byte words its parameters take on the GPU (`BsdfKind::gpu_words`).
    pub words: usize,
    /// Its generated WGSL constants (tables computed in Rust), if any.
    pub consts: fn() -> String,
}

/// No generated WGSL constants.
fn no_consts() -> String {
    String::new()
}

/// The list of kinds: the union's variants, in the order of their GPU codes.
macro_rules! bsdf_kinds {
    ($($(#[$doc:meta])* $variant:ident($module:ident::$ty:ident) $(consts $consts:path)?),+ $(,)?) => {
        /// A scattering model with its parameters: the one tagged union of the kinds.
        #[derive(Clone, Copy, Debug, PartialEq)]
        #[allow(clippy::large_enum_variant)] // Copy and allocation-free matter more than the size
        pub enum Bsdf {
            $($(#[$doc])* $variant($module::$ty)),+
        }

        $(impl From<$module::$ty> for Bsdf {
            fn from(k: $module::$ty) -> Self {
                Bsdf::$variant(k)
            }
        })+

        /// The GPU code of each kind (its index in the list).
        #[derive(Clone, Copy, Debug, PartialEq, Eq)]
        #[repr(u32)]
        pub enum KindCode {
            $(#[allow(missing_docs)] $variant),+
        }

        /// Every kind, in the order of their codes.
        pub const KINDS: &[KindInfo] = &[$(KindInfo {
            name: stringify!($variant),
            prefix: stringify!($module),
            wgsl: $module::WGSL,
            class: $module::CLASS,
            words: $module::WORDS,
            consts: { #[allow(unused_variables)] let c: fn() -> String = no_consts; $(let c: fn() -> String = $consts;)? c },
        }),+];

        impl Bsdf {
            /// The kind's GPU code.
            pub fn code(&self) -> u32 {
                match self {
                    $(Bsdf::$variant(_) => KindCode::$variant as u32),+
                }
            }
        }

        impl BsdfKind for Bsdf {
            fn class(&self) -> SurfaceClass { match self { $(Bsdf::$variant(k) => k.class()),+ } }
            fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
                match self { $(Bsdf::$variant(k) => Bsdf::$variant(k.resolve(t, uv))),+ }
            }
            fn gpu_words(&self, out: &mut GpuWords) { match self { $(Bsdf::$variant(k) => k.gpu_words(out)),+ } }
            fn base_colour_mut(&mut self) -> Option<&mut Param> {
                match self { $(Bsdf::$variant(k) => k.base_colour_mut()),+ }
            }
            fn check(&self, at: &dyn crate::scene::locate::Locate) -> crate::error::Result<()> {
                match self { $(Bsdf::$variant(k) => k.check(at)),+ }
            }
            fn diffuse_out(&self, wo: Vec3) -> Vec3 { match self { $(Bsdf::$variant(k) => k.diffuse_out(wo)),+ } }
            fn store_weight(&self, wi: Vec3) -> f32 { match self { $(Bsdf::$variant(k) => k.store_weight(wi)),+ } }
            fn eval_lobe(&self, wi: Vec3, wo: Vec3, t: Transport) -> Vec3 {
                match self { $(Bsdf::$variant(k) => k.eval_lobe(wi, wo, t)),+ }
            }
            fn pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 { match self { $(Bsdf::$variant(k) => k.pdf_lobe(wi, wo)),+ } }
            fn sample_lobe(&self, wo: Vec3, u: [f32; 3], t: Transport) -> Option<LobeSample> {
                match self { $(Bsdf::$variant(k) => k.sample_lobe(wo, u, t)),+ }
            }
            fn has_diffuse(&self) -> bool { match self { $(Bsdf::$variant(k) => k.has_diffuse()),+ } }
            fn has_lobe(&self) -> bool { match self { $(Bsdf::$variant(k) => k.has_lobe()),+ } }
            fn lobe_is_delta(&self) -> bool { match self { $(Bsdf::$variant(k) => k.lobe_is_delta()),+ } }
            fn lobe_probability(&self, wo: Vec3) -> f32 { match self { $(Bsdf::$variant(k) => k.lobe_probability(wo)),+ } }
            fn diffuse_value(&self, wi: Vec3, wo: Vec3) -> Vec3 {
                match self { $(Bsdf::$variant(k) => k.diffuse_value(wi, wo)),+ }
            }
            fn eval(&self, wi: Vec3, wo: Vec3, t: Transport) -> Vec3 {
                match self { $(Bsdf::$variant(k) => k.eval(wi, wo, t)),+ }
            }
            fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 { match self { $(Bsdf::$variant(k) => k.pdf(wi, wo)),+ } }
            fn sample(&self, wo: Vec3, u: [f32; 3], t: Transport) -> Option<LobeSample> {
                match self { $(Bsdf::$variant(k) => k.sample(wo, u, t)),+ }
            }
            fn stores_photons(&self) -> bool { match self { $(Bsdf::$variant(k) => k.stores_photons()),+ } }
            fn casts_caustics(&self) -> bool { match self { $(Bsdf::$variant(k) => k.casts_caustics()),+ } }
            fn lobe_takes_point_lights(&self) -> bool {
                match self { $(Bsdf::$variant(k) => k.lobe_takes_point_lights()),+ }
            }
            fn passes_null(&self) -> bool { match self { $(Bsdf::$variant(k) => k.passes_null()),+ } }
            fn null_transmission(&self, wo: Vec3) -> Vec3 {
                match self { $(Bsdf::$variant(k) => k.null_transmission(wo)),+ }
            }
            fn lobe_transmits(&self) -> bool { match self { $(Bsdf::$variant(k) => k.lobe_transmits()),+ } }
            fn splits(&self) -> bool { match self { $(Bsdf::$variant(k) => k.splits()),+ } }
            fn delta_event(&self, n: Frame, d: Vec3, hit: &Hit, f: &Facing, fr: FresnelMode) -> DeltaEvent {
                match self { $(Bsdf::$variant(k) => k.delta_event(n, d, hit, f, fr)),+ }
            }
            fn surface_diffuse_albedo(&self, n: Frame, wo: Vec3) -> Vec3 {
                match self { $(Bsdf::$variant(k) => k.surface_diffuse_albedo(n, wo)),+ }
            }
            fn surface_store_weight(&self, n: Frame, wi: Vec3) -> Option<f32> {
                match self { $(Bsdf::$variant(k) => k.surface_store_weight(n, wi)),+ }
            }
            fn surface_eval_diffuse(&self, n: Frame, wi: Vec3, wo: Vec3) -> Vec3 {
                match self { $(Bsdf::$variant(k) => k.surface_eval_diffuse(n, wi, wo)),+ }
            }
            fn surface_eval_lobe(&self, n: Frame, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
                match self { $(Bsdf::$variant(k) => k.surface_eval_lobe(n, wi, wo, ns)),+ }
            }
            fn surface_eval(&self, n: Frame, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
                match self { $(Bsdf::$variant(k) => k.surface_eval(n, wi, wo, ns)),+ }
            }
            fn surface_pdf_lobe(&self, n: Frame, wi: Vec3, wo: Vec3, ns: Vec3) -> f32 {
                match self { $(Bsdf::$variant(k) => k.surface_pdf_lobe(n, wi, wo, ns)),+ }
            }
            fn lobe_is_glossy(&self) -> bool { match self { $(Bsdf::$variant(k) => k.lobe_is_glossy()),+ } }
            fn surface_sample_lobe(&self, n: Frame, d: Vec3, f: &Facing, rng: &mut Rng) -> Option<LobeRay> {
                match self { $(Bsdf::$variant(k) => k.surface_sample_lobe(n, d, f, rng)),+ }
            }
            fn photon_bounce(&self, n: Frame, d: Vec3, hit: &Hit, fr: FresnelMode, u: [f32; 3]) -> Bounce {
                match self { $(Bsdf::$variant(k) => k.photon_bounce(n, d, hit, fr, u)),+ }
            }
        }
    };
}

bsdf_kinds! {
    /// Reflects nothing (an area light's surface, an absorber).
    Black(black::Black),
    /// An index-matched boundary (Mitsuba's `null`): everything passes straight through.
    Null(null::Null),
    /// Lambertian reflection (`diffuse`).
    Diffuse(diffuse::Diffuse),
    /// A Lambertian base plus a normalised Phong lobe (TOML's `glossy`).
    Phong(phong::Phong),
    /// A perfect mirror.
    Mirror(mirror::Mirror),
    /// A smooth dielectric interface (`dielectric`).
    Glass(glass::Glass),
    /// A smooth conductor (`conductor`).
    Conductor(conductor::Conductor),
    /// A microfacet conductor.
    RoughConductor(rough_conductor::RoughConductor),
    /// A microfacet dielectric interface (`roughdielectric`).
    RoughDielectric(rough_dielectric::RoughDielectric),
    /// A thin dielectric sheet (`thindielectric`).
    ThinDielectric(thin_dielectric::ThinDielectric),
    /// A diffuse base under a smooth or rough dielectric coating (`plastic`, `roughplastic`).
    Plastic(plastic::Plastic) consts plastic::wgsl_consts,
    /// glTF 2.0's metallic-roughness material.
    MetallicRoughness(metallic_roughness::MetallicRoughness) consts metallic_roughness::wgsl_consts,
    /// Mitsuba's principled BSDF (`principled`).
    Principled(principled::Principled),
    /// Mitsuba's thin principled BSDF (`principledthin`).
    PrincipledThin(principled_thin::PrincipledThin),
}

/// A surface that reflects nothing.
impl Default for Bsdf {
    fn default() -> Self {
        Bsdf::Black(black::Black)
    }
}

impl Bsdf {
    /// Mitsuba's `diffuse` of albedo `albedo`.
    pub fn diffuse(albedo: Vec3) -> Self {
        diffuse::Diffuse::new(albedo).into()
    }

    /// Mitsuba's `conductor` (`microfacet` `None`) or `roughconductor`.
    pub fn conductor(eta: Vec3, k: Vec3, specular: Vec3, microfacet: Option<Microfacet>) -> Self {
        match microfacet {
            None => conductor::Conductor {
                eta,
                k,
                specular: Param::rgb(specular),
            }
            .into(),
            Some(mf) => rough_conductor::RoughConductor::new(eta, k, specular, mf).into(),
        }
    }

    /// Mitsuba's `dielectric` (`microfacet` `None`) or `roughdielectric` of index `eta`.
    pub fn dielectric(
        eta: f32,
        reflectance: Vec3,
        transmittance: Vec3,
        microfacet: Option<Microfacet>,
    ) -> Self {
        match microfacet {
            None => glass::Glass::tinted(eta, reflectance, transmittance).into(),
            Some(mf) => {
                rough_dielectric::RoughDielectric::new(eta, reflectance, transmittance, mf).into()
            }
        }
    }

    /// Mitsuba's `thindielectric` of index `eta`.
    pub fn thin_dielectric(eta: f32, reflectance: Vec3, transmittance: Vec3) -> Self {
        thin_dielectric::ThinDielectric::new(eta, reflectance, transmittance).into()
    }

    /// The base colour (a diffuse reflectance) of the kinds that have one, as a constant or a
    /// texture's factor.
    pub fn base_colour(&self) -> Option<Param> {
        let mut b = *self;
        b.base_colour_mut().copied()
    }

    /// `eval * |wi.z|`: the value Mitsuba's `BSDF::eval` returns.
    pub fn eval_cos(&self, wi: Vec3, wo: Vec3, transport: Transport) -> Vec3 {
        self.eval(wi, wo, transport) * wi.z.abs()
    }
}
