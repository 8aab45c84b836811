//! The spot light's cone: its angular falloff, the falloff's integral over the sphere (the
//! light's power is its on-axis intensity times that), and directions sampled in proportion
//! to it; the spot light itself ([`Spot`]: its photons, shadow rays and GPU words). WGSL twin:
//! `spot.wgsl` beside it (`spot_falloff`, `spot_cos`, `spot_emit`, ...); the scene builder's
//! call is in `build.rs`.
//!
//! Two falloffs ([`SpotFalloff`]), 1 inside the inner cone and 0 outside the outer one:
//! - glTF's `KHR_lights_punctual` reference form: with `cd` the cosine between the spot axis
//!   and the direction to the lit point, `scale = 1 / max(0.001, cos_inner - cos_outer)`,
//!   `offset = -cos_outer * scale`, `att = clamp(cd * scale + offset, 0, 1)^2`, a ramp
//!   quadratic in the cosine;
//! - Mitsuba 3's `spot`: `att = (outer - theta) / (outer - inner)` for an angle `theta`
//!   between the half-angles, a ramp linear in the angle.
//!
//! The linear ramp's mass over the cosine, measured from the outer edge, is
//! `D(theta) / (outer - inner)` with `D(theta) = x cos(outer - x) - 2 cos(outer - x/2) sin(x/2)`
//! and `x = outer - theta` (the integral of `(outer - s) sin s` from `theta` to `outer`); it has
//! no closed-form inverse, so sampling bisects it [`SpotCone::BISECTIONS`] times.
//!
//! A spot may project a texture over its cone ([`SpotTexture`], Mitsuba 3's `texture`): a
//! direction of local coordinates `(x, y, z)` (z along the axis) reads it at
//! `uv = 1/2 + (x, y) / (2 z tan(outer))`, so the image's square holds the outer cone's
//! disc, and the intensity there is multiplied by the texel. Photons still leave by the
//! falloff, each carrying its texel over the texture's mean under the falloff
//! (`crate::lights::emission`), which the light's power includes.

mod build;

pub use build::SpotLight;

use crate::lights::area::texel;
use crate::lights::interface::{word, Emission, LightContext, LightKind, LightSample, ParamWords};
use crate::math::sampling::to_world;
use glam::{Vec2, Vec3};

/// A spot light: a point source whose intensity in direction `w` is `intensity` times the
/// falloff of its [`SpotCone`] at `cos = dot(direction, w)`; invisible to the camera.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Spot {
    /// Where it is.
    pub position: Vec3,
    /// Unit axis of the cone, the direction it shines in.
    pub direction: Vec3,
    /// Radiant intensity on the axis, W/sr per channel.
    pub intensity: Vec3,
    /// Its cone (full intensity inside the inner half-angle, none outside the outer).
    pub cone: SpotCone,
    /// The texture it projects, if any (its index is the light's emission texture,
    /// `crate::lights::emission::texture_of`).
    pub projection: Option<SpotTexture>,
}

/// The texture a spot projects over its cone (module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotTexture {
    /// Index of the texture in the scene's textures.
    pub texture: u32,
    /// The light's local x axis: a unit vector across the axis (u grows along it).
    pub x_axis: Vec3,
    /// Whether its local y axis is `-direction × x_axis` (a mirrored frame) rather than
    /// `direction × x_axis`.
    pub mirrored: bool,
}

impl Spot {
    /// The uv at which a projecting spot reads its texture in unit direction `w` (module
    /// docs; `None` without a texture).
    pub fn uv(&self, w: Vec3) -> Option<Vec2> {
        let t = self.projection?;
        let y = self.direction.cross(t.x_axis) * if t.mirrored { -1.0 } else { 1.0 };
        Some(spot_uv(
            Vec3::new(w.dot(t.x_axis), w.dot(y), w.dot(self.direction)),
            self.cone.cos_outer,
        ))
    }

