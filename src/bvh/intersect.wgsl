// Ray-primitive intersection and BVH traversal (trace_ray assembles the hit: instances walked
// by instances.wgsl, its shading frame from shading_frame.wgsl); twin of src/math/geometry.rs
// and src/bvh/. OFFSET_SCALE, OFFSET_FLOOR, BOX_SLACK (1 + 2 gamma(3): the slab test's exit
// distance is widened by its rounding bound) and FLAT come from the generated prelude.
// Library, no entry point; writes nothing but the loop budget it spends.

struct Hit {
    t: f32,
    position: vec3<f32>,
    normal: vec3<f32>,
    // Shading normal on the side of `normal` (equal to it where flat).
    shading: vec3<f32>,
    material: u32,
    light: u32,
    // Texture coordinates (zero without textures).
    uv: vec2<f32>,
    found: bool,
    // Unit tangent of the shading frame before any normal map (Mitsuba's sh_frame.s; zero
    // where it vanishes; a bump map's: bump_tangent): the BSDF frame's x (frame_tangent).
    tangent: vec3<f32>,
}

fn max_abs(p: vec3<f32>) -> f32 {
    let a = abs(p);
    return max(a.x, max(a.y, a.z));
}

fn offset_origin(p: vec3<f32>, n: vec3<f32>, dir: vec3<f32>) -> vec3<f32> {
    let eps = OFFSET_SCALE * (max_abs(p) + OFFSET_FLOOR);
    return select(p - n * eps, p + n * eps, dot(dir, n) >= 0.0);
}

// Moves a point of `tri` towards its centroid by the ray-offset distance (at most half way),
// so that a hit on an edge does not start its next ray on the plane of the face meeting it
// there (twin of inset in src/math/geometry.rs).
fn inset(tri: Triangle, p: vec3<f32>) -> vec3<f32> {
    let to_c = (tri.v0 + tri.v1 + tri.v2) / 3.0 - p;
    let len = length(to_c);
    if len == 0.0 {
        return p;
    }
    let eps = OFFSET_SCALE * (max_abs(p) + OFFSET_FLOOR);
    return p + to_c * min(eps / len, 0.5);
}

// Per-ray constants of the watertight test (twin of Shear in src/math/geometry.rs): the axes
// (kx, ky, kz) and the shear (sx, sy).
struct Shear {
    k: vec3<u32>,
    s: vec2<f32>,
}

fn make_shear(d: vec3<f32>) -> Shear {
    let a = abs(d);
    var kz = 2u;
    if a.x > a.y && a.x > a.z {
        kz = 0u;
    } else if a.y > a.z {
        kz = 1u;
    }
    let kx = (kz + 1u) % 3u;
    let ky = (kz + 2u) % 3u;
    return Shear(vec3<u32>(kx, ky, kz), vec2<f32>(d[kx] / d[kz], d[ky] / d[kz]));
}

fn shear_project(sh: Shear, v: vec3<f32>, o: vec3<f32>) -> vec2<f32> {
    let p = v - o;
    return vec2<f32>(p[sh.k.x] - sh.s.x * p[sh.k.z], p[sh.k.y] - sh.s.y * p[sh.k.z]);
}

// p.x q.y - p.y q.x in one canonical order of the end points: the two triangles sharing an
// edge get exactly opposite values, even where the compiler fuses the multiply-adds.
fn edge_function(p: vec2<f32>, q: vec2<f32>) -> f32 {
    if p.x < q.x || (p.x == q.x && p.y < q.y) {
        return p.x * q.y - p.y * q.x;
    }
    return -(q.x * p.y - q.y * p.x);
}

// Watertight ray-triangle test (Woop, Benthin and Wald 2013): (t, u, v) with u, v the
// weights of v1, v2, and t < 0 for a miss.
fn intersect_triangle(v0: vec3<f32>, v1: vec3<f32>, v2: vec3<f32>, o: vec3<f32>, d: vec3<f32>, sh: Shear, t_max: f32) -> vec3<f32> {
    let miss = vec3<f32>(-1.0, 0.0, 0.0);
    let a = shear_project(sh, v0, o);
    let b = shear_project(sh, v1, o);
    let c = shear_project(sh, v2, o);
    let e0 = edge_function(c, b);
    let e1 = edge_function(a, c);
    let e2 = edge_function(b, a);
    if (e0 < 0.0 || e1 < 0.0 || e2 < 0.0) && (e0 > 0.0 || e1 > 0.0 || e2 > 0.0) {
        return miss;
    }
    let det = e0 + e1 + e2;
    if det == 0.0 {
        return miss;
    }
    // t from the world-space plane equation: exactly 0 for a ray starting on an axis-aligned
    // plane.
    let n = cross(v1 - v0, v2 - v0);
    let t = dot(v0 - o, n) / dot(d, n);
    if t > 0.0 && t < t_max {
        return vec3<f32>(t, e1 / det, e2 / det);
    }
    return miss;
}

