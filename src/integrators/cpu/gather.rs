//! The camera pass on the CPU (twin: `src/integrators/gpu/gather.wgsl`): camera rays with jittered
//! supersampling, the mirror/glass chain, and at diffuse and glossy hits the radiance
//! estimate from the photon maps and (in `direct` and `gather` modes) shadow rays to the
//! lights; in `gather` mode the gather ray of `final_gather.rs` stands for the global map.
//!
//! Low-discrepancy samples (`crate::math::sobol`, issue 10): the pixel jitter is Sobol pair
//! [`PAIR_JITTER`] of the sample; at the *first diffuse or glossy hit the sample shades* (the
//! first `shade` call, after any mirror/glass chain; with a glass split below
//! [`GLASS_SPLIT_DEPTH`] that is the heavier branch's (reflectance >= 0.5: the reflected
//! one), traced first) the first shadow sample of the first sampled area light (`direct`, in
//! `direct_light.rs`) takes `u[0], u[1]` from pair [`crate::math::sobol::PAIR_LIGHT`] and
//! `u[2]` from dimension [`crate::math::sobol::DIM_LIGHT_THIRD`], and the gather direction
//! takes pair [`crate::math::sobol::PAIR_GATHER`]. Those numbers are not drawn from the hash
//! `Rng` at all; every other draw stays on it, in order.

use crate::bsdfs::shading::{
    bsdf_at, escape, power_heuristic, DeltaEvent, SurfaceBsdf, SurfaceClass, GLASS_SPLIT_DEPTH,
};
use crate::bsdfs::BsdfKind;
use crate::bvh::{CpuBvh, Hit};
use crate::integrators::cpu::cache::RadianceCache;
use crate::integrators::cpu::media::{medium_after, MAX_CROSSINGS};
use crate::integrators::cpu::photon_map::{estimate_at, PhotonMap};
use crate::integrators::cpu::volume_map::VolumeMap;
use crate::integrators::plan::{caustic_weight, Terms, VolumeSpec};
use crate::lights::table::LightTable;
use crate::math::geometry::{offset_origin, Facing, Ray};
use crate::math::rng::Rng;
use crate::math::sobol::{sample_pair, SobolSampler, SobolStream, PAIR_JITTER, PAIR_LENS};
use crate::media::NO_MEDIUM;
use crate::scene::Scene;
use crate::scene::NO_LIGHT;
use crate::settings::{RenderSettings, Sampler};
use glam::Vec3;

/// A ray drawn from a glossy lobe at `from` with solid-angle density `pdf`: where it meets
/// an area light, the light's emission is weighed against the shadow rays' sampling.
#[derive(Clone, Copy, Debug)]
pub struct Mis {
    /// The point the lobe was sampled at.
    pub from: Vec3,
    /// The lobe's density of the ray's direction.
    pub pdf: f32,
    /// The shading normal there on the viewer's side: shadow rays sample lights above it
    /// only, so a light below it (a transmitted ray) is the lobe's alone.
    pub ns: Vec3,
}

/// Everything the camera pass reads.
pub struct Gatherer<'a> {
    /// The scene rendered.
    pub scene: &'a Scene,
    /// Its BVH.
    pub bvh: &'a CpuBvh,
    /// Its lights' sampling tables (shadow rays).
    pub lights: &'a LightTable,
    /// The pass's settings (size, samples, K, radii, filter).
    pub settings: &'a RenderSettings,
    /// The global photon map, if the mode has one.
    pub global: Option<&'a PhotonMap>,
    /// The caustic photon map, if the plan traced one.
    pub caustic: Option<&'a PhotonMap>,
    /// What the mode adds at a diffuse or glossy hit.
    pub terms: Terms,
    /// The radiance cache gather rays read (`terms.final_gather`; else `None`).
    pub cache: Option<&'a RadianceCache>,
    /// The volume photon map, if the plan has one.
    pub volume: Option<&'a VolumeMap>,
    /// The plan's rules for it.
    pub volume_spec: Option<VolumeSpec>,
    /// Whether the scene needs media transport (`Scene::has_media_transport`).
    pub media: bool,
}

