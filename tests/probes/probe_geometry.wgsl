// Oracle probes of ray intersection and a hit's surface (src/bvh/*.wgsl) for
// tests/intersect_gpu.rs and hit_gpu.rs, never used by a render: primitive tests, the BVH walk,
// surface-frame helpers, and shading normals, uv tangents, alpha tests and frames on a scene.
// Dispatch: ceil(width / WG_SIZE) workgroups of WG_SIZE, one invocation per ray. Writes:
// accum[] as each entry point says. Composed after probes.wgsl (its `accum`).

// probe_intersect: ray i < width, (o, t_max) = accum[i], (d, primitive id as bits: a
// triangle, SPHERE_BIT | sphere, or 0xffffffff for none) = accum[width + i]; writes the
// primitive's test to accum[2 width + i] (a triangle's (t, u, v) of intersect_triangle, a
// sphere's (t, 0, 0) of intersect_sphere; t < 0 a miss), trace_ray's nearest hit
// (t, found, material, light as f32 or -1) to accum[3 width + i], its position and normal to
// accum[4 width + i] and accum[5 width + i], and the any-hit walk's found with the nearest
// hit's shading normal, (found, shading), to accum[6 width + i].
@compute @workgroup_size(WG_SIZE)
fn probe_intersect(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let a = accum[slot(0u, i)];
    let b = accum[slot(1u, i)];
    let o = a.xyz;
    let d = b.xyz;
    let id = bitcast<u32>(b.w);
    var prim = vec3<f32>(-2.0, 0.0, 0.0);
    if id != 0xffffffffu {
        if (id & SPHERE_BIT) == 0u {
            let tri = load_triangle(id);
            prim = intersect_triangle(tri.v0, tri.v1, tri.v2, o, d, make_shear(d), a.w);
        } else {
            prim = vec3<f32>(intersect_sphere(load_sphere(id & ~SPHERE_BIT), o, d, a.w), 0.0, 0.0);
        }
    }
    accum[slot(2u, i)] = vec4<f32>(prim, 0.0);
    let h = trace_ray(o, d, a.w, false);
    let light = select(f32(h.light), -1.0, h.light == NO_LIGHT);
    accum[slot(3u, i)] = vec4<f32>(h.t, select(0.0, 1.0, h.found), f32(h.material), light);
    accum[slot(4u, i)] = vec4<f32>(h.position, 0.0);
    accum[slot(5u, i)] = vec4<f32>(h.normal, 0.0);
    let first = trace_ray(o, d, a.w, true);
    accum[slot(6u, i)] = vec4<f32>(select(0.0, 1.0, first.found), h.shading);
}

// probe_surface: case i < width, (axis, exponent) = accum[i], (u1, u2, flipped, ior) =
// accum[w + i], ng, ns, dp_du, c (a normal map's texel) and d (the ray) = accum[2..7 w + i]
// (.xyz); writes phong_lobe(axis, exponent, u1, u2) to accum[7 w + i], (sphere_uv(axis),
// reflection_leaks(f, d), refraction_leaks(f, d)) with f the frame (ng, ns) to
// accum[8 w + i], normal_mapped(ng, ns, dp_du, flipped, c, d) to accum[9 w + i], and
// material.wgsl's functions: dielectric(d, ng, ns, ior) as (reflected, reflectance) and
// (refracted, 0) to accum[10, 11 w + i], fresnel_exact and fresnel_schlick at cosine c.x
// entering (1 to ior) and leaving (ior to 1) to accum[12 w + i], (reflect_dir(d, ns),
// phong_lobe_value(axis, -d, ns, exponent)) to accum[13 w + i], and with a BSDF's words 0-2
// = accum[14, 15, 18 w + i] (bits) and (its kind, u3) = accum[19 w + i], its
// surface_photon_bounce at a hit of normals (ng, ns) on (u1, u2, u3) as (dir, kind),
// (weight, 0) to accum[16, 17 w + i]; with dp_dv = accum[20 w + i].xyz and a height gradient
// accum[21 w + i].xy, bump_mapped(ng, ns, (dp_du, dp_dv), gradient, d) to accum[22 w + i].
@compute @workgroup_size(WG_SIZE)
fn probe_surface(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let a = accum[slot(0u, i)];
    let u = accum[slot(1u, i)];
    let ng = accum[slot(2u, i)].xyz;
    let ns = accum[slot(3u, i)].xyz;
    let d = accum[slot(6u, i)].xyz;
    accum[slot(7u, i)] = vec4<f32>(phong_lobe(a.xyz, a.w, u.x, u.y), 0.0);
    let f = Facing(ng, ns, any(ns != ng));
    let leaks = vec2<f32>(select(0.0, 1.0, reflection_leaks(f, d)), select(0.0, 1.0, refraction_leaks(f, d)));
    accum[slot(8u, i)] = vec4<f32>(sphere_uv(a.xyz), leaks);
    let n = normal_mapped(ng, ns, accum[slot(4u, i)].xyz, u.z != 0.0, accum[slot(5u, i)].xyz, d);
    accum[slot(9u, i)] = vec4<f32>(n, 0.0);
    let g = dielectric(d, ng, ns, u.w);
    accum[slot(10u, i)] = vec4<f32>(g.reflected, g.reflectance);
    accum[slot(11u, i)] = vec4<f32>(g.refracted, 0.0);
    let ci = accum[slot(5u, i)].x;
    accum[slot(12u, i)] = vec4<f32>(fresnel_exact(ci, 1.0, u.w), fresnel_exact(ci, u.w, 1.0),
        fresnel_schlick(ci, 1.0, u.w), fresnel_schlick(ci, u.w, 1.0));
    accum[slot(13u, i)] = vec4<f32>(reflect_dir(d, ns), phong_lobe_value(a.xyz, -d, ns, a.w));
    let kind = accum[slot(19u, i)];
    var s: Surface;
    s.b.kind = bitcast<u32>(kind.x);
    s.b.w0 = bitcast<vec4<u32>>(accum[slot(14u, i)]);
    s.b.w1 = bitcast<vec4<u32>>(accum[slot(15u, i)]);
    s.b.w2 = bitcast<vec4<u32>>(accum[slot(18u, i)]);
    s.n = ns;
    s.t = basis_t(ns);
    var h: Hit;
    h.normal = ng;
    h.shading = ns;
    let b = surface_photon_bounce(s, d, h, vec3<f32>(u.x, u.y, kind.y));
    accum[slot(16u, i)] = vec4<f32>(b.dir, f32(b.kind));
    accum[slot(17u, i)] = vec4<f32>(b.weight, 0.0);
    let p = UvPartials(accum[slot(4u, i)].xyz, accum[slot(20u, i)].xyz);
    accum[slot(22u, i)] = vec4<f32>(bump_mapped(ng, ns, p, accum[slot(21u, i)].xy, d), 0.0);
}

