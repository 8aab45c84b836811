//! Host-side conversion of the plan and the settings into what the kernels read: `Params`
//! (with the mode's terms as bits), the lights' photon budgets, a map's drop flags, and the
//! split of a pass into photon batches.

use crate::integrators::gpu::codes::{
    filter_code, fresnel_code, sampler_code, DROP_CAUSTIC, DROP_DIRECT, TERM_DIRECT,
    TERM_FINAL_GATHER, TERM_LOBE_RAY, TERM_POINT_LOBE,
};
use crate::integrators::gpu::types::{lights, GpuLight, GpuParams};
use crate::integrators::plan::{MapKind, MapPlan, StoreFilter, Terms};
use crate::lights::table::LightTable;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// Distance between the per-sample parameter slots (the largest storage-buffer offset
/// alignment an adapter may require).
pub const PARAMS_STRIDE: u64 = 256;

/// Most batches one pass is split into (and the stride of batch indices in the RNG's pass).
pub const MAX_BATCHES: u32 = 64;

/// `Params.terms`: the plan's terms as TERM_* bits.
pub fn terms_bits(terms: Terms) -> u32 {
    (if terms.direct { TERM_DIRECT } else { 0 })
        | (if terms.point_lobe { TERM_POINT_LOBE } else { 0 })
        | (if terms.lobe_ray { TERM_LOBE_RAY } else { 0 })
        | (if terms.final_gather {
            TERM_FINAL_GATHER
        } else {
            0
        })
}

/// `MapParams.drop_flags`: a map's filter as DROP_* bits.
pub fn drop_flags(filter: StoreFilter) -> u32 {
    (if filter.drop_direct { DROP_DIRECT } else { 0 })
        | (if filter.drop_caustic { DROP_CAUSTIC } else { 0 })
}

/// `Params` of a pass (`sample` set per gather dispatch); `pass` is the RNG's pass index.
pub fn gpu_params(scene: &Scene, s: &RenderSettings, pass: u32, n_bounds: u32) -> GpuParams {
    let c = &scene.camera;
    GpuParams {
        eye: c.eye.to_array(),
        width: s.width,
        forward: c.forward.to_array(),
        height: s.height,
        right: c.right.to_array(),
        spp: s.spp,
        up: c.up.to_array(),
        sample: 0,
        seed: s.seed,
        pass_index: pass,
        k: s.k,
        filter_kind: filter_code(s.filter),
        mode: s.mode as u32,
        max_depth: s.max_depth,
        max_photon_bounces: s.max_photon_bounces,
        shadow_samples: s.shadow_samples,
        fresnel: fresnel_code(s.fresnel),
        sampler: sampler_code(s.sampler),
        n_lights: scene.lights.len() as u32,
        n_bounds,
        n_triangles: scene.triangles.len() as u32,
        terms: terms_bits(Terms::of(s.mode)),
        pixel_filter: c.filter.code(),
        filter_param: c.filter.param(),
        aperture_radius: c.aperture_radius,
        focus_distance: c.focus_distance,
        orthographic: c.orthographic as u32,
        camera_medium: scene.camera_medium,
        outer_medium: scene.outer_medium,
        ..Default::default()
    }
}

/// The lights with the plan's photon budgets filled in: each map's in its kind's fields.
pub fn budgeted_lights(scene: &Scene, table: &LightTable, plan: &MapPlan) -> Vec<GpuLight> {
    let mut lights = lights(scene, table);
    for spec in &plan.maps {
        let b = &spec.budget;
        for (l, g) in lights.iter_mut().enumerate() {
            let fields = match spec.kind {
                MapKind::Global => (
                    &mut g.global_offset,
                    &mut g.global_count,
                    &mut g.global_power,
                ),
                MapKind::Caustic => (
                    &mut g.caustic_offset,
                    &mut g.caustic_count,
                    &mut g.caustic_power,
                ),
            };
            (*fields.0, *fields.1, *fields.2) =
                (b.offsets[l], b.counts[l], b.path_power[l].to_array());
        }
    }
    lights
}

/// The RNG pass of batch `b` of pass `pass`: batch 0 is the pass itself (as on the CPU).
pub fn batch_pass(pass: u32, b: u32) -> u32 {
    pass ^ (b << 24)
}

/// Settings of batch `b` of `n`: an equal share of the photon paths (the remainder spread
/// over the first batches).
pub fn batch_settings(s: &RenderSettings, b: u32, n: u32) -> RenderSettings {
    let share = |total: u32| total / n + u32::from(b < total % n);
    RenderSettings {
        photons: share(s.photons).max(1),
        caustic_photons: share(s.caustic_photons),
        ..s.clone()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::settings::Mode;

    #[test]
    fn only_mode_gather_sets_the_final_gather_bit() {
        for mode in [
            Mode::Photon,
            Mode::Direct,
            Mode::Gather,
            Mode::DirectOnly,
            Mode::GlobalOnly,
            Mode::CausticOnly,
        ] {
            let bits = terms_bits(Terms::of(mode));
            assert_eq!(
                bits & TERM_FINAL_GATHER != 0,
                mode == Mode::Gather,
                "{mode:?}"
            );
        }
    }
}
