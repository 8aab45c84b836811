// Mitsuba's sdfgrid shape (issue 40): twin of src/scene/sdf_grid.rs (a cell's ray-cubic
// intersection, the geometric and smooth normals), reading the grids' records, values and
// cells' entries that src/bvh/gpu_sdf.rs lays out in `leaf_prims` after the leaf entries.
// Callers are behind HAS_SDF_GRIDS (walk_bvh, trace_ray), so other scenes compile none of it.
// Library, no entry point; writes nothing but the loop budget it spends.

// A grid's record (SdfGridRecord) starts at vec4 word g of leaf_prims: rows 0-2 to_object,
// 3-5 to_world, 6 (res, material), 7 (values, smooth_normals, 0, 0).

// Flat word i of leaf_prims (component i % 4 of vec4 i / 4) as f32.
fn sdf_word(i: u32) -> f32 {
    return bitcast<f32>(leaf_prims[i >> 2u][i & 3u]);
}

// The rows (from row r) of record g applied to point p.
fn sdf_point(g: u32, r: u32, p: vec3<f32>) -> vec3<f32> {
    let q = vec4<f32>(p, 1.0);
    let a = bitcast<vec4<f32>>(leaf_prims[g + r]);
    let b = bitcast<vec4<f32>>(leaf_prims[g + r + 1u]);
    let c = bitcast<vec4<f32>>(leaf_prims[g + r + 2u]);
    return vec3<f32>(dot(a, q), dot(b, q), dot(c, q));
}

// The linear part of to_object (record g) applied to v.
fn sdf_vector(g: u32, v: vec3<f32>) -> vec3<f32> {
    let a = bitcast<vec4<f32>>(leaf_prims[g]).xyz;
    let b = bitcast<vec4<f32>>(leaf_prims[g + 1u]).xyz;
    let c = bitcast<vec4<f32>>(leaf_prims[g + 2u]).xyz;
    return vec3<f32>(dot(a, v), dot(b, v), dot(c, v));
}

// Grid g's cells per axis (its vertices minus one).
fn sdf_cells(g: u32) -> vec3<f32> {
    return vec3<f32>(leaf_prims[g + 6u].xyz) - 1.0;
}

// Mitsuba's BoundingBox::ray_intersect: (near, far) of the ray o + t d through the box lo..hi;
// a miss has near > far.
fn sdf_slab(lo: vec3<f32>, hi: vec3<f32>, o: vec3<f32>, d: vec3<f32>) -> vec2<f32> {
    let miss = vec2<f32>(1.0, -1.0);
    let inside = (o > lo) | (o < hi);
    if !all((d != vec3<f32>(0.0)) | inside) {
        return miss;
    }
    let rcp = 1.0 / d;
    let t1 = (lo - o) * rcp;
    let t2 = (hi - o) * rcp;
    let a = min(t1, t2);
    let b = max(t1, t2);
    let near = max(a.x, max(a.y, a.z));
    let far = min(b.x, min(b.y, b.z));
    return select(miss, vec2<f32>(near, far), far >= near);
}

// Mitsuba's math::solve_quadratic: whether a x^2 + b x + c has real roots, and them in order.
struct SdfRoots {
    found: bool,
    x0: f32,
    x1: f32,
}

fn sdf_solve_quadratic(a: f32, b: f32, c: f32) -> SdfRoots {
    let linear = a == 0.0;
    let valid_linear = linear && b != 0.0;
    var x0 = -c / b;
    var x1 = x0;
    let discrim = b * b - 4.0 * a * c;
    let valid_quadratic = !linear && discrim >= 0.0;
    if valid_quadratic {
        // sqrt(discrim) with b's sign (its sign bit: copysign).
        let s = sqrt(discrim);
        let temp = -0.5 * (b + select(s, -s, (bitcast<u32>(b) & 0x80000000u) != 0u));
        let p = temp / a;
        let q = c / temp;
        x0 = min(p, q);
        x1 = max(p, q);
    }
    return SdfRoots(valid_linear || valid_quadratic, x0, x1);
}