// Nearest t in (0, t_max), or -1.
fn intersect_sphere(s: Sphere, o: vec3<f32>, d: vec3<f32>, t_max: f32) -> f32 {
    let oc = o - s.center;
    let b = dot(oc, d);
    let perp = oc - b * d;
    let disc = s.radius * s.radius - dot(perp, perp);
    if disc < 0.0 {
        return -1.0;
    }
    let c = dot(oc, oc) - s.radius * s.radius;
    let sq = sqrt(disc);
    let q = select(-b + sq, -b - sq, b > 0.0);
    var t0 = 0.0;
    var t1 = 0.0;
    if q != 0.0 {
        t0 = c / q;
        t1 = q;
    }
    let lo = min(t0, t1);
    let hi = max(t0, t1);
    if lo > 0.0 && lo < t_max {
        return lo;
    }
    if hi > 0.0 && hi < t_max {
        return hi;
    }
    return -1.0;
}

fn hit_box(bmin: vec3<f32>, bmax: vec3<f32>, o: vec3<f32>, inv: vec3<f32>, t_max: f32) -> bool {
    let t0 = (bmin - o) * inv;
    let t1 = (bmax - o) * inv;
    let lo = min(t0, t1);
    let hi = max(t0, t1);
    let tmin = max(max(lo.x, max(lo.y, lo.z)), 0.0);
    let tmax = min(min(hi.x, min(hi.y, hi.z)) * BOX_SLACK, t_max);
    return tmin <= tmax;
}

// v turned by the unit quaternion (u, w): v + 2 u x (u x v + w v); exact for the identity.
// Twin of rotate in src/scene/shapes.rs.
fn sphere_rotate(u: vec3<f32>, w: f32, v: vec3<f32>) -> vec3<f32> {
    return v + 2.0 * cross(u, cross(u, v) + w * v);
}

// Sphere s's frame, object to world (Sphere::frame_words: four snorm16), normalised.
fn sphere_frame(s: Sphere) -> vec4<f32> {
    return normalize(vec4<f32>(unpack2x16snorm(s.frame.x), unpack2x16snorm(s.frame.y)));
}

// Mitsuba's sphere parameterisation of the unit direction n: u = phi / 2 pi with phi the
// azimuth from +x towards +y in [0, 2 pi), v = theta / pi from +z (texture::uv::sphere).
fn sphere_uv(n: vec3<f32>) -> vec2<f32> {
    var phi = atan2(n.y, n.x);
    if phi < 0.0 {
        phi += 2.0 * PI;
    }
    return vec2<f32>(phi / (2.0 * PI), atan2(length(n.xy), n.z) / PI);
}

// Nearest hit (any_hit = false) or the first hit found (any_hit = true) before t_max.
// Whether the ray o + t d passes primitive id hit at t (a triangle's barycentrics bc): its
// material is alpha-tested, not emissive, and its opacity there does not stop the ray; a
// blend's uniform hashes the primitive, t and d. Twin of alpha_passes in src/bvh/surface.rs.
fn alpha_passes(id: u32, t: f32, bc: vec2<f32>, o: vec3<f32>, d: vec3<f32>) -> bool {
    var mat = 0u;
    var uv = vec2<f32>(0.0);
    if (id & SPHERE_BIT) == 0u {
        mat = triangles[TRIANGLE_WORDS * id].w;
        if HAS_TEXTURES {
            uv = triangle_uv(id, bc);
        }
    } else {
        let s = load_sphere(id & ~SPHERE_BIT);
        mat = s.material;
        if HAS_TEXTURES {
            let q = sphere_frame(s);
            uv = sphere_uv(sphere_rotate(-q.xyz, q.w, normalize(o + t * d - s.center)));
        }
    }
    let w = materials[MATERIAL_WORDS * mat + MATERIAL_ALPHA_WORD];
    let mode = w.x & 3u;
    if mode == ALPHA_NONE {
        return false;
    }
    var tex = 1.0;
    if HAS_TEXTURES && w.y != NO_TEXTURE {
        // One lookup (drivers inline each call site's whole texture code).
        let c = texture_eval_rgba(w.y, uv);
        tex = select(c.w, dot(c.xyz, vec3<f32>(0.212671, 0.715160, 0.072169)), (w.x & ALPHA_LUMINANCE) != 0u);
    }
    let opacity = clamp(bitcast<f32>(w.z) * tex, 0.0, 1.0);
    if mode == ALPHA_MASK {
        return opacity < bitcast<f32>(w.w);
    }
    var key = pcg_hash(id ^ bitcast<u32>(t));
    key = pcg_hash(key ^ bitcast<u32>(d.x));
    key = pcg_hash(key ^ bitcast<u32>(d.y));
    key = pcg_hash(key ^ bitcast<u32>(d.z));
    return !(to_unit(key) < opacity);
}

