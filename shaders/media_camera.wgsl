// media_camera: the camera pass's segments through participating media (HAS_MEDIA only), twin
// of src/cpu/gather_media.rs (in_scattered), src/cpu/media.rs (the shadow walk, single
// scattering) and src/cpu/volume_map.rs (the beam estimate over the volume grid). Library of
// the gather and probe kernels; reads the volume map's bindings below, writes nothing but the
// loop budget.

// The volume map: its photons (as traced), the grid's (photon, cell) entries by slot, each
// slot's first entry ([table size] = all), and its layout (volume_grid in common/map.wgsl).
@group(1) @binding(9) var<storage, read> v_photons: array<vec4<u32>>;
@group(1) @binding(10) var<storage, read> v_refs: array<vec4<u32>>;
@group(1) @binding(11) var<storage, read> v_cells: array<u32>;
@group(1) @binding(12) var<storage, read> v_grid: array<vec4<f32>>;

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
// (changing medium there); zero behind any other surface or past MAX_CROSSINGS boundaries.
fn shadow_transmittance(origin: vec3<f32>, dir: vec3<f32>, t_max: f32, endless: bool, medium_in: u32) -> vec3<f32> {
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
            tr *= medium_transmittance(load_medium(medium), run);
        }
        if !hit.found {
            return tr;
        }
        if material_class(load_material(hit.material).kind) != CLASS_NULL {
            return vec3<f32>(0.0);
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

// LightTable::anchor: the point sample_light picks on l for u whatever the shading point
// (a point or spot light's position, an area light's point by area); not ok for
// directional and environment lights.
struct Anchor {
    y: vec3<f32>,
    ok: bool,
}

fn light_anchor(l: Light, u: vec3<f32>) -> Anchor {
    if HAS_ENVIRONMENT && l.kind == LIGHT_ENVIRONMENT {
        return Anchor(vec3<f32>(0.0), false);
    }
    if HAS_POINT_LIGHTS && (l.kind == LIGHT_POINT || l.kind == LIGHT_SPOT) {
        return Anchor(l.position, true);
    }
    if HAS_POINT_LIGHTS && l.kind == LIGHT_DIRECTIONAL {
        return Anchor(vec3<f32>(0.0), false);
    }
    return Anchor(light_point(l, u).p, true);
}

// cpu::media::single_scattering: for each light, a point on it and one distance in the
// segment from o along d (t_seg long, or endless) in `medium` drawn towards that point
// (equiangular; by transmittance for directional lights or a ray through the point), then
// one shadow ray, weighed by the phase function, sigma_s and the transmittance of both
// legs; the environment's direction drawn from the phase function. params.shadow_samples
// estimates per light, averaged, light by light (the CPU's order of random numbers).
fn single_scattering(o: vec3<f32>, d: vec3<f32>, t_seg: f32, endless: bool, medium: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    let m = load_medium(medium);
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
        if !p.ok {
            p = sample_in_segment(m, uc, ut, t_seg, endless);
        }
        if !p.ok {
            continue;
        }
        let x = o + d * p.t;
        let w = medium_transmittance(m, p.t) / p.pdf;
        if HAS_ENVIRONMENT && light.kind == LIGHT_ENVIRONMENT {
            let wi = hg_sample(m.g, d, u3.y, u3.z);
            l += w * env_radiance(light, wi) * shadow_transmittance(x, wi, 3.0e38, true, medium);
            continue;
        }
        let ls = sample_light(light, x, -d, u3);
        if all(ls.weight == vec3<f32>(0.0)) {
            continue;
        }
        let to_light = ls.point - x;
        let dist = length(to_light);
        if !(dist > 0.0) {
            continue;
        }
        let wi = to_light / dist;
        // Light travels along -wi, then on towards the camera (along -d).
        let phase = hg_eval(m.g, dot(wi, d));
        // Stop short of an area light's own surface (as the surfaces' shadow rays do).
        var t_max = dist;
        if !ls.distant && !is_delta_light(light) {
            t_max = dist - OFFSET_SCALE * (max_abs(ls.point) + OFFSET_FLOOR) * 4.0;
        }
        l += w * ls.weight * phase * shadow_transmittance(x, wi, t_max, ls.distant, medium);
    }
    return m.sigma_s * l / f32(n);
}

