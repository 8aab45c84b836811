//! Benchmarks (`gpu-photon bench`): throughput of each backend on one scene (timed per phase,
//! medians over several runs), the speed-against-error ladder (`ladder`), the progressive
//! error curve (`curve`) against a peer's recorded one (`peer`) and their plot (`plot`). The policy lives here: which backends run,
//! when a GPU failure only skips the GPU, and how a missing reference is rendered.

pub mod curve;
#[cfg(feature = "embree")]
#[allow(unsafe_code)]
pub mod embree;
pub mod gpu_rays;
pub mod ladder;
pub mod mesh;
pub mod peer;
pub mod plot;
pub mod rays;

pub use curve::{curve_csv, progressive_curve, CurvePoint};
pub use ladder::{ladder, ladder_csv, plot_title, reference_settings, LadderRow, LADDER};
pub use peer::{PeerCurve, PeerPoint};
pub use plot::{plot, PLOT_FONT};

use crate::error::{Error, Result};
use crate::render::report::{Progress, RenderReport};
use crate::render::session::{render, Backend, BackendChoice};
use crate::scene::Scene;
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

/// The benchmark's settings: the scene's with `(photons, spp, width, height)`, one classic
/// pass; or, with `None`, the scene's own default render (`gpu-photon render SCENE -o OUT`:
/// its size, photons and progressive passes).
pub fn bench_settings(scene: &Scene, sizes: Option<(u32, u32, u32, u32)>) -> RenderSettings {
    match sizes {
        Some((photons, spp, width, height)) => RenderSettings {
            photons,
            spp,
            width,
            height,
            ..scene.settings.clone()
        },
        None => scene.settings.as_default_render(),
    }
}

/// The first line of the benchmark's report: scene, size, samples, photons, mode, runs.
pub fn heading(scene_path: &std::path::Path, s: &RenderSettings, runs: usize) -> String {
    let passes = match s.pass_range {
        Some((a, b)) => format!("{} passes of ", b - a),
        None => String::new(),
    };
    format!(
        "{}: {}x{} at {passes}{} spp, {} photon paths, mode {}, medians of {runs} runs",
        scene_path.display(),
        s.width,
        s.height,
        s.spp,
        s.photons,
        s.mode.name(),
    )
}

