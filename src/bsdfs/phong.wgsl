// A Lambertian base kd plus a normalised Phong lobe ks of exponent n (twin of
// src/bsdfs/phong.rs): world-space about the caller's shading normal on the surface, and the
// classic photon roulette it shares with the Lambertian kind. Words: 0 kd, 1 ks (slots),
// 2 the exponent. Library, no entry point; writes nothing.

fn phong_lobe_value(wi: vec3<f32>, wo: vec3<f32>, n: vec3<f32>, exponent: f32) -> f32 {
    let cos_a = dot(reflect_dir(-wo, n), wi);
    if cos_a <= 0.0 {
        return 0.0;
    }
    return (exponent + 2.0) / (2.0 * PI) * pow(cos_a, exponent);
}
fn phong_pdf_value(wi: vec3<f32>, wo: vec3<f32>, n: vec3<f32>, exponent: f32) -> f32 {
    let cos_a = dot(reflect_dir(-wo, n), wi);
    if cos_a <= 0.0 {
        return 0.0;
    }
    return (exponent + 1.0) / (2.0 * PI) * pow(cos_a, exponent);
}

// Russian roulette between the diffuse part, the lobe and absorption (twin of classic_bounce):
// directions about the shading normal; one below the geometric surface absorbs the photon.
fn classic_bounce(kd: vec3<f32>, ks: vec3<f32>, exponent: f32, d: vec3<f32>, hit: Hit, u: vec3<f32>) -> Bounce {
    let f = facing(hit, dot(d, hit.normal) < 0.0);
    let ns = f.ns;
    var b = Bounce(vec3<f32>(0.0), BOUNCE_ABSORB, vec3<f32>(0.0));
    let total = max3(kd + ks);
    let sd = sum3(kd);
    let ss = sum3(ks);
    if total <= 0.0 || sd + ss <= 0.0 {
        return b;
    }
    let pd = total * sd / (sd + ss);
    let ps = total * ss / (sd + ss);
    if u.x < pd {
        b.kind = BOUNCE_DIFFUSE;
        b.dir = cosine_hemisphere(ns, u.y, u.z);
        b.weight = kd / pd;
    } else if u.x < pd + ps {
        let dir = phong_lobe(reflect_dir(d, ns), exponent, u.y, u.z);
        let c = dot(dir, ns);
        if c > 0.0 && !reflection_leaks(f, dir) {
            b.kind = BOUNCE_LOBE;
            b.dir = dir;
            b.weight = ks * ((exponent + 2.0) / (exponent + 1.0) * c / ps);
        }
    }
    if b.kind != BOUNCE_ABSORB && reflection_leaks(f, b.dir) {
        b.kind = BOUNCE_ABSORB;
    }
    return b;
}

