//! A pass's photon maps: their sizes from the plan (paths, capacity within one storage
//! binding, grid table and a first cell size), and the recording of their tracing and grid
//! builds, whose cells the device resizes from the photons actually stored (`size_grid`).

use crate::error::Result;
use crate::integrators::gpu::codes::{VOLUME_DROP_CAUSTIC, VOLUME_STORE};
use crate::integrators::gpu::grid::{cell_size_for, table_size_for};
use crate::integrators::gpu::host::drop_flags;
use crate::integrators::gpu::maps::{MapBuffers, EMPTY_MAP};
use crate::integrators::gpu::recorder::Recorder;
use crate::integrators::gpu::run::GpuRun;
use crate::integrators::gpu::types::GpuMapParams;
use crate::integrators::gpu::volume::{volume_capacity, VolumeBuffers};
use crate::integrators::plan::MapKind;
use crate::render::report::RenderReport;
use crate::scene::Scene;
use crate::settings::RenderSettings;

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
            None => MapBuffers::new(&self.ctx, &self.layouts, label, p, self.volume.bindings()),
        }
    }

    /// The maps the current plan asks for, one per [`MapKind`] slot (absent kinds with
    /// `paths == 0`).
    fn plan_maps(&mut self, scene: &Scene, s: &RenderSettings) -> PassMaps {
        let max_binding = self.ctx.max_binding;
        let max_photons = self.ctx.max_photons();
        let area = scene.storing_area();
        // The volume photons' buffer, grown when this pass's paths may store more (the maps'
        // bind groups hold the old one: they are made anew).
        let volume = volume_capacity(&self.plan, s.max_photon_bounces, max_photons);
        if volume > self.volume.capacity {
            self.volume = VolumeBuffers::new(&self.ctx, &self.layouts, volume);
            self.map_cache.clear();
        }
        let volume_flags = match self.plan.volume {
            Some(v) => {
                VOLUME_STORE
                    | if v.drop_caustic {
                        VOLUME_DROP_CAUSTIC
                    } else {
                        0
                    }
            }
            None => 0,
        };
        MapKind::ALL.map(|kind| {
            let is_caustic = (kind == MapKind::Caustic) as u32;
            let Some(spec) = self.plan.map(kind) else {
                let absent = GpuMapParams {
                    is_caustic,
                    ..EMPTY_MAP
                };
                return self.take_map(absent, &format!("{} (absent)", kind.name()));
            };
            let paths = spec.budget.total();
            // Photons a path may store (the capacity) and are expected in all (the grid's
            // first sizing): a global path one per bounce, about GLOBAL_STORES_PER_PATH; a
            // caustic path at most one, the wanted caustic photons in all.
            let (per_path, expected) = match kind {
                MapKind::Global => (
                    s.max_photon_bounces,
                    paths.saturating_mul(GLOBAL_STORES_PER_PATH),
                ),
                MapKind::Caustic => (1, s.caustic_photons),
            };
            let capacity = (paths as u64 * per_path as u64).min(max_photons as u64) as u32;
            let radius = kind.radius(s);
            let concentration = kind.area_fraction() as f32;
            let p = GpuMapParams {
                stream: kind.stream() as u32,
                paths,
                capacity,
                table_size: table_size_for(expected, max_binding),
                // Fixed-radius passes (k = 0) use cells of the radius.
                cell_size: cell_size_for(radius, s.k, expected, area, concentration),
                is_caustic,
                drop_flags: drop_flags(spec.filter),
                radius2: radius * radius,
                k: s.k,
                storing_area: area * concentration,
                // Written by the grid build.
                max_power: 0.0,
                // Only the global map drops: its L S+ V photons are the caustic paths'.
                volume_flags: match kind {
                    MapKind::Global => volume_flags,
                    MapKind::Caustic => volume_flags & VOLUME_STORE,
                },
            };
            self.take_map(p, kind.name())
        })
    }

    /// Records tracing the photon maps the plan asks for and building their grids (the
    /// phases "trace photons" and "build grids" of `rec`); returns the maps.
    pub fn record_maps(
        &mut self,
        scene: &Scene,
        s: &RenderSettings,
        rec: &mut Recorder,
        report: &mut RenderReport,
    ) -> Result<PassMaps> {
        let maps = self.plan_maps(scene, s);
        rec.enc().clear_buffer(&self.volume.count, 0, None);
        let scene_bg = &self.scene_buffers.bind_group;
        for m in maps.iter().filter(|m| m.params.paths > 0) {
            m.record_trace(rec, &self.pipelines, scene_bg);
        }
        rec.phase("trace photons", report)?;
        for m in maps.iter().filter(|m| m.params.paths > 0) {
            m.record_grid(rec, &self.pipelines, scene_bg);
        }
        if self.plan.volume.is_some() {
            let scene_bg = &self.scene_buffers.bind_group;
            self.volume
                .record_grid(&self.ctx, rec, &self.pipelines, scene_bg, s.volume_radius);
        }
        rec.phase("build grids", report)?;
        Ok(maps)
    }
}

/// A pass's photon maps, one per [`MapKind`] slot.
pub type PassMaps = [MapBuffers; 2];
