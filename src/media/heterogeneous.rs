//! Heterogeneous media (issue 41), as Mitsuba 3's `heterogeneous` defines them: extinction
//! `scale * sigma_t(x)` and albedo `albedo(x)` from volumes ([`Volume`]: constant or a voxel
//! grid), zero extinction outside the extinction volume's box, and one phase function.
//!
//! Tracking runs against a grey majorant, the largest extinction of any channel anywhere
//! (`scale` times the volume's maximum, as Mitsuba's), over the part of the ray inside the
//! box; tentative collisions are drawn from it and never bias the result:
//! - **transmittance** by ratio tracking (Novak et al. 2014): the product over tentative
//!   collisions of `1 - sigma_t(x) / majorant`, per channel, with Russian roulette once the
//!   largest channel falls below [`ROULETTE_BELOW`];
//! - **free flights** by delta tracking with spectral-tracking weights (Kutz et al. 2017): a
//!   tentative collision is real with probability `mean(sigma_t) / majorant`; a real one
//!   weighs `sigma_s / mean(sigma_t)`, a null one `(majorant - sigma_t) / (majorant -
//!   mean(sigma_t))` per channel, so a grey medium is plain delta tracking (weights 1 and
//!   the albedo) and a coloured one stays unbiased in every channel;
//! - **points in a segment** from the majorant's exponential truncated to the box, whose
//!   density is known; their transmittance then comes from ratio tracking.

use crate::math::rng::Rng;
use crate::media::grid::{Volume, VolumeKind};
use crate::media::{Flight, SegmentPoint};
use glam::Vec3;

/// Tentative collisions one tracking walk may take: a bound on the work of one ray, reached
/// only past an optical depth of the majorant of about this many (a walk that reaches it
/// counts as absorbed).
pub const MAX_TRACKING_STEPS: u32 = 1 << 16;

/// Ratio tracking plays Russian roulette once the largest channel of the transmittance
/// estimate falls below this.
pub const ROULETTE_BELOW: f32 = 0.1;

/// A heterogeneous medium's extinction and albedo (the phase function is the medium's).
#[derive(Clone, Debug, PartialEq)]
pub struct Heterogeneous {
    /// Extinction per channel per scene unit, before `scale`.
    pub sigma_t: Volume,
    /// Single-scattering albedo per channel.
    pub albedo: Volume,
    /// Multiplies the extinction.
    pub scale: f32,
    /// The tracking majorant: `scale` times `sigma_t`'s largest value.
    pub majorant: f32,
}

impl Heterogeneous {
    /// A medium of extinction `scale * sigma_t` and albedo `albedo`.
    pub fn new(sigma_t: Volume, albedo: Volume, scale: f32) -> Heterogeneous {
        let majorant = scale * sigma_t.max();
        Heterogeneous {
            sigma_t,
            albedo,
            scale,
            majorant,
        }
    }

    /// Bytes its grids hold.
    pub fn grid_bytes(&self) -> u64 {
        [&self.sigma_t, &self.albedo]
            .iter()
            .map(|v| match &v.kind {
                VolumeKind::Grid { grid, .. } => 4 * grid.data.len() as u64,
                VolumeKind::Constant(_) => 0,
            })
            .sum()
    }

    /// Extinction at `x` per channel (zero outside the extinction volume's box).
    pub fn sigma_t_at(&self, x: Vec3) -> Vec3 {
        let v = &self.sigma_t;
        match x.cmpge(v.lo).all() && x.cmple(v.hi).all() {
            true => self.scale * v.eval(x),
            false => Vec3::ZERO,
        }
    }

    /// Scattering coefficient at `x`: the albedo there times the extinction.
    pub fn sigma_s_at(&self, x: Vec3) -> Vec3 {
        self.sigma_t_at(x) * self.albedo.eval(x)
    }

