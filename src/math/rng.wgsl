// Counter-based RNG, the twin of src/math/rng.rs (tests/gpu_oracle.rs checks bit equality).
// The STREAM_* ids come from the generated prelude (src/math/rng.rs Stream).
// Library, no entry point; writes nothing.

fn pcg_hash(v: u32) -> u32 {
    let state = v * 747796405u + 2891336453u;
    let word = ((state >> ((state >> 28u) + 4u)) ^ state) * 277803737u;
    return (word >> 22u) ^ word;
}

fn path_key(seed: u32, stream: u32, pass_index: u32, index: u32) -> u32 {
    let a = pcg_hash(seed ^ pcg_hash(stream));
    let b = pcg_hash(a ^ pass_index);
    return pcg_hash(b ^ index);
}

fn draw_u32(key: u32, dim: u32) -> u32 {
    return pcg_hash(key ^ pcg_hash(dim));
}

fn to_unit(bits: u32) -> f32 {
    return f32(bits >> 8u) * (1.0 / 16777216.0);
}

struct Rng {
    key: u32,
    dim: u32,
}

fn rng_next(r: ptr<function, Rng>) -> f32 {
    let v = to_unit(draw_u32((*r).key, (*r).dim));
    (*r).dim += 1u;
    return v;
}
