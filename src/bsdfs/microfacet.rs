//! Microfacet distributions (Beckmann and GGX / Trowbridge-Reitz, anisotropic), Smith's
//! separable shadowing-masking, visible-normal sampling, and the Fresnel equations, with the
//! conventions of Mitsuba 3.9.1 (`include/mitsuba/render/microfacet.h` and `fresnel.h`).
//!
//! Directions live in the local shading frame (z = normal). The roughness is clamped to at
//! least 1e-4 by [`Microfacet::new`], as Mitsuba does when it builds a distribution.

use crate::bsdfs::math::{erf, erfinv, safe_sqrt, square_to_disk_concentric};
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

pub use crate::bsdfs::ior::{named_conductor, METAL_NAMES};

/// The normal distribution function of a microfacet model.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Distribution {
    /// Trowbridge-Reitz (GGX): long tails.
    Ggx,
    /// Beckmann: slopes of a Gaussian random surface.
    Beckmann,
}

/// The GPU code of [`Distribution::Ggx`] (`MF_GGX` in WGSL).
pub const MF_GGX: u32 = 0;
/// The GPU code of [`Distribution::Beckmann`] (`MF_BECKMANN` in WGSL).
pub const MF_BECKMANN: u32 = 1;

/// A distribution's GPU code.
pub fn distribution_code(d: Distribution) -> u32 {
    match d {
        Distribution::Ggx => MF_GGX,
        Distribution::Beckmann => MF_BECKMANN,
    }
}

/// A microfacet distribution with roughness `alpha_u` along x and `alpha_v` along y.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microfacet {
    /// Which normal distribution.
    pub distribution: Distribution,
    /// Roughness along the tangent (x) direction.
    pub alpha_u: f32,
    /// Roughness along the bitangent (y) direction.
    pub alpha_v: f32,
}

impl Microfacet {
    /// An anisotropic distribution; each roughness is clamped to at least 1e-4 (as Mitsuba).
    pub fn new(distribution: Distribution, alpha_u: f32, alpha_v: f32) -> Self {
        Self {
            distribution,
            alpha_u: alpha_u.max(1e-4),
            alpha_v: alpha_v.max(1e-4),
        }
    }

    /// An isotropic distribution (`alpha_u = alpha_v = alpha`, clamped to at least 1e-4).
    pub fn isotropic(distribution: Distribution, alpha: f32) -> Self {
        Self::new(distribution, alpha, alpha)
    }

    /// The distribution of normals D(m) (per unit solid angle of m, projected: its integral
    /// times cos theta_m over the hemisphere is 1). Zero below the horizon or where
    /// `D cos theta_m <= 1e-20`.
    pub fn d(&self, m: Vec3) -> f32 {
        let (au, av) = (self.alpha_u, self.alpha_v);
        let c2 = m.z * m.z;
        let r = match self.distribution {
            Distribution::Beckmann => {
                let e = -((m.x / au).powi(2) + (m.y / av).powi(2)) / c2;
                e.exp() / (PI * au * av * c2 * c2)
            }
            Distribution::Ggx => {
                let s = (m.x / au).powi(2) + (m.y / av).powi(2) + c2;
                1.0 / (PI * au * av * s * s)
            }
        };
        if r * m.z > 1e-20 {
            r
        } else {
            0.0
        }
    }

    /// Smith's shadowing-masking for one direction `v` and microfacet `m` (Beckmann through
    /// Walter's rational fit, GGX exact); zero when `v` sees the back of `m`.
    pub fn smith_g1(&self, v: Vec3, m: Vec3) -> f32 {
        let xy = (self.alpha_u * v.x).powi(2) + (self.alpha_v * v.y).powi(2);
        if v.dot(m) * v.z <= 0.0 {
            return 0.0;
        }
        if xy == 0.0 {
            return 1.0;
        }
        let tan2 = xy / (v.z * v.z);
        match self.distribution {
            Distribution::Beckmann => {
                let a = 1.0 / tan2.sqrt();
                if a >= 1.6 {
                    1.0
                } else {
                    let a2 = a * a;
                    (3.535 * a + 2.181 * a2) / (1.0 + 2.276 * a + 2.577 * a2)
                }
            }
            Distribution::Ggx => 2.0 / (1.0 + (1.0 + tan2).sqrt()),
        }
    }

