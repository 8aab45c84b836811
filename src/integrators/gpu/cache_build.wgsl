// cache_build: the radiance cache's values (mode gather), twin of RadianceCache::build in
// src/integrators/cpu/cache.rs. list_cache_points (one invocation per global photon slot) lists the cache
// points; size_cache_build writes the values' dispatch; build_cache (K-nearest, one workgroup
// of CACHE_LANES per point; fixed radii: cache_fixed.wgsl) shares the point's search: a
// distance histogram picks the K-th photon, then an exact fixed-point sum. Writes cache(_list).

// cache_list (prelude offsets): [0..3] the values' dispatch (x, y, 1), [CACHE_LIST_COUNT]
// the number of cache points, [CACHE_LIST_FIRST + k] the sorted index of the k-th point.

// The search's shared state. Keys: key24(d2) orders photons by distance (ties: equal keys).
var<workgroup> hist: array<atomic<u32>, CACHE_BINS>;
// (d2 bits, sorted index) of the photons a sum may take: [0, CACHE_SELECT_LOW) those before
// the K-th's bin, then up to CACHE_CANDIDATES in its bin (ranked to find the K-th).
var<workgroup> sel: array<vec2<u32>, CACHE_SELECT_LOW + CACHE_CANDIDATES>;
var<workgroup> n_low: atomic<u32>;
var<workgroup> n_cand: atomic<u32>;
// (d2 bits, sorted index) of every photon the ring search saw, while they fit.
var<workgroup> near: array<vec2<u32>, CACHE_NEAR>;
var<workgroup> n_near: atomic<u32>;
var<workgroup> m_bits: atomic<u32>;
var<workgroup> lane_sum: array<vec2<u32>, CACHE_LANES>;
var<workgroup> lane_hi: array<vec3<u32>, CACHE_LANES>;
var<workgroup> lane_lo: array<vec3<u32>, CACHE_LANES>;
var<workgroup> wg_u: vec2<u32>;
var<workgroup> wg_pick: vec3<u32>;
var<workgroup> wg_kth: vec2<u32>;
var<workgroup> wg_point: u32;
var<workgroup> wg_scalar: u32;
var<workgroup> wg_counts: vec2<u32>;

// What one scan does with each photon within the radius: count its key digit (HIST; RING
// also lists it in `near`), list it in `sel` (SELECT), bound the terms (MAX), sum (SUM).
const SCAN_HIST: u32 = 0u;
const SCAN_RING: u32 = 1u;
const SCAN_SELECT: u32 = 2u;
const SCAN_MAX: u32 = 3u;
const SCAN_SUM: u32 = 4u;

// One scan: the mode; the key digits chosen so far (HIST counts the next digit of keys with
// key >> shift >> 8 == prefix; SELECT and MAX take key >> shift <= prefix, the K-th's bin
// being key >> shift == prefix); the sum's limit (d2 < t2, or d2 == t2 and ordered before
// photon kth; kth = CACHE_NONE takes d2 <= t2) and fixed-point scale.
struct CacheScan {
    mode: u32,
    shift: u32,
    prefix: u32,
    t2: f32,
    kth: u32,
    scale: f32,
    // RING lists photons whose level-0 bin is below this (those within about a cell).
    near_lim: u32,
}

// A lane's share of a scan: the largest term, and the fixed-point sum (see radius_scan).
struct LaneScan {
    m: f32,
    sum: FixedSum,
}

// Photons the global map holds sorted (its grid's total, at most its capacity).
fn global_count() -> u32 {
    return min(g_cells[g_map.table_size], g_map.capacity);
}

// Whether photon j (squared distance d2 bits) orders before photon k (bits dk): nearest,
// then photon identity (the CPU's order).
fn photon_before(d2: u32, j: u32, dk: u32, k: u32) -> bool {
    if d2 != dk {
        return d2 < dk;
    }
    let pa = map_photon(0u, j);
    let pb = map_photon(0u, k);
    if pa.id != pb.id {
        return pa.id < pb.id;
    }
    return pa.flags < pb.flags;
}

// 24-bit distance key: monotonic in d2 within [0, r2].
fn key24(d2: f32, r2: f32) -> u32 {
    return min(u32(d2 / r2 * 16777216.0), 16777215u);
}