// Where the DDA leaves cell c along `axis` (infinite where the ray runs parallel to it).
fn dda_boundary(c: vec3<i32>, axis: u32, step: vec3<i32>, lo: vec3<f32>, cell: f32, o: vec3<f32>, inv: vec3<f32>) -> f32 {
    if step[axis] == 0 {
        return 3.4e38;
    }
    let edge = lo[axis] + f32(c[axis] + select(0, 1, step[axis] > 0)) * cell;
    return (edge - o[axis]) * inv[axis];
}

// One beam query's constants: the ray, its part in the photons' bounds [t0, t1), r^2, and
// which photons count (those of `medium`, without depth 0 with skip_direct).
struct BeamQuery {
    o: vec3<f32>,
    d: vec3<f32>,
    t0: f32,
    t1: f32,
    r2: f32,
    medium: u32,
    which: u32,
    m: Medium,
}

// BeamPhotons::keeps: whether a photon of these flags counts in a beam of kind `which`.
fn beam_keeps(which: u32, flags: u32) -> bool {
    if which == BEAM_SKIP_DIRECT {
        return (flags & DEPTH_MASK) != 0u;
    }
    if which == BEAM_CAUSTIC {
        return (flags & FLAG_CAUSTIC) != 0u;
    }
    return true;
}

// Grid entry k's share of the beam in cell c, whose part of the ray is [t_enter, t_exit):
// zero for another cell's entry hashed to the same slot, a photon of another medium or one
// the beam's kind leaves out (beam_keeps), or one whose nearest point on the ray lies outside that part
// (it counts in the cell holding that point) or farther than r.
fn beam_entry(q: BeamQuery, k: u32, c: vec3<i32>, t_enter: f32, t_exit: f32) -> vec3<f32> {
    let e = v_refs[k];
    if any(bitcast<vec3<i32>>(e.yzw) != c) {
        return vec3<f32>(0.0);
    }
    let a = v_photons[PHOTON_WORDS * e.x];
    let w = v_photons[PHOTON_WORDS * e.x + 2u];
    if w.w != q.medium || !beam_keeps(q.which, a.w) {
        return vec3<f32>(0.0);
    }
    let to = bitcast<vec3<f32>>(a.xyz) - q.o;
    let t = dot(to, q.d);
    if t < t_enter || t >= t_exit || t < q.t0 || t >= q.t1 {
        return vec3<f32>(0.0);
    }
    let v = to - q.d * t;
    if dot(v, v) >= q.r2 {
        return vec3<f32>(0.0);
    }
    let phase = hg_eval(q.m.g, dot(bitcast<vec3<f32>>(w.xyz), -q.d));
    let power = bitcast<vec3<f32>>(v_photons[PHOTON_WORDS * e.x + 1u].xyz);
    return medium_transmittance(q.m, t) * phase * power;
}

// Entries k..k+4 (those before `last`) of beam_entry.
fn beam_four(q: BeamQuery, k: u32, last: u32, c: vec3<i32>, t_enter: f32, t_exit: f32) -> vec3<f32> {
    var sum = vec3<f32>(0.0);
    if k < last {
        sum += beam_entry(q, k, c, t_enter, t_exit);
    }
    if k + 1u < last {
        sum += beam_entry(q, k + 1u, c, t_enter, t_exit);
    }
    if k + 2u < last {
        sum += beam_entry(q, k + 2u, c, t_enter, t_exit);
    }
    if k + 3u < last {
        sum += beam_entry(q, k + 3u, c, t_enter, t_exit);
    }
    return sum;
}

// Entries k..k+16 (those before `last`) of beam_entry.
fn beam_sixteen(q: BeamQuery, k: u32, last: u32, c: vec3<i32>, t_enter: f32, t_exit: f32) -> vec3<f32> {
    var sum = beam_four(q, k, last, c, t_enter, t_exit);
    if k + 4u < last {
        sum += beam_four(q, k + 4u, last, c, t_enter, t_exit);
    }
    if k + 8u < last {
        sum += beam_four(q, k + 8u, last, c, t_enter, t_exit);
    }
    if k + 12u < last {
        sum += beam_four(q, k + 12u, last, c, t_enter, t_exit);
    }
    return sum;
}