    /// The separable Smith term `G1(wi, m) G1(wo, m)`.
    pub fn g(&self, wi: Vec3, wo: Vec3, m: Vec3) -> f32 {
        self.smith_g1(wi, m) * self.smith_g1(wo, m)
    }

    /// Samples a normal from the distribution of normals visible from `wo` (`wo.z > 0`):
    /// stretch, sample the alpha = 1 slopes, rotate and unstretch (Heitz and d'Eon; for GGX
    /// Heitz's 2018 hemisphere-projection method, for Beckmann Jakob's Newton inversion).
    /// `u.x` and `u.y` both shape the normal. Returns `(m, pdf_visible(wo, m))`.
    /// For Beckmann, `u` is clamped to [1e-6, 1 - 1e-6] as in Mitsuba.
    pub fn sample_visible(&self, wo: Vec3, u: Vec2) -> (Vec3, f32) {
        let (au, av) = (self.alpha_u, self.alpha_v);
        let wp = Vec3::new(au * wo.x, av * wo.y, wo.z).normalize();
        let sin2 = wp.x * wp.x + wp.y * wp.y;
        let (sin_phi, cos_phi) = if sin2 <= 4.0 * f32::EPSILON / 2.0 {
            (0.0, 1.0)
        } else {
            let inv = 1.0 / sin2.sqrt();
            ((wp.y * inv).clamp(-1.0, 1.0), (wp.x * inv).clamp(-1.0, 1.0))
        };
        let s = self.sample_visible_11(wp.z, u);
        let sx = (cos_phi * s.x - sin_phi * s.y) * au;
        let sy = (sin_phi * s.x + cos_phi * s.y) * av;
        let m = Vec3::new(-sx, -sy, 1.0).normalize();
        (m, self.pdf_visible(wo, m))
    }

    /// Slopes of the alpha = 1 distribution of normals visible from inclination `cos_theta`.
    fn sample_visible_11(&self, cos_theta: f32, u: Vec2) -> Vec2 {
        match self.distribution {
            Distribution::Beckmann => {
                Vec2::new(beckmann_slope_x(cos_theta, u.x), beckmann_slope_y(u.y))
            }
            Distribution::Ggx => ggx_slopes(cos_theta, square_to_disk_concentric(u)),
        }
    }

    /// Density (per solid angle of m) of [`sample_visible`](Self::sample_visible):
    /// `D(m) G1(wo, m) |wo . m| / wo.z`.
    pub fn pdf_visible(&self, wo: Vec3, m: Vec3) -> f32 {
        self.d(m) * self.smith_g1(wo, m) * wo.dot(m).abs() / wo.z
    }
}

/// Beckmann, alpha = 1: the slope along the incidence plane for `u` (Jakob's numerical
/// inversion of the visible-slope CDF: an analytic first guess, then three Newton steps in
/// the erf domain). Depends on `cos_theta` and `u` only, which the plastic's precomputation
/// uses.
pub(crate) fn beckmann_slope_x(cos_theta: f32, u: f32) -> f32 {
    let tan_theta = safe_sqrt(1.0 - cos_theta * cos_theta) / cos_theta;
    let cot_theta = 1.0 / tan_theta;
    let maxval = erf(cot_theta);
    let u = u.clamp(1e-6, 1.0 - 1e-6);
    // Initial guess: the analytic solution for theta = pi/2.
    let mut x = maxval - (maxval + 1.0) * erf((-u.ln()).sqrt());
    let inv_sqrt_pi = 0.564_189_6_f32;
    let target = u * (1.0 + maxval + inv_sqrt_pi * tan_theta * (-cot_theta * cot_theta).exp());
    for _ in 0..3 {
        let slope = erfinv(x);
        let value = 1.0 + x + inv_sqrt_pi * tan_theta * (-slope * slope).exp() - target;
        let derivative = 1.0 - slope * tan_theta;
        x -= value / derivative;
    }
    erfinv(x)
}

/// Beckmann, alpha = 1: the slope across the incidence plane (a Gaussian), odd in `u - 1/2`.
pub(crate) fn beckmann_slope_y(u: f32) -> f32 {
    erfinv(2.0 * u.clamp(1e-6, 1.0 - 1e-6) - 1.0)
}

