// Heterogeneous media (issue 41): twin of src/media/grid.rs (a volume's lookup),
// src/media/majorant.rs (the majorant grid's DDA walk) and src/media/heterogeneous.rs (the
// extinction and albedo at a point, ratio tracking, delta tracking), reading the records
// src/media/gpu.rs appends to `media`. Callers are behind HAS_HETERO_MEDIA, so other scenes
// compile none of it. Library, no entry point; writes nothing.

// Word i of `media` read flat (component i % 4 of vec4 i / 4), as f32, as u32, and three on.
fn media_f32(i: u32) -> f32 {
    return media[i >> 2u][i & 3u];
}

fn media_u32(i: u32) -> u32 {
    return bitcast<u32>(media_f32(i));
}

fn media_vec3(i: u32) -> vec3<f32> {
    return vec3<f32>(media_f32(i), media_f32(i + 1u), media_f32(i + 2u));
}

// The flat word of a heterogeneous medium's record (m.grid is its vec4 index).
fn hetero_record(m: Medium) -> u32 {
    return 4u * m.grid;
}

// VolumeGrid::voxel: voxel (x, y, z) of a grid of resolution n whose data starts at word
// `data`, as RGB (`three` channels, else one: its value in all three). Branch-free (a
// one-channel grid's word read three times): a lookup inlines eight of these.
fn volume_voxel(data: u32, n: vec3<u32>, three: bool, x: u32, y: u32, z: u32) -> vec3<f32> {
    let s = select(0u, 1u, three);
    let i = data + ((z * n.y + y) * n.x + x) * (1u + 2u * s);
    return vec3<f32>(media_f32(i), media_f32(i + s), media_f32(i + 2u * s));
}

// VolumeGrid::lookup's clamp: index i (a whole number) clamped to 0..=last.
fn volume_index(i: f32, last: u32) -> u32 {
    return u32(clamp(i, 0.0, f32(last)));
}

// VolumeGrid::lookup: the filtered value at p in the grid's unit cube (outside it, the
// nearest edge's). The trilinear sum is unrolled in the CPU's order (z, then y, then x), so
// it needs no loop.
fn grid_lookup(v: u32, p: vec3<f32>) -> vec3<f32> {
    let n = vec3<u32>(media_u32(v + VOLUME_RES), media_u32(v + VOLUME_RES + 1u), media_u32(v + VOLUME_RES + 2u));
    let res = vec3<f32>(n);
    let last = n - vec3<u32>(1u);
    let data = media_u32(v + VOLUME_DATA);
    let three = media_u32(v + VOLUME_CHANNELS) != 1u;
    if media_u32(v + VOLUME_FILTER) == FILTER_NEAREST {
        let i = floor(p * res);
        return volume_voxel(data, n, three, volume_index(i.x, last.x), volume_index(i.y, last.y), volume_index(i.z, last.z));
    }
    let pos = p * res - 0.5;
    let i0 = floor(pos);
    let f = pos - i0;
    let g = vec3<f32>(1.0) - f;
    let x0 = volume_index(i0.x, last.x);
    let x1 = volume_index(i0.x + 1.0, last.x);
    let y0 = volume_index(i0.y, last.y);
    let y1 = volume_index(i0.y + 1.0, last.y);
    let z0 = volume_index(i0.z, last.z);
    let z1 = volume_index(i0.z + 1.0, last.z);
    var value = vec3<f32>(0.0);
    value += volume_voxel(data, n, three, x0, y0, z0) * (g.x * g.y * g.z);
    value += volume_voxel(data, n, three, x1, y0, z0) * (f.x * g.y * g.z);
    value += volume_voxel(data, n, three, x0, y1, z0) * (g.x * f.y * g.z);
    value += volume_voxel(data, n, three, x1, y1, z0) * (f.x * f.y * g.z);
    value += volume_voxel(data, n, three, x0, y0, z1) * (g.x * g.y * f.z);
    value += volume_voxel(data, n, three, x1, y0, z1) * (f.x * g.y * f.z);
    value += volume_voxel(data, n, three, x0, y1, z1) * (g.x * f.y * f.z);
    value += volume_voxel(data, n, three, x1, y1, z1) * (f.x * f.y * f.z);
    return value;
}

// Volume::eval: the value at world point x of the volume whose record starts at word v.
fn volume_eval(v: u32, x: vec3<f32>) -> vec3<f32> {
    if media_u32(v + VOLUME_KIND) == VOLUME_CONSTANT {
        return media_vec3(v + VOLUME_VALUE);
    }
    let m = v + VOLUME_TO_LOCAL;
    let p = media_vec3(m) * x.x + media_vec3(m + 3u) * x.y + media_vec3(m + 6u) * x.z + media_vec3(m + 9u);
    return grid_lookup(v, p);
}

