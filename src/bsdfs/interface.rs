//! The one interface every scattering model implements ([`BsdfKind`]), and what its methods
//! answer with. A kind is one file of this folder (its parameters, this trait, its GPU words)
//! with its WGSL twin beside it, and one entry in the list of `mod.rs`; the union
//! [`crate::bsdfs::Bsdf`] dispatches every method to its kinds in one `match`, and the WGSL
//! dispatch is generated from the same list (`crate::bsdfs::gpu`).
//!
//! Two levels, both with defaults so that a kind writes only what differs:
//! - the BSDF in the local shading frame (z the front shading normal), as Mitsuba defines it
//!   (`eval`, `pdf`, `sample`), split as the photon mapper uses it: a Lambertian-like diffuse
//!   part estimated from photon density (`diffuse_out`, `store_weight`) plus a lobe part,
//!   delta or glossy, traced by rays (`eval_lobe`, `pdf_lobe`, `sample_lobe`);
//! - the surface as the integrators see it, in world space (`class`, `delta_event`,
//!   `photon_bounce`, the `surface_*` methods), whose defaults go through the local frame; the
//!   classic kinds (Lambert, Phong, mirror, smooth glass) override them with their own
//!   world-space rules.

pub use crate::bsdfs::fresnel::Dielectric;
use crate::bsdfs::param::GpuWords;
use crate::bvh::hit::Hit;
use crate::error::Result;
use crate::math::geometry::Facing;
use crate::math::rng::Rng;
use crate::math::sampling::{basis, cosine_hemisphere};
use crate::scene::locate::Locate;
use crate::settings::FresnelMode;
use crate::textures::SceneTexture;
use glam::{Vec2, Vec3};
use std::f32::consts::PI;

/// What a surface does with a ray that reaches it, the integrators' one dispatch.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceClass {
    /// Reflects nothing: a path ends here (after its emission).
    Black,
    /// Only delta lobes (mirror, smooth glass): the path follows its chain without shading.
    Delta,
    /// A diffuse part or a non-delta lobe: the path shades here (photon estimates, shadow
    /// rays, gather rays) and may go on along the lobe.
    Shaded,
    /// An index-matched boundary: the path goes on straight through, unscattered and not
    /// counted as a bounce; only the medium changes.
    Null,
}

/// The ways a delta surface sends on a ray.
#[derive(Clone, Copy, Debug)]
pub enum DeltaEvent {
    /// One direction with its weight.
    Reflect {
        /// The new direction.
        dir: Vec3,
        /// Factor on the throughput.
        weight: Vec3,
    },
    /// A dielectric interface: the reflected and refracted directions and the Fresnel
    /// reflectance (the integrator chooses or splits).
    Split(Dielectric),
}

/// A ray drawn from a lobe.
#[derive(Clone, Copy, Debug)]
pub struct LobeRay {
    /// Its direction.
    pub dir: Vec3,
    /// `f cos / pdf`.
    pub weight: Vec3,
    /// The solid-angle density it was drawn with; 0 for a delta lobe.
    pub pdf: f32,
}

/// The outcome of a photon's scattering (Russian roulette for the classic kinds).
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

/// The local shading frame a BSDF is evaluated in (Mitsuba's `Frame3f`): unit tangent `s`,
/// bitangent `t = n x s` and the shading normal `n`. An anisotropic BSDF's `alpha_u` runs along
/// `s`, which is the surface's `dp/du` (Mitsuba's `sh_frame.s`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    /// The tangent (local x).
    pub s: Vec3,
    /// The bitangent (local y).
    pub t: Vec3,
    /// The unit shading normal (local z).
    pub n: Vec3,
}

