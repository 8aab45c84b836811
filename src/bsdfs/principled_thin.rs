//! Mitsuba 3.9's `principledthin` BSDF (Disney's thin-surface principled model as Mitsuba
//! writes it): a two-dimensional sheet, the same seen from either side (a viewer behind it sees
//! both directions mirrored through the origin, as Mitsuba's `mulsign`). With `st` the
//! specular transmission weight and `dt = diff_trans / 2` (Mitsuba's range [0, 2] made [0, 1]):
//!
//! ```text
//! f = st F_thin D G / (4 cos_i cos_o)                          glossy reflection (GGX)
//!   + st base (1 - F) D_s G_s / (4 cos_i |cos_o|)              glossy transmission, unbent
//!   + (1 - st)(1 - dt) base/pi lerp(f_diff + f_retro, f_ss, flatness)   diffuse reflection
//!   + (1 - st)(1 - dt) sheen (1 - cos_d)^5 c_sheen            sheen
//!   + (1 - st) dt base / pi                                   diffuse transmission
//! ```
//!
//! `F` the dielectric Fresnel of `eta` at the half vector, `F_thin = lerp(F, Schlick of the
//! tinted R0, spec_tint)`; the transmission is a reflection off the half vector of `wi`
//! mirrored to the viewer's side, turned to the other side, with GGX roughness scaled by
//! `0.65 eta - 0.35` (Burley 2015). Without `spec_trans` there is no specular lobe at all
//! (Mitsuba's quirk, kept). The sampler is Mitsuba's: `u[0]` picks the glossy reflection
//! (`st / 2`), the glossy transmission (`st / 2`), cosine reflection (`(1 - st)(1 - dt)`) or
//! cosine transmission (`(1 - st) dt`), `u[1], u[2]` the direction. A thin sheet does not
//! refract: radiance and importance are transported alike and the medium is the shape's.
//!
//! The photon-mapping split: the diffuse part is the separable `(1 - flatness)(1 - st)(1 - dt)
//! base f_diff / pi` on either side, exact; the lobe part (traced) is everything else, the
//! diffuse transmission included. [`PrincipledThin::sample_lobe`](BsdfKind::sample_lobe) is
//! Mitsuba's strategy with the cosine reflection weighted for the lobe part's remainder.
//! Twin: `principled_thin.wgsl`.

use crate::bsdfs::interface::{BsdfKind, LobeSample, SurfaceClass, Transport};
use crate::bsdfs::math::{cosine_hemisphere_pdf, mulsign, reflect, square_to_cosine_hemisphere};
use crate::bsdfs::metallic_roughness::schlick_weight;
use crate::bsdfs::microfacet::{fresnel_dielectric, Distribution, Microfacet};
use crate::bsdfs::param::{GpuWords, Param};
use crate::bsdfs::principled::Principled;
use crate::bsdfs::principled_terms::{calc_schlick, compatible, disney_diffuse, mean, tint};
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// The WGSL twin.
pub const WGSL: &str = include_str!("principled_thin.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 10;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Shaded;

/// Mitsuba's `principledthin`: every parameter a [`Param`] (a float one reads `value.x`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrincipledThin {
    /// Base colour (linear RGB).
    pub base_color: Param,
    /// Roughness of the glossy lobes; GGX alpha `roughness^2` (at least 0.001).
    pub roughness: Param,
    /// Anisotropy in [0, 1]: alphas `r^2 / a`, `r^2 a` with `a = sqrt(1 - 0.9 anisotropic)`.
    pub anisotropic: Param,
    /// Weight of the specular (glossy) reflection and transmission, in [0, 1].
    pub spec_trans: Param,
    /// Diffuse transmission in [0, 2], as Mitsuba takes it (half of it is the weight).
    pub diff_trans: Param,
    /// Relative index of refraction of the sheet (Mitsuba's `eta`, default 1.5).
    pub eta: Param,
    /// Weight of the sheen lobe.
    pub sheen: Param,
    /// Tint of the sheen towards the base colour, in [0, 1].
    pub sheen_tint: Param,
    /// Blend of the diffuse response towards the fake subsurface term, in [0, 1].
    pub flatness: Param,
    /// Tint of the glossy reflection's Fresnel towards the base colour, in [0, 1].
    pub spec_tint: Param,
}

/// The viewer's direction on the front and the light's with it (both through the origin
/// when the viewer is behind: Mitsuba's `mulsign`), or `None` for a grazing viewer.
fn to_front(wi: Vec3, wo: Vec3) -> Option<(Vec3, Vec3)> {
    (wo.z != 0.0).then(|| (mulsign(wi, wo.z), mulsign(wo, wo.z)))
}