// Heterogeneous::sigma_t_at: the extinction at x per channel (zero outside the extinction
// volume's box) of the medium whose record starts at word h.
fn hetero_sigma_t_at(h: u32, x: vec3<f32>) -> vec3<f32> {
    let v = h + HETERO_SIGMA_T;
    if all(x >= media_vec3(v + VOLUME_LO)) && all(x <= media_vec3(v + VOLUME_HI)) {
        return media_f32(h + HETERO_SCALE) * volume_eval(v, x);
    }
    return vec3<f32>(0.0);
}

// Heterogeneous::sigma_s_at: the albedo at x times the extinction.
fn hetero_sigma_s_at(h: u32, x: vec3<f32>) -> vec3<f32> {
    return hetero_sigma_t_at(h, x) * volume_eval(h + HETERO_ALBEDO, x);
}

// Heterogeneous::span: the part (t0, t1) of [0, t_max) of the ray from o along unit d inside
// the extinction's box; t0 >= t1 where it misses or the majorant is zero.
fn hetero_span(h: u32, o: vec3<f32>, d: vec3<f32>, t_max: f32) -> vec2<f32> {
    if media_f32(h + HETERO_MAJORANT) <= 0.0 {
        return vec2<f32>(1.0, 0.0);
    }
    let inv = 1.0 / d;
    let a = (media_vec3(h + HETERO_SIGMA_T + VOLUME_LO) - o) * inv;
    let b = (media_vec3(h + HETERO_SIGMA_T + VOLUME_HI) - o) * inv;
    let near = min(a, b);
    let far = max(a, b);
    let t0 = max(max(near.x, max(near.y, near.z)), 0.0);
    let t1 = min(min(far.x, min(far.y, far.z)), t_max);
    return vec2<f32>(t0, t1);
}

// MajorantGrid::walk's state: the cell c, the distances to its next boundary per axis, and
// where the cell majorant_walk_next last found spans [a, b) with majorant mu.
struct MajorantWalk {
    n: vec3<i32>,
    cells: u32,
    c: vec3<i32>,
    step: vec3<i32>,
    t_next: vec3<f32>,
    t_delta: vec3<f32>,
    ta: f32,
    t1: f32,
    // Cells left to visit (n.x + n.y + n.z at most: a ray crosses one cell per axis step);
    // 0 once the walk is done.
    left: u32,
    single: bool,
    // The loop budget ran out (the walk counts as absorbed).
    exhausted: bool,
    a: f32,
    b: f32,
    mu: f32,
}

// MajorantGrid::walk's set-up: the walk over [t0, t1) of the ray from o along unit d
// through the majorant grid of the medium whose record starts at word h.
fn majorant_walk_start(h: u32, o: vec3<f32>, d: vec3<f32>, t0: f32, t1: f32) -> MajorantWalk {
    var w: MajorantWalk;
    let res = vec3<u32>(media_u32(h + HETERO_CELLS_RES), media_u32(h + HETERO_CELLS_RES + 1u), media_u32(h + HETERO_CELLS_RES + 2u));
    w.n = vec3<i32>(res);
    w.cells = media_u32(h + HETERO_CELLS);
    w.ta = t0;
    w.t1 = t1;
    w.single = res.x * res.y * res.z == 1u;
    w.left = select(res.x + res.y + res.z, 1u, w.single);
    w.exhausted = false;
    let lo = media_vec3(h + HETERO_CELLS_LO);
    let size = media_vec3(h + HETERO_CELL_SIZE);
    let p = o + d * t0;
    let c = clamp(floor((p - lo) / size), vec3<f32>(0.0), vec3<f32>(w.n - vec3<i32>(1)));
    w.c = vec3<i32>(c);
    w.step = vec3<i32>(sign(d));
    let inv = 1.0 / d;
    let up = select(vec3<i32>(0), vec3<i32>(1), w.step > vec3<i32>(0));
    let edge = lo + vec3<f32>(w.c + up) * size;
    w.t_next = select((edge - o) * inv, vec3<f32>(3.0e38), w.step == vec3<i32>(0));
    w.t_delta = abs(size * inv);
    return w;
}

