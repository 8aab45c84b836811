//! The `gpu-photon` command line: render, diff.

use anyhow::{bail, Context, Result};
use clap::{Args, Parser, Subcommand, ValueEnum};
use gpu_photon::film::{diff, Image};
use gpu_photon::report::Progress;
use gpu_photon::scene::mitsuba;
use gpu_photon::session::{render, render_slice, BackendChoice, SliceJob};
use gpu_photon::settings::{Filter, FresnelMode, Mode, RenderSettings, Sampler, MAX_PASSES};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

#[derive(Parser)]
#[command(
    name = "gpu-photon",
    version,
    about = "Photon-mapping renderer (WGSL compute kernels via wgpu, rayon CPU reference)"
)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Render a scene to an EXR (linear float) or PNG (sRGB) image.
    Render(Box<RenderArgs>),
    /// List the Vulkan adapters with their type and the limits that matter.
    Adapters,
    /// Combine progressive slices (`render --pass-range`) into the image of all their passes.
    Merge {
        /// Slices (EXR written by `render --pass-range` or `--passes`).
        inputs: Vec<PathBuf>,
        #[arg(short, long)]
        output: PathBuf,
        /// Write the mean of the passes there even when some of the render's are missing.
        #[arg(long)]
        partial: bool,
    },
    /// Throughput of each available backend on one scene: photon paths traced per second,
    /// map build time, gather time per megapixel-sample (medians of --runs).
    Bench(BenchArgs),
    /// Compare two images: RMSE, per-channel mean ratio, max error.
    Diff {
        /// The image to measure.
        a: PathBuf,
        /// The reference.
        b: PathBuf,
        /// Side of the blocks whose means the block RMSE compares.
        #[arg(long, default_value_t = 16)]
        block: u32,
        /// Also write |a - b| per pixel to this image (.exr or .png).
        #[arg(long)]
        error_image: Option<PathBuf>,
    },
}

#[derive(Args)]
struct BenchArgs {
    /// Scene file.
    scene: PathBuf,
    #[arg(long, default_value_t = 200_000)]
    photons: u32,
    #[arg(long, default_value_t = 4)]
    spp: u32,
    #[arg(long, default_value_t = 128)]
    width: u32,
    #[arg(long, default_value_t = 128)]
    height: u32,
    /// Runs per backend (medians are reported).
    #[arg(long, default_value_t = 3)]
    runs: usize,
    /// Only this backend.
    #[arg(long, value_enum)]
    backend: Option<BackendArg>,
    /// Reference image: with --passes, also measure a progressive curve (error against time).
    #[arg(long)]
    reference: Option<PathBuf>,
    /// Progressive passes of the curve (measured at 1, 2, 4, ... and the last).
    #[arg(long)]
    passes: Option<u32>,
    /// With --out: the modes the ladder compares, comma-separated (e.g. `direct,gather`;
    /// default: the scene's mode).
    #[arg(long)]
    modes: Option<String>,
    /// Write the curve as DIR/progressive.csv.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Bench the scene's default render (as `render SCENE -o OUT`) instead of --photons etc.
    #[arg(long)]
    default_render: bool,
}

#[derive(Clone, Copy, ValueEnum)]
enum BackendArg {
    /// The GPU when an adapter is there, else the CPU (with a warning).
    Auto,
    Cpu,
    Gpu,
}

