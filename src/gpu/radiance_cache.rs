//! The radiance cache of final gathering (mode gather) on the device, twin of the CPU's
//! cache: after a pass's maps are built, `build_cache` (shaders/radiance_cache.wgsl) writes
//! one value per global photon slot, parallel to the global map's sorted photons (the cache
//! points are the photons `plan::CACHE_STRIDE` picks; the others hold zero), and the gather
//! looks it up through the global map's grid. No other mode allocates or dispatches it.

use super::buffers::{cache_buffers, CACHE_ENTRY_BYTES};
use super::codes::CACHE_LIST_FIRST;
use super::maps::MapBuffers;
use super::run::GpuRun;
use crate::error::{Error, Result};

impl GpuRun {
    /// Grows the cache buffer to hold one entry per slot of `global` (kept across passes).
    pub fn ensure_cache(&mut self, global: &MapBuffers) {
        let slots = global.params.capacity;
        if self.cache[0].size() < slots as u64 * CACHE_ENTRY_BYTES {
            self.cache = cache_buffers(&self.ctx.device, slots);
        }
    }

    /// Records building the radiance cache of `global` into `enc`: lists the cache points
    /// (one invocation per stored photon, the grid's indirect dispatch), sizes the build's
    /// dispatch from their count, then computes their values, one workgroup each; nothing is
    /// read back. `caustic` and `accum` complete the gather group, untouched.
    pub fn record_cache(
        &mut self,
        enc: &mut wgpu::CommandEncoder,
        global: &MapBuffers,
        caustic: &MapBuffers,
        accum: &wgpu::Buffer,
    ) -> Result<()> {
        self.ensure_cache(global);
        let Some(pipelines) = &self.pipelines.radiance_cache else {
            return Err(Error::Gpu(
                "the radiance cache's pipeline was not created (a render not in mode gather)"
                    .into(),
            ));
        };
        let bg = self.gather_bind_group(global, caustic, accum);
        // build_cache's dispatch and the count of cache points.
        enc.clear_buffer(&self.cache[1], 0, Some(4 * CACHE_LIST_FIRST as u64));
        let [list, size, build] = pipelines;
        {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("radiance cache points"),
                timestamp_writes: None,
            });
            cp.set_bind_group(0, &self.scene_buffers.bind_group, &[0]);
            cp.set_bind_group(1, &bg, &[]);
            cp.set_pipeline(list);
            cp.dispatch_workgroups_indirect(&global.dispatch, 0);
            cp.set_pipeline(size);
            cp.dispatch_workgroups(1, 1, 1);
        }
        enc.copy_buffer_to_buffer(&self.cache[1], 0, &self.cache[2], 0, 12);
        {
            let mut cp = enc.begin_compute_pass(&wgpu::ComputePassDescriptor {
                label: Some("radiance cache values"),
                timestamp_writes: None,
            });
            cp.set_bind_group(0, &self.scene_buffers.bind_group, &[0]);
            cp.set_bind_group(1, &bg, &[]);
            cp.set_pipeline(build);
            cp.dispatch_workgroups_indirect(&self.cache[2], 0);
        }
        Ok(())
    }
}
