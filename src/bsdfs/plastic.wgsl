// A diffuse base under a smooth or rough dielectric coating (twin of src/bsdfs/plastic.rs):
// the base's inter-reflections in closed form, the rough coating's transmittance from its
// table in bsdf_tables; two-sided. Words: 0 the base, 1 the coating's tint (slots), 2 eta,
// nonlinear, table offset, sampling weight, 3 Fdr, distribution (or none), alpha. Library.

struct PlasticParams {
    albedo: vec3<f32>,
    specular: vec3<f32>,
    eta: f32,
    nonlinear: u32,
    table: u32,
    specular_sampling_weight: f32,
    internal_reflectance: f32,
    rough: bool,
    mf: Microfacet,
}
fn plastic_params(b: Bsdf) -> PlasticParams {
    let a = bitcast<f32>(b.w3.z);
    return PlasticParams(w_rgb(b.w0), w_rgb(b.w1), bitcast<f32>(b.w2.x), b.w2.y, b.w2.z, bitcast<f32>(b.w2.w),
        bitcast<f32>(b.w3.x), b.w3.y != PLASTIC_NO_MICROFACET, Microfacet(b.w3.y, a, a));
}
fn plastic_transmittance(b: PlasticParams, cos_theta: f32) -> f32 {
    if !b.rough { return 1.0 - fresnel_dielectric_mi(cos_theta, b.eta).f; }
    let x = cos_theta * f32(BSDF_TABLE_RES - 1u);
    let i = min(u32(max(x, 0.0)), BSDF_TABLE_RES - 2u);
    let v0 = bsdf_tables[b.table + i];
    let v1 = bsdf_tables[b.table + i + 1u];
    return v0 + (v1 - v0) * (x - f32(i));
}
fn plastic_front_diffuse_out(b: PlasticParams, cos_o: f32) -> vec3<f32> {
    let kd = b.albedo; let ri = b.internal_reflectance;
    let denom = select(vec3<f32>(1.0 - ri), vec3<f32>(1.0) - kd * ri, b.nonlinear != 0u);
    return kd / denom * (plastic_transmittance(b, cos_o) / (b.eta * b.eta));
}
fn plastic_prob_specular(b: PlasticParams, cos_o: f32) -> f32 {
    let t = plastic_transmittance(b, cos_o);
    let ssw = b.specular_sampling_weight;
    let ps = (1.0 - t) * ssw; let pd = t * (1.0 - ssw);
    return select(0.0, ps / (ps + pd), ps + pd > 0.0);
}
fn plastic_front_eval_lobe(b: PlasticParams, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if !b.rough || wi.z <= 0.0 || wo.z <= 0.0 { return vec3<f32>(0.0); }
    let mf = b.mf;
    let h = bsdf_normalize(wi + wo);
    let f = fresnel_dielectric_mi(bsdf_dot(wo, h), b.eta).f;
    return b.specular * (f * mf_d(mf, h) * mf_g(mf, wo, wi, h) / (4.0 * wo.z * wi.z));
}
fn plastic_front_pdf_lobe(b: PlasticParams, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if !b.rough || wi.z <= 0.0 || wo.z <= 0.0 { return 0.0; }
    let mf = b.mf;
    let h = bsdf_normalize(wi + wo);
    return mf_d(mf, h) * mf_smith_g1(mf, wo, h) / (4.0 * wo.z);
}
fn plastic_front_sample_lobe(b: PlasticParams, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let ks = b.specular;
    if !b.rough {
        let f = fresnel_dielectric_mi(wo.z, b.eta).f;
        return LobeSampleW(reflect_z(wo), ks * f, 0.0, true, true);
    }
    let mf = b.mf;
    let ms = mf_sample_visible(mf, wo, u.yz);
    let wi = bsdf_reflect(wo, ms.m);
    if ms.pdf == 0.0 || wi.z <= 0.0 { return lobe_none(); }
    let f = fresnel_dielectric_mi(bsdf_dot(wo, ms.m), b.eta).f;
    let pdf = ms.pdf / (4.0 * bsdf_dot(wi, ms.m));
    return LobeSampleW(wi, ks * (f * mf_smith_g1(mf, wi, ms.m)), pdf, false, pdf > 0.0);
}
fn plastic_front_pdf(b: PlasticParams, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if wi.z <= 0.0 || wo.z <= 0.0 { return 0.0; }
    let ps = plastic_prob_specular(b, wo.z);
    let spec = select(0.0, ps * plastic_front_pdf_lobe(b, wi, wo), b.rough);
    return spec + (1.0 - ps) * cosine_hemisphere_pdf(wi);
}
fn plastic_front_sample(b: PlasticParams, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let ps = plastic_prob_specular(b, wo.z);
    let rough = b.rough;
    if u.x < ps && !rough {
        var s = plastic_front_sample_lobe(b, wo, u);
        s.weight /= ps;
        return s;
    }
    var wi: vec3<f32>;
    if u.x < ps {
        wi = bsdf_reflect(wo, mf_sample_visible(b.mf, wo, u.yz).m);
    } else {
        wi = square_to_cosine_hemisphere(u.yz);
    }
    let pdf = plastic_front_pdf(b, wi, wo);
    if pdf <= 0.0 { return lobe_none(); }
    let diffuse = plastic_front_diffuse_out(b, wo.z) * (plastic_transmittance(b, wi.z) * BSDF_FRAC_1_PI);
    let weight = (diffuse + plastic_front_eval_lobe(b, wi, wo)) * wi.z / pdf;
    return LobeSampleW(wi, weight, pdf, false, true);
}

