//! glTF 2.0's metallic-roughness material as the specification's Appendix B defines it, with
//! `KHR_materials_specular`, `KHR_materials_ior` and a thin-walled
//! `KHR_materials_transmission`:
//!
//! ```text
//! F_d(c)   = f0 + (f90 - f0) (1 - c)^5           dielectric, f0 = min(F0(ior) specular_colour, 1) specular,
//!                                                 f90 = specular
//! F_m(c)   = base + (1 - base) (1 - c)^5         metal
//! spec     = D(h) G1(wi) G1(wo) / (4 cos_i cos_o)   GGX, alpha = roughness^2
//! f        = (1 - metallic) [F_d spec + (1 - max F_d) ((1 - t) base / pi + t base spec~)]
//!          + metallic F_m spec
//! ```
//!
//! with `c = wo . h`, `t` the transmission and `spec~` the thin-walled transmission: the
//! reflection lobe mirrored through the surface (the light passes straight on, blurred by
//! the roughness). Smith's term is the separable one the specification writes.
//!
//! The photon-mapping split: the lobe part is the reflection and transmission lobes (traced);
//! the diffuse part is the base's `(1 - metallic)(1 - t) (1 - max F_d(wo . h)) base / pi`
//! with the Fresnel factor replaced by its cosine-weighted mean over `wi`,
//! `g(cos_o) = 1 - f0' - (f90 - f0') S(cos_o)` (`f0' = max f0`, S in [`schlick_mean`]),
//! so that the part factors as `diffuse_out(wo) store_weight(wi) / pi` as photon estimates
//! need. Its albedo towards every `wo` is the specification's exactly; only its spread over
//! `wi` is cosine instead of (1 - F(wo . h)) cosine, a difference below 0.3% of the value
//! unless both directions are within 25 degrees of the horizon.
//!
//! Front side: both sides of the surface behave alike (a thin sheet), so a `wo` below is
//! mirrored to the front; the `front_*` methods take `wo.z > 0`, `wi.z > 0` reflects and
//! `wi.z < 0` transmits. The parameters' textures are glTF's: the base colour's, the
//! metallic-roughness texture's blue (metalness) and green (roughness), the transmission
//! texture's red, the specular colour texture (F0's colour, `f0 = min(f0 c, f90)`) and the
//! specular texture's alpha (both F0 and F90). Twin: `metallic_roughness.wgsl`.

use crate::bsdfs::interface::{back_to_side, to_front, LobeSample, Transport};
use crate::bsdfs::interface::{BsdfKind, SurfaceClass};
use crate::bsdfs::math::{
    cosine_hemisphere_pdf, gauss_legendre, reflect, square_to_cosine_hemisphere,
};
use crate::bsdfs::microfacet::{Distribution, Microfacet};
use crate::bsdfs::param::{GpuWords, Param};
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;
use std::sync::OnceLock;

/// Intervals of the table of [`schlick_mean`] over `cos_o` in [0, 1] (one more entry).
pub const SCHLICK_MEAN_RES: usize = 32;

/// The WGSL twin.
pub const WGSL: &str = include_str!("metallic_roughness.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 7;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Shaded;

/// A metallic-roughness material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MetallicRoughness {
    /// Base colour (linear): the diffuse albedo, the metal's F0 and the transmission tint.
    pub base: Param,
    /// Metalness in [0, 1].
    pub metallic: Param,
    /// Perceptual roughness in [0, 1]; the GGX alpha is its square.
    pub roughness: Param,
    /// The dielectric's F0: `min(((ior - 1) / (ior + 1))^2 specular_colour, 1) specular`;
    /// its texture is the specular colour's.
    pub f0: Param,
    /// The dielectric's F90: the specular factor.
    pub f90: f32,
    /// `KHR_materials_transmission`'s factor in [0, 1] (thin-walled).
    pub transmission: Param,
    /// One, or the specular texture's alpha, which scales F0 and F90 at each hit.
    pub specular: Param,
}

