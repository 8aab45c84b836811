// glTF 2.0's metallic-roughness material (twin of src/bsdfs/metallic_roughness.rs: Appendix
// B, KHR_materials_specular/_ior, thin-walled _transmission), same operation order; two-sided,
// wi.z < 0 transmits. Words: 0 base, 1 f0, 2 metallic, 3 roughness, 4 transmission, 5 the
// specular texture's alpha (slots), 6 f90. Needs BSDF_GLTF_MEAN (generated). Library.

struct MrParams { base: vec3<f32>, f0: vec3<f32>, metallic: f32, roughness: f32, transmission: f32, f90: f32 }
fn mr_params(b: Bsdf) -> MrParams {
    return MrParams(w_rgb(b.w0), w_rgb(b.w1), w_f(b.w2), w_f(b.w3), w_f(b.w4), w_f(b.w6));
}
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
fn gltf_microfacet(b: MrParams) -> Microfacet {
    let a = max(b.roughness * b.roughness, 1e-4);
    return Microfacet(MF_GGX, a, a);
}
fn gltf_diffuse_weight(b: MrParams) -> f32 { return (1.0 - b.metallic) * (1.0 - b.transmission); }
fn gltf_dielectric_max(b: MrParams, c: f32) -> f32 {
    let f0 = gltf_max3(b.f0);
    return f0 + (b.f90 - f0) * gltf_schlick_weight(c);
}
fn gltf_reflect_tint(b: MrParams, c: f32) -> vec3<f32> {
    let w = gltf_schlick_weight(c);
    let fd = b.f0 + (vec3<f32>(b.f90) - b.f0) * w;
    let fm = b.base + (vec3<f32>(1.0) - b.base) * w;
    return fd * (1.0 - b.metallic) + fm * b.metallic;
}
fn gltf_transmit_tint(b: MrParams, c: f32) -> vec3<f32> {
    let w = (1.0 - b.metallic) * b.transmission * (1.0 - gltf_dielectric_max(b, c));
    return b.base * max(w, 0.0);
}
fn gltf_reflect_probability(b: MrParams, c: f32) -> f32 {
    if b.transmission <= 0.0 || b.metallic >= 1.0 { return 1.0; }
    let r = gltf_mean(gltf_reflect_tint(b, c));
    let t = gltf_mean(gltf_transmit_tint(b, c));
    if r + t > 0.0 { return r / (r + t); }
    return 1.0;
}
fn gltf_diffuse_out(b: MrParams, cos_o: f32) -> vec3<f32> {
    let f0 = gltf_max3(b.f0);
    let g = 1.0 - f0 - (b.f90 - f0) * gltf_schlick_mean(cos_o);
    return b.base * (gltf_diffuse_weight(b) * max(g, 0.0));
}
fn gltf_has_diffuse(b: MrParams) -> bool { return gltf_diffuse_weight(b) > 0.0; }