// One walk's nearest (or first) primitive: t, id (as in leaf_prims), barycentrics, found.
struct PrimHit {
    t: f32,
    id: u32,
    bc: vec2<f32>,
    found: bool,
}

// The dominant axis of d (x, then y, on ties as the CPU's walk).
fn dominant_axis(d: vec3<f32>) -> u32 {
    if abs(d.x) > abs(d.y) && abs(d.x) > abs(d.z) {
        return 0u;
    } else if abs(d.y) > abs(d.z) {
        return 1u;
    }
    return 2u;
}

// The next leaf whose box the ray enters before t_max, from node *ni of the copy at
// first_word (n_nodes nodes; boxes on the grid base, step): its (first entry, count), and *ni
// past it; count 0 when the walk is over (or the loop budget spent). Nodes only: a SIMD
// group's lanes then test their leaves together, instead of every node step waiting on the
// lanes that are in a leaf.
fn next_leaf(first_word: u32, n_nodes: u32, ni: ptr<function, u32>, grid_base: vec3<i32>, step: vec3<f32>, o: vec3<f32>, inv: vec3<f32>, t_max: f32) -> vec2<u32> {
    while *ni < n_nodes && spend() {
        let node = nodes[first_word + NODE_WORDS * *ni];
        let lo = vec3<i32>(node.xyz & vec3<u32>(0xffffu));
        let hi = vec3<i32>(node.xyz >> vec3<u32>(16u));
        let c = node.w >> LEAF_COUNT_SHIFT;
        if !hit_box(vec3<f32>(grid_base + lo) * step, vec3<f32>(grid_base + hi) * step, o, inv, t_max) {
            *ni = select(*ni + 1u, node.w, c == 0u);
            continue;
        }
        *ni += 1u;
        if c != 0u {
            return vec2<u32>(node.w & ((1u << LEAF_COUNT_SHIFT) - 1u), c);
        }
    }
    return vec2<u32>(0u);
}

// The nearest of leaf entries first .. first + count along o + t d before best.t, or best
// (the leaf step of walk_bvh, and of the ray benchmark's walk_wide in src/bvh/gpu_wide.wgsl).
fn leaf_hits(first: u32, count: u32, o: vec3<f32>, d: vec3<f32>, sh: Shear, best_in: PrimHit) -> PrimHit {
    var best = best_in;
    for (var i = 0u; i < count && spend(); i += 1u) {
        // LeafPrim's words: (v0, id), (v1, _pad0), (v2, _pad1); a sphere needs only id,
        // an SDF cell reads them as sdf_intersect_cell does.
        let w = LEAF_PRIM_WORDS * (first + i);
        let w0 = leaf_prims[w];
        let id = w0.w;
        if (id & SPHERE_BIT) == 0u {
            let v0 = bitcast<vec3<f32>>(w0.xyz);
            let v1 = bitcast<vec3<f32>>(leaf_prims[w + 1u].xyz);
            let v2 = bitcast<vec3<f32>>(leaf_prims[w + 2u].xyz);
            let h = intersect_triangle(v0, v1, v2, o, d, sh, best.t);
            if h.x > 0.0 && !(HAS_ALPHA && alpha_passes(id, h.x, h.yz, o, d)) {
                best = PrimHit(h.x, id, h.yz, true);
            }
        } else if HAS_SDF_GRIDS && (id & SDF_BIT) != 0u {
            // An SDF grid's cell (src/bvh/gpu_sdf.rs): the hit's id names its grid's
            // record instead, which the surface reads.
            let g = leaf_prims[w + 2u].w;
            let t = sdf_intersect_cell(g, w, o, d, best.t);
            if t >= 0.0 {
                best = PrimHit(t, SPHERE_BIT | SDF_BIT | g, vec2<f32>(0.0), true);
            }
        } else if HAS_SPHERES {
            let t = intersect_sphere(load_sphere(id & ~SPHERE_BIT), o, d, best.t);
            if t > 0.0 && !(HAS_ALPHA && alpha_passes(id, t, vec2<f32>(0.0), o, d)) {
                best = PrimHit(t, id, vec2<f32>(0.0), true);
            }
        }
    }
    return best;
}

