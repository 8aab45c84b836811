//! Direct light at a diffuse or glossy hit of the camera pass on the CPU: shadow rays to the
//! area lights (their glossy part weighed against the lobe's own sampling by the power
//! heuristic) and to the delta lights, through the media they cross in scenes with media.
//! `Gatherer::shade` (`gather.rs`) adds it; `Mis` there is the lobe ray's side of the weighing.

use crate::bsdfs::shading::{power_heuristic, SurfaceBsdf};
use crate::bvh::Hit;
use crate::integrators::cpu::gather::Gatherer;
use crate::integrators::cpu::media::{medium_after, transmittance};
use crate::math::geometry::{offset_origin, Facing, Ray, OFFSET_FLOOR, OFFSET_SCALE};
use crate::math::rng::Rng;
use crate::math::sobol::{sample, sample_pair, SobolStream, DIM_LIGHT_THIRD, PAIR_LIGHT};
use glam::Vec3;

impl Gatherer<'_> {
    /// Direct light by shadow rays. With `terms.direct`: area lights through the diffuse part
    /// and delta lights (`LightKind::is_delta`) through the whole BRDF; otherwise only
    /// delta lights' glossy lobe. A directional light's shadow ray has no end.
    /// With `sobol`, the first area-light sample takes its three numbers from it. The BRDF
    /// and cosine use the shading normal `f.ns`; a light below the geometric surface gives
    /// nothing, unless it is a delta light and the lobe transmits (a rough dielectric: then
    /// the shading frame alone decides, on either side).
    /// In scenes with media, shadow rays carry the transmittance of the media they cross
    /// (starting in the one a ray leaving the hit is in, `medium` the viewer's).
    #[allow(clippy::too_many_arguments)]
    pub(super) fn direct(
        &self,
        hit: &Hit,
        bsdf: &SurfaceBsdf,
        f: &Facing,
        wo: Vec3,
        rng: &mut Rng,
        mut sobol: Option<SobolStream>,
        medium: u32,
    ) -> Vec3 {
        let mut l = Vec3::ZERO;
        for (li, light) in self.scene.lights.iter().enumerate() {
            let is_delta = light.shape.is_delta();
            if !self.terms.direct && !is_delta {
                continue;
            }
            let n_samples = if is_delta {
                1
            } else {
                self.settings.shadow_samples
            };
            let mut acc = Vec3::ZERO;
            for _ in 0..n_samples {
                let sobol_here = if is_delta { None } else { sobol.take() };
                let u = match sobol_here {
                    Some(st) => {
                        let (u0, u1) = sample_pair(st.key, st.index, PAIR_LIGHT);
                        [u0, u1, sample(st.key, st.index, DIM_LIGHT_THIRD)]
                    }
                    None => [rng.next(), rng.next(), rng.next()],
                };
                let ls = self.lights.sample(self.scene, li, hit.position, f.ns, u);
                if ls.weight == Vec3::ZERO {
                    continue;
                }
                let to_light = ls.point - hit.position;
                let wi = to_light / to_light.length();
                let ns = f.ns;
                let cos = wi.dot(ns);
                // A delta light behind a transmitting lobe is lit through it (no lobe ray
                // can reach it); an area light there is the lobe ray's alone (`Mis::ns`).
                // Through a transmitting lobe, the shading frame alone says which side a
                // delta light is on (Mitsuba's emitter sampling): the shadow ray leaves on
                // the geometric side it points to, as the lobe's rays do.
                let free = is_delta && bsdf.lobe_transmits();
                let leaks = match free {
                    true => cos == 0.0,
                    false => cos <= 0.0 || f.reflection_leaks(wi),
                };
                if leaks {
                    continue;
                }
                let cos = cos.abs();
                let f = match (is_delta, self.terms.direct) {
                    (true, true) => bsdf.eval(wi, wo, ns),
                    (true, false) => bsdf.eval_lobe(wi, wo, ns),
                    // An area light: the diffuse part, and a glossy lobe weighed against
                    // the lobe's own sampling (power heuristic).
                    _ if bsdf.lobe_is_glossy() => {
                        let n = n_samples as f32;
                        // Only the environment is a distant light with a density.
                        let pdf_light = n * if ls.distant {
                            self.lights.direction_pdf(self.scene, li, f.ns, wi)
                        } else {
                            self.lights
                                .solid_angle_pdf(li, hit.position, ls.point, ls.normal)
                        };
                        let pdf_lobe = bsdf.pdf_lobe(wi, wo, ns);
                        bsdf.eval_diffuse(wi, wo)
                            + bsdf.eval_lobe(wi, wo, ns) * power_heuristic(pdf_light, pdf_lobe)
                    }
                    _ => bsdf.eval_diffuse(wi, wo),
                };
                if f == Vec3::ZERO {
                    continue;
                }
                let origin = offset_origin(hit.position, hit.normal, wi);
                // Area lights: stop short of the light's own surface. A delta light is no
                // surface: the ray runs all the way, so a wall however close still shadows.
                let end_eps = if is_delta {
                    0.0
                } else {
                    OFFSET_SCALE * (ls.point.abs().max_element() + OFFSET_FLOOR) * 4.0
                };
                // Aim from the moved origin: `wi` (from the surface point) would pass the
                // light by up to the offset, e.g. outside a corner that hides it.
                // A directional light is at infinity, in the same direction from everywhere.
                let (dir, t_max) = if ls.distant {
                    (wi, f32::INFINITY)
                } else {
                    let to = ls.point - origin;
                    let len = to.length();
                    (to / len, len - end_eps)
                };
                if self.media {
                    let tr = match t_max > 0.0 {
                        true => {
                            let m = medium_after(self.scene, hit, medium, dir);
                            transmittance(self.scene, self.bvh, origin, dir, t_max, m, rng)
                        }
                        false => Vec3::ONE,
                    };
                    acc += f * ls.weight * cos * tr;
                    continue;
                }
                if t_max > 0.0 && self.bvh.occluded(self.scene, &Ray { origin, dir }, t_max) {
                    continue;
                }
                acc += f * ls.weight * cos;
            }
            l += acc / n_samples as f32;
        }
        l
    }
}
