//! Scattering: Fresnel, Snell, and the per-material sampling used by photons and camera rays.
//!
//! Twin: `src/bsdfs/classic.wgsl`.

use crate::math::geometry::Facing;
use crate::math::sampling::{cosine_hemisphere, phong_lobe};
use crate::scene::{Material, MaterialKind};
use crate::settings::FresnelMode;
use glam::Vec3;
use std::f32::consts::PI;

/// Mirror reflection of `d` (pointing towards the surface) about unit `n`.
#[inline]
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Snell refraction of unit `d` through unit `n` (facing against `d`) with `eta` = n_i / n_t.
/// `None` on total internal reflection.
#[inline]
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = (-d.dot(n)).clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((eta * d + (eta * cos_i - cos_t) * n).normalize())
}

/// Exact unpolarised Fresnel reflectance for light arriving at cosine `cos_i` (>= 0) from a
/// medium of index `n_i` onto one of index `n_t`. 1 on total internal reflection.
#[inline]
pub fn fresnel_exact(cos_i: f32, n_i: f32, n_t: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let eta = n_i / n_t;
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (n_i * cos_i - n_t * cos_t) / (n_i * cos_i + n_t * cos_t);
    let rp = (n_t * cos_i - n_i * cos_t) / (n_t * cos_i + n_i * cos_t);
    (0.5 * (rs * rs + rp * rp)).clamp(0.0, 1.0)
}

/// Schlick's approximation, using the cosine on the optically thinner side so that total
/// internal reflection is exact.
#[inline]
pub fn fresnel_schlick(cos_i: f32, n_i: f32, n_t: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let r0 = ((n_i - n_t) / (n_i + n_t)).powi(2);
    let c = if n_i > n_t {
        let eta = n_i / n_t;
        let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
        if sin2_t >= 1.0 {
            return 1.0;
        }
        (1.0 - sin2_t).sqrt()
    } else {
        cos_i
    };
    r0 + (1.0 - r0) * (1.0 - c).powi(5)
}

/// Fresnel reflectance by the chosen formula.
#[inline]
pub fn fresnel(mode: FresnelMode, cos_i: f32, n_i: f32, n_t: f32) -> f32 {
    match mode {
        FresnelMode::Exact => fresnel_exact(cos_i, n_i, n_t),
        FresnelMode::Schlick => fresnel_schlick(cos_i, n_i, n_t),
    }
}

/// The two ways a ray leaves a dielectric interface, with the Fresnel weight of reflection.
#[derive(Clone, Copy, Debug)]
pub struct Dielectric {
    /// The mirror direction.
    pub reflected: Vec3,
    /// `None` on total internal reflection.
    pub refracted: Option<Vec3>,
    /// Fresnel reflectance (1 on total internal reflection).
    pub reflectance: f32,
}

/// Splits unit `d` arriving at a glass surface with front (outward) normal `n`.
pub fn dielectric(d: Vec3, n: Vec3, ior: f32, mode: FresnelMode) -> Dielectric {
    dielectric_shading(d, n, n, ior, mode)
}

/// [`dielectric`] on a smooth surface: the geometric front normal `ng` says whether the ray
/// enters or leaves (which index is inside), the shading normal `ns` (on the side of `ng`)
/// bends and weighs the directions. The caller drops a direction that ends on the wrong side
/// of the geometric surface ([`Facing`]).
pub fn dielectric_shading(d: Vec3, ng: Vec3, ns: Vec3, ior: f32, mode: FresnelMode) -> Dielectric {
    let entering = d.dot(ng) < 0.0;
    let (nn, n_i, n_t) = if entering {
        (ns, 1.0, ior)
    } else {
        (-ns, ior, 1.0)
    };
    let cos_i = -d.dot(nn);
    let reflected = reflect(d, nn);
    let refracted = refract(d, nn, n_i / n_t);
    let reflectance = if refracted.is_none() {
        1.0
    } else {
        fresnel(mode, cos_i, n_i, n_t)
    };
    Dielectric {
        reflected,
        refracted,
        reflectance,
    }
}

/// Normalised Phong lobe value `(n + 2) / (2 pi) cos^n(alpha)` for unit `wi`, `wo` (both
/// pointing away from the surface) about unit normal `n`.
#[inline]
pub fn phong_lobe_value(wi: Vec3, wo: Vec3, n: Vec3, exponent: f32) -> f32 {
    let cos_a = reflect(-wo, n).dot(wi);
    if cos_a <= 0.0 {
        return 0.0;
    }
    (exponent + 2.0) / (2.0 * PI) * cos_a.powf(exponent)
}

/// One camera-path ray drawn from a glossy material's lobe about the mirror direction of `d`
/// (pointing towards the surface), with the hit's normals `f` facing `-d`, from the uniforms
/// (u1, u2): the direction and its weight `ks (n + 2) / (n + 1) cos` (the lobe's pdf cancels
/// the rest of BRDF x cosine), or `None` below the shading or the geometric surface.
/// Twin: `lobe_ray` in `src/integrators/gpu/gather.wgsl`.
#[inline]
pub fn lobe_ray(m: &Material, d: Vec3, f: &Facing, u1: f32, u2: f32) -> Option<(Vec3, Vec3)> {
    let dir = phong_lobe(reflect(d, f.ns), m.exponent, u1, u2);
    let cos = dir.dot(f.ns);
    (cos > 0.0 && !f.reflection_leaks(dir))
        .then(|| (dir, m.ks * ((m.exponent + 2.0) / (m.exponent + 1.0) * cos)))
}

