//! The gather ray of final gathering on the CPU (twin: `gather_ray` in `src/integrators/gpu/gather.wgsl`).
//! At a shaded camera hit x in `gather` mode one cosine-weighted direction about the facing
//! normal is drawn (`rng.next2()`, after the direct light and before the lobe ray; at the
//! sample's first shaded hit Sobol pair `sobol::PAIR_GATHER` instead); the ray follows
//! mirrors (times ks) and glass (always one branch: one `rng.next()` < reflectance
//! reflects), depth + 1 per bounce up to `max_depth`, and at its first shaded hit y adds the
//! diffuse albedo of y times the radiance cache at y (normal facing the ray; where no cache
//! point matches, the global map's estimate at y). Where y has a
//! lobe the ray goes on along one direction drawn from it (weight as the camera's lobe ray).
//! It never counts emission: light from a light directly (shadow rays) or over delta and
//! glossy lobes (L (S|G)+ D: the caustic map) is counted elsewhere. The caller multiplies by
//! the diffuse albedo of x: the cosine pdf cancels the cosine and 1/pi.

use crate::bsdfs::shading::{bsdf_at, DeltaEvent, SurfaceBsdf, SurfaceClass};
use crate::bvh::Hit;
use crate::integrators::cpu::cache::RadianceCache;
use crate::integrators::cpu::gather::Gatherer;
use crate::integrators::cpu::media::{medium_after, MAX_CROSSINGS};
use crate::integrators::cpu::photon_map::estimate_at;
use crate::math::geometry::{offset_origin, Facing, Ray};
use crate::math::rng::Rng;
use crate::math::sampling::cosine_hemisphere;
use crate::math::sobol::{sample_pair, SobolStream, PAIR_GATHER};
use crate::media::NO_MEDIUM;
use glam::Vec3;