// VolumeMap::beam: the sum over the volume photons of `medium` whose sphere the segment from
// o along unit d (t_max long) passes through, each at its nearest point t on the ray, of
// T(t) p(cos) power / (pi r^2), over the photons `which` (a BEAM_* code) keeps. A 3D DDA over
// the cells the segment crosses, each photon taken in the cell holding its nearest point.
// A cell's entries are read 64 a loop step: lavapipe's loop cut counts steps, not work.
fn beam(o: vec3<f32>, d: vec3<f32>, t_max: f32, medium: u32, m: Medium, which: u32) -> vec3<f32> {
    let g2 = v_grid[2];
    if bitcast<u32>(g2.y) == 0u {
        return vec3<f32>(0.0);
    }
    let table = bitcast<u32>(g2.x);
    let lo = v_grid[0].xyz;
    let cell = v_grid[0].w;
    let hi = v_grid[1].xyz;
    let r = v_grid[1].w;
    // Clip the segment to the photons' bounds (slab test).
    let inv = 1.0 / d;
    let ta = (lo - o) * inv;
    let tb = (hi - o) * inv;
    let tn = min(ta, tb);
    let tf = max(ta, tb);
    let t0 = max(max(max(tn.x, tn.y), tn.z), 0.0);
    let t1 = min(min(min(tf.x, tf.y), tf.z), t_max);
    if !(t0 < t1) {
        return vec3<f32>(0.0);
    }
    let q = BeamQuery(o, d, t0, t1, r * r, medium, which, m);
    var sum = vec3<f32>(0.0);
    var c = volume_cell(o + d * t0, lo, cell);
    let step = vec3<i32>(sign(d));
    var t_next = vec3<f32>(dda_boundary(c, 0u, step, lo, cell, o, inv), dda_boundary(c, 1u, step, lo, cell, o, inv), dda_boundary(c, 2u, step, lo, cell, o, inv));
    let t_delta = abs(cell * inv);
    var t_enter = t0;
    while spend() {
        var axis = 2u;
        if t_next.x <= t_next.y && t_next.x <= t_next.z {
            axis = 0u;
        } else if t_next.y <= t_next.z {
            axis = 1u;
        }
        let t_exit = min(t_next[axis], t1);
        let h = cell_hash(c, table);
        let last = v_cells[h + 1u];
        for (var k = v_cells[h]; k < last && spend(); k += 64u) {
            sum += beam_sixteen(q, k, last, c, t_enter, t_exit);
            if k + 16u < last {
                sum += beam_sixteen(q, k + 16u, last, c, t_enter, t_exit);
            }
            if k + 32u < last {
                sum += beam_sixteen(q, k + 32u, last, c, t_enter, t_exit);
            }
            if k + 48u < last {
                sum += beam_sixteen(q, k + 48u, last, c, t_enter, t_exit);
            }
        }
        if t_exit >= t1 {
            break;
        }
        t_enter = t_exit;
        c[axis] += step[axis];
        t_next[axis] += t_delta[axis];
    }
    return sum / (PI * q.r2);
}

