//! Decoupled rates (issue 10): the caustic-map estimate on one camera sample in N, weighted,
//! gives the same caustic light as on every sample, on both backends (the caustic-only view
//! isolates it; the photon maps are the same, so only the samples' positions differ).

mod common;

use gpu_photon::film::Image;
use gpu_photon::report::Progress;
use gpu_photon::session::{render, Backend};
use gpu_photon::settings::{Mode, RenderSettings};

fn caustic_view(backend: Backend, every: u32, caustic_photons: u32) -> Image {
    let scene =
        gpu_photon::scene::load(std::path::Path::new("scenes/cornell-caustics.toml")).unwrap();
    let s = RenderSettings {
        width: 48,
        height: 48,
        spp: 64,
        photons: 20_000,
        caustic_photons,
        mode: Mode::CausticOnly,
        caustic_every: every,
        ..scene.settings.clone()
    };
    render(&scene, &s, backend, Progress::default()).unwrap().0
}

fn mean(img: &Image) -> f64 {
    let s: f64 = img
        .pixels
        .iter()
        .map(|p| p.iter().map(|&c| c as f64).sum::<f64>())
        .sum();
    s / (3 * img.pixels.len()) as f64
}

fn check(backend: Backend) {
    // The visible light's emission, which the caustic view shows too, is subtracted.
    let emitted = mean(&caustic_view(backend, 1, 0));
    let a = mean(&caustic_view(backend, 1, 20_000)) - emitted;
    let q = mean(&caustic_view(backend, 4, 20_000)) - emitted;
    eprintln!("{backend:?}: caustic light {a} (every sample), {q} (every 4th)");
    assert!(a > 1e-3, "{backend:?}: the caustic view is dark ({a})");
    // Same maps, a quarter of the samples at 4x weight: the image mean moves only by the
    // sampling of caustic edges within pixels (measured at 64 spp: 0.01% CPU, 0.5% GPU); a missing weight would
    // lose 75% of the caustic light.
    assert!(
        ((q - a) / a).abs() < 0.03,
        "{backend:?}: caustic mean {q} with every 4 vs {a} with every sample"
    );
}

#[test]
fn cpu_caustic_estimate_on_fewer_samples_keeps_the_caustic_light() {
    check(Backend::Cpu);
}

#[test]
fn gpu_caustic_estimate_on_fewer_samples_keeps_the_caustic_light() {
    if common::gpu().is_none() {
        return;
    }
    check(Backend::Gpu);
}
