// media_camera: the camera pass's segments through participating media (HAS_MEDIA only), twin
// of src/integrators/cpu/gather_media.rs (in_scattered, gathered_in_medium) and src/integrators/cpu/media.rs (the
// shadow walk, single scattering). Library of the gather and probe kernels, after
// volume_estimate.wgsl (the volume map's estimates); writes nothing but the loop budget.

// exp(x) - 1 and ln(1 + x), keeping a small x's digits (Rust's exp_m1 and ln_1p).
fn expm1_f(x: f32) -> f32 {
    if abs(x) < 1e-3 {
        return x * (1.0 + x * (0.5 + x / 6.0));
    }
    return exp(x) - 1.0;
}

fn ln1p_f(x: f32) -> f32 {
    if abs(x) < 1e-3 {
        return x * (1.0 - x * (0.5 - x / 3.0));
    }
    return log(1.0 + x);
}

// Medium::sample_in_segment's result (ok: a distance was drawn).
struct SegmentPoint {
    t: f32,
    pdf: f32,
    ok: bool,
}

// A channel's mass over the segment, 1 - T(t_max) (1 when endless).
fn segment_mass(s: f32, t_max: f32, endless: bool) -> f32 {
    if endless {
        return 1.0;
    }
    return -expm1_f(-s * t_max);
}

fn segment_density(s: f32, t: f32, t_max: f32, endless: bool) -> f32 {
    if s > 0.0 {
        return s * exp(-s * t) / segment_mass(s, t_max, endless);
    }
    return select(1.0 / t_max, 0.0, endless);
}

// Medium::sample_in_segment: a distance in [0, t_max) in proportion to one channel's
// sigma_t T(t), the channel chosen by uc; the density is the channels' mean.
fn sample_in_segment(m: Medium, uc: f32, u: f32, t_max: f32, endless: bool) -> SegmentPoint {
    let c = min(u32(uc * 3.0), 2u);
    let sigma = m.sigma_t[c];
    var t = 0.0;
    if sigma > 0.0 {
        t = -ln1p_f(-u * segment_mass(sigma, t_max, endless)) / sigma;
    } else if !endless {
        t = u * t_max;
    } else {
        return SegmentPoint(0.0, 0.0, false);
    }
    if !endless {
        t = min(t, t_max * (1.0 - F32_EPSILON));
    }
    let st = m.sigma_t;
    let pdf = (segment_density(st.x, t, t_max, endless) + segment_density(st.y, t, t_max, endless)
        + segment_density(st.z, t, t_max, endless)) / 3.0;
    return SegmentPoint(t, pdf, pdf > 0.0 && t <= 3.0e38);
}

// cpu::media::transmittance: what travels from `origin` along unit `dir` over t_max (or to
// the scene's end when `endless`) starting in `medium`, through index-matched boundaries
// (changing medium there) and thin sheets (times bsdf_null_transmission); zero behind any
// other surface or past MAX_CROSSINGS boundaries. A heterogeneous medium's is an unbiased
// estimate (ratio tracking, numbers from rng).
fn shadow_transmittance(origin: vec3<f32>, dir: vec3<f32>, t_max: f32, endless: bool, medium_in: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    var o = origin;
    var left = select(t_max, 3.0e38, endless);
    var medium = medium_in;
    var tr = vec3<f32>(1.0);
    // Runs are measured between the true points (hits, the ends), not the offset origins.
    let end = origin + dir * t_max;
    var at = origin;
    for (var k = 0u; k < MAX_CROSSINGS && spend(); k += 1u) {
        let hit = trace_ray(o, dir, left, false);
        var run = 3.0e38;
        if hit.found {
            run = length(hit.position - at);
        } else if !endless {
            run = length(end - at);
        }
        if medium != NO_MEDIUM {
            tr *= medium_transmittance_along(load_medium(medium), at, dir, run, rng);
        }
        if !hit.found {
            return tr;
        }
        if material_class(load_material(hit.material).kind) != CLASS_NULL {
            // A thin sheet lets through its null transmission (Mitsuba's volpath).
            let s = bsdf_at(hit, dir);
            let w = bsdf_null_transmission(s.b, surface_local(s, -dir));
            if all(w == vec3<f32>(0.0)) {
                return vec3<f32>(0.0);
            }
            tr *= w;
        }
        medium = medium_after(hit, medium, dir);
        at = hit.position;
        let next = offset_origin(hit.position, hit.normal, dir);
        if !endless {
            left -= dot(next - o, dir);
            if left <= 0.0 {
                return tr;
            }
        }
        o = next;
    }
    return vec3<f32>(0.0);
}