    /// The mean of its projected `texture` over directions drawn as its photons are (by the
    /// falloff), by the midpoints of a 64 x 64 grid of the two numbers that draw them: the
    /// mean the photons' texels are divided by (one without a projection).
    pub fn projected_mean(&self, texture: &crate::textures::SceneTexture) -> Vec3 {
        let n = 64;
        let mut sum = glam::DVec3::ZERO;
        for j in 0..n {
            let cd = self.cone.sample_cos((j as f32 + 0.5) / n as f32);
            let s = (1.0 - cd * cd).max(0.0).sqrt();
            for i in 0..n {
                let phi = 2.0 * std::f32::consts::PI * (i as f32 + 0.5) / n as f32;
                let w = to_world(Vec3::new(s * phi.cos(), s * phi.sin(), cd), self.direction);
                match self.uv(w) {
                    Some(uv) => sum += texture.eval(uv).as_dvec3(),
                    None => return Vec3::ONE,
                }
            }
        }
        (sum / (n * n) as f64).as_vec3()
    }

    /// The texel its projected texture has in unit direction `w` (one without a texture).
    fn texel(&self, c: &LightContext, w: Vec3) -> Vec3 {
        match self.uv(w) {
            Some(uv) => texel(c, uv),
            None => Vec3::ONE,
        }
    }
}

/// The uv of local direction `local` (z along the axis) for a cone of outer cosine
/// `cos_outer` (module docs).
pub fn spot_uv(local: Vec3, cos_outer: f32) -> Vec2 {
    let tan_outer = (1.0 - cos_outer * cos_outer).max(0.0).sqrt() / cos_outer;
    Vec2::splat(0.5) + 0.5 * Vec2::new(local.x, local.y) / (local.z * tan_outer)
}

impl LightKind for Spot {
    fn is_delta(&self) -> bool {
        true
    }
    /// Photons by the falloff (`u[3]` the cosine to the axis, `u[4]` the azimuth), so that
    /// every photon of a spot without a texture carries the same power; a projecting one's
    /// carries its texel over the texture's mean.
    fn emit(&self, c: &LightContext, u: [f32; 5]) -> Emission {
        let cd = self.cone.sample_cos(u[3]);
        let s = (1.0 - cd * cd).max(0.0).sqrt();
        let phi = 2.0 * std::f32::consts::PI * u[4];
        let local = Vec3::new(s * phi.cos(), s * phi.sin(), cd);
        let dir = to_world(local, self.direction);
        let mean = c.texture_mean;
        let scale = match self.projection {
            Some(_) => Vec3::select(
                mean.cmpgt(Vec3::ZERO),
                self.texel(c, dir) / mean,
                Vec3::ZERO,
            ),
            None => Vec3::ONE,
        };
        Emission {
            origin: self.position,
            dir,
            normal: Vec3::ZERO,
            scale,
        }
    }
    fn sample(&self, c: &LightContext, x: Vec3, _ns: Vec3, _u: [f32; 3]) -> LightSample {
        let to_x = x - self.position;
        let d2 = to_x.length_squared().max(1e-20);
        let w = to_x / d2.sqrt();
        let att = self.cone.falloff(self.direction.dot(w));
        let texel = match att > 0.0 {
            true => self.texel(c, w),
            false => Vec3::ONE,
        };
        LightSample::delta(self.position, self.intensity * texel * (att / d2), false)
    }
    fn anchor(&self, _c: &LightContext, _u: [f32; 3]) -> Option<Vec3> {
        Some(self.position)
    }
    fn gpu_words(&self, _c: &LightContext) -> ParamWords {
        [
            word(self.position, self.cone.profile.code()),
            word(self.direction, self.cone.cos_inner.to_bits()),
            word(self.intensity, self.cone.cos_outer.to_bits()),
            match self.projection {
                Some(t) => word(t.x_axis, if t.mirrored { 2 } else { 1 }),
                None => [0; 4],
            },
        ]
    }
}

/// Whether some spot light of `lights` has Mitsuba's falloff: the override `HAS_LINEAR_SPOTS`
/// compiles its sampling code only then.
pub fn gpu_overrides(lights: &[crate::lights::Light]) -> Vec<(&'static str, f64)> {
    let linear = lights.iter().any(|l| {
        matches!(l.shape, crate::lights::LightShape::Spot(s) if s.cone.profile == SpotFalloff::LinearAngle)
    });
    vec![("HAS_LINEAR_SPOTS", linear as u32 as f64)]
}

