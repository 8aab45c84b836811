// trace_photons: one invocation per photon path (global or caustic map, per map_params), the
// twin of src/integrators/cpu/photons.rs. Dispatch: ceil(paths / WG_SIZE) workgroups of WG_SIZE (2D when
// large). Writes: photons[] through counters[0], and in media (HAS_MEDIA) volume photons to
// volume[] through volume_count[0]; overflow past either buffer is dropped and counted in
// stats[STAT_PHOTON_OVERFLOW].

fn store_photon(p: Photon) {
    let slot = atomicAdd(&counters[0], 1u);
    if slot < map_params.capacity {
        let w = PHOTON_WORDS * slot;
        photons[w] = vec4<u32>(bitcast<vec3<u32>>(p.position), p.flags);
        photons[w + 1u] = vec4<u32>(bitcast<vec3<u32>>(p.power), p.id);
        photons[w + 2u] = vec4<u32>(bitcast<vec3<u32>>(p.dir), p.normal);
    } else {
        atomicAdd(&stats[STAT_PHOTON_OVERFLOW], 1u);
    }
}

// A volume photon (Photon::in_medium: its medium's index in the normal's word).
fn store_volume_photon(p: Photon) {
    let slot = atomicAdd(&volume_count[0], 1u);
    if slot < arrayLength(&volume) / PHOTON_WORDS {
        let w = PHOTON_WORDS * slot;
        volume[w] = vec4<u32>(bitcast<vec3<u32>>(p.position), p.flags);
        volume[w + 1u] = vec4<u32>(bitcast<vec3<u32>>(p.power), p.id);
        volume[w + 2u] = vec4<u32>(bitcast<vec3<u32>>(p.dir), p.normal);
    } else {
        atomicAdd(&stats[STAT_PHOTON_OVERFLOW], 1u);
    }
}

@compute @workgroup_size(WG_SIZE)
fn trace_photons(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if i >= map_params.paths {
        return;
    }
    let caustic_map = map_params.is_caustic != 0u;
    let light = load_light(light_of(i, caustic_map));
    var rng = Rng(path_key(params.seed, map_params.stream, params.pass_index, i), 0u);
    let u0 = vec3<f32>(rng_next(&rng), rng_next(&rng), rng_next(&rng));
    let u3 = rng_next(&rng);
    let u4 = rng_next(&rng);
    let e = emit(light, u0, u3, u4);
    if caustic_map && !aims_at(e.origin, e.dir) {
        return;
    }
    var power = select(light.global_power, light.caustic_power, caustic_map) * e.scale;
    var o = e.origin;
    if any(e.normal != vec3<f32>(0.0)) {
        o = offset_origin(e.origin, e.normal, e.dir);
    }
    var d = e.dir;
    var all_specular = true;
    // NO_MEDIUM in a scene without media.
    var medium = NO_MEDIUM;
    if HAS_MEDIA {
        medium = photon_medium(light, e, o);
    }
    var crossings = 0u;
    var depth = 0u;
    while depth < params.max_photon_bounces && spend() {
        let hit = trace_ray(o, d, 3.0e38, false);
        if HAS_MEDIA && medium != NO_MEDIUM {
            let md = load_medium(medium);
            let f = medium_flight(md, o, d, select(3.0e38, hit.t, hit.found), &rng);
            if f.in_medium {
                let x = o + d * f.t;
                let scattered = power * f.weight;
                let caustic = depth > 0u && all_specular;
                let vf = map_params.volume_flags;
                if (vf & VOLUME_STORE) != 0u {
                    // A caustic path keeps only L S+ V; the global paths leave those to it.
                    var keep = caustic;
                    if !caustic_map {
                        keep = !(caustic && (vf & VOLUME_DROP_CAUSTIC) != 0u);
                    }
                    if keep && max3(scattered) > 0.0 {
                        let flags = min(depth, DEPTH_MASK) | select(0u, FLAG_CAUSTIC, caustic);
                        store_volume_photon(Photon(x, flags, scattered, i, d, medium));
                    }
                }
                if caustic_map {
                    return;
                }
                // Absorption by Russian roulette on the scattering weight.
                let q = min(max3(f.weight), 1.0);
                if !(rng_next(&rng) < q) {
                    return;
                }
                power = scattered / q;
                let u1 = rng_next(&rng);
                let u2 = rng_next(&rng);
                d = hg_sample(md.g, d, u1, u2);
                o = x;
                all_specular = false;
                depth += 1u;
                if power_ends(power) {
                    return;
                }
                continue;
            }
            power *= f.weight;
        }
        if !hit.found {
            return;
        }
        let m = bsdf_at(hit, d);
        if HAS_MEDIA && surface_class(m) == CLASS_NULL {
            // An index-matched boundary: straight on, in the medium behind it.
            crossings += 1u;
            if crossings > MAX_CROSSINGS {
                return;
            }
            medium = medium_after(hit, medium, d);
            o = offset_origin(hit.position, hit.normal, d);
            continue;
        }
        if surface_stores(m) {
            let stored_normal = pack_normal(select(-hit.normal, hit.normal, dot(d, hit.normal) < 0.0));
            let caustic = depth > 0u && all_specular;
            let flags = min(depth, DEPTH_MASK) | select(0u, FLAG_CAUSTIC, caustic);
            // The caustic map keeps only L (S|G)+ D photons: its paths end at the first
            // diffuse bounce (below).
            if !caustic_map || caustic {
                // A plastic's base sees the light its coating lets through.
                let stored = power * surface_store_weight(m, -d);
                store_photon(Photon(hit.position, flags, stored, i, d, stored_normal));
            }
        }
        let u = vec3<f32>(rng_next(&rng), rng_next(&rng), rng_next(&rng));
        let b = surface_photon_bounce(m, d, hit, u);
        if b.kind == BOUNCE_ABSORB || (caustic_map && b.kind == BOUNCE_DIFFUSE) {
            return;
        }
        // Delta and glossy lobes alike: every lobe is traced from the camera, so light
        // arriving over any of them is a caustic.
        if b.kind == BOUNCE_DIFFUSE {
            all_specular = false;
        }
        power *= b.weight;
        if power_ends(power) {
            return;
        }
        // A thin sheet passed in a media scene is a null event: no bounce, not a caustic's
        // specular event (twin of cpu::photons).
        let null_pass = HAS_MEDIA && dot(b.dir, hit.normal) * dot(d, hit.normal) > 0.0 && bsdf_passes_null(m.b);
        d = b.dir;
        if HAS_MEDIA {
            medium = medium_after(hit, medium, d);
        }
        o = offset_origin(hit.position, hit.normal, d);
        if !null_pass {
            depth += 1u;
        }
    }
}
