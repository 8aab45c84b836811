// The GPU ray benchmark's kernel (src/bench/gpu_rays.rs): one ray per invocation through the
// world's hierarchy, by the binary walk (walk_bvh) or the four-wide one (walk_wide in
// src/bvh/gpu_wide.wgsl; WIDE_WALK), nearest or first hit (ANY_HIT). Ray
// i < params.width: (origin, t_max) = accum[i], (direction, 0) = accum[width + i]; writes
// (t, found, id bits, 0) to accum[2 width + i].

@group(1) @binding(6) var<storage, read_write> accum: array<vec4<f32>>;

override WIDE_WALK: bool = false;
override ANY_HIT: bool = false;

@compute @workgroup_size(WG_SIZE)
fn bench_rays(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let n = params.width;
    let i = gid.x + gid.y * nwg.x * WG_SIZE;
    if i >= n {
        return;
    }
    let a = accum[i];
    let start = PrimHit(a.w, 0u, vec2<f32>(0.0), false);
    var h: PrimHit;
    if WIDE_WALK {
        h = walk_wide(0u, a.xyz, accum[n + i].xyz, start, ANY_HIT);
    } else {
        h = walk_bvh(0u, a.xyz, accum[n + i].xyz, start, ANY_HIT);
    }
    accum[2u * n + i] = vec4<f32>(h.t, select(0.0, 1.0, h.found), bitcast<f32>(h.id), 0.0);
}