// medium::sample_equiangular: a distance in [0, t_max) (or endless) along o + t d in
// proportion to the inverse square distance to y, uniform in the angle the segment subtends
// at y; not ok for a ray through y.
fn sample_equiangular(o: vec3<f32>, d: vec3<f32>, t_max: f32, endless: bool, y: vec3<f32>, u: f32) -> SegmentPoint {
    let to_y = y - o;
    let delta = dot(to_y, d);
    let dist = length(to_y - d * delta);
    if !(dist > 1e-6 * length(to_y)) || !(dist <= 3.0e38) {
        return SegmentPoint(0.0, 0.0, false);
    }
    let a = atan2(-delta, dist);
    var b = 0.5 * PI;
    if !endless {
        b = atan2(t_max - delta, dist);
    }
    if !(b > a) {
        return SegmentPoint(0.0, 0.0, false);
    }
    var t = max(delta + dist * tan(a + u * (b - a)), 0.0);
    if !endless {
        t = min(t, t_max * (1.0 - F32_EPSILON));
    }
    let s = t - delta;
    let pdf = dist / ((b - a) * (dist * dist + s * s));
    return SegmentPoint(t, pdf, pdf > 0.0 && pdf <= 3.0e38 && t <= 3.0e38);
}

// cpu::media::single_scattering: for each light, a point on it and one distance in the
// segment from o along d (t_seg long, or endless) in `medium` drawn towards that point
// (equiangular; by transmittance for directional lights or a ray through the point), then
// one shadow ray, weighed by the phase function, sigma_s and the transmittance of both
// legs; the environment's direction drawn from the phase function. params.shadow_samples
// estimates per light, averaged, light by light (the CPU's order of random numbers). In a
// heterogeneous medium a transmittance-drawn point is a free flight (hetero_track: none when
// it leaves the segment), sigma_s is the point's, and an equiangular point's transmittance is
// ratio-tracked after its shadow ray (Medium::scatter_in_segment, sigma_s_at,
// transmittance_along, in the CPU's order).
fn single_scattering(o: vec3<f32>, d: vec3<f32>, t_seg: f32, endless: bool, medium: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    let m = load_medium(medium);
    let hetero = HAS_HETERO_MEDIA && m.grid != NO_MEDIUM;
    var l = vec3<f32>(0.0);
    let n = max(params.shadow_samples, 1u);
    for (var k = 0u; k < params.n_lights * n && spend(); k += 1u) {
        let light = load_light(k / n);
        let u3 = vec3<f32>(rng_next(rng), rng_next(rng), rng_next(rng));
        let uc = rng_next(rng);
        let ut = rng_next(rng);
        let an = light_anchor(light, u3);
        var p = SegmentPoint(0.0, 0.0, false);
        if an.ok {
            p = sample_equiangular(o, d, t_seg, endless, an.y, ut);
        }
        // sig * w: what the light scattered at x towards o is multiplied by (sig 1 and
        // m.sigma_s after the sum for a homogeneous medium); `equiangular`: w is drawn after
        // the shadow ray (heterogeneous).
        var sig = vec3<f32>(1.0);
        var w = vec3<f32>(0.0);
        var t = p.t;
        var equiangular = false;
        if hetero {
            if p.ok {
                sig = hetero_sigma_s_at(hetero_record(m), o + d * p.t);
                equiangular = true;
            } else {
                let f = hetero_track(hetero_record(m), o, d, select(t_seg, 3.0e38, endless), rng);
                if !f.found {
                    continue;
                }
                t = f.t;
                sig = f.sigma_s;
                w = f.tr_over_pdf;
            }
            if all(sig == vec3<f32>(0.0)) {
                continue;
            }
        } else {
            if !p.ok {
                p = sample_in_segment(m, uc, ut, t_seg, endless);
            }
            if !p.ok {
                continue;
            }
            t = p.t;
            w = medium_transmittance(m, p.t) / p.pdf;
        }
        let x = o + d * t;
        // The shadow ray's direction and length, and the light it brings as a * b: one
        // shadow walk for every kind (a kernel inlines each call site).
        var wi: vec3<f32>;
        var t_max = 3.0e38;
        var distant = true;
        var a: vec3<f32>;
        var b = 1.0;
        if HAS_ENVIRONMENT && light.kind == LIGHT_ENVIRONMENT {
            wi = hg_sample(m.g, d, u3.y, u3.z);
            a = env_radiance(light, wi);
        } else {
            let ls = sample_light(light, x, -d, u3);
            if all(ls.weight == vec3<f32>(0.0)) {
                continue;
            }
            let to_light = ls.point - x;
            let dist = length(to_light);
            if !(dist > 0.0) {
                continue;
            }
            wi = to_light / dist;
            // Light travels along -wi, then on towards the camera (along -d).
            a = ls.weight;
            b = hg_eval(m.g, dot(wi, d));
            distant = ls.distant;
            // Stop short of an area light's own surface (as the surfaces' shadow rays do).
            t_max = dist;
            if !ls.distant && !is_delta_light(light) {
                t_max = dist - OFFSET_SCALE * (max_abs(ls.point) + OFFSET_FLOOR) * 4.0;
            }
        }
        let tr = shadow_transmittance(x, wi, t_max, distant, medium, rng);
        if equiangular {
            w = medium_transmittance_along(m, o, d, t, rng) / p.pdf;
        }
        l += sig * w * a * b * tr;
    }
    return select(m.sigma_s, vec3<f32>(1.0), hetero) * l / f32(n);
}

