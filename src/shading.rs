//! The one shading interface between the integrators (photon tracing, the camera pass, the
//! gather rays) and the closed set of materials: [`bsdf_at`] turns a hit into a
//! [`SurfaceBsdf`], the only code that reads material fields, and the integrators ask it
//! what the surface does. Twin: `shaders/common/shading.wgsl` (`bsdf_at`).
//!
//! The photon-mapping split, one rule for every material: a BSDF is a Lambertian-like
//! *diffuse part*, estimated from photon density at the hit (photons are stored where a
//! material has one), plus a *lobe part* (a delta or glossy lobe), which rays trace: the
//! camera path and the gather rays go on along it, and caustic photons pass it.

use crate::bvh::Hit;
use crate::geometry::Facing;
use crate::material::{
    brdf, dielectric_shading, phong_lobe_value, photon_bounce_shading, reflect, Bounce,
    Dielectric,
};
use crate::sampling::phong_lobe;
use crate::scene::{Material, MaterialKind, Scene};
use crate::settings::FresnelMode;
use glam::Vec3;
use std::f32::consts::PI;

/// What a surface does with a ray that reaches it, the integrators' one dispatch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceClass {
    /// Reflects nothing: a path ends here (after its emission).
    Black,
    /// Only delta lobes (mirror, smooth glass): the path follows its chain without shading.
    Delta,
    /// A diffuse part or a non-delta lobe: the path shades here (photon estimates, shadow
    /// rays, gather rays) and may go on along the lobe.
    Shaded,
}

/// The ways a delta surface sends on a ray.
#[derive(Clone, Copy, Debug)]
pub enum DeltaEvent {
    /// One direction with its weight.
    Reflect {
        /// The new direction.
        dir: Vec3,
        /// Factor on the throughput.
        weight: Vec3,
    },
    /// A dielectric interface: the reflected and refracted directions and the Fresnel
    /// reflectance (the integrator chooses or splits).
    Split(Dielectric),
}

/// The BSDF at one surface point, as the integrators see it.
#[derive(Clone, Copy, Debug)]
pub struct SurfaceBsdf<'a> {
    m: &'a Material,
}

/// The BSDF of the surface `hit` lies on: the one place a material's fields are read.
#[inline]
pub fn bsdf_at<'a>(scene: &'a Scene, hit: &Hit) -> SurfaceBsdf<'a> {
    SurfaceBsdf {
        m: &scene.materials[hit.material as usize],
    }
}

/// Radiance reaching the camera along a ray that leaves the scene: none (no environment).
#[inline]
pub fn escape(_dir: Vec3) -> Vec3 {
    Vec3::ZERO
}

/// How the integrators treat a surface of material kind `kind` (the GPU's `material_class`
/// is generated from this table: `gpu::codes::wgsl_material_class`).
pub const fn class_of(kind: MaterialKind) -> SurfaceClass {
    match kind {
        MaterialKind::Black => SurfaceClass::Black,
        MaterialKind::Mirror | MaterialKind::Glass => SurfaceClass::Delta,
        MaterialKind::Diffuse | MaterialKind::Glossy => SurfaceClass::Shaded,
    }
}

impl SurfaceBsdf<'_> {
    /// How the integrators treat the surface.
    #[inline]
    pub fn class(&self) -> SurfaceClass {
        class_of(self.m.kind)
    }

    /// Radiance emitted towards a ray arriving from the front (`front`) or the back.
    #[inline]
    pub fn emitted(&self, front: bool) -> Vec3 {
        if front || self.m.two_sided_emission {
            self.m.emission
        } else {
            Vec3::ZERO
        }
    }

    /// The delta event of a [`SurfaceClass::Delta`] surface for a ray along `d` at `hit`
    /// (normals turned by the caller's `f`).
    #[inline]
    pub fn delta(&self, d: Vec3, hit: &Hit, f: &Facing, fresnel: FresnelMode) -> DeltaEvent {
        match self.m.kind {
            MaterialKind::Mirror => DeltaEvent::Reflect {
                dir: reflect(d, f.ns),
                weight: self.m.ks,
            },
            _ => DeltaEvent::Split(dielectric_shading(
                d,
                hit.normal,
                hit.shading,
                self.m.ior,
                fresnel,
            )),
        }
    }

    /// The diffuse part's albedo towards the viewer: photon estimates and gather rays weigh
    /// the incident light by `diffuse_albedo / pi` (Lambertian: `kd`).
    #[inline]
    pub fn diffuse_albedo(&self) -> Vec3 {
        self.m.kd
    }

    /// The diffuse part's BSDF value `f_D(wi, wo)` (Lambertian: `kd / pi`).
    #[inline]
    pub fn eval_diffuse(&self) -> Vec3 {
        self.m.kd / PI
    }

    /// Whether the surface has a non-delta lobe that the camera path and gather rays trace.
    #[inline]
    pub fn has_lobe(&self) -> bool {
        self.m.kind == MaterialKind::Glossy && self.m.ks.max_element() > 0.0
    }

    /// Whether the lobe is lit by delta lights through shadow rays when the mode adds no
    /// direct light (`Terms::point_lobe`).
    #[inline]
    pub fn lobe_takes_point_lights(&self) -> bool {
        self.m.kind == MaterialKind::Glossy
    }

    /// The lobe part's value `f_lobe(wi, wo)` about the shading normal `ns`.
    #[inline]
    pub fn eval_lobe(&self, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
        if self.m.kind != MaterialKind::Glossy {
            return Vec3::ZERO;
        }
        self.m.ks * phong_lobe_value(wi, wo, ns, self.m.exponent)
    }

    /// The whole non-delta BSDF `f(wi, wo)` (diffuse part and lobe).
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
        brdf(self.m, wi, wo, ns)
    }

    /// One ray drawn from the lobe for a path arriving along `d` (towards the surface), with
    /// the hit's normals `f` facing `-d`, from the uniforms (u1, u2): the direction and its
    /// weight `f cos / pdf`, or `None` below the shading or the geometric surface.
    #[inline]
    pub fn sample_lobe(&self, d: Vec3, f: &Facing, u1: f32, u2: f32) -> Option<(Vec3, Vec3)> {
        let m = self.m;
        let dir = phong_lobe(reflect(d, f.ns), m.exponent, u1, u2);
        let cos = dir.dot(f.ns);
        (cos > 0.0 && !f.reflection_leaks(dir))
            .then(|| (dir, m.ks * ((m.exponent + 2.0) / (m.exponent + 1.0) * cos)))
    }

    /// Whether photons are stored here (the surface has a diffuse part).
    #[inline]
    pub fn stores_photons(&self) -> bool {
        self.m.stores_photons()
    }

    /// Whether the surface is only delta lobes (a caustic path passes it).
    #[inline]
    pub fn is_specular(&self) -> bool {
        self.m.is_specular()
    }

    /// Russian roulette for a photon arriving along `d` at `hit` (three uniforms `u`).
    #[inline]
    pub fn photon_bounce(&self, d: Vec3, hit: &Hit, fresnel: FresnelMode, u: [f32; 3]) -> Bounce {
        photon_bounce_shading(self.m, d, hit.normal, hit.shading, fresnel, u)
    }
}