impl Gatherer<'_> {
    /// Mean radiance of pixel (x, y) over `spp` jittered camera samples.
    pub fn pixel(&self, x: u32, y: u32, pass: u32) -> Vec3 {
        self.pixel_samples(x, y, pass, self.settings.spp)
    }

    /// Mean radiance of pixel (x, y) over `count` jittered camera samples (adaptive
    /// sampling's count, `crate::render::adaptive`, the same in every pass): sample i is
    /// index `pass * count + i` of the pixel's Sobol sequence, so the passes continue one
    /// sequence, and RNG index `pixel * stride + i` with `stride` = `adaptive::stride`
    /// (`spp` without adaptive sampling).
    pub fn pixel_samples(&self, x: u32, y: u32, pass: u32, count: u32) -> Vec3 {
        let s = self.settings;
        let pixel_index = y * s.width + x;
        let stride = crate::render::adaptive::stride(s.spp, s.adaptive);
        let sobol = SobolSampler::new(s.seed, pass, pixel_index, count);
        let mut sum = Vec3::ZERO;
        for i in 0..count {
            let mut rng = Rng::new(
                s.seed,
                crate::math::rng::Stream::Camera,
                pass,
                pixel_index.wrapping_mul(stride).wrapping_add(i),
            );
            let st = sobol.stream(i);
            // `sampler = "independent"`: the jitter, light and gather numbers from the RNG.
            let (mut stream, (u1, u2)) = match s.sampler {
                Sampler::Sobol => (Some(st), sample_pair(st.key, st.index, PAIR_JITTER)),
                Sampler::Independent => (None, rng.next2()),
            };
            // The pixel filter warps the jitter; a thin lens draws its aperture sample next.
            let cam = &self.scene.camera;
            let (fx, fy) = cam.filter.jitter(u1, u2);
            let lens = match (cam.is_thin_lens(), s.sampler) {
                (false, _) => (0.0, 0.0),
                (true, Sampler::Sobol) => sample_pair(st.key, st.index, PAIR_LENS),
                (true, Sampler::Independent) => rng.next2(),
            };
            let (origin, dir) = cam.ray(x as f32 + fx, y as f32 + fy, s.width, s.height, lens);
            sum += self.radiance(
                &Ray { origin, dir },
                0,
                &mut rng,
                &mut stream,
                caustic_weight(count, s.caustic_every, i),
                None,
                self.scene.camera_medium,
            );
        }
        sum / count as f32
    }

    /// Radiance arriving along `ray` (the chain of specular bounces, then shading), which
    /// travels in `medium`: in a medium, the light scattered towards the camera along the
    /// segment (`Gatherer::in_scattered`) plus the transmittance times what arrives at its end.
    /// `first` is the sample's Sobol stream until a diffuse or glossy hit is shaded (which
    /// takes it; see the module's doc), then `None`. `cw` weighs the caustic-map estimate
    /// (`plan::caustic_weight`; 0 skips it).
    #[allow(clippy::too_many_arguments)]
    pub fn radiance(
        &self,
        ray: &Ray,
        depth: u32,
        rng: &mut Rng,
        first: &mut Option<SobolStream>,
        cw: f32,
        mis: Option<Mis>,
        medium: u32,
    ) -> Vec3 {
        let (mut ray, mut medium) = (*ray, medium);
        let (mut sum, mut tr) = (Vec3::ZERO, Vec3::ONE);
        // Index-matched boundaries are crossed here, not counted as bounces (Mitsuba's
        // volpath counts only scattering events), at most `MAX_CROSSINGS` in a row.
        for crossing in 0..=MAX_CROSSINGS {
            let hit = self.bvh.intersect(self.scene, &ray, f32::INFINITY);
            if medium != NO_MEDIUM {
                let t = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
                let skip_direct = self.volume_spec.is_some_and(|v| v.camera_skips_direct);
                // The near part's gather ray runs where nothing else draws numbers before the
                // next shading (the GPU's camera path takes it after its chain of mirrors and
                // glass).
                let near = hit.as_ref().is_none_or(|h| {
                    self.scene.materials[h.material as usize].bsdf.class() == SurfaceClass::Shaded
                });
                // A scattering event in the medium is a bounce: past max_depth, none.
                let nee = self.terms.direct && depth < self.settings.max_depth;
                sum += tr * self.in_scattered(&ray, t, medium, nee, skip_direct, near, depth, rng);
                let m = &self.scene.media[medium as usize];
                tr *= m.transmittance_along(ray.origin, ray.dir, t, rng);
                if tr == Vec3::ZERO {
                    return sum;
                }
            }
            let crosses = hit.as_ref().is_some_and(|h| {
                let material = &self.scene.materials[h.material as usize];
                material.bsdf.class() == SurfaceClass::Null
                    && crossing < MAX_CROSSINGS
                    && bsdf_at(self.scene, h, ray.dir).emitted(ray.dir.dot(h.normal) < 0.0)
                        == Vec3::ZERO
            });
            match hit {
                Some(h) if crosses => {
                    medium = medium_after(self.scene, &h, medium, ray.dir);
                    ray.origin = offset_origin(h.position, h.normal, ray.dir);
                }
                _ => {
                    return sum + tr * self.arriving(&ray, hit, depth, rng, first, cw, mis, medium)
                }
            }
        }
        sum
    }

    /// What arrives along `ray` at its hit (`None`: it left the scene), `ray` having travelled
    /// in `medium`: the surface's emission and what it scatters, or the environment.
    #[allow(clippy::too_many_arguments)]
    fn arriving(
        &self,
        ray: &Ray,
        hit: Option<Hit>,
        depth: u32,
        rng: &mut Rng,
        first: &mut Option<SobolStream>,
        cw: f32,
        mis: Option<Mis>,
        medium: u32,
    ) -> Vec3 {
        let Some(hit) = hit else {
            return self.escape(ray.dir, mis);
        };
        let bsdf = bsdf_at(self.scene, &hit, ray.dir);
        let front = ray.dir.dot(hit.normal) < 0.0;
        let mut emitted = bsdf.emitted(front);
        // A lobe sample that meets an area light shares it with the shadow rays.
        if let Some(mis) = mis.filter(|_| hit.light != NO_LIGHT && emitted != Vec3::ZERO) {
            let n = self.settings.shadow_samples as f32;
            let above = (hit.position - mis.from).dot(mis.ns) > 0.0;
            let pdf_light = if above {
                n * self.lights.solid_angle_pdf(
                    hit.light as usize,
                    mis.from,
                    hit.position,
                    hit.normal,
                )
            } else {
                0.0
            };
            emitted *= power_heuristic(mis.pdf, pdf_light);
        }
        let can_recurse = depth < self.settings.max_depth;
        let after = |dir: Vec3| medium_after(self.scene, &hit, medium, dir);
        match bsdf.class() {
            SurfaceClass::Black => emitted,
            // An index-matched boundary that emits (or one past `MAX_CROSSINGS` in a row, which
            // `radiance` crosses itself): straight on in the medium behind it, as a step of
            // the depth, which bounds the work.
            SurfaceClass::Null => {
                if !can_recurse {
                    return emitted;
                }
                let next = Ray {
                    origin: offset_origin(hit.position, hit.normal, ray.dir),
                    dir: ray.dir,
                };
                emitted + self.radiance(&next, depth + 1, rng, first, cw, mis, after(ray.dir))
            }
            SurfaceClass::Delta => {
                if !can_recurse {
                    return emitted;
                }
                let f = Facing::new(hit.normal, hit.shading, front);
                let next = |dir: Vec3| Ray {
                    origin: offset_origin(hit.position, hit.normal, dir),
                    dir,
                };
                match bsdf.delta(ray.dir, &hit, &f, self.settings.fresnel) {
                    DeltaEvent::Reflect { dir, weight } => {
                        if f.reflection_leaks(dir) {
                            return emitted;
                        }
                        emitted
                            + weight
                                * self.radiance(
                                    &next(dir),
                                    depth + 1,
                                    rng,
                                    first,
                                    cw,
                                    None,
                                    after(dir),
                                )
                    }
                    DeltaEvent::Split(g) => {
                        // A thin sheet's pass-through in a scene with media is a null event
                        // (Mitsuba's volpath): no bounce, and one branch chosen, not split.
                        let null_pass = self.media && bsdf.passes_null();
                        // A branch that ends on the other side of the geometric surface than
                        // its shading normal meant (smooth triangles) goes on there, as
                        // Mitsuba's spawned rays do: cutting it darkened smooth glass meshes
                        // by 2% (scripts/media_suite_probe.py, docs/media.md).
                        let trace = |dir: Vec3, rng: &mut Rng, first: &mut Option<SobolStream>| {
                            let refracts = Some(dir) == g.refracted;
                            // Radiance-mode transmission (`Dielectric::refracted_radiance`).
                            let k = if refracts {
                                g.refracted_radiance()
                            } else {
                                1.0
                            };
                            // Past a null pass the lobe sample's weighing of the light it
                            // meets carries over (shadow rays cross the sheet too).
                            let (d, m) = match refracts && null_pass {
                                true => (depth, mis),
                                false => (depth + 1, None),
                            };
                            k * self.radiance(&next(dir), d, rng, first, cw, m, after(dir))
                        };
                        let Some(t) = g.refracted else {
                            return emitted + trace(g.reflected, rng, first);
                        };
                        if depth < GLASS_SPLIT_DEPTH && !null_pass {
                            // The heavier branch first: it gets the Sobol hit if one is left.
                            let (r, tr) = if g.reflectance >= 0.5 {
                                let r = trace(g.reflected, rng, first);
                                (r, trace(t, rng, first))
                            } else {
                                let tr = trace(t, rng, first);
                                (trace(g.reflected, rng, first), tr)
                            };
                            emitted + g.reflectance * r + (1.0 - g.reflectance) * tr
                        } else if rng.next() < g.reflectance {
                            emitted + trace(g.reflected, rng, first)
                        } else {
                            emitted + trace(t, rng, first)
                        }
                    }
                }
            }
            SurfaceClass::Shaded => {
                let sobol = first.take();
                emitted + self.shade(&hit, &bsdf, -ray.dir, depth, rng, sobol, cw, medium)
            }
        }
    }

    /// Radiance of the environment along a ray that left the scene in direction `dir`; drawn
    /// from a glossy lobe (`mis`), it shares the environment with the shadow rays as an area
    /// light does.
    fn escape(&self, dir: Vec3, mis: Option<Mis>) -> Vec3 {
        let le = escape(self.scene, dir);
        let Some(mis) = mis.filter(|_| le != Vec3::ZERO) else {
            return le;
        };
        let l = self.scene.lights.len() - 1;
        let pdf_light = if dir.dot(mis.ns) > 0.0 {
            let n = self.settings.shadow_samples as f32;
            n * self.lights.direction_pdf(self.scene, l, mis.ns, dir)
        } else {
            0.0
        };
        le * power_heuristic(mis.pdf, pdf_light)
    }

    /// Radiance leaving a diffuse or glossy hit towards `wo`; `sobol` is the sample's Sobol
    /// stream at its first shaded hit (first shadow sample and gather direction), else `None`;
    /// `cw` the caustic estimate's weight; `medium` the one the viewer's ray came through.
    #[allow(clippy::too_many_arguments)]
    fn shade(
        &self,
        hit: &Hit,
        bsdf: &SurfaceBsdf,
        wo: Vec3,
        depth: u32,
        rng: &mut Rng,
        sobol: Option<SobolStream>,
        cw: f32,
        medium: u32,
    ) -> Vec3 {
        let f = Facing::new(hit.normal, hit.shading, wo.dot(hit.normal) >= 0.0);
        let s = self.settings;
        let mut l = Vec3::ZERO;
        // Light arriving here makes the path a bounce longer: past max_depth bounces a hit
        // only emits (Mitsuba's max_depth M counts segments: max_depth is M - 1).
        if depth >= s.max_depth {
            return l;
        }
        if self.terms.direct || (self.terms.point_lobe && bsdf.lobe_takes_point_lights()) {
            l += self.direct(hit, bsdf, &f, wo, rng, sobol, medium);
        }
        // The photon estimate uses the diffuse part; the lobe is traced below.
        let kd_over_pi = bsdf.estimate_brdf(wo);
        // Final gathering replaces the global map's estimate here by the gather ray below.
        let global = if self.terms.final_gather {
            None
        } else {
            self.global
        };
        let caustic = self.caustic.filter(|_| cw > 0.0);
        for (map, max_r, w) in [(global, s.radius, 1.0), (caustic, s.caustic_radius, cw)] {
            if let Some(map) = map {
                // The geometric normal: photons carry their surface's.
                l += w * estimate_at(
                    map,
                    hit.position,
                    f.ng,
                    s.k as usize,
                    max_r * max_r,
                    s.filter,
                    kd_over_pi,
                );
            }
        }
        let albedo = bsdf.diffuse_albedo(wo);
        if self.terms.final_gather && depth < s.max_depth && albedo.max_element() > 0.0 {
            l += albedo * self.final_gather(hit, bsdf, &f, depth, rng, sobol, medium);
        }
        if self.terms.lobe_ray && bsdf.has_lobe() && depth < s.max_depth {
            if let Some(lobe) = bsdf.sample_lobe(-wo, &f, rng) {
                let dir = lobe.dir;
                // With shadow rays to area lights, a glossy lobe's hit on one is weighed.
                let mis = (self.terms.direct && lobe.pdf > 0.0).then_some(Mis {
                    from: hit.position,
                    pdf: lobe.pdf,
                    ns: f.ns,
                });
                l += lobe.weight
                    * self.radiance(
                        &Ray {
                            origin: offset_origin(hit.position, hit.normal, dir),
                            dir,
                        },
                        depth + 1,
                        rng,
                        &mut None,
                        cw,
                        mis,
                        medium_after(self.scene, hit, medium, dir),
                    );
            }
        }
        l
    }
}