#[derive(Args)]
struct RenderArgs {
    /// Scene file: .toml, Mitsuba .xml, glTF .gltf/.glb (see scenes/README.md).
    scene: PathBuf,
    /// Output image: .exr or .png.
    #[arg(short, long)]
    output: PathBuf,
    #[arg(long, value_enum, default_value = "auto")]
    backend: BackendArg,
    /// The glTF camera to render from, by name (default: the first in the scene).
    #[arg(long)]
    camera: Option<String>,
    /// The environment light, supplied or replaced: `R,G,B` or a lat-long image (Mitsuba's).
    #[arg(long, value_name = "FILE|R,G,B")]
    env: Option<String>,
    /// Factor on --env's radiance or image.
    #[arg(long, value_name = "S", requires = "env")]
    env_scale: Option<f32>,
    /// A Mitsuba scene's parameter `$NAME` (overrides its <default>; Mitsuba's -D).
    #[arg(short = 'D', long, value_name = "NAME=VALUE", value_parser = mitsuba::parse_define)]
    define: Vec<(String, String)>,
    /// Photon paths for the global map.
    #[arg(long)]
    photons: Option<u32>,
    /// Photons aimed at specular surfaces for the caustic map (0: none).
    #[arg(long)]
    caustic_photons: Option<u32>,
    /// K nearest photons in the radiance estimate.
    #[arg(long)]
    k: Option<u32>,
    /// Maximum search radius of the global map.
    #[arg(long)]
    radius: Option<f32>,
    /// Maximum search radius of the caustic map.
    #[arg(long)]
    caustic_radius: Option<f32>,
    /// Camera samples per pixel (a perfect square gives an n x n jittered grid).
    #[arg(long)]
    spp: Option<u32>,
    /// Shadow rays per area light per camera sample (direct mode).
    #[arg(long)]
    shadow_samples: Option<u32>,
    /// Run the caustic-map estimate on one camera sample in N (1: every sample).
    #[arg(long)]
    caustic_every: Option<u32>,
    /// photon | direct | gather | direct-only | global-only | caustic-only
    #[arg(long)]
    mode: Option<String>,
    /// sobol | independent: where camera samples' first numbers come from.
    #[arg(long)]
    sampler: Option<String>,
    /// disc | cone | epanechnikov
    #[arg(long)]
    filter: Option<String>,
    /// Use Schlick's approximation instead of exact Fresnel.
    #[arg(long)]
    schlick: bool,
    #[arg(long)]
    seed: Option<u32>,
    #[arg(long)]
    width: Option<u32>,
    #[arg(long)]
    height: Option<u32>,
    /// PNG exposure in stops.
    #[arg(long)]
    exposure: Option<f32>,
    /// Progressive photon mapping: render passes 0..N and write their mean (0: one classic
    /// pass with K-nearest estimates; default: the scene's `passes`, else 4).
    #[arg(long)]
    passes: Option<u32>,
    /// Progressive passes A..B only (a slice of a longer render, for `gpu-photon merge`).
    #[arg(long, value_parser = gpu_photon::merge::parse_range)]
    pass_range: Option<(u32, u32)>,
    /// With --passes P: only slice I (0-based) of N of the passes (balanced); `/N` takes I
    /// from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX.
    #[arg(long, value_name = "I/N", value_parser = gpu_photon::slice::parse_spec)]
    slice: Option<gpu_photon::slice::SliceSpec>,
    /// Stop progressive passes after this many seconds (without --passes: pass until then).
    #[arg(long)]
    time: Option<f64>,
    /// Stop progressive passes at the first even pass count whose estimated relative noise
    /// is at most this (e.g. 0.03); without --passes: pass until then.
    #[arg(long)]
    noise: Option<f64>,
    /// Write the running mean every N progressive passes.
    #[arg(long)]
    write_every: Option<u32>,
    /// Radius reduction of progressive passes, in (0, 1).
    #[arg(long)]
    alpha: Option<f32>,
    /// Global-map radius of the first progressive pass (default: chosen from the scene).
    #[arg(long)]
    initial_radius: Option<f32>,
    /// No progress bars or timings.
    #[arg(short, long)]
    quiet: bool,
}

impl RenderArgs {
    fn apply(&self, s: &mut RenderSettings) -> Result<()> {
        macro_rules! set {
            ($($f:ident),*) => { $(if let Some(v) = self.$f { s.$f = v; })* };
        }
        set!(photons, caustic_photons, k, radius, caustic_radius);
        set!(spp, shadow_samples, caustic_every, seed, width);
        set!(height, exposure, alpha);
        if self.initial_radius.is_some() {
            s.initial_radius = self.initial_radius;
        }
        s.passes = self.passes.unwrap_or(s.passes);
        let until = self.time.or(self.noise);
        s.pass_range = match (self.passes, self.pass_range, until) {
            (Some(_), Some(_), _) => bail!("--passes and --pass-range exclude each other"),
            (Some(0), _, _) if self.slice.is_some() || until.is_some() => {
                bail!("--passes 0 (one classic pass) excludes --slice, --time and --noise")
            }
            (None, _, _) if self.slice.is_some() => bail!("--slice needs --passes"),
            (Some(0), None, _) => None,
            (Some(n), None, _) => Some(gpu_photon::slice::pass_range(n, self.slice)?),
            (None, Some(r), _) => Some(r),
            (None, None, Some(_)) => Some((0, MAX_PASSES)),
            (None, None, None) => s.as_default_render().pass_range,
        };
        if let Some(m) = &self.mode {
            s.mode = Mode::parse(m).with_context(|| {
                format!("--mode {m}: expected one of {}", Mode::NAMES.join(", "))
            })?;
        }
        if let Some(f) = &self.filter {
            s.filter = Filter::parse(f).with_context(|| {
                format!("--filter {f}: expected one of {}", Filter::NAMES.join(", "))
            })?;
        }
        if let Some(m) = &self.sampler {
            s.sampler = Sampler::parse(m).with_context(|| {
                format!(
                    "--sampler {m}: expected one of {}",
                    Sampler::NAMES.join(", ")
                )
            })?;
        }
        if self.schlick {
            s.fresnel = FresnelMode::Schlick;
        }
        Ok(())
    }
}

