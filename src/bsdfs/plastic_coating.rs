//! The rough plastic coating's precomputed terms: Mitsuba's Gauss-Legendre quadrature over
//! visible normals that fills the transmittance table at its cosines and gives the internal
//! reflectance. It runs once per material on the CPU; the BSDF (`plastic.rs`) and its GPU twin
//! only read the results.

use crate::bsdfs::math::{gauss_legendre, reflect, refract, square_to_disk_concentric};
use crate::bsdfs::microfacet::{
    beckmann_slope_x, beckmann_slope_y, fresnel_dielectric, ggx_slopes, Distribution, Microfacet,
};
use glam::{Vec2, Vec3};

/// Number of cosines (0 to 1, evenly spaced) of the rough coating's transmittance table.
pub const TRANSMITTANCE_RES: usize = 64;

/// Gauss-Legendre nodes per dimension of Mitsuba's `eval_transmittance` and
/// `eval_reflectance`: 32 when the index seen from the arriving side exceeds 1, else 128.
pub(crate) fn quadrature_res(eta: f32) -> usize {
    if eta > 1.0 {
        32
    } else {
        128
    }
}

/// The cosines Mitsuba tabulates: `max(1e-6, j / (RES - 1))`.
pub(crate) fn table_cos(j: usize) -> f32 {
    (j as f32 / (TRANSMITTANCE_RES - 1) as f32).max(1e-6)
}

/// Mitsuba's tensor Gauss-Legendre rule on the unit square of visible-normal samples, with
/// what does not depend on the incidence precomputed: the nodes mapped to [0, 1], their
/// weights, and per distribution the incidence-free part of the slope (GGX: the concentric
/// disk point of every node pair; Beckmann: the slope across the incidence plane).
pub(crate) struct Rule {
    u: Vec<f32>,
    w: Vec<f64>,
    disk: Vec<Vec2>,
    slope_y: Vec<f32>,
}

impl Rule {
    /// The rule of `n` nodes per dimension for `distribution`'s slopes.
    pub(crate) fn new(n: usize, distribution: Distribution) -> Self {
        let (u, w): (Vec<f32>, Vec<f64>) = gauss_legendre(n)
            .into_iter()
            .map(|(x, w)| ((x * 0.5 + 0.5) as f32, w))
            .unzip();
        let (mut disk, mut slope_y) = (Vec::new(), Vec::new());
        match distribution {
            Distribution::Ggx => {
                for &uy in &u {
                    disk.extend(
                        u.iter()
                            .map(|&ux| square_to_disk_concentric(Vec2::new(ux, uy))),
                    );
                }
            }
            Distribution::Beckmann => slope_y = u.iter().map(|&uy| beckmann_slope_y(uy)).collect(),
        }
        Self {
            u,
            w,
            disk,
            slope_y,
        }
    }
}

/// `integral over visible normals m of G1(w', m) (1 - F)` (transmit) or `G1(w', m) F`
/// (reflect) for incidence `cos_theta` in the xz-plane, w' the refracted or reflected
/// direction: Mitsuba's `eval_transmittance` and `eval_reflectance` with the same nodes. The
/// integrand is even in m.y (the incidence has no y), so only half the node pairs are visited
/// (GGX: the y slope is odd in the disk's x; Beckmann: odd in the node's y), at twice weight.
pub(crate) fn coating_integral(
    mf: &Microfacet,
    rule: &Rule,
    cos_theta: f32,
    eta: f32,
    transmit: bool,
) -> f64 {
    let wi = Vec3::new((1.0 - cos_theta * cos_theta).sqrt(), 0.0, cos_theta);
    let a = mf.alpha_u;
    // The stretched incidence (azimuth 0: the unstretching rotation is the identity).
    let cos_p = Vec3::new(a * wi.x, 0.0, wi.z).normalize().z;
    let integrand = |slope: Vec2| -> f32 {
        let m = Vec3::new(-slope.x * a, -slope.y * a, 1.0).normalize();
        let (f, cos_t, _, eta_ti) = fresnel_dielectric(wi.dot(m), eta);
        if transmit {
            let wo = refract(wi, m, cos_t, eta_ti);
            if wo.z * wi.z >= 0.0 {
                0.0
            } else {
                mf.smith_g1(wo, m) * (1.0 - f)
            }
        } else {
            let wo = reflect(wi, m);
            if wo.z <= 0.0 || wi.z <= 0.0 {
                0.0
            } else {
                mf.smith_g1(wo, m) * f
            }
        }
    };
    let n = rule.u.len();
    let mut sum = 0.0f64;
    match mf.distribution {
        Distribution::Beckmann => {
            for ix in 0..n {
                let sx = beckmann_slope_x(cos_p, rule.u[ix]);
                for iy in 0..n / 2 {
                    let v = integrand(Vec2::new(sx, rule.slope_y[iy]));
                    sum += v as f64 * rule.w[ix] * rule.w[iy];
                }
            }
        }
        Distribution::Ggx => {
            for iy in 0..n {
                for ix in 0..n / 2 {
                    let v = integrand(ggx_slopes(cos_p, rule.disk[iy * n + ix]));
                    sum += v as f64 * rule.w[ix] * rule.w[iy];
                }
            }
        }
    }
    // 0.25: the nodes' Jacobian from [-1, 1]^2 to the unit square; 2: the mirrored half.
    sum * 0.25 * 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The same integral straight from `sample_visible` over every node pair.
    fn direct(mf: &Microfacet, cos_theta: f32, eta: f32, transmit: bool) -> f64 {
        let wi = Vec3::new((1.0 - cos_theta * cos_theta).sqrt(), 0.0, cos_theta);
        let nodes = gauss_legendre(quadrature_res(eta));
        let mut sum = 0.0;
        for &(y, wy) in &nodes {
            for &(x, wx) in &nodes {
                let u = Vec2::new((x * 0.5 + 0.5) as f32, (y * 0.5 + 0.5) as f32);
                let m = mf.sample_visible(wi, u).0;
                let (f, cos_t, _, eta_ti) = fresnel_dielectric(wi.dot(m), eta);
                let v = if transmit {
                    let wo = refract(wi, m, cos_t, eta_ti);
                    if wo.z * wi.z < 0.0 {
                        mf.smith_g1(wo, m) * (1.0 - f)
                    } else {
                        0.0
                    }
                } else {
                    let wo = reflect(wi, m);
                    if wo.z > 0.0 {
                        mf.smith_g1(wo, m) * f
                    } else {
                        0.0
                    }
                };
                sum += v as f64 * wx * wy * 0.25;
            }
        }
        sum
    }

    #[test]
    fn halved_rule_equals_the_direct_sum() {
        for d in [Distribution::Ggx, Distribution::Beckmann] {
            let mf = Microfacet::isotropic(d, 0.3);
            for (eta, transmit) in [(1.5, true), (1.0 / 1.5, false)] {
                let rule = Rule::new(quadrature_res(eta), d);
                for mu in [1e-6, 0.2, 0.7, 1.0] {
                    let (a, b) = (
                        coating_integral(&mf, &rule, mu, eta, transmit),
                        direct(&mf, mu, eta, transmit),
                    );
                    assert!((a - b).abs() < 1e-6, "{d:?} eta {eta} mu {mu}: {a} vs {b}");
                }
            }
        }
    }
}
