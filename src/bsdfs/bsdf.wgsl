// The BSDFs of Mitsuba 3.9.1 (diffuse, conductors, dielectrics, thin dielectric, plastics) in f32: twin of src/bsdf/,
// function for function, same operation order; local frame z = front shading normal, wo towards the viewer, wi the light.
// Library, no entry point; writes nothing. Needs the prelude's PI, the BSDF_*/MF_* codes (src/integrators/gpu/bsdf_params.rs), bsdf_gltf.wgsl and a
// module-scope read-only storage `bsdf_tables: array<f32>` holding the rough plastics' tables (BsdfParams.table: offset).

// A resolved BSDF (Rust twin: gpu::bsdf_params::GpuBsdf, 112 bytes); each kind reads the fields its Rust variant has.
struct BsdfParams {
    eta_c: vec3<f32>,           // conductor: real part of the complex index
    kind: u32,                  // BSDF_* code
    k_c: vec3<f32>,             // conductor: imaginary part
    distribution: u32,          // MF_GGX or MF_BECKMANN (rough kinds)
    specular: vec3<f32>,        // conductor tint; dielectric, thin and plastic specular_reflectance
    alpha_u: f32,
    transmittance: vec3<f32>,   // dielectric and thin: specular_transmittance
    alpha_v: f32,
    albedo: vec3<f32>,          // diffuse albedo; plastic diffuse_reflectance
    eta: f32,                   // dielectric, thin, plastic: interior / exterior
    nonlinear: u32,             // plastic: 1 when nonlinear
    table: u32,                 // rough plastic: offset of its BSDF_TABLE_RES words in bsdf_tables
    specular_sampling_weight: f32,
    internal_reflectance: f32,
    textures: vec4<u32>,        // metallic-roughness: its textures (mr, transmission, specular, specular colour)
}

// Rust's Option<LobeSample>: ok false for None.
struct LobeSampleW { wi: vec3<f32>, weight: vec3<f32>, pdf: f32, delta: bool, ok: bool }
struct Microfacet { distribution: u32, alpha_u: f32, alpha_v: f32 }
struct MfSample { m: vec3<f32>, pdf: f32 }
// fresnel_dielectric's tuple (F, cos_theta_t, eta_it, eta_ti).
struct FresnelW { f: f32, cos_t: f32, eta_it: f32, eta_ti: f32 }
const BSDF_FRAC_1_PI: f32 = 0.31830987f;
const BSDF_FRAC_PI_2: f32 = 1.5707964f;
const BSDF_FRAC_PI_4: f32 = 0.7853982f;
const MF_SIN2_MIN: f32 = 2.3841858e-7f; // 4 f32::EPSILON / 2
fn lobe_none() -> LobeSampleW { return LobeSampleW(vec3<f32>(0.0), vec3<f32>(0.0), 0.0, false, false); }