impl BackendArg {
    fn choice(self) -> BackendChoice {
        match self {
            BackendArg::Auto => BackendChoice::Auto,
            BackendArg::Cpu => BackendChoice::Cpu,
            BackendArg::Gpu => BackendChoice::Gpu,
        }
    }
}

fn run_render(args: &RenderArgs) -> Result<()> {
    gpu_photon::film::check_output_path(&args.output)?;
    let (camera, defines, env) = (args.camera.as_deref(), &args.define, args.env.as_deref());
    let mut scene = gpu_photon::scene::load_with_options(&args.scene, camera, defines)?;
    gpu_photon::scene::apply_env_arg(&mut scene, env, args.env_scale, &args.scene)?;
    let mut settings = scene.settings.clone();
    args.apply(&mut settings)?;
    let show = !args.quiet && std::io::stderr().is_terminal();
    let progress = Progress { enabled: show };
    if settings.pass_range.is_some() {
        return run_progressive(args, &scene, &settings, progress);
    }
    let (image, report) = render(&scene, &settings, args.backend.choice(), progress)?;
    image.write(&args.output, settings.exposure)?;
    warn_if_incomplete(&args.output, &report);
    if !args.quiet {
        for line in report.summary(&args.output, &settings) {
            eprintln!("{line}");
        }
    }
    Ok(())
}

fn run_progressive(
    args: &RenderArgs,
    scene: &gpu_photon::Scene,
    settings: &RenderSettings,
    progress: Progress,
) -> Result<()> {
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    let interrupted = Arc::new(AtomicBool::new(false));
    let flag = interrupted.clone();
    // A second Ctrl-C while finishing the pass is left to the default handler's absence:
    // the flag is simply set again.
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));
    let job = SliceJob {
        scene_path: &args.scene,
        output: &args.output,
        time: args.time,
        write_every: args.write_every,
        noise: args.noise,
        stop: &interrupted,
        total_passes: args.passes,
    };
    let done = render_slice(scene, settings, args.backend.choice(), progress, &job)?;
    warn_if_incomplete(&args.output, &done.report);
    if !args.quiet {
        for line in done.summary(&args.output, settings, interrupted.load(Ordering::SeqCst)) {
            eprintln!("{line}");
        }
    }
    Ok(())
}

/// Warns (even with --quiet) when a GPU render hit one of its bounds.
fn warn_if_incomplete(output: &std::path::Path, report: &gpu_photon::report::RenderReport) {
    if let Some(warning) = report.incomplete_warning(output) {
        eprintln!("{warning}");
    }
}

fn run_merge(inputs: &[PathBuf], output: &PathBuf, partial: bool) -> Result<()> {
    let s = gpu_photon::merge::merge(inputs, output, partial)?;
    eprintln!("{}: {s}", output.display());
    Ok(())
}

fn run_bench(args: &BenchArgs) -> Result<()> {
    use gpu_photon::bench::{self, BenchBackends};
    let scene = gpu_photon::scene::load(&args.scene)?;
    let sizes = (args.photons, args.spp, args.width, args.height);
    let s = bench::bench_settings(&scene, (!args.default_render).then_some(sizes));
    let which = BenchBackends::of(args.backend.map(BackendArg::choice));
    let modes = match &args.modes {
        Some(list) => Mode::parse_list(list)?,
        None => vec![s.mode],
    };
    println!("{}", bench::heading(&args.scene, &s, args.runs));
    println!("{}", bench::Throughput::header());
    let results = bench::throughputs(&scene, &s, &which, args.runs, |r| match r {
        Ok(t) => println!("{t}"),
        Err(why) => eprintln!("gpu: skipped ({why})"),
    })?;
    let ran = which.only(results.iter().map(|t| t.kind).collect());
    if let Some(dir) = &args.out {
        let reference = match &args.reference {
            Some(r) => r.clone(),
            None => {
                std::fs::create_dir_all(dir)
                    .with_context(|| format!("creating {}", dir.display()))?;
                let path = dir.join("reference.exr");
                println!(
                    "no --reference: rendering one first with the CPU backend ({}) to {}",
                    bench::ladder::describe_reference(&bench::reference_settings(&scene)),
                    path.display()
                );
                bench::ladder::render_reference(&scene, &path)?;
                path
            }
        };
        ladder_bench(&scene, &args.scene, &s, &ran, &modes, &reference, dir)?;
    }
    if let (Some(reference), Some(passes)) = (&args.reference, args.passes) {
        curve_bench(&scene, &s, &ran, reference, passes, args.out.as_deref())?;
    }
    bench::phase_table(&results)
        .iter()
        .for_each(|l| println!("{l}"));
    if let [cpu, gpu] = &results[..] {
        println!("{}", bench::ratios(cpu, gpu));
    }
    Ok(())
}

