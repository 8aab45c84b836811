// The radiance estimate over the two photon maps a gather reads (group 1 bindings 0-5):
// the K-nearest search of a map's hash grid with a bounded max-heap, the fixed-radius
// estimate summed exactly in fixed point, and the filter kernels. Library, no entry point;
// twin of src/integrators/estimate.rs. Writes only stats[STAT_GATHER_TRUNCATED] when a search is cut.

// The maps' sorted photons as PHOTON_WORDS words each (common/photon.wgsl); read them
// through map_photon, map_word and map_position.
@group(1) @binding(0) var<storage, read> g_photons: array<vec4<u32>>;
@group(1) @binding(1) var<storage, read> g_cells: array<u32>;
@group(1) @binding(2) var<storage, read> g_map: MapParams;
@group(1) @binding(3) var<storage, read> c_photons: array<vec4<u32>>;
@group(1) @binding(4) var<storage, read> c_cells: array<u32>;
@group(1) @binding(5) var<storage, read> c_map: MapParams;

// MAX_HEAP (prelude): largest K the heap holds (GpuRenderer rejects a larger --k).
// MAX_CELLS (prelude): grid cells one estimate may visit (rings of cells around the query).
// Photons one estimate may examine: the backends' shared bound (SEARCH_VISIT_BOUND, prelude),
// or half the loop budget where that is less (lavapipe); past it the estimate uses what it
// found and counts stats[STAT_GATHER_TRUNCATED].
override MAX_VISITS: u32 = min(LOOP_BUDGET / 2u, SEARCH_VISIT_BOUND);

// The heap: (squared distance bits, photon index) pairs; a max-heap during the search.
var<private> heap: array<vec2<u32>, MAX_HEAP>;
// Neighbours found by the last estimate (read by probe_knn).
var<private> last_found: u32 = 0u;

// Word k (0: position and flags, 1: power and id, 2: dir and normal) of photon i of map
// `which`.
fn map_word(which: u32, i: u32, k: u32) -> vec4<u32> {
    if which == 0u {
        return g_photons[PHOTON_WORDS * i + k];
    }
    return c_photons[PHOTON_WORDS * i + k];
}

fn map_photon(which: u32, i: u32) -> Photon {
    return photon_of_words(map_word(which, i, 0u), map_word(which, i, 1u), map_word(which, i, 2u));
}

// Only the position: the searches read nothing else of most photons they visit.
fn map_position(which: u32, i: u32) -> vec3<f32> {
    return bitcast<vec3<f32>>(map_word(which, i, 0u).xyz);
}

fn map_cell(which: u32, h: u32) -> vec2<u32> {
    if which == 0u {
        return vec2<u32>(g_cells[h], g_cells[h + 1u]);
    }
    return vec2<u32>(c_cells[h], c_cells[h + 1u]);
}

// Heap order: (squared distance, photon id, flags), so ties never depend on memory order.
fn heap_less(which: u32, d2a: f32, ia: u32, d2b: f32, ib: u32) -> bool {
    if d2a != d2b {
        return d2a < d2b;
    }
    let pa = map_photon(which, ia);
    let pb = map_photon(which, ib);
    if pa.id != pb.id {
        return pa.id < pb.id;
    }
    return pa.flags < pb.flags;
}

fn heap_d2(i: u32) -> f32 {
    return bitcast<f32>(heap[i].x);
}

fn heap_swap(a: u32, b: u32) {
    let t = heap[a];
    heap[a] = heap[b];
    heap[b] = t;
}

// Whether heap entry a orders before entry b.
fn entry_less(which: u32, a: u32, b: u32) -> bool {
    return heap_less(which, heap_d2(a), heap[a].y, heap_d2(b), heap[b].y);
}

// Restores the max-heap property below `start` within [0, n).
fn sift_down(which: u32, start: u32, n: u32) {
    var i = start;
    for (var step = 0u; step < 16u && spend(); step += 1u) {
        let l = 2u * i + 1u;
        if l >= n {
            return;
        }
        var c = l;
        if l + 1u < n && entry_less(which, l, l + 1u) {
            c = l + 1u;
        }
        if !entry_less(which, i, c) {
            return;
        }
        heap_swap(i, c);
        i = c;
    }
}

fn sift_up(which: u32, start: u32) {
    var i = start;
    for (var step = 0u; step < 16u && i > 0u && spend(); step += 1u) {
        let p = (i - 1u) / 2u;
        if !entry_less(which, p, i) {
            return;
        }
        heap_swap(i, p);
        i = p;
    }
}

// The density estimate's kernel at squared distance d2 within r2, and its normalisation
// (twins of crate::estimate's; the cone's constants come from there).
fn kernel_weight(d2: f32, r2: f32) -> f32 {
    if params.filter_kind == FILTER_CONE {
        return max(1.0 - sqrt(d2 / r2) * INV_CONE_K, 0.0);
    }
    if params.filter_kind == FILTER_EPANECHNIKOV {
        return max(1.0 - d2 / r2, 0.0);
    }
    return 1.0;
}