/// `(1 - c)^5` for `c` clamped to [0, 1].
#[inline]
pub(crate) fn schlick_weight(c: f32) -> f32 {
    let m = (1.0 - c).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

#[inline]
fn flip_z(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

#[inline]
fn mean(v: Vec3) -> f32 {
    (v.x + v.y + v.z) / 3.0
}

/// The table of `S(mu)`: the cosine-weighted mean over the hemisphere of directions `wi` of
/// `(1 - wo . h)^5`, h the half vector, for `wo` at `cos theta = mu = j / RES` (Gauss-Legendre
/// quadrature in f64; S(1) ~ 5e-4, S(0) ~ 0.03).
pub fn schlick_mean_table() -> &'static [f32; SCHLICK_MEAN_RES + 1] {
    static TABLE: OnceLock<[f32; SCHLICK_MEAN_RES + 1]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let nodes = gauss_legendre(96);
        let mut t = [0.0f32; SCHLICK_MEAN_RES + 1];
        for (j, out) in t.iter_mut().enumerate() {
            let mu = j as f64 / SCHLICK_MEAN_RES as f64;
            let so = (1.0 - mu * mu).max(0.0).sqrt();
            let mut sum = 0.0;
            // cos theta_i = u in [0, 1], phi in [0, pi] (the integrand is even in phi).
            for &(xu, wu) in &nodes {
                let u = 0.5 * (xu + 1.0);
                let su = (1.0 - u * u).max(0.0).sqrt();
                for &(xp, wp) in &nodes {
                    let phi = 0.5 * (xp + 1.0) * std::f64::consts::PI;
                    let dot = u * mu + su * so * phi.cos();
                    let vh = ((1.0 + dot) * 0.5).max(0.0).sqrt();
                    sum += wu * wp * (1.0 - vh).powi(5) * u;
                }
            }
            // Jacobians: du = dx / 2, dphi = pi dx / 2; both halves of phi; 1 / pi.
            *out = (sum * 0.25 * std::f64::consts::PI * 2.0 / std::f64::consts::PI) as f32;
        }
        t
    })
}

/// The WGSL constants the twin reads: S(mu)'s table as Rust computed it (Debug prints the
/// shortest decimal that reads back to the same f32).
pub fn wgsl_consts() -> String {
    let table: Vec<String> = schlick_mean_table()
        .iter()
        .map(|v| format!("{v:?}f"))
        .collect();
    format!(
        "const GLTF_MEAN_RES: u32 = {SCHLICK_MEAN_RES}u;\nconst BSDF_GLTF_MEAN = array<f32, {}>({});\n",
        SCHLICK_MEAN_RES + 1,
        table.join(", ")
    )
}

/// `S(cos_o)`: [`schlick_mean_table`] looked up linearly (twin: `gltf_schlick_mean`).
pub fn schlick_mean(cos_o: f32) -> f32 {
    let t = schlick_mean_table();
    let x = cos_o.clamp(0.0, 1.0) * SCHLICK_MEAN_RES as f32;
    let i = (x as usize).min(SCHLICK_MEAN_RES - 1);
    let f = x - i as f32;
    t[i] + (t[i + 1] - t[i]) * f
}

impl MetallicRoughness {
    /// An untextured material.
    pub fn new(
        base: Vec3,
        metallic: f32,
        roughness: f32,
        f0: Vec3,
        f90: f32,
        transmission: f32,
    ) -> Self {
        Self {
            base: Param::rgb(base),
            metallic: Param::constant(metallic),
            roughness: Param::constant(roughness),
            f0: Param::rgb(f0),
            f90,
            transmission: Param::constant(transmission),
            specular: Param::constant(1.0),
        }
    }

    /// The GGX distribution of `alpha = roughness^2` (at least 1e-4, as Mitsuba clamps).
    pub fn microfacet(&self) -> Microfacet {
        Microfacet::isotropic(
            Distribution::Ggx,
            self.roughness.float() * self.roughness.float(),
        )
    }

    /// Weight of the base's diffuse reflection: `(1 - metallic)(1 - transmission)`.
    fn diffuse_weight(&self) -> f32 {
        (1.0 - self.metallic.float()) * (1.0 - self.transmission.float())
    }

    /// The dielectric's largest Fresnel channel at `c`: `max f0 + (f90 - max f0)(1 - c)^5`.
    fn dielectric_max(&self, c: f32) -> f32 {
        let f0 = self.f0.get().max_element();
        f0 + (self.f90 - f0) * schlick_weight(c)
    }

    /// The reflection lobe's tint at `c = wo . h`: `(1 - metallic) F_d + metallic F_m`.
    fn reflect_tint(&self, c: f32) -> Vec3 {
        let w = schlick_weight(c);
        let (f0, base, metallic) = (self.f0.get(), self.base.get(), self.metallic.float());
        let fd = f0 + (Vec3::splat(self.f90) - f0) * w;
        let fm = base + (Vec3::ONE - base) * w;
        fd * (1.0 - metallic) + fm * metallic
    }

    /// The transmission lobe's tint at `c = wo . h`: `(1 - metallic) t (1 - max F_d) base`.
    fn transmit_tint(&self, c: f32) -> Vec3 {
        let w = (1.0 - self.metallic.float())
            * self.transmission.float()
            * (1.0 - self.dielectric_max(c));
        self.base.get() * w.max(0.0)
    }

