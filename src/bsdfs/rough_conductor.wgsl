// A microfacet conductor (twin of src/bsdfs/rough_conductor.rs): F D G / (4 cos_o cos_i)
// times a tint, visible-normal sampling, two-sided. Words: 0 eta (xyz) and the distribution
// (w), 1 k, 2 the tint slot, 3 alpha_u, 4 alpha_v (slots). Library, no entry point; writes
// nothing.

fn rough_conductor_microfacet(b: Bsdf) -> Microfacet { return Microfacet(b.w0.w, w_f(b.w3), w_f(b.w4)); }
fn rough_conductor_front_eval(mf: Microfacet, eta: vec3<f32>, k: vec3<f32>, specular: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 { return vec3<f32>(0.0); }
    let h = bsdf_normalize(wi + wo);
    let d = mf_d(mf, h);
    if d == 0.0 { return vec3<f32>(0.0); }
    let value = d * mf_g(mf, wo, wi, h) / (4.0 * wo.z * wi.z);
    return fresnel_conductor(bsdf_dot(wo, h), eta, k) * specular * value;
}
fn rough_conductor_front_pdf(mf: Microfacet, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let h = bsdf_normalize(wi + wo);
    if wi.z <= 0.0 || wo.z <= 0.0 || bsdf_dot(wo, h) <= 0.0 || bsdf_dot(wi, h) <= 0.0 { return 0.0; }
    return mf_d(mf, h) * mf_smith_g1(mf, wo, h) / (4.0 * wo.z);
}
fn rough_conductor_front_sample(mf: Microfacet, eta: vec3<f32>, k: vec3<f32>, specular: vec3<f32>, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let ms = mf_sample_visible(mf, wo, u.yz); let m = ms.m;
    let wi = bsdf_reflect(wo, m);
    if ms.pdf == 0.0 || wi.z <= 0.0 { return lobe_none(); }
    let pdf = ms.pdf / (4.0 * bsdf_dot(wi, m));
    let weight = fresnel_conductor(bsdf_dot(wo, m), eta, k) * specular * mf_smith_g1(mf, wi, m);
    return LobeSampleW(wi, weight, pdf, false, pdf > 0.0);
}
fn rough_conductor_eval_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    let fr = to_front(wi, wo);
    if !fr.ok { return vec3<f32>(0.0); }
    return rough_conductor_front_eval(rough_conductor_microfacet(b), w_rgb(b.w0), w_rgb(b.w1), w_rgb(b.w2), fr.wi, fr.wo);
}
fn rough_conductor_pdf_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let fr = to_front(wi, wo);
    if !fr.ok { return 0.0; }
    return rough_conductor_front_pdf(rough_conductor_microfacet(b), fr.wi, fr.wo);
}
fn rough_conductor_sample_lobe(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo);
    if !fr.ok { return lobe_none(); }
    let s = rough_conductor_front_sample(rough_conductor_microfacet(b), w_rgb(b.w0), w_rgb(b.w1), w_rgb(b.w2), fr.wo, u);
    return back_to_side(s, fr.flipped);
}
