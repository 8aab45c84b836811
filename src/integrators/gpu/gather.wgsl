// gather: the camera pass, twin of src/integrators/cpu/gather.rs: Sobol-jittered camera ray, the mirror
// and glass chain (glass hits split as on the CPU, one branch deferred: glass_branches.wgsl),
// then at diffuse and glossy hits the maps' estimate, shadow rays, final-gather rays into
// radiance_cache.wgsl and the glossy lobe. One invocation per pixel of a band of rows for a
// sample, or per listed pixel for a round of its deferred glass branches (both `gather`).

@group(1) @binding(6) var<storage, read_write> accum: array<vec4<f32>>;

// Shadow-ray direct light: area lights through kd/pi, delta lights (is_delta_light)
// through the whole BRDF (or only the glossy lobe without TERM_DIRECT). With use_sobol, the first area-light sample
// takes u from the Sobol stream sob (pair SOBOL_PAIR_LIGHT, dimension SOBOL_DIM_LIGHT_THIRD).
// The BRDF and cosine use the shading normal f.ns; a light below the geometric surface
// gives nothing, unless it is a delta light and the lobe transmits (a rough dielectric). With media, shadow rays carry the transmittance of those they cross, from
// the one a ray leaving `hit` is in (`medium` the viewer's).
fn direct_light(hit: Hit, f: Facing, wo: vec3<f32>, m: Surface, rng: ptr<function, Rng>, sob: SobolStream, use_sobol: bool, medium: u32) -> vec3<f32> {
    let x = hit.position;
    let n = f.ng;
    let ns = f.ns;
    let with_direct = (params.terms & TERM_DIRECT) != 0u;
    var total = vec3<f32>(0.0);
    var sobol_left = use_sobol;
    for (var li = 0u; li < params.n_lights && spend(); li += 1u) {
        let light = load_light(li);
        let is_delta = is_delta_light(light);
        if !with_direct && !is_delta {
            continue;
        }
        let samples = select(params.shadow_samples, 1u, is_delta);
        var acc = vec3<f32>(0.0);
        for (var s = 0u; s < samples && spend(); s += 1u) {
            var u: vec3<f32>;
            if sobol_left && !is_delta {
                sobol_left = false;
                let uv = sobol_sample_pair(sob.key, sob.index, SOBOL_PAIR_LIGHT);
                u = vec3<f32>(uv, sobol_sample(sob.key, sob.index, SOBOL_DIM_LIGHT_THIRD));
            } else {
                u = vec3<f32>(rng_next(rng), rng_next(rng), rng_next(rng));
            }
            let ls = sample_light(light, x, ns, u);
            if all(ls.weight == vec3<f32>(0.0)) {
                continue;
            }
            let to_light = ls.point - x;
            let dist = length(to_light);
            let wi = to_light / dist;
            let c_signed = dot(wi, ns);
            // A delta light behind a transmitting lobe is lit through it (no lobe ray can
            // reach it); an area light there is the lobe ray's alone. Through a transmitting
            // lobe the shading frame alone says which side a delta light is on (Mitsuba's
            // emitter sampling), as the lobe's rays go on on either side.
            let free = is_delta && bsdf_lobe_transmits(m.b);
            let leaks = select(c_signed <= 0.0 || reflection_leaks(f, wi), c_signed == 0.0, free);
            if leaks {
                continue;
            }
            let c = abs(c_signed);
            var f = surface_eval_diffuse(m, wi, wo);
            if is_delta {
                f = select(surface_eval_lobe(m, wi, wo, ns), f + surface_eval_lobe(m, wi, wo, ns), with_direct);
            } else if surface_lobe_is_glossy(m) {
                // A glossy lobe weighed against its own sampling (power heuristic).
                let w = power_heuristic(f32(samples) * ls.pdf, surface_pdf_lobe(m, wi, wo, ns));
                f += surface_eval_lobe(m, wi, wo, ns) * w;
            }
            if all(f == vec3<f32>(0.0)) {
                continue;
            }
            let o = offset_origin(x, n, wi);
            // Area lights: stop short of the light's surface; a point light is no surface.
            let end_eps = select(OFFSET_SCALE * (max_abs(ls.point) + OFFSET_FLOOR) * 4.0, 0.0, is_delta);
            // Aim from the moved origin (wi from x would pass the light by up to the offset);
            // a directional light is at infinity, in the same direction from everywhere.
            var dir = wi;
            var t_max = 3.0e38;
            if !ls.distant {
                let to = ls.point - o;
                let len = length(to);
                dir = to / len;
                t_max = len - end_eps;
            }
            if HAS_MEDIA {
                var tr = vec3<f32>(1.0);
                if t_max > 0.0 {
                    tr = shadow_transmittance(o, dir, t_max, ls.distant, medium_after(hit, medium, dir), rng);
                }
                acc += f * ls.weight * c * tr;
                continue;
            }
            if t_max > 0.0 && trace_ray(o, dir, t_max, true).found {
                continue;
            }
            acc += f * ls.weight * c;
        }
        total += acc / f32(samples);
    }
    return total;
}

