//! Whole-image agreement of the GPU and CPU backends on every example scene (small images).
//!
//! Statistic: with CPU renders at seeds 1 and 2 and a GPU render at seed 1, the GPU image
//! must be no farther from CPU(seed 2) than CPU(seed 1) is, up to 30%:
//! `rmse(gpu1, cpu2) <= 1.3 rmse(cpu1, cpu2)`, and likewise for 8x8 block means, which
//! keep bias but average away most noise (`block(gpu1, cpu2) <= 1.5 block(cpu1, cpu2)`).
//! Two independent renders differ by sqrt(2) sigma per pixel; a backend with the same
//! noise and no bias gives the same figure, one with extra bias or noise a larger one. The
//! slack covers the GPU's stochastic Fresnel choice at glass (the CPU splits the first
//! bounces), which converges to the same image with somewhat more noise.

mod common;

use common::gpu;
use gpu_photon::film::diff;
use gpu_photon::report::Progress;
use gpu_photon::session::{render, Backend};
use gpu_photon::settings::RenderSettings;

fn settings(scene: &gpu_photon::Scene, seed: u32) -> RenderSettings {
    RenderSettings {
        width: 48,
        height: 48,
        spp: 4,
        photons: 40_000,
        caustic_photons: 20_000,
        seed,
        ..scene.settings.clone()
    }
}

