//! Mitsuba 3.9's `principled` BSDF (Disney's principled model as Mitsuba writes it, which the
//! mitsuba-blender exporter writes for Blender's Principled BSDF): with `brdf = (1 - metallic)
//! (1 - spec_trans)` and `bsdf = (1 - metallic) spec_trans`,
//!
//! ```text
//! f = F_p D G / (4 |cos_i cos_o|)                      main specular reflection (GGX, both sides)
//!   + sqrt(base) bsdf (1 - F) D G |...|                rough dielectric transmission
//!   + 0.25 clearcoat F_cc D_cc G_cc                    clearcoat (GTR1; Mitsuba's has no 1/(4 cos cos))
//!   + brdf base/pi lerp(f_diff + f_retro, f_ss, flatness)   Disney diffuse, front only
//!   + sheen (1 - metallic) (1 - cos_d)^5 c_sheen       sheen, front only
//! ```
//!
//! `F` the dielectric Fresnel of `eta`, `F_p` its blend with the metal's and the tinted
//! Schlick terms (`principled_fresnel`; the back side sees `bsdf F` alone), `f_diff = (1 - Fi /
//! 2)(1 - Fo / 2)` with `F = (1 - cos)^5`, `f_retro = Rr (Fo + Fi + Fo Fi (Rr - 1))`, `Rr = 2
//! roughness cos_d^2`. The surface is one interface like `roughdielectric`: `wo.z < 0` is the
//! viewer inside, where only the specular reflection and transmission act.
//!
//! The photon-mapping split: the diffuse part is the separable `(1 - flatness) brdf base
//! f_diff / pi` (`diffuse_out(wo) = (1 - flatness) brdf base (1 - Fo/2)`, `store_weight(wi) =
//! 1 - Fi/2`), exact; the lobe part (traced) is everything else, including the retro-
//! reflection, fake subsurface and sheen terms that depend on the half vector (sampled
//! cosine-weighted). [`Principled::sample`] is Mitsuba's sampler (same uniforms, same
//! directions); [`Principled::sample_lobe`] is the same strategy with the cosine component
//! weighted for the lobe part's remainder. The anisotropic roughness is along the local
//! frame's x (Mitsuba: the surface's `dp/du`). Inside Mitsuba's `twosided` (as the
//! mitsuba-blender exporter writes a reflective one) both sides are the front. Twin:
//! `principled.wgsl`. The terms it shares with `principledthin` are in `principled_terms.rs`.

use crate::bsdfs::interface::{back_to_side, BsdfKind, LobeSample, SurfaceClass, Transport};
use crate::bsdfs::math::{
    cosine_hemisphere_pdf, mulsign, reflect, refract, square_to_cosine_hemisphere,
};
use crate::bsdfs::metallic_roughness::schlick_weight;
use crate::bsdfs::microfacet::{fresnel_dielectric, Distribution, Microfacet};
use crate::bsdfs::param::{GpuWords, Param};
use crate::bsdfs::principled_terms::{
    calc_schlick, compatible, disney_diffuse, gtr1_d, gtr1_sample, mean, smith_ggx1, tint,
};
use crate::bsdfs::rough_dielectric::half_vector;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};
use std::f32::consts::FRAC_1_PI;

/// The WGSL twin.
pub const WGSL: &str = include_str!("principled.wgsl");
/// The words its parameters take on the GPU.
pub const WORDS: usize = 12;
/// Its class.
pub const CLASS: SurfaceClass = SurfaceClass::Shaded;

