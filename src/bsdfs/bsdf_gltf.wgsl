// glTF 2.0's metallic-roughness material (Appendix B, KHR_materials_specular/_ior, thin-walled _transmission): twin of
// src/bsdfs/gltf.rs, function for function, same operation order; front side only (wo.z > 0), wi.z < 0 transmits.
// Library, no entry point; writes nothing. Composed with bsdf.wgsl (its dispatch calls these), needs BSDF_GLTF_MEAN
// (S(mu), generated from Rust's table). BsdfParams fields: albedo = base colour, eta_c = (metallic, roughness,
// transmission), specular = the dielectric's f0, eta = its f90; textures = its parameter textures (bsdf_at reads them).

fn gltf_schlick_weight(c: f32) -> f32 {
    let m = clamp(1.0 - c, 0.0, 1.0);
    let m2 = m * m;
    return m2 * m2 * m;
}
fn gltf_mean(v: vec3<f32>) -> f32 { return (v.x + v.y + v.z) / 3.0; }
fn gltf_max3(v: vec3<f32>) -> f32 { return max(max(v.x, v.y), v.z); }

// S(cos_o) looked up linearly in the table of schlick_mean_table.
fn gltf_schlick_mean(cos_o: f32) -> f32 {
    let x = clamp(cos_o, 0.0, 1.0) * f32(GLTF_MEAN_RES);
    let i = min(u32(x), GLTF_MEAN_RES - 1u);
    let f = x - f32(i);
    let a = BSDF_GLTF_MEAN[i];
    return a + (BSDF_GLTF_MEAN[i + 1u] - a) * f;
}
fn gltf_microfacet(b: BsdfParams) -> Microfacet {
    let a = max(b.eta_c.y * b.eta_c.y, 1e-4);
    return Microfacet(MF_GGX, a, a);
}
fn gltf_diffuse_weight(b: BsdfParams) -> f32 { return (1.0 - b.eta_c.x) * (1.0 - b.eta_c.z); }
fn gltf_dielectric_max(b: BsdfParams, c: f32) -> f32 {
    let f0 = gltf_max3(b.specular);
    return f0 + (b.eta - f0) * gltf_schlick_weight(c);
}
fn gltf_reflect_tint(b: BsdfParams, c: f32) -> vec3<f32> {
    let w = gltf_schlick_weight(c);
    let fd = b.specular + (vec3<f32>(b.eta) - b.specular) * w;
    let fm = b.albedo + (vec3<f32>(1.0) - b.albedo) * w;
    return fd * (1.0 - b.eta_c.x) + fm * b.eta_c.x;
}
fn gltf_transmit_tint(b: BsdfParams, c: f32) -> vec3<f32> {
    let w = (1.0 - b.eta_c.x) * b.eta_c.z * (1.0 - gltf_dielectric_max(b, c));
    return b.albedo * max(w, 0.0);
}
fn gltf_reflect_probability(b: BsdfParams, c: f32) -> f32 {
    if b.eta_c.z <= 0.0 || b.eta_c.x >= 1.0 { return 1.0; }
    let r = gltf_mean(gltf_reflect_tint(b, c));
    let t = gltf_mean(gltf_transmit_tint(b, c));
    if r + t > 0.0 { return r / (r + t); }
    return 1.0;
}
fn gltf_diffuse_out(b: BsdfParams, cos_o: f32) -> vec3<f32> {
    let f0 = gltf_max3(b.specular);
    let g = 1.0 - f0 - (b.eta - f0) * gltf_schlick_mean(cos_o);
    return b.albedo * (gltf_diffuse_weight(b) * max(g, 0.0));
}
fn gltf_has_diffuse(b: BsdfParams) -> bool { return gltf_diffuse_weight(b) > 0.0; }

