// The hit's shading frame: the shading normal (interpolated vertex normals), the uv tangent and
// the frame's tangent, normal and bump mapping, and the normals turned to the ray's side
// (Facing, the leak tests); twin of src/math/geometry.rs, src/bvh/surface.rs and
// src/bvh/hit.rs. trace_ray (intersect.wgsl) assembles a hit's frame with it.
// Library, no entry point; writes nothing.

// The shading normal at (u, v) of a triangle with geometric normal ng and vertex normals i:
// their normalised interpolation, negated when against ng, ng where it vanishes (twin of
// shading_normal in src/math/geometry.rs).
fn shading_normal(ng: vec3<f32>, i: u32, uv: vec2<f32>) -> vec3<f32> {
    let n = shading_normals[i];
    let s = (1.0 - uv.x - uv.y) * n.n0 + uv.x * n.n1 + uv.y * n.n2;
    let len = length(s);
    if !(len > 0.0) {
        return ng;
    }
    let ns = s / len;
    return select(ns, -ns, dot(ns, ng) < 0.0);
}

// A triangle's uv tangent (Mitsuba's dp_du up to its positive scale) in xyz and w = 1 when the
// parameterisation is flipped (det < 0); w = -1 for a degenerate mapping (twin of
// triangle_tangent in src/math/geometry.rs).
fn triangle_tangent(e1: vec3<f32>, e2: vec3<f32>, uv0: vec2<f32>, uv1: vec2<f32>, uv2: vec2<f32>) -> vec4<f32> {
    let d0 = uv1 - uv0;
    let d1 = uv2 - uv0;
    let det = d0.x * d1.y - d0.y * d1.x;
    if det == 0.0 || !(abs(det) <= 3.4028235e38) {
        return vec4<f32>(0.0, 0.0, 0.0, -1.0);
    }
    let dp_du = (d1.y * e1 - d0.y * e2) * sign(det);
    return vec4<f32>(dp_du, select(0.0, 1.0, det < 0.0));
}

// The interpolated vertex tangent at barycentrics bc of the tangents from word r on, as
// triangle_tangent gives it (xyz, w = 1 when flipped); zero xyz where it vanishes (twin of
// vertex_tangent in src/math/geometry.rs).
fn vertex_tangent(r: u32, bc: vec2<f32>) -> vec4<f32> {
    let m = (1.0 - bc.x - bc.y) * uvs[r] + bc.x * uvs[r + 1u] + bc.y * uvs[r + 2u];
    return vec4<f32>(m.xyz, select(0.0, 1.0, m.w < 0.0));
}

// Triangle id's uv tangent at barycentrics bc: its vertex tangents' where it has them, else
// its corner uvs', unflipped (twin of uv_tangent in src/bvh/surface.rs). A mesh without uvs reads the
// placeholder's zeros: degenerate, so normal_mapped takes the basis.
fn uv_tangent(id: u32, e1: vec3<f32>, e2: vec3<f32>, bc: vec2<f32>) -> vec4<f32> {
    let r = uv_record(id);
    if HAS_TANGENTS {
        let t = vertex_tangent(r + UV_WORDS, bc);
        if any(t.xyz != vec3<f32>(0.0)) {
            return t;
        }
    }
    let a = uvs[r];
    // Never flipped from corner uvs (Mitsuba 3.9.1's t = n x s): w 1 becomes 0.
    let t = triangle_tangent(e1, e2, a.xy, a.zw, uvs[r + 1u].xy);
    return vec4<f32>(t.xyz, min(t.w, 0.0));
}

// t made orthogonal to unit n and normalised; zero where that vanishes or is not finite (twin
// of orthogonal_tangent in src/math/geometry.rs).
fn orthogonal_tangent(n: vec3<f32>, t: vec3<f32>) -> vec3<f32> {
    let s = t - n * dot(n, t);
    let l2 = dot(s, s);
    if l2 > 0.0 && l2 <= 3.4028235e38 {
        return s / sqrt(l2);
    }
    return vec3<f32>(0.0);
}

// The unit tangent of a hit's shading frame at shading normal ns: the uv tangent dp_du, or
// fallback where that is zero, made orthogonal to ns (twin of shading_tangent in
// src/math/geometry.rs).
fn shading_tangent(ns: vec3<f32>, dp_du: vec3<f32>, fallback: vec3<f32>) -> vec3<f32> {
    return orthogonal_tangent(ns, select(dp_du, fallback, all(dp_du == vec3<f32>(0.0))));
}

// Mitsuba's normalmap: the shading normal that linear texel c gives at a hit with front normal
// ng, shading normal ns (side of ng), uv tangent dp_du (zero: none), flipped parameterisation,
// for a ray along d (twin of normal_mapped in src/math/geometry.rs, which documents the frame).
fn normal_mapped(ng: vec3<f32>, ns: vec3<f32>, dp_du: vec3<f32>, flipped: bool, c: vec3<f32>, d: vec3<f32>) -> vec3<f32> {
    let s0 = dp_du - ns * dot(ns, dp_du);
    let len2 = dot(s0, s0);
    var s = basis_t(ns);
    var t = basis_b(ns);
    if len2 > 0.0 && len2 <= 3.4028235e38 {
        s = normalize(s0);
        t = cross(ns, s);
        if flipped {
            t = -t;
        }
    }
    var m = 2.0 * c - vec3<f32>(1.0);
    let wi = -d;
    if dot(wi, ns) * dot(wi, s * m.x + t * m.y + ns * m.z) <= 0.0 {
        m = vec3<f32>(-m.x, -m.y, m.z);
    }
    let w = s * m.x + t * m.y + ns * m.z;
    let len = length(w);
    if !(len > 0.0) {
        return ns;
    }
    let n = w / len;
    return select(n, -n, dot(n, ng) < 0.0);
}

