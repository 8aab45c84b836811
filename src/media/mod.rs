//! Homogeneous participating media (issue 24), as Mitsuba 3's `homogeneous` defines them:
//! an extinction coefficient `sigma_t` per linear RGB channel (per scene unit of length, after
//! `scale`), a single-scattering albedo (`sigma_s = albedo sigma_t`) and a Henyey-Greenstein
//! phase function. Shapes bound media through their material's [`MediumInterface`]; the
//! camera may sit in one (`Scene::camera_medium`).
//!
//! Transport through a medium is Beer-Lambert: `T(t) = exp(-sigma_t t)` per channel
//! ([`Medium::transmittance`]). Free-flight sampling ([`Medium::sample_flight`]) draws a
//! distance from one channel chosen uniformly and weighs by the mean of the three channels'
//! densities (the one-sample MIS over channels of spectral tracking), so a grey medium
//! samples exactly and a coloured one without bias.
//!
//! Heterogeneous media (issue 41, Mitsuba's `heterogeneous`: [`heterogeneous`], voxel grids
//! in [`grid`]) are the other [`MediumKind`]; the methods that take a ray dispatch on it.

pub mod builder;
pub mod flight;
pub mod gpu;
pub mod grid;
pub mod heterogeneous;
pub mod majorant;
pub mod phase;

use crate::math::rng::Rng;
use crate::media::heterogeneous::Heterogeneous;
use crate::media::phase::HenyeyGreenstein;
use glam::Vec3;
use std::sync::Arc;

pub use crate::media::flight::{Flight, Scatter};

/// Distances at which a final-gather ray's segment through a medium takes the volume map's
/// point estimate (the CPU's `Gatherer::gathered_in_medium`, the GPU's `gathered_in_medium`).
pub const GATHER_MEDIUM_POINTS: u32 = 4;

/// The point estimate's radius over the beam's r (at most 2: a query reads the cells within
/// that of its point, each no narrower than 2 r; the CPU's `VolumeMap::point`, the GPU's
/// `volume_point`). The first pass's r is sized for beams (K / 4 photons along a segment as
/// long as the media's box), where a ball of radius r holds about a fifth of a photon at
/// the mean density: a gather ray's point estimates mostly found none, and in a dense
/// medium a few passes carried most of a block's light (docs/media.md). Twice the radius
/// holds eight times the photons.
pub const POINT_RADIUS_FACTOR: f32 = 2.0;

/// The near part of a camera segment through a medium, as a fraction of its length inside
/// the volume photons' bounds, whose multiply scattered light one gather ray brings instead
/// of the beam estimate (in `gather` mode). The beam gives each photon near the camera a
/// weight over the image that grows as the inverse square of its distance (its disc covers
/// that many more pixels), so the few photons there made most of the image's
/// low-frequency noise; a gather ray from a point drawn in the near part reads the photons
/// where it lands instead. Volume caustic photons (L S+ V, which no gather ray sees) still
/// come from the beam there (docs/media.md).
pub const NEAR_GATHER_FRACTION: f32 = 0.5;

/// Marks "no medium" (vacuum) in a [`MediumInterface`] or `Scene::camera_medium`.
pub const NO_MEDIUM: u32 = u32::MAX;

/// A medium: homogeneous, or heterogeneous ([`MediumKind`]). The integrators reach a medium
/// only through the methods that take a ray ([`Medium::transmittance_along`],
/// [`Medium::flight`], [`Medium::point_in_segment`], [`Medium::sigma_s_at`],
/// [`Medium::transmittances`]), which dispatch on the kind here, in one place.
#[derive(Clone, Debug, PartialEq)]
pub struct Medium {
    /// Extinction coefficient per channel, per scene unit (>= 0); of a heterogeneous medium,
    /// its majorant in every channel (a bound).
    pub sigma_t: Vec3,
    /// Single-scattering albedo per channel, in [0, 1]; of a heterogeneous medium, the
    /// albedo's largest value in every channel (a bound).
    pub albedo: Vec3,
    /// Its phase function.
    pub phase: HenyeyGreenstein,
    /// How its extinction and albedo vary over space.
    pub kind: MediumKind,
}

/// The kinds of medium.
#[derive(Clone, Debug, Default, PartialEq)]
pub enum MediumKind {
    /// `sigma_t` and `albedo` everywhere (Beer-Lambert, exact sampling).
    #[default]
    Homogeneous,
    /// Extinction and albedo from volumes (tracking against a majorant).
    Heterogeneous(Arc<Heterogeneous>),
}

