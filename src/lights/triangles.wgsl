// The emissive mesh light (twin of src/lights/triangles.rs): a triangle by area through its
// CDF, a uniform point on it, then the area lights' emission and shadow ray (area.wgsl).
// p0 = (first triangle, count, start of its CDF in light_cdf). Library, no entry point.

// Triangle of light l by area: binary search of its CDF (bounded by 32 steps).
fn triangles_pick(l: Light, u: f32) -> u32 {
    let first = l.p0.x;
    let count = l.p0.y;
    var lo = 0u;
    var hi = count;
    for (var i = 0u; i < 32u && lo < hi && spend(); i += 1u) {
        let mid = (lo + hi) / 2u;
        if light_cdf[l.p0.z + mid] <= u {
            lo = mid + 1u;
        } else {
            hi = mid;
        }
    }
    return first + min(lo, count - 1u);
}

fn triangles_point(l: Light, u: vec3<f32>) -> SurfacePoint {
    let t = triangles_pick(l, u.x);
    let tri = load_triangle(t);
    let s = sqrt(u.y);
    let b1 = 1.0 - s;
    let b2 = u.z * s;
    let e1 = tri.v1 - tri.v0;
    let e2 = tri.v2 - tri.v0;
    var sp: SurfacePoint;
    sp.p = tri.v0 + b1 * e1 + b2 * e2;
    sp.n = normalize(cross(e1, e2));
    sp.material = tri.material;
    sp.texel = area_texel(l, triangle_uv(t, vec2<f32>(b1, b2)));
    return sp;
}

fn triangles_emit(l: Light, u0: vec3<f32>, u3: f32, u4: f32) -> Emission {
    return area_emit(l, triangles_point(l, u0), u3, u4);
}

fn triangles_sample(l: Light, x: vec3<f32>, ns: vec3<f32>, u: vec3<f32>) -> LightSample {
    return area_sample(l, triangles_point(l, u), x);
}

fn triangles_anchor(l: Light, u: vec3<f32>) -> Anchor {
    return Anchor(triangles_point(l, u).p, true);
}

fn triangles_material(l: Light) -> LightSurface {
    return LightSurface(load_triangle(l.p0.x).material, true);
}