// A triangle's uv partials (dp_du, dp_dv) from its corner uvs; both zero for a degenerate
// mapping (twin of uv_jacobian in src/math/geometry.rs).
struct UvPartials {
    du: vec3<f32>,
    dv: vec3<f32>,
}

fn uv_jacobian(e1: vec3<f32>, e2: vec3<f32>, uv0: vec2<f32>, uv1: vec2<f32>, uv2: vec2<f32>) -> UvPartials {
    let d0 = uv1 - uv0;
    let d1 = uv2 - uv0;
    let det = d0.x * d1.y - d0.y * d1.x;
    let inv = select(0.0, 1.0 / det, det != 0.0);
    return UvPartials((d1.y * e1 - d0.y * e2) * inv, (d0.x * e2 - d1.x * e1) * inv);
}

// Mitsuba's sphere parameterisation's uv partials at outward unit normal n, radius r (twin of
// sphere_partials in src/math/geometry.rs).
fn sphere_partials(n: vec3<f32>, r: f32) -> UvPartials {
    let rd = sqrt(n.x * n.x + n.y * n.y);
    var polar = vec3<f32>(1.0, 0.0, 0.0);
    if rd != 0.0 {
        polar = vec3<f32>(n.z * (n.x / rd), n.z * (n.y / rd), -rd);
    }
    return UvPartials(2.0 * PI * r * vec3<f32>(-n.y, n.x, 0.0), PI * r * polar);
}

// Mitsuba's bumpmap: the shading normal that height gradient grad (times the scale) gives at a
// hit with front normal ng, shading normal ns (side of ng), uv partials p, for a ray along d
// (twin of bump_mapped in src/math/geometry.rs, which documents it).
fn bump_mapped(ng: vec3<f32>, ns: vec3<f32>, p: UvPartials, grad: vec2<f32>, d: vec3<f32>) -> vec3<f32> {
    let du = p.du + ns * (grad.x - dot(ns, p.du));
    let dv = p.dv + ns * (grad.y - dot(ns, p.dv));
    let c = cross(du, dv);
    if !(dot(c, c) > 1e-12 * dot(du, du) * dot(dv, dv)) {
        return ns;
    }
    var n = normalize(c);
    n = select(n, -n, dot(n, ng) < 0.0);
    let wi = -d;
    if dot(wi, ns) * dot(wi, n) <= 0.0 {
        n = 2.0 * dot(ns, n) * ns - n;
    }
    let l = length(n);
    if !(l > 0.0) {
        return ns;
    }
    n = n / l;
    return select(n, -n, dot(n, ng) < 0.0);
}

// The tangent of Mitsuba 3.9.1's bumped frame: the world dp_du made orthogonal, as if it were
// local, to the bumped normal n written in the unperturbed frame (ns, tangent s or, where s
// is zero, basis_t(ns)), taken back to world space; s where that vanishes (twin of
// bump_tangent in src/math/geometry.rs, which documents it).
fn bump_tangent(ns: vec3<f32>, s_in: vec3<f32>, dp_du: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    let s = select(s_in, basis_t(ns), all(s_in == vec3<f32>(0.0)));
    let t = cross(ns, s);
    let l = orthogonal_tangent(vec3<f32>(dot(n, s), dot(n, t), dot(n, ns)), dp_du);
    if all(l == vec3<f32>(0.0)) {
        return s;
    }
    return s * l.x + t * l.y + ns * l.z;
}

// The hit's normals turned to the side a ray arrives from (`front`), twin of Facing in
// src/math/geometry.rs: ng for sidedness, offsets and leaks, ns for the BSDF.
struct Facing {
    ng: vec3<f32>,
    ns: vec3<f32>,
    interpolated: bool,
}

fn facing(hit: Hit, front: bool) -> Facing {
    let s = select(-1.0, 1.0, front);
    return Facing(s * hit.normal, s * hit.shading,
        (HAS_SMOOTH || HAS_NORMAL_MAPS || HAS_SDF_GRIDS) && any(hit.shading != hit.normal));
}

// A reflected direction below the geometric surface carries nothing (smooth triangles only).
fn reflection_leaks(f: Facing, dir: vec3<f32>) -> bool {
    return f.interpolated && dot(dir, f.ng) <= 0.0;
}

// A refracted direction that stays on the ray's side carries nothing (smooth triangles only).
fn refraction_leaks(f: Facing, dir: vec3<f32>) -> bool {
    return f.interpolated && dot(dir, f.ng) >= 0.0;
}