// Where a chain of mirror and glass bounces ends: the hit to shade (diffuse or glossy; none
// when the path left the scene, met a black surface, leaked or ran out of depth), and the
// emission met on the way.
struct ChainEnd {
    hit: Hit,
    m: Surface,
    emitted: vec3<f32>,
    shade: bool,
    // The last segment's near gather ray (in_scattered), for the camera path to trace.
    gather: bool,
    gather_x: vec3<f32>,
    gather_dir: vec3<f32>,
    gather_w: vec3<f32>,
    gather_medium: u32,
    gather_depth: u32,
}

// Traces from *o along *d through mirrors and glass (*t the throughput, *depth + 1 per bounce
// up to max_depth) to the next diffuse or glossy hit, adding *t times the emission of every
// surface met from its emitting side when `emission`. `emission` marks the camera path, whose
// glass hits split (camera_delta); the gather ray's choose one branch (surface_delta). The
// camera path and the gather ray call this in a loop of its own and shade after it, so the
// lanes of a SIMD group shade together, not once per chain length.
// `mis_pdf` > 0: the ray was drawn from a glossy lobe at mis_from (shading normal mis_ns
// facing the viewer) with that density, and an area light it meets first is weighed against
// the shadow rays' sampling (twin of cpu::gather::Mis).
// With media (HAS_MEDIA), *medium is the one the ray travels in: each segment in a medium adds
// *t times what it scatters towards the viewer (camera paths, `emission`: in_scattered, with
// next-event estimation and without the single-scattering photons in modes with direct
// light; gather rays: gathered_in_medium) and multiplies *t by its
// transmittance; `null` boundaries pass the ray on (not a step of *depth) in the medium behind.
fn follow_chain(o: ptr<function, vec3<f32>>, d: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, depth: ptr<function, u32>, medium: ptr<function, u32>, emission: bool, rng: ptr<function, Rng>, mis_pdf: f32, mis_from: vec3<f32>, mis_ns: vec3<f32>) -> ChainEnd {
    var end: ChainEnd;
    var pdf = mis_pdf;
    // Index-matched boundaries crossed in a row: not bounces (twin of cpu::gather::radiance).
    var crossings = 0u;
    while *depth <= params.max_depth && spend() {
        let hit = trace_ray(*o, *d, 3.0e38, false);
        if HAS_MEDIA && *medium != NO_MEDIUM {
            if emission {
                let direct = (params.terms & TERM_DIRECT) != 0u;
                // The near gather ray waits for a chain that ends here (no number drawn
                // before the camera path traces it, as on the CPU).
                var near = !hit.found;
                if hit.found {
                    near = material_class(load_material(hit.material).kind) == CLASS_SHADED;
                }
                // A scattering event in the medium is a bounce: past max_depth, none.
                let nee = direct && *depth < params.max_depth;
                let sl = in_scattered(*o, *d, hit.t, !hit.found, *medium, nee, direct, near, *depth, rng);
                end.emitted += *t * sl.l;
                if sl.gather {
                    end.gather = true;
                    end.gather_x = sl.x;
                    end.gather_dir = sl.dir;
                    end.gather_w = *t * sl.w;
                    end.gather_medium = *medium;
                    end.gather_depth = *depth;
                }
            } else {
                end.emitted += *t * gathered_in_medium(*o, *d, hit.t, !hit.found, *medium, rng);
            }
            *t *= medium_transmittance_along(load_medium(*medium), *o, *d, select(3.0e38, hit.t, hit.found), rng);
            if all(*t == vec3<f32>(0.0)) {
                break;
            }
        }
        if !hit.found {
            if emission {
                var le = escape(*d);
                // A glossy lobe's ray shares the environment with the shadow rays.
                if HAS_ENVIRONMENT && pdf > 0.0 {
                    var pdf_light = 0.0;
                    if dot(*d, mis_ns) > 0.0 {
                        pdf_light = f32(params.shadow_samples) * env_pdf(load_light(params.n_lights - 1u), mis_ns, *d);
                    }
                    le *= power_heuristic(pdf, pdf_light);
                }
                end.emitted += *t * le;
            }
            break;
        }
        let m = bsdf_at(hit, *d);
        if emission {
            var le = surface_emitted(m, dot(*d, hit.normal) < 0.0);
            if pdf > 0.0 && hit.light != NO_LIGHT && any(le != vec3<f32>(0.0)) {
                var pdf_light = 0.0;
                if dot(hit.position - mis_from, mis_ns) > 0.0 {
                    pdf_light = f32(params.shadow_samples) * light_solid_angle_pdf(load_light(hit.light), mis_from, hit.position, hit.normal);
                }
                le *= power_heuristic(pdf, pdf_light);
            }
            end.emitted += *t * le;
        }
        let kind_class = surface_class(m);
        // An index-matched boundary: straight on in the medium behind it (a lobe sample's
        // weighing of the light it meets carries over), not a bounce; one that emits (camera
        // paths) or past MAX_CROSSINGS in a row is a step of the depth, which bounds the work.
        if HAS_MEDIA && kind_class == CLASS_NULL {
            let emits = emission && any(surface_emitted(m, dot(*d, hit.normal) < 0.0) != vec3<f32>(0.0));
            if emits || crossings >= MAX_CROSSINGS {
                if *depth >= params.max_depth {
                    break;
                }
                *depth += 1u;
                crossings = 0u;
            } else {
                crossings += 1u;
            }
            *medium = medium_after(hit, *medium, *d);
            *o = offset_origin(hit.position, hit.normal, *d);
            continue;
        }
        let pdf_in = pdf;
        pdf = 0.0;
        if kind_class == CLASS_BLACK {
            break;
        }
        if kind_class == CLASS_DELTA {
            if *depth >= params.max_depth {
                break;
            }
            // A thin sheet's pass-through in a media scene is a null event (Mitsuba's volpath):
            // no bounce, and the camera path chooses one branch there (twin of cpu::gather).
            let null_pass = HAS_MEDIA && emission && bsdf_passes_null(m.b);
            let d_in = *d;
            var goes_on: bool;
            if emission && !null_pass {
                goes_on = camera_delta(hit, m, d, o, t, *depth, *medium, rng);
            } else {
                goes_on = surface_delta(hit, m, d, o, t, rng);
            }
            if !goes_on {
                break;
            }
            if HAS_MEDIA {
                *medium = medium_after(hit, *medium, *d);
            }
            if null_pass && dot(*d, hit.normal) * dot(d_in, hit.normal) > 0.0 {
                // The lobe sample's weighing of the light it meets carries over.
                pdf = pdf_in;
            } else {
                *depth += 1u;
            }
            crossings = 0u;
            continue;
        }
        end.hit = hit;
        end.m = m;
        end.shade = true;
        break;
    }
    return end;
}

