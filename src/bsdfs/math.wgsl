// Scalar helpers the BSDFs share (twin of src/bsdfs/math.rs, same operation order): erf and
// erfinv in f32, Mitsuba's square-to-disk and cosine-hemisphere warps, the local-frame
// reflection and refraction. Library, no entry point; writes nothing.
// Directions are in the local shading frame (z the front shading normal).

const BSDF_FRAC_1_PI: f32 = 0.31830987f;
const BSDF_FRAC_PI_2: f32 = 1.5707964f;
const BSDF_FRAC_PI_4: f32 = 0.7853982f;

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
