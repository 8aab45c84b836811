//! The one shading interface between the integrators (photon tracing, the camera pass, the
//! gather rays) and the closed set of materials: [`bsdf_at`] turns a hit into a
//! [`SurfaceBsdf`], the only code that reads material fields, and the integrators ask it
//! what the surface does. Twin: `src/bsdfs/shading.wgsl` (`bsdf_at`).
//!
//! The photon-mapping split, one rule for every material: a BSDF is a Lambertian-like
//! *diffuse part*, estimated from photon density at the hit (photons are stored where a
//! material has one), plus a *lobe part* (a delta or glossy lobe), which rays trace: the
//! camera path and the gather rays go on along it, and caustic photons pass it.

use crate::bsdfs::{fresnel_dielectric, Bsdf, MetallicRoughness, Transport};
use crate::bvh::Hit;
use crate::math::geometry::Facing;
use crate::bsdfs::classic::{
    brdf, dielectric_shading, phong_lobe_value, photon_bounce_shading, reflect, Bounce, Dielectric,
};
use crate::math::rng::Rng;
use crate::math::sampling::{basis, cosine_hemisphere, phong_lobe, to_world};
use crate::scene::{Material, MaterialKind, Scene, NO_TEXTURE};
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
    /// An index-matched boundary: the path goes on straight through, unscattered and not
    /// counted as a bounce; only the medium changes.
    Null,
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

/// Below this depth a camera path at a glass hit ([`DeltaEvent::Split`]) traces both the
/// reflected and the refracted ray, weighted by the reflectance and its complement; deeper,
/// one of them is chosen with the Fresnel probability (unbiased, bounded work). Photons and
/// final-gather rays always choose one. Both backends' camera paths use it (the GPU's
/// prelude carries it; its pending branches fit in this many slots).
pub const GLASS_SPLIT_DEPTH: u32 = 3;

/// A ray drawn from a lobe.
#[derive(Clone, Copy, Debug)]
pub struct LobeRay {
    /// Its direction.
    pub dir: Vec3,
    /// `f cos / pdf`.
    pub weight: Vec3,
    /// The solid-angle density it was drawn with; 0 for a delta lobe.
    pub pdf: f32,
}

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
    /// `kd` with its texture looked up.
    kd: Vec3,
    /// `m.bsdf` with its textured parameters looked up.
    b: Option<Bsdf>,
    /// The unflipped shading normal: the local frame's z for [`crate::bsdfs`]'s kinds.
    n: Vec3,
    /// The emitted radiance, with its texture looked up.
    emission: Vec3,
}

/// The BSDF of the surface `hit` lies on: the one place a material's fields (and its
/// textures) are read.
#[inline]
pub fn bsdf_at<'a>(scene: &'a Scene, hit: &Hit) -> SurfaceBsdf<'a> {
    let m = &scene.materials[hit.material as usize];
    let (kd, mut b) = match m.kd_texture {
        NO_TEXTURE => (m.kd, m.bsdf),
        t => {
            let kd = scene.textures[t as usize].eval(hit.uv);
            // A plastic's base reflectance is its `kd`, a metallic-roughness material's
            // base colour too.
            let b = match m.bsdf {
                Some(Bsdf::Plastic(p)) => Some(Bsdf::Plastic(p.with_diffuse(kd))),
                Some(Bsdf::MetallicRoughness(g)) => {
                    Some(Bsdf::MetallicRoughness(MetallicRoughness { base: kd, ..g }))
                }
                b => b,
            };
            (kd, b)
        }
    };
    if let Some(Bsdf::MetallicRoughness(g)) = &mut b {
        gltf_textures(scene, m, hit, g);
    }
    let emission = match m.emission_texture {
        NO_TEXTURE => m.emission,
        t => m.emission * scene.textures[t as usize].eval(hit.uv),
    };
    SurfaceBsdf {
        m,
        kd,
        b,
        n: hit.shading,
        emission,
    }
}