// Minus the cubic of coefficients c (constant first) at t.
fn sdf_cubic(c: vec4<f32>, t: f32) -> f32 {
    return -(((c.w * t + c.z) * t + c.y) * t + c.x);
}

// Mitsuba's sdf_solve_cubic: the first zero in t_beg..t_end of sdf_cubic(c), bracketed
// between the derivative's roots, then regula falsi (at most CUBIC_STEPS steps, to
// CUBIC_TOLERANCE); -1 for none.
fn sdf_solve_cubic(t_beg: f32, t_end: f32, c: vec4<f32>) -> f32 {
    let r = sdf_solve_quadratic(3.0 * c.w, 2.0 * c.z, c.y);
    var near = t_beg;
    var far = t_end;
    if r.found && near <= r.x0 && r.x0 <= far {
        if sdf_cubic(c, t_beg) * sdf_cubic(c, r.x0) <= 0.0 {
            far = r.x0;
        } else {
            near = r.x0;
        }
    }
    if r.found && near <= r.x1 && r.x1 <= far {
        if sdf_cubic(c, near) * sdf_cubic(c, r.x1) <= 0.0 {
            far = r.x1;
        } else {
            near = r.x1;
        }
    }
    var f_near = sdf_cubic(c, near);
    var f_far = sdf_cubic(c, far);
    if !(f_near * f_far <= 0.0) {
        return -1.0;
    }
    var t = 0.0;
    for (var i = 0u; i < CUBIC_STEPS && spend(); i += 1u) {
        t = near + (far - near) * (-f_near / (f_far - f_near));
        let f_t = sdf_cubic(c, t);
        if f_t * f_near <= 0.0 {
            far = t;
            f_far = f_t;
        } else if f_t * f_near > 0.0 {
            near = t;
            f_near = f_t;
        }
        if abs(near - far) < CUBIC_TOLERANCE {
            break;
        }
    }
    return t;
}

// SdfGrid::intersect_cell: the distance in [0, t_max) along the world ray o + t d to the
// surface in the cell whose leaf entry starts at vec4 word w (its grid's record at g), tested
// against its tight box first; -1 for none.
fn sdf_intersect_cell(g: u32, w: u32, o: vec3<f32>, d: vec3<f32>, t_max: f32) -> f32 {
    let oo = sdf_point(g, 0u, o);
    let od = sdf_vector(g, d);
    let e1 = leaf_prims[w + 1u];
    let e2 = leaf_prims[w + 2u];
    if !hit_box(bitcast<vec3<f32>>(leaf_prims[w].xyz), bitcast<vec3<f32>>(e1.xyz), oo, 1.0 / od, t_max) {
        return -1.0;
    }
    let n = sdf_cells(g);
    let h = 1.0 / n;
    let c = bitcast<vec3<f32>>(e2.xyz);
    let span = sdf_slab(c * h, (c + 1.0) * h, oo, od);
    let t_beg = max(span.x, 0.0);
    if t_beg >= span.y {
        return -1.0;
    }
    // The ray in the cell's unit cube, and the cubic of its trilinear function along it.
    let p = (oo + t_beg * od) * n - c;
    let q = od * n;
    let lo = bitcast<vec4<f32>>(leaf_prims[e1.w]);
    let hi = bitcast<vec4<f32>>(leaf_prims[e1.w + 1u]);
    let a = hi.y - hi.x;
    let k0 = lo.x;
    let k1 = lo.y - lo.x;
    let k2 = lo.z - lo.x;
    let k3 = lo.w - lo.z - k1;
    let k4 = k0 - hi.x;
    let k5 = k1 - a;
    let k6 = k2 - (hi.z - hi.x);
    let k7 = k3 - (hi.w - hi.z - a);
    let m0 = p.x * p.y;
    let m1 = q.x * q.y;
    let m2 = p.x * q.y + p.y * q.x;
    let m3 = k5 * p.z - k1;
    let m4 = k6 * p.z - k2;
    let m5 = k7 * p.z - k3;
    let c0 = (k4 * p.z - k0) + (p.x * m3 + (p.y * m4 + m0 * m5));
    let c1 = (q.x * m3 + q.y * m4) + m2 * m5 + q.z * (k4 + (k5 * p.x + (k6 * p.y + k7 * m0)));
    let c2 = m1 * m5 + q.z * (k5 * q.x + (k6 * q.y + k7 * m2));
    let c3 = k7 * m1 * q.z;
    let t = sdf_solve_cubic(0.0, span.y - t_beg, vec4<f32>(c0, c1, c2, c3));
    if t < 0.0 {
        return -1.0;
    }
    let s = t_beg + t;
    return select(-1.0, s, s >= 0.0 && s < t_max);
}

