// Oracle probes of the lights (common/light.wgsl, common/photon.wgsl) for tests/light_gpu.rs,
// never used by a render: emission, shadow-ray samples, the owner of a photon path and the
// end of a spent path, on chosen random numbers, to compare with src/lights/mod.rs and
// src/integrators/photon.rs. Dispatch: ceil(width / WG_SIZE) workgroups of WG_SIZE, one invocation per
// case. Writes: accum[] as each entry point says. Composed after probes.wgsl (its `accum`).

// probe_light: light bitcast(accum[i].w) of the scene for case i < width, with
// u0 = accum[i].xyz, (x, u3) = accum[width + i], (ns, u4) = accum[2 width + i]; writes
// emit(l, u0, u3, u4) as (origin, triangle picked by u0.x or -1) to accum[3 width + i],
// (dir, 0), (normal, 1 when aims_at(origin, dir): towards the caustic bounds), (scale, 1
// when is_delta_light(l)) to accum[4..6 width + i], and
// sample_light(l, x, ns, (u0.x, u3, u4)) as (point, pdf) and (weight, 1 when distant) to
// accum[7 width + i] and accum[8 width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_light(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let a = accum[slot(0u, i)];
    let b = accum[slot(1u, i)];
    let c = accum[slot(2u, i)];
    let l = load_light(bitcast<u32>(a.w));
    let e = emit(l, a.xyz, b.w, c.w);
    var tri = -1.0;
    if l.kind == LIGHT_TRIANGLES {
        tri = f32(triangles_pick(l, a.x));
    }
    accum[slot(3u, i)] = vec4<f32>(e.origin, tri);
    accum[slot(4u, i)] = vec4<f32>(e.dir, 0.0);
    accum[slot(5u, i)] = vec4<f32>(e.normal, select(0.0, 1.0, aims_at(e.origin, e.dir)));
    accum[slot(6u, i)] = vec4<f32>(e.scale, select(0.0, 1.0, is_delta_light(l)));
    let s = sample_light(l, b.xyz, c.xyz, vec3<f32>(a.x, b.w, c.w));
    accum[slot(7u, i)] = vec4<f32>(s.point, s.pdf);
    accum[slot(8u, i)] = vec4<f32>(s.weight, select(0.0, 1.0, s.distant));
}

// probe_paths: for path i < width, power accum[i].xyz; writes (light_of(i, global map),
// light_of(i, caustic map), 1 when power_ends(power), 0) to accum[width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_paths(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let ends = power_ends(accum[slot(0u, i)].xyz);
    accum[slot(1u, i)] = vec4<f32>(f32(light_of(i, false)), f32(light_of(i, true)), select(0.0, 1.0, ends), 0.0);
}
