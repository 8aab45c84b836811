//! Scalar helpers the BSDFs share: `erf`/`erfinv` in single precision, the square-to-disk and
//! square-to-cosine-hemisphere warps (the same mappings Mitsuba 3 uses, so equal uniforms give
//! equal directions), Gauss-Legendre nodes for the plastic's precomputation, and the local-frame
//! reflection and refraction formulas.
//!
//! Everything is branch-light f32 arithmetic without tables, so the WGSL twin can copy it line
//! by line (the Gauss-Legendre nodes run once per material on the CPU only, in f64).

use glam::{Vec2, Vec3};
use std::f32::consts::{FRAC_PI_2, FRAC_PI_4, PI};

/// The error function in single precision (Numerical Recipes' `erfcc` rational fit, fractional
/// error below 1.2e-7 everywhere; `erf(±inf) = ±1`).
#[allow(clippy::excessive_precision)] // the published coefficients, as printed
pub fn erf(x: f32) -> f32 {
    let z = x.abs();
    let t = 1.0 / (1.0 + 0.5 * z);
    let poly = -1.265_512_2
        + t * (1.000_023_7
            + t * (0.374_091_96
                + t * (0.096_784_18
                    + t * (-0.186_288_06
                        + t * (0.278_868_07
                            + t * (-1.135_203_98
                                + t * (1.488_515_87 + t * (-0.822_152_23 + t * 0.170_872_77))))))));
    let erfc = t * (-z * z + poly).exp();
    let r = 1.0 - erfc;
    if x < 0.0 {
        -r
    } else {
        r
    }
}

/// The inverse error function in single precision (M. Giles, "Approximating the erfinv
/// function", GPU Computing Gems, 2011), for `x` in (-1, 1).
#[allow(clippy::excessive_precision)] // the published coefficients, as printed
pub fn erfinv(x: f32) -> f32 {
    let mut w = -((1.0 - x) * (1.0 + x)).ln();
    let p = if w < 5.0 {
        w -= 2.5;
        let mut p = 2.810_226_36e-08;
        p = 3.432_739_39e-07 + p * w;
        p = -3.523_387_7e-06 + p * w;
        p = -4.391_506_54e-06 + p * w;
        p = 0.000_218_580_87 + p * w;
        p = -0.001_253_725_03 + p * w;
        p = -0.004_177_681_64 + p * w;
        p = 0.246_640_727 + p * w;
        1.501_409_41 + p * w
    } else {
        w = w.sqrt() - 3.0;
        let mut p = -0.000_200_214_257;
        p = 0.000_100_950_558 + p * w;
        p = 0.001_349_343_22 + p * w;
        p = -0.003_673_428_44 + p * w;
        p = 0.005_739_507_73 + p * w;
        p = -0.007_622_461_3 + p * w;
        p = 0.009_438_870_47 + p * w;
        p = 1.001_674_06 + p * w;
        2.832_976_82 + p * w
    };
    p * x
}

/// `sqrt(max(x, 0))`.
#[inline]
pub fn safe_sqrt(x: f32) -> f32 {
    x.max(0.0).sqrt()
}

/// Shirley and Chiu's concentric map of the unit square onto the unit disk.
pub fn square_to_disk_concentric(u: Vec2) -> Vec2 {
    let r1 = 2.0 * u.x - 1.0;
    let r2 = 2.0 * u.y - 1.0;
    if r1 == 0.0 && r2 == 0.0 {
        return Vec2::ZERO;
    }
    let (r, phi) = if r1.abs() < r2.abs() {
        (r2, FRAC_PI_2 - FRAC_PI_4 * (r1 / r2))
    } else {
        (r1, FRAC_PI_4 * (r2 / r1))
    };
    let (s, c) = phi.sin_cos();
    Vec2::new(r * c, r * s)
}