// Half vector of wi (mirrored to the front when it transmits) and wo; ok false when degenerate.
struct GltfHalf { h: vec3<f32>, wr: vec3<f32>, ok: bool }
fn gltf_half(wi: vec3<f32>, wo: vec3<f32>) -> GltfHalf {
    let wr = select(wi, flip_z(wi), wi.z < 0.0);
    let h = wr + wo;
    if wr.z > 0.0 && wo.z > 0.0 && bsdf_dot(h, h) > 0.0 { return GltfHalf(bsdf_normalize(h), wr, true); }
    return GltfHalf(vec3<f32>(0.0), wr, false);
}
fn gltf_eval_lobe(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let hv = gltf_half(wi, wo);
    if !hv.ok { return vec3<f32>(0.0); }
    let mf = gltf_microfacet(b);
    let spec = mf_d(mf, hv.h) * mf_g(mf, hv.wr, wo, hv.h) / (4.0 * hv.wr.z * wo.z);
    let c = bsdf_dot(wo, hv.h);
    let tint = select(gltf_reflect_tint(b, c), gltf_transmit_tint(b, c), wi.z < 0.0);
    return tint * spec;
}
fn gltf_pdf_lobe(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let hv = gltf_half(wi, wo);
    if !hv.ok { return 0.0; }
    let c = bsdf_dot(wo, hv.h);
    if c <= 0.0 { return 0.0; }
    var p = gltf_reflect_probability(b, c);
    if wi.z < 0.0 { p = 1.0 - p; }
    return p * mf_pdf_visible(gltf_microfacet(b), wo, hv.h) / (4.0 * c);
}
fn gltf_sample_lobe(b: BsdfParams, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let mf = gltf_microfacet(b);
    let ms = mf_sample_visible(mf, wo, u.yz);
    let wr = bsdf_reflect(wo, ms.m);
    let c = bsdf_dot(wo, ms.m);
    if ms.pdf <= 0.0 || wr.z <= 0.0 || c <= 0.0 { return lobe_none(); }
    let p_r = gltf_reflect_probability(b, c);
    var wi = wr;
    var tint = gltf_reflect_tint(b, c);
    var p = p_r;
    if u.x >= p_r {
        wi = flip_z(wr);
        tint = gltf_transmit_tint(b, c);
        p = 1.0 - p_r;
    }
    let pdf = p * ms.pdf / (4.0 * c);
    let weight = tint * (mf_smith_g1(mf, wr, ms.m) / p);
    if pdf > 0.0 && gltf_max3(weight) > 0.0 { return LobeSampleW(wi, weight, pdf, false, true); }
    return lobe_none();
}
fn gltf_lobe_probability(b: BsdfParams, cos_o: f32) -> f32 {
    let d = gltf_mean(gltf_diffuse_out(b, cos_o));
    if d <= 0.0 { return 1.0; }
    let l = gltf_mean(gltf_reflect_tint(b, cos_o) + gltf_transmit_tint(b, cos_o));
    return clamp(l / (l + d), 0.05, 0.95);
}
fn gltf_diffuse_value(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 { return vec3<f32>(0.0); }
    return gltf_diffuse_out(b, wo.z) * BSDF_FRAC_1_PI;
}
fn gltf_pdf(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = gltf_lobe_probability(b, wo.z);
    return p * gltf_pdf_lobe(b, wi, wo) + (1.0 - p) * cosine_hemisphere_pdf(wi);
}
fn gltf_sample(b: BsdfParams, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let p = gltf_lobe_probability(b, wo.z);
    if u.x < p {
        let s = gltf_sample_lobe(b, wo, vec3<f32>(u.x / p, u.y, u.z));
        if !s.ok { return lobe_none(); }
        let pdf = gltf_pdf(b, s.wi, wo);
        let f = gltf_eval_lobe(b, s.wi, wo) + gltf_diffuse_value(b, s.wi, wo);
        if pdf > 0.0 { return LobeSampleW(s.wi, f * abs(s.wi.z) / pdf, pdf, false, true); }
        return lobe_none();
    }
    let wi = square_to_cosine_hemisphere(u.yz);
    let pdf = gltf_pdf(b, wi, wo);
    let f = gltf_eval_lobe(b, wi, wo) + gltf_diffuse_value(b, wi, wo);
    if pdf > 0.0 && wi.z > 0.0 { return LobeSampleW(wi, f * wi.z / pdf, pdf, false, true); }
    return lobe_none();
}
