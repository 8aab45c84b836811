// build_grid: the photon map's spatial hash grid, built on the device by a counting sort.
// Dispatch, in order over one map's group-1 buffers: size_grid, count_cells, scan_blocks,
// scan_sums, add_offsets, scatter, scatter_rest (shapes below). Writes: map_params (cell_size,
// max_power), counters[1..4] (per-photon kernels' dispatch) and [COUNTER_MAX_POWER], cell_start
// (first sorted photon per cell; [table_size] = photons in the grid), sorted, block_sums.

// Entry points:
//   size_grid     (one invocation)                  cell size and dispatch from the count
//   count_cells   (one invocation per stored photon, indirect)  cell_count[h] += 1, max power
//   scan_blocks   (SCAN_BLOCK-wide, one per SCAN_SPAN cells)  cell_start = exclusive scan
//                                                   within blocks
//   scan_sums     (one workgroup of SCAN_BLOCK)     block_sums = exclusive scan of block totals;
//                                                   map_params.max_power from the counters
//   add_offsets   (one invocation per cell)         cell_start += block offset; cell_count = 0
//   scatter       (one per stored photon, indirect)  sorted[cell_start[h] + k] = cache point
//   scatter_rest  (one per stored photon, indirect)  the same for the other photons
// Loops: the scan's 8 steps, SCAN_ITEMS cells per scan_blocks invocation and scan_sums'
// chunks of at most 16 blocks (table_size <= 2^24) per invocation, far below lavapipe's 65,535 (these kernels need no loop budget).

fn stored_count() -> u32 {
    return min(atomicLoad(&counters[0]), map_params.capacity);
}

// Twin of grid::cell_size_for (src/integrators/gpu/grid.rs): the expected distance to the K-th photon
// when `stored` photons cover map_params.storing_area uniformly, within [radius / MAX_RINGS,
// radius]; the radius itself for fixed-radius estimates (k = 0).
fn cell_size_for(stored: u32) -> f32 {
    let radius = sqrt(map_params.radius2);
    if map_params.k == 0u {
        return radius;
    }
    let density = f32(max(stored, 1u)) / max(map_params.storing_area, 1e-30);
    let r_k = sqrt(f32(map_params.k) / (PI * density));
    // A NaN or infinite r_k gives the radius.
    if !(r_k <= 3.0e38) {
        return radius;
    }
    return clamp(r_k, radius / f32(MAX_RINGS), radius);
}

// Sizes the grid from the photons the trace stored, on the device (no read-back inside a
// pass): the cell edge (kept where storing_area is 0: an uploaded map's cells are the
// host's), and in counters[1..4] the count_cells/scatter dispatch of
// ceil(stored / WG_SIZE) workgroups, split in 2D as src/integrators/gpu/buffers.rs grid_2d does.
@compute @workgroup_size(1)
fn size_grid() {
    let stored = stored_count();
    if map_params.storing_area > 0.0 {
        map_params.cell_size = cell_size_for(stored);
    }
    let groups = max((stored + WG_SIZE - 1u) / WG_SIZE, 1u);
    let x = min(groups, 65535u);
    atomicStore(&counters[1], x);
    atomicStore(&counters[2], (groups + x - 1u) / x);
    atomicStore(&counters[3], 1u);
}

// The grid slot of the stored photon whose first word (position, flags) is w0, or
// 0xffffffff when the map drops it.
fn grid_slot(w0: vec4<u32>) -> u32 {
    if !keep_photon(w0.w, map_params.drop_flags) {
        return 0xffffffffu;
    }
    return cell_hash(cell_of(bitcast<vec3<f32>>(w0.xyz), map_params.cell_size), map_params.table_size);
}

@compute @workgroup_size(WG_SIZE)
fn count_cells(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if i >= stored_count() {
        return;
    }
    let h = grid_slot(photon_word(i, 0u));
    if h != 0xffffffffu {
        atomicAdd(&cell_count[h], 1u);
        // The largest power channel (bits of a non-negative float order as the float).
        let m = bitcast<u32>(max(max3(bitcast<vec3<f32>>(photon_word(i, 1u).xyz)), 0.0));
        if m > atomicLoad(&counters[COUNTER_MAX_POWER]) {
            atomicMax(&counters[COUNTER_MAX_POWER], m);
        }
    }
}

var<workgroup> scan_tmp: array<u32, SCAN_BLOCK>;

