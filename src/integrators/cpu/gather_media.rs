//! The camera pass's segments through participating media on the CPU (issue 24): what a
//! medium scatters towards the camera along a segment (`Medium::transmittance` is what it
//! lets through). The camera rays (`gather.rs`) and the gather rays (`final_gather.rs`) call these.

use crate::integrators::cpu::gather::Gatherer;
use crate::integrators::cpu::media::single_scattering;
use crate::integrators::photon::BeamPhotons;
use crate::math::geometry::Ray;
use crate::math::rng::Rng;
use crate::media::{GATHER_MEDIUM_POINTS, NEAR_GATHER_FRACTION};
use glam::Vec3;

impl Gatherer<'_> {
    /// The light scattered towards the camera along a segment of `ray`, `t` long, in
    /// `medium`: single scattering by next-event estimation (with `nee`) and the volume map's
    /// beam estimate (without its single-scattering photons when `skip_direct`). With `near`
    /// (the segment ends at a shaded surface or leaves the scene) in `gather` mode, the near
    /// part of the segment ([`NEAR_GATHER_FRACTION`] of its length within the photons'
    /// bounds) takes its multiply scattered light from one gather ray instead
    /// ([`Gatherer::near_gather`]); `depth` is the segment's camera depth.
    #[allow(clippy::too_many_arguments)]
    pub fn in_scattered(
        &self,
        ray: &Ray,
        t: f32,
        medium: u32,
        nee: bool,
        skip_direct: bool,
        near: bool,
        depth: u32,
        rng: &mut Rng,
    ) -> Vec3 {
        let m = &self.scene.media[medium as usize];
        let mut l = Vec3::ZERO;
        if nee && m.sigma_s().max_element() > 0.0 {
            l += single_scattering(
                self.scene,
                self.bvh,
                self.lights,
                ray.origin,
                ray.dir,
                t,
                medium,
                self.settings.shadow_samples,
                rng,
            );
        }
        let Some(v) = self.volume else {
            return l;
        };
        let gathers = near
            && skip_direct
            && self.cache.is_some()
            && depth < self.settings.max_depth
            && m.sigma_s().max_element() > 0.0;
        let zn = match gathers {
            true => NEAR_GATHER_FRACTION * t.min(v.exit(ray.origin, ray.dir)),
            false => 0.0,
        };
        let which = match skip_direct {
            true => BeamPhotons::SkipDirect,
            false => BeamPhotons::All,
        };
        // One transmittance walk serves every photon of the segment (exact if homogeneous).
        let tr = m.transmittances(ray.origin, ray.dir, t, rng);
        if !(zn > 0.0 && zn.is_finite()) {
            return l + v.beam_through((ray.origin, ray.dir, t), (m, medium), which, &tr);
        }
        let far = ray.origin + ray.dir * zn;
        let (tr_zn, tr_far) = tr.split(zn);
        l += tr_zn * v.beam_through((far, ray.dir, t - zn), (m, medium), which, &tr_far);
        let caustic = BeamPhotons::Caustic;
        l += v.beam_through((ray.origin, ray.dir, zn), (m, medium), caustic, &tr);
        l + self.near_gather(ray, zn, medium, depth, rng)
    }

    /// The light scattered at least twice that reaches the camera from the first `zn` of
    /// `ray` in `medium` (camera depth `depth`): a distance drawn in proportion to
    /// `sigma_t T(t)` (`Medium::sample_in_segment`: two numbers), a direction from the phase
    /// function (two more; it cancels), and the gather ray's radiance from there, times
    /// `sigma_s`, the transmittance and over the distance's density.
    fn near_gather(&self, ray: &Ray, zn: f32, medium: u32, depth: u32, rng: &mut Rng) -> Vec3 {
        let m = &self.scene.media[medium as usize];
        let (uc, ut) = (rng.next(), rng.next());
        let (u1, u2) = (rng.next(), rng.next());
        let Some(p) = m.scatter_in_segment(ray.origin, ray.dir, (uc, ut), zn, rng) else {
            return Vec3::ZERO;
        };
        let gather = Ray {
            origin: ray.origin + ray.dir * p.t,
            dir: m.phase.sample(ray.dir, u1, u2),
        };
        let li = self.gather_ray(&gather, depth + 1, rng, medium);
        p.weight() * li
    }

    /// The light scattered towards a final-gather ray's origin along its segment of `ray`,
    /// `t` long, in `medium`: the volume map's point estimate (`VolumeMap::point`) at
    /// [`GATHER_MEDIUM_POINTS`] distances drawn in the segment in proportion to
    /// `sigma_t T(t)` (`Medium::sample_in_segment`, stratified: one channel, the strata of
    /// one uniform number), each weighed by the transmittance to it over its density. All
    /// the volume photons count (a gather ray has no next-event estimate). A few table
    /// probes where the whole beam walks every cell the segment crosses: gather rays are
    /// most of the camera pass's volume queries, and their noise is averaged by the pixel's
    /// samples.
    pub fn gathered_in_medium(&self, ray: &Ray, t: f32, medium: u32, rng: &mut Rng) -> Vec3 {
        let (uc, u) = (rng.next(), rng.next());
        let Some(v) = self.volume else {
            return Vec3::ZERO;
        };
        let m = &self.scene.media[medium as usize];
        let mut sum = Vec3::ZERO;
        for i in 0..GATHER_MEDIUM_POINTS {
            let ui = (i as f32 + u) / GATHER_MEDIUM_POINTS as f32;
            // None: the chosen channel cannot scatter (homogeneous), or the flight left the
            // segment (heterogeneous): no light from this point.
            let Some(p) = m.scatter_in_segment(ray.origin, ray.dir, (uc, ui), t, rng) else {
                continue;
            };
            let x = ray.origin + ray.dir * p.t;
            // The point estimate holds sigma_s already (in the photons' power).
            sum += p.tr_over_pdf * v.point(x, -ray.dir, m, medium);
        }
        sum / GATHER_MEDIUM_POINTS as f32
    }
}