    /// The part `[t0, t1)` of `[0, t_max)` along the ray from `o` along unit `d` inside the
    /// extinction's box, `None` where it misses or the majorant is zero.
    fn span(&self, o: Vec3, d: Vec3, t_max: f32) -> Option<(f32, f32)> {
        if !(self.majorant > 0.0) {
            return None;
        }
        let inv = d.recip();
        let (a, b) = ((self.sigma_t.lo - o) * inv, (self.sigma_t.hi - o) * inv);
        // An axis the ray runs parallel to gives NaN (0 * inf) only when it starts on a face.
        let t0 = a.min(b).max_element().max(0.0);
        let t1 = a.max(b).min_element().min(t_max);
        (t0 < t1).then_some((t0, t1))
    }

    /// An unbiased estimate of the transmittance over `[0, t)` (ratio tracking).
    pub fn transmittance(&self, o: Vec3, d: Vec3, t: f32, rng: &mut Rng) -> Vec3 {
        self.ratio_track(o, d, t, rng, |_, _| {})
    }

    /// The steps of one ratio-tracking walk over `[0, t_max)`: `(s, T)` for each tentative
    /// collision at distance `s`, `T` the estimate beyond it, in order; the estimate before
    /// the first is 1. Every distance's estimate is unbiased (the beam estimate reads many
    /// distances from one walk: [`Transmittances`](crate::media::Transmittances)).
    pub fn steps(&self, o: Vec3, d: Vec3, t_max: f32, rng: &mut Rng) -> Vec<(f32, Vec3)> {
        let mut steps = Vec::new();
        self.ratio_track(o, d, t_max, rng, |s, tr| steps.push((s, tr)));
        steps
    }

    /// Ratio tracking over `[0, t)`, calling `visit(s, T)` after each tentative collision.
    fn ratio_track(
        &self,
        o: Vec3,
        d: Vec3,
        t: f32,
        rng: &mut Rng,
        mut visit: impl FnMut(f32, Vec3),
    ) -> Vec3 {
        let Some((t0, t1)) = self.span(o, d, t) else {
            return Vec3::ONE;
        };
        let mu = self.majorant;
        let (mut s, mut tr) = (t0, Vec3::ONE);
        for _ in 0..MAX_TRACKING_STEPS {
            s -= (1.0 - rng.next()).ln() / mu;
            if s >= t1 {
                return tr;
            }
            // The majorant bounds the density; the max only absorbs the filter's rounding.
            tr *= (Vec3::ONE - self.sigma_t_at(o + d * s) / mu).max(Vec3::ZERO);
            let q = tr.max_element();
            if q < ROULETTE_BELOW {
                tr = match rng.next() < q {
                    true => tr / q,
                    false => Vec3::ZERO,
                };
            }
            visit(s, tr);
            if tr == Vec3::ZERO {
                return tr;
            }
        }
        visit(s, Vec3::ZERO);
        Vec3::ZERO
    }

    /// A free flight from `o` along unit `d` towards a surface `t_max` away (delta tracking
    /// with spectral-tracking weights; see the module's header).
    pub fn sample_flight(&self, o: Vec3, d: Vec3, t_max: f32, rng: &mut Rng) -> Flight {
        let through = |weight| Flight {
            t: t_max,
            in_medium: false,
            weight,
        };
        let Some((t0, t1)) = self.span(o, d, t_max) else {
            return through(Vec3::ONE);
        };
        let mu = self.majorant;
        let (mut s, mut w) = (t0, Vec3::ONE);
        for _ in 0..MAX_TRACKING_STEPS {
            s -= (1.0 - rng.next()).ln() / mu;
            if s >= t1 {
                return through(w);
            }
            let x = o + d * s;
            let sigma = self.sigma_t_at(x);
            let mean = sigma.element_sum() / 3.0;
            if rng.next() * mu < mean {
                let weight = w * sigma * self.albedo.eval(x) / mean;
                return Flight {
                    t: s,
                    in_medium: true,
                    weight,
                };
            }
            w *= (Vec3::splat(mu) - sigma).max(Vec3::ZERO) / (mu - mean);
        }
        through(Vec3::ZERO)
    }

