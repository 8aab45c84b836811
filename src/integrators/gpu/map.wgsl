// Group 1 of the map-building kernels (trace_photons.wgsl, build_grid.wgsl): one photon
// map's buffers and parameters, and the volume photons (table: MAP_GROUP in
// src/integrators/gpu/bindings.rs); the flat index of their WG_SIZE-wide 2D dispatches.
// Library, no entry point.

// photons (as traced) and sorted (by cell): PHOTON_WORDS words per photon (common/photon.wgsl).
@group(1) @binding(0) var<storage, read_write> photons: array<vec4<u32>>;
@group(1) @binding(1) var<storage, read_write> counters: array<atomic<u32>>;
@group(1) @binding(2) var<storage, read_write> cell_count: array<atomic<u32>>;
@group(1) @binding(3) var<storage, read_write> cell_start: array<u32>;
@group(1) @binding(4) var<storage, read_write> sorted: array<vec4<u32>>;
@group(1) @binding(5) var<storage, read_write> block_sums: array<u32>;
// Read-write: the grid build sets cell_size (size_grid, from the photons stored) and
// max_power (scan_sums) on the device.
@group(1) @binding(6) var<storage, read_write> map_params: MapParams;
// Volume photons (participating media), PHOTON_WORDS words each, shared by the pass's maps:
// their paths append through volume_count[0] (src/integrators/gpu/volume.rs; one placeholder photon
// without media).
@group(1) @binding(7) var<storage, read_write> volume: array<vec4<u32>>;
@group(1) @binding(8) var<storage, read_write> volume_count: array<atomic<u32>>;
// The volume grid's layout, written by size_volume (volume_grid.wgsl): (lo, cell), (hi, r),
// (table size, photons) as bits.
@group(1) @binding(9) var<storage, read_write> volume_grid: array<vec4<f32>>;

// Flat invocation index of a 2D dispatch of WG_SIZE-wide workgroups.
fn flat_index(gid: vec3<u32>, nwg: vec3<u32>) -> u32 {
    return gid.x + gid.y * nwg.x * WG_SIZE;
}

// Word k of traced photon i.
fn photon_word(i: u32, k: u32) -> vec4<u32> {
    return photons[PHOTON_WORDS * i + k];
}

// Traced photon i into slot `slot` of the sorted photons, word by word.
fn copy_to_sorted(i: u32, slot: u32) {
    for (var k = 0u; k < PHOTON_WORDS; k += 1u) {
        sorted[PHOTON_WORDS * slot + k] = photon_word(i, k);
    }
}