// ---- math.rs -------------------------------------------------------------------------------
// glam's dot and normalize (v * (1 / length)), spelled out so the order of operations is Rust's.
fn bsdf_dot(a: vec3<f32>, b: vec3<f32>) -> f32 { return a.x * b.x + a.y * b.y + a.z * b.z; }
fn bsdf_normalize(v: vec3<f32>) -> vec3<f32> { return v * (1.0 / sqrt(bsdf_dot(v, v))); }
fn safe_sqrt(x: f32) -> f32 { return sqrt(max(x, 0.0)); }
fn erf(x: f32) -> f32 {
    let z = abs(x);
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -1.2655122 + t * (1.0000237 + t * (0.37409196 + t * (0.09678418 + t * (-0.18628806
        + t * (0.27886807 + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277))))))));
    let erfc = t * exp(-z * z + poly);
    let r = 1.0 - erfc;
    return select(r, -r, x < 0.0);
}
fn erfinv(x: f32) -> f32 {
    var w = -log((1.0 - x) * (1.0 + x));
    var p: f32;
    if w < 5.0 {
        w -= 2.5;
        p = 2.81022636e-08; p = 3.43273939e-07 + p * w; p = -3.5233877e-06 + p * w;
        p = -4.39150654e-06 + p * w; p = 0.00021858087 + p * w; p = -0.00125372503 + p * w;
        p = -0.00417768164 + p * w; p = 0.246640727 + p * w; p = 1.50140941 + p * w;
    } else {
        w = sqrt(w) - 3.0;
        p = -0.000200214257; p = 0.000100950558 + p * w; p = 0.00134934322 + p * w;
        p = -0.00367342844 + p * w; p = 0.00573950773 + p * w; p = -0.0076224613 + p * w;
        p = 0.00943887047 + p * w; p = 1.00167406 + p * w; p = 2.83297682 + p * w;
    }
    return p * x;
}
fn square_to_disk_concentric(u: vec2<f32>) -> vec2<f32> {
    let r1 = 2.0 * u.x - 1.0; let r2 = 2.0 * u.y - 1.0;
    if r1 == 0.0 && r2 == 0.0 { return vec2<f32>(0.0); }
    var r = r1;
    var phi: f32;
    if abs(r1) < abs(r2) {
        r = r2;
        phi = BSDF_FRAC_PI_2 - BSDF_FRAC_PI_4 * (r1 / r2);
    } else {
        phi = BSDF_FRAC_PI_4 * (r2 / r1);
    }
    return vec2<f32>(r * cos(phi), r * sin(phi));
}
fn square_to_cosine_hemisphere(u: vec2<f32>) -> vec3<f32> {
    let p = square_to_disk_concentric(u);
    return vec3<f32>(p.x, p.y, safe_sqrt(1.0 - (p.x * p.x + p.y * p.y)));
}
fn cosine_hemisphere_pdf(w: vec3<f32>) -> f32 { return max(w.z, 0.0) / PI; }
fn reflect_z(w: vec3<f32>) -> vec3<f32> { return vec3<f32>(-w.x, -w.y, w.z); }
fn bsdf_reflect(w: vec3<f32>, m: vec3<f32>) -> vec3<f32> { return 2.0 * bsdf_dot(w, m) * m - w; }
fn bsdf_refract(w: vec3<f32>, m: vec3<f32>, cos_theta_t: f32, eta_ti: f32) -> vec3<f32> {
    return m * (bsdf_dot(w, m) * eta_ti + cos_theta_t) - w * eta_ti;
}
// `a` with the sign of `b` (the sign bit: -0.0 counts as negative).
fn mulsign(a: vec3<f32>, b: f32) -> vec3<f32> { return select(a, -a, (bitcast<u32>(b) & 0x80000000u) != 0u); }
fn flip_z(w: vec3<f32>) -> vec3<f32> { return vec3<f32>(w.x, w.y, -w.z); }

