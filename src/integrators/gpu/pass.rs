//! One pass on the device: photon maps in batches (as many as one storage binding per map
//! requires), the radiance cache in mode gather, then every camera sample gathered into the
//! accumulator: all of a batch's stages recorded into one encoder and one submission, the
//! photon counts, the phases' device times (where the device has timestamps) and the image
//! read back once, when the pass ends.

use crate::error::Result;
use crate::integrators::gpu::branches::ROUNDS;
use crate::integrators::gpu::buffers::{empty_buffer, grid_2d, read_back, wait};
use crate::integrators::gpu::codes::STATS_LEN;
use crate::integrators::gpu::host::{batch_pass, batch_settings, MAX_BATCHES, PARAMS_STRIDE};
use crate::integrators::gpu::maps::MapBuffers;
use crate::integrators::gpu::recorder::Recorder;
use crate::integrators::gpu::run::GpuRun;
use crate::integrators::gpu::types::GpuParams;
use crate::integrators::plan::{caustic_weight, MapKind};
use crate::render::film::Image;
use crate::render::report::{Progress, RenderReport};
use crate::scene::Scene;
use crate::settings::RenderSettings;
use std::time::Instant;

impl GpuRun {
    /// One pass: photon maps (in batches when one storage binding cannot hold them), then
    /// every camera sample gathered into `accum`; returns the pass's image.
    ///
    /// Batch b traces paths of its own (RNG pass `batch_pass(pass, b)`), builds its grid and
    /// gathers every camera sample; the image is the mean of the batches. The batch count
    /// grows until no map overflows (decided by the first batch's counts, read back when the
    /// pass ends, so it is deterministic; a pass that overflowed is rendered again).
    pub fn render_pass(
        &mut self,
        scene: &Scene,
        s: &RenderSettings,
        pass: u32,
        accum: &wgpu::Buffer,
        progress: &Progress,
        report: &mut RenderReport,
    ) -> Result<Image> {
        if s.k > 0 && !self.knn {
            return Err(crate::error::Error::Gpu(
                "a K-nearest pass on pipelines built for a progressive render (fixed radii)".into(),
            ));
        }
        self.ensure_bands(scene, s)?;
        let accum_bytes = accum.size();
        let (phases_before, kernels_before) = (report.phases.len(), report.kernels.len());
        let mut batches = 1u32;
        // Photons each batch's maps stored: one count per map slot, then the volume
        // photons', per batch.
        let slots = MapKind::ALL.len();
        let per = slots + 1;
        let counts = empty_buffer(
            &self.ctx.device,
            "photon counts",
            4 * (per * MAX_BATCHES as usize) as u64,
            wgpu::BufferUsages::COPY_DST | wgpu::BufferUsages::COPY_SRC,
        );
        loop {
            let t = Instant::now();
            self.ctx
                .queue
                .write_buffer(accum, 0, &vec![0u8; accum_bytes as usize]);
            let mut capacity = vec![1u32; per];
            let mut recorders = Vec::new();
            let bar = progress.bar(batches as u64 * s.spp as u64, "gather");
            for b in 0..batches {
                let sb = batch_settings(s, b, batches);
                self.configure_pass(scene, &sb, batch_pass(pass, b));
                let mut rec = Recorder::new(self.ctx.clone(), s.timed_phases);
                let maps = self.record_maps(scene, &sb, &mut rec, report)?;
                for (i, m) in maps.iter().enumerate() {
                    let at = 4 * (per * b as usize + i) as u64;
                    rec.enc()
                        .copy_buffer_to_buffer(&m.counters, 0, &counts, at, 4);
                    if b == 0 {
                        capacity[i] = m.params.capacity.max(1);
                    }
                }
                let at = 4 * (per * b as usize + slots) as u64;
                rec.enc()
                    .copy_buffer_to_buffer(&self.volume.count, 0, &counts, at, 4);
                if b == 0 {
                    capacity[slots] = self.volume.capacity;
                }
                let global = &maps[MapKind::Global as usize];
                if self.plan_final_gather() && global.params.paths > 0 {
                    self.record_cache(&mut rec, maps.each_ref(), accum)?;
                    rec.phase("build cache", report)?;
                }
                self.record_gather(rec.enc(), s, maps.each_ref(), accum);
                rec.kernel("gather");
                rec.phase("gather", report)?;
                rec.submit();
                recorders.push(rec);
                self.map_cache.extend(maps);
            }
            wait(&self.ctx)?;
            self.ctx.check()?;
            bar.inc(batches as u64 * s.spp as u64);
            bar.finish_and_clear();
            let n: Vec<u32> = read_back(&self.ctx, &counts, 4 * (per * batches as usize) as u64)?;
            let overflow = (0..per)
                .map(|i| n[i].div_ceil(capacity[i]))
                .max()
                .unwrap_or(1);
            if overflow > 1 && batches < MAX_BATCHES {
                batches = (batches * overflow + batches / 4 + 1).min(MAX_BATCHES);
                report.phases.truncate(phases_before);
                report.kernels.truncate(kernels_before);
                let stats = &self.scene_buffers.stats;
                self.ctx.queue.write_buffer(stats, 0, &[0u8; STATS_LEN * 4]);
                continue;
            }
            let last = per * (batches as usize - 1);
            for (i, stored) in report.stored.iter_mut().enumerate() {
                *stored = n[last + i] as usize;
            }
            if self.plan.volume.is_some() {
                report.volume_stored = n[last + slots] as usize;
            }
            for rec in &recorders {
                rec.times(report)?;
            }
            if !s.timed_phases && !recorders.iter().any(Recorder::on_device) {
                report.phase("device pass", t);
            }
            break;
        }
        report.batches = report.batches.max(batches);
        let px: Vec<[f32; 4]> = read_back(&self.ctx, accum, accum_bytes)?;
        let mut image = Image::new(s.width, s.height);
        let scale = 1.0 / batches as f32;
        for (dst, src) in image.pixels.iter_mut().zip(&px) {
            *dst = [src[0] * scale, src[1] * scale, src[2] * scale];
        }
        Ok(image)
    }

