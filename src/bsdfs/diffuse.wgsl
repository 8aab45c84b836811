// Lambertian reflection (twin of src/bsdfs/diffuse.rs): albedo / pi, two-sided, the cosine
// hemisphere in the local frame; on the surface the albedo as it is, and the classic photon
// roulette (phong.wgsl's classic_bounce). Words: 0 the reflectance slot. Library, no entry
// point; writes nothing.

fn diffuse_front_pdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    return select(0.0, cosine_hemisphere_pdf(wi), wi.z > 0.0 && wo.z > 0.0);
}
fn diffuse_diffuse_out(b: Bsdf, wo: vec3<f32>) -> vec3<f32> {
    if wo.z == 0.0 { return vec3<f32>(0.0); }
    return w_rgb(b.w0);
}
fn diffuse_store_weight(b: Bsdf, wi: vec3<f32>) -> f32 { return select(1.0, 0.0, wi.z == 0.0); }
fn diffuse_has_diffuse(b: Bsdf) -> bool { return true; }
fn diffuse_has_lobe(b: Bsdf) -> bool { return false; }
fn diffuse_pdf(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let fr = to_front(wi, wo);
    if !fr.ok { return 0.0; }
    return diffuse_front_pdf(fr.wi, fr.wo);
}
fn diffuse_sample(b: Bsdf, wo_in: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo_in);
    if !fr.ok { return lobe_none(); }
    let wi = square_to_cosine_hemisphere(u.yz);
    let pdf = diffuse_front_pdf(wi, fr.wo);
    return back_to_side(LobeSampleW(wi, w_rgb(b.w0), pdf, false, pdf > 0.0), fr.flipped);
}

fn diffuse_surface_diffuse_albedo(s: Surface, wo: vec3<f32>) -> vec3<f32> { return w_rgb(s.b.w0); }
fn diffuse_surface_store_weight(s: Surface, wi: vec3<f32>) -> f32 { return 1.0; }
fn diffuse_surface_eval_diffuse(s: Surface, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> { return w_rgb(s.b.w0) / PI; }
fn diffuse_surface_photon_bounce(s: Surface, d: vec3<f32>, hit: Hit, u: vec3<f32>) -> Bounce {
    return classic_bounce(w_rgb(s.b.w0), vec3<f32>(0.0), 0.0, d, hit, u);
}