fn plastic_diffuse_out(b: Bsdf, wo: vec3<f32>) -> vec3<f32> {
    if wo.z == 0.0 { return vec3<f32>(0.0); }
    return plastic_front_diffuse_out(plastic_params(b), abs(wo.z));
}
fn plastic_store_weight(b: Bsdf, wi: vec3<f32>) -> f32 {
    if wi.z == 0.0 { return 0.0; }
    return plastic_transmittance(plastic_params(b), abs(wi.z));
}
fn plastic_eval_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    let fr = to_front(wi, wo);
    if !fr.ok { return vec3<f32>(0.0); }
    return plastic_front_eval_lobe(plastic_params(b), fr.wi, fr.wo);
}
fn plastic_pdf_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let fr = to_front(wi, wo);
    if !fr.ok { return 0.0; }
    return plastic_front_pdf_lobe(plastic_params(b), fr.wi, fr.wo);
}
fn plastic_sample_lobe(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo);
    if !fr.ok { return lobe_none(); }
    return back_to_side(plastic_front_sample_lobe(plastic_params(b), fr.wo, u), fr.flipped);
}
fn plastic_has_diffuse(b: Bsdf) -> bool { return true; }
fn plastic_lobe_is_delta(b: Bsdf) -> bool { return b.w3.y == PLASTIC_NO_MICROFACET; }
fn plastic_pdf(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let fr = to_front(wi, wo);
    if !fr.ok { return 0.0; }
    return plastic_front_pdf(plastic_params(b), fr.wi, fr.wo);
}
fn plastic_sample(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo);
    if !fr.ok { return lobe_none(); }
    return back_to_side(plastic_front_sample(plastic_params(b), fr.wo, u), fr.flipped);
}
// A textured base or tint changes the coating's sampling weight (Plastic::with_diffuse).
fn plastic_finish(b_in: Bsdf) -> Bsdf {
    var b = b_in;
    if (b.textured & 3u) != 0u {
        let kd = w_rgb(b.w0);
        let ks = w_rgb(b.w1);
        let d_mean = (kd.x + kd.y + kd.z) / 3.0;
        let s_mean = (ks.x + ks.y + ks.z) / 3.0;
        b.w2.w = bitcast<u32>(s_mean / (d_mean + s_mean));
    }
    return b;
}