/// The falloffs' constants the WGSL twin uses.
pub fn wgsl_consts() -> String {
    format!(
        "const SPOT_MIN_RAMP: f32 = {:?};\nconst SPOT_BISECTIONS: u32 = {}u;\n\
         const SPOT_GLTF: u32 = {}u;\nconst SPOT_LINEAR_ANGLE: u32 = {}u;\n",
        SpotCone::MIN_RAMP,
        SpotCone::BISECTIONS,
        SpotFalloff::Gltf.code(),
        SpotFalloff::LinearAngle.code()
    )
}
use std::f64::consts::PI;

/// How a spot's intensity falls off between its inner and outer half-angles.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SpotFalloff {
    /// glTF's reference form: quadratic in the cosine (module docs).
    #[default]
    Gltf,
    /// Mitsuba 3's: linear in the angle (module docs).
    LinearAngle,
}

impl SpotFalloff {
    /// Every falloff, in [`Self::code`] order.
    pub const ALL: [SpotFalloff; 2] = [SpotFalloff::Gltf, SpotFalloff::LinearAngle];
    /// Their names in scene files (TOML `falloff`), in the same order.
    pub const NAMES: [&'static str; 2] = ["gltf", "linear-angle"];

    /// The code the GPU's light record carries (`SPOT_GLTF`, `SPOT_LINEAR_ANGLE` in WGSL).
    pub fn code(self) -> u32 {
        self as u32
    }

    /// Its name in scene files.
    pub fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The falloff called `name`, if any.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// A spot light's cone, by the cosines of its inner and outer half-angles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotCone {
    /// Cosine of the inner half-angle (full intensity inside).
    pub cos_inner: f32,
    /// Cosine of the outer half-angle (nothing outside).
    pub cos_outer: f32,
    /// The ramp between them.
    pub profile: SpotFalloff,
}

impl SpotCone {
    /// Smallest cosine difference of the glTF ramp (glTF's `max(0.001, ...)`).
    pub const MIN_RAMP: f32 = 0.001;
    /// Bisection steps that invert the linear ramp's mass (a 2^-24 fraction of the ramp).
    pub const BISECTIONS: u32 = 24;

    /// The cone of `inner` and `outer` half-angles in degrees with glTF's falloff.
    pub fn from_degrees(inner: f32, outer: f32) -> Self {
        Self::with_profile(inner, outer, SpotFalloff::Gltf)
    }

    /// The cone of `inner` and `outer` half-angles in degrees with the falloff `profile`.
    pub fn with_profile(inner: f32, outer: f32, profile: SpotFalloff) -> Self {
        SpotCone {
            cos_inner: inner.to_radians().cos(),
            cos_outer: outer.to_radians().cos(),
            profile,
        }
    }

    /// Width of the glTF ramp in cosine: `cos_inner - cos_outer`, at least
    /// [`Self::MIN_RAMP`].
    pub fn ramp(&self) -> f32 {
        (self.cos_inner - self.cos_outer).max(Self::MIN_RAMP)
    }

    /// The falloff at cosine `cd` to the axis (module docs).
    pub fn falloff(&self, cd: f32) -> f32 {
        match self.profile {
            SpotFalloff::Gltf => {
                let scale = 1.0 / self.ramp();
                let offset = -self.cos_outer * scale;
                let a = (cd * scale + offset).clamp(0.0, 1.0);
                a * a
            }
            SpotFalloff::LinearAngle => {
                if cd >= self.cos_inner {
                    1.0
                } else if cd > self.cos_outer {
                    let (inner, outer) = (self.cos_inner.acos(), self.cos_outer.acos());
                    ((outer - cd.clamp(-1.0, 1.0).acos()) / (outer - inner)).clamp(0.0, 1.0)
                } else {
                    0.0
                }
            }
        }
    }