// Vertex v of grid g (in range).
fn sdf_voxel(g: u32, v: vec3<u32>) -> f32 {
    let res = leaf_prims[g + 6u].xyz;
    return sdf_word(leaf_prims[g + 7u].x + (v.z * res.y + v.y) * res.x + v.x);
}

// SdfData::value_at: the trilinear value at p of the unit cube, as Mitsuba's texture lookup
// (voxel centres, indices clamped); the sum in the CPU's order (z, then y, then x).
fn sdf_value_at(g: u32, p: vec3<f32>) -> f32 {
    let n = leaf_prims[g + 6u].xyz;
    let res = vec3<f32>(n);
    let inv = 1.0 / res;
    let pos = (p * (1.0 - inv) + inv / 2.0) * res - 0.5;
    let i0 = floor(pos);
    let f = pos - i0;
    let e = vec3<f32>(1.0) - f;
    let last = vec3<f32>(n - vec3<u32>(1u));
    let v0 = vec3<u32>(clamp(i0, vec3<f32>(0.0), last));
    let v1 = vec3<u32>(clamp(i0 + 1.0, vec3<f32>(0.0), last));
    var value = 0.0;
    value += sdf_voxel(g, vec3<u32>(v0.x, v0.y, v0.z)) * (e.x * e.y * e.z);
    value += sdf_voxel(g, vec3<u32>(v1.x, v0.y, v0.z)) * (f.x * e.y * e.z);
    value += sdf_voxel(g, vec3<u32>(v0.x, v1.y, v0.z)) * (e.x * f.y * e.z);
    value += sdf_voxel(g, vec3<u32>(v1.x, v1.y, v0.z)) * (f.x * f.y * e.z);
    value += sdf_voxel(g, vec3<u32>(v0.x, v0.y, v1.z)) * (e.x * e.y * f.z);
    value += sdf_voxel(g, vec3<u32>(v1.x, v0.y, v1.z)) * (f.x * e.y * f.z);
    value += sdf_voxel(g, vec3<u32>(v0.x, v1.y, v1.z)) * (e.x * f.y * f.z);
    value += sdf_voxel(g, vec3<u32>(v1.x, v1.y, v1.z)) * (f.x * f.y * f.z);
    return value;
}

// SdfData::cell_gradient: the gradient at p of the trilinear function of cell v (differences
// across the cell through p, in object units).
fn sdf_cell_gradient(g: u32, p: vec3<f32>, v: vec3<i32>) -> vec3<f32> {
    let h = 1.0 / sdf_cells(g);
    let p0 = vec3<f32>(v) * h;
    let p1 = p0 + h;
    let x = sdf_value_at(g, vec3<f32>(p1.x, p.y, p.z)) - sdf_value_at(g, vec3<f32>(p0.x, p.y, p.z));
    let y = sdf_value_at(g, vec3<f32>(p.x, p1.y, p.z)) - sdf_value_at(g, vec3<f32>(p.x, p0.y, p.z));
    let z = sdf_value_at(g, vec3<f32>(p.x, p.y, p1.z)) - sdf_value_at(g, vec3<f32>(p.x, p.y, p0.z));
    return vec3<f32>(x, y, z) / h;
}

