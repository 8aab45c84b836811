//! The gather ray of final gathering on the CPU (twin: `gather_ray` in `shaders/gather.wgsl`).
//! At a diffuse or glossy camera hit x in `gather` mode one cosine-weighted direction about
//! the facing normal is drawn (`rng.next2()`, after the direct light and before the glossy
//! lobe ray; at the sample's first shaded hit Sobol pair `sobol::PAIR_GATHER` instead); the ray follows mirrors (times ks) and glass (always one branch: one
//! `rng.next()` < reflectance reflects, 1 on total internal reflection), depth + 1 per bounce
//! up to `max_depth`, ignores emission (shadow rays and the caustic map count it), and at
//! its first diffuse or glossy hit y returns kd(y) times the radiance cache at y (normal
//! facing the ray). The caller multiplies by kd(x): the cosine pdf cancels the cosine and 1/pi.

use crate::bvh::Hit;
use crate::cpu::gather::Gatherer;
use crate::geometry::{offset_origin, Facing, Ray};
use crate::material::{dielectric_shading, reflect};
use crate::rng::Rng;
use crate::sampling::cosine_hemisphere;
use crate::scene::MaterialKind;
use crate::sobol::{sample_pair, SobolStream, PAIR_GATHER};
use glam::Vec3;

impl Gatherer<'_> {
    /// Indirect diffuse light at camera hit `hit` (normals `f` facing the viewer, camera
    /// depth `depth`) by one gather ray about the shading normal, before the factor kd(x):
    /// (u1, u2) for the direction from `sobol`'s pair `PAIR_GATHER` when given (the first
    /// shaded hit), else from `rng`; then one `rng` number per glass bounce. A direction
    /// below the geometric surface gives zero.
    pub fn final_gather(
        &self,
        hit: &Hit,
        f: &Facing,
        depth: u32,
        rng: &mut Rng,
        sobol: Option<SobolStream>,
    ) -> Vec3 {
        let (u1, u2) = match sobol {
            Some(st) => sample_pair(st.key, st.index, PAIR_GATHER),
            None => rng.next2(),
        };
        let dir = cosine_hemisphere(f.ns, u1, u2);
        if f.reflection_leaks(dir) {
            return Vec3::ZERO;
        }
        self.gather_ray(
            &Ray {
                origin: offset_origin(hit.position, hit.normal, dir),
                dir,
            },
            depth + 1,
            rng,
        )
    }

    /// Radiance the cache gives along `ray` (its hit at depth `depth`): the specular chain,
    /// then kd times the cache at the first diffuse or glossy hit; zero on a miss, at a black
    /// surface or when the chain runs past `max_depth`.
    fn gather_ray(&self, ray: &Ray, depth: u32, rng: &mut Rng) -> Vec3 {
        let (mut ray, mut depth, mut throughput) = (*ray, depth, Vec3::ONE);
        loop {
            let Some(hit) = self.bvh.intersect(self.scene, &ray, f32::INFINITY) else {
                return Vec3::ZERO;
            };
            let m = &self.scene.materials[hit.material as usize];
            let can_recurse = depth < self.settings.max_depth;
            let dir = match m.kind {
                MaterialKind::Black => return Vec3::ZERO,
                MaterialKind::Diffuse | MaterialKind::Glossy => {
                    let Some(cache) = self.cache else {
                        return Vec3::ZERO;
                    };
                    let ny = if ray.dir.dot(hit.normal) <= 0.0 {
                        hit.normal
                    } else {
                        -hit.normal
                    };
                    return throughput * m.kd * cache.lookup(hit.position, ny);
                }
                _ if !can_recurse => return Vec3::ZERO,
                MaterialKind::Mirror => {
                    let f = hit.facing(ray.dir);
                    throughput *= m.ks;
                    let dir = reflect(ray.dir, f.ns);
                    if f.reflection_leaks(dir) {
                        return Vec3::ZERO;
                    }
                    dir
                }
                MaterialKind::Glass => {
                    let (ng, ns) = (hit.normal, hit.shading);
                    let g = dielectric_shading(ray.dir, ng, ns, m.ior, self.settings.fresnel);
                    let f = hit.facing(ray.dir);
                    let u = rng.next();
                    match g.refracted {
                        Some(t) if u >= g.reflectance => {
                            if f.refraction_leaks(t) {
                                return Vec3::ZERO;
                            }
                            t
                        }
                        _ if f.reflection_leaks(g.reflected) => return Vec3::ZERO,
                        _ => g.reflected,
                    }
                }
            };
            ray = Ray {
                origin: offset_origin(hit.position, hit.normal, dir),
                dir,
            };
            depth += 1;
        }
    }
}