fn phong_lobe_choice(b: Bsdf) -> f32 {
    let sd = sum3(w_rgb(b.w0));
    let ss = sum3(w_rgb(b.w1));
    return select(0.0, ss / (sd + ss), sd + ss > 0.0);
}
fn phong_diffuse_out(b: Bsdf, wo: vec3<f32>) -> vec3<f32> {
    if wo.z == 0.0 { return vec3<f32>(0.0); }
    return w_rgb(b.w0);
}
fn phong_store_weight(b: Bsdf, wi: vec3<f32>) -> f32 { return select(1.0, 0.0, wi.z == 0.0); }
fn phong_eval_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>, radiance: bool) -> vec3<f32> {
    let fr = to_front(wi, wo);
    if !fr.ok { return vec3<f32>(0.0); }
    return w_rgb(b.w1) * phong_lobe_value(fr.wi, fr.wo, vec3<f32>(0.0, 0.0, 1.0), w_f(b.w2));
}
fn phong_pdf_lobe(b: Bsdf, wi: vec3<f32>, wo: vec3<f32>) -> f32 {
    let fr = to_front(wi, wo);
    if !fr.ok { return 0.0; }
    return phong_pdf_value(fr.wi, fr.wo, vec3<f32>(0.0, 0.0, 1.0), w_f(b.w2));
}
fn phong_sample_lobe(b: Bsdf, wo_in: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo_in);
    if !fr.ok { return lobe_none(); }
    let e = w_f(b.w2);
    let wi = phong_lobe(reflect_z(fr.wo), e, u.y, u.z);
    let pdf = phong_pdf_value(wi, fr.wo, vec3<f32>(0.0, 0.0, 1.0), e);
    if wi.z <= 0.0 || pdf <= 0.0 { return lobe_none(); }
    let weight = w_rgb(b.w1) * ((e + 2.0) / (e + 1.0) * wi.z);
    return back_to_side(LobeSampleW(wi, weight, pdf, false, true), fr.flipped);
}
fn phong_has_diffuse(b: Bsdf) -> bool { return true; }
fn phong_has_lobe(b: Bsdf) -> bool { return max3(w_rgb(b.w1)) > 0.0; }
fn phong_lobe_probability(b: Bsdf, wo: vec3<f32>) -> f32 { return phong_lobe_choice(b); }
fn phong_pdf(b: Bsdf, wi_in: vec3<f32>, wo_in: vec3<f32>) -> f32 {
    let fr = to_front(wi_in, wo_in);
    if !fr.ok || fr.wi.z <= 0.0 { return 0.0; }
    let p = phong_lobe_choice(b);
    return p * phong_pdf_value(fr.wi, fr.wo, vec3<f32>(0.0, 0.0, 1.0), w_f(b.w2)) + (1.0 - p) * cosine_hemisphere_pdf(fr.wi);
}
fn phong_sample(b: Bsdf, wo_in: vec3<f32>, u: vec3<f32>, radiance: bool) -> LobeSampleW {
    let fr = to_front(vec3<f32>(0.0, 0.0, 1.0), wo_in);
    if !fr.ok { return lobe_none(); }
    var wi: vec3<f32>;
    if u.x < phong_lobe_choice(b) {
        wi = phong_lobe(reflect_z(fr.wo), w_f(b.w2), u.y, u.z);
    } else {
        wi = square_to_cosine_hemisphere(u.yz);
    }
    let pdf = phong_pdf(b, wi, fr.wo);
    if pdf <= 0.0 { return lobe_none(); }
    let weight = bsdf_eval(b, wi, fr.wo, radiance) * wi.z / pdf;
    return back_to_side(LobeSampleW(wi, weight, pdf, false, true), fr.flipped);
}

fn phong_surface_diffuse_albedo(s: Surface, wo: vec3<f32>) -> vec3<f32> { return w_rgb(s.b.w0); }
fn phong_surface_store_weight(s: Surface, wi: vec3<f32>) -> f32 { return 1.0; }
fn phong_surface_eval_diffuse(s: Surface, wi: vec3<f32>, wo: vec3<f32>) -> vec3<f32> { return w_rgb(s.b.w0) / PI; }
fn phong_surface_lobe_takes_point_lights(s: Surface) -> bool { return true; }
fn phong_surface_eval_lobe(s: Surface, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>) -> vec3<f32> {
    return w_rgb(s.b.w1) * phong_lobe_value(wi, wo, ns, w_f(s.b.w2));
}
fn phong_surface_pdf_lobe(s: Surface, wi: vec3<f32>, wo: vec3<f32>, ns: vec3<f32>) -> f32 {
    return phong_pdf_value(wi, wo, ns, w_f(s.b.w2));
}
// Two numbers from rng: the lobe about the mirror direction of d.
fn phong_surface_sample_lobe(s: Surface, d: vec3<f32>, f: Facing, rng: ptr<function, Rng>) -> LobeRay {
    let e = w_f(s.b.w2);
    let u1 = rng_next(rng);
    let u2 = rng_next(rng);
    let dir = phong_lobe(reflect_dir(d, f.ns), e, u1, u2);
    let c = dot(dir, f.ns);
    let ok = c > 0.0 && !reflection_leaks(f, dir);
    return LobeRay(dir, w_rgb(s.b.w1) * ((e + 2.0) / (e + 1.0) * c), ok, phong_pdf_value(dir, -d, f.ns, e));
}
fn phong_surface_photon_bounce(s: Surface, d: vec3<f32>, hit: Hit, u: vec3<f32>) -> Bounce {
    return classic_bounce(w_rgb(s.b.w0), w_rgb(s.b.w1), w_f(s.b.w2), d, hit, u);
}
