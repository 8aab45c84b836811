//! Transport through participating media on the CPU (issue 24): which medium a path is in
//! (`MediumInterface::after` at every surface, the light's medium at emission), shadow rays'
//! transmittance across index-matched boundaries, and single scattering along a camera
//! segment by next-event estimation. The photon side is in `photons.rs`, the volume map and
//! its beam estimate in `volume_map.rs`. Scenes without media never call these.

use crate::bsdfs::shading::bsdf_at;
use crate::bsdfs::{BsdfKind, SurfaceClass};
use crate::bvh::{CpuBvh, Hit};
use crate::lights::interface::Emission;
use crate::lights::interface::LightKind;
use crate::lights::table::LightTable;
use crate::math::geometry::{offset_origin, Ray, OFFSET_FLOOR, OFFSET_SCALE};
use crate::math::rng::Rng;
use crate::media::{sample_equiangular, NO_MEDIUM};
use crate::scene::{LightShape, Scene};
use glam::Vec3;

/// Index-matched boundaries a shadow ray may cross before it counts as blocked (a bound on
/// the work of one ray through nested media).
pub const MAX_CROSSINGS: u32 = 64;

/// The medium a ray that was in `current` is in after the surface of `hit` sent it along
/// `dir` (`MediumInterface::after`: unchanged at a surface that bounds no medium, so scenes
/// without media stay in `NO_MEDIUM`).
#[inline]
pub fn medium_after(scene: &Scene, hit: &Hit, current: u32, dir: Vec3) -> u32 {
    scene.materials[hit.material as usize]
        .media
        .after(current, hit.normal, dir)
}

/// The medium a photon of light `l` starts in: an area light's shape's medium on the side it
/// emits towards; lights without a surface sit in the camera's
/// medium (a scene filled with fog has them in it; our file formats give such lights no
/// medium of their own).
pub fn light_medium(scene: &Scene, l: usize, e: &Emission) -> u32 {
    let Some(material) = scene.lights[l]
        .shape
        .material(&scene.triangles, &scene.spheres)
    else {
        return scene.camera_medium;
    };
    let media = scene.materials[material as usize].media;
    media.after(scene.camera_medium, e.normal, e.dir)
}

/// The medium a photon of light `l` emitted as `e` starts in from `origin` (its ray's offset
/// start): [`light_medium`], except in a scene with media for a light without a surface
/// (point, spot, projector, directional, environment) or an area light whose shape bounds no
/// medium. Mitsuba traces from the camera only, so its files need not say which medium such a
/// light sits in (a point light or a glowing torus inside a medium-filled sphere): the
/// photon's medium is then the one [`enclosing_medium`] finds along its ray, point by point of
/// the emitter, so an emitter that straddles a boundary is right on both sides, and a
/// directional light's photons, which start outside the scene, enter a bounded medium at its
/// boundary.
pub fn photon_medium(scene: &Scene, bvh: &CpuBvh, l: usize, e: &Emission, origin: Vec3) -> u32 {
    let named = scene.lights[l]
        .shape
        .material(&scene.triangles, &scene.spheres)
        .is_some_and(|m| !scene.materials[m as usize].media.is_vacuum());
    match named || scene.media.is_empty() {
        true => light_medium(scene, l, e),
        false => enclosing_medium(scene, bvh, origin, e.dir),
    }
}

/// The medium at `origin`: the side of the first surface bounding a medium that a ray along
/// `dir` meets (the interior when the ray leaves through its front), past surfaces that bound
/// none, at most [`MAX_CROSSINGS`] of them; the medium outside every shape
/// (`Scene::outer_medium`) when it meets none.
pub fn enclosing_medium(scene: &Scene, bvh: &CpuBvh, origin: Vec3, dir: Vec3) -> u32 {
    let mut ray = Ray { origin, dir };
    for _ in 0..MAX_CROSSINGS {
        let Some(hit) = bvh.intersect(scene, &ray, f32::INFINITY) else {
            break;
        };
        let media = scene.materials[hit.material as usize].media;
        if !media.is_vacuum() {
            return match dir.dot(hit.normal) > 0.0 {
                true => media.interior,
                false => media.exterior,
            };
        }
        ray.origin = offset_origin(hit.position, hit.normal, dir);
    }
    scene.outer_medium
}

