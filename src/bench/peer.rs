//! A peer renderer's error against time, as recorded beside a reference image (the
//! `peer_curve` of its JSON sidecar, written by `scripts/media_references.py`: Mitsuba 3's
//! own renders of the scene at a few spp, timed and measured against the reference), and
//! where a curve point of ours stands against it at equal error.
//!
//! An unbiased path tracer's squared error times its time is a constant (its variance
//! falls as 1 / samples); with the reference's own noise taken out in quadrature from both
//! sides, the peer's time at an error `e` is that constant over `e^2` (the median over its
//! recorded points, which are on one machine, at one moment: not this run's).

use crate::error::{Error, Result};
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// One recorded render of the peer.
#[derive(Clone, Debug, Deserialize, PartialEq)]
pub struct PeerPoint {
    /// Samples per pixel.
    pub spp: u32,
    /// Its wall time, seconds.
    pub seconds: f64,
    /// Its RMSE against the reference (the reference's own noise included).
    pub rmse: f64,
}

/// The peer's curve and the reference's own noise.
#[derive(Clone, Debug, PartialEq)]
pub struct PeerCurve {
    /// Which renderer (the sidecar's `renderer`).
    pub renderer: String,
    /// Its recorded renders.
    pub points: Vec<PeerPoint>,
    /// The reference's own per-pixel RMSE (`estimated_rmse_of_reference`).
    pub reference_noise: f64,
    /// The sidecar it came from.
    pub path: PathBuf,
}

#[derive(Deserialize)]
struct Sidecar {
    #[serde(default)]
    renderer: String,
    #[serde(default)]
    peer_curve: Vec<PeerPoint>,
    #[serde(default)]
    estimated_rmse_of_reference: f64,
}

/// The squared error with the reference's noise taken out (never below zero).
fn own_squared(rmse: f64, noise: f64) -> f64 {
    (rmse * rmse - noise * noise).max(0.0)
}

impl PeerCurve {
    /// The curve beside `reference` (`NAME.json` next to `NAME.exr`): `None` when there is
    /// no sidecar or it records no curve; an error naming the file when it is unreadable.
    pub fn beside(reference: &Path) -> Result<Option<Self>> {
        let path = reference.with_extension("json");
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(source) => return Err(Error::Io { path, source }),
        };
        let s: Sidecar = serde_json::from_str(&text).map_err(|e| Error::Scene {
            file: path.display().to_string(),
            line: e.line(),
            field: "peer_curve".into(),
            message: e.to_string(),
        })?;
        let points: Vec<PeerPoint> = s
            .peer_curve
            .into_iter()
            .filter(|p| p.seconds > 0.0 && p.rmse.is_finite() && p.seconds.is_finite())
            .collect();
        Ok((!points.is_empty()).then(|| PeerCurve {
            renderer: s.renderer,
            points,
            reference_noise: s.estimated_rmse_of_reference.max(0.0),
            path,
        }))
    }

    /// The peer's seconds to reach RMSE `rmse` (against the same reference): the median of
    /// its points' squared error times seconds over `rmse^2`, both without the reference's
    /// noise. `None` where `rmse` is within the reference's noise (no error left to compare)
    /// or no point is above it.
    pub fn seconds_at(&self, rmse: f64) -> Option<f64> {
        let e2 = own_squared(rmse, self.reference_noise);
        let mut c: Vec<f64> = self
            .points
            .iter()
            .map(|p| own_squared(p.rmse, self.reference_noise) * p.seconds)
            .filter(|c| *c > 0.0)
            .collect();
        if !(e2 > 0.0) || c.is_empty() {
            return None;
        }
        c.sort_by(f64::total_cmp);
        let n = c.len();
        let median = match n % 2 {
            1 => c[n / 2],
            _ => 0.5 * (c[n / 2 - 1] + c[n / 2]),
        };
        Some(median / e2)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Points on an exact 1/sqrt(time) law (after the reference's noise) give that law back;
    /// an error within the reference's noise gives nothing.
    #[test]
    fn seconds_at_equal_error_follow_the_inverse_square_law() {
        let noise = 0.01;
        let law = |t: f64| (0.04 / t + noise * noise).sqrt();
        let curve = PeerCurve {
            renderer: "peer".into(),
            points: [1.0, 4.0, 16.0]
                .iter()
                .map(|&t| PeerPoint {
                    spp: t as u32 * 16,
                    seconds: t,
                    rmse: law(t),
                })
                .collect(),
            reference_noise: noise,
            path: PathBuf::new(),
        };
        let s = curve.seconds_at(law(9.0)).unwrap();
        assert!((s - 9.0).abs() < 1e-9, "{s}");
        assert_eq!(curve.seconds_at(0.5 * noise), None);
    }
}