    /// The probability of following reflection rather than transmission at `c = wo . m`
    /// (by the tints' means; 1 without transmission).
    pub fn reflect_probability(&self, c: f32) -> f32 {
        if self.transmission.float() <= 0.0 || self.metallic.float() >= 1.0 {
            return 1.0;
        }
        let r = mean(self.reflect_tint(c));
        let t = mean(self.transmit_tint(c));
        if r + t > 0.0 {
            r / (r + t)
        } else {
            1.0
        }
    }

    /// The diffuse part's factor towards `wo` (`wo.z > 0`): `(1 - metallic)(1 - t) base
    /// g(cos_o)`, see the module documentation.
    pub fn front_diffuse_out(&self, cos_o: f32) -> Vec3 {
        let f0 = self.f0.get().max_element();
        let g = 1.0 - f0 - (self.f90 - f0) * schlick_mean(cos_o);
        self.base.get() * (self.diffuse_weight() * g.max(0.0))
    }

    /// Whether the base reflects diffusely anywhere (the material stores photons).
    pub fn base_is_diffuse(&self) -> bool {
        self.diffuse_weight() > 0.0
    }

    /// The half vector of `wi`, `wo` (transmission: `wi` mirrored to the front first), or
    /// `None` when it is degenerate or either direction sees its back.
    fn half(wi: Vec3, wo: Vec3) -> Option<Vec3> {
        let wr = if wi.z < 0.0 { flip_z(wi) } else { wi };
        let h = wr + wo;
        (wr.z > 0.0 && wo.z > 0.0 && h.length_squared() > 0.0).then(|| h.normalize())
    }

    /// The lobes' value f(wi, wo) without the cosine (`wo.z > 0`).
    pub fn front_eval_lobe(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        let Some(h) = Self::half(wi, wo) else {
            return Vec3::ZERO;
        };
        let wr = if wi.z < 0.0 { flip_z(wi) } else { wi };
        let mf = self.microfacet();
        let spec = mf.d(h) * mf.g(wr, wo, h) / (4.0 * wr.z * wo.z);
        let c = wo.dot(h);
        let tint = if wi.z < 0.0 {
            self.transmit_tint(c)
        } else {
            self.reflect_tint(c)
        };
        tint * spec
    }

    /// Density of [`front_sample_lobe`](Self::front_sample_lobe) (`wo.z > 0`): the visible normal's
    /// density over `4 wo . h`, times the chosen branch's probability.
    pub fn front_pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        let Some(h) = Self::half(wi, wo) else {
            return 0.0;
        };
        let c = wo.dot(h);
        if c <= 0.0 {
            return 0.0;
        }
        let p = self.reflect_probability(c);
        let p = if wi.z < 0.0 { 1.0 - p } else { p };
        p * self.microfacet().pdf_visible(wo, h) / (4.0 * c)
    }

    /// A visible normal from `u[1], u[2]`; `u[0]` picks reflection or transmission (the
    /// mirror direction flipped through the surface). Weight `tint G1(wi) / p`.
    pub fn front_sample_lobe(&self, wo: Vec3, u: [f32; 3]) -> Option<LobeSample> {
        let mf = self.microfacet();
        let (m, pdf_m) = mf.sample_visible(wo, Vec2::new(u[1], u[2]));
        let wr = reflect(wo, m);
        let c = wo.dot(m);
        if pdf_m <= 0.0 || wr.z <= 0.0 || c <= 0.0 {
            return None;
        }
        let p = self.reflect_probability(c);
        let (wi, tint, p) = if u[0] < p {
            (wr, self.reflect_tint(c), p)
        } else {
            (flip_z(wr), self.transmit_tint(c), 1.0 - p)
        };
        let pdf = p * pdf_m / (4.0 * c);
        let weight = tint * (mf.smith_g1(wr, m) / p);
        (pdf > 0.0 && weight.max_element() > 0.0).then_some(LobeSample {
            wi,
            weight,
            pdf,
            delta: false,
        })
    }

    /// The probability with which a photon (or [`front_sample`](Self::front_sample)) follows the lobes
    /// rather than the diffuse base: the lobes' mean albedo estimate at normal incidence of
    /// the view against the base's, kept inside [0.05, 0.95] when both exist.
    pub fn front_lobe_probability(&self, cos_o: f32) -> f32 {
        let d = mean(self.front_diffuse_out(cos_o));
        if d <= 0.0 {
            return 1.0;
        }
        let l = mean(self.reflect_tint(cos_o) + self.transmit_tint(cos_o));
        (l / (l + d)).clamp(0.05, 0.95)
    }

    /// Samples the whole BSDF: the lobes with [`front_lobe_probability`](Self::front_lobe_probability)
    /// (`u[0]` rescaled for the lobe's own choice), else a cosine-weighted diffuse direction.
    pub fn front_sample(&self, wo: Vec3, u: [f32; 3]) -> Option<LobeSample> {
        let p = self.front_lobe_probability(wo.z);
        if u[0] < p {
            let s = self.front_sample_lobe(wo, [u[0] / p, u[1], u[2]])?;
            let pdf = self.front_pdf(s.wi, wo);
            let f = self.front_eval_lobe(s.wi, wo) + self.front_diffuse_value(s.wi, wo);
            return (pdf > 0.0).then(|| LobeSample {
                weight: f * s.wi.z.abs() / pdf,
                pdf,
                ..s
            });
        }
        let wi = square_to_cosine_hemisphere(Vec2::new(u[1], u[2]));
        let pdf = self.front_pdf(wi, wo);
        let f = self.front_eval_lobe(wi, wo) + self.front_diffuse_value(wi, wo);
        (pdf > 0.0 && wi.z > 0.0).then(|| LobeSample {
            wi,
            weight: f * wi.z / pdf,
            pdf,
            delta: false,
        })
    }

    /// Density of [`front_sample`](Self::front_sample).
    pub fn front_pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        let p = self.front_lobe_probability(wo.z);
        p * self.front_pdf_lobe(wi, wo) + (1.0 - p) * cosine_hemisphere_pdf(wi)
    }

    /// The diffuse part's value (zero across the surface).
    fn front_diffuse_value(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        if wi.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.front_diffuse_out(wo.z) * FRAC_1_PI
    }
}

