// Warping uniform numbers to directions (orthonormal bases, cosine hemisphere, uniform sphere,
// Phong lobe); twin of src/math/sampling.rs.
// Library, no entry point; writes nothing.

// Rust's 1.0.copysign(n.z): -1 for every z with the sign bit set, -0.0 included.
fn basis_sign(z: f32) -> f32 {
    return select(1.0, -1.0, (bitcast<u32>(z) & 0x80000000u) != 0u);
}

fn basis_t(n: vec3<f32>) -> vec3<f32> {
    let s = basis_sign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(1.0 + s * n.x * n.x * a, s * b, -s * n.x);
}

fn basis_b(n: vec3<f32>) -> vec3<f32> {
    let s = basis_sign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    return vec3<f32>(b, s + n.y * n.y * a, -n.y);
}

fn to_world(l: vec3<f32>, n: vec3<f32>) -> vec3<f32> {
    return basis_t(n) * l.x + basis_b(n) * l.y + n * l.z;
}

fn cosine_hemisphere(n: vec3<f32>, u1: f32, u2: f32) -> vec3<f32> {
    let r = sqrt(u1);
    let phi = 2.0 * PI * u2;
    let z = sqrt(max(1.0 - u1, 0.0));
    return to_world(vec3<f32>(r * cos(phi), r * sin(phi), z), n);
}

fn uniform_sphere(u1: f32, u2: f32) -> vec3<f32> {
    let z = 1.0 - 2.0 * u1;
    let r = sqrt(max(1.0 - z * z, 0.0));
    let phi = 2.0 * PI * u2;
    return vec3<f32>(r * cos(phi), r * sin(phi), z);
}

fn phong_lobe(axis: vec3<f32>, exponent: f32, u1: f32, u2: f32) -> vec3<f32> {
    let cos_a = pow(u1, 1.0 / (exponent + 1.0));
    let sin_a = sqrt(max(1.0 - cos_a * cos_a, 0.0));
    let phi = 2.0 * PI * u2;
    return to_world(vec3<f32>(sin_a * cos(phi), sin_a * sin(phi), cos_a), axis);
}
