//! The volume photon map on the device (participating media, issue 24): one buffer that every
//! photon map's paths append the photons they leave in media to (`store_volume_photon` in
//! src/integrators/gpu/trace_photons.wgsl), with its count, bound in every map's group 1; and its grid,
//! twin of `cpu::volume_map` (src/integrators/gpu/volume_grid.wgsl): cells of at least 2r sized on the
//! device from the photons stored, each photon listed in every cell its sphere's box
//! overlaps, hashed into a table built by the photon maps' own scan kernels. A scene without
//! a volume map binds one-photon placeholders that nothing writes.

use crate::integrators::gpu::bindings::Layouts;
use crate::integrators::gpu::buffers::{empty_buffer, grid_2d};
use crate::integrators::gpu::codes::{SCAN_BLOCK, SCAN_ITEMS, VOLUME_MAX_PHOTONS};
use crate::integrators::gpu::context::GpuContext;
use crate::integrators::gpu::grid::table_size_for;
use crate::integrators::gpu::maps::{MapBuffers, EMPTY_MAP};
use crate::integrators::gpu::pipelines::Pipelines;
use crate::integrators::gpu::recorder::Recorder;
use crate::integrators::gpu::types::GpuMapParams;
use crate::integrators::photon::Photon;
use crate::integrators::plan::{MapKind, MapPlan};

/// Counters of the volume photons (`volume_count`): `[0]` the photons stored (may pass the
/// capacity; the excess is dropped), the rest unused.
pub const VOLUME_COUNTERS: u64 = 4;
/// Cells a photon's sphere's box overlaps at most (cells of at least 2r): the grid's entries
/// per photon.
pub const CELLS_PER_PHOTON: u64 = 8;
/// Bytes of one grid entry (photon index, cell coordinates).
const ENTRY_BYTES: u64 = 16;

/// The volume photons, their count and their grid.
pub struct VolumeBuffers {
    /// Photons the buffer holds.
    pub capacity: u32,
    /// `capacity` photons (`volume`; the gather's `v_photons`).
    pub photons: wgpu::Buffer,
    /// `volume_count`.
    pub count: wgpu::Buffer,
    /// The grid's layout (`volume_grid`; the gather's `v_grid`), written by `size_volume`.
    pub grid: wgpu::Buffer,
    /// The grid's hash table: `cell_count`, `cell_start` (the gather's `v_cells`), and its
    /// entries in `sorted` (the gather's `v_refs`), built over these photons.
    pub map: MapBuffers,
}

impl VolumeBuffers {
    /// Buffers of `capacity` (at least one) volume photons, their counters and grid.
    pub fn new(ctx: &GpuContext, layouts: &Layouts, capacity: u32) -> Self {
        let capacity = capacity.clamp(1, VOLUME_MAX_PHOTONS);
        let rw = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC;
        let bytes = capacity as u64 * std::mem::size_of::<Photon>() as u64;
        let photons = empty_buffer(&ctx.device, "volume photons", bytes, rw);
        let count = empty_buffer(&ctx.device, "volume counters", 4 * VOLUME_COUNTERS, rw);
        // (lo, cell), (hi, r), (table size, photons): zero photons until a grid is built.
        let grid = empty_buffer(&ctx.device, "volume grid", 48, rw);
        let entries = (capacity as u64 * CELLS_PER_PHOTON).min(ctx.max_binding / ENTRY_BYTES);
        let params = GpuMapParams {
            capacity: 1,
            table_size: table_size_for(capacity.saturating_mul(2), ctx.max_binding),
            ..EMPTY_MAP
        };
        let map = MapBuffers::sized(
            ctx,
            layouts,
            "volume grid",
            params,
            [&photons, &count, &grid],
            entries * ENTRY_BYTES,
        );
        VolumeBuffers {
            capacity,
            photons,
            count,
            grid,
            map,
        }
    }

    /// The map group's volume bindings (`volume`, `volume_count`, `volume_grid`).
    pub fn bindings(&self) -> [&wgpu::Buffer; 3] {
        [&self.photons, &self.count, &self.grid]
    }

    /// Records building the grid over the volume photons stored, spheres of `radius`, into
    /// `rec`: sized on the device (`size_volume`), nothing read back.
    pub fn record_grid(
        &mut self,
        ctx: &GpuContext,
        rec: &mut Recorder,
        p: &Pipelines,
        scene_bg: &wgpu::BindGroup,
        radius: f32,
    ) {
        let params = GpuMapParams {
            radius2: radius * radius,
            ..self.map.params
        };
        self.map.set_params(ctx, params);
        let map = &self.map;
        rec.enc().clear_buffer(&map.cell_count, 0, None);
        {
            let mut pass = map.begin(rec.enc(), "size volume", scene_bg);
            pass.set_pipeline(&p.size_volume);
            pass.dispatch_workgroups(1, 1, 1);
        }
        rec.kernel("size_volume");
        rec.enc()
            .copy_buffer_to_buffer(&map.counters, 4, &map.dispatch, 0, 12);
        let t = params.table_size;
        let stages = [
            ("count_volume", &p.count_volume, None),
            (
                "scan_blocks",
                &p.scan_blocks,
                Some((t.div_ceil(SCAN_ITEMS), SCAN_BLOCK)),
            ),
            ("scan_sums", &p.scan_sums, Some((SCAN_BLOCK, SCAN_BLOCK))),
            ("add_offsets", &p.add_offsets, Some((t, p.shape.wg_size))),
            ("scatter_volume", &p.scatter_volume, None),
        ];
        for (name, pipeline, size) in stages {
            {
                let mut pass = map.begin(rec.enc(), name, scene_bg);
                pass.set_pipeline(pipeline);
                match size {
                    Some((n, wg)) => {
                        let (x, y) = grid_2d(n.div_ceil(wg));
                        pass.dispatch_workgroups(x, y, 1);
                    }
                    None => pass.dispatch_workgroups_indirect(&map.dispatch, 0),
                }
            }
            rec.kernel(name);
        }
    }
}

/// Volume photons the paths of `plan` may store (0 without a volume map): a global path one
/// per bounce, a caustic path at most one; within `max_photons` (one storage binding).
pub fn volume_capacity(plan: &MapPlan, max_photon_bounces: u32, max_photons: u32) -> u32 {
    if plan.volume.is_none() {
        return 0;
    }
    let n: u64 = plan
        .maps
        .iter()
        .map(|m| {
            let per_path = match m.kind {
                MapKind::Global => max_photon_bounces as u64,
                MapKind::Caustic => 1,
            };
            m.budget.total() as u64 * per_path
        })
        .sum();
    n.min(max_photons as u64) as u32
}
