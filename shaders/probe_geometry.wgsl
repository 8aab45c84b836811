// Oracle probe of ray intersection (common/intersect.wgsl) for tests/intersect_gpu.rs, never
// used by a render: one primitive's watertight triangle or sphere test and the BVH walk
// (nearest and any hit) on chosen rays, to compare with src/geometry.rs and src/bvh.rs.
// Dispatch: ceil(width / WG_SIZE) workgroups of WG_SIZE, one invocation per ray. Writes:
// accum[] as the entry point says. Composed after probes.wgsl (its `accum`).

// probe_intersect: ray i < width, (o, t_max) = accum[i], (d, primitive id as bits: a
// triangle, SPHERE_BIT | sphere, or 0xffffffff for none) = accum[width + i]; writes the
// primitive's test to accum[2 width + i] (a triangle's (t, u, v) of intersect_triangle, a
// sphere's (t, 0, 0) of intersect_sphere; t < 0 a miss), trace_ray's nearest hit
// (t, found, material, light as f32 or -1) to accum[3 width + i], its position and normal to
// accum[4 width + i] and accum[5 width + i], and the any-hit walk's (found, 0, 0, 0) to
// accum[6 width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_intersect(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    let w = params.width;
    if i >= w {
        return;
    }
    let a = accum[i];
    let b = accum[w + i];
    let o = a.xyz;
    let d = b.xyz;
    let id = bitcast<u32>(b.w);
    var prim = vec3<f32>(-2.0, 0.0, 0.0);
    if id != 0xffffffffu {
        if (id & SPHERE_BIT) == 0u {
            let tri = load_triangle(id);
            prim = intersect_triangle(tri.v0, tri.v1, tri.v2, o, d, make_shear(d), a.w);
        } else {
            prim = vec3<f32>(intersect_sphere(load_sphere(id & ~SPHERE_BIT), o, d, a.w), 0.0, 0.0);
        }
    }
    accum[2u * w + i] = vec4<f32>(prim, 0.0);
    let h = trace_ray(o, d, a.w, false);
    let light = select(f32(h.light), -1.0, h.light == NO_LIGHT);
    accum[3u * w + i] = vec4<f32>(h.t, select(0.0, 1.0, h.found), f32(h.material), light);
    accum[4u * w + i] = vec4<f32>(h.position, 0.0);
    accum[5u * w + i] = vec4<f32>(h.normal, 0.0);
    let first = trace_ray(o, d, a.w, true);
    accum[6u * w + i] = vec4<f32>(select(0.0, 1.0, first.found), 0.0, 0.0, 0.0);
}