// ---- microfacet.rs -------------------------------------------------------------------------
fn bsdf_microfacet(b: BsdfParams) -> Microfacet { return Microfacet(b.distribution, b.alpha_u, b.alpha_v); }
fn mf_d(mf: Microfacet, m: vec3<f32>) -> f32 {
    let au = mf.alpha_u; let av = mf.alpha_v;
    let c2 = m.z * m.z;
    let sx = m.x / au; let sy = m.y / av;
    var r: f32;
    if mf.distribution == MF_BECKMANN {
        let e = -(sx * sx + sy * sy) / c2;
        r = exp(e) / (PI * au * av * c2 * c2);
    } else {
        let s = sx * sx + sy * sy + c2;
        r = 1.0 / (PI * au * av * s * s);
    }
    return select(0.0, r, r * m.z > 1e-20);
}
fn mf_smith_g1(mf: Microfacet, v: vec3<f32>, m: vec3<f32>) -> f32 {
    let ax = mf.alpha_u * v.x; let ay = mf.alpha_v * v.y;
    let xy = ax * ax + ay * ay;
    if bsdf_dot(v, m) * v.z <= 0.0 { return 0.0; }
    if xy == 0.0 { return 1.0; }
    let tan2 = xy / (v.z * v.z);
    if mf.distribution == MF_BECKMANN {
        let a = 1.0 / sqrt(tan2);
        if a >= 1.6 { return 1.0; }
        let a2 = a * a;
        return (3.535 * a + 2.181 * a2) / (1.0 + 2.276 * a + 2.577 * a2);
    }
    return 2.0 / (1.0 + sqrt(1.0 + tan2));
}
fn mf_g(mf: Microfacet, wi: vec3<f32>, wo: vec3<f32>, m: vec3<f32>) -> f32 {
    return mf_smith_g1(mf, wi, m) * mf_smith_g1(mf, wo, m);
}
fn mf_sample_visible_11(mf: Microfacet, cos_theta: f32, u_in: vec2<f32>) -> vec2<f32> {
    if mf.distribution == MF_BECKMANN {
        let tan_theta = safe_sqrt(1.0 - cos_theta * cos_theta) / cos_theta;
        let cot_theta = 1.0 / tan_theta;
        let maxval = erf(cot_theta);
        let u = clamp(u_in, vec2<f32>(1e-6), vec2<f32>(1.0 - 1e-6));
        // Initial guess: the analytic solution for theta = pi/2.
        var x = maxval - (maxval + 1.0) * erf(sqrt(-log(u.x)));
        let inv_sqrt_pi = 0.5641896;
        let target_ = u.x * (1.0 + maxval + inv_sqrt_pi * tan_theta * exp(-cot_theta * cot_theta));
        for (var i = 0u; i < 3u; i++) {
            let slope = erfinv(x);
            let value = 1.0 + x + inv_sqrt_pi * tan_theta * exp(-slope * slope) - target_;
            let derivative = 1.0 - slope * tan_theta;
            x -= value / derivative;
        }
        return vec2<f32>(erfinv(x), erfinv(2.0 * u.y - 1.0));
    }
    var p = square_to_disk_concentric(u_in);
    let s = 0.5 * (1.0 + cos_theta);
    let h = safe_sqrt(1.0 - p.x * p.x);
    p.y = h + (p.y - h) * s;
    let z = safe_sqrt(1.0 - (p.x * p.x + p.y * p.y));
    let sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
    let norm = 1.0 / (sin_theta * p.y + cos_theta * z);
    return vec2<f32>(cos_theta * p.y - sin_theta * z, p.x) * norm;
}
fn mf_pdf_visible(mf: Microfacet, wo: vec3<f32>, m: vec3<f32>) -> f32 {
    return mf_d(mf, m) * mf_smith_g1(mf, wo, m) * abs(bsdf_dot(wo, m)) / wo.z;
}