/// The transmittance from a ray's origin to any distance along it, for an estimate that
/// reads many distances of one segment (the beam estimate): exact for a homogeneous medium,
/// one ratio-tracking walk's steps for a heterogeneous one (each distance unbiased).
#[derive(Clone, Debug, PartialEq)]
pub enum Transmittances {
    /// Beer-Lambert with this extinction.
    Exact(Vec3),
    /// `(s, T)`: the estimate is `T` beyond `s`, 1 before the first step.
    Steps(Vec<(f32, Vec3)>),
}

impl Transmittances {
    /// The transmittance to distance `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        match self {
            Transmittances::Exact(sigma_t) => {
                Vec3::select(sigma_t.cmpgt(Vec3::ZERO), (-*sigma_t * t).exp(), Vec3::ONE)
            }
            Transmittances::Steps(steps) => match steps.partition_point(|&(s, _)| s <= t) {
                0 => Vec3::ONE,
                i => steps[i - 1].1,
            },
        }
    }

    /// The transmittance to `z`, and the transmittances from there on (`at(z + t)` is the
    /// pair's `T(z) * at(t)`): how a segment split at `z` reads its far part.
    pub fn split(&self, z: f32) -> (Vec3, Transmittances) {
        match self {
            Transmittances::Exact(_) => (self.at(z), self.clone()),
            Transmittances::Steps(steps) => {
                let beyond = steps.iter().map(|&(s, tr)| (s - z, tr)).collect();
                (Vec3::ONE, Transmittances::Steps(beyond))
            }
        }
    }
}

/// The media on either side of a surface: `interior` behind it (against its normal),
/// `exterior` in front; [`NO_MEDIUM`] for vacuum.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct MediumInterface {
    /// Medium on the side the surface's normal points away from.
    pub interior: u32,
    /// Medium on the side the normal points into.
    pub exterior: u32,
}

impl Default for MediumInterface {
    fn default() -> Self {
        MediumInterface {
            interior: NO_MEDIUM,
            exterior: NO_MEDIUM,
        }
    }
}

impl MediumInterface {
    /// Whether the surface bounds no medium on either side.
    pub fn is_vacuum(&self) -> bool {
        self.interior == NO_MEDIUM && self.exterior == NO_MEDIUM
    }

    /// The medium a ray is in after this surface (geometric normal `n`) sent it along `dir`,
    /// when it was in `current` before: Mitsuba 3's rule (its `volpath`). A surface that
    /// bounds a medium on either side is a medium transition: the ray is then in the medium
    /// on the side `dir` leaves towards (exterior where `n` points, else interior), after a
    /// reflection as after a refraction. A surface that bounds none leaves `current` as it
    /// was, so walls inside fog need no medium of their own.
    #[inline]
    pub fn after(&self, current: u32, n: Vec3, dir: Vec3) -> u32 {
        match (self.is_vacuum(), dir.dot(n) > 0.0) {
            (true, _) => current,
            (false, true) => self.exterior,
            (false, false) => self.interior,
        }
    }
}

/// A distance drawn in a segment by [`Medium::sample_in_segment`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentPoint {
    /// Distance along the segment.
    pub t: f32,
    /// Its density: the mean over the channels of `sigma_c T_c(t) / (1 - T_c(t_max))`.
    pub pdf: f32,
}

/// Draws a distance in `[0, t_max)` along the ray from `o` along unit `d` (`t_max` may be
/// infinite) in proportion to `1 / |o + t d - y|^2`, the inverse square distance to the point
/// `y`: equiangular sampling (Kulla and Fajardo 2012), uniform in the angle the ray subtends
/// at `y`. Single scattering from a light at (or sampled at) `y` is then estimated with the
/// light's own `1/d^2` cancelled, where drawing by transmittance leaves it as the noise of a
/// segment passing near the light. `None` when the ray passes through `y` (or `y` is not
/// finite): the caller draws by transmittance instead.
pub fn sample_equiangular(o: Vec3, d: Vec3, t_max: f32, y: Vec3, u: f32) -> Option<SegmentPoint> {
    let to_y = y - o;
    let delta = to_y.dot(d);
    let dist = (to_y - d * delta).length();
    // A ray through y (to float precision): no angle to draw.
    if !(dist > 1e-6 * to_y.length()) || !dist.is_finite() {
        return None;
    }
    let a = (-delta).atan2(dist);
    let b = match t_max.is_finite() {
        true => (t_max - delta).atan2(dist),
        false => std::f32::consts::FRAC_PI_2,
    };
    if !(b > a) {
        return None;
    }
    let theta = a + u * (b - a);
    let t = (delta + dist * theta.tan()).clamp(0.0, t_max * (1.0 - f32::EPSILON));
    let s = t - delta;
    let pdf = dist / ((b - a) * (dist * dist + s * s));
    (pdf > 0.0 && pdf.is_finite() && t.is_finite()).then_some(SegmentPoint { t, pdf })
}

