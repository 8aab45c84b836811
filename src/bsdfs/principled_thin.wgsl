// Mitsuba 3.9's principledthin BSDF (twin of src/bsdfs/principled_thin.rs, same operation
// order): a sheet seen alike from both sides, transmission unbent. Words (slots): 0 base_color,
// 1 roughness, 2 anisotropic, 3 spec_trans, 4 diff_trans, 5 eta, 6 sheen, 7 sheen_tint,
// 8 flatness, 9 spec_tint. Uses principled.wgsl's pr_luminance, pr_calc_schlick, pr_compatible,
// pr_half_schlick, pr_disney_diffuse; metallic_roughness.wgsl's gltf_schlick_weight, gltf_mean.

struct PtParams {
    base: vec3<f32>, roughness: f32, anisotropic: f32, spec_trans: f32, diff_trans: f32,
    eta: f32, sheen: f32, sheen_tint: f32, flatness: f32, spec_tint: f32,
}
fn principled_thin_params(b: Bsdf) -> PtParams {
    return PtParams(w_rgb(b.w0), w_f(b.w1), w_f(b.w2), w_f(b.w3), w_f(b.w4), w_f(b.w5),
        w_f(b.w6), w_f(b.w7), w_f(b.w8), w_f(b.w9));
}
fn pt_distribution(p: PtParams, r: f32) -> Microfacet {
    let r2 = r * r;
    let aspect = sqrt(max(1.0 - 0.9 * p.anisotropic, 0.0));
    return Microfacet(MF_GGX, max(max(r2 / aspect, 0.001), 1e-4), max(max(r2 * aspect, 0.001), 1e-4));
}
fn pt_microfacet(p: PtParams) -> Microfacet { return pt_distribution(p, p.roughness); }
fn pt_transmission_microfacet(p: PtParams) -> Microfacet {
    return pt_distribution(p, (0.65 * p.eta - 0.35) * p.roughness);
}
fn pt_dt(p: PtParams) -> f32 { return p.diff_trans / 2.0; }
fn pt_brdf(p: PtParams) -> f32 { return (1.0 - p.spec_trans) * (1.0 - pt_dt(p)); }
fn pt_diffuse_weight(p: PtParams) -> f32 { return (1.0 - p.flatness) * pt_brdf(p); }
fn pt_tint(p: PtParams) -> vec3<f32> {
    let lum = pr_luminance(p.base);
    if lum > 0.0 { return p.base / lum; }
    return vec3<f32>(1.0);
}
// The half vector of the front-side wo and wi mirrored to wo's side.
fn pt_half(wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    return bsdf_normalize(wo + vec3<f32>(wi.x, wi.y, abs(wi.z)));
}