// A normal visible from wo (wo.z > 0) and its density pdf_visible(wo, m).
fn mf_sample_visible(mf: Microfacet, wo: vec3<f32>, u: vec2<f32>) -> MfSample {
    let au = mf.alpha_u; let av = mf.alpha_v;
    let wp = bsdf_normalize(vec3<f32>(au * wo.x, av * wo.y, wo.z));
    let sin2 = wp.x * wp.x + wp.y * wp.y;
    var sin_phi = 0.0; var cos_phi = 1.0;
    if !(sin2 <= MF_SIN2_MIN) {
        let inv = 1.0 / sqrt(sin2);
        sin_phi = clamp(wp.y * inv, -1.0, 1.0);
        cos_phi = clamp(wp.x * inv, -1.0, 1.0);
    }
    let s = mf_sample_visible_11(mf, wp.z, u);
    let sx = (cos_phi * s.x - sin_phi * s.y) * au;
    let sy = (sin_phi * s.x + cos_phi * s.y) * av;
    let m = bsdf_normalize(vec3<f32>(-sx, -sy, 1.0));
    return MfSample(m, mf_pdf_visible(mf, wo, m));
}
fn fresnel_dielectric_mi(cos_theta_i: f32, eta: f32) -> FresnelW {
    let outside = cos_theta_i >= 0.0;
    let rcp_eta = 1.0 / eta;
    let eta_it = select(rcp_eta, eta, outside); let eta_ti = select(eta, rcp_eta, outside);
    let cos_t_sqr = 1.0 - (1.0 - cos_theta_i * cos_theta_i) * (eta_ti * eta_ti);
    let ci = abs(cos_theta_i);
    let ct = safe_sqrt(cos_t_sqr);
    var r = 1.0;
    if eta == 1.0 {
        r = 0.0;
    } else if ci != 0.0 {
        let a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
        let a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
        r = 0.5 * (a_s * a_s + a_p * a_p);
    }
    return FresnelW(r, select(ct, -ct, outside), eta_it, eta_ti);
}
fn fresnel_conductor_1(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
    let c2 = cos_theta_i * cos_theta_i;
    let s2 = 1.0 - c2;
    let s4 = s2 * s2;
    let t1 = eta * eta - k * k - s2;
    let a2pb2 = safe_sqrt(t1 * t1 + 4.0 * k * k * eta * eta);
    let a = safe_sqrt(0.5 * (a2pb2 + t1));
    let term1 = a2pb2 + c2;
    let term2 = 2.0 * cos_theta_i * a;
    let r_s = (term1 - term2) / (term1 + term2);
    let term3 = a2pb2 * c2 + s4;
    let term4 = term2 * s2;
    let r_p = r_s * (term3 - term4) / (term3 + term4);
    return 0.5 * (r_s + r_p);
}
fn fresnel_conductor(cos_theta_i: f32, eta: vec3<f32>, k: vec3<f32>) -> vec3<f32> {
    return vec3<f32>(fresnel_conductor_1(cos_theta_i, eta.x, k.x), fresnel_conductor_1(cos_theta_i, eta.y, k.y),
        fresnel_conductor_1(cos_theta_i, eta.z, k.z));
}

// ---- diffuse.rs, conductor.rs --------------------------------------------------------------
fn diffuse_pdf(wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    return select(0.0, cosine_hemisphere_pdf(wi), wi.z > 0.0 && wo.z > 0.0);
}
fn diffuse_sample(albedo: vec3<f32>, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let wi = square_to_cosine_hemisphere(u.yz);
    let pdf = diffuse_pdf(wi, wo);
    return LobeSampleW(wi, albedo, pdf, false, pdf > 0.0);
}
fn conductor_eval(mf: Microfacet, eta: vec3<f32>, k: vec3<f32>, specular: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if wi.z <= 0.0 || wo.z <= 0.0 { return vec3<f32>(0.0); }
    let h = bsdf_normalize(wi + wo);
    let d = mf_d(mf, h);
    if d == 0.0 { return vec3<f32>(0.0); }
    let value = d * mf_g(mf, wo, wi, h) / (4.0 * wo.z * wi.z);
    return fresnel_conductor(bsdf_dot(wo, h), eta, k) * specular * value;
}
fn conductor_pdf(mf: Microfacet, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let h = bsdf_normalize(wi + wo);
    if wi.z <= 0.0 || wo.z <= 0.0 || bsdf_dot(wo, h) <= 0.0 || bsdf_dot(wi, h) <= 0.0 { return 0.0; }
    return mf_d(mf, h) * mf_smith_g1(mf, wo, h) / (4.0 * wo.z);
}
fn conductor_sample(mf: Microfacet, eta: vec3<f32>, k: vec3<f32>, specular: vec3<f32>, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let ms = mf_sample_visible(mf, wo, u.yz); let m = ms.m;
    let wi = bsdf_reflect(wo, m);
    if ms.pdf == 0.0 || wi.z <= 0.0 { return lobe_none(); }
    let pdf = ms.pdf / (4.0 * bsdf_dot(wi, m));
    let weight = fresnel_conductor(bsdf_dot(wo, m), eta, k) * specular * mf_smith_g1(mf, wi, m);
    return LobeSampleW(wi, weight, pdf, false, pdf > 0.0);
}
fn conductor_sample_smooth(eta: vec3<f32>, k: vec3<f32>, specular: vec3<f32>, wo: vec3<f32>) -> LobeSampleW {
    return LobeSampleW(reflect_z(wo), fresnel_conductor(wo.z, eta, k) * specular, 0.0, true, true);
}

