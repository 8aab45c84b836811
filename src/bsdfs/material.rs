//! The scene's materials: the closed set of kinds and their parameters (`crate::bsdfs::shading`
//! is the one place the integrators read them).

use crate::bsdfs::param::Param;
use crate::bsdfs::{Bsdf, BsdfKind, SurfaceClass};
use crate::media::MediumInterface;
use glam::Vec3;

pub use crate::textures::NO_TEXTURE;

/// A material: a BSDF and its wrappers. A material is two-sided (Mitsuba's `twosided`) unless
/// `one_sided`; the normal map and the mask are fields here rather than wrapping variants.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// How the surface scatters light.
    pub bsdf: Bsdf,
    /// Radiance emitted from the front face (zero for non-emitters).
    pub emission: Vec3,
    /// Whether emission leaves both faces.
    pub two_sided_emission: bool,
    /// Black seen from the back of the geometric normal: Mitsuba's reflective BSDFs not
    /// wrapped in `twosided` (`diffuse`, `plastic`, `conductor` and their rough kinds reflect
    /// nothing when `cos(theta_i) <= 0`). Read once, by `crate::bsdfs::shading::bsdf_at`.
    pub one_sided: bool,
    /// Index into [`Scene::textures`](crate::scene::Scene::textures) of a tangent-space normal map (Mitsuba's `normalmap`
    /// bsdf, glTF's `normalTexture`: the texture's rgb `c` is the normal `2 c - 1` in the
    /// hit's shading frame, see `crate::bvh::perturb`), or [`NO_TEXTURE`].
    pub normal_texture: u32,
    /// Whether the normal map shadows light arriving at grazing angles to the surface
    /// (Mitsuba's `use_shadowing_function`, default on; Estevez et al., "A Microfacet-Based
    /// Shadowing Function to Solve the Bump Terminator Problem", 2019): the light side of the
    /// BSDF is multiplied by [`terminator`] (`crate::bsdfs::shading`).
    pub normal_shadowing: bool,
    /// `normal_texture` is a height map, not a normal map: Mitsuba's `bumpmap`, whose
    /// luminance gradient times this scale tilts the shading normal
    /// (`crate::math::geometry::bump_mapped`); `None` for a normal map.
    pub bump: Option<f32>,
    /// Index into [`Scene::textures`](crate::scene::Scene::textures) of a texture multiplying `emission` at each point (glTF
    /// `emissiveTexture`, Mitsuba's textured `radiance`; `crate::lights::emission`), or
    /// [`NO_TEXTURE`].
    pub emission_texture: u32,
    /// Cut-outs and partial coverage (glTF `alphaMode` MASK and BLEND, Mitsuba's `mask`);
    /// `None` for an opaque surface.
    pub alpha: Option<Alpha>,
    /// The media the surface bounds (vacuum on both sides by default; `crate::media`).
    pub media: MediumInterface,
    /// A blend of two other materials (Mitsuba's `blendbsdf`, `crate::bsdfs::blend`): then
    /// `bsdf` is the first component's (what a question about the kind alone sees) and the
    /// surface scatters as the component chosen at each hit; emission, normal map, mask and
    /// media are this material's own.
    pub blend: Option<Blend>,
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

/// The shadowing of a normal map (Estevez et al. 2019, as Mitsuba's `normalmap` and
/// `bumpmap`): a Smith G1 of roughness `alpha2 = min(tan^2(theta_p) / 8, 1)`, `theta_p` the
/// angle of the perturbed normal to the unperturbed one (`cos_p`), for light arriving at
/// `cos_w` to the unperturbed normal. 1 for an unperturbed normal.
#[inline]
pub fn terminator(cos_p: f32, cos_w: f32) -> f32 {
    let tan2 = |c: f32| {
        let c2 = (c * c).max(1e-12);
        ((1.0 - c2) / c2).max(0.0)
    };
    let alpha2 = (0.125 * tan2(cos_p)).min(1.0);
    2.0 / (1.0 + (1.0 + alpha2 * tan2(cos_w)).sqrt())
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

/// A blend of two materials (their indices in the scene's materials): Mitsuba's `blendbsdf`,
/// chosen between at each hit by `crate::bsdfs::blend::choose`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Blend {
    /// The material chosen with probability `1 - weight`.
    pub first: u32,
    /// The material chosen with probability `weight`.
    pub second: u32,
    /// The probability of `second`: its first number, clamped to [0, 1].
    pub weight: Param,
    /// Whether either component stores photons (their union is where the blend's light is
    /// estimated).
    pub stores_photons: bool,
    /// Whether either component casts caustics.
    pub casts_caustics: bool,
    /// Whether both components are only delta lobes.
    pub specular: bool,
    /// How many blends deep the nest is (1: both components are plain materials).
    pub depth: u32,
}

