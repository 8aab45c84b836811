//! What free-flight sampling and a point drawn in a segment give the integrators (issue 24,
//! 41), shared by both medium kinds (`media/mod.rs`, `media/heterogeneous.rs`).

use glam::Vec3;

/// What a free flight of [`Medium::sample_flight`](crate::media::Medium::sample_flight) ended in.
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

/// A point drawn in a segment by [`Medium::scatter_in_segment`](crate::media::Medium::scatter_in_segment).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Scatter {
    /// Distance along the segment.
    pub t: f32,
    /// The transmittance to it over its density, `T(t) / pdf(t)` (an estimate in a
    /// heterogeneous medium).
    pub tr_over_pdf: Vec3,
    /// The scattering coefficient there.
    pub sigma_s: Vec3,
}

impl Scatter {
    /// `sigma_s T(t) / pdf(t)`: what the light scattered there towards the segment's origin
    /// is multiplied by.
    pub fn weight(&self) -> Vec3 {
        self.tr_over_pdf * self.sigma_s
    }
}
