// Oracle probes for tests/gpu_oracle.rs and tests/media_gpu.rs, never used by a render: single
// library functions (the RNG, the K-nearest estimate, the media's) run on chosen inputs so a
// test can compare them with their Rust twins. Dispatch: ceil(width / WG_SIZE) workgroups of
// WG_SIZE, one invocation per value. Writes: accum[] as each entry point says. Composed after
// common/estimate.wgsl, media_camera.wgsl and radiance_cache.wgsl.

@group(1) @binding(6) var<storage, read_write> accum: array<vec4<f32>>;

// Where every probe keeps case i's values (inputs and outputs alike): slot k is
// accum[k * width + i], for the cases i < params.width, one an invocation.
fn slot(k: u32, i: u32) -> u32 {
    return k * params.width + i;
}

// probe_rng: accum[i] = (path_key(seed, 1 + i % 4, pass, i), draw_u32(key, i % 9),
// bits of to_unit(draw), pcg_hash(i)) as raw bits, for i < width.
@compute @workgroup_size(WG_SIZE)
fn probe_rng(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let key = path_key(params.seed, 1u + i % 4u, params.pass_index, i);
    let bits = draw_u32(key, i % 9u);
    accum[slot(0u, i)] = bitcast<vec4<f32>>(vec4<u32>(key, bits, bitcast<u32>(to_unit(bits)), pcg_hash(i)));
}

// probe_knn: for query i < width, position accum[i].xyz and normal accum[width + i].xyz,
// writes the global map's estimate with f = 1 and the neighbour count to accum[2 width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_knn(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let x = accum[slot(0u, i)].xyz;
    let ns = accum[slot(1u, i)].xyz;
    let l = estimate(0u, x, ns, vec3<f32>(1.0));
    accum[slot(2u, i)] = vec4<f32>(l, f32(last_found));
}

// probe_cache: for query i < width, position accum[i].xyz and normal accum[width + i].xyz,
// writes the radiance cache's lookup and the sorted index it read (-1 when none) to
// accum[2 width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_cache(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let y = accum[slot(0u, i)].xyz;
    let n = accum[slot(1u, i)].xyz;
    let j = cache_find(y, n);
    var l = vec3<f32>(0.0);
    if j != CACHE_NONE {
        l = cache[j].xyz;
    }
    accum[slot(2u, i)] = vec4<f32>(l, select(f32(j), -1.0, j == CACHE_NONE));
}

// probe_cosine: for i < width, normal accum[i].xyz and (u1, u2) = accum[width + i].xy, writes
// cosine_hemisphere(normal, u1, u2) (the final gather's direction) to accum[2 width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_cosine(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let u = accum[slot(1u, i)].xy;
    accum[slot(2u, i)] = vec4<f32>(cosine_hemisphere(accum[slot(0u, i)].xyz, u.x, u.y), 0.0);
}

// probe_env: the scene's environment (its last light) for case i < width: direction
// accum[i].xyz, shading normal accum[width + i].xyz, uniforms accum[2 width + i].xyz; writes
// (env_radiance(dir), env_pdf(ns, dir)) to accum[3 width + i] and the shadow-ray sample
// env_sample(ns, u) (direction, pdf) to accum[4 width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_env(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let l = load_light(params.n_lights - 1u);
    let d = accum[slot(0u, i)].xyz;
    let ns = accum[slot(1u, i)].xyz;
    accum[slot(3u, i)] = vec4<f32>(env_radiance(l, d), env_pdf(l, ns, d));
    let s = env_sample(l, ns, accum[slot(2u, i)].xyz);
    accum[slot(4u, i)] = vec4<f32>(s.dir, s.pdf);
}

