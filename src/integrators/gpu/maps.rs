//! One photon map on the device: its buffers, its group-1 bind group, and the recording of
//! its tracing and hash-grid build (count, scan, offsets, scatter) into the caller's encoder.

use crate::integrators::gpu::bindings::{bind_group, Layouts, MAP_GROUP};
use crate::integrators::gpu::buffers::{empty_buffer, grid_2d};
use crate::integrators::gpu::codes::{COUNTER_MAX_POWER, SCAN_BLOCK, SCAN_ITEMS};
use crate::integrators::gpu::context::GpuContext;
use crate::integrators::gpu::pipelines::Pipelines;
use crate::integrators::gpu::recorder::Recorder;
use crate::integrators::gpu::types::GpuMapParams;
use crate::integrators::photon::Photon;
use wgpu::util::DeviceExt;

/// Parameters of an absent map (`paths == 0`: the gather skips it).
pub const EMPTY_MAP: GpuMapParams = GpuMapParams {
    stream: 0,
    paths: 0,
    capacity: 1,
    table_size: SCAN_BLOCK,
    cell_size: 1.0,
    is_caustic: 0,
    drop_flags: 0,
    radius2: 0.0,
    k: 0,
    storing_area: 0.0,
    max_power: 0.0,
    volume_flags: 0,
};

/// Map parameters of `n` uploaded photons (a probe's map: nothing traced, nothing dropped,
/// cells of `cell_size`: `size_grid` is not run).
pub fn probe_map_params(n: u32, cell_size: f32, table_size: u32, radius2: f32) -> GpuMapParams {
    GpuMapParams {
        stream: 0,
        paths: n.max(1),
        capacity: n.max(1),
        table_size,
        cell_size,
        is_caustic: 0,
        drop_flags: 0,
        radius2,
        k: 0,
        storing_area: 0.0,
        max_power: 0.0,
        volume_flags: 0,
    }
}

/// One photon map on the device: the traced photons, the hash grid and its parameters.
pub struct MapBuffers {
    /// The parameters last written to `params_buf`.
    pub params: GpuMapParams,
    /// Photons in the order tracing stored them (`photons`).
    pub photons: wgpu::Buffer,
    /// `counters[0]`: photons stored (may pass the capacity; the excess is dropped);
    /// `counters[1..4]`: the per-photon grid kernels' dispatch, written by `size_grid`;
    /// `counters[COUNTER_MAX_POWER]`: the largest photon power channel in the grid.
    pub counters: wgpu::Buffer,
    /// The per-photon grid kernels' indirect dispatch, copied from `counters[1..4]` (a
    /// buffer bound read-write cannot also be a dispatch's indirect arguments).
    pub dispatch: wgpu::Buffer,
    /// Photons per grid cell (`cell_count`).
    pub cell_count: wgpu::Buffer,
    /// First sorted photon of each cell, and the total at `table_size` (`cell_start`).
    pub cell_start: wgpu::Buffer,
    /// Photons sorted by cell (`sorted`).
    pub sorted: wgpu::Buffer,
    /// The scan's per-block sums (`block_sums`).
    pub block_sums: wgpu::Buffer,
    /// `params` on the device (`map_params`).
    pub params_buf: wgpu::Buffer,
    /// The map-building kernels' group 1 over these buffers.
    pub bind_group: wgpu::BindGroup,
}

impl MapBuffers {
    /// Allocates a map of `params.capacity` photons and `params.table_size` cells, its paths
    /// storing volume photons into `volume` (`volume`, `volume_count`, `volume_grid`: see
    /// `gpu::volume`).
    pub fn new(
        ctx: &GpuContext,
        layouts: &Layouts,
        label: &str,
        params: GpuMapParams,
        volume: [&wgpu::Buffer; 3],
    ) -> Self {
        let photon_bytes = params.capacity as u64 * std::mem::size_of::<Photon>() as u64;
        Self::sized(ctx, layouts, label, params, volume, photon_bytes)
    }

