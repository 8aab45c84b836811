//! Bounded work per photon search (issue 26): a point light just above a plane far larger
//! than its lit patch (`tests/data/dense-point-light.toml`). The first progressive radius,
//! sized for photons spread over the whole plane, holds every photon of a pass. The CPU
//! narrows such searches (`cpu::density`), counts them and still renders the analytic image;
//! the GPU cuts them at its visit bound (the same `SEARCH_VISIT_BOUND` at most) and counts that.

mod common;

use glam::DVec3;
use gpu_photon::render::progressive::Flow;
use gpu_photon::render::report::Progress;
use gpu_photon::render::session::{render_progressive, Backend};
use gpu_photon::scene::Scene;

fn scene() -> Scene {
    gpu_photon::importers::load(std::path::Path::new("tests/data/dense-point-light.toml")).unwrap()
}

#[test]
fn dense_searches_are_narrowed_and_the_image_stays_analytic() {
    let sc = scene();
    let s = sc.settings.clone();
    let (acc, report) =
        render_progressive(&sc, &s, Backend::Cpu, Progress::default(), 0..4, |_| {
            Flow::Continue
        })
        .unwrap();
    let light = DVec3::new(0.0, 0.1, 0.0);
    let want =
        common::point_lit_plane_mean(&sc.camera, 0.8, [1.0; 3], light, 1000.0, s.width, s.height)
            [0];
    let got = acc.mean().mean();
    let searches = 4 * s.width as u64 * s.height as u64 * s.spp as u64;
    eprintln!(
        "narrowed {} of about {searches} searches; mean {:?} analytic {want:.6} ({:+.4})",
        report.narrowed,
        got,
        got[0] / want - 1.0
    );
    // Every camera sample sees the plane near the light, where the first radius holds the
    // whole pass: nearly all searches are narrowed.
    assert!(report.narrowed > searches / 2, "{}", report.narrowed);
    // Measured +0.5% (narrowed only to the visit bound, 16x the photons per search: +2.4%).
    assert!(
        got.iter().all(|&m| (m / want - 1.0).abs() < 0.02),
        "{got:?} vs {want}"
    );
}

#[test]
fn the_gpu_counts_the_searches_its_visit_bound_cuts() {
    let Some(_gpu) = common::gpu() else {
        eprintln!("no GPU adapter: skipped");
        return;
    };
    let sc = scene();
    let s = gpu_photon::settings::RenderSettings {
        width: 8,
        height: 8,
        ..sc.settings.clone()
    };
    let (_, report) = render_progressive(&sc, &s, Backend::Gpu, Progress::default(), 0..1, |_| {
        Flow::Continue
    })
    .unwrap();
    eprintln!("gpu bounds {:?}", report.gpu_stats);
    // [photons dropped, invocations out of loop budget, searches truncated]: every search
    // would read the whole pass (about 10^5 photons), past the visit bound of any adapter
    // (at most SEARCH_VISIT_BOUND, 16,384), so each is cut and counted (render's warning
    // reports them).
    let searches = s.width * s.height * s.spp;
    assert_eq!(report.gpu_stats[2], searches, "{:?}", report.gpu_stats);
}