// probe_medium: the scene's medium 0 for case i < width: (u_channel, u, t_max, u1) =
// accum[i], (dir, u2) = accum[width + i]; writes sample_flight's (weight, t) to
// accum[2 width + i] and (hg_sample(g, dir, u1, u2), 1 when the flight ended in the medium)
// to accum[3 width + i]; with (c, interior, exterior, current as bits) = accum[4 width + i]
// and n = accum[5 width + i].xyz, writes (hg_eval(g, c), medium_interface_after((interior,
// exterior), current, n, dir) as bits) to accum[6 width + i]; with (flags, drop, id, light)
// = accum[7 width + i] as bits, (x, cell) = accum[8 width + i] and (lo, material as bits) =
// accum[9 width + i], writes (keep_photon, is_cache_point as 0/1, medium_after at a hit of
// that material with normal n, light_medium of that light emitting along dir with normal n,
// as bits) to accum[10 width + i] and volume_cell(x, lo, cell) as bits to accum[11 width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_medium(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let m = load_medium(0u);
    let a = accum[slot(0u, i)];
    let b = accum[slot(1u, i)];
    let f = sample_flight(m, a.x, a.y, a.z);
    accum[slot(2u, i)] = vec4<f32>(f.weight, f.t);
    accum[slot(3u, i)] = vec4<f32>(hg_sample(m.g, b.xyz, a.w, b.w), select(0.0, 1.0, f.in_medium));
    let c = accum[slot(4u, i)];
    let iface = bitcast<vec2<u32>>(c.yz);
    let after = medium_interface_after(iface, bitcast<u32>(c.w), accum[slot(5u, i)].xyz, b.xyz);
    accum[slot(6u, i)] = vec4<f32>(hg_eval(m.g, c.x), bitcast<f32>(after), 0.0, 0.0);
    let k = bitcast<vec4<u32>>(accum[slot(7u, i)]);
    let x = accum[slot(8u, i)];
    let lo = accum[slot(9u, i)];
    let n = accum[slot(5u, i)].xyz;
    let material = bitcast<u32>(lo.w);
    let hit = Hit(1.0, vec3<f32>(0.0), n, n, material, NO_LIGHT, vec2<f32>(0.0), true, vec3<f32>(0.0));
    let e = Emission(vec3<f32>(0.0), b.xyz, n, vec3<f32>(1.0));
    let keep = select(0.0, 1.0, keep_photon(k.x, k.y));
    let cache_point = select(0.0, 1.0, is_cache_point(k.x, k.z));
    let after_hit = medium_after(hit, bitcast<u32>(c.w), b.xyz);
    let emitted = light_medium(load_light(k.w), e);
    let media = bitcast<vec2<f32>>(vec2<u32>(after_hit, emitted));
    accum[slot(10u, i)] = vec4<f32>(keep, cache_point, media);
    accum[slot(11u, i)] = vec4<f32>(bitcast<vec3<f32>>(volume_cell(x.xyz, lo.xyz, x.w)), 0.0);
}

// probe_beam: the volume map's beam estimate for query i < width: (o, t_max) = accum[i],
// (d, medium as bits) = accum[width + i], (which BEAM_* code, z) = accum[2 width + i].xy;
// writes beam(...) with the scene's medium over the segment's part beyond z to
// accum[3 width + i]. A heterogeneous medium's transmittance is the walk of the whole
// segment on the stream (params.seed, STREAM_PHOTON, 0, i), read from z on
// (Transmittances::split).
@compute @workgroup_size(WG_SIZE)
fn probe_beam(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let a = accum[slot(0u, i)];
    let b = accum[slot(1u, i)];
    let c = accum[slot(2u, i)];
    let medium = bitcast<u32>(b.w);
    let m = load_medium(medium);
    var walk: TrackReplay;
    if HAS_HETERO_MEDIA && m.grid != NO_MEDIUM {
        let rng = Rng(path_key(params.seed, STREAM_PHOTON, 0u, i), 0u);
        walk = replay_start(hetero_record(m), a.xyz, b.xyz, a.w, rng, c.y);
    }
    let bt = select(a.w - c.y, a.w, a.w >= 3.0e38);
    let l = beam(a.xyz + b.xyz * c.y, b.xyz, bt, medium, m, u32(c.x), &walk);
    accum[slot(3u, i)] = vec4<f32>(l, 0.0);
}