impl Frame {
    /// The frame of unit normal `n` whose tangent is `tangent` made orthogonal to `n` and
    /// normalised (Gram-Schmidt, as Mitsuba's `initialize_sh_frame` and the normal map's
    /// perturbed frame build it); where that vanishes (a zero tangent, one along `n`) the
    /// orthonormal basis `basis(n)` (Mitsuba's `coordinate_system`). Twin: `frame_tangent` in
    /// `src/bsdfs/shading.wgsl`.
    #[inline]
    pub fn new(n: Vec3, tangent: Vec3) -> Frame {
        match crate::math::geometry::orthogonal_tangent(n, tangent) {
            Some(s) => Frame {
                s,
                t: n.cross(s),
                n,
            },
            None => {
                let (s, t) = basis(n);
                Frame { s, t, n }
            }
        }
    }

    /// `w` in this frame.
    #[inline]
    pub fn local(&self, w: Vec3) -> Vec3 {
        Vec3::new(w.dot(self.s), w.dot(self.t), w.dot(self.n))
    }

    /// Local direction `l` in world space.
    #[inline]
    pub fn world(&self, l: Vec3) -> Vec3 {
        self.s * l.x + self.t * l.y + self.n * l.z
    }
}

/// `w` in the local shading frame `n` (z the normal).
#[inline]
pub fn local(n: Frame, w: Vec3) -> Vec3 {
    n.local(w)
}

/// A local sample direction in world space (frame `n`) with its weight, or `None`
/// when it leaks through the geometric surface (a reflection below it, a transmission above
/// it) or carries nothing.
#[inline]
pub fn world_direction(n: Frame, wi: Vec3, weight: Vec3, f: &Facing) -> Option<(Vec3, Vec3)> {
    let dir = n.world(wi).normalize();
    let reflects = dir.dot(f.ns) > 0.0;
    let leaks = if reflects {
        f.reflection_leaks(dir) || dir.dot(f.ng) <= 0.0
    } else {
        f.refraction_leaks(dir) || dir.dot(f.ng) >= 0.0
    };
    (!leaks && weight.max_element() > 0.0).then_some((dir, weight))
}

/// A scattering model: its parameters (each textureable one a [`crate::bsdfs::param::Param`]),
/// the BSDF in the local frame, the surface's behaviour for the integrators, and its GPU words.
/// Directions: `wo` towards the viewer (for a photon where it came from), `wi` towards the
/// light (for a photon where it goes), both away from the surface.
pub trait BsdfKind: Copy {
    /// How the integrators treat the surface.
    fn class(&self) -> SurfaceClass;

    /// The kind with every textured parameter looked up at `uv` (and what depends on them
    /// recomputed); the integrators only ever see resolved kinds.
    fn resolve(&self, textures: &[SceneTexture], uv: Vec2) -> Self;

    /// Writes the parameters as the WGSL twin reads them: slot words (a value and its texture)
    /// and plain words (`crate::bsdfs::param::GpuWords`).
    fn gpu_words(&self, out: &mut GpuWords);

    /// The parameter an importer's base colour (or diffuse reflectance) texture varies, for the
    /// kinds that have one.
    fn base_colour_mut(&mut self) -> Option<&mut crate::bsdfs::param::Param> {
        None
    }

    /// The scene builder's checks of the parameters (the importers check their own ranges).
    fn check(&self, _at: &dyn Locate) -> Result<()> {
        Ok(())
    }

    // ---- the BSDF in the local frame --------------------------------------------------------

    /// The diffuse part's factor on the viewer's side (`f_D = diffuse_out(wo) store_weight(wi)
    /// / pi` for both directions on one side); zero without a diffuse part.
    fn diffuse_out(&self, _wo: Vec3) -> Vec3 {
        Vec3::ZERO
    }

    /// The diffuse part's factor on the light's side, applied when a photon arriving along
    /// `wi` is stored; zero without a diffuse part.
    fn store_weight(&self, _wi: Vec3) -> f32 {
        0.0
    }

    /// The lobe part's non-delta value.
    fn eval_lobe(&self, _wi: Vec3, _wo: Vec3, _transport: Transport) -> Vec3 {
        Vec3::ZERO
    }

