// cache_fixed: the radiance cache's values for fixed radii (params.k = 0: every pass of a
// progressive render), twin of RadianceCache::build in src/cpu/cache.rs. build_cache_fixed:
// one invocation per cache point (dispatch by size_cache_build) sums every facing global
// photon within the radius, BRDF 1/pi. Reads cache_list (the points; at CACHE_LIST_MAX the
// largest photon term, from list_cache_points); writes cache.

// The cache value at the k-th cache point: radius_scan's fixed-point sum with the scale of
// the largest term of the whole map (one scan, no per-point maximum), so the sum is exact
// and independent of the photons' order in a cell; each term's rounding is at most 2^-25 of
// that term.
@compute @workgroup_size(WG_SIZE)
fn build_cache_fixed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let k = gid.x + gid.y * nwg.x * WG_SIZE;
    if k >= atomicLoad(&cache_list[CACHE_LIST_COUNT]) {
        return;
    }
    let i = atomicLoad(&cache_list[CACHE_LIST_FIRST + k]);
    let m = bitcast<f32>(atomicLoad(&cache_list[CACHE_LIST_MAX]));
    var l = vec3<f32>(0.0);
    // (Below 1e-30 the scale 2^24 / m would overflow; such light is nothing.)
    if m > 1e-30 {
        let p = g_photons[i];
        let mp = g_map;
        let s = radius_scan(0u, mp, p.position, unpack_normal(p.normal), vec3<f32>(1.0 / PI), 16777216.0 / m);
        let sum = vec3<f32>(s.hi) * 4294967296.0 + vec3<f32>(s.lo);
        l = sum * (m / 16777216.0) * kernel_norm(mp.radius2);
    }
    cache[i] = vec4<f32>(l, 1.0);
}