// Walks the hierarchy whose BvhFrame starts at word `frame` of `nodes` (the world's at 0, a
// mesh's after it) for the primitive nearest along o + t d before best.t (the first found
// when any_hit).
fn walk_bvh(frame: u32, o: vec3<f32>, d: vec3<f32>, best_in: PrimHit, any_hit: bool) -> PrimHit {
    var best = best_in;
    let inv = 1.0 / d;
    let sh = make_shear(d);
    let axis = dominant_axis(d);
    // The BvhFrame's words: (base, nodes per copy), (step, next).
    let f0 = nodes[frame];
    let grid_base = bitcast<vec3<i32>>(f0.xyz);
    let n_nodes = f0.w;
    let step = bitcast<vec3<f32>>(nodes[frame + 1u].xyz);
    // Stackless: the depth-first order that enters the left child first when the ray runs
    // up its dominant axis, else the right child first. `nodes` holds every node once per
    // order, numbered in that order's preorder: entering a node or finishing a leaf goes to
    // the next node, missing an interior node's box to the end of its subtree (its link).
    let left_first = d[axis] >= 0.0;
    let first_word = frame + FRAME_WORDS + select(n_nodes, 0u, left_first) * NODE_WORDS;
    var ni = 0u;
    // While-while: next_leaf walks nodes only, up to the next leaf whose box the ray hits;
    // its primitives are tested after it. The outer loop is bounded by the budget too: it
    // ends when next_leaf finds no leaf, which it does once spend() refuses.
    loop {
        let leaf = next_leaf(first_word, n_nodes, &ni, grid_base, step, o, inv, best.t);
        let first = leaf.x;
        let count = leaf.y;
        if count == 0u {
            break;
        }
        best = leaf_hits(first, count, o, d, sh, best);
        if any_hit && best.found {
            return best;
        }
    }
    return best;
}

