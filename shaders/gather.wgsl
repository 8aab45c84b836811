// gather: one invocation per pixel for camera sample `params.sample` (the host dispatches
// one sample layer at a time). Twin of src/cpu/gather.rs: camera ray, the mirror/glass
// chain (a stochastic Fresnel choice instead of recursion), then at diffuse and glossy hits
// the K-nearest estimate over each photon map's hash grid, shadow rays in `direct` mode,
// and the glossy lobe continued as the same path. Dispatch: ceil(width/8) x ceil(height/8)
// workgroups of 8x8. Writes: accum[pixel] += radiance / spp.

@group(1) @binding(0) var<storage, read> g_photons: array<Photon>;
@group(1) @binding(1) var<storage, read> g_cells: array<u32>;
@group(1) @binding(2) var<storage, read> g_map: MapParams;
@group(1) @binding(3) var<storage, read> c_photons: array<Photon>;
@group(1) @binding(4) var<storage, read> c_cells: array<u32>;
@group(1) @binding(5) var<storage, read> c_map: MapParams;
@group(1) @binding(6) var<storage, read_write> accum: array<vec4<f32>>;

// Largest K the GPU heap holds (src/gpu/mod.rs rejects a larger --k).
const MAX_HEAP: u32 = 256u;
// Grid cells one estimate may visit (rings of cells around the query).
const MAX_CELLS: u32 = 1331u; // 11^3: rings 0..=5
// Photons one estimate may examine (half the loop budget); past it the estimate uses what
// it found and counts stats[STAT_GATHER_TRUNCATED].
override MAX_VISITS: u32 = LOOP_BUDGET / 2u;

// The heap: (squared distance bits, photon index) pairs; a max-heap during the search.
var<private> heap: array<vec2<u32>, MAX_HEAP>;
// Neighbours found by the last estimate (read by probe_knn).
var<private> last_found: u32 = 0u;

fn map_photon(which: u32, i: u32) -> Photon {
    if which == 0u {
        return g_photons[i];
    }
    return c_photons[i];
}