// probe_transmittance: the shadow walk for case i < width: (o, t_max) = accum[i] (endless
// when t_max >= 3e38), (d, medium as bits) = accum[width + i], on the stream
// (params.seed, STREAM_PHOTON, 0, i); writes shadow_transmittance(...) to accum[2 width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_transmittance(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let a = accum[slot(0u, i)];
    let b = accum[slot(1u, i)];
    var rng = Rng(path_key(params.seed, STREAM_PHOTON, 0u, i), 0u);
    let tr = shadow_transmittance(a.xyz, b.xyz, a.w, a.w >= 3.0e38, bitcast<u32>(b.w), &rng);
    accum[slot(2u, i)] = vec4<f32>(tr, 0.0);
}

// probe_hetero: the scene's medium 0 (heterogeneous) for case i < width: (o, t) =
// accum[i], (d, seed as bits) = accum[width + i]; writes hetero_sigma_t_at(o) to
// accum[2 width + i], hetero_sigma_s_at(o) to accum[3 width + i], hetero_transmittance over
// [0, t) on the stream (seed, STREAM_PHOTON, 0, i) to accum[4 width + i],
// hetero_sample_flight towards t on (seed, STREAM_CAUSTIC, 0, i) as (weight, t) to
// accum[5 width + i], and (1 when that flight ended in the medium, the cells the majorant
// walk over the span visits, the sum of their majorants times their lengths, 1 when the
// walk ran out) to accum[6 width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_hetero(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let h = hetero_record(load_medium(0u));
    let a = accum[slot(0u, i)];
    let b = accum[slot(1u, i)];
    let seed = bitcast<u32>(b.w);
    accum[slot(2u, i)] = vec4<f32>(hetero_sigma_t_at(h, a.xyz), 0.0);
    accum[slot(3u, i)] = vec4<f32>(hetero_sigma_s_at(h, a.xyz), 0.0);
    var rng = Rng(path_key(seed, STREAM_PHOTON, 0u, i), 0u);
    accum[slot(4u, i)] = vec4<f32>(hetero_transmittance(h, a.xyz, b.xyz, a.w, &rng), 0.0);
    var rng2 = Rng(path_key(seed, STREAM_CAUSTIC, 0u, i), 0u);
    let f = hetero_sample_flight(h, a.xyz, b.xyz, a.w, &rng2);
    accum[slot(5u, i)] = vec4<f32>(f.weight, f.t);
    var cells = 0.0;
    var depth = 0.0;
    let span = hetero_span(h, a.xyz, b.xyz, a.w);
    var w = majorant_walk_start(h, a.xyz, b.xyz, span.x, span.y);
    if span.x < span.y {
        while majorant_walk_next(&w) {
            cells += 1.0;
            depth += (w.b - w.a) * w.mu;
        }
    }
    accum[slot(6u, i)] = vec4<f32>(select(0.0, 1.0, f.in_medium), cells, depth, select(0.0, 1.0, w.exhausted));
}

// probe_segment: a camera segment through the scene's medium 0 for case i < width, over the
// volume map's grid: (o, t) = accum[i] (endless when t >= 3e38), d = accum[width + i].xyz.
// Writes single_scattering on the stream (params.seed, STREAM_PHOTON, 0, i) to
// accum[2 width + i] and gathered_in_medium on (params.seed, STREAM_CAUSTIC, 0, i) to
// accum[3 width + i]. (in_scattered's beams are probe_beam's; a probe of all of it took
// lavapipe's compiler over ten minutes.)
@compute @workgroup_size(WG_SIZE)
fn probe_segment(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let a = accum[slot(0u, i)];
    let d = accum[slot(1u, i)].xyz;
    let endless = a.w >= 3.0e38;
    var rng = Rng(path_key(params.seed, STREAM_PHOTON, 0u, i), 0u);
    accum[slot(2u, i)] = vec4<f32>(single_scattering(a.xyz, d, a.w, endless, 0u, &rng), 0.0);
    var rng2 = Rng(path_key(params.seed, STREAM_CAUSTIC, 0u, i), 0u);
    accum[slot(3u, i)] = vec4<f32>(gathered_in_medium(a.xyz, d, a.w, endless, 0u, &rng2), 0.0);
}