/// Mitsuba's `principled`: every parameter a [`Param`] (a float one reads `value.x`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Principled {
    /// Base colour (linear RGB).
    pub base_color: Param,
    /// Roughness of the main specular lobes; GGX alpha `roughness^2` (at least 0.001).
    pub roughness: Param,
    /// Anisotropy in [0, 1]: alphas `r^2 / a`, `r^2 a` with `a = sqrt(1 - 0.9 anisotropic)`.
    pub anisotropic: Param,
    /// Metalness in [0, 1].
    pub metallic: Param,
    /// Weight of the specular transmission in [0, 1].
    pub spec_trans: Param,
    /// Tint of the dielectric reflection towards the base colour, in [0, 1].
    pub spec_tint: Param,
    /// Weight of the sheen lobe.
    pub sheen: Param,
    /// Tint of the sheen towards the base colour, in [0, 1].
    pub sheen_tint: Param,
    /// Weight of the clearcoat lobe.
    pub clearcoat: Param,
    /// Gloss of the clearcoat: GTR1 alpha `lerp(0.1, 0.001, gloss)`.
    pub clearcoat_gloss: Param,
    /// Blend of the diffuse response towards the fake subsurface term, in [0, 1].
    pub flatness: Param,
    /// Relative index of refraction, interior / exterior (Mitsuba's `eta`, or derived from
    /// `specular`).
    pub eta: f32,
    /// Inside Mitsuba's `twosided`: a viewer behind the surface sees it as from the front
    /// (both directions mirrored), as the mitsuba-blender exporter writes reflective ones.
    pub two_sided: bool,
}

/// The unnormalised choice weights of the sampler's components at a dielectric Fresnel `f`:
/// (cosine, clearcoat, transmission, reflection), given the cosine component's weight `cos_w`.
fn weights(front: bool, cos_w: f32, clearcoat: f32, bsdf: f32, f: f32) -> [f32; 4] {
    if front {
        [
            cos_w,
            0.25 * clearcoat,
            bsdf * (1.0 - f),
            1.0 - bsdf * (1.0 - f),
        ]
    } else {
        [0.0, 0.0, 1.0 - f, f]
    }
}

impl Principled {
    /// Mitsuba's defaults: base colour 0.5, roughness 0.5, specular 0.5, the rest zero.
    pub fn new() -> Self {
        let z = Param::constant(0.0);
        Self {
            base_color: Param::rgb(Vec3::splat(0.5)),
            roughness: Param::constant(0.5),
            anisotropic: z,
            metallic: z,
            spec_trans: z,
            spec_tint: z,
            sheen: z,
            sheen_tint: z,
            clearcoat: z,
            clearcoat_gloss: z,
            flatness: z,
            eta: Self::eta_of_specular(0.5),
            two_sided: false,
        }
    }

    /// Both directions mirrored to the front when the kind is two-sided and `wo` is behind,
    /// with whether they were. A sign factor, not `flip_z`: with the negations, rustc 1.95
    /// inlined `sample` then `pdf` so that a sample's own direction had density 0 (caught by
    /// tests/bsdf_stats.rs chi2_principled).
    fn oriented(&self, wi: Vec3, wo: Vec3) -> (Vec3, Vec3, bool) {
        let flip = self.two_sided && wo.z < 0.0;
        let s = if flip { -1.0 } else { 1.0 };
        let w = |v: Vec3| Vec3::new(v.x, v.y, v.z * s);
        (w(wi), w(wo), flip)
    }

    /// The index Mitsuba derives from `specular`: `2 / (1 - sqrt(0.08 specular)) - 1`.
    pub fn eta_of_specular(specular: f32) -> f32 {
        2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
    }

    /// The main specular lobes' GGX distribution.
    pub fn microfacet(&self) -> Microfacet {
        let r2 = self.roughness.float() * self.roughness.float();
        let aspect = (1.0 - 0.9 * self.anisotropic.float()).max(0.0).sqrt();
        Microfacet::new(
            Distribution::Ggx,
            (r2 / aspect).max(0.001),
            (r2 * aspect).max(0.001),
        )
    }

    fn brdf(&self) -> f32 {
        (1.0 - self.metallic.float()) * (1.0 - self.spec_trans.float())
    }

    fn bsdf(&self) -> f32 {
        (1.0 - self.metallic.float()) * self.spec_trans.float()
    }