    /// Solid-angle density with which [`sample_lobe`](Self::sample_lobe) produces a non-delta
    /// `wi` (zero for a delta lobe).
    fn pdf_lobe(&self, _wi: Vec3, _wo: Vec3) -> f32 {
        0.0
    }

    /// Samples the lobe part alone (`None` without one, or when the sample carries nothing).
    /// Every sampler takes three uniforms: `u[0]` picks a component, `u[1]`, `u[2]` a direction.
    fn sample_lobe(&self, _wo: Vec3, _u: [f32; 3], _transport: Transport) -> Option<LobeSample> {
        None
    }

    /// Whether the BSDF has a diffuse part.
    fn has_diffuse(&self) -> bool {
        false
    }

    /// Whether the BSDF has a lobe part (delta or glossy).
    fn has_lobe(&self) -> bool {
        true
    }

    /// Whether the lobe part is a delta; false without a lobe.
    fn lobe_is_delta(&self) -> bool {
        false
    }

    /// The probability with which a photon seen from `wo` follows the lobe part rather than
    /// the diffuse part (kinds with both), kept inside [0.05, 0.95].
    fn lobe_probability(&self, wo: Vec3) -> f32 {
        (1.0 - self.store_weight(wo)).clamp(0.05, 0.95)
    }

    /// The diffuse part's value f_D(wi, wo) itself (zero across the surface).
    fn diffuse_value(&self, wi: Vec3, wo: Vec3) -> Vec3 {
        if !self.has_diffuse() || wi.z * wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.diffuse_out(wo) * (self.store_weight(wi) * std::f32::consts::FRAC_1_PI)
    }

    /// The non-delta BSDF value f(wi, wo), without the cosine.
    fn eval(&self, wi: Vec3, wo: Vec3, transport: Transport) -> Vec3 {
        self.diffuse_value(wi, wo) + self.eval_lobe(wi, wo, transport)
    }

