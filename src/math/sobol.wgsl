// Owen-scrambled Sobol points (Burley 2020) in independently scrambled dimension pairs, the
// twin of src/math/sobol.rs and the `sobol_burley` crate it calls (tests/sobol.rs checks bit
// equality). A library, no entry points, no bindings: src/math/sobol.rs wgsl_library() prefixes it
// with generated constants; rng.wgsl (pcg_hash) must come first. No loops and no direction
// table (lavapipe would keep one in per-lane scratch memory).

// The crate's `parts::hash` (from hash-prospector).
fn sobol_hash(v: u32) -> u32 {
    var n = v ^ 0xe6fe3bebu;
    n ^= n >> 16u;
    n *= 0x7feb352du;
    n ^= n >> 15u;
    n *= 0x846ca68bu;
    n ^= n >> 16u;
    return n;
}

// The crate's `parts::owen_scramble_rev`: a hash that approximates an Owen scramble of a
// bit-reversed integer.
fn sobol_owen_rev(v: u32, scramble: u32) -> u32 {
    var n = v;
    n ^= n * 0x3d20adeau;
    n += scramble;
    n *= (scramble >> 16u) | 1u;
    n ^= n * 0x05526c56u;
    n ^= n * 0x53a22864u;
    return n;
}

// The crate's index shuffle (a nested uniform scramble of `index` by `seed`), un-reversed.
fn sobol_shuffle(index: u32, seed: u32) -> u32 {
    return reverseBits(sobol_owen_rev(reverseBits(index), sobol_hash(seed ^ 0x79c68e4au)));
}

// The crate's Owen scramble of the bit-reversed Sobol integer `sobol_rev` of dimension `dim`,
// as a float in [0, 1).
fn sobol_finish(sobol_rev: u32, dim: u32, seed: u32) -> f32 {
    var lanes = array<u32, 4>(0x912f69bau, 0x174f18abu, 0x691e72cau, 0xb40cc1b8u);
    let scramble = (dim >> 2u) ^ (seed * 0x9c8f2d3bu) ^ lanes[dim & 3u];
    let bits = reverseBits(sobol_owen_rev(sobol_rev, sobol_hash(scramble)));
    return bitcast<f32>((bits >> 9u) | 0x3f800000u) - 1.0;
}

// The crate's unscrambled (bit-reversed) Sobol integers of dimensions 0 and 1 for the index
// bits `bits` (twin of sobol::rev_pair, which tests them against the crate's direction
// numbers): dimension 0 is `bits` itself; dimension 1 XORs row k of Pascal's triangle mod 2
// per set bit k, a superset XOR-sum over the 4-bit k in four butterfly steps.
fn sobol_rev_pair(bits: u32) -> vec2<u32> {
    var y = bits;
    y ^= (y >> 1u) & 0x5555u;
    y ^= (y >> 2u) & 0x3333u;
    y ^= (y >> 4u) & 0x0f0fu;
    y ^= (y >> 8u) & 0x00ffu;
    return vec2<u32>(bits, y);
}

// The crate's `sample(index, dim, seed)` for index < 2^SOBOL_INDEX_BITS, dim < SOBOL_SET_DIMENSIONS.
fn sobol_burley_sample(index: u32, dim: u32, seed: u32) -> f32 {
    let rev = sobol_rev_pair(sobol_shuffle(index, seed) & ((1u << SOBOL_INDEX_BITS) - 1u));
    return sobol_finish(select(rev.y, rev.x, dim == 0u), dim, seed);
}

// The crate's dimensions 0 and 1 together (its `sample_4d(index, 0, seed)`, first two lanes).
fn sobol_burley_pair(index: u32, seed: u32) -> vec2<f32> {
    let rev = sobol_rev_pair(sobol_shuffle(index, seed) & ((1u << SOBOL_INDEX_BITS) - 1u));
    return vec2<f32>(sobol_finish(rev.x, 0u, seed), sobol_finish(rev.y, 1u, seed));
}

// sobol::pixel_key: the key of one pixel's sequence.
fn sobol_pixel_key(seed: u32, pixel: u32) -> u32 {
    return pcg_hash(pcg_hash(seed) ^ pixel);
}

// sobol::crate_seed: the crate's seed for a block of 2^SOBOL_INDEX_BITS indices and a set of
// SOBOL_SET_DIMENSIONS dimensions.
fn sobol_crate_seed(key: u32, block: u32, dim_set: u32) -> u32 {
    return pcg_hash(pcg_hash(key ^ block) ^ dim_set);
}

// sobol::sample: dimension `dim` of point `index` of the sequence keyed `key`, in [0, 1).
fn sobol_sample(key: u32, index: u32, dim: u32) -> f32 {
    let seed = sobol_crate_seed(key, index >> SOBOL_INDEX_BITS, dim / SOBOL_SET_DIMENSIONS);
    let mask = (1u << SOBOL_INDEX_BITS) - 1u;
    return sobol_burley_sample(index & mask, dim % SOBOL_SET_DIMENSIONS, seed);
}

// sobol::sample_pair: dimensions 2 pair and 2 pair + 1 of point `index`, one shuffle.
fn sobol_sample_pair(key: u32, index: u32, pair: u32) -> vec2<f32> {
    let seed = sobol_crate_seed(key, index >> SOBOL_INDEX_BITS, pair);
    return sobol_burley_pair(index & ((1u << SOBOL_INDEX_BITS) - 1u), seed);
}

// sobol::SobolStream: the dimensions of one sample in order.
struct SobolStream {
    key: u32,
    index: u32,
    dim: u32,
}

// SobolSampler::new(seed, pass_index, pixel, spp).stream(sample).
fn sobol_stream(seed: u32, pass_index: u32, pixel: u32, spp: u32, sample: u32) -> SobolStream {
    return SobolStream(sobol_pixel_key(seed, pixel), pass_index * spp + sample, 0u);
}

// SobolStream::next: the next dimension, in [0, 1).
fn sobol_next(s: ptr<function, SobolStream>) -> f32 {
    let v = sobol_sample((*s).key, (*s).index, (*s).dim);
    (*s).dim += 1u;
    return v;
}

// SobolStream::next2: the next pair (2j, 2j + 1), skipping a dimension if mid-pair.
fn sobol_next2(s: ptr<function, SobolStream>) -> vec2<f32> {
    (*s).dim += (*s).dim & 1u;
    let v = sobol_sample_pair((*s).key, (*s).index, (*s).dim / SOBOL_SET_DIMENSIONS);
    (*s).dim += 2u;
    return v;
}
