//! The scene's materials: the closed set of kinds and their parameters (`crate::bsdfs::shading`
//! is the one place the integrators read them).

use crate::bsdfs::Bsdf;
use crate::media::MediumInterface;
use glam::Vec3;

/// The kind of surface scattering a material performs.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MaterialKind {
    /// Lambertian: BRDF = albedo / pi, two-sided.
    Diffuse,
    /// Lambertian `kd` plus a normalised Phong lobe `ks (n+2)/(2 pi) cos^n` around the mirror direction.
    Glossy,
    /// Perfect mirror: reflected radiance = reflectance x incident radiance.
    Mirror,
    /// Smooth dielectric with index of refraction `ior` inside, 1.0 outside.
    Glass,
    /// Reflects nothing (the surface of an area light, or a black absorber).
    Black,
    /// Smooth conductor (complex index of refraction): [`Material::bsdf`], a delta lobe.
    Conductor,
    /// Microfacet conductor: [`Material::bsdf`].
    RoughConductor,
    /// Microfacet dielectric boundary (reflection and transmission): [`Material::bsdf`].
    RoughDielectric,
    /// Thin dielectric sheet (delta reflection and straight pass-through): [`Material::bsdf`].
    ThinDielectric,
    /// Diffuse base under a smooth dielectric coating: [`Material::bsdf`].
    Plastic,
    /// Diffuse base under a microfacet coating: [`Material::bsdf`].
    RoughPlastic,
    /// glTF 2.0's metallic-roughness material: [`Material::bsdf`], with
    /// [`Material::kd_texture`] its base colour and [`Material::mr_texture`] its metalness
    /// and roughness.
    MetallicRoughness,
    /// An index-matched boundary (Mitsuba's `null`): rays and photons pass straight through,
    /// unscattered; it only bounds media ([`Material::media`]).
    Null,
}

impl MaterialKind {
    /// Every kind, in the order of their GPU codes.
    pub const ALL: [MaterialKind; 13] = [
        MaterialKind::Diffuse,
        MaterialKind::Glossy,
        MaterialKind::Mirror,
        MaterialKind::Glass,
        MaterialKind::Black,
        MaterialKind::Conductor,
        MaterialKind::RoughConductor,
        MaterialKind::RoughDielectric,
        MaterialKind::ThinDielectric,
        MaterialKind::Plastic,
        MaterialKind::RoughPlastic,
        MaterialKind::MetallicRoughness,
        MaterialKind::Null,
    ];

    /// The kind a [`Bsdf`] of `crate::bsdfs` is rendered as.
    pub fn of_bsdf(b: &Bsdf) -> MaterialKind {
        match b {
            Bsdf::Diffuse { .. } => MaterialKind::Diffuse,
            Bsdf::Conductor {
                microfacet: None, ..
            } => MaterialKind::Conductor,
            Bsdf::Conductor { .. } => MaterialKind::RoughConductor,
            Bsdf::Dielectric {
                microfacet: None, ..
            } => MaterialKind::Glass,
            Bsdf::Dielectric { .. } => MaterialKind::RoughDielectric,
            Bsdf::ThinDielectric { .. } => MaterialKind::ThinDielectric,
            Bsdf::Plastic(p) if p.microfacet.is_none() => MaterialKind::Plastic,
            Bsdf::Plastic(_) => MaterialKind::RoughPlastic,
            Bsdf::MetallicRoughness(_) => MaterialKind::MetallicRoughness,
        }
    }
}

pub use crate::textures::NO_TEXTURE;