/// GGX, alpha = 1: both slopes from a point `p` of the unit disk (Heitz 2018: squash the
/// disk onto the visible half of the projected hemisphere); the `y` slope is odd in `p.x`.
pub(crate) fn ggx_slopes(cos_theta: f32, mut p: Vec2) -> Vec2 {
    let s = 0.5 * (1.0 + cos_theta);
    let h = safe_sqrt(1.0 - p.x * p.x);
    p.y = h + (p.y - h) * s;
    let z = safe_sqrt(1.0 - p.length_squared());
    let sin_theta = safe_sqrt(1.0 - cos_theta * cos_theta);
    let norm = 1.0 / (sin_theta * p.y + cos_theta * z);
    Vec2::new(cos_theta * p.y - sin_theta * z, p.x) * norm
}

/// Unpolarised Fresnel reflectance of a dielectric interface, as Mitsuba's `fresnel()`.
/// `eta` = interior / exterior index; a negative `cos_theta_i` means arriving from inside.
/// Returns `(F, cos_theta_t, eta_it, eta_ti)`: the reflectance, the signed cosine of the
/// refracted direction (opposite side to the incident one; 0 under total internal reflection),
/// the relative index in the direction of travel and its reciprocal.
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> (f32, f32, f32, f32) {
    let outside = cos_theta_i >= 0.0;
    let rcp_eta = 1.0 / eta;
    let (eta_it, eta_ti) = if outside {
        (eta, rcp_eta)
    } else {
        (rcp_eta, eta)
    };
    let cos_t_sqr = 1.0 - (1.0 - cos_theta_i * cos_theta_i) * (eta_ti * eta_ti);
    let ci = cos_theta_i.abs();
    let ct = safe_sqrt(cos_t_sqr);
    let r = if eta == 1.0 {
        0.0
    } else if ci == 0.0 {
        1.0
    } else {
        let a_s = (ci - eta_it * ct) / (ci + eta_it * ct);
        let a_p = (ct - eta_it * ci) / (ct + eta_it * ci);
        0.5 * (a_s * a_s + a_p * a_p)
    };
    let cos_theta_t = if cos_theta_i >= 0.0 { -ct } else { ct };
    (r, cos_theta_t, eta_it, eta_ti)
}

/// Unpolarised Fresnel reflectance of a conductor with complex index `eta + i k` (per
/// channel), light arriving from outside (`cos_theta_i >= 0`).
pub fn fresnel_conductor(cos_theta_i: f32, eta: Vec3, k: Vec3) -> Vec3 {
    let f = |eta: f32, k: f32| {
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
        0.5 * (r_s + r_p)
    };
    Vec3::new(f(eta.x, k.x), f(eta.y, k.y), f(eta.z, k.z))
}

/// The diffuse Fresnel reflectance (Fdr) of a dielectric with relative index `eta`, by the
/// same fits Mitsuba uses: Egan and Hilgeman (1973) for `eta < 1`, d'Eon and Irving (2011)
/// otherwise.
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    let inv = 1.0 / eta;
    if eta < 1.0 {
        0.0636 * inv + (eta * (eta * -1.4399 + 0.7099) + 0.6681)
    } else {
        0.919_317
            + inv
                * (-3.4793
                    + inv * (6.753_35 + inv * (-7.809_89 + inv * (4.985_54 + inv * -1.368_81))))
    }
}

/// A microfacet distribution whose roughness is textureable: what a rough kind keeps (its
/// `Param` slots, clamped to at least 1e-4 where looked up) and resolves at a hit into a
/// [`Microfacet`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Roughness {
    /// The normal distribution.
    pub distribution: Distribution,
    /// Roughness along the tangent.
    pub alpha_u: crate::bsdfs::param::Param,
    /// Roughness along the bitangent.
    pub alpha_v: crate::bsdfs::param::Param,
}

impl Roughness {
    /// The untextured roughness of `mf`.
    pub fn new(mf: Microfacet) -> Self {
        use crate::bsdfs::param::Param;
        Roughness {
            distribution: mf.distribution,
            alpha_u: Param::constant(mf.alpha_u),
            alpha_v: Param::constant(mf.alpha_v),
        }
    }

    /// Its textures looked up at `uv` (each at least 1e-4).
    pub fn resolved(&self, t: &[crate::textures::SceneTexture], uv: glam::Vec2) -> Self {
        use crate::bsdfs::param::Param;
        let clamped = |p: &Param| match p.is_textured() {
            true => Param::constant(p.eval(t, uv).x.max(1e-4)),
            false => *p,
        };
        Roughness {
            alpha_u: clamped(&self.alpha_u),
            alpha_v: clamped(&self.alpha_v),
            ..*self
        }
    }

