// The emissive sphere light (twin of src/lights/sphere.rs): a uniform point of the sphere, then
// the area lights' emission and shadow ray (area.wgsl). p0.x its sphere. Library, no entry
// point; writes nothing.

fn sphere_point(l: Light, u: vec3<f32>) -> SurfacePoint {
    let s = load_sphere(l.p0.x);
    let n = uniform_sphere(u.y, u.z);
    var sp: SurfacePoint;
    sp.p = s.center + s.radius * n;
    sp.n = n;
    sp.material = s.material;
    let q = sphere_frame(s);
    sp.texel = area_texel(l, sphere_uv(sphere_rotate(-q.xyz, q.w, n)));
    return sp;
}

fn sphere_emit(l: Light, u0: vec3<f32>, u3: f32, u4: f32) -> Emission {
    return area_emit(l, sphere_point(l, u0), u3, u4);
}

fn sphere_sample(l: Light, x: vec3<f32>, ns: vec3<f32>, u: vec3<f32>) -> LightSample {
    return area_sample(l, sphere_point(l, u), x);
}

fn sphere_anchor(l: Light, u: vec3<f32>) -> Anchor {
    return Anchor(sphere_point(l, u).p, true);
}

fn sphere_material(l: Light) -> LightSurface {
    return LightSurface(load_sphere(l.p0.x).material, true);
}