/// A material. Unused coefficients are zero.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// How the surface scatters light.
    pub kind: MaterialKind,
    /// Diffuse albedo (`diffuse`) or `kd` (`glossy`).
    pub kd: Vec3,
    /// Specular coefficient (`glossy`) or reflectance (`mirror`).
    pub ks: Vec3,
    /// Phong exponent of the glossy lobe.
    pub exponent: f32,
    /// Index of refraction of a glass interior.
    pub ior: f32,
    /// Radiance emitted from the front face (zero for non-emitters).
    pub emission: Vec3,
    /// Whether emission leaves both faces.
    pub two_sided_emission: bool,
    /// The parameters of the kinds after `Black` (conductors, rough dielectrics, plastics);
    /// `None` for the others.
    pub bsdf: Option<Bsdf>,
    /// Index into [`Scene::textures`](crate::scene::Scene::textures) of the texture that gives `kd` at a hit (a `diffuse`
    /// material's albedo), or [`NO_TEXTURE`].
    pub kd_texture: u32,
    /// Index into [`Scene::textures`](crate::scene::Scene::textures) of a tangent-space normal map (Mitsuba's `normalmap`
    /// bsdf: the texture's rgb `c` is the normal `2 c - 1` in the hit's shading frame, see
    /// `crate::bvh::perturb`), or [`NO_TEXTURE`].
    pub normal_texture: u32,
    /// Index into [`Scene::textures`](crate::scene::Scene::textures) of a metallic-roughness material's metalness (blue)
    /// and roughness (green) texture, multiplying its factors, or [`NO_TEXTURE`].
    pub mr_texture: u32,
    /// glTF's other parameter textures of a metallic-roughness material, each
    /// [`NO_TEXTURE`] when absent: `KHR_materials_transmission`'s (red scales the
    /// transmission), `KHR_materials_specular`'s specular (alpha scales the specular factor)
    /// and specular colour (rgb scales the F0 colour).
    pub gltf_textures: [u32; 3],
    /// Index into [`Scene::textures`](crate::scene::Scene::textures) of a texture multiplying `emission` at each point (glTF
    /// `emissiveTexture`, Mitsuba's textured `radiance`; `crate::lights::emission`), or
    /// [`NO_TEXTURE`].
    pub emission_texture: u32,
    /// Cut-outs and partial coverage (glTF `alphaMode` MASK and BLEND, Mitsuba's `mask`);
    /// `None` for an opaque surface.
    pub alpha: Option<Alpha>,
    /// The media the surface bounds (vacuum on both sides by default; `crate::media`).
    pub media: MediumInterface,
}

/// Whether a ray passes a surface of a material with an [`Alpha`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AlphaMode {
    /// Opaque where the opacity is at least the cutoff, else fully transparent (glTF MASK).
    Mask(f32),
    /// Opaque with probability equal to the opacity (glTF BLEND, Mitsuba's `mask`): a
    /// stochastic choice per ray and hit, unbiased for the coverage.
    Blend,
}

/// The opacity of a surface: `factor` times the texture's alpha (or luminance) at the hit.
/// Emitters ignore it: a light's surface is opaque.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Alpha {
    /// Mask or blend.
    pub mode: AlphaMode,
    /// Constant opacity (glTF `baseColorFactor`'s alpha, Mitsuba's float `opacity`).
    pub factor: f32,
    /// Index into [`Scene::textures`](crate::scene::Scene::textures) of the texture that varies it, or [`NO_TEXTURE`].
    pub texture: u32,
    /// Read the texture's luminance (Mitsuba's textured `opacity`) instead of its alpha
    /// (glTF's base colour alpha).
    pub luminance: bool,
}

impl Alpha {
    /// The opacity at `uv`, in [0, 1].
    pub fn opacity(&self, textures: &[crate::textures::SceneTexture], uv: glam::Vec2) -> f32 {
        let t = match self.texture {
            NO_TEXTURE => 1.0,
            i if self.luminance => {
                // Rec. 709 luminance of linear RGB, as Mitsuba's `luminance()`.
                textures[i as usize]
                    .eval(uv)
                    .dot(Vec3::new(0.212_671, 0.715_160, 0.072_169))
            }
            i => textures[i as usize].eval_alpha(uv),
        };
        (self.factor * t).clamp(0.0, 1.0)
    }

    /// Whether a ray is stopped at a point of opacity `opacity`; `u` in [0, 1) is the ray's
    /// own uniform for this hit (used by [`AlphaMode::Blend`]).
    pub fn stops(&self, opacity: f32, u: f32) -> bool {
        match self.mode {
            AlphaMode::Mask(cutoff) => opacity >= cutoff,
            AlphaMode::Blend => u < opacity,
        }
    }
}