    /// Whether the current plan's mode gathers through the radiance cache.
    fn plan_final_gather(&self) -> bool {
        crate::integrators::plan::Terms::of(self.plan.mode).final_gather
    }

    /// Records gathering every camera sample of `s` over the maps into `accum` in
    /// `enc`: each band's, sample's and dispatch's parameters in its slot (written before the
    /// submission), then per band of rows and sample one `gather` dispatch and, where the
    /// scene splits at glass, `branches::ROUNDS` rounds of glass branches, `gather` again with
    /// one invocation per pixel of the band (those past the pixels the queue lists return).
    fn record_gather(
        &self,
        enc: &mut wgpu::CommandEncoder,
        s: &RenderSettings,
        maps: [&MapBuffers; 2],
        accum: &wgpu::Buffer,
    ) {
        let ctx = &self.ctx;
        let gather_bg = self.gather_bind_group(maps, accum);
        let tile = ctx.shape.gather_tile;
        let rows = self.band_rows.max(1);
        let bands = s.height.div_ceil(rows).max(1);
        let (wx, wy) = (s.width.div_ceil(tile), rows.min(s.height).div_ceil(tile));
        let dispatches = if self.pipelines.glass_rounds {
            1 + ROUNDS
        } else {
            1
        };
        let mut slots = vec![0u8; (PARAMS_STRIDE * (bands * s.spp * dispatches) as u64) as usize];
        for band in 0..bands {
            for sample in 0..s.spp {
                for round in 0..dispatches {
                    let p = GpuParams {
                        sample,
                        caustic_weight: caustic_weight(s.spp, s.caustic_every, sample),
                        first_row: band * rows,
                        branch_round: round,
                        ..self.params
                    };
                    let slot = (band * s.spp + sample) * dispatches + round;
                    let at = (PARAMS_STRIDE * slot as u64) as usize;
                    slots[at..at + std::mem::size_of::<GpuParams>()]
                        .copy_from_slice(bytemuck::bytes_of(&p));
                }
            }
        }
        ctx.queue
            .write_buffer(&self.scene_buffers.params, 0, &slots);
        let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
            label: Some("gather"),
            timestamp_writes: None,
        });
        cp.set_bind_group(1, &gather_bg, &[]);
        let band_pixels = s.width * rows.min(s.height);
        let (rx, ry) = grid_2d(band_pixels.div_ceil(tile * tile));
        for slot in (0..bands * s.spp).map(|i| i * dispatches) {
            let offset = |round: u32| (PARAMS_STRIDE * (slot + round) as u64) as u32;
            cp.set_pipeline(&self.pipelines.gather);
            for round in 0..dispatches {
                cp.set_bind_group(0, &self.scene_buffers.bind_group, &[offset(round)]);
                match round {
                    0 => cp.dispatch_workgroups(wx, wy, 1),
                    _ => cp.dispatch_workgroups(rx, ry, 1),
                }
            }
        }
    }
}