// What a camera segment scatters towards the viewer (l), and the near part's gather ray
// (Gatherer::near_gather) when `gather`: from x along dir, weighed by w; the camera path
// traces it once its chain ends (gather_ray calls follow_chain, which calls this).
struct SegmentLight {
    l: vec3<f32>,
    gather: bool,
    x: vec3<f32>,
    dir: vec3<f32>,
    w: vec3<f32>,
}

// Gatherer::in_scattered: the light scattered towards the viewer along the segment from o
// along d, t long (endless: the ray left the scene), in `medium`: single scattering by
// next-event estimation (with nee) and the volume map's beam estimate (without its single-
// scattering photons when skip_direct). With `near` (the segment ends at a shaded surface or
// leaves) in final-gather modes, the first NEAR_GATHER_FRACTION of the segment within the
// photons' bounds takes only the caustic photons' beam, and a point and direction drawn there
// for the gather ray (four rng numbers; `depth`: the segment's camera depth). Camera rays
// pass nee = skip_direct = TERM_DIRECT, gather rays take gathered_in_medium instead.
// In a heterogeneous medium the beams read one ratio-tracking walk of the segment (the CPU's
// Medium::transmittances, drawn after single scattering: each beam replays it from a copy of
// rng, and rng passes it once), and the near part's point is a free flight (hetero_track).
fn in_scattered(o: vec3<f32>, d: vec3<f32>, t: f32, endless: bool, medium: u32, nee: bool, skip_direct: bool, near: bool, depth: u32, rng: ptr<function, Rng>) -> SegmentLight {
    let m = load_medium(medium);
    let hetero = HAS_HETERO_MEDIA && m.grid != NO_MEDIUM;
    var s: SegmentLight;
    if nee && max3(m.sigma_s) > 0.0 {
        s.l += single_scattering(o, d, t, endless, medium, rng);
    }
    let which = select(BEAM_ALL, BEAM_SKIP_DIRECT, skip_direct);
    let t_max = select(t, 3.0e38, endless);
    let walk_rng = *rng;
    if hetero && bitcast<u32>(v_grid[2].y) != 0u {
        _ = hetero_transmittance(hetero_record(m), o, d, t_max, rng);
    }
    var zn = 0.0;
    if near && skip_direct && (params.terms & TERM_FINAL_GATHER) != 0u && depth < params.max_depth && max3(m.sigma_s) > 0.0 {
        zn = NEAR_GATHER_FRACTION * min(t_max, volume_exit(o, d));
    }
    // The beams: the whole segment, or its far part (weighed by the transmittance to it)
    // then the near part's caustic photons. One call site: lavapipe compiles each inlined.
    let split = zn > 0.0 && zn < 3.0e38;
    for (var i = 0u; i < select(1u, 2u, split) && spend(); i += 1u) {
        var bo = o;
        var bt = t_max;
        var bw = vec3<f32>(1.0);
        var bwhich = which;
        var off = 0.0;
        if split && i == 0u {
            bo = o + d * zn;
            bt = t_max - zn;
            off = zn;
            if !hetero {
                bw = medium_transmittance(m, zn);
            }
        } else if split {
            bt = zn;
            bwhich = BEAM_CAUSTIC;
        }
        var walk: TrackReplay;
        if hetero {
            walk = replay_start(hetero_record(m), o, d, t_max, walk_rng, off);
        }
        s.l += bw * beam(bo, d, bt, medium, m, bwhich, &walk);
    }
    if !split {
        return s;
    }
    let uc = rng_next(rng);
    let ut = rng_next(rng);
    let u1 = rng_next(rng);
    let u2 = rng_next(rng);
    if hetero {
        let f = hetero_track(hetero_record(m), o, d, zn, rng);
        if f.found {
            s.gather = true;
            s.x = o + d * f.t;
            s.dir = hg_sample(m.g, d, u1, u2);
            s.w = f.tr_over_pdf * f.sigma_s;
        }
        return s;
    }
    let p = sample_in_segment(m, uc, ut, zn, false);
    if p.ok {
        s.gather = true;
        s.x = o + d * p.t;
        s.dir = hg_sample(m.g, d, u1, u2);
        s.w = medium_transmittance(m, p.t) / p.pdf * m.sigma_s;
    }
    return s;
}

