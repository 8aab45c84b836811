// The directional light (twin of src/lights/directional/mod.rs): p0 the scene's bounding
// sphere (centre, radius), p1 the direction of travel, p2 the irradiance. Library, no entry
// point.

fn directional_emit(l: Light, u0: vec3<f32>, u3: f32, u4: f32) -> Emission {
    // A uniform point of the disc of the sphere's radius, two radii back from the centre.
    let r = bitcast<f32>(l.p0.w);
    let d = light_vec(l.p1);
    let origin = light_vec(l.p0) - 2.0 * r * d + light_disc(r, d, u0.y, u0.z);
    return Emission(origin, d, vec3<f32>(0.0), vec3<f32>(1.0));
}

fn directional_sample(l: Light, x: vec3<f32>, ns: vec3<f32>, u: vec3<f32>) -> LightSample {
    return LightSample(x - light_vec(l.p1), light_vec(l.p2), true, 0.0);
}

fn directional_anchor(l: Light, u: vec3<f32>) -> Anchor {
    return Anchor(vec3<f32>(0.0), false);
}