// MajorantGrid::walk, one cell per call: true with the next cell's span [a, b) (non-empty)
// and majorant mu; false when the walk is done or the loop budget ran out (exhausted).
fn majorant_walk_next(w: ptr<function, MajorantWalk>) -> bool {
    if (*w).single {
        if (*w).left == 0u {
            return false;
        }
        (*w).left = 0u;
        (*w).a = (*w).ta;
        (*w).b = (*w).t1;
        (*w).mu = media_f32((*w).cells);
        return true;
    }
    while (*w).left > 0u {
        if !spend() {
            (*w).exhausted = true;
            return false;
        }
        (*w).left -= 1u;
        let t = (*w).t_next;
        var axis = 2u;
        if t.x <= t.y && t.x <= t.z {
            axis = 0u;
        } else if t.y <= t.z {
            axis = 1u;
        }
        let tb = min(t[axis], (*w).t1);
        let ta = (*w).ta;
        let c = (*w).c;
        let n = (*w).n;
        let mu = media_f32((*w).cells + u32((c.z * n.y + c.y) * n.x + c.x));
        if tb >= (*w).t1 {
            (*w).left = 0u;
        } else {
            (*w).ta = max(ta, tb);
            let next = c[axis] + (*w).step[axis];
            (*w).c[axis] = next;
            if next < 0 || next >= n[axis] {
                (*w).left = 0u;
            } else {
                (*w).t_next[axis] += (*w).t_delta[axis];
            }
        }
        if tb > ta {
            (*w).a = ta;
            (*w).b = tb;
            (*w).mu = mu;
            return true;
        }
    }
    return false;
}

// Heterogeneous::collisions' state: the tentative collision last drawn (distance s, its
// cell's majorant mu), how many were drawn, whether the walk's current cell is being drawn
// in, and whether the walk ran out (more than MAX_TRACKING_STEPS collisions, or the loop
// budget): such a walk counts as absorbed, as on the CPU.
struct Tracking {
    s: f32,
    mu: f32,
    steps: u32,
    in_cell: bool,
    exhausted: bool,
}

// Heterogeneous::collisions, one tentative collision per call (fresh exponential steps from
// each cell's entry, none in an empty cell, one number per step as the CPU draws them): true
// with (*k).s and (*k).mu; false when the walk w is done or ran out ((*k).exhausted).
fn tracking_next(w: ptr<function, MajorantWalk>, k: ptr<function, Tracking>, rng: ptr<function, Rng>) -> bool {
    loop {
        if !spend() {
            (*k).exhausted = true;
            return false;
        }
        if !(*k).in_cell {
            if !majorant_walk_next(w) {
                (*k).exhausted = (*w).exhausted;
                return false;
            }
            if (*w).mu <= 0.0 {
                continue;
            }
            (*k).in_cell = true;
            (*k).s = (*w).a;
        }
        (*k).s -= log(1.0 - rng_next(rng)) / (*w).mu;
        if (*k).s >= (*w).b {
            (*k).in_cell = false;
            continue;
        }
        (*k).steps += 1u;
        if (*k).steps > MAX_TRACKING_STEPS {
            (*k).exhausted = true;
            return false;
        }
        (*k).mu = (*w).mu;
        return true;
    }
    return false;
}

// Heterogeneous::transmittance: an unbiased estimate of the transmittance over [0, t) of
// the ray from o along unit d (ratio tracking, Russian roulette below ROULETTE_BELOW); zero
// for a walk that ran out. Each step of the loop spends the budget in tracking_next.
fn hetero_transmittance(h: u32, o: vec3<f32>, d: vec3<f32>, t: f32, rng: ptr<function, Rng>) -> vec3<f32> {
    let span = hetero_span(h, o, d, t);
    if !(span.x < span.y) {
        return vec3<f32>(1.0);
    }
    var w = majorant_walk_start(h, o, d, span.x, span.y);
    var k = Tracking(0.0, 0.0, 0u, false, false);
    var tr = vec3<f32>(1.0);
    while tracking_next(&w, &k, rng) {
        // The cell's majorant bounds the density; the max absorbs the filter's rounding.
        tr *= max(vec3<f32>(1.0) - hetero_sigma_t_at(h, o + d * k.s) / k.mu, vec3<f32>(0.0));
        let q = max(tr.x, max(tr.y, tr.z));
        if q < ROULETTE_BELOW {
            tr = select(vec3<f32>(0.0), tr / q, rng_next(rng) < q);
        }
        if all(tr == vec3<f32>(0.0)) {
            break;
        }
    }
    if k.exhausted {
        return vec3<f32>(0.0);
    }
    return tr;
}