    /// Solid-angle density with which [`sample`](Self::sample) produces a non-delta `wi`.
    fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        self.pdf_lobe(wi, wo)
    }

    /// Samples the whole BSDF (Mitsuba's strategies); `None` when the sample carries nothing.
    fn sample(&self, wo: Vec3, u: [f32; 3], transport: Transport) -> Option<LobeSample> {
        self.sample_lobe(wo, u, transport)
    }

    // ---- the surface as the integrators see it ----------------------------------------------

    /// Whether photons are stored here (the surface has a diffuse part).
    fn stores_photons(&self) -> bool {
        self.has_diffuse()
    }

    /// Whether caustic photons are aimed at the surface and pass it (a delta or glossy lobe).
    fn casts_caustics(&self) -> bool {
        self.has_lobe()
    }

    /// Whether the lobe is lit by delta lights through shadow rays when the mode adds no
    /// direct light (`plan::Terms::point_lobe`): every non-delta lobe.
    fn lobe_takes_point_lights(&self) -> bool {
        self.has_lobe() && !self.lobe_is_delta()
    }

    /// Whether the lobe transmits light across the surface (a rough dielectric): then shadow
    /// rays to delta lights are also taken through it, from below the shading normal.
    fn lobe_transmits(&self) -> bool {
        false
    }

    /// Whether passing straight through is a *null* event, as Mitsuba's `volpath` counts a
    /// thin dielectric's transmission: in scenes with media a path crossing it is no bounce
    /// longer (its depth, towards `max_depth`, stays), and camera paths choose one branch there.
    fn passes_null(&self) -> bool {
        false
    }

    /// What a shadow ray keeps crossing the surface from `wo` (local) as a null event, in
    /// scenes with media (Mitsuba's `eval_null_transmission`): zero but for [`passes_null`]
    /// kinds.
    ///
    /// [`passes_null`]: Self::passes_null
    fn null_transmission(&self, _wo: Vec3) -> Vec3 {
        Vec3::ZERO
    }

    /// Whether a camera path's delta event here is a [`DeltaEvent::Split`] (glass and the
    /// thin dielectric), which camera paths split into two branches below a depth.
    fn splits(&self) -> bool {
        false
    }

    /// The delta event of a [`SurfaceClass::Delta`] surface for a ray along `d` at `hit`
    /// (shading normal `n`, normals turned by the caller's `f`): by default the mirror
    /// direction, weighted by the lobe's own delta sample.
    fn delta_event(
        &self,
        n: Frame,
        d: Vec3,
        _hit: &Hit,
        f: &Facing,
        _fresnel: FresnelMode,
    ) -> DeltaEvent {
        let weight = self
            .sample_lobe(local(n, -d), [0.0; 3], Transport::Radiance)
            .map_or(Vec3::ZERO, |s| s.weight);
        DeltaEvent::Reflect {
            dir: crate::bsdfs::fresnel::reflect(d, f.ns),
            weight,
        }
    }

    /// The diffuse part's albedo towards the viewer at `wo` (world space): photon estimates
    /// weigh incident light by it over pi.
    fn surface_diffuse_albedo(&self, n: Frame, wo: Vec3) -> Vec3 {
        self.diffuse_out(local(n, wo))
    }

    /// The diffuse part's factor for light arriving from `wi` (world space); `None` when it is
    /// exactly 1.
    fn surface_store_weight(&self, n: Frame, wi: Vec3) -> Option<f32> {
        Some(self.store_weight(local(n, wi)))
    }

    /// The diffuse part's BSDF value `f_D(wi, wo)` (world space).
    fn surface_eval_diffuse(&self, n: Frame, wi: Vec3, wo: Vec3) -> Vec3 {
        let (wi, wo) = (local(n, wi), local(n, wo));
        if wi.z * wo.z <= 0.0 {
            return Vec3::ZERO;
        }
        self.diffuse_out(wo) * (self.store_weight(wi) / PI)
    }

    /// The lobe part's value (world space; `ns` the caller's shading normal).
    fn surface_eval_lobe(&self, n: Frame, wi: Vec3, wo: Vec3, _ns: Vec3) -> Vec3 {
        self.eval_lobe(local(n, wi), local(n, wo), Transport::Radiance)
    }

    /// The whole non-delta BSDF `f(wi, wo)` (world space).
    fn surface_eval(&self, n: Frame, wi: Vec3, wo: Vec3, ns: Vec3) -> Vec3 {
        self.surface_eval_diffuse(n, wi, wo) + self.surface_eval_lobe(n, wi, wo, ns)
    }

    /// The density with which [`surface_sample_lobe`](Self::surface_sample_lobe) draws `wi`.
    fn surface_pdf_lobe(&self, n: Frame, wi: Vec3, wo: Vec3, _ns: Vec3) -> f32 {
        self.pdf_lobe(local(n, wi), local(n, wo))
    }

    /// Whether the lobe can be reached by shadow rays (a glossy, not a delta, lobe).
    fn lobe_is_glossy(&self) -> bool {
        self.has_lobe() && !self.lobe_is_delta()
    }

    /// One ray drawn from the lobe for a path arriving along `d` (towards the surface), normals
    /// `f` facing `-d`; by default three numbers from `rng` through the local frame. A
    /// transmitting lobe's ray goes on on whichever side of the geometric surface it ends
    /// (Mitsuba's spawned rays; the lobe chose reflection or refraction in the shading frame);
    /// other lobes' rays that leak through it carry nothing.
    fn surface_sample_lobe(&self, n: Frame, d: Vec3, f: &Facing, rng: &mut Rng) -> Option<LobeRay> {
        let u = [rng.next(), rng.next(), rng.next()];
        let s = self.sample_lobe(local(n, -d), u, Transport::Radiance)?;
        let (dir, weight) = match self.lobe_transmits() {
            true => Some((n.world(s.wi).normalize(), s.weight))
                .filter(|(_, w)| w.max_element() > 0.0)?,
            false => world_direction(n, s.wi, s.weight, f)?,
        };
        Some(LobeRay {
            dir,
            weight,
            pdf: s.pdf,
        })
    }

    /// A photon arriving along `d` at `hit` (three uniforms `u`). By default the photon samples
    /// the BSDF without roulette (its lobes reflect at most what arrives): a kind with both
    /// parts picks its lobe with [`lobe_probability`](Self::lobe_probability) (`u[0]`), then the
    /// lobe or a cosine-weighted base direction (`u[1], u[2]`).
    fn photon_bounce(
        &self,
        n: Frame,
        d: Vec3,
        hit: &Hit,
        _fresnel: FresnelMode,
        u: [f32; 3],
    ) -> Bounce {
        let f = hit.facing(d);
        let wo = local(n, -d);
        let (wi, weight, delta) = if self.has_diffuse() {
            let p = self.lobe_probability(wo);
            if u[0] < p {
                let Some(s) = self.sample_lobe(wo, [u[0] / p, u[1], u[2]], Transport::Importance)
                else {
                    return Bounce::Absorb;
                };
                (s.wi, s.weight / p, s.delta)
            } else {
                let dir = cosine_hemisphere(f.ns, u[1], u[2]);
                if f.reflection_leaks(dir) {
                    return Bounce::Absorb;
                }
                // f_D cos / (pdf_cos (1 - p)) with pdf_cos = cos / pi.
                let w = self.diffuse_out(wo) * (self.store_weight(local(n, dir)) / (1.0 - p));
                return Bounce::Diffuse { dir, weight: w };
            }
        } else {
            let Some(s) = self.sample_lobe(wo, u, Transport::Importance) else {
                return Bounce::Absorb;
            };
            (s.wi, s.weight, s.delta)
        };
        match world_direction(n, wi, weight, &f) {
            Some((dir, weight)) => Bounce::Specular { dir, weight, delta },
            None => Bounce::Absorb,
        }
    }
}