    /// The base colour's tint.
    fn tint(&self) -> Vec3 {
        tint(self.base_color.get())
    }

    /// The main reflection's Fresnel term at `c = wo . h` (Mitsuba's `principled_fresnel`).
    fn fresnel_p(&self, f_dielectric: f32, c: f32, front: bool) -> Vec3 {
        if !front {
            return Vec3::splat(self.bsdf() * f_dielectric);
        }
        let (metallic, spec_tint) = (self.metallic.float(), self.spec_tint.float());
        let eta_it = if c >= 0.0 { self.eta } else { 1.0 / self.eta };
        let r0 = ((eta_it - 1.0) / (eta_it + 1.0)).powi(2);
        let metal = calc_schlick(self.base_color.get(), c, self.eta) * metallic;
        let tinted = calc_schlick(self.tint() * r0, c, self.eta) * ((1.0 - metallic) * spec_tint);
        Vec3::splat((1.0 - metallic) * (1.0 - spec_tint) * f_dielectric) + metal + tinted
    }

    /// The clearcoat's GTR1 roughness.
    fn clearcoat_alpha(&self) -> f32 {
        0.1 + (0.001 - 0.1) * self.clearcoat_gloss.float()
    }

    /// The diffuse part's separable factor `1 - (1 - cos)^5 / 2` of one direction.
    pub(crate) fn half_schlick(cos: f32) -> f32 {
        1.0 - 0.5 * schlick_weight(cos.abs())
    }

    /// The weight of the diffuse part: `(1 - flatness) brdf`.
    fn diffuse_weight(&self) -> f32 {
        (1.0 - self.flatness.float()) * self.brdf()
    }

    /// f(wi, wo) in two parts: the separable diffuse one and the rest (the lobe part).
    pub fn parts(&self, wi: Vec3, wo: Vec3, transport: Transport) -> (Vec3, Vec3) {
        if wo.z == 0.0 || wi.z == 0.0 {
            return (Vec3::ZERO, Vec3::ZERO);
        }
        let (metallic, clearcoat) = (self.metallic.float(), self.clearcoat.float());
        let (brdf, bsdf) = (self.brdf(), self.bsdf());
        let base = self.base_color.get();
        let front = wo.z > 0.0;
        let (h, reflect, eta_path) = half_vector(self.eta, wi, wo);
        let f = fresnel_dielectric(wo.dot(h), self.eta).0;
        let mf = self.microfacet();
        let (d, g) = (mf.d(h), mf.g(wo, wi, h));
        let (mut diffuse, mut lobe) = (Vec3::ZERO, Vec3::ZERO);
        if reflect && compatible(h, wo, wi, true) {
            if f > 0.0 {
                lobe +=
                    self.fresnel_p(f, wo.dot(h), front) * (d * g) / (4.0 * wo.z.abs() * wi.z.abs());
            }
            if front && clearcoat > 0.0 {
                let fcc = calc_schlick(Vec3::splat(0.04), wo.dot(h), self.eta).x;
                let dcc = gtr1_d(self.clearcoat_alpha(), h);
                let gcc = smith_ggx1(wo, h, 0.25) * smith_ggx1(wi, h, 0.25);
                lobe += Vec3::splat(0.25 * clearcoat * fcc * dcc * gcc);
            }
        }
        if !reflect && bsdf > 0.0 && f < 1.0 && compatible(h, wo, wi, false) {
            let scale = match transport {
                Transport::Radiance => 1.0 / (eta_path * eta_path),
                Transport::Importance => 1.0,
            };
            let (dot_o, dot_i) = (wo.dot(h), wi.dot(h));
            let v = (scale * (1.0 - f) * d * g * eta_path * eta_path * dot_o * dot_i
                / (wo.z * wi.z * (dot_o + eta_path * dot_i).powi(2)))
            .abs();
            lobe += Vec3::new(base.x.sqrt(), base.y.sqrt(), base.z.sqrt()) * (bsdf * v);
        }
        if reflect && front {
            let cos_d = h.dot(wi);
            if brdf > 0.0 {
                let (roughness, flatness) = (self.roughness.float(), self.flatness.float());
                let (d, rest) = disney_diffuse(wo.z, wi.z, cos_d, roughness, flatness);
                let k = base * (brdf * FRAC_1_PI);
                diffuse += k * d;
                lobe += k * rest;
            }
            let sheen = self.sheen.float();
            if sheen > 0.0 && 1.0 - metallic > 0.0 {
                let c_sheen = Vec3::ONE + (self.tint() - Vec3::ONE) * self.sheen_tint.float();
                lobe += c_sheen * (sheen * (1.0 - metallic) * schlick_weight(cos_d.abs()));
            }
        }
        (diffuse, lobe)
    }