    /// A distance in `[0, t_max)` drawn from the majorant's exponential within the box, with
    /// its density; `None` when the segment misses the box (nothing scatters there).
    pub fn sample_in_segment(&self, o: Vec3, d: Vec3, u: f32, t_max: f32) -> Option<SegmentPoint> {
        let (t0, t1) = self.span(o, d, t_max)?;
        let mu = self.majorant;
        let mass = -(-mu * (t1 - t0)).exp_m1();
        let s = -(-u * mass).ln_1p() / mu;
        let t = (t0 + s).min(t1 * (1.0 - f32::EPSILON)).max(t0);
        let pdf = mu * (-mu * (t - t0)).exp() / mass;
        (pdf > 0.0 && pdf.is_finite()).then_some(SegmentPoint { t, pdf })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::Stream;
    use crate::media::grid::{Filter, VolumeGrid};
    use glam::Affine3A;
    use std::sync::Arc;

    /// A density ramp along x over the unit cube: 2 x 1 x 1 voxels of `a` and `b` filtered
    /// trilinearly, so `sigma_t(x) = a` for x < 1/4, `b` beyond 3/4, linear between.
    fn ramp(a: Vec3, b: Vec3, albedo: Vec3) -> Heterogeneous {
        let grid = VolumeGrid {
            res: [2, 1, 1],
            channels: 3,
            bbox: [Vec3::ZERO, Vec3::ONE],
            data: vec![a.x, a.y, a.z, b.x, b.y, b.z],
        };
        let kind = VolumeKind::Grid {
            grid: Arc::new(grid),
            to_local: Affine3A::IDENTITY,
            filter: Filter::Trilinear,
        };
        let unit = Affine3A::IDENTITY;
        Heterogeneous::new(
            Volume::new(kind, unit),
            Volume::new(VolumeKind::Constant(albedo), unit),
            1.0,
        )
    }

    /// The optical depth along x from -1 to `x` (clipped to the cube) of [`ramp`].
    fn depth(a: f32, b: f32, x: f32) -> f32 {
        let x = x.clamp(0.0, 1.0);
        let below = a * x.min(0.25);
        // Between the centres sigma rises linearly from a to b over half a unit.
        let lin = |s: f32| a * (s - 0.25) + (b - a) * (s - 0.25).powi(2);
        below + lin(x.clamp(0.25, 0.75)) + b * (x - 0.75).max(0.0)
    }

    #[test]
    fn ratio_tracking_matches_the_ramps_optical_depth() {
        let (a, b) = (Vec3::new(0.5, 2.0, 4.0), Vec3::new(3.0, 0.0, 6.0));
        let m = ramp(a, b, Vec3::splat(0.5));
        let o = Vec3::new(-1.0, 0.5, 0.5);
        let mut rng = Rng::new(7, Stream::Photon, 0, 0);
        for x in [0.2f32, 0.6, 0.9, 3.0] {
            let n = 100_000;
            let mut sum = Vec3::ZERO;
            let mut sum2 = Vec3::ZERO;
            for _ in 0..n {
                let t = m.transmittance(o, Vec3::X, x + 1.0, &mut rng);
                sum += t;
                sum2 += t * t;
            }
            let mean = sum / n as f32;
            let sd = ((sum2 / n as f32 - mean * mean).max(Vec3::ZERO) / n as f32).powf(0.5);
            for c in 0..3 {
                let want = (-depth(a[c], b[c], x)).exp();
                assert!(
                    (mean[c] - want).abs() <= 4.0 * sd[c] + 1e-4,
                    "x {x} channel {c}: {} vs {want} (sd {})",
                    mean[c],
                    sd[c]
                );
            }
        }
    }

    /// Free flights in a grey ramp: the distances' distribution against the analytic CDF
    /// `1 - exp(-tau(x))` by a chi-square test over ten bins of equal probability, and in a
    /// coloured one the weights' means per channel against the scattered fraction and the
    /// transmittance.
    #[test]
    fn delta_tracking_samples_the_ramps_free_flights() {
        let (a, b) = (0.5f32, 3.0f32);
        let m = ramp(Vec3::splat(a), Vec3::splat(b), Vec3::ONE);
        let o = Vec3::new(-1.0, 0.5, 0.5);
        let mut rng = Rng::new(9, Stream::Photon, 0, 0);
        let total = 1.0 - (-depth(a, b, 1.0)).exp();
        // Bin edges: x where the CDF of an event reaches k/10 of the events' mass.
        let edges: Vec<f32> = (1..10)
            .map(|k| {
                let want = total * k as f32 / 10.0;
                let (mut lo, mut hi) = (0.0f32, 1.0f32);
                for _ in 0..40 {
                    let mid = 0.5 * (lo + hi);
                    match 1.0 - (-depth(a, b, mid)).exp() < want {
                        true => lo = mid,
                        false => hi = mid,
                    }
                }
                0.5 * (lo + hi)
            })
            .collect();
        let n = 200_000;
        let (mut counts, mut events) = ([0u32; 10], 0u32);
        for _ in 0..n {
            let f = m.sample_flight(o, Vec3::X, 5.0, &mut rng);
            if f.in_medium {
                let x = f.t - 1.0;
                counts[edges.iter().filter(|&&e| x >= e).count()] += 1;
                events += 1;
                assert!((f.weight - Vec3::ONE).abs().max_element() < 1e-4, "{}", f.weight);
            } else {
                assert_eq!(f.t, 5.0);
                assert!((f.weight - Vec3::ONE).abs().max_element() < 1e-4, "{}", f.weight);
            }
        }
        let p_event = events as f64 / n as f64;
        assert!((p_event - total as f64).abs() < 4.0 * (total as f64 / n as f64).sqrt());
        let expect = events as f64 / 10.0;
        let chi2: f64 = counts.iter().map(|&c| (c as f64 - expect).powi(2) / expect).sum();
        // 9 degrees of freedom: P(chi2 > 27.9) = 0.001.
        assert!(chi2 < 27.9, "chi2 {chi2}: {counts:?}");

        // Coloured, with one clear channel: per channel, the events' weights sum to the
        // scattered fraction and the pass-through weights to the transmittance.
        let (a, b) = (Vec3::new(0.5, 2.0, 0.0), Vec3::new(3.0, 0.2, 0.0));
        let albedo = Vec3::new(0.9, 0.5, 0.7);
        let m = ramp(a, b, albedo);
        let (mut scattered, mut through) = (Vec3::ZERO, Vec3::ZERO);
        for _ in 0..n {
            let f = m.sample_flight(o, Vec3::X, 1.6, &mut rng);
            match f.in_medium {
                true => scattered += f.weight / n as f32,
                false => through += f.weight / n as f32,
            }
        }
        for c in 0..3 {
            let tr = (-depth(a[c], b[c], 0.6)).exp();
            assert!((through[c] - tr).abs() < 0.01, "{through} vs {tr}");
            let s = albedo[c] * (1.0 - tr);
            assert!((scattered[c] - s).abs() < 0.01, "{scattered} vs {s}");
        }
    }

    /// Points drawn in a segment: the density integrates to one over the part in the box,
    /// and a segment that misses the box gives none.
    #[test]
    fn segment_points_have_their_density() {
        let m = ramp(Vec3::splat(1.0), Vec3::splat(2.0), Vec3::ONE);
        let o = Vec3::new(-1.0, 0.5, 0.5);
        let mut integral = 0.0f64;
        let n = 4096;
        for i in 0..n {
            let p = m.sample_in_segment(o, Vec3::X, (i as f32 + 0.5) / n as f32, 1.5).unwrap();
            assert!(p.t >= 1.0 && p.t < 1.5, "{p:?}");
            integral += 1.0 / p.pdf as f64 / n as f64;
        }
        // E[1 / pdf] = the length of the part in the box.
        assert!((integral - 0.5).abs() < 1e-3, "{integral}");
        assert_eq!(m.sample_in_segment(o, Vec3::Y, 0.5, 9.0), None);
    }
}
