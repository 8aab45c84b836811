// Mitsuba 3.9's principled BSDF (twin of src/bsdfs/principled.rs and, pr_luminance to pr_compatible,
// principled_terms.rs; same operation order): one interface, wo.z < 0 the viewer inside. Words
// (slots): 0 base_color, 1 roughness, 2 anisotropic, 3 metallic, 4 spec_trans, 5 spec_tint, 6 sheen,
// 7 sheen_tint, 8 clearcoat, 9 clearcoat_gloss, 10 flatness; 11 eta and two-sidedness (u32). Uses
// gltf_schlick_weight, gltf_mean (metallic_roughness.wgsl), rough_dielectric_half_vector. Library.

struct PrParams {
    base: vec3<f32>, roughness: f32, anisotropic: f32, metallic: f32, spec_trans: f32,
    spec_tint: f32, sheen: f32, sheen_tint: f32, clearcoat: f32, clearcoat_gloss: f32,
    flatness: f32, eta: f32, two_sided: bool,
}
fn principled_params(b: Bsdf) -> PrParams {
    return PrParams(w_rgb(b.w0), w_f(b.w1), w_f(b.w2), w_f(b.w3), w_f(b.w4), w_f(b.w5),
        w_f(b.w6), w_f(b.w7), w_f(b.w8), w_f(b.w9), w_f(b.w10), w_f(b.w11), b.w11.y != 0u);
}
fn pr_luminance(c: vec3<f32>) -> f32 { return 0.212671 * c.x + 0.71516 * c.y + 0.072169 * c.z; }
fn pr_calc_schlick(r0: vec3<f32>, cos_i: f32, eta: f32) -> vec3<f32> {
    let outside = cos_i >= 0.0;
    let eta_it = select(1.0 / eta, eta, outside);
    let eta_ti = select(eta, 1.0 / eta, outside);
    let cos_t = safe_sqrt(1.0 - (1.0 - cos_i * cos_i) * (eta_ti * eta_ti));
    let w = select(gltf_schlick_weight(cos_t), gltf_schlick_weight(abs(cos_i)), eta_it > 1.0);
    return vec3<f32>(w) + (vec3<f32>(1.0) - vec3<f32>(w)) * r0;
}
// Disney's diffuse at positive cosines: ((1 - flatness) f_diff, the rest) (disney_diffuse).
fn pr_disney_diffuse(cos_o: f32, cos_i: f32, cos_d: f32, roughness: f32, flatness: f32) -> vec2<f32> {
    let fo = gltf_schlick_weight(cos_o);
    let fi = gltf_schlick_weight(cos_i);
    let f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo);
    let rr = 2.0 * roughness * cos_d * cos_d;
    let f_retro = rr * (fo + fi + fo * fi * (rr - 1.0));
    let fss90 = rr / 2.0;
    let fss = (1.0 + (fss90 - 1.0) * fo) * (1.0 + (fss90 - 1.0) * fi);
    let f_ss = 1.25 * (fss * (1.0 / (cos_o + cos_i) - 0.5) + 0.5);
    return vec2<f32>((1.0 - flatness) * f_diff, (1.0 - flatness) * f_retro + flatness * f_ss);
}
fn pr_gtr1_d(alpha: f32, m: vec3<f32>) -> f32 {
    let a2 = alpha * alpha;
    let r = (a2 - 1.0) / (PI * log(a2) * (1.0 + (a2 - 1.0) * m.z * m.z));
    return select(0.0, r, r * m.z > 1e-20);
}
fn pr_gtr1_sample(alpha: f32, u: vec2<f32>) -> vec3<f32> {
    let phi = 2.0 * PI * u.x;
    let a2 = alpha * alpha;
    let cos2 = (1.0 - pow(a2, 1.0 - u.y)) / (1.0 - a2);
    let sin_t = sqrt(max(1.0 - cos2, 0.0));
    return vec3<f32>(cos(phi) * sin_t, sin(phi) * sin_t, sqrt(max(cos2, 0.0)));
}
fn pr_smith_ggx1(v: vec3<f32>, m: vec3<f32>, alpha: f32) -> f32 {
    if bsdf_dot(v, m) * v.z <= 0.0 { return 0.0; }
    if v.z == 1.0 { return 1.0; }
    let c2 = v.z * v.z;
    let tan2 = (1.0 - c2) / c2;
    return 2.0 / (1.0 + sqrt(1.0 + alpha * alpha * tan2));
}
fn pr_compatible(m: vec3<f32>, wo: vec3<f32>, wi: vec3<f32>, reflection: bool) -> bool {
    let ms = mulsign(m, wo.z);
    if bsdf_dot(wo, ms) <= 0.0 { return false; }
    if reflection { return bsdf_dot(wi, ms) > 0.0; }
    return bsdf_dot(wi, ms) < 0.0;
}
// (cosine, clearcoat, transmission, reflection) weights, unnormalised.
fn pr_weights(front: bool, cos_w: f32, clearcoat: f32, bsdf: f32, f: f32) -> vec4<f32> {
    if front { return vec4<f32>(cos_w, 0.25 * clearcoat, bsdf * (1.0 - f), 1.0 - bsdf * (1.0 - f)); }
    return vec4<f32>(0.0, 0.0, 1.0 - f, f);
}
fn pr_microfacet(p: PrParams) -> Microfacet {
    let r2 = p.roughness * p.roughness;
    let aspect = sqrt(max(1.0 - 0.9 * p.anisotropic, 0.0));
    return Microfacet(MF_GGX, max(max(r2 / aspect, 0.001), 1e-4), max(max(r2 * aspect, 0.001), 1e-4));
}
fn pr_brdf(p: PrParams) -> f32 { return (1.0 - p.metallic) * (1.0 - p.spec_trans); }
fn pr_bsdf(p: PrParams) -> f32 { return (1.0 - p.metallic) * p.spec_trans; }
fn pr_tint(p: PrParams) -> vec3<f32> {
    let lum = pr_luminance(p.base);
    if lum > 0.0 { return p.base / lum; }
    return vec3<f32>(1.0);
}
fn pr_fresnel(p: PrParams, f_dielectric: f32, c: f32, front: bool) -> vec3<f32> {
    if !front { return vec3<f32>(pr_bsdf(p) * f_dielectric); }
    let eta_it = select(1.0 / p.eta, p.eta, c >= 0.0);
    let r = (eta_it - 1.0) / (eta_it + 1.0);
    let r0 = r * r;
    let metal = pr_calc_schlick(p.base, c, p.eta) * p.metallic;
    let tinted = pr_calc_schlick(pr_tint(p) * r0, c, p.eta) * ((1.0 - p.metallic) * p.spec_tint);
    return vec3<f32>((1.0 - p.metallic) * (1.0 - p.spec_tint) * f_dielectric) + metal + tinted;
}
fn pr_clearcoat_alpha(p: PrParams) -> f32 { return 0.1 + (0.001 - 0.1) * p.clearcoat_gloss; }
fn pr_half_schlick(c: f32) -> f32 { return 1.0 - 0.5 * gltf_schlick_weight(abs(c)); }
fn pr_diffuse_weight(p: PrParams) -> f32 { return (1.0 - p.flatness) * pr_brdf(p); }