    /// The density of [`sample_with`](Self::sample_with) for the cosine component's weight
    /// `cos_w(wo)` (Mitsuba's `pdf` for `brdf`).
    fn pdf_with(&self, wi: Vec3, wo: Vec3, cos_w: f32) -> f32 {
        if wo.z == 0.0 || wi.z == 0.0 {
            return 0.0;
        }
        let front = wo.z > 0.0;
        let bsdf = self.bsdf();
        if !front && bsdf <= 0.0 {
            return 0.0;
        }
        let (h, reflect, eta_path) = half_vector(self.eta, wi, wo);
        let f = fresnel_dielectric(wo.dot(h), self.eta).0;
        let w = weights(front, cos_w, self.clearcoat.float(), bsdf, f);
        let total = w.iter().sum::<f32>();
        let [p_cos, p_cc, p_trans, p_refl] = w.map(|x| x / total);
        let (dot_o, dot_i) = (wo.dot(h), wi.dot(h));
        let jacobian = if reflect {
            (1.0 / (4.0 * dot_i)).abs()
        } else {
            (eta_path * eta_path * dot_i / (dot_o + eta_path * dot_i).powi(2)).abs()
        };
        let d_vis = self.microfacet().pdf_visible(mulsign(wo, wo.z), h);
        let mut pdf = 0.0;
        if reflect {
            if compatible(h, wo, wi, true) {
                pdf += p_refl * d_vis * jacobian;
                if p_cc > 0.0 {
                    pdf += p_cc * h.z * gtr1_d(self.clearcoat_alpha(), h) * jacobian;
                }
            }
            pdf += p_cos * cosine_hemisphere_pdf(wi);
        } else if compatible(h, wo, wi, false) {
            pdf += p_trans * d_vis * jacobian;
        }
        pdf
    }

    /// The visible normal `m` that `u2` picks for `wo` and the sampler's thresholds on `u[0]`
    /// (the cumulative probabilities of the cosine, clearcoat and transmission components;
    /// above the last, the reflection), given the cosine component's weight `cos_w`.
    fn choice(&self, wo: Vec3, u2: Vec2, cos_w: f32) -> (Vec3, [f32; 3]) {
        let (m, _) = self.microfacet().sample_visible(mulsign(wo, wo.z), u2);
        let f = fresnel_dielectric(wo.dot(m), self.eta).0;
        let w = weights(wo.z > 0.0, cos_w, self.clearcoat.float(), self.bsdf(), f);
        let total = w.iter().sum::<f32>();
        let c = [
            w[0] / total,
            (w[0] + w[1]) / total,
            (w[0] + w[1] + w[2]) / total,
        ];
        (m, c)
    }

    /// The thresholds on `u[0]` of [`sample`](BsdfKind::sample) (`lobe` false) or
    /// [`sample_lobe`](BsdfKind::sample_lobe) for `wo` and `u[1], u[2]` (see `choice`).
    pub fn sample_thresholds(&self, wo: Vec3, u: [f32; 3], lobe: bool) -> [f32; 3] {
        let cos_w = if lobe {
            self.remainder_weight(wo)
        } else {
            self.full_weight(wo)
        };
        self.choice(wo, Vec2::new(u[1], u[2]), cos_w).1
    }

