// Fresnel (exact or Schlick, FRESNEL_* codes), Snell, the glossy lobe and the photon's
// Russian-roulette bounce (BOUNCE_* kinds) about the shading normal; twin of src/bsdfs/classic.rs.
// Library, no entry point; writes nothing.

fn reflect_dir(d: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return d - 2.0 * dot(d, n) * n;
}

fn fresnel_exact(cos_in: f32, n_i: f32, n_t: f32) -> f32 {
    let cos_i = clamp(cos_in, 0.0, 1.0);
    let eta = n_i / n_t;
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = sqrt(1.0 - sin2_t);
    let rs = (n_i * cos_i - n_t * cos_t) / (n_i * cos_i + n_t * cos_t);
    let rp = (n_t * cos_i - n_i * cos_t) / (n_t * cos_i + n_i * cos_t);
    return clamp(0.5 * (rs * rs + rp * rp), 0.0, 1.0);
}

fn fresnel_schlick(cos_in: f32, n_i: f32, n_t: f32) -> f32 {
    let cos_i = clamp(cos_in, 0.0, 1.0);
    let r = (n_i - n_t) / (n_i + n_t);
    let r0 = r * r;
    var c = cos_i;
    if n_i > n_t {
        let eta = n_i / n_t;
        let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        c = sqrt(1.0 - sin2_t);
    }
    return r0 + (1.0 - r0) * pow(1.0 - c, 5.0);
}

// A dielectric split: reflected and refracted directions and the reflectance (1 on TIR).
struct Dielectric {
    reflected: vec3<f32>,
    refracted: vec3<f32>,
    reflectance: f32,
}

// The geometric normal ng says whether the ray enters (which index is inside), the shading
// normal ns (on the side of ng) bends and weighs the directions (twin of dielectric_shading).
fn dielectric(d: vec3<f32>, ng: vec3<f32>, ns: vec3<f32>, ior: f32) -> Dielectric {
    let entering = dot(d, ng) < 0.0;
    let nn = select(-ns, ns, entering);
    let n_i = select(ior, 1.0, entering);
    let n_t = select(1.0, ior, entering);
    let cos_i = clamp(-dot(d, nn), 0.0, 1.0);
    let eta = n_i / n_t;
    let sin2_t = eta * eta * max(1.0 - cos_i * cos_i, 0.0);
    var out: Dielectric;
    out.reflected = reflect_dir(d, nn);
    if sin2_t >= 1.0 {
        out.refracted = vec3<f32>(0.0);
        out.reflectance = 1.0;
        return out;
    }
    let cos_t = sqrt(1.0 - sin2_t);
    out.refracted = normalize(eta * d + (eta * cos_i - cos_t) * nn);
    if params.fresnel == FRESNEL_SCHLICK {
        out.reflectance = fresnel_schlick(cos_i, n_i, n_t);
    } else {
        out.reflectance = fresnel_exact(cos_i, n_i, n_t);
    }
    return out;
}

fn max3(v: vec3<f32>) -> f32 {
    return max(v.x, max(v.y, v.z));
}

fn sum3(v: vec3<f32>) -> f32 {
    return v.x + v.y + v.z;
}

fn phong_lobe_value(wi: vec3<f32>, wo: vec3<f32>, n: vec3<f32>, exponent: f32) -> f32 {
    let cos_a = dot(reflect_dir(-wo, n), wi);
    if cos_a <= 0.0 {
        return 0.0;
    }
    return (exponent + 2.0) / (2.0 * PI) * pow(cos_a, exponent);
}

// Outcome of Russian roulette: kind 0 absorb, 1 diffuse, 2 glossy lobe, 3 delta specular.
struct Bounce {
    dir: vec3<f32>,
    kind: u32,
    weight: vec3<f32>,
}

// Bounce.kind is one of BOUNCE_* (generated prelude, src/integrators/gpu/codes.rs). Directions are
// sampled about the shading normal; one below the geometric surface absorbs the photon
// (twin of photon_bounce_shading).
fn photon_bounce(m: Material, d: vec3<f32>, hit: Hit, u: vec3<f32>) -> Bounce {
    let f = facing(hit, dot(d, hit.normal) < 0.0);
    let ns = f.ns;
    var b = Bounce(vec3<f32>(0.0), BOUNCE_ABSORB, vec3<f32>(0.0));
    if m.kind == MAT_DIFFUSE || m.kind == MAT_GLOSSY {
        let total = max3(m.kd + m.ks);
        let sd = sum3(m.kd);
        let ss = sum3(m.ks);
        if total <= 0.0 || sd + ss <= 0.0 {
            return b;
        }
        let pd = total * sd / (sd + ss);
        let ps = total * ss / (sd + ss);
        if u.x < pd {
            b.kind = BOUNCE_DIFFUSE;
            b.dir = cosine_hemisphere(ns, u.y, u.z);
            b.weight = m.kd / pd;
        } else if u.x < pd + ps {
            let dir = phong_lobe(reflect_dir(d, ns), m.exponent, u.y, u.z);
            let c = dot(dir, ns);
            if c > 0.0 && !reflection_leaks(f, dir) {
                b.kind = BOUNCE_LOBE;
                b.dir = dir;
                b.weight = m.ks * ((m.exponent + 2.0) / (m.exponent + 1.0) * c / ps);
            }
        }
    } else if m.kind == MAT_MIRROR {
        let p = max3(m.ks);
        if u.x < p {
            b.kind = BOUNCE_DELTA;
            b.dir = reflect_dir(d, ns);
            b.weight = m.ks / p;
        }
    } else if HAS_GLASS && m.kind == MAT_GLASS {
        let g = dielectric(d, hit.normal, hit.shading, m.ior);
        b.kind = BOUNCE_DELTA;
        b.weight = vec3<f32>(1.0);
        let reflects = u.x < g.reflectance;
        b.dir = select(g.refracted, g.reflected, reflects);
        if (reflects && reflection_leaks(f, b.dir)) || (!reflects && refraction_leaks(f, b.dir)) {
            b.kind = BOUNCE_ABSORB;
        }
        return b;
    }
    if b.kind != BOUNCE_ABSORB && reflection_leaks(f, b.dir) {
        b.kind = BOUNCE_ABSORB;
    }
    return b;
}