// What photon j, at squared distance d2 (within the radius) of x, adds to a scan `sc`.
fn take_photon(j: u32, d2: f32, x: vec3<f32>, ns: vec3<f32>, sc: CacheScan, out: ptr<function, LaneScan>) {
    let key = key24(d2, g_map.radius2) >> sc.shift;
    if sc.mode == SCAN_RING || sc.mode == SCAN_HIST {
        if (key >> 8u) == sc.prefix {
            atomicAdd(&hist[key & (CACHE_BINS - 1u)], 1u);
        }
        if sc.mode == SCAN_RING && key < sc.near_lim {
            let at = atomicAdd(&n_near, 1u);
            if at < CACHE_NEAR {
                near[at] = vec2<u32>(bitcast<u32>(d2), j);
            }
        }
        return;
    }
    if key > sc.prefix {
        return;
    }
    if sc.mode == SCAN_SELECT {
        if key < sc.prefix {
            let at = atomicAdd(&n_low, 1u);
            if at < CACHE_SELECT_LOW {
                sel[at] = vec2<u32>(bitcast<u32>(d2), j);
            }
        } else {
            let at = atomicAdd(&n_cand, 1u);
            if at < CACHE_CANDIDATES {
                sel[CACHE_SELECT_LOW + at] = vec2<u32>(bitcast<u32>(d2), j);
            }
        }
        return;
    }
    let f = vec3<f32>(1.0 / PI);
    if sc.mode == SCAN_MAX {
        let p = map_photon(0u, j);
        if photon_faces(p, x, ns) {
            let t = f * p.power;
            (*out).m = max((*out).m, max(t.x, max(t.y, t.z)));
        }
        return;
    }
    if sc.kth == CACHE_NONE {
        if d2 > sc.t2 {
            return;
        }
    } else if !photon_before(bitcast<u32>(d2), j, bitcast<u32>(sc.t2), sc.kth) {
        return;
    }
    let p = map_photon(0u, j);
    if !photon_faces(p, x, ns) {
        return;
    }
    let q = vec3<u32>(f * p.power * kernel_weight(d2, sc.t2) * sc.scale + 0.5);
    (*out).sum = fixed_add((*out).sum, q);
}

// This lane's share of the photons within the radius in the cells at Chebyshev distance
// s_lo..=s_hi of x's cell (cells farther than bound2 skipped), treated per `sc`: the lanes
// walk the cells together and split each cell's photons.
fn scan_cells(lid: u32, x: vec3<f32>, ns: vec3<f32>, s_lo: i32, s_hi: i32, bound2: f32, sc: CacheScan) -> LaneScan {
    var out = LaneScan();
    let mp = g_map;
    let home = cell_of(x, mp.cell_size);
    let side = u32(2 * s_hi + 1);
    var visits = 0u;
    for (var t = 0u; t < side * side * side && spend(); t += 1u) {
        let d = vec3<i32>(vec3<u32>(t % side, (t / side) % side, t / (side * side))) - vec3<i32>(s_hi);
        if max(abs(d.x), max(abs(d.y), abs(d.z))) < s_lo {
            continue;
        }
        let c = home + d;
        if cell_gap2(c, x, mp.cell_size) > bound2 {
            continue;
        }
        let range = map_cell(0u, cell_hash(c, mp.table_size));
        for (var j = range.x + lid; j < range.y; j += CACHE_LANES) {
            visits += 1u;
            if visits > MAX_VISITS || !spend() {
                atomicAdd(&stats[STAT_GATHER_TRUNCATED], 1u);
                return out;
            }
            let pos = map_position(0u, j);
            if any(cell_of(pos, mp.cell_size) != c) {
                continue;
            }
            let dv = pos - x;
            let d2 = dot(dv, dv);
            if d2 <= mp.radius2 {
                take_photon(j, d2, x, ns, sc, &out);
            }
        }
    }
    return out;
}

