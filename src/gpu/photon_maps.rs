//! A pass's photon maps: their sizes from the plan (paths, capacity within one storage
//! binding, grid table and a first cell size), and the recording of their tracing and grid
//! builds, whose cells the device resizes from the photons actually stored (`size_grid`).

use super::grid::{cell_size_for, table_size_for};
use super::host::drop_flags;
use super::maps::{MapBuffers, EMPTY_MAP};
use super::recorder::Recorder;
use super::run::GpuRun;
use super::types::GpuMapParams;
use crate::error::Result;
use crate::photon::Photon;
use crate::report::RenderReport;
use crate::rng::Stream;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// The caustic map's photons are expected on this fraction of the storing area (its grid's
/// cells are sized for that concentration).
const CAUSTIC_CONCENTRATION: f32 = crate::plan::CAUSTIC_AREA_FRACTION as f32;
/// Photons a global path is expected to store, for the first sizing of the grid.
const GLOBAL_STORES_PER_PATH: u32 = 3;

impl GpuRun {
    /// A map with parameters `p`: a cached one of the same sizes (its parameters rewritten)
    /// or a new one.
    fn take_map(&mut self, p: GpuMapParams, label: &str) -> MapBuffers {
        let same = |m: &MapBuffers| {
            m.params.capacity == p.capacity
                && m.params.table_size == p.table_size
                && m.params.is_caustic == p.is_caustic
        };
        match self.map_cache.iter().position(same) {
            Some(i) => {
                let mut m = self.map_cache.swap_remove(i);
                m.set_params(&self.ctx, p);
                m
            }
            None => MapBuffers::new(&self.ctx, &self.layouts, label, p),
        }
    }

    /// The global and caustic maps the current plan asks for (absent ones with `paths == 0`).
    fn plan_maps(&mut self, scene: &Scene, s: &RenderSettings) -> (MapBuffers, MapBuffers) {
        let max_binding = self.ctx.max_binding;
        let max_photons = (max_binding / std::mem::size_of::<Photon>() as u64) as u32;
        let area = scene.storing_area();
        // A map's grid parameters; fixed-radius passes (k = 0) use cells of the radius.
        let params = |caustic: bool,
                      paths: u32,
                      capacity: u32,
                      expected: u32,
                      radius: f32,
                      concentration: f32,
                      drop_flags: u32| GpuMapParams {
            stream: if caustic {
                Stream::Caustic
            } else {
                Stream::Photon
            } as u32,
            paths,
            capacity,
            table_size: table_size_for(expected, max_binding),
            cell_size: cell_size_for(radius, s.k, expected, area, concentration),
            is_caustic: caustic as u32,
            drop_flags,
            radius2: radius * radius,
            k: s.k,
            storing_area: area * concentration,
            // Written by the grid build.
            max_power: 0.0,
        };
        let (gp, glabel) = match &self.plan.global {
            Some(b) => {
                let paths = b.total();
                let capacity =
                    (paths as u64 * s.max_photon_bounces as u64).min(max_photons as u64) as u32;
                let drop = drop_flags(self.plan.global_filter());
                let expected = paths.saturating_mul(GLOBAL_STORES_PER_PATH);
                let p = params(false, paths, capacity, expected, s.radius, 1.0, drop);
                (p, "global")
            }
            None => (EMPTY_MAP, "global (absent)"),
        };
        let (cp, clabel) = match &self.plan.caustic {
            Some((b, _)) => {
                let paths = b.total();
                let capacity = paths.min(max_photons);
                let (expected, r) = (s.caustic_photons, s.caustic_radius);
                let p = params(true, paths, capacity, expected, r, CAUSTIC_CONCENTRATION, 0);
                (p, "caustic")
            }
            None => {
                let absent = GpuMapParams {
                    is_caustic: 1,
                    ..EMPTY_MAP
                };
                (absent, "caustic (absent)")
            }
        };
        let global = self.take_map(gp, glabel);
        let caustic = self.take_map(cp, clabel);
        (global, caustic)
    }

    /// Records tracing the photon maps the plan asks for and building their grids (the
    /// phases "trace photons" and "build grids" of `rec`); returns the maps.
    pub fn record_maps(
        &mut self,
        scene: &Scene,
        s: &RenderSettings,
        rec: &mut Recorder,
        report: &mut RenderReport,
    ) -> Result<(MapBuffers, MapBuffers)> {
        let (global, caustic) = self.plan_maps(scene, s);
        let scene_bg = &self.scene_buffers.bind_group;
        for m in [&global, &caustic] {
            if m.params.paths > 0 {
                m.record_trace(rec, &self.pipelines, scene_bg);
            }
        }
        rec.phase("trace photons", report)?;
        for m in [&global, &caustic] {
            if m.params.paths > 0 {
                m.record_grid(rec, &self.pipelines, scene_bg);
            }
        }
        rec.phase("build grids", report)?;
        Ok((global, caustic))
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn caustic_concentration_is_the_plans_fraction() {
        assert_eq!(super::CAUSTIC_CONCENTRATION.to_bits(), 0.05f32.to_bits());
    }
}