/// The memory of the scene's heterogeneous media, one line each: the grids' voxels (every
/// volume read from a file) and the majorant grid's cells, in bytes. Empty without such media.
pub fn media_memory(scene: &Scene) -> Vec<String> {
    use crate::media::MediumKind;
    let mut lines = Vec::new();
    for (i, m) in scene.media.iter().enumerate() {
        if let MediumKind::Heterogeneous(h) = &m.kind {
            let (_, _, res, cells) = h.majorants.parts();
            lines.push(format!(
                "medium {i} (heterogeneous): grids {} bytes, majorant grid {}x{}x{} cells {} bytes",
                h.grid_bytes(),
                res.x,
                res.y,
                res.z,
                std::mem::size_of_val(cells)
            ));
        }
    }
    lines
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
    /// Median seconds of every phase of the render, in the order they ran (on the GPU each
    /// phase is its own submission, waited for: a per-submission wall time).
    pub phases: Vec<(&'static str, f64)>,
    /// Median device seconds of every GPU kernel (timestamp queries; empty on the CPU and
    /// on a device without them).
    pub kernels: Vec<(&'static str, f64)>,
}

/// The per-phase table of `results` (one column per backend, then the GPU/CPU ratio when
/// both ran): where each backend's time goes, phase by phase; then each GPU kernel's device
/// time, where timed (rows `kernel NAME`).
pub fn phase_table(results: &[Throughput]) -> Vec<String> {
    // The names in `times` of any result, in the order they first appear.
    let names_in = |times: fn(&Throughput) -> &[(&'static str, f64)]| {
        let mut names: Vec<&'static str> = Vec::new();
        for &(n, _) in results.iter().flat_map(times) {
            if !names.contains(&n) {
                names.push(n);
            }
        }
        names
    };
    let names = names_in(|t| &t.phases);
    let secs = |t: &Throughput, n: &str| t.phases.iter().find(|p| p.0 == n).map(|p| p.1);
    // The name column: 22 wide, wider for a long kernel name.
    let w = results
        .iter()
        .flat_map(|t| &t.kernels)
        .map(|k| "kernel ".len() + k.0.len() + 1)
        .fold(22, usize::max);
    let mut head = format!("{:<w$}", "phase (s, median)");
    for t in results {
        head += &format!(" {:>10}", backend_name(t.kind));
    }
    let pair = match results {
        [c, g] if c.kind == Backend::Cpu && g.kind == Backend::Gpu => Some((c, g)),
        _ => None,
    };
    if pair.is_some() {
        head += &format!(" {:>8}", "gpu/cpu");
    }
    let mut lines = vec![head];
    for n in names {
        let mut row = format!("{n:<w$}");
        for t in results {
            row += &match secs(t, n) {
                Some(s) => format!(" {s:>10.3}"),
                None => format!(" {:>10}", "-"),
            };
        }
        if let Some((c, g)) = pair {
            row += &match (secs(c, n), secs(g, n)) {
                (Some(a), Some(b)) if a > 0.0 => format!(" {:>8.2}", b / a),
                _ => format!(" {:>8}", "-"),
            };
        }
        lines.push(row);
    }
    for n in names_in(|t| &t.kernels) {
        let mut row = format!("{:<w$}", format!("kernel {n}"));
        for t in results {
            row += &match t.kernels.iter().find(|k| k.0 == n) {
                Some(k) => format!(" {:>10.3}", k.1),
                None => format!(" {:>10}", "-"),
            };
        }
        lines.push(row);
    }
    lines
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

/// One backend's runs so far.
struct Runs {
    kind: Backend,
    name: String,
    /// (paths/s, build s, gather s per Mpix-sample, total s) of each run.
    rows: Vec<[f64; 4]>,
    phases: Vec<(&'static str, Vec<f64>)>,
    kernels: Vec<(&'static str, Vec<f64>)>,
}

impl Runs {
    fn new(kind: Backend) -> Self {
        Runs {
            kind,
            name: String::new(),
            rows: Vec::new(),
            phases: Vec::new(),
            kernels: Vec::new(),
        }
    }

    /// Adds one render's report; `paths` and `msamples` are the render's photon paths and
    /// camera samples (millions).
    fn add(&mut self, r: &RenderReport, paths: f64, msamples: f64) {
        self.name = r.backend.clone();
        for (all, times) in [
            (&mut self.phases, &r.phases),
            (&mut self.kernels, &r.kernels),
        ] {
            for &(n, d) in times {
                match all.iter_mut().find(|p| p.0 == n) {
                    Some(p) => p.1.push(d.as_secs_f64()),
                    None => all.push((n, vec![d.as_secs_f64()])),
                }
            }
        }
        self.rows.push([
            paths / phase(r, &["trace photons"]).max(1e-9),
            phase(r, &["build kd-trees", "build grids"]),
            phase(r, &["gather"]) / msamples.max(1e-12),
            r.total().as_secs_f64(),
        ]);
    }

    fn medians(self) -> Throughput {
        let col = |i: usize| median(self.rows.iter().map(|r| r[i]).collect());
        Throughput {
            kind: self.kind,
            backend: self.name.clone(),
            paths_per_s: col(0),
            build_s: col(1),
            gather_s_per_mpix_sample: col(2),
            total_s: col(3),
            phases: self
                .phases
                .into_iter()
                .map(|(n, v)| (n, median(v)))
                .collect(),
            kernels: self
                .kernels
                .into_iter()
                .map(|(n, v)| (n, median(v)))
                .collect(),
        }
    }
}

/// The median throughput of every backend of `which` over `runs` renders each, in order.
/// The backends take turns run by run (CPU, GPU, CPU, GPU, ...), so a machine whose speed
/// drifts during the benchmark slows both alike and their ratio stays fair. `on_result`
/// sees each result, or the reason a failing GPU was skipped (at its first failure).
/// Returns those that ran.
pub fn throughputs(
    scene: &Scene,
    s: &RenderSettings,
    which: &BenchBackends,
    runs: usize,
    mut on_result: impl FnMut(std::result::Result<&Throughput, &str>),
) -> Result<Vec<Throughput>> {
    let plan = crate::integrators::plan::MapPlan::new(
        scene,
        &crate::lights::table::LightTable::new(scene),
        s,
    );
    // Every pass traces the first pass's paths (the radius shrinks, the count stays).
    let passes = s.pass_range.map_or(1, |(a, b)| b - a) as f64;
    let paths = passes * plan.total_paths() as f64;
    let msamples = passes * s.width as f64 * s.height as f64 * s.spp as f64 / 1e6;
    // Each GPU phase its own submission, so the phases can be timed apart.
    let s = &RenderSettings {
        timed_phases: true,
        ..s.clone()
    };
    let mut all: Vec<Option<Runs>> = which.backends.iter().map(|&b| Some(Runs::new(b))).collect();
    for _ in 0..runs.max(1) {
        for slot in all.iter_mut() {
            let Some(acc) = slot else { continue };
            match render(scene, s, acc.kind, Progress::default()) {
                Ok((_, r)) => acc.add(&r, paths, msamples),
                Err(e) => match which.skips(&e) {
                    Some(why) => {
                        on_result(Err(why));
                        *slot = None;
                    }
                    None => return Err(e),
                },
            }
        }
    }
    let results: Vec<Throughput> = all.into_iter().flatten().map(Runs::medians).collect();
    for t in &results {
        on_result(Ok(t));
    }
    Ok(results)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn run(kind: Backend, phases: Vec<(&'static str, f64)>) -> Throughput {
        Throughput {
            kind,
            backend: backend_name(kind).into(),
            paths_per_s: 1.0,
            build_s: 0.0,
            gather_s_per_mpix_sample: 0.0,
            total_s: phases.iter().map(|p| p.1).sum(),
            phases,
            kernels: Vec::new(),
        }
    }

    #[test]
    fn the_phase_table_lines_up_phases_and_gives_the_gpu_cpu_ratio() {
        let cpu = run(
            Backend::Cpu,
            vec![
                ("trace photons", 0.5),
                ("build kd-trees", 0.25),
                ("gather", 2.0),
            ],
        );
        let mut gpu = run(
            Backend::Gpu,
            vec![
                ("trace photons", 1.0),
                ("build grids", 0.5),
                ("gather", 7.0),
            ],
        );
        gpu.kernels = vec![("count_cells", 0.125), ("list_cache_points", 0.0625)];
        let t = phase_table(&[cpu, gpu]);
        assert!(t[0].contains("cpu") && t[0].contains("gpu") && t[0].contains("gpu/cpu"));
        let row = |name: &str| t.iter().find(|l| l.starts_with(name)).unwrap().clone();
        // "kernel list_cache_points" is 24 characters: the name column is 25 wide.
        let cells = |name: &str| -> Vec<String> {
            row(name)[25..]
                .split_whitespace()
                .map(String::from)
                .collect()
        };
        assert_eq!(cells("trace photons"), ["0.500", "1.000", "2.00"]);
        assert_eq!(cells("gather"), ["2.000", "7.000", "3.50"]);
        assert_eq!(cells("build kd-trees"), ["0.250", "-", "-"]);
        assert_eq!(cells("build grids"), ["-", "0.500", "-"]);
        // Kernels after the phases, GPU column only (no ratio: the CPU has no kernels).
        assert_eq!(cells("kernel count_cells"), ["-", "0.125"]);
        assert_eq!(cells("kernel list_cache_points"), ["-", "0.062"]);
        assert_eq!(t.len(), 7);
    }
}
