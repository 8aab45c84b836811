//! The progressive curve: error against the reference after 1, 2, 4, ... passes and the last,
//! with the wall time, per backend.

use crate::bench::{backend_name, BenchBackends};
use crate::error::{Error, Result};
use crate::render::film::Image;
use crate::render::image_diff::diff;
use crate::render::progressive::Flow;
use crate::render::report::Progress;
use crate::render::session::render_progressive;
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// One point of the curve.
#[derive(Clone, Debug)]
pub struct CurvePoint {
    /// "cpu" or "gpu".
    pub backend: &'static str,
    /// Passes in the mean so far.
    pub passes: u32,
    /// Wall seconds since the backend's first pass began (its set-up included).
    pub seconds: f64,
    /// RMSE against the reference.
    pub rmse: f64,
    /// Relative MSE against the reference.
    pub rel_mse: f64,
    /// Per-channel ratio of the image mean to the reference's.
    pub mean_ratio: [f64; 3],
}

impl CurvePoint {
    /// The header of the curve's table ([`CurvePoint`]'s `Display` gives its rows).
    pub fn header() -> String {
        format!(
            "{:<8} {:>7} {:>10} {:>10} {:>10} {:>24}",
            "backend", "passes", "seconds", "rmse", "rel_mse", "mean ratio"
        )
    }
}

impl std::fmt::Display for CurvePoint {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let m = self.mean_ratio;
        write!(
            f,
            "{:<8} {:>7} {:>10.2} {:>10.5} {:>10.5} {:>8.4} {:>7.4} {:>7.4}",
            self.backend, self.passes, self.seconds, self.rmse, self.rel_mse, m[0], m[1], m[2]
        )
    }
}

/// Renders `passes` progressive passes at the reference's size on each backend of `which`,
/// measuring the running mean after 1, 2, 4, ... passes and the last; `on_point` sees each
/// point as it comes, `on_skip` the reason a failing GPU was skipped.
pub fn progressive_curve(
    scene: &Scene,
    s: &RenderSettings,
    which: &BenchBackends,
    reference: &Image,
    passes: u32,
    mut on_point: impl FnMut(&CurvePoint),
    mut on_skip: impl FnMut(&str),
) -> Result<Vec<CurvePoint>> {
    let s = &RenderSettings {
        width: reference.width,
        height: reference.height,
        ..s.clone()
    };
    let mut points = Vec::new();
    for &b in &which.backends {
        let start = std::time::Instant::now();
        let mut failure = None;
        let result = render_progressive(scene, s, b, Progress::default(), 0..passes, |acc| {
            if acc.count.is_power_of_two() || acc.count == passes {
                let seconds = start.elapsed().as_secs_f64();
                match diff(&acc.mean(), reference, 16) {
                    Ok(d) => {
                        let p = CurvePoint {
                            backend: backend_name(b),
                            passes: acc.count,
                            seconds,
                            rmse: d.rmse,
                            rel_mse: d.rel_mse,
                            mean_ratio: d.mean_ratio,
                        };
                        on_point(&p);
                        points.push(p);
                    }
                    Err(message) => {
                        failure = Some(message);
                        return Flow::Stop;
                    }
                }
            }
            Flow::Continue
        });
        if let Some(message) = failure {
            return Err(Error::Setting {
                field: "reference",
                message,
            });
        }
        if let Err(e) = result {
            match which.skips(&e) {
                Some(why) => on_skip(why),
                None => return Err(e),
            }
        }
    }
    Ok(points)
}

/// The curve as CSV: one header row, one row per point.
pub fn curve_csv(points: &[CurvePoint]) -> String {
    let mut csv = String::from(
        "backend,passes,seconds,rmse,rel_mse,mean_ratio_r,mean_ratio_g,mean_ratio_b\n",
    );
    for p in points {
        let m = p.mean_ratio;
        csv.push_str(&format!(
            "{},{},{:.4},{:.6},{:.6},{:.5},{:.5},{:.5}\n",
            p.backend, p.passes, p.seconds, p.rmse, p.rel_mse, m[0], m[1], m[2]
        ));
    }
    csv
}
