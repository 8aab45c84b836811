//! The hash grid's sizing and counting sort; its cell functions (twin:
//! src/integrators/gpu/grid.wgsl) are `crate::integrators::estimate`'s, which the CPU's density tables share.

pub use crate::integrators::estimate::{cell_hash, cell_of};

/// Table size: the power of two at or above `expected` photons (load factor <= 1), at least
/// 256 (one scan block) and within one storage binding.
pub fn table_size_for(expected: u32, max_binding: u64) -> u32 {
    let cap = ((max_binding / 4).saturating_sub(1) as u32).max(256);
    let cap = 1u32 << (31 - cap.leading_zeros());
    expected
        .max(256)
        .checked_next_power_of_two()
        .unwrap_or(cap)
        .min(cap)
}

/// Cell size: the expected distance to the K-th photon if `expected` photons covered
/// `area * concentration` uniformly (rings 0..=2 then usually hold the K nearest, and the
/// radiance cache's lookup scans few photons per cell; twice that measured slower on
/// lavapipe), kept within [radius / MAX_RINGS, radius] so a search visits at most
/// (2 MAX_RINGS + 1)^3 cells (`codes::MAX_CELLS`, the bound of the WGSL search). Fixed-radius estimates (`k == 0`)
/// use cells of the radius.
pub fn cell_size_for(radius: f32, k: u32, expected: u32, area: f32, concentration: f32) -> f32 {
    if k == 0 {
        return radius;
    }
    let density = expected.max(1) as f32 / (area * concentration).max(1e-30);
    let r_k = (k as f32 / (std::f32::consts::PI * density)).sqrt();
    if r_k.is_finite() {
        r_k.clamp(
            radius / crate::integrators::gpu::codes::MAX_RINGS as f32,
            radius,
        )
    } else {
        radius
    }
}

/// The CPU counting sort the device grid build must equal: `(cell_start, sorted ids)` with
/// photons in each cell listed by their position in `keys` (the device's order within a cell
/// is unspecified, so tests compare cells as sets).
pub fn counting_sort(keys: &[u32], table_size: u32) -> (Vec<u32>, Vec<u32>) {
    let mut start = vec![0u32; table_size as usize + 1];
    for &h in keys {
        start[h as usize + 1] += 1;
    }
    for i in 0..table_size as usize {
        start[i + 1] += start[i];
    }
    let mut fill = start.clone();
    let mut order = vec![0u32; keys.len()];
    for (i, &h) in keys.iter().enumerate() {
        order[fill[h as usize] as usize] = i as u32;
        fill[h as usize] += 1;
    }
    (start, order)
}