// f(wi, wo) of a front-side wo as (the separable diffuse part, the lobe part).
struct PtParts { diffuse: vec3<f32>, lobe: vec3<f32> }
fn pt_parts(p: PtParams, wi: vec3<f32>, wo: vec3<f32>) -> PtParts {
    let ci = wo.z;
    let co = wi.z;
    if co == 0.0 { return PtParts(vec3<f32>(0.0), vec3<f32>(0.0)); }
    let st = p.spec_trans;
    let dt = pt_dt(p);
    let reflect = co > 0.0;
    let h = pt_half(wi, wo);
    var diffuse = vec3<f32>(0.0);
    var lobe = vec3<f32>(0.0);
    if st > 0.0 {
        let f = fresnel_dielectric_mi(bsdf_dot(wo, h), p.eta).f;
        if reflect && pr_compatible(h, wo, wi, true) {
            let mf = pt_microfacet(p);
            let r = (p.eta - 1.0) / (p.eta + 1.0);
            let schlick = pr_calc_schlick(pt_tint(p) * (r * r), bsdf_dot(wo, h), p.eta);
            let f_thin = vec3<f32>(f) + (schlick - vec3<f32>(f)) * p.spec_tint;
            lobe += f_thin * (st * mf_d(mf, h) * mf_g(mf, wo, wi, h) / (4.0 * ci * co));
        }
        if !reflect && pr_compatible(h, wo, wi, false) {
            let mf = pt_transmission_microfacet(p);
            let v = st * (1.0 - f) * mf_d(mf, h) * mf_g(mf, wo, wi, h) / (4.0 * ci * abs(co));
            lobe += p.base * v;
        }
    }
    if reflect && st < 1.0 && dt < 1.0 {
        let cos_d = bsdf_dot(h, wi);
        let dd = pr_disney_diffuse(co, ci, cos_d, p.roughness, p.flatness);
        let k = p.base * (pt_brdf(p) * BSDF_FRAC_1_PI);
        diffuse += k * dd.x;
        lobe += k * dd.y;
        if p.sheen > 0.0 {
            let c_sheen = vec3<f32>(1.0) + (pt_tint(p) - vec3<f32>(1.0)) * p.sheen_tint;
            lobe += c_sheen * (p.sheen * pt_brdf(p) * gltf_schlick_weight(abs(cos_d)));
        }
    }
    if !reflect && st < 1.0 && dt > 0.0 {
        lobe += p.base * ((1.0 - st) * dt * BSDF_FRAC_1_PI);
    }
    return PtParts(diffuse, lobe);
}
// (glossy reflection, glossy transmission, cosine reflection, cosine transmission).
fn pt_probabilities(p: PtParams, cos_w: f32) -> vec4<f32> {
    let w = vec4<f32>(p.spec_trans / 2.0, p.spec_trans / 2.0, cos_w, (1.0 - p.spec_trans) * pt_dt(p));
    return w * (1.0 / (w.x + w.y + w.z + w.w));
}
fn pt_pdf_with(p: PtParams, wi: vec3<f32>, wo: vec3<f32>, cos_w: f32) -> f32 {
    let co = wi.z;
    let pr = pt_probabilities(p, cos_w);
    var pdf = 0.0;
    if p.spec_trans > 0.0 {
        let h = pt_half(wi, wo);
        let jacobian = abs(1.0 / (4.0 * bsdf_dot(vec3<f32>(wi.x, wi.y, abs(wi.z)), h)));
        if co > 0.0 && pr_compatible(h, wo, wi, true) {
            pdf += pr.x * mf_pdf_visible(pt_microfacet(p), wo, h) * jacobian;
        }
        if co < 0.0 && pr_compatible(h, wo, wi, false) {
            pdf += pr.y * mf_pdf_visible(pt_transmission_microfacet(p), wo, h) * jacobian;
        }
    }
    if co > 0.0 { pdf += pr.z * cosine_hemisphere_pdf(wi); }
    if co < 0.0 { pdf += pr.w * cosine_hemisphere_pdf(-wi); }
    return pdf;
}
fn pt_sample_with(p: PtParams, wo: vec3<f32>, u: vec3<f32>, cos_w: f32, lobe: bool) -> LobeSampleW {
    if wo.z == 0.0 { return lobe_none(); }
    let wo_f = mulsign(wo, wo.z);
    let pr = pt_probabilities(p, cos_w);
    let c0 = pr.x;
    let c1 = pr.x + pr.y;
    let c2 = pr.x + pr.y + pr.z;
    var wi: vec3<f32>;
    var ok = true;
    if u.x < c0 {
        let m = mf_sample_visible(pt_microfacet(p), wo_f, u.yz).m;
        wi = bsdf_reflect(wo_f, m);
        ok = wi.z > 0.0 && pr_compatible(m, wo_f, wi, true);
    } else if u.x < c1 {
        let m = mf_sample_visible(pt_transmission_microfacet(p), wo_f, u.yz).m;
        wi = flip_z(bsdf_reflect(wo_f, m));
        ok = wi.z < 0.0 && pr_compatible(m, wo_f, wi, false);
    } else if u.x < c2 {
        wi = square_to_cosine_hemisphere(u.yz);
    } else {
        wi = -square_to_cosine_hemisphere(u.yz);
        ok = pt_dt(p) > 0.0;
    }
    if !ok { return lobe_none(); }
    let pdf = pt_pdf_with(p, wi, wo_f, cos_w);
    let parts = pt_parts(p, wi, wo_f);
    let f = select(parts.diffuse + parts.lobe, parts.lobe, lobe);
    if pdf > 0.0 { return LobeSampleW(mulsign(wi, wo.z), f * (abs(wi.z) / pdf), pdf, false, true); }
    return lobe_none();
}
fn pt_cos_weight(p: PtParams, wo: vec3<f32>, lobe: bool) -> f32 {
    if !lobe { return pt_brdf(p); }
    let g = gltf_schlick_weight(abs(wo.z)) + 0.05;
    let retro = (1.0 - p.flatness) * 2.0 * p.roughness * g + p.flatness;
    return pt_brdf(p) * (retro + p.sheen * g);
}