impl Gatherer<'_> {
    /// Indirect diffuse light at camera hit `hit` (normals `f` facing the viewer, camera
    /// depth `depth`) by one gather ray about the shading normal, before the factor kd(x):
    /// (u1, u2) for the direction from `sobol`'s pair `PAIR_GATHER` when given (the first
    /// shaded hit), else from `rng`; then one `rng` number per glass bounce. A direction
    /// below the geometric surface gives zero. `medium`: the one the viewer's ray came
    /// through.
    #[allow(clippy::too_many_arguments)]
    pub fn final_gather(
        &self,
        hit: &Hit,
        bsdf: &SurfaceBsdf,
        f: &Facing,
        depth: u32,
        rng: &mut Rng,
        sobol: Option<SobolStream>,
        medium: u32,
    ) -> Vec3 {
        let (u1, u2) = match sobol {
            Some(st) => sample_pair(st.key, st.index, PAIR_GATHER),
            None => rng.next2(),
        };
        let dir = cosine_hemisphere(f.ns, u1, u2);
        if f.reflection_leaks(dir) {
            return Vec3::ZERO;
        }
        let l = self.gather_ray(
            &Ray {
                origin: offset_origin(hit.position, hit.normal, dir),
                dir,
            },
            depth + 1,
            rng,
            medium_after(self.scene, hit, medium, dir),
        );
        match bsdf.store_weight(dir) {
            Some(w) => w * l,
            None => l,
        }
    }

    /// The radiance cache's value at `x` (normal `n`), or where no cache point matches, the
    /// global map's estimate there as a cache point's value is made (K nearest within the
    /// global radius, BRDF 1/pi): sparse cache points (one photon in `CACHE_STRIDE`) leave
    /// dim regions without one, and a zero there darkened the indirect light (rule:
    /// `plan::CACHE_NORMAL_COS`).
    fn cached(&self, cache: &RadianceCache, x: Vec3, n: Vec3) -> Vec3 {
        cache.lookup(x, n).unwrap_or_else(|| {
            let s = self.settings;
            let white = Vec3::splat(std::f32::consts::FRAC_1_PI);
            self.global.map_or(Vec3::ZERO, |g| {
                estimate_at(g, x, n, s.k as usize, s.radius * s.radius, s.filter, white)
            })
        })
    }

    /// Radiance the cache gives along `ray` (its hit at depth `depth`): the specular chain,
    /// then kd times the cache at the first diffuse or glossy hit, continued over glossy
    /// lobes; nothing more on a miss, at a black surface or past `max_depth`. Through a
    /// medium (`medium`), every segment adds the volume map's in-scattered light
    /// (`gathered_in_medium`) and carries its transmittance.
    pub(crate) fn gather_ray(&self, ray: &Ray, depth: u32, rng: &mut Rng, medium: u32) -> Vec3 {
        let (mut ray, mut depth, mut throughput) = (*ray, depth, Vec3::ONE);
        let mut medium = medium;
        let mut sum = Vec3::ZERO;
        // Index-matched boundaries crossed in a row: not bounces (as the camera path's).
        let mut crossings = 0;
        loop {
            // Emission is never counted here: light reaching x from a light (direct) or over
            // delta and glossy lobes (L (S|G)+ D) is in the shadow rays and the caustic map.
            let hit = self.bvh.intersect(self.scene, &ray, f32::INFINITY);
            if medium != NO_MEDIUM {
                let t = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
                sum += throughput * self.gathered_in_medium(&ray, t, medium, rng);
                let m = &self.scene.media[medium as usize];
                throughput *= m.transmittance_along(ray.origin, ray.dir, t, rng);
                if throughput == Vec3::ZERO {
                    return sum;
                }
            }
            let Some(hit) = hit else {
                return sum;
            };
            let bsdf = bsdf_at(self.scene, &hit, ray.dir);
            let can_recurse = depth < self.settings.max_depth;
            let crosses = bsdf.class() == SurfaceClass::Null && crossings < MAX_CROSSINGS;
            let dir = match bsdf.class() {
                SurfaceClass::Black => return sum,
                SurfaceClass::Shaded => {
                    let Some(cache) = self.cache else {
                        return sum;
                    };
                    let f = Facing::new(hit.normal, hit.shading, ray.dir.dot(hit.normal) <= 0.0);
                    sum += throughput
                        * bsdf.diffuse_albedo(-ray.dir)
                        * self.cached(cache, hit.position, f.ng);
                    // A lobe is not in the cache (it holds Lambertian radiance): the ray goes
                    // on along one direction drawn from the lobe, weighted as the camera's
                    // lobe ray is.
                    if !bsdf.has_lobe() || !can_recurse {
                        return sum;
                    }
                    let Some(lobe) = bsdf.sample_lobe(ray.dir, &f, rng) else {
                        return sum;
                    };
                    throughput *= lobe.weight;
                    lobe.dir
                }
                SurfaceClass::Null if crossings < MAX_CROSSINGS => ray.dir,
                _ if !can_recurse => return sum,
                SurfaceClass::Null => ray.dir,
                SurfaceClass::Delta => {
                    let f = hit.facing(ray.dir);
                    match bsdf.delta(ray.dir, &hit, &f, self.settings.fresnel) {
                        DeltaEvent::Reflect { dir, weight } => {
                            throughput *= weight;
                            if f.reflection_leaks(dir) {
                                return sum;
                            }
                            dir
                        }
                        DeltaEvent::Split(g) => {
                            let u = rng.next();
                            match g.refracted {
                                Some(t) if u >= g.reflectance => {
                                    if f.refraction_leaks(t) {
                                        return sum;
                                    }
                                    throughput *= g.refracted_radiance();
                                    t
                                }
                                _ if f.reflection_leaks(g.reflected) => return sum,
                                _ => g.reflected,
                            }
                        }
                    }
                }
            };
            medium = medium_after(self.scene, &hit, medium, dir);
            ray = Ray {
                origin: offset_origin(hit.position, hit.normal, dir),
                dir,
            };
            match crosses {
                true => crossings += 1,
                false => (crossings, depth) = (0, depth + 1),
            }
        }
    }
}