    /// The falloff's integral over the cosine, `∫ att(c) dc` over `[cos_outer, 1]`, in two
    /// parts: the ramp and the flat top `1 - a`, with `a` the cosine where the ramp ends.
    fn masses(&self) -> (f64, f64, f64) {
        match self.profile {
            SpotFalloff::Gltf => {
                // The ramp is (a - co)^3 / (3 w^2), w = ramp(), a = min(1, co + w).
                let (co, w) = (self.cos_outer as f64, self.ramp() as f64);
                let a = (co + w).min(1.0);
                ((a - co).powi(3) / (3.0 * w * w), 1.0 - a, a)
            }
            SpotFalloff::LinearAngle => {
                let (inner, outer) = self.angles();
                let ramp = match outer > inner {
                    true => linear_ramp_mass(outer, outer - inner) / (outer - inner),
                    false => 0.0,
                };
                (ramp, 1.0 - inner.cos(), inner.cos())
            }
        }
    }

    /// The half-angles in radians, inner and outer (from the cosines, as the GPU has them).
    fn angles(&self) -> (f64, f64) {
        let inner = (self.cos_inner as f64).clamp(-1.0, 1.0).acos();
        (inner, (self.cos_outer as f64).clamp(-1.0, 1.0).acos())
    }

    /// The falloff integrated over the sphere of directions, in sr:
    /// `2 pi ∫ att(c) dc` (exact). A spot's power is its on-axis intensity times this.
    pub fn solid_angle(&self) -> f64 {
        let (ramp, top, _) = self.masses();
        2.0 * PI * (ramp + top)
    }

