//! The interface every light kind implements ([`LightKind`]), and what its methods return: a
//! photon leaving the light ([`Emission`]) and a shadow-ray target ([`LightSample`]).
//!
//! A kind sees the scene through a [`LightContext`]: the primitives, materials and textures
//! it may be made of and its own sampling data from the light table. [`crate::lights::LightShape`]
//! dispatches every method to its kinds in one `match`; the WGSL dispatch is generated from
//! the same list (`crate::lights::gpu`).

use crate::bsdfs::material::Material;
use crate::lights::environment::sampling::EnvDistribution;
use crate::math::sampling::basis;
use crate::scene::shapes::{Sphere, Triangle};
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};

/// 16-byte words of a light's own parameters on the GPU (`Light.p0` to `p3` in WGSL).
pub const LIGHT_PARAM_WORDS: usize = 4;

/// A light's parameter words on the GPU, bit patterns of `u32` and `f32` values.
pub type ParamWords = [[u32; 4]; LIGHT_PARAM_WORDS];

/// What a light kind may read of the scene and of its own sampling tables.
#[derive(Clone, Copy)]
pub struct LightContext<'a> {
    /// The scene's triangles.
    pub triangles: &'a [Triangle],
    /// The scene's analytic spheres.
    pub spheres: &'a [Sphere],
    /// The scene's materials.
    pub materials: &'a [Material],
    /// The scene's textures.
    pub textures: &'a [SceneTexture],
    /// Each triangle's corner uvs (empty without uvs).
    pub uvs: &'a [[Vec2; 3]],
    /// The light's power (W per channel).
    pub power: Vec3,
    /// Its emitting area (0 without a surface).
    pub area: f32,
    /// A triangle light's area CDF over its triangles, a projector's image distribution
    /// ([`LightKind::distribution`]); empty for the others.
    pub cdf: &'a [f32],
    /// Where its data starts in the GPU's `light_cdf`: a triangle light's CDF, the
    /// environment's distribution.
    pub cdf_start: u32,
    /// Its emission texture (`NO_TEXTURE` without one).
    pub emission_texture: u32,
    /// Its emission texture's mean over its surface (one without a texture).
    pub texture_mean: Vec3,
    /// The scene's bounding sphere (centre, radius): where distant lights' photons start.
    pub bounds: (Vec3, f32),
    /// An image environment's sampling distribution.
    pub env: Option<&'a EnvDistribution>,
}

impl LightContext<'_> {
    /// A uniform point of the disc of the bounding sphere's radius across `direction`,
    /// relative to its centre (`light_disc` in WGSL).
    pub fn disc(&self, direction: Vec3, u: [f32; 2]) -> Vec3 {
        let (t, b) = basis(direction);
        let rho = self.bounds.1 * u[0].sqrt();
        let phi = 2.0 * std::f32::consts::PI * u[1];
        rho * (phi.cos() * t + phi.sin() * b)
    }
}

/// A photon leaving a light.
#[derive(Clone, Copy, Debug)]
pub struct Emission {
    /// Where it leaves the light.
    pub origin: Vec3,
    /// Unit direction it leaves in.
    pub dir: Vec3,
    /// Normal of the emitting surface (zero for lights without a surface), for the
    /// ray offset.
    pub normal: Vec3,
    /// Factor on the photon's power: a textured emitter's texel at the origin over the
    /// texture's mean (one for every other light).
    pub scale: Vec3,
}

/// A point on a light seen from a shading point, for a shadow ray.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// Position on the light.
    pub point: Vec3,
    /// Incident radiance times the geometry term over the pdf, excluding the receiver's cosine
    /// and BRDF: `Le cos_l / (d^2 pdf_A)` for area lights, `I / d^2` for point lights, the
    /// irradiance `E` for directional lights.
    pub weight: Vec3,
    /// Unit normal of the light surface at `point` (zero for the other lights).
    pub normal: Vec3,
    /// A directional light: `point` is one unit from the shading point towards the light,
    /// and the shadow ray runs to infinity.
    pub distant: bool,
}

impl LightSample {
    /// A target without a surface: a light's position, or a distant light's
    /// direction one unit from the shading point.
    pub fn delta(point: Vec3, weight: Vec3, distant: bool) -> Self {
        LightSample {
            point,
            weight,
            normal: Vec3::ZERO,
            distant,
        }
    }
}

/// A kind of light: its parameters, its photons, its shadow-ray targets and its GPU words.
/// The WGSL twin of each method is `<prefix>_<method>` in the kind's WGSL file, which the
/// generated dispatch calls; what a kind leaves out takes the default.
pub trait LightKind {
    /// Delta lights: a point or a direction, no surface. Shadow rays
    /// reach them exactly (one sample), nothing else can hit them, and they light every BRDF
    /// lobe through shadow rays.
    fn is_delta(&self) -> bool {
        false
    }

    /// Its emitting area and, for a light of several triangles, their area CDF (normalised
    /// to end at 1) by which [`Self::emit`] and [`Self::sample`] pick one.
    fn surface(&self, _triangles: &[Triangle], _spheres: &[Sphere]) -> (f32, Vec<f32>) {
        (0.0, Vec::new())
    }

    /// Sampling data of its own that the light table appends to [`Self::surface`]'s CDF
    /// (`LightContext::cdf`, from `cdf_start` in the GPU's `light_cdf`): a projector's image
    /// distribution. None by default.
    fn distribution(&self, _textures: &[SceneTexture]) -> Vec<f32> {
        Vec::new()
    }

    /// The material of its emitting surface, for an area light.
    fn material(&self, _triangles: &[Triangle], _spheres: &[Sphere]) -> Option<u32> {
        None
    }

    /// Emits a photon from five uniform numbers.
    fn emit(&self, c: &LightContext, u: [f32; 5]) -> Emission;

    /// A shadow-ray target for shading point `x` (shading normal `ns`) from three uniform
    /// numbers.
    fn sample(&self, c: &LightContext, x: Vec3, ns: Vec3, u: [f32; 3]) -> LightSample;

    /// The point [`Self::sample`] picks for `u` whatever the shading point, where there is
    /// one (`None` for distant lights): single scattering draws its distance towards it.
    fn anchor(&self, c: &LightContext, u: [f32; 3]) -> Option<Vec3>;

    /// The solid-angle density with which [`Self::sample`] picks direction `dir` from a
    /// point of shading normal `ns`, for lights sampled by direction (the environment).
    fn direction_pdf(&self, _c: &LightContext, _ns: Vec3, _dir: Vec3) -> f32 {
        0.0
    }

    /// Its parameters as the GPU's light record holds them (`Light.p0..p3`).
    fn gpu_words(&self, c: &LightContext) -> ParamWords;
}

/// `v` and `w` as one parameter word: a vector's bits and one more word.
pub fn word(v: Vec3, w: u32) -> [u32; 4] {
    [v.x.to_bits(), v.y.to_bits(), v.z.to_bits(), w]
}