// The same over the photons the ring search listed (when they all fitted in `near`).
fn scan_near(lid: u32, n: u32, x: vec3<f32>, ns: vec3<f32>, sc: CacheScan) -> LaneScan {
    var out = LaneScan();
    for (var e = lid; e < n && spend(); e += CACHE_LANES) {
        let v = near[e];
        take_photon(v.y, bitcast<f32>(v.x), x, ns, sc, &out);
    }
    return out;
}

// The same over the photons SELECT listed: c.x before the K-th's bin, c.y in it.
fn scan_sel(lid: u32, c: vec2<u32>, x: vec3<f32>, ns: vec3<f32>, sc: CacheScan) -> LaneScan {
    var out = LaneScan();
    for (var e = lid; e < c.x + c.y && spend(); e += CACHE_LANES) {
        let v = sel[select(e, CACHE_SELECT_LOW + e - c.x, e >= c.x)];
        take_photon(v.y, bitcast<f32>(v.x), x, ns, sc, &out);
    }
    return out;
}

// One scan over the listed photons (n <= CACHE_NEAR: all those the scan takes) or, when they did not fit, the cells
// of rings 0..=outer.
fn scan(lid: u32, n: u32, x: vec3<f32>, ns: vec3<f32>, outer: i32, bound2: f32, sc: CacheScan) -> LaneScan {
    if n <= CACHE_NEAR {
        return scan_near(lid, n, x, ns, sc);
    }
    return scan_cells(lid, x, ns, 0, outer, bound2, sc);
}

// Clears the histogram (uniform control flow; ends with a barrier).
fn clear_hist(lid: u32) {
    for (var b = lid; b < CACHE_BINS && spend(); b += CACHE_LANES) {
        atomicStore(&hist[b], 0u);
    }
    workgroupBarrier();
}

// (photons in bins below `lim`, photons in all bins), the same in every lane.
fn hist_count(lid: u32, lim: u32) -> vec2<u32> {
    var s = vec2<u32>(0u);
    for (var b = lid; b < CACHE_BINS && spend(); b += CACHE_LANES) {
        let h = atomicLoad(&hist[b]);
        s += vec2<u32>(select(0u, h, b < lim), h);
    }
    lane_sum[lid] = s;
    workgroupBarrier();
    if lid == 0u {
        var t = vec2<u32>(0u);
        for (var l = 0u; l < CACHE_LANES && spend(); l += 1u) {
            t += lane_sum[l];
        }
        wg_u = t;
    }
    return workgroupUniformLoad(&wg_u);
}

// (the bin where the running count reaches `rank` (1-based, at most the total), the count
// below it, the count in it), the same in every lane.
fn pick_bin(lid: u32, rank: u32) -> vec3<u32> {
    // Each lane totals its run of bins; the lane whose run holds the rank walks it.
    let per = CACHE_BINS / CACHE_LANES;
    var s = 0u;
    for (var b = 0u; b < per && spend(); b += 1u) {
        s += atomicLoad(&hist[lid * per + b]);
    }
    lane_sum[lid] = vec2<u32>(s, 0u);
    workgroupBarrier();
    var c = 0u;
    for (var l = 0u; l < lid && spend(); l += 1u) {
        c += lane_sum[l].x;
    }
    if c < rank && c + s >= rank {
        for (var b = 0u; b < per && spend(); b += 1u) {
            let h = atomicLoad(&hist[lid * per + b]);
            if c + h >= rank {
                wg_pick = vec3<u32>(lid * per + b, c, h);
                break;
            }
            c += h;
        }
    }
    return workgroupUniformLoad(&wg_pick);
}

// Clears every entry of the cache and lists the cache points (count cleared before).
@compute @workgroup_size(WG_SIZE)
fn list_cache_points(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = gid.x + gid.y * nwg.x * WG_SIZE;
    if g_map.paths == 0u || i >= global_count() {
        return;
    }
    cache[i] = vec4<f32>(0.0);
    if is_cache_point(map_word(0u, i, 0u).w, map_word(0u, i, 1u).w) {
        let k = atomicAdd(&cache_list[CACHE_LIST_COUNT], 1u);
        atomicStore(&cache_list[CACHE_LIST_FIRST + k], i);
    }
}

