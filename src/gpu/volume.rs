//! The volume photons on the device (participating media, issue 24): one buffer that every
//! photon map's paths append the photons they leave in media to (`store_volume_photon` in
//! shaders/trace_photons.wgsl), with its count, bound in every map's group 1. A scene
//! without a volume map binds a one-photon placeholder that nothing writes.

use super::buffers::empty_buffer;
use super::context::GpuContext;
use crate::photon::Photon;
use crate::plan::{MapKind, MapPlan};

/// Counters of the volume photons (`volume_count`): `[0]` the photons stored (may pass the
/// capacity; the excess is dropped), the rest reserved for the volume grid's build.
pub const VOLUME_COUNTERS: u64 = 8;

/// The volume photons' buffer and count.
pub struct VolumeBuffers {
    /// Photons the buffer holds.
    pub capacity: u32,
    /// `capacity` photons (`volume`).
    pub photons: wgpu::Buffer,
    /// `volume_count`.
    pub count: wgpu::Buffer,
}

impl VolumeBuffers {
    /// A buffer of `capacity` (at least one) volume photons and its counters.
    pub fn new(ctx: &GpuContext, capacity: u32) -> Self {
        let capacity = capacity.max(1);
        let rw = wgpu::BufferUsages::STORAGE
            | wgpu::BufferUsages::COPY_DST
            | wgpu::BufferUsages::COPY_SRC;
        let bytes = capacity as u64 * std::mem::size_of::<Photon>() as u64;
        VolumeBuffers {
            capacity,
            photons: empty_buffer(&ctx.device, "volume photons", bytes, rw),
            count: empty_buffer(&ctx.device, "volume counters", 4 * VOLUME_COUNTERS, rw),
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
