// cache_fixed: the radiance cache's values for fixed radii (params.k = 0: every pass of a
// progressive render), twin of RadianceCache::build in src/integrators/cpu/cache.rs. build_cache_fixed:
// one invocation per cache point (dispatch by size_cache_build) sums every facing global
// photon within the radius, BRDF 1/pi (estimate.wgsl's fixed_radius_estimate: one scan, exact
// in fixed point). Reads cache_list (the points); writes cache.

// The cache value at the k-th listed cache point.
@compute @workgroup_size(WG_SIZE)
fn build_cache_fixed(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let k = gid.x + gid.y * nwg.x * WG_SIZE;
    if k >= atomicLoad(&cache_list[CACHE_LIST_COUNT]) {
        return;
    }
    let i = atomicLoad(&cache_list[CACHE_LIST_FIRST + k]);
    let p = map_photon(0u, i);
    let l = fixed_radius_estimate(0u, g_map, p.position, unpack_normal(p.normal), vec3<f32>(1.0 / PI));
    cache[i] = vec4<f32>(l, 1.0);
}