// The pixel's camera ray of sample params.sample (Sobol-jittered), for camera_path; rng and
// first_shade go on to the path and the sample's deferred glass branches.
fn camera_sample(px: u32, py: u32, rng: ptr<function, Rng>, sob: SobolStream, first_shade: ptr<function, bool>) -> CameraRay {
    var jitter: vec2<f32>;
    if *first_shade {
        jitter = sobol_sample_pair(sob.key, sob.index, SOBOL_PAIR_JITTER);
    } else {
        jitter.x = rng_next(rng);
        jitter.y = rng_next(rng);
    }
    // The pixel filter warps the jitter; a thin lens draws its aperture sample next.
    let j = filter_jitter(params.pixel_filter, params.filter_param, jitter);
    var lens = vec2<f32>(0.0);
    if params.aperture_radius > 0.0 {
        if *first_shade {
            lens = sobol_sample_pair(sob.key, sob.index, SOBOL_PAIR_LENS);
        } else {
            lens.x = rng_next(rng);
            lens.y = rng_next(rng);
        }
    }
    return camera_ray(params.eye, params.forward, params.right, params.up, params.aperture_radius, params.focus_distance, params.orthographic, f32(px) + j.x, f32(py) + j.y, f32(params.width), f32(params.height), lens);
}

// A camera path (the camera's ray, or a glass branch popped from the pixel's stack) from o
// along d with throughput t at `depth` in `medium`, to its end: the radiance it carries
// towards the camera. The first diffuse or glossy hit shaded while *first_shade takes the
// Sobol light and gather samples (sampler "independent": every number from the RNG).
fn camera_path(o_in: vec3<f32>, d_in: vec3<f32>, t_in: vec3<f32>, depth_in: u32, medium_in: u32, rng: ptr<function, Rng>, sob: SobolStream, first_shade: ptr<function, bool>) -> vec3<f32> {
    var o = o_in;
    var d = d_in;
    var throughput = t_in;
    var depth = depth_in;
    var medium = medium_in;
    var radiance = vec3<f32>(0.0);
    // The last lobe sample's density, where it was drawn and that point's normal (MIS).
    var mis_pdf = 0.0;
    var mis_from = vec3<f32>(0.0);
    var mis_ns = vec3<f32>(0.0);
    loop {
        // Bounded as in gather_ray: no shading once the loop budget is spent, and no branch
        // pushed.
        let end = follow_chain(&o, &d, &throughput, &depth, &medium, true, rng, mis_pdf, mis_from, mis_ns);
        radiance += end.emitted;
        let hit = end.hit;
        let m = end.m;
        // Light arriving at a hit makes the path a bounce longer: past max_depth bounces a
        // hit only emits (as the CPU's shade).
        let can_continue = depth < params.max_depth;
        let wo = -d;
        let f = facing(hit, dot(wo, hit.normal) >= 0.0);
        let ns = f.ns;
        // The first diffuse or glossy hit takes the Sobol samples.
        let use_sobol = *first_shade && end.shade;
        if end.shade {
            *first_shade = false;
        }
        // The chain's near gather ray in a medium (traced first, as on the CPU), then the
        // shaded hit's light and its final-gather ray: one gather_ray call site for both
        // (a driver inlines every call site, and lavapipe's compile time grows faster than
        // the code).
        for (var k = 0u; k < 2u; k += 1u) {
            var g: GatherStart;
            if k == 0u {
                if !(HAS_MEDIA && end.gather) {
                    continue;
                }
                g = GatherStart(end.gather_x, vec3<f32>(0.0), end.gather_dir, end.gather_depth, end.gather_medium, end.gather_w);
            } else {
                if !end.shade || !can_continue {
                    break;
                }
                // Diffuse or glossy: shade.
                var l = vec3<f32>(0.0);
                if (params.terms & TERM_DIRECT) != 0u || ((params.terms & TERM_POINT_LOBE) != 0u && surface_lobe_takes_point_lights(m)) {
                    l += direct_light(hit, f, wo, m, rng, sob, use_sobol, medium);
                }
                let kd_pi = surface_estimate_brdf(m, wo);
                let albedo = surface_diffuse_albedo(m, wo);
                let final_gather = (params.terms & TERM_FINAL_GATHER) != 0u;
                // The geometric normal: photons carry their surface's.
                if !final_gather {
                    l += estimate(0u, hit.position, f.ng, kd_pi);
                }
                if params.caustic_weight > 0.0 {
                    l += params.caustic_weight * estimate(1u, hit.position, f.ng, kd_pi);
                }
                radiance += throughput * l;
                if !final_gather || !(max3(albedo) > 0.0) {
                    break;
                }
                var gu: vec2<f32>;
                if use_sobol {
                    gu = sobol_sample_pair(sob.key, sob.index, SOBOL_PAIR_GATHER);
                } else {
                    gu.x = rng_next(rng);
                    gu.y = rng_next(rng);
                }
                let dir = cosine_hemisphere(ns, gu.x, gu.y);
                if reflection_leaks(f, dir) {
                    break;
                }
                var gm = medium;
                if HAS_MEDIA {
                    gm = medium_after(hit, medium, dir);
                }
                g = GatherStart(hit.position, hit.normal, dir, depth, gm, throughput * albedo * surface_store_weight(m, dir));
            }
            radiance += g.w * gather_ray(g.x, g.n, g.dir, g.depth, g.medium, rng);
        }
        if !end.shade || !can_continue || (params.terms & TERM_LOBE_RAY) == 0u || !surface_has_lobe(m) {
            break;
        }
        let lr = surface_sample_lobe(m, -wo, f, rng);
        if !lr.ok {
            break;
        }
        throughput *= lr.weight;
        // With shadow rays to area lights, a glossy lobe's hit on one is weighed.
        mis_pdf = select(0.0, lr.pdf, (params.terms & TERM_DIRECT) != 0u);
        mis_from = hit.position;
        mis_ns = ns;
        d = lr.dir;
        if HAS_MEDIA {
            medium = medium_after(hit, medium, d);
        }
        o = offset_origin(hit.position, hit.normal, d);
        depth += 1u;
    }
    return radiance;
}