// ---- dielectric.rs -------------------------------------------------------------------------
struct HalfVector { m: vec3<f32>, reflect: bool, e: f32 }
fn dielectric_half_vector(eta: f32, wi: vec3<f32>, wo: vec3<f32>) -> HalfVector {
    let refl = wo.z * wi.z > 0.0;
    let e = select(1.0 / eta, eta, wo.z > 0.0);
    let m = bsdf_normalize(wo + wi * select(e, 1.0, refl));
    return HalfVector(mulsign(m, m.z), refl, e);
}
fn dielectric_eval(mf: Microfacet, eta: f32, reflectance: vec3<f32>, transmittance: vec3<f32>, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    if wo.z == 0.0 || wi.z == 0.0 { return vec3<f32>(0.0); }
    let hv = dielectric_half_vector(eta, wi, wo);
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
fn dielectric_pdf(mf: Microfacet, eta: f32, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if wo.z == 0.0 { return 0.0; }
    let hv = dielectric_half_vector(eta, wi, wo);
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
fn dielectric_sample(mf: Microfacet, eta: f32, reflectance: vec3<f32>, transmittance: vec3<f32>, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
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
fn dielectric_sample_smooth(eta: f32, reflectance: vec3<f32>, transmittance: vec3<f32>, wo: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = fresnel_dielectric_mi(wo.z, eta);
    if u.x <= fr.f { return LobeSampleW(reflect_z(wo), reflectance, 0.0, true, true); }
    let factor = select(1.0, fr.eta_ti * fr.eta_ti, radiance);
    let wi = vec3<f32>(-fr.eta_ti * wo.x, -fr.eta_ti * wo.y, fr.cos_t);
    return LobeSampleW(wi, transmittance * factor, 0.0, true, true);
}
fn dielectric_sample_thin(eta: f32, reflectance: vec3<f32>, transmittance: vec3<f32>, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let r0 = fresnel_dielectric_mi(abs(wo.z), eta).f;
    let r = r0 * 2.0 / (1.0 + r0);
    if u.x <= r { return LobeSampleW(reflect_z(wo), reflectance, 0.0, true, true); }
    return LobeSampleW(-wo, transmittance, 0.0, true, true);
}

// ---- plastic.rs (front side: wo.z > 0) ----------------------------------------------------
fn plastic_transmittance(b: BsdfParams, cos_theta: f32) -> f32 {
    if b.kind != BSDF_ROUGH_PLASTIC { return 1.0 - fresnel_dielectric_mi(cos_theta, b.eta).f; }
    let x = cos_theta * f32(BSDF_TABLE_RES - 1u);
    let i = min(u32(max(x, 0.0)), BSDF_TABLE_RES - 2u);
    let v0 = bsdf_tables[b.table + i];
    let v1 = bsdf_tables[b.table + i + 1u];
    return v0 + (v1 - v0) * (x - f32(i));
}
fn plastic_diffuse_out(b: BsdfParams, cos_o: f32) -> vec3<f32> {
    let kd = b.albedo; let ri = b.internal_reflectance;
    let denom = select(vec3<f32>(1.0 - ri), vec3<f32>(1.0) - kd * ri, b.nonlinear != 0u);
    return kd / denom * (plastic_transmittance(b, cos_o) / (b.eta * b.eta));
}
fn plastic_prob_specular(b: BsdfParams, cos_o: f32) -> f32 {
    let t = plastic_transmittance(b, cos_o);
    let ssw = b.specular_sampling_weight;
    let ps = (1.0 - t) * ssw; let pd = t * (1.0 - ssw);
    return select(0.0, ps / (ps + pd), ps + pd > 0.0);
}
fn plastic_eval_lobe(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> {
    if b.kind != BSDF_ROUGH_PLASTIC || wi.z <= 0.0 || wo.z <= 0.0 { return vec3<f32>(0.0); }
    let mf = bsdf_microfacet(b);
    let h = bsdf_normalize(wi + wo);
    let f = fresnel_dielectric_mi(bsdf_dot(wo, h), b.eta).f;
    return b.specular * (f * mf_d(mf, h) * mf_g(mf, wo, wi, h) / (4.0 * wo.z * wi.z));
}
fn plastic_pdf_lobe(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if b.kind != BSDF_ROUGH_PLASTIC || wi.z <= 0.0 || wo.z <= 0.0 { return 0.0; }
    let mf = bsdf_microfacet(b);
    let h = bsdf_normalize(wi + wo);
    return mf_d(mf, h) * mf_smith_g1(mf, wo, h) / (4.0 * wo.z);
}
fn plastic_sample_lobe(b: BsdfParams, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let ks = b.specular;
    if b.kind != BSDF_ROUGH_PLASTIC {
        let f = fresnel_dielectric_mi(wo.z, b.eta).f;
        return LobeSampleW(reflect_z(wo), ks * f, 0.0, true, true);
    }
    let mf = bsdf_microfacet(b);
    let ms = mf_sample_visible(mf, wo, u.yz);
    let wi = bsdf_reflect(wo, ms.m);
    if ms.pdf == 0.0 || wi.z <= 0.0 { return lobe_none(); }
    let f = fresnel_dielectric_mi(bsdf_dot(wo, ms.m), b.eta).f;
    let pdf = ms.pdf / (4.0 * bsdf_dot(wi, ms.m));
    return LobeSampleW(wi, ks * (f * mf_smith_g1(mf, wi, ms.m)), pdf, false, pdf > 0.0);
}
fn plastic_pdf(b: BsdfParams, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    if wi.z <= 0.0 || wo.z <= 0.0 { return 0.0; }
    let ps = plastic_prob_specular(b, wo.z);
    let spec = select(0.0, ps * plastic_pdf_lobe(b, wi, wo), b.kind == BSDF_ROUGH_PLASTIC);
    return spec + (1.0 - ps) * cosine_hemisphere_pdf(wi);
}
fn plastic_sample(b: BsdfParams, wo: vec3<f32>, u: vec3<f32>) -> LobeSampleW {
    let ps = plastic_prob_specular(b, wo.z);
    let rough = b.kind == BSDF_ROUGH_PLASTIC;
    if u.x < ps && !rough {
        var s = plastic_sample_lobe(b, wo, u);
        s.weight /= ps;
        return s;
    }
    var wi: vec3<f32>;
    if u.x < ps {
        wi = bsdf_reflect(wo, mf_sample_visible(bsdf_microfacet(b), wo, u.yz).m);
    } else {
        wi = square_to_cosine_hemisphere(u.yz);
    }
    let pdf = plastic_pdf(b, wi, wo);
    if pdf <= 0.0 { return lobe_none(); }
    let diffuse = plastic_diffuse_out(b, wo.z) * (plastic_transmittance(b, wi.z) * BSDF_FRAC_1_PI);
    let weight = (diffuse + plastic_eval_lobe(b, wi, wo)) * wi.z / pdf;
    return LobeSampleW(wi, weight, pdf, false, true);
}