// f(wi, wo) as (the separable diffuse part, the lobe part).
struct PrParts { diffuse: vec3<f32>, lobe: vec3<f32> }
fn pr_parts(p: PrParams, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> PrParts {
    if wo.z == 0.0 || wi.z == 0.0 { return PrParts(vec3<f32>(0.0), vec3<f32>(0.0)); }
    let brdf = pr_brdf(p);
    let bsdf = pr_bsdf(p);
    let front = wo.z > 0.0;
    let hv = rough_dielectric_half_vector(p.eta, wi, wo);
    let h = hv.m;
    let f = fresnel_dielectric_mi(bsdf_dot(wo, h), p.eta).f;
    let mf = pr_microfacet(p);
    let d = mf_d(mf, h);
    let g = mf_g(mf, wo, wi, h);
    var diffuse = vec3<f32>(0.0);
    var lobe = vec3<f32>(0.0);
    if hv.reflect && pr_compatible(h, wo, wi, true) {
        if f > 0.0 {
            lobe += pr_fresnel(p, f, bsdf_dot(wo, h), front) * (d * g) / (4.0 * abs(wo.z) * abs(wi.z));
        }
        if front && p.clearcoat > 0.0 {
            let fcc = pr_calc_schlick(vec3<f32>(0.04), bsdf_dot(wo, h), p.eta).x;
            let dcc = pr_gtr1_d(pr_clearcoat_alpha(p), h);
            let gcc = pr_smith_ggx1(wo, h, 0.25) * pr_smith_ggx1(wi, h, 0.25);
            lobe += vec3<f32>(0.25 * p.clearcoat * fcc * dcc * gcc);
        }
    }
    if !hv.reflect && bsdf > 0.0 && f < 1.0 && pr_compatible(h, wo, wi, false) {
        let e = hv.e;
        let scale = select(1.0, 1.0 / (e * e), radiance);
        let dot_o = bsdf_dot(wo, h);
        let dot_i = bsdf_dot(wi, h);
        let den = dot_o + e * dot_i;
        let v = abs(scale * (1.0 - f) * d * g * e * e * dot_o * dot_i / (wo.z * wi.z * (den * den)));
        lobe += sqrt(p.base) * (bsdf * v);
    }
    if hv.reflect && front {
        let cos_d = bsdf_dot(h, wi);
        if brdf > 0.0 {
            let dd = pr_disney_diffuse(wo.z, wi.z, cos_d, p.roughness, p.flatness);
            let k = p.base * (brdf * BSDF_FRAC_1_PI);
            diffuse += k * dd.x;
            lobe += k * dd.y;
        }
        if p.sheen > 0.0 && 1.0 - p.metallic > 0.0 {
            let c_sheen = vec3<f32>(1.0) + (pr_tint(p) - vec3<f32>(1.0)) * p.sheen_tint;
            lobe += c_sheen * (p.sheen * (1.0 - p.metallic) * gltf_schlick_weight(abs(cos_d)));
        }
    }
    return PrParts(diffuse, lobe);
}
fn pr_pdf_with(p: PrParams, wi: vec3<f32>, wo: vec3<f32>, cos_w: f32) -> f32 {
    if wo.z == 0.0 || wi.z == 0.0 { return 0.0; }
    let front = wo.z > 0.0;
    let bsdf = pr_bsdf(p);
    if !front && bsdf <= 0.0 { return 0.0; }
    let hv = rough_dielectric_half_vector(p.eta, wi, wo);
    let h = hv.m;
    let e = hv.e;
    let f = fresnel_dielectric_mi(bsdf_dot(wo, h), p.eta).f;
    let w = pr_weights(front, cos_w, p.clearcoat, bsdf, f);
    let pw = w / (w.x + w.y + w.z + w.w);
    let dot_o = bsdf_dot(wo, h);
    let dot_i = bsdf_dot(wi, h);
    let den = dot_o + e * dot_i;
    let jacobian = select(abs(e * e * dot_i / (den * den)), abs(1.0 / (4.0 * dot_i)), hv.reflect);
    let d_vis = mf_pdf_visible(pr_microfacet(p), mulsign(wo, wo.z), h);
    var pdf = 0.0;
    if hv.reflect {
        if pr_compatible(h, wo, wi, true) {
            pdf += pw.w * d_vis * jacobian;
            if pw.y > 0.0 {
                pdf += pw.y * h.z * pr_gtr1_d(pr_clearcoat_alpha(p), h) * jacobian;
            }
        }
        pdf += pw.x * cosine_hemisphere_pdf(wi);
    } else if pr_compatible(h, wo, wi, false) {
        pdf += pw.z * d_vis * jacobian;
    }
    return pdf;
}
// The visible normal u2 picks and the thresholds on u.x (cosine, clearcoat, transmission).
struct PrChoice { m: vec3<f32>, c: vec3<f32> }
fn pr_choice(p: PrParams, wo: vec3<f32>, u2: vec2<f32>, cos_w: f32) -> PrChoice {
    let ms = mf_sample_visible(pr_microfacet(p), mulsign(wo, wo.z), u2);
    let f = fresnel_dielectric_mi(bsdf_dot(wo, ms.m), p.eta).f;
    let w = pr_weights(wo.z > 0.0, cos_w, p.clearcoat, pr_bsdf(p), f);
    let total = w.x + w.y + w.z + w.w;
    return PrChoice(ms.m, vec3<f32>(w.x / total, (w.x + w.y) / total, (w.x + w.y + w.z) / total));
}
fn pr_sample_with(p: PrParams, wo: vec3<f32>, u: vec3<f32>, radiance: bool, cos_w: f32, lobe: bool) -> LobeSampleW {
    let front = wo.z > 0.0;
    let bsdf = pr_bsdf(p);
    if wo.z == 0.0 || (!front && bsdf <= 0.0) { return lobe_none(); }
    let ch = pr_choice(p, wo, u.yz, cos_w);
    let m = ch.m;
    let fr = fresnel_dielectric_mi(bsdf_dot(wo, m), p.eta);
    let c0 = ch.c.x;
    let c1 = ch.c.y;
    let c2 = ch.c.z;
    var wi: vec3<f32>;
    var ok: bool;
    if u.x < c0 {
        wi = square_to_cosine_hemisphere(u.yz);
        ok = wi.z * wo.z > 0.0;
    } else if u.x < c1 {
        let mc = pr_gtr1_sample(pr_clearcoat_alpha(p), u.yz);
        wi = bsdf_reflect(wo, mc);
        ok = wi.z * wo.z > 0.0 && pr_compatible(mc, wo, wi, true);
    } else if u.x < c2 {
        wi = bsdf_refract(wo, m, fr.cos_t, fr.eta_ti);
        ok = wi.z * wo.z < 0.0 && pr_compatible(m, wo, wi, false);
    } else {
        wi = bsdf_reflect(wo, m);
        ok = wi.z * wo.z > 0.0 && pr_compatible(m, wo, wi, true);
    }
    if !ok { return lobe_none(); }
    let pdf = pr_pdf_with(p, wi, wo, cos_w);
    let parts = pr_parts(p, wi, wo, radiance);
    let f = select(parts.diffuse + parts.lobe, parts.lobe, lobe);
    if pdf > 0.0 { return LobeSampleW(wi, f * (abs(wi.z) / pdf), pdf, false, true); }
    return lobe_none();
}
fn pr_remainder_weight(p: PrParams, wo: vec3<f32>) -> f32 {
    if wo.z <= 0.0 { return 0.0; }
    let g = gltf_schlick_weight(wo.z) + 0.05;
    let retro = (1.0 - p.flatness) * 2.0 * p.roughness * g + p.flatness;
    return (1.0 - p.metallic) * ((1.0 - p.spec_trans) * retro + p.sheen * g);
}
fn pr_full_weight(p: PrParams, wo: vec3<f32>) -> f32 { return select(0.0, pr_brdf(p), wo.z > 0.0); }

// Both directions mirrored to the front when two-sided and wo is behind (to_front's result).
fn pr_oriented(p: PrParams, wi: vec3<f32>, wo: vec3<f32>) -> Front {
    if p.two_sided && wo.z < 0.0 { return Front(flip_z(wi), flip_z(wo), true, true); }
    return Front(wi, wo, false, true);
}
fn principled_diffuse_out(b: Bsdf, wo_in: vec3<f32>) -> vec3<f32> {
    let p = principled_params(b);
    let wo = pr_oriented(p, vec3<f32>(0.0, 0.0, 1.0), wo_in).wo;
    if wo.z > 0.0 { return p.base * (pr_diffuse_weight(p) * pr_half_schlick(wo.z)); }
    return vec3<f32>(0.0);
}
fn principled_store_weight(b: Bsdf, wi: vec3<f32>) -> f32 {
    let p = principled_params(b);
    let z = select(wi.z, abs(wi.z), p.two_sided);
    if z > 0.0 && pr_diffuse_weight(p) > 0.0 { return pr_half_schlick(z); }
    return 0.0;
}
fn principled_eval_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    let p = principled_params(b);
    let o = pr_oriented(p, wi, wo);
    return pr_parts(p, o.wi, o.wo, radiance).lobe;
}
fn principled_pdf_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = principled_params(b);
    let o = pr_oriented(p, wi, wo);
    return pr_pdf_with(p, o.wi, o.wo, pr_remainder_weight(p, o.wo));
}
fn principled_sample_lobe(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let p = principled_params(b);
    let o = pr_oriented(p, vec3<f32>(0.0, 0.0, 1.0), wo);
    return back_to_side(pr_sample_with(p, o.wo, u, radiance, pr_remainder_weight(p, o.wo), true), o.flipped);
}
fn principled_has_diffuse(b: Bsdf) -> bool { return pr_diffuse_weight(principled_params(b)) > 0.0; }
fn principled_lobe_probability(b: Bsdf, wo_in: vec3<f32>) -> f32 {
    let p = principled_params(b);
    let wo = pr_oriented(p, vec3<f32>(0.0, 0.0, 1.0), wo_in).wo;
    let d = gltf_mean(principled_diffuse_out(b, wo));
    if d <= 0.0 { return 1.0; }
    let c = abs(wo.z);
    let f = fresnel_dielectric_mi(c, p.eta).f;
    let l = gltf_mean(pr_fresnel(p, f, c, true))
        + pr_bsdf(p) * (1.0 - f) * gltf_mean(sqrt(p.base))
        + 0.25 * p.clearcoat * 0.04
        + pr_remainder_weight(p, wo) * gltf_mean(p.base);
    return clamp(l / (l + d), 0.05, 0.95);
}
fn principled_eval(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    let p = principled_params(b);
    let o = pr_oriented(p, wi, wo);
    let parts = pr_parts(p, o.wi, o.wo, radiance);
    return parts.diffuse + parts.lobe;
}
fn principled_pdf(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let p = principled_params(b);
    let o = pr_oriented(p, wi, wo);
    return pr_pdf_with(p, o.wi, o.wo, pr_full_weight(p, o.wo));
}
fn principled_sample(b: Bsdf, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let p = principled_params(b);
    let o = pr_oriented(p, vec3<f32>(0.0, 0.0, 1.0), wo);
    return back_to_side(pr_sample_with(p, o.wo, u, radiance, pr_full_weight(p, o.wo), false), o.flipped);
}
// A textured metalness, transmission or flatness may leave a diffuse part anywhere.
fn principled_surface_stores_photons(s: Surface) -> bool {
    return (s.b.textured & 0x418u) != 0u || principled_has_diffuse(s.b);
}