impl Blend {
    /// The blend of `materials[first]` and `materials[second]` by `weight`; `None` when an
    /// index is out of range.
    pub fn new(first: u32, second: u32, weight: Param, materials: &[Material]) -> Option<Self> {
        let a = materials.get(first as usize)?;
        let b = materials.get(second as usize)?;
        Some(Self {
            first,
            second,
            weight,
            stores_photons: a.stores_photons() || b.stores_photons(),
            casts_caustics: a.casts_caustics() || b.casts_caustics(),
            specular: a.is_specular() && b.is_specular(),
            depth: 1 + a
                .blend
                .map_or(0, |c| c.depth)
                .max(b.blend.map_or(0, |c| c.depth)),
        })
    }
}

impl Material {
    /// A material of BSDF `bsdf` (of any kind), emitting nothing.
    pub fn of(bsdf: impl Into<Bsdf>) -> Self {
        Self {
            bsdf: bsdf.into(),
            ..Self::black()
        }
    }
    /// A Lambertian surface of `albedo`.
    pub fn diffuse(albedo: Vec3) -> Self {
        Self::of(crate::bsdfs::diffuse::Diffuse::new(albedo))
    }
    /// Lambertian `kd` plus a normalised Phong lobe `ks` of exponent `exponent`.
    pub fn glossy(kd: Vec3, ks: Vec3, exponent: f32) -> Self {
        Self::of(crate::bsdfs::phong::Phong::new(kd, ks, exponent))
    }
    /// A perfect mirror of `reflectance`.
    pub fn mirror(reflectance: Vec3) -> Self {
        Self::of(crate::bsdfs::mirror::Mirror::new(reflectance))
    }
    /// A smooth dielectric of index `ior` inside.
    pub fn glass(ior: f32) -> Self {
        Self::of(crate::bsdfs::glass::Glass::new(ior))
    }
    /// An index-matched boundary: passes everything straight through (bounds media).
    pub fn null() -> Self {
        Self::of(crate::bsdfs::null::Null)
    }
    /// A surface that reflects and emits nothing; the base of the other constructors.
    pub fn black() -> Self {
        Self {
            bsdf: Bsdf::Black(crate::bsdfs::black::Black),
            emission: Vec3::ZERO,
            two_sided_emission: false,
            one_sided: false,
            normal_texture: NO_TEXTURE,
            normal_shadowing: false,
            bump: None,
            emission_texture: NO_TEXTURE,
            alpha: None,
            media: MediumInterface::default(),
            blend: None,
        }
    }
    /// A material of `b` (the same as [`Material::of`]).
    pub fn from_bsdf(b: Bsdf) -> Self {
        Self::of(b)
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
        match self.blend {
            Some(b) => b.specular,
            None => self.bsdf.class() == SurfaceClass::Delta,
        }
    }
    /// Surfaces where photons are stored and radiance is estimated: those with a diffuse
    /// part (somewhere, for a textured kind).
    pub fn stores_photons(&self) -> bool {
        match self.blend {
            Some(b) => b.stores_photons,
            None => self.bsdf.stores_photons(),
        }
    }
    /// Surfaces with a lobe that is not Lambertian (delta or glossy): caustic photons are
    /// aimed at them and pass them (L (S|G)+ D).
    pub fn casts_caustics(&self) -> bool {
        match self.blend {
            Some(b) => b.casts_caustics,
            None => self.bsdf.casts_caustics(),
        }
    }
    /// Whether it emits in some channel.
    pub fn is_emissive(&self) -> bool {
        self.emission.max_element() > 0.0
    }
}
