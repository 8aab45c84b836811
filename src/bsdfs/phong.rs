//! A Lambertian base `kd` plus a normalised Phong lobe `ks (n + 2) / (2 pi) cos^n` about the
//! mirror direction (TOML's `glossy`), with the classic photon roulette it shares with the
//! Lambertian kind ([`classic_bounce`]): the surface's behaviour is world-space, about the
//! caller's shading normal. Twin: `phong.wgsl`.

use crate::bsdfs::fresnel::reflect;
use crate::bsdfs::interface::{back_to_side, to_front, LobeSample, Transport};
use crate::bsdfs::interface::{Bounce, BsdfKind, Frame, LobeRay, SurfaceClass};
use crate::bsdfs::math::{cosine_hemisphere_pdf, reflect_z, square_to_cosine_hemisphere};
use crate::bsdfs::param::{GpuWords, Param};
use crate::bvh::hit::Hit;
use crate::error::Result;
use crate::math::geometry::Facing;
use crate::math::rng::Rng;
use crate::math::sampling::{cosine_hemisphere, phong_lobe};
use crate::scene::locate::{check_color, Locate, Part};
use crate::settings::FresnelMode;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// The WGSL twin.
pub const WGSL: &str = include_str!("phong.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 3;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Shaded;

/// Lambertian `kd` plus a Phong lobe `ks` of exponent `exponent`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Phong {
    /// Diffuse reflectance.
    pub kd: Param,
    /// The lobe's reflectance.
    pub ks: Param,
    /// The lobe's exponent.
    pub exponent: f32,
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

/// The lobe's density `(n + 1) / (2 pi) cos^n(alpha)` of drawing `wi` seen from `wo`.
#[inline]
fn phong_pdf(wi: Vec3, wo: Vec3, n: Vec3, exponent: f32) -> f32 {
    let cos_a = reflect(-wo, n).dot(wi);
    if cos_a <= 0.0 {
        return 0.0;
    }
    (exponent + 1.0) / (2.0 * PI) * cos_a.powf(exponent)
}

/// Russian roulette for a photon travelling along `d` that hits a surface of diffuse `kd` and
/// lobe `ks` (exponent `exponent`) at `hit`: diffuse reflection, the lobe or absorption with
/// the coefficients' probabilities, and the power weight that keeps the estimate unbiased.
/// Directions are drawn about the shading normal; one below the geometric surface absorbs the
/// photon (no light leaks through the terminator; no adjoint shading-normal correction, see
/// scenes/README.md). Reads `u[0]` (the choice) and `u[1], u[2]` (the direction).
pub fn classic_bounce(
    kd: Vec3,
    ks: Vec3,
    exponent: f32,
    d: Vec3,
    hit: &Hit,
    u: [f32; 3],
) -> Bounce {
    let f = Facing::new(hit.normal, hit.shading, d.dot(hit.normal) < 0.0);
    let nf = f.ns;
    // Choice probabilities: the larger of each coefficient's channels, scaled so that
    // p_d + p_s <= max(kd + ks) <= 1.
    let total = (kd + ks).max_element();
    let (sd, ss) = (kd.element_sum(), ks.element_sum());
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
            weight: kd / pd,
        }
    } else if u[0] < pd + ps {
        let axis = reflect(d, nf);
        let dir = phong_lobe(axis, exponent, u[1], u[2]);
        let cos = dir.dot(nf);
        if cos <= 0.0 {
            return Bounce::Absorb;
        }
        // f cos / pdf = ks (n+2)/(n+1) cos(theta).
        let w = (exponent + 2.0) / (exponent + 1.0) * cos;
        if f.reflection_leaks(dir) {
            return Bounce::Absorb;
        }
        Bounce::Specular {
            dir,
            weight: ks * (w / ps),
            delta: false,
        }
    } else {
        Bounce::Absorb
    }
}

impl Phong {
    /// Lambertian `kd` plus a lobe `ks` of exponent `exponent`, untextured.
    pub fn new(kd: Vec3, ks: Vec3, exponent: f32) -> Self {
        Self {
            kd: Param::rgb(kd),
            ks: Param::rgb(ks),
            exponent,
        }
    }

    /// The probability of sampling the lobe rather than the base (local `sample`).
    fn lobe_choice(&self) -> f32 {
        let (sd, ss) = (self.kd.get().element_sum(), self.ks.get().element_sum());
        if sd + ss > 0.0 {
            ss / (sd + ss)
        } else {
            0.0
        }
    }
}

