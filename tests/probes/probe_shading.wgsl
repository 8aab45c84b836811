// Oracle probe of the shading interface (src/bsdfs/shading.wgsl) for tests/shading_gpu.rs, never
// used by a render: bsdf_at at the nearest hit of a ray on the bound scene and every question
// the integrators ask of the Surface, to compare with src/bsdfs/shading.rs at the same hit.
// Dispatch: ceil(width / WG_SIZE) workgroups of WG_SIZE, one invocation per case. Writes:
// accum[] as the entry point says. Composed after probes.wgsl (its `accum`).

// The flags of slot 8, one bit each: surface_splits, surface_has_lobe,
// surface_lobe_takes_point_lights, surface_lobe_is_glossy, surface_stores_photons.
fn shading_flags(s: Surface) -> u32 {
    return select(0u, 1u, surface_splits(s)) | select(0u, 2u, surface_has_lobe(s))
        | select(0u, 4u, surface_lobe_takes_point_lights(s))
        | select(0u, 8u, surface_lobe_is_glossy(s)) | select(0u, 16u, surface_stores(s));
}

// probe_shading: case i < width, (o, t_max) = accum[i], (d, rng key as bits) = accum[w + i],
// (wi, a) = accum[2 w + i], (wo, b) = accum[3 w + i], u = accum[4 w + i].xyz. Writes
// (escape(d), power_heuristic(a, b)) to accum[22 w + i]; and at trace_ray(o, d, t_max)'s
// nearest hit h (else slot 5's w is -1 and slots 6..21 are unwritten), with s = bsdf_at(h, d) and
// f = facing(h, d . normal < 0): the hit as (position, material), (normal, light as bits),
// (shading, t) to accum[5..7 w + i]; (uv, surface_class, shading_flags) to accum[8 w + i];
// (surface_emitted(front), surface_store_weight(wi)), (surface_emitted(back),
// surface_pdf_lobe(wi, wo, f.ns)), (surface_diffuse_albedo(wo), 0), surface_eval_diffuse(wi,
// wo), surface_estimate_brdf(wo), surface_eval_lobe(wi, wo, f.ns) to accum[9..14 w + i];
// surface_sample_lobe(d, f, Rng(key, 0)) as (dir, ok), (weight, pdf) to accum[15, 16 w + i];
// for a delta class, surface_delta(h, s, d, Rng(key, 0)) as (dir, not leaking), (throughput
// from 1, 0), (origin, 0) to accum[17..19 w + i] (w = -2 for another class); and
// surface_photon_bounce(s, d, h, u) as (dir, kind), (weight, 0) to accum[20, 21 w + i]; the
// hit's tangent as (tangent, 0) to accum[23 w + i].
@compute @workgroup_size(WG_SIZE)
fn probe_shading(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let a = accum[slot(0u, i)];
    let b = accum[slot(1u, i)];
    let wi = accum[slot(2u, i)];
    let wo = accum[slot(3u, i)];
    let u = accum[slot(4u, i)].xyz;
    let d = b.xyz;
    let key = bitcast<u32>(b.w);
    accum[slot(22u, i)] = vec4<f32>(escape(d), power_heuristic(wi.w, wo.w));
    let h = trace_ray(a.xyz, d, a.w, false);
    if !h.found {
        accum[slot(5u, i)] = vec4<f32>(0.0, 0.0, 0.0, -1.0);
        return;
    }
    let s = bsdf_at(h, d);
    let f = facing(h, dot(d, h.normal) < 0.0);
    accum[slot(5u, i)] = vec4<f32>(h.position, f32(h.material));
    accum[slot(6u, i)] = vec4<f32>(h.normal, bitcast<f32>(h.light));
    accum[slot(7u, i)] = vec4<f32>(h.shading, h.t);
    accum[slot(23u, i)] = vec4<f32>(h.tangent, 0.0);
    accum[slot(8u, i)] = vec4<f32>(h.uv, f32(surface_class(s)), f32(shading_flags(s)));
    accum[slot(9u, i)] = vec4<f32>(surface_emitted(s, true), surface_store_weight(s, wi.xyz));
    let pdf = surface_pdf_lobe(s, wi.xyz, wo.xyz, f.ns);
    accum[slot(10u, i)] = vec4<f32>(surface_emitted(s, false), pdf);
    accum[slot(11u, i)] = vec4<f32>(surface_diffuse_albedo(s, wo.xyz), 0.0);
    accum[slot(12u, i)] = vec4<f32>(surface_eval_diffuse(s, wi.xyz, wo.xyz), 0.0);
    accum[slot(13u, i)] = vec4<f32>(surface_estimate_brdf(s, wo.xyz), 0.0);
    accum[slot(14u, i)] = vec4<f32>(surface_eval_lobe(s, wi.xyz, wo.xyz, f.ns), 0.0);
    var rng = Rng(key, 0u);
    let r = surface_sample_lobe(s, d, f, &rng);
    accum[slot(15u, i)] = vec4<f32>(r.dir, select(0.0, 1.0, r.ok));
    accum[slot(16u, i)] = vec4<f32>(r.weight, r.pdf);
    if surface_class(s) == CLASS_DELTA {
        var rd = Rng(key, 0u);
        var dd = d;
        var o = vec3<f32>(0.0);
        var t = vec3<f32>(1.0);
        let ok = surface_delta(h, s, &dd, &o, &t, &rd);
        accum[slot(17u, i)] = vec4<f32>(dd, select(0.0, 1.0, ok));
        accum[slot(18u, i)] = vec4<f32>(t, 0.0);
        accum[slot(19u, i)] = vec4<f32>(o, 0.0);
    } else {
        accum[slot(17u, i)] = vec4<f32>(0.0, 0.0, 0.0, -2.0);
    }
    let bo = surface_photon_bounce(s, d, h, u);
    accum[slot(20u, i)] = vec4<f32>(bo.dir, f32(bo.kind));
    accum[slot(21u, i)] = vec4<f32>(bo.weight, 0.0);
}
