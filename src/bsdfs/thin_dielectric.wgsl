// A thin dielectric sheet (twin of src/bsdfs/thin_dielectric.rs): delta reflection with
// R' = 2R / (1 + R), straight pass-through with 1 - R', either side alike; camera paths split
// at it as at glass. Words: 0 eta (x), 1 reflectance, 2 transmittance (slots). Library, no
// entry point; writes nothing.

fn thin_dielectric_front_sample(eta: f32, reflectance: vec3<f32>, transmittance: vec3<f32>, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let r0 = fresnel_dielectric_mi(abs(wo.z), eta).f;
    let r = r0 * 2.0 / (1.0 + r0);
    if u.x <= r { return LobeSampleW(reflect_z(wo), reflectance, 0.0, true, true); }
    return LobeSampleW(-wo, transmittance, 0.0, true, true);
}
fn thin_dielectric_lobe_is_delta(b: Bsdf) -> bool { return true; }
fn thin_dielectric_passes_null(b: Bsdf) -> bool { return true; }
fn thin_dielectric_null_transmission(b: Bsdf, wo: vec3<f32>) -> vec3<f32> {
    let r = fresnel_dielectric_mi(abs(wo.z), w_f(b.w0)).f;
    return w_rgb(b.w2) * (1.0 - select(1.0, 2.0 * r / (1.0 + r), r < 1.0));
}
fn thin_dielectric_sample_lobe(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    return thin_dielectric_front_sample(w_f(b.w0), w_rgb(b.w1), w_rgb(b.w2), wo, u);
}
fn thin_dielectric_surface_split(hit: Hit, s: Surface, f: Facing, d: vec3<f32>) -> Dielectric {
    let r = fresnel_dielectric_mi(abs(dot(d, f.ns)), w_f(s.b.w0)).f;
    return Dielectric(reflect_dir(d, f.ns), d, select(1.0, 2.0 * r / (1.0 + r), r < 1.0), 1.0);
}
fn thin_dielectric_surface_delta(hit: Hit, s: Surface, f: Facing, d: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, rng: ptr<function, Rng>) -> bool {
    let r = fresnel_dielectric_mi(abs(dot(*d, f.ns)), w_f(s.b.w0)).f;
    let reflectance = select(1.0, 2.0 * r / (1.0 + r), r < 1.0);
    let reflects = rng_next(rng) < reflectance;
    if reflects {
        *d = reflect_dir(*d, f.ns);
    }
    return !select(refraction_leaks(f, *d), reflection_leaks(f, *d), reflects);
}