// The slots of probe_hit's per-triangle outputs when the function does not apply (a sphere,
// or a scene without uvs or tangents).
const NOT_RUN: vec4<f32> = vec4<f32>(0.0, 0.0, 0.0, -2.0);

// probe_hit: the hit's surface on the bound scene for case i < width: (o, t) = accum[i],
// (d, primitive id as bits) = accum[w + i], (ng, t_max) = accum[2 w + i], barycentrics
// (bc, 0, 0) = accum[3 w + i]. Writes, for a triangle id: (shading_normal(ng, its normals,
// bc), 1) to accum[4 w + i] ((ng, 0) when it is flat), triangle_tangent of its edges and
// corner uvs, vertex_tangent of its tangents at bc and uv_tangent(id, ...) to accum[5..7 w + i]
// (NOT_RUN without uvs, or tangents for vertex_tangent); (alpha_passes(id, t, bc, o, d),
// found, material, interpolated) of trace_ray(o, d, t_max)'s nearest hit to accum[8 w + i],
// the facing(hit, d . normal < 0) frame's ng and ns to accum[9 w + i], accum[10 w + i], and
// (offset_origin(o, ng, d), pack_normal(d) as bits) to accum[11 w + i], and the nearest hit's
// (tangent, 0) to accum[12 w + i].
@compute @workgroup_size(WG_SIZE)
fn probe_hit(@builtin(global_invocation_id) gid: vec3<u32>) {
    let i = gid.x;
    if i >= params.width { return; }
    let a = accum[slot(0u, i)];
    let b = accum[slot(1u, i)];
    let c = accum[slot(2u, i)];
    let bc = accum[slot(3u, i)].xy;
    let o = a.xyz;
    let d = b.xyz;
    let id = bitcast<u32>(b.w);
    var shading = vec4<f32>(c.xyz, 0.0);
    var tangents = array<vec4<f32>, 3>(NOT_RUN, NOT_RUN, NOT_RUN);
    if (id & SPHERE_BIT) == 0u {
        let tri = load_triangle(id);
        if tri.shading != FLAT {
            shading = vec4<f32>(shading_normal(c.xyz, tri.shading, bc), 1.0);
        }
        let e1 = tri.v1 - tri.v0;
        let e2 = tri.v2 - tri.v0;
        if HAS_TEXTURES {
            let r = uv_record(id);
            tangents[0] = triangle_tangent(e1, e2, uvs[r].xy, uvs[r].zw, uvs[r + 1u].xy);
            if HAS_TANGENTS {
                tangents[1] = vertex_tangent(r + UV_WORDS, bc);
            }
            tangents[2] = uv_tangent(id, e1, e2, bc);
        }
    }
    accum[slot(4u, i)] = shading;
    accum[slot(5u, i)] = tangents[0];
    accum[slot(6u, i)] = tangents[1];
    accum[slot(7u, i)] = tangents[2];
    let h = trace_ray(o, d, c.w, false);
    let f = facing(h, dot(d, h.normal) < 0.0);
    let passes = select(0.0, 1.0, alpha_passes(id, a.w, bc, o, d));
    accum[slot(8u, i)] = vec4<f32>(passes, select(0.0, 1.0, h.found), f32(h.material), select(0.0, 1.0, f.interpolated));
    accum[slot(9u, i)] = vec4<f32>(f.ng, 0.0);
    accum[slot(10u, i)] = vec4<f32>(f.ns, 0.0);
    accum[slot(11u, i)] = vec4<f32>(offset_origin(o, c.xyz, d), bitcast<f32>(pack_normal(d)));
    accum[slot(12u, i)] = vec4<f32>(h.tangent, 0.0);
}