fn kernel_norm(r2: f32) -> f32 {
    if params.filter_kind == FILTER_CONE {
        return 1.0 / (CONE_NORM * PI * r2);
    }
    if params.filter_kind == FILTER_EPANECHNIKOV {
        return 2.0 / (PI * r2);
    }
    return 1.0 / (PI * r2);
}

// The heap's K (K-nearest estimates only; params.k = 0 means a fixed radius).
fn heap_k() -> u32 {
    return min(params.k, MAX_HEAP);
}

// A per-channel sum of non-negative integers in 64 bits (hi, lo). The estimates over photon
// lists round each term to an integer multiple of a bound's fraction and add it here: integer
// sums do not depend on the order of their terms, which the atomics of tracing and sorting
// leave free, so an estimate is the same on every run.
struct FixedSum {
    hi: vec3<u32>,
    lo: vec3<u32>,
}

// s + q, carrying into hi.
fn fixed_add(s: FixedSum, q: vec3<u32>) -> FixedSum {
    let lo = s.lo + q;
    return FixedSum(s.hi + select(vec3<u32>(0u), vec3<u32>(1u), lo < q), lo);
}

// The sum's value, hi 2^32 + lo, in float.
fn fixed_value(s: FixedSum) -> vec3<f32> {
    return vec3<f32>(s.hi) * 4294967296.0 + vec3<f32>(s.lo);
}

// One scan over every photon of map `which` within its radius of x that faces the surface,
// in cell order. With scale = 2^24 / m (m bounding every term f * power * w): each term,
// rounded to an integer multiple of m / 2^24, is added into a FixedSum; scale = 0 only
// counts (n).
struct RadiusScan {
    sum: FixedSum,
    // Photons within the radius, facing or not (read by probe_knn).
    n: u32,
}

fn radius_scan(which: u32, mp: MapParams, x: vec3<f32>, ns: vec3<f32>, f: vec3<f32>, scale: f32) -> RadiusScan {
    var out = RadiusScan();
    let home = cell_of(x, mp.cell_size);
    let rings = i32(ceil(sqrt(mp.radius2) / mp.cell_size));
    var visits = 0u;
    // The (2 rings + 1)^3 cells in one loop, dx fastest, then dy, then dz.
    let side = u32(2 * rings + 1);
    var dc = vec3<i32>(-rings);
    for (var ci = 0u; ci < side * side * side && spend(); ci += 1u) {
        if ci != 0u {
            dc.x += 1;
            if dc.x > rings {
                dc.x = -rings;
                dc.y += 1;
                if dc.y > rings {
                    dc.y = -rings;
                    dc.z += 1;
                }
            }
        }
        let c = home + dc;
        // Skip a cell that lies beyond the radius (with slack for rounding: its photons
        // would all fail the distance test below).
        if cell_gap2(c, x, mp.cell_size) > mp.radius2 * 1.001 {
            continue;
        }
        let range = map_cell(which, cell_hash(c, mp.table_size));
        for (var j = range.x; j < range.y; j += 1u) {
            visits += 1u;
            if visits > MAX_VISITS || !spend() {
                atomicAdd(&stats[STAT_GATHER_TRUNCATED], 1u);
                return out;
            }
            let w0 = map_word(which, j, 0u);
            let pos = bitcast<vec3<f32>>(w0.xyz);
            if any(cell_of(pos, mp.cell_size) != c) {
                continue;
            }
            let dv = pos - x;
            let d2 = dot(dv, dv);
            if d2 > mp.radius2 {
                continue;
            }
            out.n += 1u;
            let p = photon_of_words(w0, map_word(which, j, 1u), map_word(which, j, 2u));
            if !photon_faces(p, x, ns) {
                continue;
            }
            let t = f * p.power * kernel_weight(d2, mp.radius2);
            out.sum = fixed_add(out.sum, vec3<u32>(t * scale + 0.5));
        }
    }
    return out;
}

// The fixed-radius (progressive) estimate: every facing photon within the radius, summed
// exactly in fixed point in one scan (see radius_scan). The scale bounds every term: the
// largest BRDF channel times the map's largest photon power channel (the grid build's
// max_power; kernel weights are at most 1). Each term's rounding is at most 2^-25 of that.
fn fixed_radius_estimate(which: u32, mp: MapParams, x: vec3<f32>, ns: vec3<f32>, f: vec3<f32>) -> vec3<f32> {
    let m = max3(f) * mp.max_power;
    // (Below 1e-30 the scale 2^24 / m would overflow; such light is nothing. The count of
    // photons found is still taken, for probe_knn.)
    if !(m > 1e-30) {
        last_found = radius_scan(which, mp, x, ns, f, 0.0).n;
        return vec3<f32>(0.0);
    }
    let s = radius_scan(which, mp, x, ns, f, 16777216.0 / m);
    last_found = s.n;
    return fixed_value(s.sum) * (m / 16777216.0) * kernel_norm(mp.radius2);
}

// What a ring search does with the cell at offset dc from home in ring s.
const RING_SCAN: u32 = 0u;
// Not in ring s (inner rings hold it).
const RING_SKIP: u32 = 1u;
// The loop budget or MAX_CELLS is spent: the search is cut (truncated).
const RING_STOP: u32 = 2u;

