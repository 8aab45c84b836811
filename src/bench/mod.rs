//! Benchmarks (`gpu-photon bench`): throughput of each backend on one scene (timed per phase,
//! medians over several runs), the speed-against-error ladder (`ladder`), the progressive
//! error curve (`curve`) and their plot (`plot`). The policy lives here: which backends run,
//! when a GPU failure only skips the GPU, and how a missing reference is rendered.

pub mod curve;
pub mod ladder;
pub mod plot;

pub use curve::{curve_csv, progressive_curve, CurvePoint};
pub use ladder::{ladder, ladder_csv, plot_title, reference_settings, LadderRow, LADDER};
pub use plot::{plot, PLOT_FONT};

use crate::error::{Error, Result};
use crate::report::{Progress, RenderReport};
use crate::scene::Scene;
use crate::session::{render, Backend, BackendChoice};
use crate::settings::RenderSettings;

/// Which backends a benchmark runs, and whether a GPU failure skips the GPU or ends it.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct BenchBackends {
    /// The backends, CPU first.
    pub backends: Vec<Backend>,
    /// A GPU failure (`Error::Gpu`) skips the GPU instead of failing the benchmark.
    pub skip_gpu_failures: bool,
}

impl BenchBackends {
    /// `None` (no `--backend`): both, a failing GPU skipped; `Cpu` or `Gpu`: that one;
    /// `Auto`: both, a failing GPU an error.
    pub fn of(choice: Option<BackendChoice>) -> Self {
        let backends = match choice {
            Some(BackendChoice::Cpu) => vec![Backend::Cpu],
            Some(BackendChoice::Gpu) => vec![Backend::Gpu],
            _ => vec![Backend::Cpu, Backend::Gpu],
        };
        BenchBackends {
            backends,
            skip_gpu_failures: choice.is_none(),
        }
    }

    /// The same policy over other backends (those that ran the throughput benchmark).
    pub fn only(&self, backends: Vec<Backend>) -> Self {
        BenchBackends {
            backends,
            skip_gpu_failures: self.skip_gpu_failures,
        }
    }

    /// Why `e` only skips the GPU (`Some(reason)`), or `None` when it ends the benchmark.
    pub fn skips<'e>(&self, e: &'e Error) -> Option<&'e str> {
        match e {
            Error::Gpu(why) if self.skip_gpu_failures => Some(why),
            _ => None,
        }
    }
}

/// The settings of the throughput benchmark: the scene's, with its own photons, samples and
/// size.
pub fn bench_settings(
    scene: &Scene,
    photons: u32,
    spp: u32,
    width: u32,
    height: u32,
) -> RenderSettings {
    RenderSettings {
        photons,
        spp,
        width,
        height,
        ..scene.settings.clone()
    }
}

/// The first line of the benchmark's report: scene, size, samples, photons, mode, runs.
pub fn heading(scene_path: &std::path::Path, s: &RenderSettings, runs: usize) -> String {
    format!(
        "{}: {}x{} at {} spp, {} photon paths, mode {}, medians of {runs} runs",
        scene_path.display(),
        s.width,
        s.height,
        s.spp,
        s.photons,
        s.mode.name(),
    )
}

/// How the GPU's times compare with the CPU's, phase by phase (above 1: the GPU is slower).
pub fn ratios(cpu: &Throughput, gpu: &Throughput) -> String {
    format!(
        "gpu/cpu time ratios: trace {:.2}, build {:.2}, gather {:.2}, total {:.2}",
        cpu.paths_per_s / gpu.paths_per_s,
        gpu.build_s / cpu.build_s.max(1e-9),
        gpu.gather_s_per_mpix_sample / cpu.gather_s_per_mpix_sample,
        gpu.total_s / cpu.total_s
    )
}

/// The lower-case name of a backend in tables and CSV files.
pub fn backend_name(b: Backend) -> &'static str {
    match b {
        Backend::Cpu => "cpu",
        Backend::Gpu => "gpu",
    }
}

/// Median throughput of one backend.
#[derive(Clone, Debug)]
pub struct Throughput {
    /// The backend measured.
    pub kind: Backend,
    /// Which backend ran, in words (its report's).
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

impl Throughput {
    /// The header of the throughput table ([`Throughput`]'s `Display` gives its rows).
    pub fn header() -> String {
        format!(
            "{:<44} {:>14} {:>12} {:>18} {:>10}",
            "backend", "paths/s", "build (s)", "gather (s/Mpix/spp)", "total (s)"
        )
    }
}

impl std::fmt::Display for Throughput {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{:<44} {:>14.0} {:>12.4} {:>18.3} {:>10.3}",
            self.backend,
            self.paths_per_s,
            self.build_s,
            self.gather_s_per_mpix_sample,
            self.total_s
        )
    }
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
    let plan = crate::plan::MapPlan::new(scene, s);
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
        kind: backend,
        backend: name,
        paths_per_s: median(rows.iter().map(|r| r.0).collect()),
        build_s: median(rows.iter().map(|r| r.1).collect()),
        gather_s_per_mpix_sample: median(rows.iter().map(|r| r.2).collect()),
        total_s: median(rows.iter().map(|r| r.3).collect()),
    })
}

/// The throughput of every backend of `which`, in order; `on_result` sees each result as it
/// comes, or the reason a failing GPU was skipped. Returns those that ran.
pub fn throughputs(
    scene: &Scene,
    s: &RenderSettings,
    which: &BenchBackends,
    runs: usize,
    mut on_result: impl FnMut(std::result::Result<&Throughput, &str>),
) -> Result<Vec<Throughput>> {
    let mut results = Vec::new();
    for &b in &which.backends {
        match throughput(scene, s, b, runs) {
            Ok(t) => {
                on_result(Ok(&t));
                results.push(t);
            }
            Err(e) => match which.skips(&e) {
                Some(why) => on_result(Err(why)),
                None => return Err(e),
            },
        }
    }
    Ok(results)
}