    /// The distribution of a resolved roughness.
    pub fn microfacet(&self) -> Microfacet {
        Microfacet {
            distribution: self.distribution,
            alpha_u: self.alpha_u.float(),
            alpha_v: self.alpha_v.float(),
        }
    }

    /// Its two slots, after the kind's other words (`mf_slots` reads them in WGSL).
    pub fn gpu_words(&self, out: &mut crate::bsdfs::param::GpuWords) {
        out.slot(&self.alpha_u);
        out.slot(&self.alpha_v);
    }

    /// The distribution's code (`MF_GGX`, `MF_BECKMANN`).
    pub fn code(&self) -> u32 {
        distribution_code(self.distribution)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn d_is_normalised() {
        // Integral of D(m) cos theta_m over the hemisphere is 1 (midpoint rule in (cos, phi)).
        for dist in [Distribution::Ggx, Distribution::Beckmann] {
            for (au, av) in [(0.3, 0.3), (0.2, 0.5)] {
                let mf = Microfacet::new(dist, au, av);
                let (nt, np) = (800, 200);
                let mut sum = 0.0f64;
                for i in 0..nt {
                    let c = (i as f32 + 0.5) / nt as f32;
                    let s = (1.0 - c * c).sqrt();
                    for j in 0..np {
                        let phi = 2.0 * PI * (j as f32 + 0.5) / np as f32;
                        let m = Vec3::new(s * phi.cos(), s * phi.sin(), c);
                        sum += (mf.d(m) * c) as f64;
                    }
                }
                let integral = sum * (1.0 / nt as f64) * (2.0 * std::f64::consts::PI / np as f64);
                assert!(
                    (integral - 1.0).abs() < 2e-3,
                    "{dist:?} {au} {av}: {integral}"
                );
            }
        }
    }

    #[test]
    fn visible_normals_are_normalised() {
        // The integral of pdf_visible(wo, m) over m is 1 (Beckmann: up to the 0.35% of
        // Walter's rational fit of G1).
        for dist in [Distribution::Ggx, Distribution::Beckmann] {
            let mf = Microfacet::new(dist, 0.25, 0.6);
            for wo in [
                Vec3::new(0.3, 0.2, 0.932_737_9),
                Vec3::new(0.8, -0.5, 0.331_662_5),
            ] {
                let (nt, np) = (1000, 200);
                let mut sum = 0.0f64;
                for i in 0..nt {
                    let t = (i as f32 + 0.5) / nt as f32 * 0.5 * PI;
                    for j in 0..np {
                        let phi = 2.0 * PI * (j as f32 + 0.5) / np as f32;
                        let m = Vec3::new(t.sin() * phi.cos(), t.sin() * phi.sin(), t.cos());
                        sum += (mf.pdf_visible(wo, m) * t.sin()) as f64;
                    }
                }
                let integral = sum * (0.5 * PI / nt as f32) as f64 * (2.0 * PI / np as f32) as f64;
                assert!(
                    (integral - 1.0).abs() < 5e-3,
                    "{dist:?} wo {wo}: {integral}"
                );
            }
        }
    }

    #[test]
    fn fresnel_limits() {
        let (f, ct, eta_it, eta_ti) = fresnel_dielectric(1.0, 1.5);
        assert!((f - 0.04).abs() < 1e-6 && (ct + 1.0).abs() < 1e-6);
        assert_eq!((eta_it, eta_ti), (1.5, 1.0 / 1.5));
        // Total internal reflection from inside.
        let (f, ct, _, _) = fresnel_dielectric(-0.3, 1.5);
        assert_eq!((f, ct), (1.0, 0.0));
        // A perfect conductor (eta 0, k 1) reflects everything.
        let f = fresnel_conductor(0.4, Vec3::ZERO, Vec3::ONE);
        assert!((f - Vec3::ONE).abs().max_element() < 1e-6);
        // Fdr seen from outside and from inside a glass of index 1.5.
        assert!((fresnel_diffuse_reflectance(1.5) - 0.0918).abs() < 1e-3);
        assert!((fresnel_diffuse_reflectance(1.0 / 1.5) - 0.5968).abs() < 1e-3);
    }
}
