// Microfacet distributions (Beckmann, GGX; anisotropic), Smith's shadowing, visible-normal
// sampling and the Fresnel equations of dielectrics and conductors, as Mitsuba 3.9.1 defines
// them: twin of src/bsdfs/microfacet.rs, function for function. Library, no entry point;
// writes nothing. MF_GGX and MF_BECKMANN come from the generated BSDF codes.

struct Microfacet { distribution: u32, alpha_u: f32, alpha_v: f32 }
struct MfSample { m: vec3<f32>, pdf: f32 }
// fresnel_dielectric's tuple (F, cos_theta_t, eta_it, eta_ti).
struct FresnelW { f: f32, cos_t: f32, eta_it: f32, eta_ti: f32 }
const MF_SIN2_MIN: f32 = 2.3841858e-7f; // 4 f32::EPSILON / 2

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
