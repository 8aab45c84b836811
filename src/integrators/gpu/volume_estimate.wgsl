// volume_estimate: the volume photon map's estimates over its grid (HAS_MEDIA only), twin of
// src/integrators/cpu/volume_map.rs: the beam estimate along a camera segment, the point estimate of a
// final-gather ray and the photons' exit distance. Sums are exact in fixed point, so an
// estimate does not depend on the order the grid lists its photons in. Library of the gather
// and probe kernels; reads the volume map's bindings, writes nothing but the loop budget.

// The volume map: its photons (as traced), the grid's (photon, cell) entries by slot, each
// slot's first entry ([table size] = all), and its layout (volume_grid in common/map.wgsl).
@group(1) @binding(9) var<storage, read> v_photons: array<vec4<u32>>;
@group(1) @binding(10) var<storage, read> v_refs: array<vec4<u32>>;
@group(1) @binding(11) var<storage, read> v_cells: array<u32>;
@group(1) @binding(12) var<storage, read> v_grid: array<vec4<f32>>;

// Where the DDA leaves cell c along `axis` (infinite where the ray runs parallel to it).
fn dda_boundary(c: vec3<i32>, axis: u32, step: vec3<i32>, lo: vec3<f32>, cell: f32, o: vec3<f32>, inv: vec3<f32>) -> f32 {
    if step[axis] == 0 {
        return 3.4e38;
    }
    let edge = lo[axis] + f32(c[axis] + select(0, 1, step[axis] > 0)) * cell;
    return (edge - o[axis]) * inv[axis];
}

// One beam query's constants: the ray, its part in the photons' bounds [t0, t1), r^2,
// which photons count (those of `medium` that `which` keeps) and the fixed-point scale.
struct BeamQuery {
    o: vec3<f32>,
    d: vec3<f32>,
    t0: f32,
    t1: f32,
    r2: f32,
    medium: u32,
    which: u32,
    m: Medium,
    scale: f32,
    // The medium is heterogeneous: transmittances from a replayed walk's chunk.
    hetero: bool,
}

// The volume estimates' terms T p power are at most the phase's largest value (forward for
// g > 0; float operations are monotone, so no term exceeds it) times the map's largest power
// channel (size_volume). Their fixed-point sums (FixedSum) count multiples of bound / one.
fn volume_bound(m: Medium) -> f32 {
    return hg_eval(m.g, sign(m.g)) * v_grid[2].z;
}
// The beam's unit: a term is at most 2^27 of them, so 16 add up within a u32.
const BEAM_ONE: f32 = 134217728.0;
// The point estimate's unit, 2^30 (terms are added one by one).
const POINT_ONE: f32 = 1073741824.0;