/// glTF's parameter textures at `hit`: the metallic-roughness texture's blue scales the
/// metalness and its green the roughness; the transmission texture's red the transmission;
/// the specular colour texture's rgb the F0 colour (`f0 = min(f0 c, f90)`, exact while
/// `F0(ior)` times the colour factor is at most 1); the specular texture's alpha both F0
/// and F90.
fn gltf_textures(scene: &Scene, m: &Material, hit: &Hit, g: &mut MetallicRoughness) {
    let tex = |t: u32| (t != NO_TEXTURE).then(|| &scene.textures[t as usize]);
    if let Some(t) = tex(m.mr_texture) {
        let c = t.eval(hit.uv);
        g.metallic *= c.z;
        g.roughness *= c.y;
    }
    let [transmission, specular, colour] = m.gltf_textures;
    if let Some(t) = tex(transmission) {
        g.transmission *= t.eval(hit.uv).x;
    }
    if let Some(t) = tex(colour) {
        g.f0 = (g.f0 * t.eval(hit.uv)).min(Vec3::splat(g.f90));
    }
    if let Some(t) = tex(specular) {
        let a = t.eval_alpha(hit.uv);
        g.f0 *= a;
        g.f90 *= a;
    }
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

/// How the integrators treat a surface of material kind `kind` (the GPU's `material_class`
/// is generated from this table: `gpu::codes::wgsl_material_class`).
pub const fn class_of(kind: MaterialKind) -> SurfaceClass {
    match kind {
        MaterialKind::Black => SurfaceClass::Black,
        MaterialKind::Null => SurfaceClass::Null,
        MaterialKind::Mirror
        | MaterialKind::Glass
        | MaterialKind::Conductor
        | MaterialKind::ThinDielectric => SurfaceClass::Delta,
        MaterialKind::Diffuse
        | MaterialKind::Glossy
        | MaterialKind::RoughConductor
        | MaterialKind::RoughDielectric
        | MaterialKind::Plastic
        | MaterialKind::RoughPlastic
        | MaterialKind::MetallicRoughness => SurfaceClass::Shaded,
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
            self.emission
        } else {
            Vec3::ZERO
        }
    }

    /// `w` in the local frame of [`crate::bsdfs`] (z the front shading normal).
    #[inline]
    fn local(&self, w: Vec3) -> Vec3 {
        let (t, b) = basis(self.n);
        Vec3::new(w.dot(t), w.dot(b), w.dot(self.n))
    }

    /// The delta event of a [`SurfaceClass::Delta`] surface for a ray along `d` at `hit`
    /// (normals turned by the caller's `f`).
    #[inline]
    pub fn delta(&self, d: Vec3, hit: &Hit, f: &Facing, fresnel: FresnelMode) -> DeltaEvent {
        match (self.m.kind, &self.b) {
            (MaterialKind::Mirror, _) => DeltaEvent::Reflect {
                dir: reflect(d, f.ns),
                weight: self.m.ks,
            },
            (MaterialKind::Conductor, Some(b)) => {
                let weight = b
                    .sample_lobe(self.local(-d), [0.0; 3], Transport::Radiance)
                    .map_or(Vec3::ZERO, |s| s.weight);
                DeltaEvent::Reflect {
                    dir: reflect(d, f.ns),
                    weight,
                }
            }
            (MaterialKind::ThinDielectric, Some(Bsdf::ThinDielectric { eta, .. })) => {
                let r = fresnel_dielectric(d.dot(f.ns).abs(), *eta).0;
                DeltaEvent::Split(Dielectric {
                    reflected: reflect(d, f.ns),
                    refracted: Some(d),
                    reflectance: if r < 1.0 { 2.0 * r / (1.0 + r) } else { 1.0 },
                })
            }
            _ => DeltaEvent::Split(dielectric_shading(
                d,
                hit.normal,
                hit.shading,
                self.m.ior,
                fresnel,
            )),
        }
    }

    /// The diffuse part's albedo towards the viewer at `wo`: photon estimates weigh the
    /// incident light by `diffuse_albedo / pi`, gather rays (cosine-distributed) by it times
    /// [`store_weight`](Self::store_weight) of their direction (Lambertian: `kd` and 1).
    #[inline]
    pub fn diffuse_albedo(&self, wo: Vec3) -> Vec3 {
        match &self.b {
            Some(b) => b.diffuse_out(self.local(wo)),
            None => self.kd,
        }
    }

    /// The diffuse part's factor on the light's side for light arriving from `wi`, by which
    /// a stored photon's power is multiplied (1 for a Lambertian surface, the coating's
    /// transmittance for a plastic); `None` when it is exactly 1.
    #[inline]
    pub fn store_weight(&self, wi: Vec3) -> Option<f32> {
        self.b.as_ref().map(|b| b.store_weight(self.local(wi)))
    }

    /// The diffuse part's BSDF value `f_D(wi, wo)` (Lambertian: `kd / pi`).
    #[inline]
    pub fn eval_diffuse(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        match &self.b {
            Some(b) => {
                let (wi, wo) = (self.local(wi), self.local(wo));
                if wi.z * wo.z <= 0.0 {
                    return Vec3::ZERO;
                }
                b.diffuse_out(wo) * (b.store_weight(wi) / PI)
            }
            None => self.kd / PI,
        }
    }

    /// The diffuse part's value for a photon estimate at a point seen from `wo`: the
    /// constant BRDF the estimate weighs each photon by (photons already carry
    /// [`store_weight`](Self::store_weight)).
    #[inline]
    pub fn estimate_brdf(&self, wo: Vec3) -> Vec3 {
        match &self.b {
            Some(_) => self.diffuse_albedo(wo) / PI,
            None => self.kd / PI,
        }
    }

    /// Whether the surface has a lobe that the camera path and gather rays trace (delta or
    /// glossy, besides its diffuse part).
    #[inline]
    pub fn has_lobe(&self) -> bool {
        match self.m.kind {
            MaterialKind::Glossy => self.m.ks.max_element() > 0.0,
            MaterialKind::Diffuse | MaterialKind::Black | MaterialKind::Null => false,
            _ => true,
        }
    }

    /// Whether the lobe is lit by delta lights through shadow rays when the mode adds no
    /// direct light (`Terms::point_lobe`): every non-delta lobe.
    #[inline]
    pub fn lobe_takes_point_lights(&self) -> bool {
        matches!(
            self.m.kind,
            MaterialKind::Glossy
                | MaterialKind::RoughConductor
                | MaterialKind::RoughDielectric
                | MaterialKind::RoughPlastic
                | MaterialKind::MetallicRoughness
        )
    }

    /// The lobe part's value `f_lobe(wi, wo)` about the shading normal `ns`.
    #[inline]
    pub fn eval_lobe(&self, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
        match (self.m.kind, &self.b) {
            (MaterialKind::Glossy, _) => self.m.ks * phong_lobe_value(wi, wo, ns, self.m.exponent),
            (_, Some(b)) => b.eval_lobe(self.local(wi), self.local(wo), Transport::Radiance),
            _ => Vec3::ZERO,
        }
    }

    /// The whole non-delta BSDF `f(wi, wo)` (diffuse part and lobe).
    #[inline]
    pub fn eval(&self, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
        match self.b {
            Some(_) => self.eval_diffuse(wi, wo) + self.eval_lobe(wi, wo, ns),
            None if self.m.kd_texture != NO_TEXTURE => {
                let m = Material {
                    kd: self.kd,
                    ..*self.m
                };
                brdf(&m, wi, wo, ns)
            }
            None => brdf(self.m, wi, wo, ns),
        }
    }

    /// The solid-angle density with which [`sample_lobe`](Self::sample_lobe) draws `wi`
    /// (0 for a delta lobe): the lobe's half of multiple importance sampling with the
    /// shadow rays.
    #[inline]
    pub fn pdf_lobe(&self, wi: Vec3, wo: Vec3, ns: Vec3) -> f32 {
        match (self.m.kind, &self.b) {
            (MaterialKind::Glossy, _) => {
                let cos_a = reflect(-wo, ns).dot(wi);
                if cos_a <= 0.0 {
                    return 0.0;
                }
                (self.m.exponent + 1.0) / (2.0 * PI) * cos_a.powf(self.m.exponent)
            }
            (_, Some(b)) => b.pdf_lobe(self.local(wi), self.local(wo)),
            _ => 0.0,
        }
    }

    /// Whether the lobe can be reached by shadow rays (a glossy, not a delta, lobe): then
    /// light sampling and lobe sampling share area lights by multiple importance sampling.
    #[inline]
    pub fn lobe_is_glossy(&self) -> bool {
        match (self.m.kind, &self.b) {
            (MaterialKind::Glossy, _) => self.has_lobe(),
            (_, Some(b)) => b.has_lobe() && !b.lobe_is_delta(),
            _ => false,
        }
    }

    /// One ray drawn from the lobe for a path arriving along `d` (towards the surface), with
    /// the hit's normals `f` facing `-d`: the direction, its weight `f cos / pdf` and the pdf
    /// (0 for a delta lobe), or `None` below the shading or the geometric surface (or across
    /// it for a reflection). The Phong lobe takes two numbers from `rng`, [`crate::bsdfs`]'s
    /// kinds three.
    #[inline]
    pub fn sample_lobe(&self, d: Vec3, f: &Facing, rng: &mut Rng) -> Option<LobeRay> {
        let m = self.m;
        let Some(b) = &self.b else {
            let (u1, u2) = rng.next2();
            let dir = phong_lobe(reflect(d, f.ns), m.exponent, u1, u2);
            let cos = dir.dot(f.ns);
            return (cos > 0.0 && !f.reflection_leaks(dir)).then(|| LobeRay {
                dir,
                weight: m.ks * ((m.exponent + 2.0) / (m.exponent + 1.0) * cos),
                pdf: self.pdf_lobe(dir, -d, f.ns),
            });
        };
        let u = [rng.next(), rng.next(), rng.next()];
        let s = b.sample_lobe(self.local(-d), u, Transport::Radiance)?;
        let (dir, weight) = self.world_direction(s.wi, s.weight, f)?;
        Some(LobeRay {
            dir,
            weight,
            pdf: s.pdf,
        })
    }

    /// A local sample direction in world space with its weight, or `None` when it leaks
    /// through the geometric surface (a reflection below it, a transmission above it).
    #[inline]
    fn world_direction(&self, wi: Vec3, weight: Vec3, f: &Facing) -> Option<(Vec3, Vec3)> {
        let dir = to_world(wi, self.n).normalize();
        let reflects = dir.dot(f.ns) > 0.0;
        let leaks = if reflects {
            f.reflection_leaks(dir) || dir.dot(f.ng) <= 0.0
        } else {
            f.refraction_leaks(dir) || dir.dot(f.ng) >= 0.0
        };
        (!leaks && weight.max_element() > 0.0).then_some((dir, weight))
    }

    /// Whether photons are stored here (the surface has a diffuse part).
    #[inline]
    pub fn stores_photons(&self) -> bool {
        self.m.stores_photons()
    }

    /// Whether the surface is only delta lobes.
    #[inline]
    pub fn is_specular(&self) -> bool {
        self.m.is_specular()
    }

    /// Russian roulette for a photon arriving along `d` at `hit` (three uniforms `u`). On
    /// [`crate::bsdfs`]'s kinds the photon samples the BSDF without roulette (their lobes
    /// reflect at most what arrives): a kind with both parts picks its lobe with
    /// [`Bsdf::lobe_probability`] (`u[0]`), then the coating's lobe or a cosine-weighted base
    /// direction (`u[1], u[2]`).
    #[inline]
    pub fn photon_bounce(&self, d: Vec3, hit: &Hit, fresnel: FresnelMode, u: [f32; 3]) -> Bounce {
        let Some(b) = &self.b else {
            if self.m.kd_texture != NO_TEXTURE {
                let m = Material {
                    kd: self.kd,
                    ..*self.m
                };
                return photon_bounce_shading(&m, d, hit.normal, hit.shading, fresnel, u);
            }
            return photon_bounce_shading(self.m, d, hit.normal, hit.shading, fresnel, u);
        };
        let f = hit.facing(d);
        let wo = self.local(-d);
        let (wi, weight, delta) = if b.has_diffuse() {
            let p = b.lobe_probability(wo);
            if u[0] < p {
                let Some(s) = b.sample_lobe(wo, [u[0] / p, u[1], u[2]], Transport::Importance)
                else {
                    return Bounce::Absorb;
                };
                (s.wi, s.weight / p, s.delta)
            } else {
                let dir = cosine_hemisphere(f.ns, u[1], u[2]);
                if f.reflection_leaks(dir) {
                    return Bounce::Absorb;
                }
                // f_D cos / (pdf_cos (1 - p)) with pdf_cos = cos / pi.
                let w = b.diffuse_out(wo) * (b.store_weight(self.local(dir)) / (1.0 - p));
                return Bounce::Diffuse { dir, weight: w };
            }
        } else {
            let Some(s) = b.sample_lobe(wo, u, Transport::Importance) else {
                return Bounce::Absorb;
            };
            (s.wi, s.weight, s.delta)
        };
        match self.world_direction(wi, weight, &f) {
            Some((dir, weight)) => Bounce::Specular { dir, weight, delta },
            None => Bounce::Absorb,
        }
    }
}