// Nearest hit (any_hit = false) or the first hit found (any_hit = true) before t_max: the
// world's hierarchy, then, with instances, theirs with what is left of the ray.
fn trace_ray(o: vec3<f32>, d: vec3<f32>, t_max_in: f32, any_hit: bool) -> Hit {
    var best = Hit(t_max_in, vec3<f32>(0.0), vec3<f32>(0.0), vec3<f32>(0.0), 0u, NO_LIGHT, vec2<f32>(0.0), false, vec3<f32>(0.0));
    var w = PrimHit(t_max_in, 0u, vec2<f32>(0.0), false);
    // A scene without primitives binds a placeholder node that must not be walked.
    if !(params.n_triangles == 0u && !HAS_SPHERES && !HAS_SDF_GRIDS) {
        w = walk_bvh(0u, o, d, w, any_hit);
    }
    var inst = NO_LIGHT;
    if HAS_INSTANCES && !(any_hit && w.found) {
        let top = nodes[1].w;
        if top != 0u {
            inst = walk_instances(top, o, d, &w, any_hit);
        }
    }
    best.t = w.t;
    best.found = w.found;
    if any_hit || !w.found {
        return best;
    }
    // The hit is assembled where it was found: an instance's in its object space, then
    // carried to world space.
    var ho = o;
    var hd = d;
    var ht = w.t;
    var rec = 0u;
    if HAS_INSTANCES && inst != NO_LIGHT {
        rec = nodes[nodes[1].w + 1u].w + INSTANCE_WORDS * inst;
        let od = affine_vector(rec, d);
        let k = length(od);
        ho = affine_point(rec, o);
        hd = od / k;
        ht = w.t * k;
    }
    let best_id = w.id;
    let best_uv = w.bc;
    // The normal map's texture, the uv tangent (w: flipped; zero without uvs or for a
    // degenerate mapping) and the frame's tangent without it: the first edge in a scene
    // without uvs, else the geometric normal's basis (Bvh's hit_at); none on a sphere.
    var nt = NO_TEXTURE;
    var tg = vec4<f32>(0.0);
    var fallback = vec3<f32>(0.0);
    // A bump map's uv partials (Bvh's uv_partials), made only where a scene has bump maps.
    var pd = UvPartials(vec3<f32>(0.0), vec3<f32>(0.0));
    if (best_id & SPHERE_BIT) == 0u {
        let tri = load_triangle(best_id);
        let e1 = tri.v1 - tri.v0;
        let e2 = tri.v2 - tri.v0;
        best.position = inset(tri, tri.v0 + best_uv.x * e1 + best_uv.y * e2);
        best.normal = normalize(cross(e1, e2));
        best.shading = best.normal;
        if HAS_SMOOTH && tri.shading != FLAT {
            best.shading = shading_normal(best.normal, tri.shading, best_uv);
        }
        best.material = tri.material;
        best.light = tri.light;
        if HAS_UVS {
            tg = uv_tangent(best_id, e1, e2, best_uv);
        }
        if HAS_BUMP_MAPS {
            pd = UvPartials(e1, e2);
            if HAS_UVS {
                let r = uv_record(best_id);
                pd = uv_jacobian(e1, e2, uvs[r].xy, uvs[r].zw, uvs[r + 1u].xy);
            }
        }
        fallback = select(basis_t(best.normal), e1, !HAS_UVS);
        if HAS_TEXTURES {
            best.uv = triangle_uv(best_id, best_uv);
            if HAS_NORMAL_MAPS {
                nt = materials[MATERIAL_WORDS * tri.material + MATERIAL_NORMAL_WORD].w;
            }
        }
    } else if HAS_SDF_GRIDS && (best_id & SDF_BIT) != 0u {
        // No uv, dp/du or normal map (Mitsuba's sdfgrid has no parameterisation; as the CPU's
        // SdfBvh::intersect); never a light.
        let g = best_id & ~(SPHERE_BIT | SDF_BIT);
        let s = sdf_surface(g, o + w.t * d);
        best.position = s.position;
        best.normal = s.normal;
        best.shading = s.shading;
        best.material = leaf_prims[g + 6u].w;
    } else {
        let s = load_sphere(best_id & ~SPHERE_BIT);
        let n = normalize(ho + ht * hd - s.center);
        best.position = s.center + n * s.radius;
        best.normal = n;
        best.shading = n;
        best.material = s.material;
        best.light = s.light;
        // Mitsuba's uv and dp/du are the sphere's object space's (Sphere::uv, ::tangent).
        let q = sphere_frame(s);
        let l = sphere_rotate(-q.xyz, q.w, n);
        tg = vec4<f32>(sphere_rotate(q.xyz, q.w, vec3<f32>(-l.y, l.x, 0.0)), 0.0);
        if HAS_BUMP_MAPS {
            let p = sphere_partials(l, s.radius);
            pd = UvPartials(sphere_rotate(q.xyz, q.w, p.du), sphere_rotate(q.xyz, q.w, p.dv));
        }
        if HAS_TEXTURES {
            best.uv = sphere_uv(l);
            if HAS_NORMAL_MAPS {
                nt = materials[MATERIAL_WORDS * s.material + MATERIAL_NORMAL_WORD].w;
            }
        }
    }
    if HAS_INSTANCES && inst != NO_LIGHT {
        // Points by to_world, normals by the inverse transpose, the tangent by to_world (a
        // mirroring map flips its frame).
        let to_world = rec + 3u;
        best.position = affine_point(to_world, best.position);
        best.normal = normalize(affine_normal(rec, best.normal));
        best.shading = normalize(affine_normal(rec, best.shading));
        let l = array<vec3<f32>, 3>(affine_row(to_world, 0u).xyz, affine_row(to_world, 1u).xyz, affine_row(to_world, 2u).xyz);
        let flips = dot(l[0], cross(l[1], l[2])) < 0.0;
        tg = vec4<f32>(affine_vector(to_world, tg.xyz), select(tg.w, 1.0 - tg.w, flips));
        fallback = affine_vector(to_world, fallback);
        if HAS_BUMP_MAPS {
            pd = UvPartials(affine_vector(to_world, pd.du), affine_vector(to_world, pd.dv));
        }
    }
    best.tangent = shading_tangent(best.shading, tg.xyz, fallback);
    if HAS_TEXTURES && HAS_NORMAL_MAPS && nt != NO_TEXTURE {
        // The bump map's scale and flag (x, y), read only where a scene has bump maps.
        var bump = vec2<u32>(0u);
        if HAS_BUMP_MAPS {
            bump = materials[MATERIAL_WORDS * best.material + MATERIAL_BUMP_WORD].xy;
        }
        if bump.y != 0u {
            let grad = bitcast<f32>(bump.x) * texture_grad(nt, best.uv);
            let n = bump_mapped(best.normal, best.shading, pd, grad, d);
            best.tangent = bump_tangent(best.shading, best.tangent, pd.du, n);
            best.shading = n;
        } else {
            best.shading = normal_mapped(best.normal, best.shading, tg.xyz, tg.w > 0.5, texture_eval(nt, best.uv), d);
        }
    }
    return best;
}
