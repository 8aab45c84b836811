//! A pass's photon maps: their sizes from the plan (paths, capacity within one storage
//! binding, grid table and cell size), tracing them and building their grids on the device,
//! with the cells resized from the photons actually stored.

use super::buffers::{read_back, wait};
use super::grid::{cell_size_for, table_size_for};
use super::host::drop_flags;
use super::maps::{MapBuffers, EMPTY_MAP};
use super::run::GpuRun;
use super::types::GpuMapParams;
use crate::error::Result;
use crate::photon::Photon;
use crate::report::RenderReport;
use crate::rng::Stream;
use crate::scene::Scene;
use crate::settings::RenderSettings;
use std::time::Instant;

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

    /// Traces the photon maps the plan asks for and builds their grids on the device.
    pub fn trace_maps(
        &mut self,
        scene: &Scene,
        s: &RenderSettings,
        report: &mut RenderReport,
    ) -> Result<(MapBuffers, MapBuffers)> {
        let mut t = Instant::now();
        let (mut global, mut caustic) = self.plan_maps(scene, s);
        let ctx = &self.ctx;
        let area = scene.storing_area();
        // Two submissions, each waited for, so the phases can be timed apart.
        for (trace, grid, name) in [(true, false, "trace photons"), (false, true, "build grids")] {
            let mut enc = ctx
                .device
                .create_command_encoder(&wgpu::CommandEncoderDescriptor { label: Some(name) });
            for m in [&global, &caustic] {
                if m.params.paths > 0 {
                    let scene_bg = &self.scene_buffers.bind_group;
                    m.record_build(&mut enc, &self.pipelines, scene_bg, trace, grid);
                }
            }
            ctx.queue.submit([enc.finish()]);
            wait(ctx)?;
            ctx.check()?;
            report.phase(name, t);
            t = Instant::now();
            if trace {
                let gc: Vec<u32> = read_back(ctx, &global.counters, 16)?;
                let cc: Vec<u32> = read_back(ctx, &caustic.counters, 16)?;
                report.global_stored = gc[0] as usize;
                report.caustic_stored = cc[0] as usize;
                // Size the grid's cells from the photons actually stored (an open scene stores
                // far fewer per path than a closed one; too small cells would make sparse
                // searches run out of cells and be cut).
                for (m, stored, concentration) in [
                    (&mut global, gc[0], 1.0f32),
                    (&mut caustic, cc[0], CAUSTIC_CONCENTRATION),
                ] {
                    if m.params.paths == 0 {
                        continue;
                    }
                    let cell = cell_size_for(
                        m.params.radius2.sqrt(),
                        s.k,
                        stored.min(m.params.capacity),
                        area,
                        concentration,
                    );
                    if cell != m.params.cell_size {
                        let p = GpuMapParams {
                            cell_size: cell,
                            ..m.params
                        };
                        m.set_params(ctx, p);
                    }
                }
                t = Instant::now();
            }
        }
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
