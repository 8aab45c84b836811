//! Reflection, Snell refraction and the Fresnel reflectance of a dielectric interface (exact
//! or Schlick's, [`FresnelMode`]) in world space: what the classic mirror and glass kinds, and
//! the camera paths' glass splits, use. Twin: `fresnel.wgsl`.

use crate::settings::FresnelMode;
use glam::Vec3;

/// The two ways a ray leaves a dielectric interface, with the Fresnel weight of reflection.
#[derive(Clone, Copy, Debug)]
pub struct Dielectric {
    /// The mirror direction.
    pub reflected: Vec3,
    /// `None` on total internal reflection.
    pub refracted: Option<Vec3>,
    /// Fresnel reflectance (1 on total internal reflection).
    pub reflectance: f32,
    /// `n_i / n_t` across the interface along the refracted ray (1 for a thin sheet).
    pub eta: f32,
}

impl Dielectric {
    /// Factor on the radiance a camera path carries back along the refracted ray,
    /// `(n_i / n_t)^2` (Mitsuba's radiance-mode transmission): radiance over `n^2` is what
    /// is conserved, so light inside glass, estimated from photons there, looks dimmer from
    /// outside; a path that enters and leaves the glass gets `eta^2` and `1 / eta^2`.
    #[inline]
    pub fn refracted_radiance(&self) -> f32 {
        self.eta * self.eta
    }
}

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
        eta: n_i / n_t,
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