impl Medium {
    /// The transmittance over `[0, t)` of the ray from `o` along unit `d` (`t` may be
    /// infinite): exact ([`Self::transmittance`], no random numbers) for a homogeneous
    /// medium, an unbiased estimate by ratio tracking for a heterogeneous one.
    pub fn transmittance_along(&self, o: Vec3, d: Vec3, t: f32, rng: &mut Rng) -> Vec3 {
        match &self.kind {
            MediumKind::Homogeneous => self.transmittance(t),
            MediumKind::Heterogeneous(h) => h.transmittance(o, d, t, rng),
        }
    }

    /// The transmittance to every distance of the segment `[0, t_max)` of the ray from `o`
    /// along unit `d` (see [`Transmittances`]).
    pub fn transmittances(&self, o: Vec3, d: Vec3, t_max: f32, rng: &mut Rng) -> Transmittances {
        match &self.kind {
            MediumKind::Homogeneous => Transmittances::Exact(self.sigma_t),
            MediumKind::Heterogeneous(h) => Transmittances::Steps(h.steps(o, d, t_max, rng)),
        }
    }

    /// A free flight along the ray from `o` along unit `d` towards a surface `t_max` away:
    /// [`Self::sample_flight`] from two numbers for a homogeneous medium, delta tracking
    /// for a heterogeneous one.
    pub fn flight(&self, o: Vec3, d: Vec3, t_max: f32, rng: &mut Rng) -> Flight {
        match &self.kind {
            MediumKind::Homogeneous => {
                let (uc, u) = (rng.next(), rng.next());
                self.sample_flight(uc, u, t_max)
            }
            MediumKind::Heterogeneous(h) => h.sample_flight(o, d, t_max, rng),
        }
    }

    /// A point in `[0, t_max)` of the ray from `o` along unit `d` where light scatters
    /// towards `o`, with the weight `sigma_s(x) T(t) / pdf(t)` that estimates the scattered
    /// light's integral over the segment from one point: for a homogeneous medium drawn in
    /// proportion to `sigma_t T(t)` ([`Self::sample_in_segment`], `u_channel` and `u`); for a
    /// heterogeneous one a free flight by delta tracking (numbers from `rng`; `None` when it
    /// leaves the segment, which the estimate counts as zero), so the points follow the
    /// density where a majorant's exponential would seldom reach a sparse medium's far side.
    pub fn scatter_in_segment(
        &self,
        o: Vec3,
        d: Vec3,
        (u_channel, u): (f32, f32),
        t_max: f32,
        rng: &mut Rng,
    ) -> Option<Scatter> {
        match &self.kind {
            MediumKind::Homogeneous => {
                let p = self.sample_in_segment(u_channel, u, t_max)?;
                Some(Scatter {
                    t: p.t,
                    tr_over_pdf: self.transmittance(p.t) / p.pdf,
                    sigma_s: self.sigma_s(),
                })
            }
            MediumKind::Heterogeneous(h) => h.track(o, d, t_max, rng).ok(),
        }
    }

    /// The scattering coefficient at `x`.
    pub fn sigma_s_at(&self, x: Vec3) -> Vec3 {
        match &self.kind {
            MediumKind::Homogeneous => self.sigma_s(),
            MediumKind::Heterogeneous(h) => h.sigma_s_at(x),
        }
    }

    /// Whether it is homogeneous (the GPU compiles heterogeneous tracking only for scenes with
    /// another kind: `HAS_HETERO_MEDIA`).
    pub fn is_homogeneous(&self) -> bool {
        matches!(self.kind, MediumKind::Homogeneous)
    }