// Heterogeneous::track's result: an event (found) at t with T / pdf and sigma_s there, or
// the weight of a flight that passed the segment.
struct HeteroScatter {
    found: bool,
    t: f32,
    tr_over_pdf: vec3<f32>,
    sigma_s: vec3<f32>,
    weight: vec3<f32>,
}

// Heterogeneous::track: delta tracking with spectral-tracking weights over [0, t_max) of the
// ray from o along unit d (history-aware: w the weight so far). A tentative collision is real
// with probability P = sum(w sigma_t) / (majorant sum(w)), weighing w / (majorant P); a null
// one multiplies w by (majorant - sigma_t) / (majorant (1 - P)), keeping sum(w) at 3.
fn hetero_track(h: u32, o: vec3<f32>, d: vec3<f32>, t_max: f32, rng: ptr<function, Rng>) -> HeteroScatter {
    let none = HeteroScatter(false, t_max, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(1.0));
    let span = hetero_span(h, o, d, t_max);
    if !(span.x < span.y) {
        return none;
    }
    var w = majorant_walk_start(h, o, d, span.x, span.y);
    var k = Tracking(0.0, 0.0, 0u, false, false);
    var weight = vec3<f32>(1.0);
    while tracking_next(&w, &k, rng) {
        let x = o + d * k.s;
        let sigma = hetero_sigma_t_at(h, x);
        let ws = weight * sigma;
        let p_real = min((ws.x + ws.y + ws.z) / (k.mu * (weight.x + weight.y + weight.z)), 1.0);
        if rng_next(rng) < p_real {
            let sigma_s = sigma * volume_eval(h + HETERO_ALBEDO, x);
            return HeteroScatter(true, k.s, weight / (k.mu * p_real), sigma_s, vec3<f32>(0.0));
        }
        weight *= max(vec3<f32>(k.mu) - sigma, vec3<f32>(0.0)) / (k.mu * (1.0 - p_real));
    }
    if k.exhausted {
        weight = vec3<f32>(0.0);
    }
    return HeteroScatter(false, t_max, vec3<f32>(0.0), vec3<f32>(0.0), weight);
}

// Heterogeneous::sample_flight: a free flight towards a surface t_max away (a miss passes a
// t_max beyond every flight): an event weighs sigma_s T / pdf, a pass the tracking's weight.
fn hetero_sample_flight(h: u32, o: vec3<f32>, d: vec3<f32>, t_max: f32, rng: ptr<function, Rng>) -> Flight {
    let s = hetero_track(h, o, d, t_max, rng);
    if s.found {
        return Flight(s.t, true, s.tr_over_pdf * s.sigma_s);
    }
    return Flight(t_max, false, s.weight);
}

// Transmittances::Steps on the device: one ratio-tracking walk (Heterogeneous::steps, the
// CPU's numbers in its order) replayed along a beam in order of distance, where the CPU
// records every step. The walk runs from o over [0, t_max); its distances read s - off (a
// beam from o + off d: Transmittances::split). `pending`: the step at (k.s, k.mu) is drawn
// and not applied yet; `zero`: that step is where the walk ran out (it ends at zero).
struct TrackReplay {
    w: MajorantWalk,
    k: Tracking,
    rng: Rng,
    h: u32,
    o: vec3<f32>,
    d: vec3<f32>,
    off: f32,
    tr: vec3<f32>,
    pending: bool,
    zero: bool,
}

// At most BEAM_CHUNK steps of a replay, in order (distances s - off in s.xyzw then u.xyzw,
// beyond every distance where unused; the estimate after each in t0..t7) and the estimate
// before the first: what a beam reads over one part of a cell. Fields, not an array: a
// beam reads it in every one of its unrolled entries, and lavapipe compiles a private
// array's dynamic index there into far more code.
const BEAM_CHUNK: u32 = 8u;
struct ReplaySteps {
    n: u32,
    before: vec3<f32>,
    s: vec4<f32>,
    u: vec4<f32>,
    t0: vec3<f32>,
    t1: vec3<f32>,
    t2: vec3<f32>,
    t3: vec3<f32>,
    t4: vec3<f32>,
    t5: vec3<f32>,
    t6: vec3<f32>,
    t7: vec3<f32>,
}

// Draws the replay's next step (tracking_next), noting a walk that ran out as a last step.
// (The walk's parts are copied: naga 30's SPIR-V writer fails on a pointer to a member
// passed on as an argument.)
fn replay_draw(r: ptr<function, TrackReplay>) {
    var w = (*r).w;
    var k = (*r).k;
    var rng = (*r).rng;
    let next = tracking_next(&w, &k, &rng);
    (*r).w = w;
    (*r).k = k;
    (*r).rng = rng;
    (*r).zero = !next && k.exhausted;
    (*r).pending = next || (*r).zero;
}

