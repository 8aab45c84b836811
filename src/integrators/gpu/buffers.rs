//! Device buffer helpers: created with a label, initialised or zero-sized safely, and read
//! back to the host; and the split of a workgroup count over the 2D dispatch grid.

use crate::error::{Error, Result};
use crate::integrators::gpu::context::GpuContext;
use bytemuck::Pod;
use wgpu::util::DeviceExt;

/// A storage buffer holding `data` (256 zero bytes when `data` is empty: bindings may not be
/// empty), with usages `extra` besides STORAGE.
pub fn storage_buffer<T: Pod>(
    dev: &wgpu::Device,
    label: &str,
    data: &[T],
    extra: wgpu::BufferUsages,
) -> wgpu::Buffer {
    let mut bytes = bytemuck::cast_slice::<T, u8>(data).to_vec();
    if bytes.is_empty() {
        bytes.resize(256, 0); // one zeroed element of any struct
    }
    dev.create_buffer_init(&wgpu::util::BufferInitDescriptor {
        label: Some(label),
        contents: &bytes,
        usage: wgpu::BufferUsages::STORAGE | extra,
    })
}

/// An uninitialised buffer of at least 64 bytes.
pub fn empty_buffer(
    dev: &wgpu::Device,
    label: &str,
    size: u64,
    usage: wgpu::BufferUsages,
) -> wgpu::Buffer {
    dev.create_buffer(&wgpu::BufferDescriptor {
        label: Some(label),
        size: size.max(64),
        usage,
        mapped_at_creation: false,
    })
}

/// Waits until the device has finished all submitted work, at most the watchdog's time
/// (`faults::watchdog`), then fails with any error the device reported meanwhile.
pub fn wait(ctx: &GpuContext) -> Result<()> {
    let limit = crate::integrators::gpu::faults::watchdog();
    let polled = ctx.device.poll(wgpu::PollType::Wait {
        submission_index: None,
        timeout: Some(limit),
    });
    ctx.check()?;
    match polled {
        Ok(_) => Ok(()),
        Err(wgpu::PollError::Timeout) => Err(Error::Gpu(format!(
            "the device did not finish its work within {:.0} s (the watchdog; GPU_PHOTON_WATCHDOG sets it): hung, or a pass far too large for it",
            limit.as_secs_f64()
        ))),
        Err(e) => Err(Error::Gpu(format!("waiting for the device: {e}"))),
    }
}

/// Reads the first `bytes` of a buffer back to the host.
pub fn read_back<T: Pod>(ctx: &GpuContext, src: &wgpu::Buffer, bytes: u64) -> Result<Vec<T>> {
    let dev = &ctx.device;
    let staging = empty_buffer(
        dev,
        "readback",
        bytes,
        wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
    );
    let mut enc = dev.create_command_encoder(&wgpu::CommandEncoderDescriptor {
        label: Some("readback"),
    });
    enc.copy_buffer_to_buffer(src, 0, &staging, 0, bytes);
    ctx.queue.submit([enc.finish()]);
    staging.map_async(wgpu::MapMode::Read, .., |_| {});
    wait(ctx)?;
    ctx.check()?;
    let data = {
        let view = staging
            .get_mapped_range(..bytes)
            .map_err(|e| Error::Gpu(format!("mapping the read-back buffer: {e:?}")))?;
        bytemuck::cast_slice(&view).to_vec()
    };
    staging.unmap();
    staging.destroy();
    Ok(data)
}

/// Splits a workgroup count over x and y so that x stays within the 65,535 limit.
pub fn grid_2d(groups: u32) -> (u32, u32) {
    let groups = groups.max(1);
    let x = groups.min(65_535);
    (x, groups.div_ceil(x))
}

/// Bytes of one radiance-cache entry (`vec4<f32>`: the value, and 1 at a cache point).
pub const CACHE_ENTRY_BYTES: u64 = 16;

/// The radiance cache's buffers for `slots` global photon slots: the cache (16 bytes a slot),
/// its point list (the values' dispatch, a count and 4 bytes a slot: layout in
/// src/integrators/gpu/cache_build.wgsl), read-write storage copyable for probes; and the indirect
/// arguments of `build_cache` or `build_cache_fixed`, copied from the list's head (a buffer
/// bound read-write in a dispatch cannot be that dispatch's indirect arguments).
pub fn cache_buffers(dev: &wgpu::Device, slots: u32) -> [wgpu::Buffer; 3] {
    let usage =
        wgpu::BufferUsages::STORAGE | wgpu::BufferUsages::COPY_SRC | wgpu::BufferUsages::COPY_DST;
    let slots = slots as u64;
    let head = crate::integrators::gpu::codes::CACHE_LIST_FIRST as u64;
    [
        empty_buffer(dev, "radiance cache", slots * CACHE_ENTRY_BYTES, usage),
        empty_buffer(dev, "radiance cache points", 4 * (slots + head), usage),
        empty_buffer(
            dev,
            "radiance cache dispatch",
            16,
            wgpu::BufferUsages::INDIRECT | wgpu::BufferUsages::COPY_DST,
        ),
    ]
}
