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

use crate::phase::HenyeyGreenstein;
use glam::Vec3;

/// Marks "no medium" (vacuum) in a [`MediumInterface`] or `Scene::camera_medium`.
pub const NO_MEDIUM: u32 = u32::MAX;

/// A homogeneous medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Medium {
    /// Extinction coefficient per channel, per scene unit (>= 0).
    pub sigma_t: Vec3,
    /// Single-scattering albedo per channel, in [0, 1].
    pub albedo: Vec3,
    /// Its phase function.
    pub phase: HenyeyGreenstein,
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
}

/// What a free flight of [`Medium::sample_flight`] ended in.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Flight {
    /// Distance travelled.
    pub t: f32,
    /// Whether it ended in the medium (a scattering or absorption event) rather than at the
    /// surface `t_max` away.
    pub in_medium: bool,
    /// What the path's throughput is multiplied by: at an event `sigma_s T(t) / pdf(t)` (the
    /// albedo-weighted scattering), at the surface `T(t_max) / P(t >= t_max)`.
    pub weight: Vec3,
}

impl Medium {
    /// Scattering coefficient per channel, `albedo sigma_t`.
    pub fn sigma_s(&self) -> Vec3 {
        self.albedo * self.sigma_t
    }

    /// Beer-Lambert transmittance over a distance `t`: `exp(-sigma_t t)` per channel.
    pub fn transmittance(&self, t: f32) -> Vec3 {
        (-self.sigma_t * t).exp()
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
    use crate::rng::{Rng, Stream};

    fn medium(sigma_t: Vec3, albedo: Vec3) -> Medium {
        Medium {
            sigma_t,
            albedo,
            phase: HenyeyGreenstein { g: 0.0 },
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
}
