//! The one shading interface between the integrators (photon tracing, the camera pass, the
//! gather rays) and the materials: [`bsdf_at`] turns a hit into a [`SurfaceBsdf`], the only
//! code that reads a material (its BSDF with the textured parameters looked up at the hit),
//! and the integrators ask it what the surface does; every answer is the BSDF union's
//! ([`BsdfKind`]). Twin: `shading.wgsl` (`bsdf_at`).
//!
//! The photon-mapping split, one rule for every material: a BSDF is a Lambertian-like
//! *diffuse part*, estimated from photon density at the hit (photons are stored where a
//! material has one), plus a *lobe part* (a delta or glossy lobe), which rays trace: the
//! camera path and the gather rays go on along it, and caustic photons pass it.

pub use crate::bsdfs::interface::{Bounce, DeltaEvent, Dielectric, LobeRay, SurfaceClass};

use crate::bsdfs::blend::choose;
use crate::bsdfs::interface::Frame;
use crate::bsdfs::material::terminator;
use crate::bsdfs::{Bsdf, BsdfKind};
use crate::bvh::hit::Hit;
use crate::math::geometry::Facing;
use crate::math::rng::Rng;
use crate::scene::{Material, Scene};
use crate::settings::FresnelMode;
use glam::Vec3;
use std::f32::consts::PI;

/// Below this depth a camera path at a glass hit ([`DeltaEvent::Split`]) traces both the
/// reflected and the refracted ray, weighted by the reflectance and its complement; deeper,
/// one of them is chosen with the Fresnel probability (unbiased, bounded work). Photons and
/// final-gather rays always choose one. Both backends' camera paths use it (the GPU's
/// prelude carries it; its pending branches fit in this many slots).
pub const GLASS_SPLIT_DEPTH: u32 = 3;

/// The power heuristic's weight of a strategy of density `a` against one of density `b`.
#[inline]
pub fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 {
        a2 / (a2 + b2)
    } else {
        0.0
    }
}

/// The BSDF at one surface point, as the integrators see it.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceBsdf<'a> {
    m: &'a Material,
    /// The material's BSDF with its textured parameters looked up.
    b: Bsdf,
    /// The local frame: the unflipped shading normal (z) and the hit's tangent (x).
    n: Frame,
    /// The emitted radiance, with its texture looked up.
    emission: Vec3,
    /// A one-sided material seen from the back: `b` is black.
    back: bool,
    /// The normal map's shadowing (`Material::normal_shadowing`): the cosine between the
    /// perturbed and the unperturbed normal, and the unperturbed (geometric) normal; `None`
    /// without it.
    shadowing: Option<(f32, Vec3)>,
}

/// The BSDF of the surface `hit` lies on, for a ray arriving along `d`: the one place a
/// material (and its textures) is read. A blend is the component chosen at the hit
/// (`crate::bsdfs::blend::choose`); a [one-sided](Material::one_sided) material seen from the
/// back is black.
#[inline]
pub fn bsdf_at<'a>(scene: &'a Scene, hit: &Hit, d: Vec3) -> SurfaceBsdf<'a> {
    let m = &scene.materials[hit.material as usize];
    let emission = match m.emission_texture {
        crate::textures::NO_TEXTURE => m.emission,
        t => m.emission * scene.textures[t as usize].eval(hit.uv),
    };
    // A blend is the component its choice at this hit names.
    let c = match m.blend {
        None => m,
        Some(_) => {
            let i = choose(
                &scene.materials,
                &scene.textures,
                hit.material,
                hit.position,
                d,
                hit.uv,
            );
            &scene.materials[i as usize]
        }
    };
    let back = c.one_sided && d.dot(hit.normal) >= 0.0;
    let b = if back {
        Bsdf::Black(crate::bsdfs::black::Black)
    } else {
        c.bsdf.resolve(&scene.textures, hit.uv)
    };
    SurfaceBsdf {
        m,
        b,
        n: Frame::new(hit.shading, hit.tangent),
        emission,
        back,
        shadowing: (m.normal_shadowing && m.normal_texture != crate::textures::NO_TEXTURE)
            .then(|| (hit.shading.dot(hit.normal).abs(), hit.normal)),
    }
}