// Heterogeneous::steps' walk from o along unit d over [0, t_max) on a copy of rng, its
// distances read less `off`.
fn replay_start(h: u32, o: vec3<f32>, d: vec3<f32>, t_max: f32, rng: Rng, off: f32) -> TrackReplay {
    var r: TrackReplay;
    r.h = h;
    r.o = o;
    r.d = d;
    r.off = off;
    r.rng = rng;
    r.tr = vec3<f32>(1.0);
    r.k = Tracking(0.0, 0.0, 0u, false, false);
    let span = hetero_span(h, o, d, t_max);
    if span.x < span.y {
        r.w = majorant_walk_start(h, o, d, span.x, span.y);
        replay_draw(&r);
    }
    return r;
}

// Applies the pending step as hetero_transmittance does (ratio, roulette), then draws the
// next; a step that leaves the estimate at zero ends the walk.
fn replay_apply(r: ptr<function, TrackReplay>) {
    if (*r).zero {
        (*r).tr = vec3<f32>(0.0);
        (*r).pending = false;
        return;
    }
    let x = (*r).o + (*r).d * (*r).k.s;
    (*r).tr *= max(vec3<f32>(1.0) - hetero_sigma_t_at((*r).h, x) / (*r).k.mu, vec3<f32>(0.0));
    let q = max((*r).tr.x, max((*r).tr.y, (*r).tr.z));
    if q < ROULETTE_BELOW {
        var rng = (*r).rng;
        (*r).tr = select(vec3<f32>(0.0), (*r).tr / q, rng_next(&rng) < q);
        (*r).rng = rng;
    }
    if all((*r).tr == vec3<f32>(0.0)) {
        (*r).pending = false;
    } else {
        replay_draw(r);
    }
}

// The pending step's distance as the beam reads it (beyond every distance when none).
fn replay_next(r: ptr<function, TrackReplay>) -> f32 {
    return select(3.4e38, (*r).k.s - (*r).off, (*r).pending);
}

// Applies the steps before `until` (beam distance) without recording them.
fn replay_skip(r: ptr<function, TrackReplay>, until: f32) {
    while replay_next(r) < until && spend() {
        replay_apply(r);
    }
}

// Chunk step j (< BEAM_CHUNK) set to distance s and estimate tr.
fn replay_set(c: ptr<function, ReplaySteps>, j: u32, s: f32, tr: vec3<f32>) {
    switch j {
        case 0u: { (*c).s.x = s; (*c).t0 = tr; }
        case 1u: { (*c).s.y = s; (*c).t1 = tr; }
        case 2u: { (*c).s.z = s; (*c).t2 = tr; }
        case 3u: { (*c).s.w = s; (*c).t3 = tr; }
        case 4u: { (*c).u.x = s; (*c).t4 = tr; }
        case 5u: { (*c).u.y = s; (*c).t5 = tr; }
        case 6u: { (*c).u.z = s; (*c).t6 = tr; }
        default: { (*c).u.w = s; (*c).t7 = tr; }
    }
}

// Applies the next steps before `until`, at most BEAM_CHUNK, recording them in c (a step
// left pending before `until` starts the next chunk).
fn replay_fill(r: ptr<function, TrackReplay>, until: f32, c: ptr<function, ReplaySteps>) {
    (*c).n = 0u;
    (*c).before = (*r).tr;
    (*c).s = vec4<f32>(3.4e38);
    (*c).u = vec4<f32>(3.4e38);
    while (*c).n < BEAM_CHUNK && replay_next(r) < until && spend() {
        let s = replay_next(r);
        replay_apply(r);
        replay_set(c, (*c).n, s, (*r).tr);
        (*c).n += 1u;
    }
}

// Transmittances::at within a chunk: the estimate after the last step at or before t (the
// steps are in order, so the last that passes wins).
fn replay_at(c: ReplaySteps, t: f32) -> vec3<f32> {
    var tr = c.before;
    tr = select(tr, c.t0, c.s.x <= t);
    tr = select(tr, c.t1, c.s.y <= t);
    tr = select(tr, c.t2, c.s.z <= t);
    tr = select(tr, c.t3, c.s.w <= t);
    tr = select(tr, c.t4, c.u.x <= t);
    tr = select(tr, c.t5, c.u.y <= t);
    tr = select(tr, c.t6, c.u.z <= t);
    return select(tr, c.t7, c.u.w <= t);
}