    /// Mitsuba's sampling strategy with the cosine component weighted `cos_w`: a visible
    /// normal `m` from `u[1], u[2]`, then `u[0]` picks the cosine, clearcoat, transmission or
    /// reflection component (transmission and reflection by the Fresnel term at `m`); the
    /// chosen one maps `u[1], u[2]` to a direction. Weight `f cos / pdf` with `f` the whole
    /// BSDF (`lobe` false) or the lobe part.
    fn sample_with(
        &self,
        wo: Vec3,
        u: [f32; 3],
        transport: Transport,
        cos_w: f32,
        lobe: bool,
    ) -> Option<LobeSample> {
        let front = wo.z > 0.0;
        let bsdf = self.bsdf();
        if wo.z == 0.0 || (!front && bsdf <= 0.0) {
            return None;
        }
        let u2 = Vec2::new(u[1], u[2]);
        let (m, [c0, c1, c2]) = self.choice(wo, u2, cos_w);
        let (_, cos_t, _, eta_ti) = fresnel_dielectric(wo.dot(m), self.eta);
        let wi = if u[0] < c0 {
            let wi = square_to_cosine_hemisphere(u2);
            (wi.z * wo.z > 0.0).then_some(wi)?
        } else if u[0] < c1 {
            let mc = gtr1_sample(self.clearcoat_alpha(), u2);
            let wi = reflect(wo, mc);
            (wi.z * wo.z > 0.0 && compatible(mc, wo, wi, true)).then_some(wi)?
        } else if u[0] < c2 {
            let wi = refract(wo, m, cos_t, eta_ti);
            (wi.z * wo.z < 0.0 && compatible(m, wo, wi, false)).then_some(wi)?
        } else {
            let wi = reflect(wo, m);
            (wi.z * wo.z > 0.0 && compatible(m, wo, wi, true)).then_some(wi)?
        };
        let pdf = self.pdf_with(wi, wo, cos_w);
        let (d, l) = self.parts(wi, wo, transport);
        let f = if lobe { l } else { d + l };
        (pdf > 0.0).then(|| LobeSample {
            wi,
            weight: f * (wi.z.abs() / pdf),
            pdf,
            delta: false,
        })
    }

    /// The cosine component's weight when sampling the whole BSDF (Mitsuba's): `brdf` in front.
    fn full_weight(&self, wo: Vec3) -> f32 {
        if wo.z > 0.0 {
            self.brdf()
        } else {
            0.0
        }
    }

    /// The cosine component's weight when sampling the lobe part alone: a rough measure of
    /// the retro-reflection, fake subsurface and sheen terms seen from `wo` (they grow
    /// towards grazing views).
    fn remainder_weight(&self, wo: Vec3) -> f32 {
        if wo.z <= 0.0 {
            return 0.0;
        }
        let g = schlick_weight(wo.z) + 0.05;
        let flatness = self.flatness.float();
        let retro = (1.0 - flatness) * 2.0 * self.roughness.float() * g + flatness;
        (1.0 - self.metallic.float())
            * ((1.0 - self.spec_trans.float()) * retro + self.sheen.float() * g)
    }
}

impl Default for Principled {
    fn default() -> Self {
        Self::new()
    }
}