fn principled_thin_diffuse_out(b: Bsdf, wo: vec3<f32>) -> vec3<f32> {
    let p = principled_thin_params(b);
    if wo.z == 0.0 { return vec3<f32>(0.0); }
    return p.base * (pt_diffuse_weight(p) * pr_half_schlick(wo.z));
}
fn principled_thin_store_weight(b: Bsdf, wi: vec3<f32>) -> f32 {
    let p = principled_thin_params(b);
    if wi.z != 0.0 && pt_diffuse_weight(p) > 0.0 { return pr_half_schlick(wi.z); }
    return 0.0;
}
fn principled_thin_eval_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    if wo.z == 0.0 { return vec3<f32>(0.0); }
    return pt_parts(principled_thin_params(b), mulsign(wi, wo.z), mulsign(wo, wo.z)).lobe;
}
fn principled_thin_pdf_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if wo.z == 0.0 { return 0.0; }
    let p = principled_thin_params(b);
    let wo_f = mulsign(wo, wo.z);
    return pt_pdf_with(p, mulsign(wi, wo.z), wo_f, pt_cos_weight(p, wo_f, true));
}
fn principled_thin_sample_lobe(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let p = principled_thin_params(b);
    return pt_sample_with(p, wo, u, pt_cos_weight(p, wo, true), true);
}
fn principled_thin_has_diffuse(b: Bsdf) -> bool { return pt_diffuse_weight(principled_thin_params(b)) > 0.0; }
fn principled_thin_lobe_probability(b: Bsdf, wo: vec3<f32>) -> f32 {
    let p = principled_thin_params(b);
    let d = gltf_mean(principled_thin_diffuse_out(b, wo));
    if d <= 0.0 { return 1.0; }
    let base = gltf_mean(p.base);
    let f = fresnel_dielectric_mi(abs(wo.z), p.eta).f;
    let st = p.spec_trans;
    let l = st * (f + (1.0 - f) * base) + (1.0 - st) * pt_dt(p) * base + pt_cos_weight(p, wo, true) * base;
    return clamp(l / (l + d), 0.05, 0.95);
}
fn principled_thin_eval(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    if wo.z == 0.0 { return vec3<f32>(0.0); }
    let parts = pt_parts(principled_thin_params(b), mulsign(wi, wo.z), mulsign(wo, wo.z));
    return parts.diffuse + parts.lobe;
}
fn principled_thin_pdf(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if wo.z == 0.0 { return 0.0; }
    let p = principled_thin_params(b);
    return pt_pdf_with(p, mulsign(wi, wo.z), mulsign(wo, wo.z), pt_brdf(p));
}
fn principled_thin_sample(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let p = principled_thin_params(b);
    return pt_sample_with(p, wo, u, pt_brdf(p), false);
}
// A textured transmission or flatness may leave a diffuse part anywhere.
fn principled_thin_surface_stores_photons(s: Surface) -> bool {
    return (s.b.textured & 0x118u) != 0u || principled_thin_has_diffuse(s.b);
}