// Only the position: the searches read nothing else of most photons they visit.
fn map_position(which: u32, i: u32) -> vec3<f32> {
    if which == 0u {
        return g_photons[i].position;
    }
    return c_photons[i].position;
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

fn kernel_weight(d2: f32, r2: f32) -> f32 {
    if params.filter_kind == 1u {
        return max(1.0 - sqrt(d2 / r2), 0.0);
    }
    if params.filter_kind == 2u {
        return max(1.0 - d2 / r2, 0.0);
    }
    return 1.0;
}

fn kernel_norm(r2: f32) -> f32 {
    if params.filter_kind == 1u {
        return 1.0 / ((1.0 - 2.0 / 3.0) * PI * r2);
    }
    if params.filter_kind == 2u {
        return 2.0 / (PI * r2);
    }
    return 1.0 / (PI * r2);
}

// The heap's K (K-nearest estimates only; params.k = 0 means a fixed radius).
fn heap_k() -> u32 {
    return min(params.k, MAX_HEAP);
}

// One scan over every photon of map `which` within its radius of x that faces the surface,
// in cell order. With scale = 0: `m` is the largest term f * power * w over photons and
// channels (a maximum: the same in any order). With scale = 2^24 / m: each term, rounded to
// an integer multiple of m / 2^24, is added into a 64-bit (hi, lo) sum per channel. Integer
// sums do not depend on the order (which the atomics of tracing and sorting leave free), so
// the fixed-radius estimate is the same on every run.
struct RadiusScan {
    m: f32,
    hi: vec3<u32>,
    lo: vec3<u32>,
    // Photons within the radius, facing or not (read by probe_knn).
    n: u32,
}

fn radius_scan(which: u32, mp: MapParams, x: vec3<f32>, ns: vec3<f32>, f: vec3<f32>, scale: f32) -> RadiusScan {
    var out = RadiusScan(0.0, vec3<u32>(0u), vec3<u32>(0u), 0u);
    let home = cell_of(x, mp.cell_size);
    let rings = i32(ceil(sqrt(mp.radius2) / mp.cell_size));
    var visits = 0u;
    for (var dz = -rings; dz <= rings && spend(); dz += 1) {
        for (var dy = -rings; dy <= rings && spend(); dy += 1) {
            for (var dx = -rings; dx <= rings && spend(); dx += 1) {
                let c = home + vec3<i32>(dx, dy, dz);
                let range = map_cell(which, cell_hash(c, mp.table_size));
                for (var j = range.x; j < range.y; j += 1u) {
                    visits += 1u;
                    if visits > MAX_VISITS || !spend() {
                        atomicAdd(&stats[STAT_GATHER_TRUNCATED], 1u);
                        return out;
                    }
                    let pos = map_position(which, j);
                    if any(cell_of(pos, mp.cell_size) != c) {
                        continue;
                    }
                    let dv = pos - x;
                    let d2 = dot(dv, dv);
                    if d2 > mp.radius2 {
                        continue;
                    }
                    out.n += 1u;
                    let p = map_photon(which, j);
                    if !photon_faces(p, x, ns) {
                        continue;
                    }
                    let t = f * p.power * kernel_weight(d2, mp.radius2);
                    if scale == 0.0 {
                        out.m = max(out.m, max(t.x, max(t.y, t.z)));
                    } else {
                        let q = vec3<u32>(t * scale + 0.5);
                        let lo = out.lo + q;
                        out.hi += select(vec3<u32>(0u), vec3<u32>(1u), lo < q);
                        out.lo = lo;
                    }
                }
            }
        }
    }
    return out;
}

// The fixed-radius (progressive) estimate: every facing photon within the radius, summed
// exactly in fixed point (two scans; see radius_scan). Each term's rounding is at most
// 2^-25 of the largest term.
fn fixed_radius_estimate(which: u32, mp: MapParams, x: vec3<f32>, ns: vec3<f32>, f: vec3<f32>) -> vec3<f32> {
    let first = radius_scan(which, mp, x, ns, f, 0.0);
    last_found = first.n;
    // (Below 1e-30 the scale 2^24 / m would overflow; such light is nothing.)
    if !(first.m > 1e-30) {
        return vec3<f32>(0.0);
    }
    let s = radius_scan(which, mp, x, ns, f, 16777216.0 / first.m);
    let sum = vec3<f32>(s.hi) * 4294967296.0 + vec3<f32>(s.lo);
    return sum * (first.m / 16777216.0) * kernel_norm(mp.radius2);
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
                    cells += 1u;
                    if cells > MAX_CELLS || !spend() {
                        truncated = true;
                        break;
                    }
                    if max(abs(dx), max(abs(dy), abs(dz))) != s {
                        continue;
                    }
                    let c = home + vec3<i32>(dx, dy, dz);
                    // Skip cells entirely farther than the current K-th photon (or the radius).
                    let lo = vec3<f32>(c) * mp.cell_size;
                    let gap = max(max(lo - x, x - (lo + vec3<f32>(mp.cell_size))), vec3<f32>(0.0));
                    let bound = select(r2_max, heap_d2(0u), n == k);
                    if dot(gap, gap) > bound {
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
// Lambertian BRDF f; see src/estimate.rs for the K-th photon's exclusion.
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
    if params.k == 0u {
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

// Shadow-ray direct light: area lights through kd/pi, point lights through the whole BRDF
// (or only the glossy lobe without TERM_DIRECT).
fn direct_light(x: vec3<f32>, n: vec3<f32>, ns: vec3<f32>, wo: vec3<f32>, m: Material, rng: ptr<function, Rng>) -> vec3<f32> {
    let with_direct = (params.terms & TERM_DIRECT) != 0u;
    var total = vec3<f32>(0.0);
    for (var li = 0u; li < params.n_lights && spend(); li += 1u) {
        let light = lights[li];
        let is_point = HAS_POINT_LIGHTS && light.kind == LIGHT_POINT;
        if !with_direct && !is_point {
            continue;
        }
        let samples = select(params.shadow_samples, 1u, is_point);
        var acc = vec3<f32>(0.0);
        for (var s = 0u; s < samples && spend(); s += 1u) {
            let u = vec3<f32>(rng_next(rng), rng_next(rng), rng_next(rng));
            let ls = sample_light(light, x, u);
            if all(ls.weight == vec3<f32>(0.0)) {
                continue;
            }
            let to_light = ls.point - x;
            let dist = length(to_light);
            let wi = to_light / dist;
            let c = dot(wi, ns);
            if c <= 0.0 {
                continue;
            }
            var f = m.kd / PI;
            if is_point {
                let lobe = m.ks * phong_lobe_value(wi, wo, ns, m.exponent);
                if m.kind != MAT_GLOSSY {
                    f = select(vec3<f32>(0.0), f, with_direct);
                } else {
                    f = select(lobe, f + lobe, with_direct);
                }
            }
            if all(f == vec3<f32>(0.0)) {
                continue;
            }
            let o = offset_origin(x, n, wi);
            // Area lights: stop short of the light's surface; a point light is no surface.
            let end_eps = select(OFFSET_SCALE * (max_abs(ls.point) + OFFSET_FLOOR) * 4.0, 0.0, is_point);
            // Aim from the moved origin (wi from x would pass the light by up to the offset).
            let to = ls.point - o;
            let len = length(to);
            let t_max = len - end_eps;
            if t_max > 0.0 && trace_ray(o, to / len, t_max, true).found {
                continue;
            }
            acc += f * ls.weight * c;
        }
        total += acc / f32(samples);
    }
    return total;
}

fn camera_sample(px: u32, py: u32, sample: u32) -> vec3<f32> {
    let pixel = py * params.width + px;
    var rng = Rng(path_key(params.seed, STREAM_CAMERA, params.pass_index, pixel * params.spp + sample), 0u);
    let jx = rng_next(&rng);
    let jy = rng_next(&rng);
    let n = u32(sqrt(f32(params.spp)));
    var fx = jx;
    var fy = jy;
    if n * n == params.spp {
        fx = (f32(sample % n) + jx) / f32(n);
        fy = (f32(sample / n) + jy) / f32(n);
    }
    let w = f32(params.width);
    let h = f32(params.height);
    let sx = (2.0 * (f32(px) + fx) / w - 1.0) * (w / h);
    let sy = 1.0 - 2.0 * (f32(py) + fy) / h;
    var d = normalize(params.forward + sx * params.right + sy * params.up);
    var o = params.eye;
    var throughput = vec3<f32>(1.0);
    var radiance = vec3<f32>(0.0);
    for (var depth = 0u; depth <= params.max_depth && spend(); depth += 1u) {
        let hit = trace_ray(o, d, 3.0e38, false);
        if !hit.found {
            break;
        }
        let m = materials[hit.material];
        let front = dot(d, hit.normal) < 0.0;
        if front || m.two_sided != 0u {
            radiance += throughput * m.emission;
        }
        let can_continue = depth < params.max_depth;
        if m.kind == MAT_BLACK {
            break;
        }
        if m.kind == MAT_MIRROR {
            if !can_continue {
                break;
            }
            let ns = select(-hit.normal, hit.normal, front);
            throughput *= m.ks;
            d = reflect_dir(d, ns);
            o = offset_origin(hit.position, hit.normal, d);
            continue;
        }
        if HAS_GLASS && m.kind == MAT_GLASS {
            if !can_continue {
                break;
            }
            let g = dielectric(d, hit.normal, m.ior);
            let u = rng_next(&rng);
            d = select(g.refracted, g.reflected, u < g.reflectance);
            o = offset_origin(hit.position, hit.normal, d);
            continue;
        }
        // Diffuse or glossy: shade.
        let wo = -d;
        let ns = select(-hit.normal, hit.normal, dot(wo, hit.normal) >= 0.0);
        var l = vec3<f32>(0.0);
        if (params.terms & TERM_DIRECT) != 0u || ((params.terms & TERM_POINT_LOBE) != 0u && m.kind == MAT_GLOSSY) {
            l += direct_light(hit.position, hit.normal, ns, wo, m, &rng);
        }
        let kd_pi = m.kd / PI;
        l += estimate(0u, hit.position, ns, kd_pi);
        l += estimate(1u, hit.position, ns, kd_pi);
        radiance += throughput * l;
        if (params.terms & TERM_LOBE_RAY) == 0u || m.kind != MAT_GLOSSY || !can_continue || max3(m.ks) <= 0.0 {
            break;
        }
        let u1 = rng_next(&rng);
        let u2 = rng_next(&rng);
        let dir = phong_lobe(reflect_dir(-wo, ns), m.exponent, u1, u2);
        let c = dot(dir, ns);
        if c <= 0.0 {
            break;
        }
        throughput *= m.ks * ((m.exponent + 2.0) / (m.exponent + 1.0) * c);
        d = dir;
        o = offset_origin(hit.position, hit.normal, d);
    }
    return radiance;
}

@compute @workgroup_size(8, 8)
fn gather(@builtin(global_invocation_id) gid: vec3<u32>) {
    if gid.x >= params.width || gid.y >= params.height {
        return;
    }
    let l = camera_sample(gid.x, gid.y, params.sample);
    let i = gid.y * params.width + gid.x;
    accum[i] += vec4<f32>(l / f32(params.spp), 0.0);
}

// Oracle probes for tests/gpu_oracle.rs (not used by a render; a pipeline compiles only
// the entry point it names).
// probe_rng: accum[i] = (path_key(seed, 1 + i % 4, pass, i), draw_u32(key, i % 9),
// bits of to_unit(draw), pcg_hash(i)) as raw bits, for i < width.
@compute @workgroup_size(64)
fn probe_rng(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width {
        return;
    }
    let key = path_key(params.seed, 1u + i % 4u, params.pass_index, i);
    let bits = draw_u32(key, i % 9u);
    accum[i] = bitcast<vec4<f32>>(vec4<u32>(key, bits, bitcast<u32>(to_unit(bits)), pcg_hash(i)));
}

// probe_knn: for query i < width, position accum[i].xyz and normal accum[width + i].xyz,
// writes the global map's estimate with f = 1 and the neighbour count to accum[2 width + i].
@compute @workgroup_size(64)
fn probe_knn(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width {
        return;
    }
    let x = accum[i].xyz;
    let ns = accum[params.width + i].xyz;
    let l = estimate(0u, x, ns, vec3<f32>(1.0));
    accum[2u * params.width + i] = vec4<f32>(l, f32(last_found));
}
