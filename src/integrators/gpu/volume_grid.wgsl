// volume_grid: the volume photon map's grid (twin of src/integrators/cpu/volume_map.rs's build), over one
// map group whose `volume` is the volume photons and whose own buffers are the grid's: cells of
// at least 2r (about VOLUME_PHOTONS_PER_CELL photons at the mean density, at most 8r), each photon
// listed in every cell its sphere's box overlaps (at most 8), hashed by cell_hash.
// Order: size_volume, count_volume, scan_blocks, scan_sums, add_offsets, scatter_volume.

// Volume photons stored (the buffer's capacity bounds what the trace kept).
fn volume_stored() -> u32 {
    return min(atomicLoad(&volume_count[0]), arrayLength(&volume) / PHOTON_WORDS);
}

var<workgroup> bounds_lo: array<vec3<f32>, SCAN_BLOCK>;
var<workgroup> bounds_hi: array<vec3<f32>, SCAN_BLOCK>;
var<workgroup> bounds_power: array<f32, SCAN_BLOCK>;

// One workgroup: the photons' bounds (each lane a strided share, at most VOLUME_MAX_PHOTONS /
// SCAN_BLOCK photons, below lavapipe's loop cut), widened by r; the cell size of
// VolumeMap::build; volume_grid[] = (lo, cell), (hi, r), (table size, photons, the largest
// power channel: the estimates' fixed-point bound); and the per-photon kernels' dispatch in
// counters[1..4].
@compute @workgroup_size(SCAN_BLOCK)
fn size_volume(@builtin(local_invocation_id) lid: vec3<u32>) {
    let n = volume_stored();
    var lo = vec3<f32>(3.0e38);
    var hi = vec3<f32>(-3.0e38);
    var power = 0.0;
    for (var i = lid.x; i < n; i += SCAN_BLOCK) {
        let p = bitcast<vec3<f32>>(volume[PHOTON_WORDS * i].xyz);
        lo = min(lo, p);
        hi = max(hi, p);
        power = max(power, max3(bitcast<vec3<f32>>(volume[PHOTON_WORDS * i + 1u].xyz)));
    }
    bounds_lo[lid.x] = lo;
    bounds_hi[lid.x] = hi;
    bounds_power[lid.x] = power;
    for (var off = SCAN_BLOCK / 2u; off > 0u; off = off / 2u) {
        workgroupBarrier();
        if lid.x < off {
            bounds_lo[lid.x] = min(bounds_lo[lid.x], bounds_lo[lid.x + off]);
            bounds_hi[lid.x] = max(bounds_hi[lid.x], bounds_hi[lid.x + off]);
            bounds_power[lid.x] = max(bounds_power[lid.x], bounds_power[lid.x + off]);
        }
    }
    workgroupBarrier();
    if lid.x != 0u {
        return;
    }
    let r = sqrt(map_params.radius2);
    var l = bounds_lo[0];
    var h = bounds_hi[0];
    if n == 0u {
        l = vec3<f32>(0.0);
        h = vec3<f32>(0.0);
    }
    l -= vec3<f32>(r);
    h += vec3<f32>(r);
    let e = h - l;
    let density = f32(n) / max(e.x * e.y * e.z, 1e-30);
    let sparse = min(pow(VOLUME_PHOTONS_PER_CELL / max(density, 1e-30), 1.0 / 3.0), 8.0 * r);
    let cell = max(max(2.0 * r, sparse), max(max(e.x, e.y), e.z) / 1.0e6);
    map_params.cell_size = cell;
    volume_grid[0] = vec4<f32>(l, cell);
    volume_grid[1] = vec4<f32>(h, r);
    volume_grid[2] = vec4<f32>(bitcast<f32>(map_params.table_size), bitcast<f32>(n), bounds_power[0], 0.0);
    let groups = max((n + WG_SIZE - 1u) / WG_SIZE, 1u);
    let x = min(groups, 65535u);
    atomicStore(&counters[1], x);
    atomicStore(&counters[2], (groups + x - 1u) / x);
    atomicStore(&counters[3], 1u);
}

// The cells photon i's sphere's box overlaps: from volume_cell of p - r to that of p + r.
fn volume_box(i: u32) -> array<vec3<i32>, 2> {
    let p = bitcast<vec3<f32>>(volume[PHOTON_WORDS * i].xyz);
    let g = volume_grid[0];
    let r = volume_grid[1].w;
    return array<vec3<i32>, 2>(volume_cell(p - vec3<f32>(r), g.xyz, g.w), volume_cell(p + vec3<f32>(r), g.xyz, g.w));
}

@compute @workgroup_size(WG_SIZE)
fn count_volume(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if i >= volume_stored() {
        return;
    }
    let b = volume_box(i);
    // At most 2 cells per axis (cells of at least 2r).
    for (var z = b[0].z; z <= min(b[1].z, b[0].z + 1); z += 1) {
        for (var y = b[0].y; y <= min(b[1].y, b[0].y + 1); y += 1) {
            for (var x = b[0].x; x <= min(b[1].x, b[0].x + 1); x += 1) {
                atomicAdd(&cell_count[cell_hash(vec3<i32>(x, y, z), map_params.table_size)], 1u);
            }
        }
    }
}

// Lists photon i in each of its cells: (photon index, the cell's coordinates), so that a
// query skips the entries of other cells hashed to the same slot.
@compute @workgroup_size(WG_SIZE)
fn scatter_volume(@builtin(global_invocation_id) gid: vec3<u32>, @builtin(num_workgroups) nwg: vec3<u32>) {
    let i = flat_index(gid, nwg);
    if i >= volume_stored() {
        return;
    }
    let b = volume_box(i);
    for (var z = b[0].z; z <= min(b[1].z, b[0].z + 1); z += 1) {
        for (var y = b[0].y; y <= min(b[1].y, b[0].y + 1); y += 1) {
            for (var x = b[0].x; x <= min(b[1].x, b[0].x + 1); x += 1) {
                let c = vec3<i32>(x, y, z);
                let h = cell_hash(c, map_params.table_size);
                let slot = cell_start[h] + atomicAdd(&cell_count[h], 1u);
                if slot < arrayLength(&sorted) {
                    sorted[slot] = vec4<u32>(i, bitcast<vec3<u32>>(c));
                }
            }
        }
    }
}