impl BsdfKind for Principled {
    fn class(&self) -> SurfaceClass {
        CLASS
    }
    fn resolve(&self, t: &[SceneTexture], uv: Vec2) -> Self {
        Self {
            base_color: self.base_color.resolved(t, uv),
            roughness: self.roughness.resolved(t, uv),
            anisotropic: self.anisotropic.resolved(t, uv),
            metallic: self.metallic.resolved(t, uv),
            spec_trans: self.spec_trans.resolved(t, uv),
            spec_tint: self.spec_tint.resolved(t, uv),
            sheen: self.sheen.resolved(t, uv),
            sheen_tint: self.sheen_tint.resolved(t, uv),
            clearcoat: self.clearcoat.resolved(t, uv),
            clearcoat_gloss: self.clearcoat_gloss.resolved(t, uv),
            flatness: self.flatness.resolved(t, uv),
            ..*self
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
            &self.metallic,
            &self.spec_trans,
            &self.spec_tint,
            &self.sheen,
            &self.sheen_tint,
            &self.clearcoat,
            &self.clearcoat_gloss,
            &self.flatness,
        ] {
            out.slot(p);
        }
        out.raw([self.eta.to_bits(), u32::from(self.two_sided), 0, 0]);
    }
    fn diffuse_out(&self, wo: Vec3) -> Vec3 {
        let (_, wo, _) = self.oriented(Vec3::Z, wo);
        if wo.z > 0.0 {
            self.base_color.get() * (self.diffuse_weight() * Self::half_schlick(wo.z))
        } else {
            Vec3::ZERO
        }
    }
    fn store_weight(&self, wi: Vec3) -> f32 {
        let z = if self.two_sided { wi.z.abs() } else { wi.z };
        if z > 0.0 && self.diffuse_weight() > 0.0 {
            Self::half_schlick(z)
        } else {
            0.0
        }
    }
    fn eval_lobe(&self, wi: Vec3, wo: Vec3, t: Transport) -> Vec3 {
        let (wi, wo, _) = self.oriented(wi, wo);
        self.parts(wi, wo, t).1
    }
    fn pdf_lobe(&self, wi: Vec3, wo: Vec3) -> f32 {
        let (wi, wo, _) = self.oriented(wi, wo);
        self.pdf_with(wi, wo, self.remainder_weight(wo))
    }
    fn sample_lobe(&self, wo: Vec3, u: [f32; 3], t: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = self.oriented(Vec3::Z, wo);
        let s = self.sample_with(wo, u, t, self.remainder_weight(wo), true);
        back_to_side(s, flipped)
    }
    fn has_diffuse(&self) -> bool {
        self.diffuse_weight() > 0.0
    }
    /// The lobes' rough albedo at `wo` against the diffuse part's, inside [0.05, 0.95].
    fn lobe_probability(&self, wo: Vec3) -> f32 {
        let (_, wo, _) = self.oriented(Vec3::Z, wo);
        let d = mean(self.diffuse_out(wo));
        if d <= 0.0 {
            return 1.0;
        }
        let c = wo.z.abs();
        let f = fresnel_dielectric(c, self.eta).0;
        let base = self.base_color.get();
        let l = mean(self.fresnel_p(f, c, true))
            + self.bsdf()
                * (1.0 - f)
                * mean(Vec3::new(base.x.sqrt(), base.y.sqrt(), base.z.sqrt()))
            + 0.25 * self.clearcoat.float() * 0.04
            + self.remainder_weight(wo) * mean(base);
        (l / (l + d)).clamp(0.05, 0.95)
    }
    fn eval(&self, wi: Vec3, wo: Vec3, t: Transport) -> Vec3 {
        let (wi, wo, _) = self.oriented(wi, wo);
        let (d, l) = self.parts(wi, wo, t);
        d + l
    }
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        let (wi, wo, _) = self.oriented(wi, wo);
        self.pdf_with(wi, wo, self.full_weight(wo))
    }
    fn sample(&self, wo: Vec3, u: [f32; 3], t: Transport) -> Option<LobeSample> {
        let (_, wo, flipped) = self.oriented(Vec3::Z, wo);
        let s = self.sample_with(wo, u, t, self.full_weight(wo), false);
        back_to_side(s, flipped)
    }
    /// Asked of the material's (unresolved) kind: a textured metalness, transmission or
    /// flatness may leave some diffuse part anywhere on it.
    fn stores_photons(&self) -> bool {
        self.metallic.is_textured()
            || self.spec_trans.is_textured()
            || self.flatness.is_textured()
            || self.has_diffuse()
    }
}