impl BsdfKind for MetallicRoughness {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        let mut f0 = self.f0.eval(t, uv);
        if self.f0.is_textured() {
            f0 = f0.min(Vec3::splat(self.f90));
        }
        let mut f90 = self.f90;
        if self.specular.is_textured() {
            let a = self.specular.eval(t, uv).x;
            f0 *= a;
            f90 *= a;
        }
        Self {
            base: self.base.resolved(t, uv),
            metallic: self.metallic.resolved(t, uv),
            roughness: self.roughness.resolved(t, uv),
            f0: Param::rgb(f0),
            f90,
            transmission: self.transmission.resolved(t, uv),
            specular: Param::constant(1.0),
        }
    }
    fn base_colour_mut(&mut self) -> Option<&mut Param> {
        Some(&mut self.base)
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        out.slot(&self.base);
        out.slot(&self.f0);
        out.slot(&self.metallic);
        out.slot(&self.roughness);
        out.slot(&self.transmission);
        out.slot(&self.specular);
        out.floats([self.f90, 0.0, 0.0, 0.0]);
    }
    fn diffuse_out(&self, wo: Vec3) -> Vec3 {
        if wo.z != 0.0 {
            self.front_diffuse_out(wo.z.abs())
        } else {
            Vec3::ZERO
        }
    }
    fn store_weight(&self, wi: Vec3) -> f32 {
        if wi.z != 0.0 && self.base_is_diffuse() {
            1.0
        } else {
            0.0
        }
    }
    fn eval_lobe(&self, wi: Vec3, wo: Vec3, _: Transport) -> Vec3 {
        to_front(wi, wo).map_or(Vec3::ZERO, |(wi, wo, _)| self.front_eval_lobe(wi, wo))
    }
    fn pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        to_front(wi, wo).map_or(0.0, |(wi, wo, _)| self.front_pdf_lobe(wi, wo))
    }
    fn sample_lobe(&self, wo: Vec3, u: [f32; 3], _: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
        back_to_side(self.front_sample_lobe(wo, u), flipped)
    }
    fn has_diffuse(&self) -> bool {
        self.base_is_diffuse()
    }
    fn lobe_probability(&self, wo: Vec3) -> f32 {
        self.front_lobe_probability(wo.z.abs())
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        to_front(wi, wo).map_or(0.0, |(wi, wo, _)| self.front_pdf(wi, wo))
    }
    fn sample(&self, wo: Vec3, u: [f32; 3], _: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = to_front(Vec3::Z, wo)?;
        back_to_side(self.front_sample(wo, u), flipped)
    }
    /// Asked of the material's (unresolved) kind: a textured metalness or transmission may
    /// leave some base diffuse anywhere on it.
    fn stores_photons(&self) -> bool {
        self.metallic.is_textured() || self.transmission.is_textured() || self.base_is_diffuse()
    }
}
