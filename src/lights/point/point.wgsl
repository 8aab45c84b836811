// The point light (twin of src/lights/point/mod.rs): an isotropic source, photons uniform over
// the sphere, one shadow ray to its position. p0 its position, p1 its intensity. Library, no
// entry point; writes nothing.

fn point_emit(l: Light, u0: vec3<f32>, u3: f32, u4: f32) -> Emission {
    return Emission(light_vec(l.p0), uniform_sphere(u3, u4), vec3<f32>(0.0), vec3<f32>(1.0));
}

fn point_sample(l: Light, x: vec3<f32>, ns: vec3<f32>, u: vec3<f32>) -> LightSample {
    let p = light_vec(l.p0);
    let d = p - x;
    return LightSample(p, light_vec(l.p1) / max(dot(d, d), 1e-20), false, 0.0);
}

fn point_anchor(l: Light, u: vec3<f32>) -> Anchor {
    return Anchor(light_vec(l.p0), true);
}