// Spends one loop step on the cell at offset dc and counts it in *cells when it lies in ring
// s (only the ring's cells count: rings 0..=MAX_RINGS hold MAX_CELLS).
fn ring_step(dc: vec3<i32>, s: i32, cells: ptr<function, u32>) -> u32 {
    if !spend() {
        return RING_STOP;
    }
    if max(abs(dc.x), max(abs(dc.y), abs(dc.z))) != s {
        return RING_SKIP;
    }
    *cells += 1u;
    if *cells > MAX_CELLS {
        return RING_STOP;
    }
    return RING_SCAN;
}

// Finds the K nearest photons of map `which` within its radius around x; returns how many
// are in the heap (then sorted nearest first).
fn knn(which: u32, x: vec3<f32>) -> u32 {
    var mp: MapParams;
    if which == 0u {
        mp = g_map;
    } else {
        mp = c_map;
    }
    let k = heap_k();
    let r2_max = mp.radius2;
    let home = cell_of(x, mp.cell_size);
    let rings = i32(ceil(sqrt(r2_max) / mp.cell_size));
    var n = 0u;
    var visits = 0u;
    var cells = 0u;
    var truncated = false;
    for (var s = 0; s <= rings && !truncated && spend(); s += 1) {
        // Ring s covers every point within s * cell_size of x (x lies inside its home cell).
        let covered = f32(s) * mp.cell_size;
        if s >= 2 && n == k && heap_d2(0u) <= (covered - mp.cell_size) * (covered - mp.cell_size) {
            break;
        }
        for (var dz = -s; dz <= s && !truncated && spend(); dz += 1) {
            for (var dy = -s; dy <= s && !truncated && spend(); dy += 1) {
                for (var dx = -s; dx <= s && !truncated; dx += 1) {
                    let step = ring_step(vec3<i32>(dx, dy, dz), s, &cells);
                    if step == RING_STOP {
                        truncated = true;
                        break;
                    }
                    if step == RING_SKIP {
                        continue;
                    }
                    let c = home + vec3<i32>(dx, dy, dz);
                    // Skip cells entirely farther than the current K-th photon (or the radius).
                    let bound = select(r2_max, heap_d2(0u), n == k);
                    if cell_gap2(c, x, mp.cell_size) > bound {
                        continue;
                    }
                    let range = map_cell(which, cell_hash(c, mp.table_size));
                    for (var j = range.x; j < range.y; j += 1u) {
                        visits += 1u;
                        if visits > MAX_VISITS || !spend() {
                            truncated = true;
                            break;
                        }
                        let pos = map_position(which, j);
                        // Hash collisions put other cells' photons here: take a photon only
                        // in its own cell, so none is seen twice.
                        if any(cell_of(pos, mp.cell_size) != c) {
                            continue;
                        }
                        let dv = pos - x;
                        let d2 = dot(dv, dv);
                        if d2 > r2_max {
                            continue;
                        }
                        if n < k {
                            heap[n] = vec2<u32>(bitcast<u32>(d2), j);
                            sift_up(which, n);
                            n += 1u;
                        } else if heap_less(which, d2, j, heap_d2(0u), heap[0].y) {
                            heap[0] = vec2<u32>(bitcast<u32>(d2), j);
                            sift_down(which, 0u, n);
                        }
                    }
                }
            }
        }
    }
    if truncated {
        atomicAdd(&stats[STAT_GATHER_TRUNCATED], 1u);
    }
    last_found = n;
    // Heapsort: ascending (nearest first), a fixed order for the sum.
    for (var end = n; end > 1u && spend(); end -= 1u) {
        heap_swap(0u, end - 1u);
        sift_down(which, 0u, end - 1u);
    }
    return n;
}

// The K-nearest radiance estimate of map `which` at x (normal ns facing the viewer) with a
// Lambertian BRDF f; see src/integrators/estimate.rs for the K-th photon's exclusion.
fn estimate(which: u32, x: vec3<f32>, ns: vec3<f32>, f: vec3<f32>) -> vec3<f32> {
    var mp: MapParams;
    if which == 0u {
        mp = g_map;
    } else {
        mp = c_map;
    }
    if mp.paths == 0u {
        return vec3<f32>(0.0);
    }
    if !KNN || params.k == 0u {
        return fixed_radius_estimate(which, mp, x, ns, f);
    }
    let n = knn(which, x);
    if n == 0u {
        return vec3<f32>(0.0);
    }
    let k = heap_k();
    var r2 = mp.radius2;
    var count = n;
    if n >= k {
        r2 = max(heap_d2(n - 1u), 1e-30);
        count = n - 1u;
    }
    var sum = vec3<f32>(0.0);
    for (var i = 0u; i < count && spend(); i += 1u) {
        let p = map_photon(which, heap[i].y);
        if !photon_faces(p, x, ns) {
            continue;
        }
        sum += f * p.power * kernel_weight(heap_d2(i), r2);
    }
    return sum * kernel_norm(r2);
}
