//! Heterogeneous media (issue 41), as Mitsuba 3's `heterogeneous` defines them: extinction
//! `scale * sigma_t(x)` and albedo `albedo(x)` from volumes ([`Volume`]: constant or a voxel
//! grid), zero extinction outside the extinction volume's box, and one phase function.
//!
//! Tracking runs against grey majorants over the part of the ray inside the box: per cell of
//! a coarse grid walked by DDA ([`MajorantGrid`], each cell's largest extinction of any
//! channel), where Mitsuba takes one global majorant (`scale` times the volume's maximum);
//! tentative collisions are drawn from them and never bias the result:
//! - **transmittance** by ratio tracking (Novak et al. 2014): the product over tentative
//!   collisions of `1 - sigma_t(x) / majorant`, per channel, with Russian roulette once the
//!   largest channel falls below [`ROULETTE_BELOW`];
//! - **free flights** by delta tracking with spectral-tracking weights (Kutz et al. 2017,
//!   their history-aware average): with the flight's weight `w` so far (1 at its start), a
//!   tentative collision is real with probability `P = sum(w sigma_t) / (majorant sum(w))`;
//!   a real one weighs `w sigma_s / (majorant P)`, a null one multiplies `w` by
//!   `(majorant - sigma_t) / (majorant (1 - P))` per channel. A null event keeps `sum(w)`
//!   at 3, so no weight exceeds 3 (an event's 3 times the albedo), where the plain
//!   average's null weights grew geometrically in a channel much clearer than the others; a
//!   grey medium is plain delta tracking (weights 1 and the albedo), a coloured one unbiased
//!   per channel;
//! - **points in a segment** where light scatters towards the camera (single scattering's
//!   distance for a directional light or the environment, the near gather's, a gather ray's
//!   point estimates) are free flights too ([`Heterogeneous::track`]): in a sparse medium a
//!   majorant's exponential would seldom reach the far side of a dense cell.

use crate::math::rng::Rng;
use crate::media::flight::{Flight, Scatter};
use crate::media::grid::{Volume, VolumeKind};
use crate::media::majorant::MajorantGrid;
use glam::Vec3;

/// Tentative collisions one tracking walk may take: a bound on the work of one ray, reached
/// only past an optical depth of the majorants of about this many where the medium is not
/// that dense (a dense one ends the walk by roulette or a real collision first); a walk that
/// reaches it counts as absorbed.
pub const MAX_TRACKING_STEPS: u32 = 4096;

/// Most optical depth the majorant may have across the extinction volume's box (its
/// diagonal): a medium beyond it lets nothing through, and a grid value that large (a
/// corrupt file) would make every walk near it take [`MAX_TRACKING_STEPS`].
pub const MAX_OPTICAL_DEPTH: f32 = 1e6;

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
    /// The global majorant: `scale` times `sigma_t`'s largest value (points in a segment
    /// are drawn from its exponential).
    pub majorant: f32,
    /// Per-cell majorants, which tracking draws its tentative collisions from.
    pub majorants: MajorantGrid,
}

