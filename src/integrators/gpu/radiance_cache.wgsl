// radiance_cache: the radiance cache of final gathering (mode gather), twin of the CPU's cache
// (src/integrators/plan.rs CACHE_STRIDE, CACHE_NORMAL_COS): cache[i] = (the global estimate at
// photon i with BRDF 1/pi, 1) at cache points, 0 elsewhere, written by cache_build.wgsl; read by
// cache_find and cache_lookup (gather.wgsl, probes.wgsl; a lookup that finds no point estimates
// the global map there). Library, no entry point; composed after common/estimate.wgsl.

@group(1) @binding(7) var<storage, read_write> cache: array<vec4<f32>>;
// build_cache's dispatch, the number of cache points and their sorted indices (in no fixed
// order: each value depends only on its photon); layout in cache_build.wgsl.
@group(1) @binding(8) var<storage, read_write> cache_list: array<atomic<u32>>;

// No cache point found.
const CACHE_NONE: u32 = 0xffffffffu;

// (d2, id, flags) of candidate a before b (the lookup's order: nearest, then photon identity).
fn cache_before(d2a: f32, pa: Photon, d2b: f32, pb: Photon) -> bool {
    if d2a != d2b {
        return d2a < d2b;
    }
    if pa.id != pb.id {
        return pa.id < pb.id;
    }
    return pa.flags < pb.flags;
}

// Index (in the global map's sorted photons) of the nearest cache point within the global
// radius of y whose normal has a cosine of at least CACHE_NORMAL_COS with n; CACHE_NONE when
// none. Rings of grid cells outward, each cut to the cells that can hold a point nearer than
// the best so far, stopping once no farther ring can; bounded by MAX_CELLS and MAX_VISITS (a
// cut search counts stats[STAT_GATHER_TRUNCATED]).
fn cache_find(y: vec3<f32>, n: vec3<f32>) -> u32 {
    let mp = g_map;
    if mp.paths == 0u {
        return CACHE_NONE;
    }
    let home = cell_of(y, mp.cell_size);
    let rings = i32(ceil(sqrt(mp.radius2) / mp.cell_size));
    var best = CACHE_NONE;
    var best_d2 = mp.radius2;
    var best_p: Photon;
    var visits = 0u;
    var cells = 0u;
    var truncated = false;
    for (var s = 0; s <= rings && !truncated && spend(); s += 1) {
        // The cells that can hold a point nearer than the best so far (the whole radius
        // before one is found), as offsets from home; padded so rounding never drops one.
        let reach = sqrt(best_d2) * 1.00001 + 1e-30;
        let near = cell_of(y - vec3<f32>(reach), mp.cell_size) - home;
        let far = cell_of(y + vec3<f32>(reach), mp.cell_size) - home;
        // Rings before s hold all of them.
        if s > max(max(max(-near.x, -near.y), -near.z), max(max(far.x, far.y), far.z)) {
            break;
        }
        // The ring's cells within [near, far], in one loop (dx fastest, then dy, then dz).
        let first = max(vec3<i32>(-s), near);
        let last = min(vec3<i32>(s), far);
        var dx = first.x;
        var dy = first.y;
        var dz = first.z;
        let ext = max(last - first + vec3<i32>(1), vec3<i32>(0));
        let n_box = u32(ext.x * ext.y * ext.z);
        for (var bi = 0u; bi < n_box && !truncated; bi += 1u) {
            if bi != 0u {
                dx += 1;
                if dx > last.x {
                    dx = first.x;
                    dy += 1;
                    if dy > last.y {
                        dy = first.y;
                        dz += 1;
                    }
                }
            }
            let step = ring_step(vec3<i32>(dx, dy, dz), s, &cells);
            if step == RING_STOP {
                truncated = true;
                break;
            }
            if step == RING_SKIP {
                continue;
            }
            let c = home + vec3<i32>(dx, dy, dz);
            if cell_gap2(c, y, mp.cell_size) > best_d2 {
                continue;
            }
            let range = map_cell(0u, cell_hash(c, mp.table_size));
            // A cell lists its cache points first (build_grid.wgsl scatter).
            for (var j = range.x; j < range.y; j += 1u) {
                visits += 1u;
                if visits > MAX_VISITS || !spend() {
                    truncated = true;
                    break;
                }
                // Words (position, flags) and (power, id); (dir, normal) only for
                // a point near enough.
                let w0 = map_word(0u, j, 0u);
                let w1 = map_word(0u, j, 1u);
                if !is_cache_point(w0.w, w1.w) {
                    break;
                }
                // A photon of a colliding cell is a cache point too, and seeing one
                // twice changes no minimum: no cell test.
                let dv = bitcast<vec3<f32>>(w0.xyz) - y;
                let d2 = dot(dv, dv);
                if d2 > best_d2 {
                    continue;
                }
                let q = photon_of_words(w0, w1, map_word(0u, j, 2u));
                if dot(unpack_normal(q.normal), n) < CACHE_NORMAL_COS {
                    continue;
                }
                if best == CACHE_NONE || cache_before(d2, q, best_d2, best_p) {
                    best = j;
                    best_d2 = d2;
                    best_p = q;
                }
            }
        }
    }
    if truncated {
        atomicAdd(&stats[STAT_GATHER_TRUNCATED], 1u);
    }
    return best;
}

// The cached radiance (white Lambertian) nearest y with normal n; where no cache point
// matches (sparse points in dim regions), the global map's estimate at y as a point's value
// is made (the CPU's Gatherer::cached).
fn cache_lookup(y: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let j = cache_find(y, n);
    if j == CACHE_NONE {
        return estimate(0u, y, n, vec3<f32>(BSDF_FRAC_1_PI));
    }
    return cache[j].xyz;
}
