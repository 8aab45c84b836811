//! The radiance cache of final gathering (mode gather) on the device, twin of the CPU's
//! cache: after a pass's maps are built, `build_cache` (K-nearest values,
//! src/integrators/gpu/cache_build.wgsl) or `build_cache_fixed` (fixed radius, src/integrators/gpu/cache_fixed.wgsl)
//! writes one value per global photon slot, parallel to the global map's sorted photons (the cache
//! points are the photons `plan::CACHE_STRIDE` picks; the others hold zero), and the gather
//! looks it up through the global map's grid. No other mode allocates or dispatches it.

use crate::error::{Error, Result};
use crate::integrators::gpu::buffers::{cache_buffers, CACHE_ENTRY_BYTES};
use crate::integrators::gpu::codes::CACHE_LIST_FIRST;
use crate::integrators::gpu::maps::MapBuffers;
use crate::integrators::gpu::recorder::Recorder;
use crate::integrators::gpu::run::GpuRun;

impl GpuRun {
    /// Grows the cache buffer to hold one entry per slot of `global` (kept across passes).
    pub fn ensure_cache(&mut self, global: &MapBuffers) {
        let slots = global.params.capacity;
        if self.cache[0].size() < slots as u64 * CACHE_ENTRY_BYTES {
            self.cache = cache_buffers(&self.ctx.device, slots);
        }
    }

    /// Records building the radiance cache of the global map (`maps`' global slot) into
    /// `enc`: lists the cache points (one invocation per stored photon, the grid's indirect
    /// dispatch), sizes the build's
    /// dispatch from their count, then computes their values (K-nearest: one workgroup per
    /// point; a fixed radius, the current parameters' `k == 0`: one invocation per point);
    /// nothing is read back; one compute pass per kernel, so that a `bench` recording times
    /// each. The other maps and `accum` complete the gather group, untouched.
    pub fn record_cache(
        &mut self,
        rec: &mut Recorder,
        maps: [&MapBuffers; 2],
        accum: &wgpu::Buffer,
    ) -> Result<()> {
        let global = maps[crate::integrators::plan::MapKind::Global as usize];
        self.ensure_cache(global);
        let Some(pipelines) = &self.pipelines.radiance_cache else {
            return Err(Error::Gpu(
                "the radiance cache's pipeline was not created (a render not in mode gather)"
                    .into(),
            ));
        };
        let bg = self.gather_bind_group(maps, accum);
        // The values' dispatch and the count of cache points.
        rec.enc()
            .clear_buffer(&self.cache[1], 0, Some(4 * CACHE_LIST_FIRST as u64));
        // size_cache_build makes the same choice on the device (from the same k).
        let (build_name, build) = if self.params.k == 0 {
            ("build_cache_fixed", &pipelines.fixed)
        } else {
            let knn = pipelines.knn.as_ref().ok_or_else(|| {
                Error::Gpu("a K-nearest radiance cache on pipelines built for fixed radii".into())
            })?;
            ("build_cache", knn)
        };
        let groups = &self.scene_buffers.bind_group;
        // One kernel's compute pass (indirect arguments, or one invocation), then its stamp.
        let dispatch = |rec: &mut Recorder, name, pipeline, indirect: Option<&wgpu::Buffer>| {
            {
                let mut cp = rec.enc().begin_compute_pass(&wgpu::ComputePassDescriptor {
                    label: Some(name),
                    timestamp_writes: None,
                });
                cp.set_bind_group(0, groups, &[0]);
                cp.set_bind_group(1, &bg, &[]);
                cp.set_pipeline(pipeline);
                match indirect {
                    Some(args) => cp.dispatch_workgroups_indirect(args, 0),
                    None => cp.dispatch_workgroups(1, 1, 1),
                }
            }
            rec.kernel(name);
        };
        dispatch(
            rec,
            "list_cache_points",
            &pipelines.list,
            Some(&global.dispatch),
        );
        dispatch(rec, "size_cache_build", &pipelines.size, None);
        rec.enc()
            .copy_buffer_to_buffer(&self.cache[1], 0, &self.cache[2], 0, 12);
        dispatch(rec, build_name, build, Some(&self.cache[2]));
        Ok(())
    }
}
