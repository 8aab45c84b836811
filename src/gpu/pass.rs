//! One pass on the device: photon maps in batches (as many as one storage binding per map
//! requires), the radiance cache in mode gather, then every camera sample gathered into the
//! accumulator in one submission.

use super::buffers::{read_back, wait};
use super::codes::{GATHER_TILE, STATS_LEN};
use super::host::{batch_pass, batch_settings, MAX_BATCHES, PARAMS_STRIDE};
use super::maps::MapBuffers;
use super::run::GpuRun;
use super::types::GpuParams;
use crate::error::Result;
use crate::film::Image;
use crate::plan::caustic_weight;
use crate::report::{Progress, RenderReport};
use crate::scene::Scene;
use crate::settings::RenderSettings;
use std::time::Instant;

/// Photons the map's kernels stored (the reports' counts).
fn report_count(r: &RenderReport, m: &MapBuffers) -> usize {
    if m.params.is_caustic != 0 {
        r.caustic_stored
    } else {
        r.global_stored
    }
}

impl GpuRun {
    /// One pass: photon maps (in batches when one storage binding cannot hold them), then
    /// every camera sample gathered into `accum`; returns the pass's image.
    ///
    /// Batch b traces paths of its own (RNG pass `batch_pass(pass, b)`), builds its grid and
    /// gathers every camera sample; the image is the mean of the batches. The batch count
    /// grows until no map overflows (decided by the first batch, so it is deterministic).
    pub fn render_pass(
        &mut self,
        scene: &Scene,
        s: &RenderSettings,
        pass: u32,
        accum: &wgpu::Buffer,
        progress: &Progress,
        report: &mut RenderReport,
    ) -> Result<Image> {
        let accum_bytes = accum.size();
        let phases_before = report.phases.len();
        let mut batches = 1u32;
        'attempt: loop {
            self.ctx
                .queue
                .write_buffer(accum, 0, &vec![0u8; accum_bytes as usize]);
            for b in 0..batches {
                let sb = batch_settings(s, b, batches);
                self.configure_pass(scene, &sb, batch_pass(pass, b));
                let (global, caustic) = self.trace_maps(scene, &sb, report)?;
                let overflow = [&global, &caustic]
                    .iter()
                    .map(|m| report_count(report, m).div_ceil(m.params.capacity.max(1) as usize))
                    .max()
                    .unwrap_or(1);
                if overflow > 1 && b == 0 && batches < MAX_BATCHES {
                    batches = (batches * overflow as u32 + batches / 4 + 1).min(MAX_BATCHES);
                    report.phases.truncate(phases_before);
                    self.ctx.queue.write_buffer(
                        &self.scene_buffers.stats,
                        0,
                        &[0u8; STATS_LEN * 4],
                    );
                    continue 'attempt;
                }
                if self.plan_final_gather() && global.params.paths > 0 {
                    let t = Instant::now();
                    let stored = report.global_stored as u32;
                    self.build_cache(&global, stored, &caustic, accum)?;
                    report.phase("build cache", t);
                }
                let t = Instant::now();
                self.gather(s, &global, &caustic, accum, progress)?;
                report.phase("gather", t);
                self.map_cache.push(global);
                self.map_cache.push(caustic);
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
        crate::plan::Terms::of(self.plan.mode).final_gather
    }

    /// Gathers every camera sample of `s` over the two maps into `accum`: each sample's
    /// parameters in its slot, then all the sample layers in one submission, waited for.
    fn gather(
        &self,
        s: &RenderSettings,
        global: &MapBuffers,
        caustic: &MapBuffers,
        accum: &wgpu::Buffer,
        progress: &Progress,
    ) -> Result<()> {
        let ctx = &self.ctx;
        let gather_bg = self.gather_bind_group(global, caustic, accum);
        let bar = progress.bar(s.spp as u64, "gather");
        let (wx, wy) = (
            s.width.div_ceil(GATHER_TILE),
            s.height.div_ceil(GATHER_TILE),
        );
        let mut slots = vec![0u8; (PARAMS_STRIDE * s.spp as u64) as usize];
        for sample in 0..s.spp {
            let p = GpuParams {
                sample,
                caustic_weight: caustic_weight(s.spp, s.caustic_every, sample),
                ..self.params
            };
            let at = (PARAMS_STRIDE * sample as u64) as usize;
            slots[at..at + std::mem::size_of::<GpuParams>()]
                .copy_from_slice(bytemuck::bytes_of(&p));
        }
        ctx.queue
            .write_buffer(&self.scene_buffers.params, 0, &slots);
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("gather"),
            });
        {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("gather"),
                timestamp_writes: None,
            });
            cp.set_pipeline(&self.pipelines.gather);
            cp.set_bind_group(1, &gather_bg, &[]);
            for sample in 0..s.spp {
                let offset = (PARAMS_STRIDE * sample as u64) as u32;
                cp.set_bind_group(0, &self.scene_buffers.bind_group, &[offset]);
                cp.dispatch_workgroups(wx, wy, 1);
            }
        }
        ctx.queue.submit([enc.finish()]);
        wait(ctx)?;
        bar.inc(s.spp as u64);
        bar.finish_and_clear();
        Ok(())
    }
}
