//! The camera pass's segments through participating media on the CPU (issue 24): what a
//! medium scatters towards the camera along a segment (`Medium::transmittance` is what it
//! lets through). The camera rays (`gather.rs`) and the gather rays (`final_gather.rs`) call these.

use crate::cpu::gather::Gatherer;
use crate::cpu::media::single_scattering;
use crate::geometry::Ray;
use crate::rng::Rng;
use glam::Vec3;

impl Gatherer<'_> {
    /// The light scattered towards the camera along a segment of `ray`, `t` long, in
    /// `medium`: single scattering by next-event estimation (with `nee`) and the volume map's
    /// beam estimate (without its single-scattering photons when `skip_direct`).
    pub fn in_scattered(
        &self,
        ray: &Ray,
        t: f32,
        medium: u32,
        nee: bool,
        skip_direct: bool,
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
                rng,
            );
        }
        if let Some(v) = self.volume {
            l += v.beam(ray.origin, ray.dir, t, m, medium, skip_direct);
        }
        l
    }
}