    /// The cosine to the axis of a direction drawn with density proportional to the falloff,
    /// from one uniform number `u` (inverting the falloff's integral over the cosine).
    pub fn sample_cos(&self, u: f32) -> f32 {
        let (ramp, top, a) = self.masses();
        let t = u as f64 * (ramp + top);
        if t >= ramp {
            return (a + (t - ramp)).min(1.0) as f32;
        }
        let c = match self.profile {
            SpotFalloff::Gltf => {
                let (co, w) = (self.cos_outer as f64, self.ramp() as f64);
                co + (3.0 * w * w * t).cbrt()
            }
            SpotFalloff::LinearAngle => {
                // Bisect x = outer - theta in [0, outer - inner] for D(x) = t (outer - inner).
                let (inner, outer) = self.angles();
                let want = t * (outer - inner);
                let (mut lo, mut hi) = (0.0, outer - inner);
                for _ in 0..Self::BISECTIONS {
                    let mid = 0.5 * (lo + hi);
                    match linear_ramp_mass(outer, mid) < want {
                        true => lo = mid,
                        false => hi = mid,
                    }
                }
                (outer - 0.5 * (lo + hi)).cos()
            }
        };
        c.min(1.0) as f32
    }
}

/// `∫ (outer - s) sin s ds` from `outer - x` to `outer`, written without the cancellation of
/// its textbook form for small `x` (module docs).
fn linear_ramp_mass(outer: f64, x: f64) -> f64 {
    x * (outer - x).cos() - 2.0 * (outer - 0.5 * x).cos() * (0.5 * x).sin()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn falloff_is_one_inside_zero_outside_and_quadratic_between() {
        let c = SpotCone::from_degrees(20.0, 30.0);
        assert_eq!(c.falloff(1.0), 1.0);
        assert_eq!(c.falloff(c.cos_inner + 1e-4), 1.0);
        assert_eq!(c.falloff(c.cos_outer - 1e-4), 0.0);
        let mid = 0.5 * (c.cos_inner + c.cos_outer);
        assert!((c.falloff(mid) - 0.25).abs() < 1e-4);
    }

    #[test]
    fn falloff_names_round_trip() {
        for f in SpotFalloff::ALL {
            assert_eq!(SpotFalloff::from_name(f.name()), Some(f));
        }
        assert_eq!(SpotFalloff::from_name("linear"), None);
    }

    #[test]
    fn linear_falloff_is_linear_in_the_angle() {
        let c = SpotCone::with_profile(20.0, 30.0, SpotFalloff::LinearAngle);
        assert_eq!(c.falloff(1.0), 1.0);
        assert_eq!(c.falloff(c.cos_inner + 1e-4), 1.0);
        assert_eq!(c.falloff(c.cos_outer - 1e-4), 0.0);
        for (deg, want) in [(22.5f32, 0.75), (25.0, 0.5), (29.0, 0.1)] {
            let got = c.falloff(deg.to_radians().cos());
            assert!((got - want).abs() < 1e-4, "{deg}: {got}");
        }
        // A hard edge: Mitsuba's beam_width equal to its cutoff_angle.
        let hard = SpotCone::with_profile(30.0, 30.0, SpotFalloff::LinearAngle);
        assert_eq!(hard.falloff(29.9f32.to_radians().cos()), 1.0);
        assert_eq!(hard.falloff(30.1f32.to_radians().cos()), 0.0);
        let h = hard.solid_angle();
        assert!((h - 2.0 * PI * (1.0 - 30f64.to_radians().cos())).abs() < 1e-6);
    }

    /// Every cone the quadrature and histogram tests try, in both profiles.
    fn cones() -> Vec<(f32, f32, SpotCone)> {
        let angles = [
            (0.0, 45.0),
            (20.0, 30.0),
            (30.0, 30.0),
            (89.0, 90.0),
            (0.0, 1.0),
        ];
        let mut all = Vec::new();
        for profile in SpotFalloff::ALL {
            for (inner, outer) in angles {
                all.push((inner, outer, SpotCone::with_profile(inner, outer, profile)));
            }
        }
        all
    }

    #[test]
    fn solid_angle_matches_a_fine_quadrature() {
        for (inner, outer, c) in cones() {
            // The falloff is 0 below cos_outer: integrate from just under it to 1.
            let (n, lo) = (200_000, (c.cos_outer as f64 - 1e-3).max(-1.0));
            let q: f64 = (0..n)
                .map(|i| {
                    let cd = lo + (1.0 - lo) * (i as f64 + 0.5) / n as f64;
                    c.falloff(cd as f32) as f64 * (1.0 - lo) / n as f64
                })
                .sum::<f64>()
                * 2.0
                * PI;
            let want = c.solid_angle();
            assert!(
                (q - want).abs() < 1e-4 * want.max(1e-3),
                "{inner} {outer}: {q} vs {want}"
            );
        }
        // A hard-edged cone of 90 degrees: the ramp is 0.001 wide, the rest a full hemisphere.
        let h = SpotCone::from_degrees(90.0, 90.0).solid_angle();
        assert!(
            (h - 2.0 * PI * (1.0 - 0.001 + 0.001 / 3.0)).abs() < 1e-6,
            "{h}"
        );
    }

    #[test]
    fn sampled_cosines_follow_the_falloff() {
        // Histogram of sample_cos over a fine grid of u against the falloff's mass per bin.
        for profile in SpotFalloff::ALL {
            histogram_follows_the_falloff(SpotCone::with_profile(10.0, 40.0, profile));
            histogram_follows_the_falloff(SpotCone::with_profile(25.0, 30.0, profile));
        }
    }

    fn histogram_follows_the_falloff(c: SpotCone) {
        let bins = 20;
        let mut hist = vec![0.0f64; bins];
        let n = 200_000;
        for i in 0..n {
            let x = c.sample_cos((i as f32 + 0.5) / n as f32);
            assert!(x >= c.cos_outer && x <= 1.0);
            let b = ((x - c.cos_outer) / (1.0 - c.cos_outer) * bins as f32) as usize;
            hist[b.min(bins - 1)] += 1.0 / n as f64;
        }
        let total = c.solid_angle() / (2.0 * PI);
        for (b, h) in hist.iter().enumerate() {
            let (lo, hi) = (b as f64 / bins as f64, (b + 1) as f64 / bins as f64);
            let span = 1.0 - c.cos_outer as f64;
            let m = 1000;
            let mass: f64 = (0..m)
                .map(|j| {
                    let x =
                        c.cos_outer as f64 + span * (lo + (hi - lo) * (j as f64 + 0.5) / m as f64);
                    c.falloff(x as f32) as f64 * span * (hi - lo) / m as f64
                })
                .sum();
            assert!(
                (h - mass / total).abs() < 2e-3,
                "{c:?} bin {b}: {h} vs {}",
                mass / total
            );
        }
    }
}
