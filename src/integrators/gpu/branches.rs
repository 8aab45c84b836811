//! The camera paths' deferred glass branches (src/integrators/gpu/glass_branches.wgsl): below
//! `GLASS_SPLIT_DEPTH` a glass hit traces its heavier branch on and leaves the other on its
//! pixel's stack, and rounds (`gather` again, `Params.branch_round`) after each sample's first `gather` dispatch pop
//! and trace them, one per pixel and round, each in an invocation (so a loop budget) of its
//! own. A queue lists the pixels each dispatch left a branch to, so a round's invocations are
//! those pixels only. A stack holds one band of image rows; a render whose stacks exceed one storage
//! binding gathers in bands of rows.

use crate::bsdfs::shading::GLASS_SPLIT_DEPTH;
use bytemuck::{Pod, Zeroable};

/// Twin of WGSL `Branch`: a glass branch waiting its turn on its pixel's stack.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBranch {
    /// Where it starts (offset off the surface).
    pub o: [f32; 3],
    /// Its camera path depth.
    pub depth: u32,
    /// Its direction.
    pub d: [f32; 3],
    /// The medium it travels in.
    pub medium: u32,
    /// Its throughput (the Fresnel weight included).
    pub t: [f32; 3],
    /// Padding to 16 bytes.
    pub _pad: u32,
}

/// Twin of WGSL `BranchStack`: one pixel's pending branches and what its sample's next path
/// resumes with.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBranchStack {
    /// Branches pending (`b[..n]`, the last popped first).
    pub n: u32,
    /// The camera RNG's next dimension, with [`SOBOL_UNUSED`] set while the sample's Sobol
    /// point is unused.
    pub resume: u32,
    /// Entry `i` (this stack's index) of the branch queue's two lists of pixels.
    pub queue: [u32; 2],
    /// The pending branches.
    pub b: [GpuBranch; GLASS_SPLIT_DEPTH as usize],
}

/// The bit of [`GpuBranchStack::resume`] set while the sample's Sobol point is unused (an
/// RNG dimension never reaches it).
pub const SOBOL_UNUSED: u32 = 1 << 31;

/// Rounds of glass branches per sample: a camera path splits at most once at each depth
/// below `GLASS_SPLIT_DEPTH`, so a sample has at most 2^GLASS_SPLIT_DEPTH - 1 branches.
pub const ROUNDS: u32 = (1 << GLASS_SPLIT_DEPTH) - 1;

/// Bytes of one pixel's stack.
pub const STACK_BYTES: u64 = std::mem::size_of::<GpuBranchStack>() as u64;

/// Counts of the branch queue (src/integrators/gpu/glass_branches.wgsl): one per dispatch of a sample,
/// the gather and its `ROUNDS` rounds.
pub const BRANCH_LISTS: u32 = ROUNDS + 1;

/// Bytes before the stacks in their binding (WGSL `BranchStacks`): the queue's counts,
/// rounded up to the stacks' 16-byte alignment.
pub const STACKS_HEAD_BYTES: u64 = (4 * BRANCH_LISTS as u64).div_ceil(16) * 16;

/// Image rows per band of the gather: all `height` rows where `width x height` stacks fit in
/// `max_binding` bytes, else the most whole `tile`-row groups that do (at least one group).
pub fn band_rows(width: u32, height: u32, tile: u32, max_binding: u64) -> u32 {
    let row = width.max(1) as u64 * STACK_BYTES;
    let fit = (max_binding.saturating_sub(STACKS_HEAD_BYTES) / row).min(u32::MAX as u64) as u32;
    if fit >= height {
        return height.max(1);
    }
    (fit / tile * tile).max(tile)
}

/// Bytes of the stacks' binding for `pixels` stacks: the queue's counts, then the stacks.
pub fn stacks_bytes(pixels: u64) -> u64 {
    STACKS_HEAD_BYTES + pixels.max(1) * STACK_BYTES
}

/// The stacks' buffer (zeroed, so every queue count starts at 0) for bands of `rows` rows of
/// `width` pixels (`split`), or a one-stack stand-in for pipelines without `GLASS_SPLIT`
/// (bound, never read).
pub fn stack_buffer(device: &wgpu::Device, width: u32, rows: u32, split: bool) -> wgpu::Buffer {
    let stacks = if split { width as u64 * rows as u64 } else { 1 };
    device.create_buffer(&wgpu::BufferDescriptor {
        label: Some("glass branch stacks"),
        size: stacks_bytes(stacks),
        usage: wgpu::BufferUsages::STORAGE,
        mapped_at_creation: false,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_fit_one_binding_in_whole_tiles() {
        assert_eq!(STACK_BYTES, 160);
        assert_eq!(ROUNDS, 7);
        // 64x64: one band.
        assert_eq!(band_rows(64, 64, 8, 128 << 20), 64);
        // 1920x1080 at lavapipe's 128 MiB: 436 rows fit, 432 in whole 8-row tiles.
        let rows = band_rows(1920, 1080, 8, 128 << 20);
        assert_eq!(rows, 432);
        assert!(stacks_bytes(1920 * rows as u64) <= 128 << 20);
        // The queue's counts come first: a binding of exactly 64 rows of stacks holds 63.
        assert_eq!(band_rows(64, 64, 8, 64 * 64 * STACK_BYTES), 56);
        assert_eq!(band_rows(64, 64, 8, stacks_bytes(64 * 64)), 64);
        // A binding smaller than one tile of rows still gets one tile.
        assert_eq!(band_rows(1920, 1080, 8, 1 << 20), 8);
    }
}