    /// [`Self::new`] with a `sorted` buffer of `sorted_bytes` (the volume grid lists its
    /// (photon, cell) entries there).
    pub fn sized(
        ctx: &GpuContext,
        layouts: &Layouts,
        label: &str,
        params: GpuMapParams,
        volume: [&wgpu::Buffer; 3],
        sorted_bytes: u64,
    ) -> Self {
        let dev = &ctx.device;
        let rw = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC;
        let photon_bytes = params.capacity as u64 * std::mem::size_of::<Photon>() as u64;
        let t = params.table_size as u64;
        let photons = empty_buffer(dev, &format!("{label} photons"), photon_bytes, rw);
        let counters = empty_buffer(
            dev,
            &format!("{label} counters"),
            4 * (COUNTER_MAX_POWER as u64 + 1),
            rw,
        );
        let indirect = wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST;
        let dispatch = empty_buffer(dev, &format!("{label} grid dispatch"), 12, indirect);
        let cell_count = empty_buffer(dev, &format!("{label} cell counts"), 4 * t, rw);
        let cell_start = empty_buffer(dev, &format!("{label} cell starts"), 4 * (t + 1), rw);
        let sorted = empty_buffer(dev, &format!("{label} sorted photons"), sorted_bytes, rw);
        let blocks = t.div_ceil((SCAN_BLOCK * SCAN_ITEMS) as u64);
        let block_sums = empty_buffer(dev, &format!("{label} block sums"), 4 * blocks, rw);
        let params_buf = dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some(&format!("{label} map params")),
            contents: bytemuck::bytes_of(&params),
            // COPY_SRC: tests read the cell size the device chose.
            usage: rw,
        });
        let bind_group = bind_group(
            dev,
            &format!("{label} map bind group"),
            &layouts.map,
            &MAP_GROUP,
            vec![
                ("photons", photons.as_entire_binding()),
                ("counters", counters.as_entire_binding()),
                ("cell_count", cell_count.as_entire_binding()),
                ("cell_start", cell_start.as_entire_binding()),
                ("sorted", sorted.as_entire_binding()),
                ("block_sums", block_sums.as_entire_binding()),
                ("map_params", params_buf.as_entire_binding()),
                ("volume", volume[0].as_entire_binding()),
                ("volume_count", volume[1].as_entire_binding()),
                ("volume_grid", volume[2].as_entire_binding()),
            ],
        );
        MapBuffers {
            params,
            photons,
            counters,
            dispatch,
            cell_count,
            cell_start,
            sorted,
            block_sums,
            params_buf,
            bind_group,
        }
    }

    /// Rewrites the map's parameters on the device.
    pub fn set_params(&mut self, ctx: &GpuContext, p: GpuMapParams) {
        ctx.queue
            .write_buffer(&self.params_buf, 0, bytemuck::bytes_of(&p));
        self.params = p;
    }

    /// A compute pass `label` in `enc` with the scene (sample slot 0) and this map bound.
    pub fn begin<'e>(
        &self,
        enc: &'e mut wgpu::CommandEncoder,
        label: &str,
        scene_bg: &wgpu::BindGroup,
    ) -> wgpu::ComputePass<'e> {
        let mut pass = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some(label),
            timestamp_writes: None,
        });
        pass.set_bind_group(0, scene_bg, &[0]);
        pass.set_bind_group(1, &self.bind_group, &[]);
        pass
    }

    /// Records tracing this map's photons into `rec`.
    pub fn record_trace(&self, rec: &mut Recorder, p: &Pipelines, scene_bg: &wgpu::BindGroup) {
        let enc = rec.enc();
        enc.clear_buffer(&self.counters, 0, None);
        {
            let mut pass = self.begin(enc, "trace photons", scene_bg);
            pass.set_pipeline(&p.trace_photons);
            let (x, y) = grid_2d(self.params.paths.div_ceil(p.shape.wg_size));
            pass.dispatch_workgroups(x, y, 1);
        }
        rec.kernel("trace_photons");
    }

    /// Records building this map's grid over the photons the trace stored into `rec`, sized
    /// on the device (`size_grid`): nothing is read back. One compute pass per kernel, so
    /// that a `bench` recording times each.
    pub fn record_grid(&self, rec: &mut Recorder, p: &Pipelines, scene_bg: &wgpu::BindGroup) {
        rec.enc().clear_buffer(&self.cell_count, 0, None);
        {
            let mut pass = self.begin(rec.enc(), "size grid", scene_bg);
            pass.set_pipeline(&p.size_grid);
            pass.dispatch_workgroups(1, 1, 1);
        }
        rec.kernel("size_grid");
        rec.enc()
            .copy_buffer_to_buffer(&self.counters, 4, &self.dispatch, 0, 12);
        let t = self.params.table_size;
        // (kernel, pipeline, invocations and workgroup width; None: one per stored photon)
        let stages = [
            ("count_cells", &p.count_cells, None),
            (
                "scan_blocks",
                &p.scan_blocks,
                Some((t.div_ceil(SCAN_ITEMS), SCAN_BLOCK)),
            ),
            ("scan_sums", &p.scan_sums, Some((SCAN_BLOCK, SCAN_BLOCK))),
            ("add_offsets", &p.add_offsets, Some((t, p.shape.wg_size))),
            ("scatter", &p.scatter, None),
            ("scatter_rest", &p.scatter_rest, None),
        ];
        for (name, pipeline, size) in stages {
            {
                let mut pass = self.begin(rec.enc(), name, scene_bg);
                pass.set_pipeline(pipeline);
                match size {
                    Some((n, wg)) => {
                        let (x, y) = grid_2d(n.div_ceil(wg));
                        pass.dispatch_workgroups(x, y, 1);
                    }
                    None => pass.dispatch_workgroups_indirect(&self.dispatch, 0),
                }
            }
            rec.kernel(name);
        }
    }
}