// VolumeMap::exit: where the ray from o along unit d leaves the volume photons' bounds (0
// where there are none or it never meets them).
fn volume_exit(o: vec3<f32>, d: vec3<f32>) -> f32 {
    if bitcast<u32>(v_grid[2].y) == 0u {
        return 0.0;
    }
    let inv = 1.0 / d;
    let tf = max((v_grid[0].xyz - o) * inv, (v_grid[1].xyz - o) * inv);
    return max(min(min(tf.x, tf.y), tf.z), 0.0);
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
fn in_scattered(o: vec3<f32>, d: vec3<f32>, t: f32, endless: bool, medium: u32, nee: bool, skip_direct: bool, near: bool, depth: u32, rng: ptr<function, Rng>) -> SegmentLight {
    let m = load_medium(medium);
    var s: SegmentLight;
    if nee && max3(m.sigma_s) > 0.0 {
        s.l += single_scattering(o, d, t, endless, medium, rng);
    }
    let which = select(BEAM_ALL, BEAM_SKIP_DIRECT, skip_direct);
    let t_max = select(t, 3.0e38, endless);
    var zn = 0.0;
    if near && skip_direct && (params.terms & TERM_FINAL_GATHER) != 0u && depth < params.max_depth && max3(m.sigma_s) > 0.0 {
        zn = NEAR_GATHER_FRACTION * min(t_max, volume_exit(o, d));
    }
    if !(zn > 0.0 && zn < 3.0e38) {
        s.l += beam(o, d, t_max, medium, m, which);
        return s;
    }
    s.l += medium_transmittance(m, zn) * beam(o + d * zn, d, t_max - zn, medium, m, which);
    s.l += beam(o, d, zn, medium, m, BEAM_CAUSTIC);
    let uc = rng_next(rng);
    let ut = rng_next(rng);
    let u1 = rng_next(rng);
    let u2 = rng_next(rng);
    let p = sample_in_segment(m, uc, ut, zn, false);
    if p.ok {
        s.gather = true;
        s.x = o + d * p.t;
        s.dir = hg_sample(m.g, d, u1, u2);
        s.w = medium_transmittance(m, p.t) / p.pdf * m.sigma_s;
    }
    return s;
}

// VolumeMap::point: the sum over the volume photons of `medium` within r of x of
// p(cos) power / (4/3 pi r^3), cos between the photon's travel and wo; one cell's entries
// (every photon within r of x is listed in x's cell).
fn volume_point(x: vec3<f32>, wo: vec3<f32>, medium: u32, m: Medium) -> vec3<f32> {
    let g2 = v_grid[2];
    let lo = v_grid[0].xyz;
    let hi = v_grid[1].xyz;
    if bitcast<u32>(g2.y) == 0u || any(x < lo) || any(x > hi) {
        return vec3<f32>(0.0);
    }
    let cell = v_grid[0].w;
    let r = v_grid[1].w;
    let c = volume_cell(x, lo, cell);
    let h = cell_hash(c, bitcast<u32>(g2.x));
    let last = v_cells[h + 1u];
    var sum = vec3<f32>(0.0);
    for (var k = v_cells[h]; k < last && spend(); k += 1u) {
        let e = v_refs[k];
        if any(bitcast<vec3<i32>>(e.yzw) != c) {
            continue;
        }
        let a = v_photons[PHOTON_WORDS * e.x];
        let w = v_photons[PHOTON_WORDS * e.x + 2u];
        let v = bitcast<vec3<f32>>(a.xyz) - x;
        if w.w != medium || dot(v, v) >= r * r {
            continue;
        }
        let power = bitcast<vec3<f32>>(v_photons[PHOTON_WORDS * e.x + 1u].xyz);
        sum += hg_eval(m.g, dot(bitcast<vec3<f32>>(w.xyz), wo)) * power;
    }
    return sum * (3.0 / (4.0 * PI * r * r * r));
}

// Gatherer::gathered_in_medium: a final-gather ray's in-scattered light along its segment
// from o along d (t long, or endless) in `medium`: the point estimate at GATHER_MEDIUM_POINTS
// distances drawn by transmittance (one channel, the strata of one number), each weighed by
// the transmittance over its density.
fn gathered_in_medium(o: vec3<f32>, d: vec3<f32>, t: f32, endless: bool, medium: u32, rng: ptr<function, Rng>) -> vec3<f32> {
    let uc = rng_next(rng);
    let u = rng_next(rng);
    let m = load_medium(medium);
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < GATHER_MEDIUM_POINTS; i += 1u) {
        let p = sample_in_segment(m, uc, (f32(i) + u) / f32(GATHER_MEDIUM_POINTS), t, endless);
        if !p.ok {
            return vec3<f32>(0.0);
        }
        sum += medium_transmittance(m, p.t) / p.pdf * volume_point(o + d * p.t, -d, medium, m);
    }
    return sum / f32(GATHER_MEDIUM_POINTS);
}