/// Which quantity a path carries; only transmission through a dielectric tells them apart
/// (radiance is scaled by 1/eta^2 of the crossing, importance is not).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Transport {
    /// Camera paths: radiance flows from `wi` to `wo`.
    Radiance,
    /// Photon paths: power flows from `wo` to `wi`.
    Importance,
}

/// What one scattering from a sampled lobe gives.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeSample {
    /// The sampled direction (towards the light; for a photon the direction it leaves in).
    pub wi: Vec3,
    /// `f |cos theta_i| / pdf`; for a delta lobe the weight of the delta (Fresnel and tint).
    pub weight: Vec3,
    /// Solid-angle density of `wi` under the sampler that produced it; 0 for a delta lobe.
    pub pdf: f32,
    /// Whether the sampled lobe is a delta (mirror, smooth refraction, pass-through).
    pub delta: bool,
}

/// Two-sided kinds: both directions' z mirrored to the front when `wo` is below, or `None`
/// when `wo` lies in the surface.
#[inline]
pub(crate) fn to_front(wi: Vec3, wo: Vec3) -> Option<(Vec3, Vec3, bool)> {
    if wo.z > 0.0 {
        Some((wi, wo, false))
    } else if wo.z < 0.0 {
        Some((flip_z(wi), flip_z(wo), true))
    } else {
        None
    }
}

#[inline]
pub(crate) fn flip_z(w: Vec3) -> Vec3 {
    Vec3::new(w.x, w.y, -w.z)
}

/// Mirrors a front-side sample back to the side `wo` was on.
#[inline]
pub(crate) fn back_to_side(s: Option<LobeSample>, flipped: bool) -> Option<LobeSample> {
    s.map(|mut s| {
        if flipped {
            s.wi = flip_z(s.wi);
        }
        s
    })
}