// Gatherer::gathered_in_medium: a final-gather ray's in-scattered light along its segment
// from o along d (t long, or endless) in `medium`: the point estimate at GATHER_MEDIUM_POINTS
// distances drawn by transmittance (one channel, the strata of one number), each weighed by
// the transmittance over its density; in a heterogeneous medium free flights (hetero_track,
// one each, none when it leaves the segment: Medium::scatter_in_segment).
fn gathered_in_medium(o: vec3<f32>, d: vec3<f32>, t: f32, endless: bool, medium: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    let uc = rng_next(rng);
    let u = rng_next(rng);
    let m = load_medium(medium);
    let hetero = HAS_HETERO_MEDIA && m.grid != NO_MEDIUM;
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < GATHER_MEDIUM_POINTS; i += 1u) {
        var x = o;
        var w = vec3<f32>(0.0);
        if hetero {
            let f = hetero_track(hetero_record(m), o, d, select(t, 3.0e38, endless), rng);
            if !f.found {
                continue;
            }
            x = o + d * f.t;
            w = f.tr_over_pdf;
        } else {
            let p = sample_in_segment(m, uc, (f32(i) + u) / f32(GATHER_MEDIUM_POINTS), t, endless);
            if !p.ok {
                return vec3<f32>(0.0);
            }
            x = o + d * p.t;
            w = medium_transmittance(m, p.t) / p.pdf;
        }
        sum += w * volume_point(x, -d, medium, m);
    }
    return sum / f32(GATHER_MEDIUM_POINTS);
}