// Inclusive Hillis-Steele scan of scan_tmp (8 steps of 256 lanes).
fn workgroup_scan(tid: u32) {
    for (var off = 1u; off < SCAN_BLOCK; off = off * 2u) {
        workgroupBarrier();
        var v = scan_tmp[tid];
        if tid >= off {
            v += scan_tmp[tid - off];
        }
        workgroupBarrier();
        scan_tmp[tid] = v;
    }
    workgroupBarrier();
}

// Cells per scan block: SCAN_ITEMS consecutive cells per invocation.
const SCAN_SPAN: u32 = SCAN_BLOCK * SCAN_ITEMS;

// Each invocation sums its SCAN_ITEMS cells, one workgroup scan over the sums, then each
// writes its cells' exclusive prefixes (on lavapipe a workgroup barrier costs far more than a
// load: the scan's barriers once per SCAN_SPAN cells rather than per SCAN_BLOCK).
@compute @workgroup_size(SCAN_BLOCK)
fn scan_blocks(@builtin(local_invocation_id) lid: vec3<u32>, @builtin(workgroup_id) wid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let block = wid.x + wid.y * nwg.x;
    let first = block * SCAN_SPAN + lid.x * SCAN_ITEMS;
    let end = min(first + SCAN_ITEMS, map_params.table_size);
    var total = 0u;
    for (var idx = first; idx < end; idx += 1u) {
        total += atomicLoad(&cell_count[idx]);
    }
    scan_tmp[lid.x] = total;
    workgroup_scan(lid.x);
    var running = scan_tmp[lid.x] - total;
    for (var idx = first; idx < end; idx += 1u) {
        cell_start[idx] = running;
        running += atomicLoad(&cell_count[idx]);
    }
    if lid.x == SCAN_BLOCK - 1u && block * SCAN_SPAN < map_params.table_size {
        block_sums[block] = scan_tmp[SCAN_BLOCK - 1u];
    }
}

@compute @workgroup_size(SCAN_BLOCK)
fn scan_sums(@builtin(local_invocation_id) lid: vec3<u32>) {
    let blocks = (map_params.table_size + SCAN_SPAN - 1u) / SCAN_SPAN;
    let chunk = (blocks + SCAN_BLOCK - 1u) / SCAN_BLOCK;
    let start = lid.x * chunk;
    let end = min(start + chunk, blocks);
    var total = 0u;
    for (var b = start; b < end; b += 1u) {
        total += block_sums[b];
    }
    scan_tmp[lid.x] = total;
    workgroup_scan(lid.x);
    var running = scan_tmp[lid.x] - total;
    for (var b = start; b < end; b += 1u) {
        let s = block_sums[b];
        block_sums[b] = running;
        running += s;
    }
    if lid.x == SCAN_BLOCK - 1u {
        cell_start[map_params.table_size] = scan_tmp[SCAN_BLOCK - 1u];
    }
    if lid.x == 0u {
        map_params.max_power = bitcast<f32>(atomicLoad(&counters[COUNTER_MAX_POWER]));
    }
}

@compute @workgroup_size(WG_SIZE)
fn add_offsets(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if i >= map_params.table_size {
        return;
    }
    cell_start[i] += block_sums[i / SCAN_SPAN];
    atomicStore(&cell_count[i], 0u);
}

// Places photon slot i in its cell if it is (`cache_points`) or is not a radiance-cache
// point (the rule of cache_build.wgsl, applied to every map: the order within a cell is
// otherwise free).
fn scatter_if(i: u32, cache_points: bool) {
    if i >= stored_count() {
        return;
    }
    let w0 = photon_word(i, 0u);
    let h = grid_slot(w0);
    if h != 0xffffffffu && is_cache_point(w0.w, photon_word(i, 1u).w) == cache_points {
        let k = atomicAdd(&cell_count[h], 1u);
        copy_to_sorted(i, cell_start[h] + k);
    }
}

// scatter, then scatter_rest: each cell lists its cache points first, so that the cache's
// lookup (radiance_cache.wgsl cache_find) stops at the first other photon.
@compute @workgroup_size(WG_SIZE)
fn scatter(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    scatter_if(flat_index(gid, nwg), true);
}

@compute @workgroup_size(WG_SIZE)
fn scatter_rest(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    scatter_if(flat_index(gid, nwg), false);
}
