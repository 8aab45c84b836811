//! Throughput benchmark: the same scene and settings on each available backend, timed per
//! phase, medians over several runs (`gpu-photon bench`).

use crate::error::Result;
use crate::render::{render, Backend, Progress, RenderReport};
use crate::scene::Scene;
use crate::settings::RenderSettings;

/// Median throughput of one backend.
#[derive(Clone, Debug)]
pub struct Throughput {
    pub backend: String,
    /// Photon paths traced per second (global + caustic paths over the trace phase).
    pub paths_per_s: f64,
    /// Seconds to build the photon maps' search structures (kd-trees or hash grids).
    pub build_s: f64,
    /// Gather seconds per megapixel at one sample per pixel.
    pub gather_s_per_mpix_sample: f64,
    /// Whole render, seconds.
    pub total_s: f64,
}

fn phase(r: &RenderReport, names: &[&str]) -> f64 {
    r.phases
        .iter()
        .filter(|p| names.contains(&p.0))
        .map(|p| p.1.as_secs_f64())
        .sum()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Renders `runs` times on `backend` and returns the medians.
pub fn throughput(
    scene: &Scene,
    s: &RenderSettings,
    backend: Backend,
    runs: usize,
) -> Result<Throughput> {
    let plan = crate::render::MapPlan::new(scene, s);
    let paths = plan.global.as_ref().map_or(0, |b| b.total()) as f64
        + plan.caustic.as_ref().map_or(0, |c| c.0.total()) as f64;
    let msamples = s.width as f64 * s.height as f64 * s.spp as f64 / 1e6;
    let mut rows = Vec::new();
    let mut name = String::new();
    for _ in 0..runs.max(1) {
        let (_, r) = render(scene, s, backend, Progress::default())?;
        name = r.backend.clone();
        rows.push((
            paths / phase(&r, &["trace photons"]).max(1e-9),
            phase(&r, &["build kd-trees", "build grids"]),
            phase(&r, &["gather"]) / msamples.max(1e-12),
            r.total().as_secs_f64(),
        ));
    }
    Ok(Throughput {
        backend: name,
        paths_per_s: median(rows.iter().map(|r| r.0).collect()),
        build_s: median(rows.iter().map(|r| r.1).collect()),
        gather_s_per_mpix_sample: median(rows.iter().map(|r| r.2).collect()),
        total_s: median(rows.iter().map(|r| r.3).collect()),
    })
}
