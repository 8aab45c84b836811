// A smooth dielectric interface (twin of src/bsdfs/glass.rs): camera paths split at it
// (glass_split), photons and gather rays choose by the exact or Schlick reflectance; in the
// local frame Mitsuba's smooth dielectric with its tints. Words: 0 the index (x), 1 and 2
// the reflection's and transmission's tints (slots). Library, no entry point; writes nothing.

// Mitsuba's smooth interface: reflect when u.x <= F, else refract (radiance scaled by eta_ti^2).
fn glass_smooth_sample(eta: f32, reflectance: vec3<f32>, transmittance: vec3<f32>, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = fresnel_dielectric_mi(wo.z, eta);
    if u.x <= fr.f { return LobeSampleW(reflect_z(wo), reflectance, 0.0, true, true); }
    let factor = select(1.0, fr.eta_ti * fr.eta_ti, radiance);
    let wi = vec3<f32>(-fr.eta_ti * wo.x, -fr.eta_ti * wo.y, fr.cos_t);
    return LobeSampleW(wi, transmittance * factor, 0.0, true, true);
}
fn glass_lobe_is_delta(b: Bsdf) -> bool { return true; }
fn glass_sample_lobe(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    return glass_smooth_sample(w_f(b.w0), w_rgb(b.w1), w_rgb(b.w2), wo, u, radiance);
}
fn glass_surface_diffuse_albedo(s: Surface, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }
fn glass_surface_store_weight(s: Surface, wi: vec3<f32>) -> f32 { return 1.0; }
fn glass_surface_eval_diffuse(s: Surface, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }
fn glass_surface_split(hit: Hit, s: Surface, f: Facing, d: vec3<f32>) -> Dielectric {
    return dielectric(d, hit.normal, hit.shading, w_f(s.b.w0));
}
fn glass_surface_delta(hit: Hit, s: Surface, f: Facing, d: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, rng: ptr<function, Rng>) -> bool {
    let g = dielectric(*d, hit.normal, hit.shading, w_f(s.b.w0));
    let u = rng_next(rng);
    let reflects = u < g.reflectance;
    *t *= select(g.eta * g.eta, 1.0, reflects);
    *d = select(g.refracted, g.reflected, reflects);
    return !select(refraction_leaks(f, *d), reflection_leaks(f, *d), reflects);
}
fn glass_surface_photon_bounce(s: Surface, d: vec3<f32>, hit: Hit, u: vec3<f32>) -> Bounce {
    let f = facing(hit, dot(d, hit.normal) < 0.0);
    var b = Bounce(vec3<f32>(0.0), BOUNCE_ABSORB, vec3<f32>(0.0));
    let g = dielectric(d, hit.normal, hit.shading, w_f(s.b.w0));
    b.kind = BOUNCE_DELTA;
    b.weight = vec3<f32>(1.0);
    let reflects = u.x < g.reflectance;
    b.dir = select(g.refracted, g.reflected, reflects);
    if (reflects && reflection_leaks(f, b.dir)) || (!reflects && refraction_leaks(f, b.dir)) {
        b.kind = BOUNCE_ABSORB;
    }
    return b;
}