impl BsdfKind for Phong {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        Self {
            kd: self.kd.resolved(t, uv),
            ks: self.ks.resolved(t, uv),
            ..*self
        }
    }
    fn base_colour_mut(&mut self) -> Option<&mut Param> {
        Some(&mut self.kd)
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        out.slot(&self.kd);
        out.slot(&self.ks);
        out.floats([self.exponent, 0.0, 0.0, 0.0]);
    }
    fn check(&self, at: &dyn Locate) -> Result<()> {
        let param = Part::Parameter;
        let (kd, ks) = (self.kd.get(), self.ks.get());
        check_color(kd, Some(1.0), param("kd"), at)?;
        check_color(ks, Some(1.0), param("ks"), at)?;
        if (kd + ks).max_element() > 1.0 {
            let message = "kd + ks must be at most 1 in every channel (energy conservation)";
            return Err(at.error(param("ks"), message.into()));
        }
        match self.exponent {
            e if e.is_finite() && e >= 0.0 => Ok(()),
            _ => Err(at.error(param("exponent"), "must be >= 0 and finite".into())),
        }
    }

    // The local frame (two-sided, as the other reflective kinds).
    fn diffuse_out(&self, wo: Vec3) -> Vec3 {
        if wo.z != 0.0 {
            self.kd.get()
        } else {
            Vec3::ZERO
        }
    }
    fn store_weight(&self, wi: Vec3) -> f32 {
        if wi.z != 0.0 {
            1.0
        } else {
            0.0
        }
    }
    fn eval_lobe(&self, wi: Vec3, wo: Vec3, _: Transport) -> Vec3 {
        to_front(wi, wo).map_or(Vec3::ZERO, |(wi, wo, _)| {
            self.ks.get() * phong_lobe_value(wi, wo, Vec3::Z, self.exponent)
        })
    }
    fn pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        to_front(wi, wo).map_or(0.0, |(wi, wo, _)| phong_pdf(wi, wo, Vec3::Z, self.exponent))
    }
    fn sample_lobe(&self, wo: Vec3, u: [f32; 3], _: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
        let wi = phong_lobe(reflect_z(wo), self.exponent, u[1], u[2]);
        let pdf = phong_pdf(wi, wo, Vec3::Z, self.exponent);
        if wi.z <= 0.0 || pdf <= 0.0 {
            return None;
        }
        let weight = self.ks.get() * ((self.exponent + 2.0) / (self.exponent + 1.0) * wi.z);
        back_to_side(
            Some(LobeSample {
                wi,
                weight,
                pdf,
                delta: false,
            }),
            flipped,
        )
    }
    fn has_diffuse(&self) -> bool {
        true
    }
    fn has_lobe(&self) -> bool {
        self.ks.get().max_element() > 0.0
    }
    fn lobe_probability(&self, _: Vec3) -> f32 {
        self.lobe_choice()
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        let Some((wi, wo, _)) = to_front(wi, wo) else {
            return 0.0;
        };
        if wi.z <= 0.0 {
            return 0.0;
        }
        let p = self.lobe_choice();
        p * phong_pdf(wi, wo, Vec3::Z, self.exponent) + (1.0 - p) * cosine_hemisphere_pdf(wi)
    }
    fn sample(&self, wo: Vec3, u: [f32; 3], t: Transport) -> Option<LobeSample> {
        let (_, wf, flipped) = to_front(Vec3::Z, wo)?;
        let wi = if u[0] < self.lobe_choice() {
            phong_lobe(reflect_z(wf), self.exponent, u[1], u[2])
        } else {
            square_to_cosine_hemisphere(Vec2::new(u[1], u[2]))
        };
        let pdf = self.pdf(wi, wf);
        if pdf <= 0.0 {
            return None;
        }
        let weight = self.eval(wi, wf, t) * wi.z / pdf;
        back_to_side(
            Some(LobeSample {
                wi,
                weight,
                pdf,
                delta: false,
            }),
            flipped,
        )
    }

    // The surface, in world space about the caller's shading normal.
    fn lobe_takes_point_lights(&self) -> bool {
        true
    }
    fn surface_diffuse_albedo(&self, _: Frame, _: Vec3) -> Vec3 {
        self.kd.get()
    }
    fn surface_store_weight(&self, _: Frame, _: Vec3) -> Option<f32> {
        None
    }
    fn surface_eval_diffuse(&self, _: Frame, _: Vec3, _: Vec3) -> Vec3 {
        self.kd.get() / PI
    }
    fn surface_eval_lobe(&self, _: Frame, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
        self.ks.get() * phong_lobe_value(wi, wo, ns, self.exponent)
    }
    fn surface_pdf_lobe(&self, _: Frame, wi: Vec3, wo: Vec3, ns: Vec3) -> f32 {
        phong_pdf(wi, wo, ns, self.exponent)
    }
    fn surface_sample_lobe(&self, _: Frame, d: Vec3, f: &Facing, rng: &mut Rng) -> Option<LobeRay> {
        let (u1, u2) = rng.next2();
        let dir = phong_lobe(reflect(d, f.ns), self.exponent, u1, u2);
        let cos = dir.dot(f.ns);
        (cos > 0.0 && !f.reflection_leaks(dir)).then(|| LobeRay {
            dir,
            weight: self.ks.get() * ((self.exponent + 2.0) / (self.exponent + 1.0) * cos),
            pdf: phong_pdf(dir, -d, f.ns, self.exponent),
        })
    }
    fn photon_bounce(&self, _: Frame, d: Vec3, hit: &Hit, _: FresnelMode, u: [f32; 3]) -> Bounce {
        classic_bounce(self.kd.get(), self.ks.get(), self.exponent, d, hit, u)
    }
}