/// The half vector of the front-side `wo` and `wi` mirrored to `wo`'s side.
fn half(wi: Vec3, wo: Vec3) -> (Vec3, Vec3) {
    let wi_r = Vec3::new(wi.x, wi.y, wi.z.abs());
    ((wo + wi_r).normalize(), wi_r)
}

impl PrincipledThin {
    /// Mitsuba's defaults: base colour 0.5, roughness 0.5, eta 1.5, the rest zero.
    pub fn new() -> Self {
        let z = Param::constant(0.0);
        Self {
            base_color: Param::rgb(Vec3::splat(0.5)),
            roughness: Param::constant(0.5),
            anisotropic: z,
            spec_trans: z,
            diff_trans: z,
            eta: Param::constant(1.5),
            sheen: z,
            sheen_tint: z,
            flatness: z,
            spec_tint: z,
        }
    }

    /// The GGX distribution of roughness `r` (Mitsuba's `calc_dist_params`).
    fn distribution(&self, r: f32) -> Microfacet {
        let r2 = r * r;
        let aspect = (1.0 - 0.9 * self.anisotropic.float()).max(0.0).sqrt();
        Microfacet::new(
            Distribution::Ggx,
            (r2 / aspect).max(0.001),
            (r2 * aspect).max(0.001),
        )
    }

    /// The glossy reflection's distribution.
    pub fn microfacet(&self) -> Microfacet {
        self.distribution(self.roughness.float())
    }

    /// The glossy transmission's: roughness scaled by `0.65 eta - 0.35`.
    pub fn transmission_microfacet(&self) -> Microfacet {
        self.distribution((0.65 * self.eta.float() - 0.35) * self.roughness.float())
    }

    /// The diffuse transmission's weight `dt` (half of Mitsuba's `diff_trans`).
    fn dt(&self) -> f32 {
        self.diff_trans.float() / 2.0
    }

    /// `(1 - st)(1 - dt)`: the weight of the diffuse reflection and sheen.
    fn brdf(&self) -> f32 {
        (1.0 - self.spec_trans.float()) * (1.0 - self.dt())
    }

    /// The weight of the diffuse part: `(1 - flatness)(1 - st)(1 - dt)`.
    fn diffuse_weight(&self) -> f32 {
        (1.0 - self.flatness.float()) * self.brdf()
    }

    /// The base colour's tint.
    fn tint(&self) -> Vec3 {
        tint(self.base_color.get())
    }