/// The speed-against-error ladder: every rung on every backend, as DIR/bench.csv and a
/// log-log plot DIR/bench.png.
fn ladder_bench(
    scene: &gpu_photon::Scene,
    scene_path: &std::path::Path,
    s: &RenderSettings,
    which: &gpu_photon::bench::BenchBackends,
    modes: &[Mode],
    reference: &std::path::Path,
    dir: &std::path::Path,
) -> Result<()> {
    use gpu_photon::bench::{ladder, ladder_csv, plot, plot_title, LadderRow, LADDER};
    let reference = Image::read(reference)?;
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    println!(
        "speed against error ({}x{}, the reference's size):",
        reference.width, reference.height
    );
    println!("{}", LadderRow::header());
    let rows = ladder(scene, s, &which.backends, modes, &reference, &LADDER, |r| {
        println!("{r}")
    })?;
    let csv = dir.join("bench.csv");
    std::fs::write(&csv, ladder_csv(&rows))
        .with_context(|| format!("writing {}", csv.display()))?;
    println!("wrote {}", csv.display());
    let png = dir.join("bench.png");
    let title = plot_title(scene_path, reference.width, reference.height, modes);
    match plot(&rows, &png, &title) {
        Ok(()) => println!("wrote {}", png.display()),
        Err(e) => eprintln!("warning: no plot: {e}"),
    }
    Ok(())
}

/// Error against the reference after 1, 2, 4, ... passes, with the wall time, per backend.
fn curve_bench(
    scene: &gpu_photon::Scene,
    s: &RenderSettings,
    which: &gpu_photon::bench::BenchBackends,
    reference: &std::path::Path,
    passes: u32,
    out: Option<&std::path::Path>,
) -> Result<()> {
    let reference = Image::read(reference)?;
    println!("progressive curve against the reference ({passes} passes):");
    println!("{}", gpu_photon::bench::CurvePoint::header());
    let points = gpu_photon::bench::progressive_curve(
        scene,
        s,
        which,
        &reference,
        passes,
        |p| println!("{p}"),
        |why| eprintln!("gpu: skipped ({why})"),
    )?;
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let path = dir.join("progressive.csv");
        std::fs::write(&path, gpu_photon::bench::curve_csv(&points))
            .with_context(|| format!("writing {}", path.display()))?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

fn run_adapters() -> Result<()> {
    let adapters = gpu_photon::gpu::list_adapters();
    if adapters.is_empty() {
        bail!("no Vulkan adapter found (install mesa-vulkan-drivers for lavapipe)");
    }
    for (i, a) in adapters.iter().enumerate() {
        a.lines(i).iter().for_each(|l| println!("{l}"));
    }
    Ok(())
}

fn run_diff(a: &PathBuf, b: &PathBuf, block: u32, error_image: Option<&PathBuf>) -> Result<()> {
    let ia = Image::read(a)?;
    let ib = Image::read(b)?;
    let d = match diff(&ia, &ib, block) {
        Ok(d) => d,
        Err(e) => bail!("{} vs {}: {e}", a.display(), b.display()),
    };
    if let Some(path) = error_image {
        ia.abs_diff(&ib).write(path, 0.0)?;
    }
    d.lines(block).iter().for_each(|l| println!("{l}"));
    Ok(())
}

fn main() -> ExitCode {
    // SAFETY: called before any thread starts. The default SIGPIPE action ends the process
    // quietly when its output pipe closes (`gpu-photon diff A B | head -1`), instead of a
    // panic in `println!`.
    #[cfg(unix)]
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
    }
    let cli = Cli::parse();
    gpu_photon::gpu::quiet_headless_vulkan();
    let result = match &cli.command {
        Command::Render(args) => run_render(args),
        Command::Adapters => run_adapters(),
        Command::Merge {
            inputs,
            output,
            partial,
        } => run_merge(inputs, output, *partial),
        Command::Bench(args) => run_bench(args),
        Command::Diff {
            a,
            b,
            block,
            error_image,
        } => run_diff(a, b, *block, error_image.as_ref()),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}