/// The bounce of a photon arriving along `d` at a surface of `m` (untextured) with geometric
/// normal `ng` and shading normal `ns` (on its side): the hit-free form of
/// [`SurfaceBsdf::photon_bounce`], for tests and tools.
pub fn photon_bounce_at(
    m: &Material,
    d: Vec3,
    ng: Vec3,
    ns: Vec3,
    fresnel: FresnelMode,
    u: [f32; 3],
) -> Bounce {
    let hit = Hit {
        t: 0.0,
        position: Vec3::ZERO,
        normal: ng,
        shading: ns,
        material: 0,
        light: crate::scene::NO_LIGHT,
        uv: glam::Vec2::ZERO,
        tangent: Vec3::ZERO,
    };
    m.bsdf
        .photon_bounce(Frame::new(ns, Vec3::ZERO), d, &hit, fresnel, u)
}

/// Radiance arriving along a ray that leaves the scene in direction `dir`: the environment's
/// (`crate::scene::Environment`), or none without one.
#[inline]
pub fn escape(scene: &Scene, dir: Vec3) -> Vec3 {
    match scene.environment() {
        Some(env) => env.eval(&scene.textures, dir),
        None => Vec3::ZERO,
    }
}

impl SurfaceBsdf<'_> {
    /// The normal map's shadowing of light arriving from `wi` (1 without it): the factor on
    /// the light side of every answer below ([`terminator`]).
    #[inline]
    pub fn shadowing(&self, wi: Vec3) -> f32 {
        match self.shadowing {
            None => 1.0,
            Some((cos_p, ng)) => terminator(cos_p, wi.dot(ng)),
        }
    }

    /// How the integrators treat the surface.
    #[inline]
    pub fn class(&self) -> SurfaceClass {
        self.b.class()
    }

    /// The resolved BSDF.
    #[inline]
    pub fn bsdf(&self) -> &Bsdf {
        &self.b
    }

    /// Radiance emitted towards a ray arriving from the front (`front`) or the back.
    #[inline]
    pub fn emitted(&self, front: bool) -> Vec3 {
        if front || self.m.two_sided_emission {
            self.emission
        } else {
            Vec3::ZERO
        }
    }

    /// The delta event of a [`SurfaceClass::Delta`] surface for a ray along `d` at `hit`
    /// (normals turned by the caller's `f`).
    #[inline]
    pub fn delta(&self, d: Vec3, hit: &Hit, f: &Facing, fresnel: FresnelMode) -> DeltaEvent {
        self.b.delta_event(self.n, d, hit, f, fresnel)
    }

    /// The diffuse part's albedo towards the viewer at `wo`: photon estimates weigh the
    /// incident light by `diffuse_albedo / pi`, gather rays (cosine-distributed) by it times
    /// [`store_weight`](Self::store_weight) of their direction (Lambertian: the albedo and 1).
    #[inline]
    pub fn diffuse_albedo(&self, wo: Vec3) -> Vec3 {
        self.b.surface_diffuse_albedo(self.n, wo)
    }

    /// The diffuse part's factor on the light's side for light arriving from `wi`, by which
    /// a stored photon's power is multiplied (1 for a Lambertian surface, the coating's
    /// transmittance for a plastic); `None` when it is exactly 1.
    #[inline]
    pub fn store_weight(&self, wi: Vec3) -> Option<f32> {
        let w = self.b.surface_store_weight(self.n, wi);
        if self.shadowing.is_none() {
            return w;
        }
        Some(w.unwrap_or(1.0) * self.shadowing(wi))
    }

    /// The diffuse part's BSDF value `f_D(wi, wo)` (Lambertian: `kd / pi`).
    #[inline]
    pub fn eval_diffuse(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        self.b.surface_eval_diffuse(self.n, wi, wo) * self.shadowing(wi)
    }

    /// The diffuse part's value for a photon estimate at a point seen from `wo`: the
    /// constant BRDF the estimate weighs each photon by (photons already carry
    /// [`store_weight`](Self::store_weight)).
    #[inline]
    pub fn estimate_brdf(&self, wo: Vec3) -> Vec3 {
        self.diffuse_albedo(wo) / PI
    }

    /// Whether the surface has a lobe that the camera path and gather rays trace (delta or
    /// glossy, besides its diffuse part).
    #[inline]
    pub fn has_lobe(&self) -> bool {
        self.b.has_lobe()
    }

    /// Whether the lobe is lit by delta lights through shadow rays when the mode adds no
    /// direct light (`Terms::point_lobe`): every non-delta lobe.
    #[inline]
    pub fn lobe_takes_point_lights(&self) -> bool {
        self.b.lobe_takes_point_lights()
    }

    /// Whether the lobe transmits across the surface: shadow rays to delta lights are then
    /// taken from below the shading normal too (a rough dielectric's transmission).
    #[inline]
    pub fn lobe_transmits(&self) -> bool {
        self.b.lobe_transmits()
    }

    /// Whether passing straight through is a null event in scenes with media (a thin
    /// dielectric's transmission, as Mitsuba's `volpath` counts it: no bounce).
    #[inline]
    pub fn passes_null(&self) -> bool {
        self.b.passes_null()
    }

    /// What a shadow ray along `d` keeps crossing the surface as a null event, in scenes with
    /// media (a thin dielectric's `1 - R'`); zero where the surface blocks it.
    #[inline]
    pub fn null_transmission(&self, d: Vec3) -> Vec3 {
        self.b.null_transmission(self.n.local(-d))
    }

    /// The lobe part's value `f_lobe(wi, wo)` about the shading normal `ns`.
    #[inline]
    pub fn eval_lobe(&self, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
        self.b.surface_eval_lobe(self.n, wi, wo, ns) * self.shadowing(wi)
    }

    /// The whole non-delta BSDF `f(wi, wo)` (diffuse part and lobe).
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
        self.b.surface_eval(self.n, wi, wo, ns) * self.shadowing(wi)
    }

    /// The solid-angle density with which [`sample_lobe`](Self::sample_lobe) draws `wi`
    /// (0 for a delta lobe): the lobe's half of multiple importance sampling with the
    /// shadow rays.
    #[inline]
    pub fn pdf_lobe(&self, wi: Vec3, wo: Vec3, ns: Vec3) -> f32 {
        self.b.surface_pdf_lobe(self.n, wi, wo, ns)
    }

    /// Whether the lobe can be reached by shadow rays (a glossy, not a delta, lobe): then
    /// light sampling and lobe sampling share area lights by multiple importance sampling.
    #[inline]
    pub fn lobe_is_glossy(&self) -> bool {
        self.b.lobe_is_glossy()
    }

    /// One ray drawn from the lobe for a path arriving along `d` (towards the surface), with
    /// the hit's normals `f` facing `-d`: the direction, its weight `f cos / pdf` and the pdf
    /// (0 for a delta lobe), or `None` below the shading or the geometric surface (or across
    /// it for a reflection), except for a transmitting lobe, whose ray goes on on either side
    /// of the geometric surface. The Phong lobe takes two numbers from `rng`, the other kinds
    /// three.
    #[inline]
    pub fn sample_lobe(&self, d: Vec3, f: &Facing, rng: &mut Rng) -> Option<LobeRay> {
        let mut lobe = self.b.surface_sample_lobe(self.n, d, f, rng)?;
        lobe.weight *= self.shadowing(lobe.dir);
        Some(lobe)
    }

    /// Whether photons are stored here (the material has a diffuse part; asked of the
    /// material's kind, so that a textured one stores everywhere).
    #[inline]
    pub fn stores_photons(&self) -> bool {
        !self.back && self.m.stores_photons()
    }

    /// Whether the surface is only delta lobes.
    #[inline]
    pub fn is_specular(&self) -> bool {
        self.b.class() == SurfaceClass::Delta
    }

    /// A photon arriving along `d` at `hit` (three uniforms `u`): the kind's bounce.
    #[inline]
    pub fn photon_bounce(&self, d: Vec3, hit: &Hit, fresnel: FresnelMode, u: [f32; 3]) -> Bounce {
        self.b.photon_bounce(self.n, d, hit, fresnel, u)
    }
}