// f32::round of each component: half away from zero (WGSL's round takes half to even).
fn sdf_round(x: vec3<f32>) -> vec3<f32> {
    let a = abs(x);
    let r = floor(a);
    return sign(x) * select(r, r + 1.0, a - r >= vec3<f32>(0.5));
}

// SdfData::smooth_normal: the unit gradients of the eight cells around the vertex nearest p
// (those at a negative index left out), blended trilinearly (object space, not normalised).
fn sdf_smooth_normal(g: u32, p: vec3<f32>) -> vec3<f32> {
    let scaled = p * sdf_cells(g);
    let v000 = vec3<i32>(sdf_round(scaled)) - vec3<i32>(1);
    var n = array<vec3<f32>, 8>();
    var valid = 0u;
    for (var i = 0u; i < 8u && spend(); i += 1u) {
        let corner = v000 + vec3<i32>(vec3<u32>(i & 1u, (i >> 1u) & 1u, (i >> 2u) & 1u));
        if all(corner >= vec3<i32>(0)) {
            valid |= 1u << i;
            let gr = sdf_cell_gradient(g, p, corner);
            n[i] = gr * (1.0 / length(gr));
        }
    }
    var w = scaled - vec3<f32>(v000 + vec3<i32>(1)) + 0.5;
    // The corners with bit a clear (side 0) per axis a; an axis whose side holds no valid
    // corner takes the other side.
    let low = vec3<u32>(0x55u, 0x33u, 0x0fu);
    w = select(w, vec3<f32>(1.0), (vec3<u32>(valid) & low) == vec3<u32>(0u));
    w = select(w, vec3<f32>(0.0), (vec3<u32>(valid) & (~low & vec3<u32>(0xffu))) == vec3<u32>(0u));
    let u = w.x;
    let v = w.y;
    let t = w.z;
    return (1.0 - t) * ((1.0 - v) * ((1.0 - u) * n[0] + u * n[1]) + v * ((1.0 - u) * n[2] + u * n[3]))
        + t * ((1.0 - v) * ((1.0 - u) * n[4] + u * n[5]) + v * ((1.0 - u) * n[6] + u * n[7]));
}

// glam's normalize_or_zero: v / |v|, or zero where that is not finite.
fn sdf_normalize(v: vec3<f32>) -> vec3<f32> {
    let r = 1.0 / length(v);
    return select(vec3<f32>(0.0), v * r, r > 0.0 && r <= 3.4028235e38);
}

// An object-space normal of grid g to world space (the inverse transpose of to_world).
fn sdf_normal(g: u32, n: vec3<f32>) -> vec3<f32> {
    let a = bitcast<vec4<f32>>(leaf_prims[g]).xyz;
    let b = bitcast<vec4<f32>>(leaf_prims[g + 1u]).xyz;
    let c = bitcast<vec4<f32>>(leaf_prims[g + 2u]).xyz;
    return sdf_normalize(a * n.x + b * n.y + c * n.z);
}

// A hit's surface: its point, unit geometric and shading normals (world space).
struct SdfSurface {
    position: vec3<f32>,
    normal: vec3<f32>,
    shading: vec3<f32>,
}

// SdfGrid::surface_at: the surface of grid g at world point x found by a ray: the point carried
// to the object space and back (as Mitsuba), the gradient of the cell holding it, and the
// smooth normal where the grid's normals are smooth.
fn sdf_surface(g: u32, x: vec3<f32>) -> SdfSurface {
    let p = sdf_point(g, 0u, x);
    let h = vec3<i32>(p * sdf_cells(g));
    let normal = sdf_normal(g, sdf_cell_gradient(g, p, h));
    var shading = normal;
    if leaf_prims[g + 7u].y != 0u {
        shading = sdf_normal(g, sdf_smooth_normal(g, p));
    }
    return SdfSurface(sdf_point(g, 3u, p), normal, shading);
}