    /// f(wi, wo) of front-side `wo` in two parts: the separable diffuse one and the rest.
    fn parts(&self, wi: Vec3, wo: Vec3) -> (Vec3, Vec3) {
        let (ci, co) = (wo.z, wi.z);
        if co == 0.0 {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        let (st, dt) = (self.spec_trans.float(), self.dt());
        let base = self.base_color.get();
        let reflect = co > 0.0;
        let (h, _) = half(wi, wo);
        let (mut diffuse, mut lobe) = (Vec3::ZERO, Vec3::ZERO);
        if st > 0.0 {
            let eta = self.eta.float();
            let f = fresnel_dielectric(wo.dot(h), eta).0;
            if reflect && compatible(h, wo, wi, true) {
                let mf = self.microfacet();
                let r0 = ((eta - 1.0) / (eta + 1.0)).powi(2);
                let schlick = calc_schlick(self.tint() * r0, wo.dot(h), eta);
                let t = self.spec_tint.float();
                let f_thin = Vec3::splat(f) + (schlick - Vec3::splat(f)) * t;
                lobe += f_thin * (st * mf.d(h) * mf.g(wo, wi, h) / (4.0 * ci * co));
            }
            if !reflect && compatible(h, wo, wi, false) {
                let mf = self.transmission_microfacet();
                let v = st * (1.0 - f) * mf.d(h) * mf.g(wo, wi, h) / (4.0 * ci * co.abs());
                lobe += base * v;
            }
        }
        if reflect && st < 1.0 && dt < 1.0 {
            let cos_d = h.dot(wi);
            let (roughness, flatness) = (self.roughness.float(), self.flatness.float());
            let (d, rest) = disney_diffuse(co, ci, cos_d, roughness, flatness);
            let k = base * (self.brdf() * FRAC_1_PI);
            diffuse += k * d;
            lobe += k * rest;
            let sheen = self.sheen.float();
            if sheen > 0.0 {
                let c_sheen = Vec3::ONE + (self.tint() - Vec3::ONE) * self.sheen_tint.float();
                lobe += c_sheen * (sheen * self.brdf() * schlick_weight(cos_d.abs()));
            }
        }
        if !reflect && st < 1.0 && dt > 0.0 {
            lobe += base * ((1.0 - st) * dt * FRAC_1_PI);
        }
        (diffuse, lobe)
    }

    /// The sampler's component probabilities (glossy reflection, glossy transmission, cosine
    /// reflection, cosine transmission) with the cosine reflection weighted `cos_w`.
    fn probabilities(&self, cos_w: f32) -> [f32; 4] {
        let (st, dt) = (self.spec_trans.float(), self.dt());
        let w = [st / 2.0, st / 2.0, cos_w, (1.0 - st) * dt];
        let rcp = 1.0 / (w[0] + w[1] + w[2] + w[3]);
        w.map(|x| x * rcp)
    }

    /// The density of [`sample_with`](Self::sample_with) for front-side `wo` (Mitsuba's `pdf`
    /// when `cos_w` is `(1 - st)(1 - dt)`).
    fn pdf_with(&self, wi: Vec3, wo: Vec3, cos_w: f32) -> f32 {
        let co = wi.z;
        let [p_sr, p_st, p_cr, p_ct] = self.probabilities(cos_w);
        let mut pdf = 0.0;
        if self.spec_trans.float() > 0.0 {
            let (h, wi_r) = half(wi, wo);
            let jacobian = (1.0 / (4.0 * wi_r.dot(h))).abs();
            if co > 0.0 && compatible(h, wo, wi, true) {
                pdf += p_sr * self.microfacet().pdf_visible(wo, h) * jacobian;
            }
            if co < 0.0 && compatible(h, wo, wi, false) {
                pdf += p_st * self.transmission_microfacet().pdf_visible(wo, h) * jacobian;
            }
        }
        if co > 0.0 {
            pdf += p_cr * cosine_hemisphere_pdf(wi);
        }
        if co < 0.0 {
            pdf += p_ct * cosine_hemisphere_pdf(-wi);
        }
        pdf
    }

    /// The sampler's thresholds on `u[0]`: the cumulative probabilities of the glossy
    /// reflection, the glossy transmission and the cosine reflection (above the last, the
    /// cosine transmission), for [`sample`](BsdfKind::sample) (`lobe` false) or
    /// [`sample_lobe`](BsdfKind::sample_lobe) at `wo`.
    pub fn sample_thresholds(&self, wo: Vec3, lobe: bool) -> [f32; 3] {
        let [a, b, c, _] = self.probabilities(self.cos_weight(wo, lobe));
        [a, a + b, a + b + c]
    }

    /// Mitsuba's sampling strategy with the cosine reflection weighted `cos_w`: `u[0]` picks a
    /// component, `u[1], u[2]` the direction (a visible normal for the glossy ones). Weight `f
    /// cos / pdf` with `f` the whole BSDF (`lobe` false) or the lobe part.
    fn sample_with(&self, wo: Vec3, u: [f32; 3], cos_w: f32, lobe: bool) -> Option<LobeSample> {
        let (_, wo_f) = to_front(Vec3::Z, wo)?;
        let [c0, c1, c2] = {
            let [a, b, c, _] = self.probabilities(cos_w);
            [a, a + b, a + b + c]
        };
        let u2 = Vec2::new(u[1], u[2]);
        let wi_f = if u[0] < c0 {
            let (m, _) = self.microfacet().sample_visible(wo_f, u2);
            let wi = reflect(wo_f, m);
            (wi.z > 0.0 && compatible(m, wo_f, wi, true)).then_some(wi)?
        } else if u[0] < c1 {
            let (m, _) = self.transmission_microfacet().sample_visible(wo_f, u2);
            let r = reflect(wo_f, m);
            let wi = Vec3::new(r.x, r.y, -r.z);
            (wi.z < 0.0 && compatible(m, wo_f, wi, false)).then_some(wi)?
        } else if u[0] < c2 {
            square_to_cosine_hemisphere(u2)
        } else if self.dt() > 0.0 {
            -square_to_cosine_hemisphere(u2)
        } else {
            return None;
        };
        let pdf = self.pdf_with(wi_f, wo_f, cos_w);
        let (d, l) = self.parts(wi_f, wo_f);
        let f = if lobe { l } else { d + l };
        (pdf > 0.0).then(|| LobeSample {
            wi: mulsign(wi_f, wo.z),
            weight: f * (wi_f.z.abs() / pdf),
            pdf,
            delta: false,
        })
    }

    /// The cosine reflection's weight: Mitsuba's `(1 - st)(1 - dt)` for the whole BSDF; for the
    /// lobe part a rough measure of its retro-reflection, fake subsurface and sheen terms
    /// seen from `wo` (they grow towards grazing views).
    fn cos_weight(&self, wo: Vec3, lobe: bool) -> f32 {
        if !lobe {
            return self.brdf();
        }
        let g = schlick_weight(wo.z.abs()) + 0.05;
        let flatness = self.flatness.float();
        let retro = (1.0 - flatness) * 2.0 * self.roughness.float() * g + flatness;
        self.brdf() * (retro + self.sheen.float() * g)
    }
}

impl Default for PrincipledThin {
    fn default() -> Self {
        Self::new()
    }
}

impl BsdfKind for PrincipledThin {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        Self {
            base_color: self.base_color.resolved(t, uv),
            roughness: self.roughness.resolved(t, uv),
            anisotropic: self.anisotropic.resolved(t, uv),
            spec_trans: self.spec_trans.resolved(t, uv),
            diff_trans: self.diff_trans.resolved(t, uv),
            eta: self.eta.resolved(t, uv),
            sheen: self.sheen.resolved(t, uv),
            sheen_tint: self.sheen_tint.resolved(t, uv),
            flatness: self.flatness.resolved(t, uv),
            spec_tint: self.spec_tint.resolved(t, uv),
        }
    }
    fn base_colour_mut(&mut self) -> Option<&mut Param> {
        Some(&mut self.base_color)
    }
    fn gpu_words(&self, out: &mut GpuWords) {
        for p in [
            &self.base_color,
            &self.roughness,
            &self.anisotropic,
            &self.spec_trans,
            &self.diff_trans,
            &self.eta,
            &self.sheen,
            &self.sheen_tint,
            &self.flatness,
            &self.spec_tint,
        ] {
            out.slot(p);
        }
    }
    fn diffuse_out(&self, wo: Vec3) -> Vec3 {
        if wo.z == 0.0 {
            return Vec3::ZERO;
        }
        self.base_color.get() * (self.diffuse_weight() * Principled::half_schlick(wo.z))
    }
    fn store_weight(&self, wi: Vec3) -> f32 {
        if wi.z != 0.0 && self.diffuse_weight() > 0.0 {
            Principled::half_schlick(wi.z)
        } else {
            0.0
        }
    }
    fn eval_lobe(&self, wi: Vec3, wo: Vec3, _: Transport) -> Vec3 {
        to_front(wi, wo).map_or(Vec3::ZERO, |(wi, wo)| self.parts(wi, wo).1)
    }
    fn pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        to_front(wi, wo).map_or(0.0, |(wi, wo)| {
            self.pdf_with(wi, wo, self.cos_weight(wo, true))
        })
    }
    fn sample_lobe(&self, wo: Vec3, u: [f32; 3], _: Transport) -> Option<LobeSample> {
        self.sample_with(wo, u, self.cos_weight(wo, true), true)
    }
    fn has_diffuse(&self) -> bool {
        self.diffuse_weight() > 0.0
    }
    /// The lobes' rough albedo at `wo` against the diffuse part's, inside [0.05, 0.95].
    fn lobe_probability(&self, wo: Vec3) -> f32 {
        let d = mean(self.diffuse_out(wo));
        if d <= 0.0 {
            return 1.0;
        }
        let base = mean(self.base_color.get());
        let f = fresnel_dielectric(wo.z.abs(), self.eta.float()).0;
        let st = self.spec_trans.float();
        let l = st * (f + (1.0 - f) * base)
            + (1.0 - st) * self.dt() * base
            + self.cos_weight(wo, true) * base;
        (l / (l + d)).clamp(0.05, 0.95)
    }
    fn eval(&self, wi: Vec3, wo: Vec3, _: Transport) -> Vec3 {
        to_front(wi, wo).map_or(Vec3::ZERO, |(wi, wo)| {
            let (d, l) = self.parts(wi, wo);
            d + l
        })
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        to_front(wi, wo).map_or(0.0, |(wi, wo)| {
            self.pdf_with(wi, wo, self.cos_weight(wo, false))
        })
    }
    fn sample(&self, wo: Vec3, u: [f32; 3], _: Transport) -> Option<LobeSample> {
        self.sample_with(wo, u, self.cos_weight(wo, false), false)
    }
    /// Asked of the material's (unresolved) kind: a textured transmission or flatness may
    /// leave some diffuse part anywhere on it.
    fn stores_photons(&self) -> bool {
        self.spec_trans.is_textured()
            || self.diff_trans.is_textured()
            || self.flatness.is_textured()
            || self.has_diffuse()
    }
}
