//! The radiance cache of final gathering (mode gather) on the device, twin of the CPU's
//! cache: after a pass's maps are built, `build_cache` (shaders/radiance_cache.wgsl) writes
//! one value per global photon slot, parallel to the global map's sorted photons (the cache
//! points are the photons `plan::CACHE_STRIDE` picks; the others hold zero), and the gather
//! looks it up through the global map's grid. No other mode allocates or dispatches it.

use super::buffers::{grid_2d, wait};
use super::codes::WG_SIZE;
use super::maps::MapBuffers;
use super::run::{cache_buffer, GpuRun};
use crate::error::{Error, Result};

/// Bytes of one cache entry (`vec4<f32>`: the value and 1 at a cache point).
pub const CACHE_ENTRY_BYTES: u64 = 16;

impl GpuRun {
    /// Grows the cache buffer to hold one entry per slot of `global` (kept across passes).
    pub fn ensure_cache(&mut self, global: &MapBuffers) {
        let bytes = global.params.capacity as u64 * CACHE_ENTRY_BYTES;
        if self.cache.size() < bytes {
            self.cache = cache_buffer(&self.ctx.device, bytes);
        }
    }

    /// Builds the radiance cache of `global` on the device (one submission, waited for);
    /// `caustic` and `accum` complete the gather group and are not touched.
    pub fn build_cache(
        &mut self,
        global: &MapBuffers,
        caustic: &MapBuffers,
        accum: &wgpu::Buffer,
    ) -> Result<()> {
        self.ensure_cache(global);
        let Some(pipeline) = &self.pipelines.build_cache else {
            return Err(Error::Gpu(
                "the radiance cache's pipeline was not created (a render not in mode gather)"
                    .into(),
            ));
        };
        let ctx = &self.ctx;
        let bg = self.gather_bind_group(global, caustic, accum);
        let mut enc = ctx
            .device
            .create_command_encoder(&wgpu::CommandEncoderDescriptor {
                label: Some("radiance cache"),
            });
        {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("radiance cache"),
                timestamp_writes: None,
            });
            cp.set_pipeline(pipeline);
            cp.set_bind_group(0, &self.scene_buffers.bind_group, &[0]);
            cp.set_bind_group(1, &bg, &[]);
            let (x, y) = grid_2d(global.params.capacity.div_ceil(WG_SIZE));
            cp.dispatch_workgroups(x, y, 1);
        }
        ctx.queue.submit([enc.finish()]);
        wait(ctx)?;
        ctx.check()
    }
}