// v s rounded to an integer (v s below 2^31): through i32, which CPUs convert to natively.
fn fixed_term(v: vec3<f32>, s: f32) -> vec3<u32> {
    return bitcast<vec3<u32>>(vec3<i32>(v * s + 0.5));
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

// Grid entry k's share of the beam in cell c, whose part of the ray is [t_enter, t_exit), in
// units of q.scale: zero for another cell's entry hashed to the same slot, a photon of another
// medium or one the beam's kind leaves out (beam_keeps), or one whose nearest point on the ray
// lies outside that part (it counts in the cell holding that point) or farther than r. A
// heterogeneous medium's transmittance is read from st, the walk's steps over that part.
fn beam_entry(q: BeamQuery, k: u32, c: vec3<i32>, t_enter: f32, t_exit: f32, st: ReplaySteps) -> vec3<u32> {
    let e = v_refs[k];
    if any(bitcast<vec3<i32>>(e.yzw) != c) {
        return vec3<u32>(0u);
    }
    let a = v_photons[PHOTON_WORDS * e.x];
    let w = v_photons[PHOTON_WORDS * e.x + 2u];
    if w.w != q.medium || !beam_keeps(q.which, a.w) {
        return vec3<u32>(0u);
    }
    let to = bitcast<vec3<f32>>(a.xyz) - q.o;
    let t = dot(to, q.d);
    if t < t_enter || t >= t_exit || t < q.t0 || t >= q.t1 {
        return vec3<u32>(0u);
    }
    let v = to - q.d * t;
    if dot(v, v) >= q.r2 {
        return vec3<u32>(0u);
    }
    let phase = hg_eval(q.m.g, dot(bitcast<vec3<f32>>(w.xyz), -q.d));
    let power = bitcast<vec3<f32>>(v_photons[PHOTON_WORDS * e.x + 1u].xyz);
    if HAS_HETERO_MEDIA && q.hetero {
        return fixed_term(replay_at(st, t) * power, phase * q.scale);
    }
    return fixed_term(medium_transmittance(q.m, t) * power, phase * q.scale);
}

// Entries k..k+4 (those before `last`) of beam_entry.
fn beam_four(q: BeamQuery, k: u32, last: u32, c: vec3<i32>, t_enter: f32, t_exit: f32, st: ReplaySteps) -> vec3<u32> {
    var sum = vec3<u32>(0u);
    if k < last {
        sum += beam_entry(q, k, c, t_enter, t_exit, st);
    }
    if k + 1u < last {
        sum += beam_entry(q, k + 1u, c, t_enter, t_exit, st);
    }
    if k + 2u < last {
        sum += beam_entry(q, k + 2u, c, t_enter, t_exit, st);
    }
    if k + 3u < last {
        sum += beam_entry(q, k + 3u, c, t_enter, t_exit, st);
    }
    return sum;
}

// Entries k..k+16 (those before `last`) of beam_entry.
fn beam_sixteen(q: BeamQuery, k: u32, last: u32, c: vec3<i32>, t_enter: f32, t_exit: f32, st: ReplaySteps) -> vec3<u32> {
    var sum = beam_four(q, k, last, c, t_enter, t_exit, st);
    if k + 4u < last {
        sum += beam_four(q, k + 4u, last, c, t_enter, t_exit, st);
    }
    if k + 8u < last {
        sum += beam_four(q, k + 8u, last, c, t_enter, t_exit, st);
    }
    if k + 12u < last {
        sum += beam_four(q, k + 12u, last, c, t_enter, t_exit, st);
    }
    return sum;
}

// VolumeMap::beam: the sum over the volume photons of `medium` whose sphere the segment from
// o along unit d (t_max long) passes through, each at its nearest point t on the ray, of
// T(t) p(cos) power / (pi r^2), over the photons `which` (a BEAM_* code) keeps. A 3D DDA over
// the cells the segment crosses, each photon taken in the cell holding its nearest point, summed
// in fixed point (volume_bound). A cell's entries are read 64 a loop step: lavapipe's loop cut
// counts steps, not work (the 64 go through one copy of 16 entries: inlined code is lavapipe's
// compile time). In a heterogeneous medium T(t) is `walk`'s (Transmittances::Steps:
// the one ratio-tracking walk of the segment, replayed), read a chunk of its steps at a time:
// a cell whose part of the ray holds more than BEAM_CHUNK steps reads its entries once per
// chunk, each time for the photons whose nearest point lies in that chunk's part.
fn beam(o: vec3<f32>, d: vec3<f32>, t_max: f32, medium: u32, m: Medium, which: u32, walk: ptr<function, TrackReplay>) -> vec3<f32> {
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
    let bound = volume_bound(m);
    if !(bound > 1e-30) {
        return vec3<f32>(0.0);
    }
    let hetero = HAS_HETERO_MEDIA && m.grid != NO_MEDIUM;
    let q = BeamQuery(o, d, t0, t1, r * r, medium, which, m, BEAM_ONE / bound, hetero);
    var st: ReplaySteps;
    if hetero {
        replay_skip(walk, t0);
    }
    var sum = FixedSum();
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
        // The cell's part [lo, hi): all of it, or a chunk of the walk's steps at a time.
        var lo = t_enter;
        loop {
            var hi = t_exit;
            if hetero {
                replay_fill(walk, t_exit, &st);
                hi = min(replay_next(walk), t_exit);
            }
            for (var k = v_cells[h]; k < last && spend(); k += 64u) {
                // Four runs of 16 through one inlined copy of beam_sixteen: a loop of four
                // steps, not counted by the budget (spend) nor near lavapipe's cut.
                for (var j = 0u; j < 64u; j += 16u) {
                    if k + j < last {
                        sum = fixed_add(sum, beam_sixteen(q, k + j, last, c, lo, hi, st));
                    }
                }
            }
            if hi >= t_exit || !spend() {
                break;
            }
            lo = hi;
        }
        if t_exit >= t1 {
            break;
        }
        t_enter = t_exit;
        c[axis] += step[axis];
        t_next[axis] += t_delta[axis];
    }
    return fixed_value(sum) * (bound / BEAM_ONE) / (PI * q.r2);
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

// VolumeMap::point: the sum over the volume photons of `medium` within R of x (R =
// POINT_RADIUS_FACTOR r) of p(cos) power / (4/3 pi R^3), cos between the photon's travel and
// wo; the cells x's box of half-width r overlaps (at most 2 an axis: every photon within R <= 2r
// is listed in one), each photon counted in one of them alone (the larger, componentwise, of
// its box's lowest cell and x's), summed in fixed point (volume_bound).
fn volume_point(x: vec3<f32>, wo: vec3<f32>, medium: u32, m: Medium) -> vec3<f32> {
    let g2 = v_grid[2];
    let lo = v_grid[0].xyz;
    let hi = v_grid[1].xyz;
    if bitcast<u32>(g2.y) == 0u || any(x < lo) || any(x > hi) {
        return vec3<f32>(0.0);
    }
    let cell = v_grid[0].w;
    let r1 = v_grid[1].w;
    let r = POINT_RADIUS_FACTOR * r1;
    let bound = volume_bound(m);
    if !(bound > 1e-30) {
        return vec3<f32>(0.0);
    }
    let scale = POINT_ONE / bound;
    let a = volume_cell(x - vec3<f32>(r1), lo, cell);
    let b = volume_cell(x + vec3<f32>(r1), lo, cell);
    var sum = FixedSum();
    // At most 8 cells (a cell is no narrower than 2r).
    for (var n = 0; n < 8; n += 1) {
        let c = a + vec3<i32>(n % 2, (n / 2) % 2, n / 4);
        if any(c > b) {
            continue;
        }
        let h = cell_hash(c, bitcast<u32>(g2.x));
        let last = v_cells[h + 1u];
        for (var k = v_cells[h]; k < last && spend(); k += 1u) {
            let e = v_refs[k];
            if any(bitcast<vec3<i32>>(e.yzw) != c) {
                continue;
            }
            let q = bitcast<vec3<f32>>(v_photons[PHOTON_WORDS * e.x].xyz);
            let w = v_photons[PHOTON_WORDS * e.x + 2u];
            let v = q - x;
            if w.w != medium || dot(v, v) >= r * r || any(max(volume_cell(q - vec3<f32>(r1), lo, cell), a) != c) {
                continue;
            }
            let power = bitcast<vec3<f32>>(v_photons[PHOTON_WORDS * e.x + 1u].xyz);
            let phase = hg_eval(m.g, dot(bitcast<vec3<f32>>(w.xyz), wo));
            sum = fixed_add(sum, fixed_term(power, phase * scale));
        }
    }
    return fixed_value(sum) * (bound / POINT_ONE) * (3.0 / (4.0 * PI * r * r * r));
}

