// A microfacet dielectric interface (twin of src/bsdfs/rough_dielectric.rs, after Walter et
// al. 2007): reflection and transmission, wo.z < 0 inside, transmitted radiance scaled by
// eta_ti^2. Words: 0 eta (x) and the distribution (y), 1 reflectance, 2 transmittance,
// 3 alpha_u, 4 alpha_v (slots). Library, no entry point; writes nothing.

fn rough_dielectric_microfacet(b: Bsdf) -> Microfacet { return Microfacet(b.w0.y, w_f(b.w3), w_f(b.w4)); }
struct HalfVector { m: vec3<f32>, reflect: bool, e: f32 }
fn rough_dielectric_half_vector(eta: f32, wi: vec3<f32>, wo: vec3<f32>) -> HalfVector {
    let refl = wo.z * wi.z > 0.0;
    let e = select(1.0 / eta, eta, wo.z > 0.0);
    let m = bsdf_normalize(wo + wi * select(e, 1.0, refl));
    return HalfVector(mulsign(m, m.z), refl, e);
}
fn rough_dielectric_front_eval(mf: Microfacet, eta: f32, reflectance: vec3<f32>, transmittance: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    if wo.z == 0.0 || wi.z == 0.0 { return vec3<f32>(0.0); }
    let hv = rough_dielectric_half_vector(eta, wi, wo);
    let m = hv.m; let e = hv.e;
    let d = mf_d(mf, m);
    let f = fresnel_dielectric_mi(bsdf_dot(wo, m), eta).f;
    let g = mf_g(mf, wo, wi, m);
    if hv.reflect { return reflectance * (f * d * g / (4.0 * abs(wo.z) * abs(wi.z))); }
    let scale = select(1.0, 1.0 / (e * e), radiance);
    let dot_o = bsdf_dot(wo, m); let dot_i = bsdf_dot(wi, m);
    let denom = dot_o + e * dot_i;
    let v = scale * (1.0 - f) * d * g * e * e * dot_o * dot_i / (wo.z * denom * denom);
    return transmittance * (abs(v) / abs(wi.z));
}
fn rough_dielectric_front_pdf(mf: Microfacet, eta: f32, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if wo.z == 0.0 { return 0.0; }
    let hv = rough_dielectric_half_vector(eta, wi, wo);
    let m = hv.m; let e = hv.e;
    let dot_o = bsdf_dot(wo, m); let dot_i = bsdf_dot(wi, m);
    if dot_o * wo.z <= 0.0 || dot_i * wi.z <= 0.0 { return 0.0; }
    var dwh_dwi: f32;
    if hv.reflect {
        dwh_dwi = 1.0 / (4.0 * dot_i);
    } else {
        let x = dot_o + e * dot_i;
        dwh_dwi = e * e * dot_i / (x * x);
    }
    let f = fresnel_dielectric_mi(dot_o, eta).f;
    let prob = mf_pdf_visible(mf, mulsign(wo, wo.z), m) * select(1.0 - f, f, hv.reflect);
    return prob * abs(dwh_dwi);
}
fn rough_dielectric_front_sample(mf: Microfacet, eta: f32, reflectance: vec3<f32>, transmittance: vec3<f32>, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    if wo.z == 0.0 { return lobe_none(); }
    let ms = mf_sample_visible(mf, mulsign(wo, wo.z), u.yz);
    if ms.pdf == 0.0 { return lobe_none(); }
    let m = ms.m;
    let dot_o = bsdf_dot(wo, m);
    let fr = fresnel_dielectric_mi(dot_o, eta); let f = fr.f;
    var wi: vec3<f32>; var weight: vec3<f32>; var pdf: f32;
    let refl = u.x <= f;
    if refl {
        wi = bsdf_reflect(wo, m);
        weight = reflectance;
        pdf = ms.pdf * f / abs(4.0 * bsdf_dot(wi, m));
    } else {
        wi = bsdf_refract(wo, m, fr.cos_t, fr.eta_ti);
        let factor = select(1.0, fr.eta_ti * fr.eta_ti, radiance);
        let dot_i = bsdf_dot(wi, m);
        let x = dot_o + fr.eta_it * dot_i;
        let dwh = fr.eta_it * fr.eta_it * dot_i / (x * x);
        weight = transmittance * factor;
        pdf = ms.pdf * (1.0 - f) * abs(dwh);
    }
    weight *= mf_smith_g1(mf, wi, m);
    let right_side = select((wi.z * wo.z) < 0.0, (wi.z * wo.z) > 0.0, refl);
    return LobeSampleW(wi, weight, pdf, false, right_side && pdf > 0.0);
}
fn rough_dielectric_eval_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    return rough_dielectric_front_eval(rough_dielectric_microfacet(b), w_f(b.w0), w_rgb(b.w1), w_rgb(b.w2), wi, wo, radiance);
}
fn rough_dielectric_pdf_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    return rough_dielectric_front_pdf(rough_dielectric_microfacet(b), w_f(b.w0), wi, wo);
}
fn rough_dielectric_sample_lobe(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    return rough_dielectric_front_sample(rough_dielectric_microfacet(b), w_f(b.w0), w_rgb(b.w1), w_rgb(b.w2), wo, u, radiance);
}
fn rough_dielectric_lobe_transmits(b: Bsdf) -> bool { return true; }
