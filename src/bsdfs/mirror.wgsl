// A perfect mirror (twin of src/bsdfs/mirror.rs): the reflectance times the mirror direction
// about the shading normal facing the ray; photons reflect by roulette on the reflectance.
// Words: 0 the reflectance slot. Library, no entry point; writes nothing.

fn mirror_lobe_is_delta(b: Bsdf) -> bool { return true; }
fn mirror_sample_lobe(b: Bsdf, wo_in: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo_in);
    if !fr.ok { return lobe_none(); }
    return back_to_side(LobeSampleW(reflect_z(fr.wo), w_rgb(b.w0), 0.0, true, true), fr.flipped);
}
fn mirror_surface_diffuse_albedo(s: Surface, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }
fn mirror_surface_store_weight(s: Surface, wi: vec3<f32>) -> f32 { return 1.0; }
fn mirror_surface_eval_diffuse(s: Surface, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> { return vec3<f32>(0.0); }
fn mirror_surface_delta(hit: Hit, s: Surface, f: Facing, d: ptr<function, vec3<f32>>, t: ptr<function, vec3<f32>>, rng: ptr<function, Rng>) -> bool {
    *t *= w_rgb(s.b.w0);
    *d = reflect_dir(*d, f.ns);
    return !reflection_leaks(f, *d);
}
fn mirror_surface_photon_bounce(s: Surface, d: vec3<f32>, hit: Hit, u: vec3<f32>) -> Bounce {
    let f = facing(hit, dot(d, hit.normal) < 0.0);
    var b = Bounce(vec3<f32>(0.0), BOUNCE_ABSORB, vec3<f32>(0.0));
    let ks = w_rgb(s.b.w0);
    let p = max3(ks);
    if u.x < p {
        b.kind = BOUNCE_DELTA;
        b.dir = reflect_dir(d, f.ns);
        b.weight = ks / p;
    }
    if b.kind != BOUNCE_ABSORB && reflection_leaks(f, b.dir) {
        b.kind = BOUNCE_ABSORB;
    }
    return b;
}
