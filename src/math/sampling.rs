//! Warping uniform numbers to directions and points. Twin: `src/math/sampling.wgsl`.

use glam::Vec3;
use std::f32::consts::PI;

/// An orthonormal basis (t, b, n) around unit `n` (Duff et al. 2017, branchless).
#[inline]
pub fn basis(n: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(n.z);
    let a = -1.0 / (sign + n.z);
    let b = n.x * n.y * a;
    (
        Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
        Vec3::new(b, sign + n.y * n.y * a, -n.y),
    )
}

/// Expresses local direction `l` (z = up) in the frame around `n`.
#[inline]
pub fn to_world(l: Vec3, n: Vec3) -> Vec3 {
    let (t, b) = basis(n);
    t * l.x + b * l.y + n * l.z
}

/// Cosine-weighted direction around `n`; pdf = cos / pi.
#[inline]
pub fn cosine_hemisphere(n: Vec3, u1: f32, u2: f32) -> Vec3 {
    let r = u1.sqrt();
    let phi = 2.0 * PI * u2;
    let z = (1.0 - u1).max(0.0).sqrt();
    to_world(Vec3::new(r * phi.cos(), r * phi.sin(), z), n)
}

/// Uniform direction on the unit sphere; pdf = 1 / (4 pi).
#[inline]
pub fn uniform_sphere(u1: f32, u2: f32) -> Vec3 {
    let z = 1.0 - 2.0 * u1;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    Vec3::new(r * phi.cos(), r * phi.sin(), z)
}

/// Direction around unit `axis` with pdf = (n + 1) / (2 pi) cos^n(angle to axis).
#[inline]
pub fn phong_lobe(axis: Vec3, exponent: f32, u1: f32, u2: f32) -> Vec3 {
    let cos_a = u1.powf(1.0 / (exponent + 1.0));
    let sin_a = (1.0 - cos_a * cos_a).max(0.0).sqrt();
    let phi = 2.0 * PI * u2;
    to_world(Vec3::new(sin_a * phi.cos(), sin_a * phi.sin(), cos_a), axis)
}

/// Uniform barycentric coordinates (u, v) on a triangle.
#[inline]
pub fn uniform_triangle(u1: f32, u2: f32) -> (f32, f32) {
    let s = u1.sqrt();
    (1.0 - s, u2 * s)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn basis_is_orthonormal_for_awkward_normals() {
        for n in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(0.0, -1.0, 1e-8).normalize(),
            Vec3::new(1.0, 2.0, -3.0).normalize(),
        ] {
            let (t, b) = basis(n);
            assert!((t.length() - 1.0).abs() < 1e-5 && (b.length() - 1.0).abs() < 1e-5);
            assert!(t.dot(b).abs() < 1e-5 && t.dot(n).abs() < 1e-5 && b.dot(n).abs() < 1e-5);
        }
    }
}