// The sample's RNG and Sobol stream at pixel (px, py).
fn camera_rng(px: u32, py: u32) -> Rng {
    let pixel = py * params.width + px;
    return Rng(path_key(params.seed, STREAM_CAMERA, params.pass_index, pixel * params.spp + params.sample), 0u);
}

fn camera_sobol(px: u32, py: u32) -> SobolStream {
    return sobol_stream(params.seed, params.pass_index, py * params.width + px, params.spp, params.sample);
}

// Dispatch params.branch_round of a sample, over the band of rows from params.first_row.
// Dispatch 0 (gather): one invocation per pixel, the camera path of sample params.sample.
// Dispatch r + 1 (with GLASS_SPLIT, up to 2^GLASS_SPLIT_DEPTH - 1 after the gather): round r
// of the deferred glass branches, invocation k (workgroup-major, so a workgroup's lanes are
// consecutive entries) taking the k-th pixel the dispatch before listed, popping its last
// pending branch and tracing it with the RNG where the previous path left it (the CPU's
// depth-first order); those past the listed pixels return. One entry point for both, so the
// camera path compiles once.
@compute @workgroup_size(GATHER_TILE, GATHER_TILE)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lane: u32) {
    let dispatch = select(0u, params.branch_round, GLASS_SPLIT);
    var px = gid.x;
    var py = gid.y + params.first_row;
    var ray = Branch(vec3<f32>(0.0), 0u, vec3<f32>(0.0), params.camera_medium, vec3<f32>(1.0), 0u);
    var rng: Rng;
    var first_shade: bool;
    if dispatch == 0u {
        if gid.x >= params.width || py >= params.height {
            return;
        }
        stack_at = gid.y * params.width + gid.x;
        n_branches = 0u;
        rng = camera_rng(px, py);
        first_shade = params.sampler == SAMPLER_SOBOL;
        let cam = camera_sample(px, py, &rng, camera_sobol(px, py), &first_shade);
        ray.o = cam.origin;
        ray.d = cam.dir;
    } else {
        let k = (wid.y * nwg.x + wid.x) * GATHER_TILE * GATHER_TILE + lane;
        if k == 0u {
            queue_reset(dispatch);
        }
        if !queued_pixel(dispatch - 1u, k) {
            return;
        }
        n_branches = branch_stacks.stacks[stack_at].n;
        if n_branches == 0u {
            return;
        }
        px = stack_at % params.width;
        py = stack_at / params.width + params.first_row;
        n_branches -= 1u;
        ray = branch_stacks.stacks[stack_at].b[n_branches];
        let resume = branch_stacks.stacks[stack_at].resume;
        rng = camera_rng(px, py);
        rng.dim = resume & ~BRANCH_SOBOL_UNUSED;
        first_shade = (resume & BRANCH_SOBOL_UNUSED) != 0u;
    }
    let l = camera_path(ray.o, ray.d, ray.t, ray.depth, ray.medium, &rng, camera_sobol(px, py), &first_shade);
    if GLASS_SPLIT {
        save_branches(rng, first_shade);
        queue_pixel(dispatch);
        if dispatch == 0u && all(gid.xy == vec2<u32>(0u)) {
            queue_reset(0u);
        }
    }
    let i = py * params.width + px;
    accum[i] += vec4<f32>(l / f32(params.spp), 0.0);
}
