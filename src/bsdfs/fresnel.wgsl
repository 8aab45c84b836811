// Reflection, Snell refraction and the exact or Schlick Fresnel reflectance (FRESNEL_* codes)
// of a dielectric interface in world space, twin of src/bsdfs/fresnel.rs: what the classic
// mirror and glass kinds and the camera paths' glass splits use. Library, no entry point;
// writes nothing.

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
    // n_i / n_t along the refracted ray (1 for a thin sheet): a camera path's radiance along
    // it scales by eta^2 (twin of Dielectric::refracted_radiance).
    eta: f32,
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
    out.eta = eta;
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