// Whether the cache's values are fixed-radius estimates (build_cache_fixed, cache_fixed.wgsl)
// rather than K-nearest ones (build_cache); the host records the same choice (k == 0).
fn fixed_radius_cache() -> bool {
    return !KNN || params.k == 0u;
}

// The values' dispatch over a 2D grid: one workgroup per cache point (build_cache), or one
// invocation per cache point (build_cache_fixed).
@compute @workgroup_size(1)
fn size_cache_build() {
    let points = atomicLoad(&cache_list[CACHE_LIST_COUNT]);
    let n = select(points, (points + WG_SIZE - 1u) / WG_SIZE, fixed_radius_cache());
    let x = min(n, 65535u);
    atomicStore(&cache_list[0], x);
    atomicStore(&cache_list[1], select(1u, (n + x - 1u) / max(x, 1u), x > 0u));
    atomicStore(&cache_list[2], 1u);
}

// The value of one cache point: the global map's K-nearest (params.k > 0; fewer within the
// radius: all of them) estimate at the photon with BRDF 1/pi, in three phases over the cells:
// (1) rings outward, a histogram of key24 until the K nearest are surely seen (listing the
// photons in `near` while they fit); (2) the bin of the K-th refined until few photons share
// it; those before it and in it listed in `sel`, the latter ranked; (3) the sum of the
// photons before the K-th (the CPU's estimate: its distance is the radius).
@compute @workgroup_size(CACHE_LANES)
fn build_cache(@builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>, @builtin(local_invocation_index) lid: u32) {
    if lid == 0u {
        let k = wid.x + wid.y * nwg.x;
        var i = CACHE_NONE;
        if k < atomicLoad(&cache_list[CACHE_LIST_COUNT]) {
            i = atomicLoad(&cache_list[CACHE_LIST_FIRST + k]);
        }
        wg_point = i;
    }
    let i = workgroupUniformLoad(&wg_point);
    if i == CACHE_NONE {
        return;
    }
    // Workgroup memory is not zeroed for this kernel (see Pipelines::new): clear what is read.
    if lid == 0u {
        atomicStore(&n_cand, 0u);
        atomicStore(&n_low, 0u);
        atomicStore(&n_near, 0u);
        atomicStore(&m_bits, 0u);
    }
    clear_hist(lid);
    let mp = g_map;
    let p = map_photon(0u, i);
    let x = p.position;
    let ns = unpack_normal(p.normal);
    let want_rings = i32(ceil(sqrt(mp.radius2) / mp.cell_size));
    let rings = min(want_rings, i32(MAX_RINGS));
    if want_rings > rings && lid == 0u {
        atomicAdd(&stats[STAT_GATHER_TRUNCATED], 1u);
    }
    let k = min(params.k, MAX_HEAP);
    // The ring search lists the photons within a cell of x (at most CACHE_NEAR): the K-th
    // usually lies there (grid::cell_size_for), and the later phases then read the list.
    let near_lim = u32(min(mp.cell_size * mp.cell_size / mp.radius2, 1.0) * f32(CACHE_BINS));
    var sc = CacheScan(SCAN_RING, 16u, 0u, mp.radius2, CACHE_NONE, 0.0, near_lim);
    var outer = rings;
    var bound2 = mp.radius2;
    var rank = 0u;
    var n = 0u;
    // (1) Ring s covers every point within s cells of x: stop once K photons lie there.
    var total = 0u;
    for (var s = 0; s <= rings; s += 1) {
        scan_cells(lid, x, ns, s, s, mp.radius2, sc);
        workgroupBarrier();
        let reach = f32(s) * mp.cell_size;
        let lim = u32(min(reach * reach / mp.radius2, 1.0) * f32(CACHE_BINS));
        let counts = hist_count(lid, select(lim, CACHE_BINS, s == rings));
        total = counts.y;
        if counts.x >= k {
            outer = s;
            bound2 = min(reach * reach, mp.radius2);
            break;
        }
    }
    if total >= k {
        rank = k;
    }
    workgroupBarrier();
    if lid == 0u {
        wg_scalar = atomicLoad(&n_near);
    }
    n = workgroupUniformLoad(&wg_scalar);
    sc.mode = SCAN_HIST;
    if rank > 0u {
        // (2) Narrow the K-th photon's key to a bin of at most CACHE_CANDIDATES photons.
        var pick = pick_bin(lid, rank);
        // The list holds every photon the later phases take only if the K-th's bin is in it.
        if pick.x >= near_lim {
            n = CACHE_NEAR + 1u;
        }
        for (var level = 0u; level < 2u && pick.z > CACHE_CANDIDATES; level += 1u) {
            rank -= pick.y;
            sc.prefix = (sc.prefix << 8u) | pick.x;
            sc.shift -= 8u;
            workgroupBarrier();
            clear_hist(lid);
            scan(lid, n, x, ns, outer, bound2, sc);
            workgroupBarrier();
            pick = pick_bin(lid, rank);
        }
        rank -= pick.y;
        sc.prefix = (sc.prefix << 8u) | pick.x;
    } else {
        // Every photon within the radius (fewer than K): all keys 0.
        sc.shift = 24u;
        sc.prefix = 1u;
        if near_lim < CACHE_BINS {
            n = CACHE_NEAR + 1u;
        }
    }
    if lid == 0u {
        // Stays when no candidate ranks K-th (more than CACHE_CANDIDATES listed).
        wg_kth = vec2<u32>(bitcast<u32>(mp.radius2), CACHE_NONE);
    }
    sc.mode = SCAN_SELECT;
    scan(lid, n, x, ns, outer, bound2, sc);
    workgroupBarrier();
    if lid == 0u {
        wg_counts = vec2<u32>(atomicLoad(&n_low), atomicLoad(&n_cand));
    }
    let counts = workgroupUniformLoad(&wg_counts);
    let c = vec2<u32>(counts.x, min(counts.y, CACHE_CANDIDATES));
    if rank > 0u {
        if counts.y > CACHE_CANDIDATES && lid == 0u {
            atomicAdd(&stats[STAT_GATHER_TRUNCATED], 1u);
        }
        for (var a = lid; a < c.y && spend(); a += CACHE_LANES) {
            let va = sel[CACHE_SELECT_LOW + a];
            var r = 0u;
            for (var b = 0u; b < c.y && spend(); b += 1u) {
                let vb = sel[CACHE_SELECT_LOW + b];
                r += u32(photon_before(vb.x, vb.y, va.x, va.y));
            }
            if r == rank - 1u {
                wg_kth = va;
            }
        }
        let kth = workgroupUniformLoad(&wg_kth);
        sc.t2 = max(bitcast<f32>(kth.x), 1e-30);
        sc.kth = kth.y;
    }
    // (3) The largest term, then the sum, exact in fixed point (so independent of the
    // photons' order in a cell), over the listed photons when they all fitted.
    let fits = counts.x <= CACHE_SELECT_LOW;
    sc.mode = SCAN_MAX;
    var lm: LaneScan;
    if fits {
        lm = scan_sel(lid, c, x, ns, sc);
    } else {
        lm = scan(lid, n, x, ns, outer, bound2, sc);
    }
    atomicMax(&m_bits, bitcast<u32>(lm.m));
    workgroupBarrier();
    if lid == 0u {
        wg_scalar = atomicLoad(&m_bits);
    }
    let m = bitcast<f32>(workgroupUniformLoad(&wg_scalar));
    var l = vec3<f32>(0.0);
    if m > 1e-30 {
        sc.mode = SCAN_SUM;
        sc.scale = 16777216.0 / m;
        var s: LaneScan;
        if fits {
            s = scan_sel(lid, c, x, ns, sc);
        } else {
            s = scan(lid, n, x, ns, outer, min(bound2, sc.t2), sc);
        }
        lane_hi[lid] = s.sum.hi;
        lane_lo[lid] = s.sum.lo;
        workgroupBarrier();
        var sum = FixedSum();
        for (var b = 0u; b < CACHE_LANES && spend(); b += 1u) {
            sum = fixed_add(FixedSum(sum.hi + lane_hi[b], sum.lo), lane_lo[b]);
        }
        l = fixed_value(sum) * (m / 16777216.0) * kernel_norm(sc.t2);
    }
    if lid == 0u {
        cache[i] = vec4<f32>(l, 1.0);
    }
}