    /// Draws a distance in `[0, t_max)` (`t_max` may be infinite) in proportion to one
    /// channel's `sigma_t T(t)`, the channel chosen uniformly by `u_channel` (the density is
    /// the channels' mean, as in [`Self::sample_flight`]): single scattering's next-event
    /// estimate along a camera segment, every sample inside it. `None` when the chosen
    /// channel cannot scatter over the segment (no extinction and no finite length).
    pub fn sample_in_segment(&self, u_channel: f32, u: f32, t_max: f32) -> Option<SegmentPoint> {
        let c = ((u_channel * 3.0) as usize).min(2);
        // The mass of channel `s` over the segment, 1 - T(t_max); 0 for a clear channel.
        let mass = |s: f32| match t_max.is_finite() {
            true => -(-s * t_max).exp_m1(),
            false => 1.0,
        };
        let sigma = self.sigma_t[c];
        let t = if sigma > 0.0 {
            // Inverse of the truncated exponential: 1 - exp(-sigma t) = u (1 - T(t_max)).
            -(-u * mass(sigma)).ln_1p() / sigma
        } else if t_max.is_finite() {
            u * t_max
        } else {
            return None;
        };
        let t = t.min(t_max * (1.0 - f32::EPSILON));
        let density = |s: f32| match (s > 0.0, t_max.is_finite()) {
            (true, _) => s * (-s * t).exp() / mass(s),
            (false, true) => 1.0 / t_max,
            (false, false) => 0.0,
        };
        let pdf =
            (density(self.sigma_t.x) + density(self.sigma_t.y) + density(self.sigma_t.z)) / 3.0;
        (pdf > 0.0 && t.is_finite()).then_some(SegmentPoint { t, pdf })
    }

    /// Scattering coefficient per channel, `albedo sigma_t`.
    pub fn sigma_s(&self) -> Vec3 {
        self.albedo * self.sigma_t
    }

    /// Beer-Lambert transmittance over a distance `t`: `exp(-sigma_t t)` per channel. `t`
    /// may be infinite (a ray that leaves the scene): only clear channels then transmit
    /// (`exp(-0 * inf)` would be NaN).
    pub fn transmittance(&self, t: f32) -> Vec3 {
        Transmittances::Exact(self.sigma_t).at(t)
    }