// Half vector of wi (mirrored to the front when it transmits) and wo; ok false when degenerate.
struct GltfHalf { h: vec3<f32>, wr: vec3<f32>, ok: bool }
fn gltf_half(wi: vec3<f32>, wo: vec3<f32>) -> GltfHalf {
    let wr = select(wi, flip_z(wi), wi.z < 0.0);
    let h = wr + wo;
    if wr.z > 0.0 && wo.z > 0.0 && bsdf_dot(h, h) > 0.0 { return GltfHalf(bsdf_normalize(h), wr, true); }
    return GltfHalf(vec3<f32>(0.0), wr, false);
}
fn gltf_eval_lobe(b: MrParams, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    let hv = gltf_half(wi, wo);
    if !hv.ok { return vec3<f32>(0.0); }
    let mf = gltf_microfacet(b);
    let spec = mf_d(mf, hv.h) * mf_g(mf, hv.wr, wo, hv.h) / (4.0 * hv.wr.z * wo.z);
    let c = bsdf_dot(wo, hv.h);
    let tint = select(gltf_reflect_tint(b, c), gltf_transmit_tint(b, c), wi.z < 0.0);
    return tint * spec;
}
fn gltf_pdf_lobe(b: MrParams, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let hv = gltf_half(wi, wo);
    if !hv.ok { return 0.0; }
    let c = bsdf_dot(wo, hv.h);
    if c <= 0.0 { return 0.0; }
    var p = gltf_reflect_probability(b, c);
    if wi.z < 0.0 { p = 1.0 - p; }
    return p * mf_pdf_visible(gltf_microfacet(b), wo, hv.h) / (4.0 * c);
}
fn gltf_sample_lobe(b: MrParams, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
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
fn gltf_lobe_probability(b: MrParams, cos_o: f32) -> f32 {
    let d = gltf_mean(gltf_diffuse_out(b, cos_o));
    if d <= 0.0 { return 1.0; }
    let l = gltf_mean(gltf_reflect_tint(b, cos_o) + gltf_transmit_tint(b, cos_o));
    return clamp(l / (l + d), 0.05, 0.95);
}
fn gltf_diffuse_value(b: MrParams, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 { return vec3<f32>(0.0); }
    return gltf_diffuse_out(b, wo.z) * BSDF_FRAC_1_PI;
}
fn gltf_pdf(b: MrParams, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = gltf_lobe_probability(b, wo.z);
    return p * gltf_pdf_lobe(b, wi, wo) + (1.0 - p) * cosine_hemisphere_pdf(wi);
}
fn gltf_sample(b: MrParams, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
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

fn metallic_roughness_diffuse_out(b: Bsdf, wo: vec3<f32>) -> vec3<f32> {
    if wo.z == 0.0 { return vec3<f32>(0.0); }
    return gltf_diffuse_out(mr_params(b), abs(wo.z));
}
fn metallic_roughness_store_weight(b: Bsdf, wi: vec3<f32>) -> f32 {
    if wi.z == 0.0 { return 0.0; }
    return select(0.0, 1.0, gltf_has_diffuse(mr_params(b)));
}
fn metallic_roughness_eval_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    let fr = to_front(wi, wo);
    if !fr.ok { return vec3<f32>(0.0); }
    return gltf_eval_lobe(mr_params(b), fr.wi, fr.wo);
}
fn metallic_roughness_pdf_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let fr = to_front(wi, wo);
    if !fr.ok { return 0.0; }
    return gltf_pdf_lobe(mr_params(b), fr.wi, fr.wo);
}
fn metallic_roughness_sample_lobe(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo);
    if !fr.ok { return lobe_none(); }
    return back_to_side(gltf_sample_lobe(mr_params(b), fr.wo, u), fr.flipped);
}
fn metallic_roughness_has_diffuse(b: Bsdf) -> bool { return gltf_has_diffuse(mr_params(b)); }
fn metallic_roughness_lobe_probability(b: Bsdf, wo: vec3<f32>) -> f32 {
    return gltf_lobe_probability(mr_params(b), abs(wo.z));
}
fn metallic_roughness_pdf(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let fr = to_front(wi, wo);
    if !fr.ok { return 0.0; }
    return gltf_pdf(mr_params(b), fr.wi, fr.wo);
}
fn metallic_roughness_sample(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo);
    if !fr.ok { return lobe_none(); }
    return back_to_side(gltf_sample(mr_params(b), fr.wo, u), fr.flipped);
}
// The specular colour texture keeps F0 below F90; the specular texture's alpha scales both.
fn metallic_roughness_finish(b_in: Bsdf) -> Bsdf {
    var b = b_in;
    var f0 = w_rgb(b.w1);
    var f90 = w_f(b.w6);
    if (b.textured & 2u) != 0u {
        f0 = min(f0, vec3<f32>(f90));
    }
    if (b.textured & 32u) != 0u {
        let a = w_f(b.w5);
        f0 *= a;
        f90 *= a;
    }
    b.w1 = vec4<u32>(bitcast<vec3<u32>>(f0), b.w1.w);
    b.w6.x = bitcast<u32>(f90);
    return b;
}
// A textured metalness or transmission may leave some base diffuse anywhere: it stores photons.
fn metallic_roughness_surface_stores_photons(s: Surface) -> bool {
    return (s.b.textured & 20u) != 0u || gltf_has_diffuse(mr_params(s.b));
}