impl Material {
    /// A Lambertian surface of `albedo`.
    pub fn diffuse(albedo: Vec3) -> Self {
        Self {
            kind: MaterialKind::Diffuse,
            kd: albedo,
            ..Self::black()
        }
    }
    /// Lambertian `kd` plus a normalised Phong lobe `ks` of exponent `exponent`.
    pub fn glossy(kd: Vec3, ks: Vec3, exponent: f32) -> Self {
        Self {
            kind: MaterialKind::Glossy,
            kd,
            ks,
            exponent,
            ..Self::black()
        }
    }
    /// A perfect mirror of `reflectance`.
    pub fn mirror(reflectance: Vec3) -> Self {
        Self {
            kind: MaterialKind::Mirror,
            ks: reflectance,
            ..Self::black()
        }
    }
    /// A smooth dielectric of index `ior` inside.
    pub fn glass(ior: f32) -> Self {
        Self {
            kind: MaterialKind::Glass,
            ior,
            ..Self::black()
        }
    }
    /// An index-matched boundary: passes everything straight through (bounds media).
    pub fn null() -> Self {
        Self {
            kind: MaterialKind::Null,
            ..Self::black()
        }
    }
    /// A surface that reflects and emits nothing; the base of the other constructors.
    pub fn black() -> Self {
        Self {
            kind: MaterialKind::Black,
            kd: Vec3::ZERO,
            ks: Vec3::ZERO,
            exponent: 0.0,
            ior: 1.0,
            emission: Vec3::ZERO,
            two_sided_emission: false,
            bsdf: None,
            kd_texture: NO_TEXTURE,
            normal_texture: NO_TEXTURE,
            mr_texture: NO_TEXTURE,
            gltf_textures: [NO_TEXTURE; 3],
            emission_texture: NO_TEXTURE,
            alpha: None,
            media: MediumInterface::default(),
        }
    }
    /// A material of one of [`crate::bsdfs`]'s BSDFs: `Diffuse` and a smooth `Dielectric`
    /// become the `diffuse` and `glass` kinds (exact Fresnel, untinted), the others keep
    /// their parameters in [`Material::bsdf`].
    pub fn from_bsdf(b: Bsdf) -> Self {
        match b {
            Bsdf::Diffuse { albedo } => Self::diffuse(albedo),
            Bsdf::Dielectric {
                eta,
                microfacet: None,
                ..
            } => Self::glass(eta),
            b => Self {
                kind: MaterialKind::of_bsdf(&b),
                bsdf: Some(b),
                ..Self::black()
            },
        }
    }
    /// An area-light surface: emits `radiance` from its front face, reflects nothing.
    pub fn emitter(radiance: Vec3) -> Self {
        Self {
            emission: radiance,
            ..Self::black()
        }
    }
    /// Delta BSDFs only (mirror, glass, smooth conductor, thin dielectric): the `S` of
    /// Heckbert's path notation.
    pub fn is_specular(&self) -> bool {
        matches!(
            self.kind,
            MaterialKind::Mirror
                | MaterialKind::Glass
                | MaterialKind::Conductor
                | MaterialKind::ThinDielectric
        )
    }
    /// Surfaces where photons are stored and radiance is estimated: those with a diffuse
    /// part (diffuse, glossy, plastics, a metallic-roughness material whose factors or
    /// texture leave some base colour diffuse).
    pub fn stores_photons(&self) -> bool {
        match self.kind {
            MaterialKind::MetallicRoughness => {
                self.mr_texture != NO_TEXTURE
                    || self.gltf_textures[0] != NO_TEXTURE
                    || self.bsdf.is_some_and(|b| b.has_diffuse())
            }
            k => matches!(
                k,
                MaterialKind::Diffuse
                    | MaterialKind::Glossy
                    | MaterialKind::Plastic
                    | MaterialKind::RoughPlastic
            ),
        }
    }
    /// Surfaces with a lobe that is not Lambertian (delta or glossy): caustic photons are
    /// aimed at them and pass them (L (S|G)+ D).
    pub fn casts_caustics(&self) -> bool {
        match self.kind {
            MaterialKind::Diffuse | MaterialKind::Black | MaterialKind::Null => false,
            MaterialKind::Glossy => self.ks.max_element() > 0.0,
            _ => true,
        }
    }
    /// Whether it emits in some channel.
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }
}