    /// Samples how far a path travels before an interaction, up to a surface `t_max` away
    /// (infinite for none), from uniform `u_channel` (which channel's density draws the
    /// distance) and `u` (the distance).
    pub fn sample_flight(&self, u_channel: f32, u: f32, t_max: f32) -> Flight {
        let c = ((u_channel * 3.0) as usize).min(2);
        let sigma = self.sigma_t[c];
        let t = match sigma > 0.0 {
            true => -(1.0 - u).max(f32::MIN_POSITIVE).ln() / sigma,
            false => f32::INFINITY,
        };
        if t < t_max {
            let tr = self.transmittance(t);
            let pdf = (self.sigma_t * tr).element_sum() / 3.0;
            let weight = match pdf > 0.0 {
                true => self.sigma_s() * tr / pdf,
                false => Vec3::ZERO,
            };
            return Flight {
                t,
                in_medium: true,
                weight,
            };
        }
        let tr = self.transmittance(t_max);
        let p = tr.element_sum() / 3.0;
        let weight = match p > 0.0 {
            true => tr / p,
            false => Vec3::ZERO,
        };
        Flight {
            t: t_max,
            in_medium: false,
            weight,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::rng::{Rng, Stream};

    fn medium(sigma_t: Vec3, albedo: Vec3) -> Medium {
        Medium {
            sigma_t,
            albedo,
            phase: HenyeyGreenstein { g: 0.0 },
            kind: MediumKind::Homogeneous,
        }
    }

    #[test]
    fn transmittance_is_beer_lambert() {
        let m = medium(Vec3::new(0.5, 1.0, 2.0), Vec3::splat(0.8));
        let t = m.transmittance(1.5);
        let want = [(-0.75f64).exp(), (-1.5f64).exp(), (-3.0f64).exp()];
        for c in 0..3 {
            assert!(
                (t[c] as f64 - want[c]).abs() < 1e-7 * want[c].max(1e-3),
                "{t}"
            );
        }
        // Two slabs in a row transmit what one slab of their total thickness does.
        let two = m.transmittance(0.4) * m.transmittance(1.1);
        assert!((two - t).abs().max_element() < 1e-6);
        // An endless run: only a clear channel transmits.
        let clear = medium(Vec3::new(0.5, 0.0, 2.0), Vec3::splat(0.8));
        assert_eq!(clear.transmittance(f32::INFINITY), Vec3::new(0.0, 1.0, 0.0));
    }

    /// The weights' mean is each channel's expectation: at events, the scattered fraction
    /// `albedo (1 - T(t_max))`; at the surface, `T(t_max)`. A coloured medium with one
    /// empty channel included.
    #[test]
    fn free_flights_are_unbiased_per_channel() {
        let m = medium(Vec3::new(0.2, 1.0, 0.0), Vec3::new(0.9, 0.5, 0.7));
        let t_max = 1.7;
        let n = 400_000;
        let mut rng = Rng::new(3, Stream::Photon, 0, 0);
        let (mut events, mut surface) = (Vec3::ZERO, Vec3::ZERO);
        for _ in 0..n {
            let f = m.sample_flight(rng.next(), rng.next(), t_max);
            match f.in_medium {
                true => events += f.weight / n as f32,
                false => surface += f.weight / n as f32,
            }
        }
        let tr = m.transmittance(t_max);
        let scattered = m.albedo * (Vec3::ONE - tr);
        for c in 0..3 {
            assert!((surface[c] - tr[c]).abs() < 0.01, "{surface} vs {tr}");
            assert!(
                (events[c] - scattered[c]).abs() < 0.01,
                "{events} vs {scattered}"
            );
        }
        // Vacuum: every flight reaches the surface with weight 1.
        let vacuum = medium(Vec3::ZERO, Vec3::ONE).sample_flight(0.5, 0.5, 3.0);
        assert_eq!((vacuum.in_medium, vacuum.weight), (false, Vec3::ONE));
    }

    /// Equiangular sampling: the density integrates to one over the segment, inverts its
    /// own CDF, and makes `1 / |x_t - y|^2` over the density the same for every sample (the
    /// angle the segment subtends at y over the distance to the line), for a light ahead of,
    /// beside and behind the origin, finite and endless segments; a ray through y gives None.
    #[test]
    fn equiangular_sampling_cancels_the_inverse_square() {
        let o = Vec3::new(0.1, -0.2, 0.3);
        let d = Vec3::new(1.0, 2.0, -0.5).normalize();
        for (y, t_max) in [
            (Vec3::new(1.0, 1.0, 1.0), 3.0),
            (Vec3::new(1.0, 1.0, 1.0), f32::INFINITY),
            (o - d * 2.0 + Vec3::new(0.0, 0.1, 0.2), 5.0),
            (o + d * 0.5 + Vec3::new(0.0, 0.0, 0.01), 1.0),
        ] {
            let to_y = y - o;
            let delta = to_y.dot(d);
            let dist = (to_y - d * delta).length();
            let (a, b) = ((-delta).atan2(dist), (t_max - delta).atan2(dist));
            let exact = (b - a) / dist;
            for i in 0..64 {
                let u = (i as f32 + 0.5) / 64.0;
                let p = sample_equiangular(o, d, t_max, y, u).expect("a point");
                assert!(p.t >= 0.0 && p.t < t_max, "{p:?}");
                let f = 1.0 / (o + d * p.t - y).length_squared();
                assert!(
                    (f / p.pdf - exact).abs() < 2e-4 * exact,
                    "{f} / {} vs {exact}",
                    p.pdf
                );
                let cdf = (((p.t - delta) / dist).atan() - a) / (b - a);
                assert!((cdf - u).abs() < 1e-4, "cdf {cdf} at u {u}");
            }
            // The density's integral over a finite segment (midpoint rule).
            if !t_max.is_finite() {
                continue;
            }
            let n = 20_000;
            let integral: f64 = (0..n)
                .map(|i| {
                    let t = (i as f32 + 0.5) / n as f32 * t_max;
                    let s = t - delta;
                    let pdf = dist / ((b - a) * (dist * dist + s * s));
                    pdf as f64 * (t_max / n as f32) as f64
                })
                .sum();
            assert!((integral - 1.0).abs() < 1e-3, "{integral}");
        }
        let through = sample_equiangular(o, d, 4.0, o + d * 2.0, 0.3);
        assert_eq!(through, None);
    }
}