/// Cosine-weighted direction on the upper hemisphere (z > 0) from the unit square (the
/// concentric disk lifted to the hemisphere); its density is [`cosine_hemisphere_pdf`].
pub fn square_to_cosine_hemisphere(u: Vec2) -> Vec3 {
    let p = square_to_disk_concentric(u);
    Vec3::new(p.x, p.y, safe_sqrt(1.0 - p.length_squared()))
}

/// Solid-angle density of [`square_to_cosine_hemisphere`]: `max(z, 0) / pi`.
#[inline]
pub fn cosine_hemisphere_pdf(w: Vec3) -> f32 {
    w.z.max(0.0) / PI
}

/// Mirror `w` about the local normal z: `(-x, -y, z)`.
#[inline]
pub fn reflect_z(w: Vec3) -> Vec3 {
    Vec3::new(-w.x, -w.y, w.z)
}

/// Mirror `w` about the unit normal `m`: `2 (w . m) m - w`.
#[inline]
pub fn reflect(w: Vec3, m: Vec3) -> Vec3 {
    2.0 * w.dot(m) * m - w
}

/// Refract `w` through the microfacet `m`, given `cos_theta_t` and `eta_ti` from
/// [`fresnel_dielectric`](crate::bsdfs::microfacet::fresnel_dielectric) evaluated at `w . m`.
#[inline]
pub fn refract(w: Vec3, m: Vec3, cos_theta_t: f32, eta_ti: f32) -> Vec3 {
    m * (w.dot(m) * eta_ti + cos_theta_t) - w * eta_ti
}

/// `a` with the sign of `b` (a zero `b` counts as positive, as for `+0.0`).
#[inline]
pub fn mulsign(a: Vec3, b: f32) -> Vec3 {
    if b.is_sign_negative() {
        -a
    } else {
        a
    }
}

/// The `n` nodes (in [-1, 1]) and weights (summing to 2) of Gauss-Legendre quadrature,
/// computed in f64 by Newton's method on the Legendre polynomial.
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    let mut out = Vec::with_capacity(n);
    for i in 0..n {
        // Chebyshev-like initial guess of the i-th root, largest first.
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
        let mut dp = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0f64, x);
            for k in 2..=n {
                let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                p0 = p1;
                p1 = p2;
            }
            let p = if n == 0 { 1.0 } else { p1 };
            let pm1 = if n == 1 { 1.0 } else { p0 };
            dp = n as f64 * (x * p - pm1) / (x * x - 1.0);
            let step = p / dp;
            x -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        let w = 2.0 / ((1.0 - x * x) * dp * dp);
        out.push((-x, w));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn erf_and_erfinv_agree() {
        for i in -99..=99 {
            let x = i as f32 / 100.0;
            let y = erfinv(x);
            assert!((erf(y) - x).abs() < 2e-6, "x {x} y {y} erf {}", erf(y));
        }
        assert_eq!(erf(f32::INFINITY), 1.0);
        assert!((erf(0.5) - 0.520_499_9).abs() < 1e-6);
    }

    #[test]
    fn gauss_legendre_integrates_polynomials() {
        for n in [1usize, 2, 5, 32, 128] {
            let q = gauss_legendre(n);
            let w: f64 = q.iter().map(|&(_, w)| w).sum();
            assert!((w - 2.0).abs() < 1e-12, "n {n} sum {w}");
            let x2: f64 = q.iter().map(|&(x, w)| w * x * x).sum();
            if n >= 2 {
                assert!((x2 - 2.0 / 3.0).abs() < 1e-12, "n {n} x2 {x2}");
            }
        }
    }

    #[test]
    fn cosine_hemisphere_is_unit() {
        for i in 0..50 {
            let u = Vec2::new((i as f32 * 0.137) % 1.0, (i as f32 * 0.311) % 1.0);
            let w = square_to_cosine_hemisphere(u);
            assert!((w.length() - 1.0).abs() < 1e-5 && w.z >= 0.0);
        }
    }
}