/// The non-delta BRDF `f(wi, wo)` of a diffuse or glossy material, both directions on the
/// side of unit normal `n`.
pub fn brdf(m: &Material, wi: Vec3, wo: Vec3, n: Vec3) -> Vec3 {
    match m.kind {
        MaterialKind::Diffuse => m.kd / PI,
        MaterialKind::Glossy => m.kd / PI + m.ks * phong_lobe_value(wi, wo, n, m.exponent),
        _ => Vec3::ZERO,
    }
}

/// The outcome of Russian roulette at a photon hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Bounce {
    /// Photon continues in `dir` with its power multiplied by `weight`.
    Diffuse {
        /// The new direction.
        dir: Vec3,
        /// Factor on the photon's power.
        weight: Vec3,
    },
    /// Continues by a specular event (mirror, glass, glossy lobe); `delta` for mirror/glass.
    Specular {
        /// The new direction.
        dir: Vec3,
        /// Factor on the photon's power.
        weight: Vec3,
        /// A mirror or glass event (a caustic path may continue).
        delta: bool,
    },
    /// The photon ends here.
    Absorb,
}

/// Russian roulette for a photon travelling in unit `d` that hits a surface with front normal
/// `n`: chooses diffuse reflection, specular reflection (or refraction) or absorption with the
/// material's coefficients, and returns the power weight that keeps the estimate unbiased.
/// Consumes the uniform numbers `u` (three of them).
pub fn photon_bounce(
    m: &Material,
    d: Vec3,
    n: Vec3,
    fresnel_mode: FresnelMode,
    u: [f32; 3],
) -> Bounce {
    photon_bounce_shading(m, d, n, n, fresnel_mode, u)
}

/// [`photon_bounce`] on a surface of geometric front normal `ng` and shading normal `ns` (on
/// the side of `ng`): directions are sampled and weighed about `ns`; one that ends on the
/// wrong side of the geometric surface absorbs the photon (no light leaks through the
/// terminator). No adjoint shading-normal correction (see scenes/README.md).
pub fn photon_bounce_shading(
    m: &Material,
    d: Vec3,
    ng: Vec3,
    ns: Vec3,
    fresnel_mode: FresnelMode,
    u: [f32; 3],
) -> Bounce {
    let f = Facing::new(ng, ns, d.dot(ng) < 0.0);
    let nf = f.ns;
    let reflected = |dir: Vec3, weight: Vec3, delta: bool| {
        if f.reflection_leaks(dir) {
            Bounce::Absorb
        } else {
            Bounce::Specular { dir, weight, delta }
        }
    };
    match m.kind {
        // crate::bsdfs's kinds bounce in `shading::SurfaceBsdf::photon_bounce`.
        MaterialKind::Black
        | MaterialKind::Null
        | MaterialKind::Conductor
        | MaterialKind::RoughConductor
        | MaterialKind::RoughDielectric
        | MaterialKind::ThinDielectric
        | MaterialKind::Plastic
        | MaterialKind::RoughPlastic
        | MaterialKind::MetallicRoughness => Bounce::Absorb,
        MaterialKind::Diffuse | MaterialKind::Glossy => {
            // Choice probabilities: the larger of each coefficient's channels, scaled so that
            // p_d + p_s <= max(kd + ks) <= 1.
            let total = (m.kd + m.ks).max_element();
            let (sd, ss) = (m.kd.element_sum(), m.ks.element_sum());
            if total <= 0.0 || sd + ss <= 0.0 {
                return Bounce::Absorb;
            }
            let pd = total * sd / (sd + ss);
            let ps = total * ss / (sd + ss);
            if u[0] < pd {
                let dir = cosine_hemisphere(nf, u[1], u[2]);
                if f.reflection_leaks(dir) {
                    return Bounce::Absorb;
                }
                Bounce::Diffuse {
                    dir,
                    weight: m.kd / pd,
                }
            } else if u[0] < pd + ps {
                let axis = reflect(d, nf);
                let dir = phong_lobe(axis, m.exponent, u[1], u[2]);
                let cos = dir.dot(nf);
                if cos <= 0.0 {
                    return Bounce::Absorb;
                }
                // f cos / pdf = ks (n+2)/(n+1) cos(theta).
                let w = (m.exponent + 2.0) / (m.exponent + 1.0) * cos;
                reflected(dir, m.ks * (w / ps), false)
            } else {
                Bounce::Absorb
            }
        }
        MaterialKind::Mirror => {
            let p = m.ks.max_element();
            if u[0] < p {
                reflected(reflect(d, nf), m.ks / p, true)
            } else {
                Bounce::Absorb
            }
        }
        MaterialKind::Glass => {
            let g = dielectric_shading(d, ng, ns, m.ior, fresnel_mode);
            match g.refracted {
                Some(t) if u[0] >= g.reflectance => {
                    if f.refraction_leaks(t) {
                        return Bounce::Absorb;
                    }
                    Bounce::Specular {
                        dir: t,
                        weight: Vec3::ONE,
                        delta: true,
                    }
                }
                _ => reflected(g.reflected, Vec3::ONE, true),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_normal_incidence_matches_closed_form() {
        // ((n1 - n2) / (n1 + n2))^2 = 0.04 for glass of 1.5, from either side.
        assert!((fresnel_exact(1.0, 1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel_exact(1.0, 1.5, 1.0) - 0.04).abs() < 1e-6);
        assert!((fresnel_schlick(1.0, 1.0, 1.5) - 0.04).abs() < 1e-6);
    }
}