/// The fraction of light that travels from `origin` along unit `dir` over `t_max` (infinite:
/// to the scene's end) starting in `medium`: the media's Beer-Lambert transmittance, through
/// index-matched boundaries (changing medium there) and thin dielectric sheets (times their
/// `SurfaceBsdf::null_transmission`, as Mitsuba's volpath); zero when any other surface is in
/// the way (a shadow ray does not see through glass) or after [`MAX_CROSSINGS`] boundaries.
/// A heterogeneous medium's is an unbiased estimate (ratio tracking, numbers from `rng`).
pub fn transmittance(
    scene: &Scene,
    bvh: &CpuBvh,
    origin: Vec3,
    dir: Vec3,
    t_max: f32,
    medium: u32,
    rng: &mut Rng,
) -> Vec3 {
    let (mut ray, mut left, mut medium) = (Ray { origin, dir }, t_max, medium);
    let mut tr = Vec3::ONE;
    // Runs are measured between the true points (hits, the ends), not the offset origins.
    let end = origin + dir * t_max;
    let mut at = origin;
    for _ in 0..MAX_CROSSINGS {
        let hit = bvh.intersect(scene, &ray, left);
        let run = match (&hit, t_max.is_finite()) {
            (Some(h), _) => (h.position - at).length(),
            (None, true) => (end - at).length(),
            (None, false) => f32::INFINITY,
        };
        if medium != NO_MEDIUM {
            tr *= scene.media[medium as usize].transmittance_along(at, dir, run, rng);
        }
        let Some(hit) = hit else {
            return tr;
        };
        if scene.materials[hit.material as usize].bsdf.class() != SurfaceClass::Null {
            // A thin sheet lets through its null transmission (Mitsuba's volpath).
            let w = bsdf_at(scene, &hit, dir).null_transmission(dir);
            if w == Vec3::ZERO {
                return Vec3::ZERO;
            }
            tr *= w;
        }
        medium = medium_after(scene, &hit, medium, dir);
        at = hit.position;
        let origin = offset_origin(hit.position, hit.normal, dir);
        left -= (origin - ray.origin).dot(dir);
        if left <= 0.0 {
            return tr;
        }
        ray.origin = origin;
    }
    Vec3::ZERO
}

/// Single scattering along a camera segment from `origin` along unit `dir`, `t_seg` long
/// (infinite: the ray left the scene), in `medium`: for each light, a point on it (three
/// uniform numbers, as the surfaces' shadow rays draw them), one distance drawn in the
/// segment towards that point (equiangular, [`sample_equiangular`], so a segment passing near
/// a light is not noise; by transmittance, `Medium::sample_in_segment`, for a directional
/// light or a segment through the point) and one shadow ray, weighed by the phase function,
/// `sigma_s` and the transmittance along the segment and the shadow ray. The environment's
/// direction is drawn from the phase function. Each light takes `samples` such estimates
/// (the render's `shadow_samples`, for delta lights too: the distance is drawn either way),
/// averaged; light by light, so one sample draws the random numbers of the light loop.
#[allow(clippy::too_many_arguments)]
pub fn single_scattering(
    scene: &Scene,
    bvh: &CpuBvh,
    lights: &LightTable,
    origin: Vec3,
    dir: Vec3,
    t_seg: f32,
    medium: u32,
    samples: u32,
    rng: &mut Rng,
) -> Vec3 {
    let m = &scene.media[medium as usize];
    let mut l = Vec3::ZERO;
    let lights_samples = (0..scene.lights.len()).flat_map(|li| (0..samples).map(move |_| li));
    for li in lights_samples {
        let light = &scene.lights[li];
        let u = [rng.next(), rng.next(), rng.next()];
        let (uc, ut) = (rng.next(), rng.next());
        let p = match lights.anchor(scene, li, u) {
            Some(y) => sample_equiangular(origin, dir, t_seg, y, ut),
            None => None,
        };
        // The equiangular point's transmittance comes after its shadow ray (the order the
        // random numbers are drawn in): `None` here.
        let s = match p {
            Some(p) => {
                let x = origin + dir * p.t;
                (p.t, None, m.sigma_s_at(x), p.pdf)
            }
            None => match m.scatter_in_segment(origin, dir, (uc, ut), t_seg, rng) {
                Some(s) => (s.t, Some(s.tr_over_pdf), s.sigma_s, 1.0),
                None => continue,
            },
        };
        let (t, tr_over_pdf, sigma_s, pdf) = s;
        if sigma_s == Vec3::ZERO {
            continue;
        }
        let x = origin + dir * t;
        let seg = |rng: &mut Rng| match tr_over_pdf {
            Some(w) => w,
            None => m.transmittance_along(origin, dir, t, rng) / pdf,
        };
        if let LightShape::Environment(e) = light.shape {
            // A direction drawn from the phase function (which then cancels): the
            // environment's own sampling covers a surface's hemisphere.
            let wi = m.phase.sample(dir, u[1], u[2]);
            let tr = transmittance(scene, bvh, x, wi, f32::INFINITY, medium, rng);
            l += sigma_s * seg(rng) * e.eval(&scene.textures, wi) * tr;
            continue;
        }
        let ls = lights.sample(scene, li, x, -dir, u);
        if ls.weight == Vec3::ZERO {
            continue;
        }
        let to_light = ls.point - x;
        let dist = to_light.length();
        if !(dist > 0.0) {
            continue;
        }
        let wi = to_light / dist;
        // Light travels along -wi, then on towards the camera (along -dir).
        let phase = m.phase.eval(wi.dot(dir));
        // Stop short of an area light's own surface (as the surfaces' shadow rays do).
        let t_max = match (ls.distant, light.shape.is_delta()) {
            (true, _) => f32::INFINITY,
            (false, true) => dist,
            (false, false) => {
                dist - OFFSET_SCALE * (ls.point.abs().max_element() + OFFSET_FLOOR) * 4.0
            }
        };
        let tr = transmittance(scene, bvh, x, wi, t_max, medium, rng);
        l += sigma_s * seg(rng) * ls.weight * phase * tr;
    }
    l / samples.max(1) as f32
}
