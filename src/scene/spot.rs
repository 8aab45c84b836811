//! The spot light's cone: its angular falloff, the falloff's integral over the sphere (the
//! light's power is its on-axis intensity times that), and directions sampled in proportion
//! to it. Used by the scene builder (power) and `src/light.rs` (shadow rays, photons); the
//! WGSL twin is `spot_falloff` / `spot_cos` in `shaders/common/light.wgsl`.
//!
//! The falloff is the reference form of glTF's `KHR_lights_punctual`: with `cd` the cosine
//! between the spot axis and the direction to the lit point,
//! `scale = 1 / max(0.001, cos_inner - cos_outer)`, `offset = -cos_outer * scale`,
//! `att = clamp(cd * scale + offset, 0, 1)^2`: 1 inside the inner cone, 0 outside the outer
//! one, a ramp quadratic in the cosine between them.

use std::f64::consts::PI;

/// A spot light's cone, by the cosines of its inner and outer half-angles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpotCone {
    /// Cosine of the inner half-angle (full intensity inside).
    pub cos_inner: f32,
    /// Cosine of the outer half-angle (nothing outside).
    pub cos_outer: f32,
}

impl SpotCone {
    /// Smallest cosine difference of the ramp (glTF's `max(0.001, ...)`).
    pub const MIN_RAMP: f32 = 0.001;

    /// The cone of `inner` and `outer` half-angles in degrees.
    pub fn from_degrees(inner: f32, outer: f32) -> Self {
        SpotCone {
            cos_inner: inner.to_radians().cos(),
            cos_outer: outer.to_radians().cos(),
        }
    }

    /// Width of the ramp in cosine: `cos_inner - cos_outer`, at least [`Self::MIN_RAMP`].
    pub fn ramp(&self) -> f32 {
        (self.cos_inner - self.cos_outer).max(Self::MIN_RAMP)
    }

    /// The falloff at cosine `cd` to the axis (glTF's reference form, module docs).
    pub fn falloff(&self, cd: f32) -> f32 {
        let scale = 1.0 / self.ramp();
        let offset = -self.cos_outer * scale;
        let a = (cd * scale + offset).clamp(0.0, 1.0);
        a * a
    }

    /// The two parts of the falloff's integral over the cosine, `∫ att(c) dc` over
    /// `[cos_outer, 1]`: the ramp `(a - co)^3 / (3 w^2)` and the flat top `1 - a`, with
    /// `w` = [`Self::ramp`] and `a = min(1, co + w)` (where the ramp reaches 1).
    fn masses(&self) -> (f64, f64, f64) {
        let (co, w) = (self.cos_outer as f64, self.ramp() as f64);
        let a = (co + w).min(1.0);
        ((a - co).powi(3) / (3.0 * w * w), 1.0 - a, a)
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
        let (co, w) = (self.cos_outer as f64, self.ramp() as f64);
        let t = u as f64 * (ramp + top);
        let c = if t < ramp {
            co + (3.0 * w * w * t).cbrt()
        } else {
            a + (t - ramp)
        };
        c.min(1.0) as f32
    }
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
    fn solid_angle_matches_a_fine_quadrature() {
        for (inner, outer) in [
            (0.0, 45.0),
            (20.0, 30.0),
            (30.0, 30.0),
            (89.0, 90.0),
            (0.0, 1.0),
        ] {
            let c = SpotCone::from_degrees(inner, outer);
            let n = 200_000;
            let q: f64 = (0..n)
                .map(|i| {
                    let cd = -1.0 + 2.0 * (i as f64 + 0.5) / n as f64;
                    c.falloff(cd as f32) as f64 * 2.0 / n as f64
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
        let c = SpotCone::from_degrees(10.0, 40.0);
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
                "bin {b}: {h} vs {}",
                mass / total
            );
        }
    }
}
