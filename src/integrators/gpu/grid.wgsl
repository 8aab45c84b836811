// Hash-grid cells (twins: src/integrators/estimate.rs, src/integrators/gpu/grid.rs): a point's cell, a cell's table slot, whether a
// map keeps a photon (DROP_* flags from the generated prelude, src/integrators/gpu/codes.rs) and whether
// it is a radiance-cache point.
// Library, no entry point; writes nothing.

fn cell_of(p: vec3<f32>, cell_size: f32) -> vec3<i32> {
    return vec3<i32>(floor(p / cell_size));
}

// Squared distance from x to the box of cell c (0 inside it).
fn cell_gap2(c: vec3<i32>, x: vec3<f32>, cell_size: f32) -> f32 {
    let lo = vec3<f32>(c) * cell_size;
    let gap = max(max(lo - x, x - (lo + vec3<f32>(cell_size))), vec3<f32>(0.0));
    return dot(gap, gap);
}

fn cell_hash(c: vec3<i32>, table_size: u32) -> u32 {
    let h = pcg_hash(bitcast<u32>(c.x) ^ pcg_hash(bitcast<u32>(c.y) ^ pcg_hash(bitcast<u32>(c.z))));
    return h & (table_size - 1u);
}

// Whether a photon with these flags belongs in a map that drops the kinds in `drop`.
fn keep_photon(flags: u32, drop: u32) -> bool {
    if (drop & DROP_DIRECT) != 0u && (flags & DEPTH_MASK) == 0u {
        return false;
    }
    if (drop & DROP_CAUSTIC) != 0u && (flags & FLAG_CAUSTIC) != 0u {
        return false;
    }
    return true;
}

// Whether the photon with these flags and id is a radiance-cache point (plan::CACHE_STRIDE):
// chosen by identity, whatever order a map holds it in.
fn is_cache_point(flags: u32, id: u32) -> bool {
    return (id + (flags & DEPTH_MASK)) % CACHE_STRIDE == 0u;
}

// A point's cell in the volume map's grid of cells of edge `cell` from corner `lo` (twin of
// VolumeMap::cell_coords).
fn volume_cell(x: vec3<f32>, lo: vec3<f32>, cell: f32) -> vec3<i32> {
    return vec3<i32>(floor((x - lo) / cell));
}