#[test]
fn gpu_matches_cpu_on_every_scene() {
    let Some(_ctx) = gpu() else { return };
    let mut failures = Vec::new();
    let mut paths: Vec<_> = std::fs::read_dir("scenes")
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    paths.sort();
    for path in paths {
        let scene = gpu_photon::scene::load(&path).unwrap();
        let run = |backend, seed| {
            render(
                &scene,
                &settings(&scene, seed),
                backend,
                Progress::default(),
            )
            .unwrap()
            .0
        };
        let cpu1 = run(Backend::Cpu, 1);
        let cpu2 = run(Backend::Cpu, 2);
        let gpu1 = run(Backend::Gpu, 1);
        assert_eq!(
            gpu1.non_finite(),
            0,
            "{}: NaN or infinity in the GPU image",
            path.display()
        );
        let self_d = diff(&cpu1, &cpu2, 8).unwrap();
        let cross = diff(&gpu1, &cpu2, 8).unwrap();
        let line = format!(
            "{}: rmse gpu1-cpu2 {:.5} vs cpu1-cpu2 {:.5}; block {:.5} vs {:.5}",
            path.display(),
            cross.rmse,
            self_d.rmse,
            cross.block_rmse,
            self_d.block_rmse
        );
        eprintln!("{line}");
        let (pixels, blocks) = common::within_seed_noise(&cross, &self_d, 1e-6);
        if !(pixels && blocks) {
            failures.push(line);
        }
        // Without glass both backends draw the same numbers for the same paths (the counter
        // RNG is shared), so the images agree far below the noise: only float rounding and
        // fused multiply-adds separate them.
        if !scene.has_glass() {
            let same = diff(&gpu1, &cpu1, 8).unwrap();
            if same.rmse > 0.01 * self_d.rmse {
                failures.push(format!(
                    "{}: same seed, rmse gpu1-cpu1 {:.6} is not << {:.6}",
                    path.display(),
                    same.rmse,
                    self_d.rmse
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "backends disagree:\n{}",
        failures.join("\n")
    );
}

/// Same seed, same backend: the same image, bit for bit.
#[test]
fn gpu_renders_are_deterministic() {
    let Some(_ctx) = gpu() else { return };
    let scene =
        gpu_photon::scene::load(std::path::Path::new("scenes/cornell-caustics.toml")).unwrap();
    let s = settings(&scene, 5);
    let a = render(&scene, &s, Backend::Gpu, Progress::default())
        .unwrap()
        .0;
    let b = render(&scene, &s, Backend::Gpu, Progress::default())
        .unwrap()
        .0;
    assert!(
        a.pixels == b.pixels,
        "two GPU renders with the same seed differ"
    );
}

/// One renderer, several passes: a pass rendered again after others is the same image bit
/// for bit (the map cache, the parameter slots and the accumulator carry nothing over), and
/// the report sums the passes' phases under one name each, with the bound counters read back.
#[test]
fn one_gpu_renderer_renders_pass_after_pass() {
    use gpu_photon::gpu::GpuRenderer;
    use gpu_photon::session::PassRenderer;
    let Some(_ctx) = gpu() else { return };
    let scene =
        gpu_photon::scene::load(std::path::Path::new("scenes/cornell-caustics.toml")).unwrap();
    let mut s = settings(&scene, 3);
    s.width = 24;
    s.height = 24;
    let quiet = Progress::default();
    let mut r = GpuRenderer::new(&scene, &s).unwrap();
    let first = r.pass(0, &s, &quiet).unwrap();
    let other = r.pass(1, &s, &quiet).unwrap();
    let again = r.pass(0, &s, &quiet).unwrap();
    assert!(first.pixels == again.pixels, "pass 0 differs after pass 1");
    assert!(
        first.pixels != other.pixels,
        "passes 0 and 1 drew the same photons"
    );
    let report = r.report().unwrap();
    assert_eq!(report.gpu_stats.len(), 4);
    let mut names: Vec<&str> = report.phases.iter().map(|p| p.0).collect();
    names.sort();
    let n = names.len();
    names.dedup();
    assert_eq!(
        names.len(),
        n,
        "a phase is listed twice: {:?}",
        report.phases
    );

    // A K the gather's heap cannot hold is an error naming the setting, not a bad image.
    let big = RenderSettings {
        k: gpu_photon::gpu::codes::MAX_HEAP + 1,
        ..s.clone()
    };
    match r.pass(0, &big, &quiet) {
        Err(gpu_photon::Error::Setting { field: "k", .. }) => {}
        other => panic!("k = {} accepted: {:?}", big.k, other.map(|_| ())),
    }
}

/// Final gathering (mode `gather`) on both backends: the same statistic as above on the
/// scenes with and without glass. Both backends draw the same numbers for each camera sample
/// (camera jitter, shadow ray, then the gather direction), cache the same photons (chosen by
/// identity) and look them up by the same rule, so the images must agree within seed noise.
#[test]
fn gpu_matches_cpu_in_gather_mode() {
    let Some(_ctx) = gpu() else { return };
    let mut failures = Vec::new();
    for name in ["scenes/cornell-box.toml", "scenes/cornell-caustics.toml"] {
        let scene = gpu_photon::scene::load(std::path::Path::new(name)).unwrap();
        let run = |backend, seed| {
            let s = RenderSettings {
                mode: gpu_photon::settings::Mode::Gather,
                ..settings(&scene, seed)
            };
            render(&scene, &s, backend, Progress::default()).unwrap().0
        };
        let cpu1 = run(Backend::Cpu, 1);
        let cpu2 = run(Backend::Cpu, 2);
        let gpu1 = run(Backend::Gpu, 1);
        assert_eq!(
            gpu1.non_finite(),
            0,
            "{name}: NaN or infinity in the GPU image"
        );
        let self_d = diff(&cpu1, &cpu2, 8).unwrap();
        let cross = diff(&gpu1, &cpu2, 8).unwrap();
        let line = format!(
            "{name} (gather): rmse gpu1-cpu2 {:.5} vs cpu1-cpu2 {:.5}; block {:.5} vs {:.5}",
            cross.rmse, self_d.rmse, cross.block_rmse, self_d.block_rmse
        );
        eprintln!("{line}");
        let (pixels, blocks) = common::within_seed_noise(&cross, &self_d, 1e-6);
        if !(pixels && blocks) {
            failures.push(line);
        }
        // Without glass the same seed draws the same numbers on both backends, gather
        // directions and cache points included: the images agree far below the noise.
        if !scene.has_glass() {
            let same = diff(&gpu1, &cpu1, 8).unwrap();
            if same.rmse > 0.01 * self_d.rmse {
                failures.push(format!(
                    "{name} (gather): same seed, rmse gpu1-cpu1 {:.6} is not << {:.6}",
                    same.rmse, self_d.rmse
                ));
            }
        }
    }
    assert!(
        failures.is_empty(),
        "backends disagree:\n{}",
        failures.join("\n")
    );
}