impl Heterogeneous {
    /// A medium of extinction `scale * sigma_t` and albedo `albedo`.
    pub fn new(sigma_t: Volume, albedo: Volume, scale: f32) -> Heterogeneous {
        let majorant = scale * sigma_t.max();
        let majorants = MajorantGrid::new(&sigma_t, scale);
        Heterogeneous {
            sigma_t,
            albedo,
            scale,
            majorant,
            majorants,
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
        if self.majorant <= 0.0 {
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

    /// Draws the tentative collisions in `[t0, t1)` of the ray from `o` along unit `d`, cell
    /// by cell of the majorant grid (fresh exponential steps from each cell's entry), calling
    /// `at(s, majorant, rng)` at each until it returns false. `Err(s)` when it would take more
    /// than [`MAX_TRACKING_STEPS`] (`s` where it stopped).
    fn collisions(
        &self,
        o: Vec3,
        d: Vec3,
        (t0, t1): (f32, f32),
        rng: &mut Rng,
        mut at: impl FnMut(f32, f32, &mut Rng) -> bool,
    ) -> Result<(), f32> {
        let (mut steps, mut result) = (0, Ok(()));
        self.majorants.walk(o, d, t0, t1, |ta, tb, mu| {
            // An empty cell: no collision to draw.
            if mu <= 0.0 {
                return true;
            }
            let mut s = ta;
            loop {
                s -= (1.0 - rng.next()).ln() / mu;
                if s >= tb {
                    return true;
                }
                steps += 1;
                if steps > MAX_TRACKING_STEPS {
                    result = Err(s);
                    return false;
                }
                if !at(s, mu, rng) {
                    return false;
                }
            }
        });
        result
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
        let mut tr = Vec3::ONE;
        let walk = self.collisions(o, d, (t0, t1), rng, |s, mu, rng| {
            // The cell's majorant bounds the density; the max absorbs the filter's rounding.
            tr *= (Vec3::ONE - self.sigma_t_at(o + d * s) / mu).max(Vec3::ZERO);
            let q = tr.max_element();
            if q < ROULETTE_BELOW {
                tr = match rng.next() < q {
                    true => tr / q,
                    false => Vec3::ZERO,
                };
            }
            visit(s, tr);
            tr != Vec3::ZERO
        });
        if let Err(s) = walk {
            tr = Vec3::ZERO;
            visit(s, tr);
        }
        tr
    }

    /// A free flight from `o` along unit `d` towards a surface `t_max` away (delta tracking
    /// with spectral-tracking weights; see the module's header).
    pub fn sample_flight(&self, o: Vec3, d: Vec3, t_max: f32, rng: &mut Rng) -> Flight {
        match self.track(o, d, t_max, rng) {
            Ok(s) => Flight {
                t: s.t,
                in_medium: true,
                weight: s.weight(),
            },
            Err(weight) => Flight {
                t: t_max,
                in_medium: false,
                weight,
            },
        }
    }

    /// Delta tracking: the event (its `T / pdf` estimate and `sigma_s` apart), or the weight
    /// of a flight that reaches `t_max`.
    pub fn track(&self, o: Vec3, d: Vec3, t_max: f32, rng: &mut Rng) -> Result<Scatter, Vec3> {
        let Some((t0, t1)) = self.span(o, d, t_max) else {
            return Err(Vec3::ONE);
        };
        let (mut w, mut event) = (Vec3::ONE, None);
        let walk = self.collisions(o, d, (t0, t1), rng, |s, mu, rng| {
            let x = o + d * s;
            let sigma = self.sigma_t_at(x);
            // History-aware: the real event's probability is the weights' mean of the
            // channels' `sigma_t / majorant`, so a null event keeps the weights' sum.
            let p_real = ((w * sigma).element_sum() / (mu * w.element_sum())).min(1.0);
            if rng.next() < p_real {
                event = Some(Scatter {
                    t: s,
                    tr_over_pdf: w / (mu * p_real),
                    sigma_s: sigma * self.albedo.eval(x),
                });
                return false;
            }
            w *= (Vec3::splat(mu) - sigma).max(Vec3::ZERO) / (mu * (1.0 - p_real));
            true
        });
        if walk.is_err() {
            w = Vec3::ZERO;
        }
        event.ok_or(w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::Stream;
    use crate::media::grid::{Filter, VolumeGrid};
    use glam::Affine3A;
    use std::sync::Arc;

    /// A density step along x over the unit cube, in a grid of 16 x 1 x 1 voxels: `a` in the
    /// first eight, `b` in the rest, filtered trilinearly, so `sigma_t(x) = a` up to the
    /// eighth voxel's centre (7.5 / 16), `b` from the ninth's (8.5 / 16), linear between;
    /// the majorant grid's four cells along x hold `a`, the larger twice, then `b`.
    fn ramp(a: Vec3, b: Vec3, albedo: Vec3) -> Heterogeneous {
        let data = (0..16).flat_map(|i| match i < 8 {
            true => a.to_array(),
            false => b.to_array(),
        });
        let grid = VolumeGrid {
            res: [16, 1, 1],
            channels: 3,
            bbox: [Vec3::ZERO, Vec3::ONE],
            data: data.collect(),
        };
        let kind = VolumeKind::Grid {
            grid: Arc::new(grid),
            to_local: Affine3A::IDENTITY,
            filter: Filter::Trilinear,
        };
        let unit = Affine3A::IDENTITY;
        let h = Heterogeneous::new(
            Volume::new(kind, unit),
            Volume::new(VolumeKind::Constant(albedo), unit),
            1.0,
        );
        assert_eq!(h.majorants.cell_count(), 64);
        h
    }

    /// The optical depth along x from -1 to `x` (clipped to the cube) of [`ramp`].
    fn depth(a: f32, b: f32, x: f32) -> f32 {
        let (x1, w) = (7.5 / 16.0, 1.0 / 16.0);
        let x = x.clamp(0.0, 1.0);
        // Between the centres sigma rises linearly from a to b over w.
        let lin = |s: f32| a * (s - x1) + (b - a) * (s - x1).powi(2) / (2.0 * w);
        a * x.min(x1) + lin(x.clamp(x1, x1 + w)) + b * (x - x1 - w).max(0.0)
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
                assert!(
                    (f.weight - Vec3::ONE).abs().max_element() < 1e-4,
                    "{}",
                    f.weight
                );
            } else {
                assert_eq!(f.t, 5.0);
                assert!(
                    (f.weight - Vec3::ONE).abs().max_element() < 1e-4,
                    "{}",
                    f.weight
                );
            }
        }
        let p_event = events as f64 / n as f64;
        assert!((p_event - total as f64).abs() < 4.0 * (total as f64 / n as f64).sqrt());
        let expect = events as f64 / 10.0;
        let chi2: f64 = counts
            .iter()
            .map(|&c| (c as f64 - expect).powi(2) / expect)
            .sum();
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
    /// A strongly chromatic step (each half dense in another channel, one channel nearly
    /// clear): the flights' weights stay bounded (the average scheme's null weight grew by
    /// about 2 per null collision in the clear channel here, so a flight of several reached
    /// tens) and their means per channel are still the scattered fraction and the
    /// transmittance, within four standard errors.
    #[test]
    fn chromatic_tracking_weights_stay_bounded_and_unbiased() {
        let (a, b) = (Vec3::new(6.0, 0.1, 3.0), Vec3::new(0.1, 6.0, 0.2));
        let albedo = Vec3::new(0.9, 0.8, 1.0);
        let m = ramp(a, b, albedo);
        let o = Vec3::new(-1.0, 0.5, 0.5);
        let mut rng = Rng::new(11, Stream::Photon, 0, 0);
        let n = 200_000;
        let (mut largest, mut sums) = (0.0f32, [[Vec3::ZERO; 2]; 2]);
        for _ in 0..n {
            let f = m.sample_flight(o, Vec3::X, 2.0, &mut rng);
            largest = largest.max(f.weight.max_element());
            let s = &mut sums[f.in_medium as usize];
            s[0] += f.weight;
            s[1] += f.weight * f.weight;
        }
        assert!(largest <= 3.0 * 1.0001, "largest weight {largest}");
        let tr = Vec3::from_array([0, 1, 2].map(|c| (-depth(a[c], b[c], 1.0)).exp()));
        for (k, want) in [(0, tr), (1, albedo * (Vec3::ONE - tr))] {
            let mean = sums[k][0] / n as f32;
            let sd = ((sums[k][1] / n as f32 - mean * mean) / n as f32).powf(0.5);
            for c in 0..3 {
                assert!(
                    (mean[c] - want[c]).abs() <= 4.0 * sd[c] + 1e-5,
                    "{k} channel {c}: {} vs {} (sd {})",
                    mean[c],
                    want[c],
                    sd[c]
                );
            }
        }
    }
}
