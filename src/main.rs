//! The `gpu-photon` command line: render, diff.

use anyhow::{bail, Context, Result};
use clap::{Args, Parser, Subcommand, ValueEnum};
use gpu_photon::film::{diff, Image};
use gpu_photon::report::Progress;
use gpu_photon::session::{render, Backend};
use gpu_photon::settings::{Filter, FresnelMode, Mode, RenderSettings};
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
    Render(RenderArgs),
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
    /// Write the curve as DIR/progressive.csv.
    #[arg(long)]
    out: Option<PathBuf>,
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
    /// Scene file (TOML; see scenes/README.md).
    scene: PathBuf,
    /// Output image: .exr or .png.
    #[arg(short, long)]
    output: PathBuf,
    #[arg(long, value_enum, default_value = "auto")]
    backend: BackendArg,
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
    /// photon | direct | direct-only | global-only | caustic-only
    #[arg(long)]
    mode: Option<String>,
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
    /// Progressive photon mapping: render passes 0..N and write their mean.
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
        set!(
            photons,
            caustic_photons,
            k,
            radius,
            caustic_radius,
            spp,
            shadow_samples,
            seed,
            width,
            height,
            exposure,
            alpha
        );
        if self.initial_radius.is_some() {
            s.initial_radius = self.initial_radius;
        }
        s.pass_range = match (self.passes, self.pass_range, self.time) {
            (Some(_), Some(_), _) => bail!("--passes and --pass-range exclude each other"),
            (Some(0), _, _) => bail!("--passes must be at least 1"),
            (None, _, _) if self.slice.is_some() => bail!("--slice needs --passes"),
            (Some(n), None, _) => Some(gpu_photon::slice::pass_range(n, self.slice)?),
            (None, Some(r), _) => Some(r),
            (None, None, Some(_)) => Some((0, u32::MAX >> 8)),
            (None, None, None) => None,
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
        if self.schlick {
            s.fresnel = FresnelMode::Schlick;
        }
        Ok(())
    }
}

fn run_render(args: &RenderArgs) -> Result<()> {
    gpu_photon::film::check_output_path(&args.output)?;
    let scene = gpu_photon::scene::load(&args.scene)?;
    let mut settings = scene.settings.clone();
    args.apply(&mut settings)?;
    let show = !args.quiet && std::io::stderr().is_terminal();
    let progress = Progress { enabled: show };
    if settings.pass_range.is_some() {
        return run_progressive(args, &scene, &settings, progress);
    }
    let (image, report) = match args.backend {
        BackendArg::Cpu => render(&scene, &settings, Backend::Cpu, progress)?,
        BackendArg::Gpu => render(&scene, &settings, Backend::Gpu, progress)?,
        BackendArg::Auto => match gpu_photon::gpu::hardware_adapter() {
            Ok(_) => match render(&scene, &settings, Backend::Gpu, progress) {
                Ok(r) => r,
                Err(gpu_photon::Error::Gpu(why)) => {
                    eprintln!("warning: GPU backend failed ({why}); rendering on the CPU");
                    render(&scene, &settings, Backend::Cpu, progress)?
                }
                Err(e) => return Err(e.into()),
            },
            Err(why) => {
                eprintln!("warning: {why}; rendering on the CPU");
                render(&scene, &settings, Backend::Cpu, progress)?
            }
        },
    };
    image.write(&args.output, settings.exposure)?;
    warn_if_incomplete(&args.output, &report);
    if !args.quiet {
        eprintln!(
            "{}: {}x{}, {} spp, mode {}, backend {}",
            args.output.display(),
            settings.width,
            settings.height,
            settings.spp,
            settings.mode.name(),
            report.backend
        );
        eprintln!(
            "  photons stored: {} global, {} caustic",
            report.global_stored, report.caustic_stored
        );
        if report.batches > 1 {
            eprintln!(
                "  photon maps split into {} batches (one storage binding each); counts are the last batch's",
                report.batches
            );
        }
        if let [overflow, budget, truncated, ..] = report.gpu_stats[..] {
            eprintln!("  gpu bounds hit: {overflow} photons dropped (buffer full), {budget} invocations out of loop budget, {truncated} truncated searches");
        }
        for (name, d) in &report.phases {
            eprintln!("  {name:<16} {:>9.3} s", d.as_secs_f64());
        }
        eprintln!("  {:<16} {:>9.3} s", "total", report.total().as_secs_f64());
    }
    Ok(())
}

fn run_progressive(
    args: &RenderArgs,
    scene: &gpu_photon::Scene,
    settings: &RenderSettings,
    progress: Progress,
) -> Result<()> {
    use gpu_photon::progressive::Flow;
    use std::sync::atomic::{AtomicBool, Ordering};
    use std::sync::Arc;
    let (a, b) = settings.pass_range.expect("progressive settings");
    let backend = match args.backend {
        BackendArg::Gpu => Backend::Gpu,
        BackendArg::Cpu => Backend::Cpu,
        BackendArg::Auto if gpu_photon::gpu::hardware_adapter().is_ok() => Backend::Gpu,
        BackendArg::Auto => Backend::Cpu,
    };
    let interrupted = Arc::new(AtomicBool::new(false));
    let flag = interrupted.clone();
    // A second Ctrl-C while finishing the pass is left to the default handler's absence:
    // the flag is simply set again.
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));
    let sig = gpu_photon::merge::signature(&args.scene, settings)?;
    let start = std::time::Instant::now();
    let write = |acc: &gpu_photon::progressive::Accumulator| -> Result<()> {
        let tags = gpu_photon::merge::slice_tags(acc, &sig, args.passes);
        acc.mean()
            .write_tagged(&args.output, settings.exposure, &tags)?;
        Ok(())
    };
    let mut write_error = None;
    let (acc, report) =
        gpu_photon::session::render_progressive(scene, settings, backend, progress, a..b, |acc| {
            if let Some(n) = args.write_every {
                if n > 0 && acc.count % n == 0 {
                    if let Err(e) = write(acc) {
                        write_error = Some(e);
                        return Flow::Stop;
                    }
                }
            }
            let out_of_time = args
                .time
                .is_some_and(|t| start.elapsed().as_secs_f64() >= t);
            if interrupted.load(Ordering::SeqCst) || out_of_time {
                Flow::Stop
            } else {
                Flow::Continue
            }
        })?;
    if let Some(e) = write_error {
        return Err(e);
    }
    write(&acc)?;
    warn_if_incomplete(&args.output, &report);
    if !args.quiet {
        let why = if interrupted.load(Ordering::SeqCst) {
            " (interrupted)"
        } else {
            ""
        };
        eprintln!(
            "{}: passes {}..{}{why}, {}x{}, {} spp per pass, mode {}, backend {}",
            args.output.display(),
            acc.first,
            acc.first + acc.count,
            settings.width,
            settings.height,
            settings.spp,
            settings.mode.name(),
            report.backend
        );
        for (name, d) in &report.phases {
            eprintln!("  {name:<18} {:>9.3} s", d.as_secs_f64());
        }
        eprintln!("  {:<18} {:>9.3} s", "wall", start.elapsed().as_secs_f64());
    }
    Ok(())
}

/// Warns (even with --quiet) when a GPU render hit one of its bounds: its image is not what
/// the settings ask for.
fn warn_if_incomplete(output: &std::path::Path, report: &gpu_photon::report::RenderReport) {
    if let [overflow, budget, truncated, ..] = report.gpu_stats[..] {
        if overflow + budget + truncated > 0 {
            eprintln!(
                "warning: {}: the GPU image is incomplete ({overflow} photons dropped, {budget} invocations out of loop budget, {truncated} searches truncated); lower --k, --radius or --initial-radius, or use --backend cpu",
                output.display()
            );
        }
    }
}

fn run_merge(inputs: &[PathBuf], output: &PathBuf, partial: bool) -> Result<()> {
    let s = gpu_photon::merge::merge(inputs, output, partial)?;
    eprintln!("{}: {s}", output.display());
    Ok(())
}

fn run_bench(args: &BenchArgs) -> Result<()> {
    use gpu_photon::bench::throughput;
    let scene = gpu_photon::scene::load(&args.scene)?;
    let s = RenderSettings {
        photons: args.photons,
        spp: args.spp,
        width: args.width,
        height: args.height,
        ..scene.settings.clone()
    };
    let backends: Vec<Backend> = match args.backend {
        Some(BackendArg::Cpu) => vec![Backend::Cpu],
        Some(BackendArg::Gpu) => vec![Backend::Gpu],
        _ => vec![Backend::Cpu, Backend::Gpu],
    };
    println!(
        "{}: {}x{} at {} spp, {} photon paths, mode {}, medians of {} runs",
        args.scene.display(),
        s.width,
        s.height,
        s.spp,
        s.photons,
        s.mode.name(),
        args.runs
    );
    println!(
        "{:<44} {:>14} {:>12} {:>18} {:>10}",
        "backend", "paths/s", "build (s)", "gather (s/Mpix/spp)", "total (s)"
    );
    let mut results = Vec::new();
    for &b in &backends {
        match throughput(&scene, &s, b, args.runs) {
            Ok(t) => {
                println!(
                    "{:<44} {:>14.0} {:>12.4} {:>18.3} {:>10.3}",
                    t.backend, t.paths_per_s, t.build_s, t.gather_s_per_mpix_sample, t.total_s
                );
                results.push(t);
            }
            Err(gpu_photon::Error::Gpu(why)) if args.backend.is_none() => {
                eprintln!("gpu: skipped ({why})")
            }
            Err(e) => return Err(e.into()),
        }
    }
    let avail: Vec<Backend> = results
        .iter()
        .map(|t| {
            if t.backend.starts_with("cpu") {
                Backend::Cpu
            } else {
                Backend::Gpu
            }
        })
        .collect();
    if let Some(dir) = &args.out {
        let reference = match &args.reference {
            Some(r) => r.clone(),
            None => {
                std::fs::create_dir_all(dir)
                    .with_context(|| format!("creating {}", dir.display()))?;
                let path = dir.join("reference.exr");
                println!(
                    "no --reference: rendering one first with the CPU backend (progressive, 16 passes x 200,000 photons x 16 spp at {}x{}) to {}",
                    scene.settings.width,
                    scene.settings.height,
                    path.display()
                );
                let rs = RenderSettings {
                    photons: 200_000,
                    spp: 16,
                    pass_range: Some((1000, 1016)),
                    ..scene.settings.clone()
                };
                let (img, _) = render(&scene, &rs, Backend::Cpu, Progress::default())?;
                img.write(&path, 0.0)?;
                path
            }
        };
        ladder_bench(&scene, &args.scene, &s, &avail, &reference, dir)?;
    }
    if let (Some(reference), Some(passes)) = (&args.reference, args.passes) {
        progressive_curve(
            &scene,
            &s,
            &avail,
            &args.backend,
            reference,
            passes,
            args.out.as_deref(),
        )?;
    }
    if let [cpu, gpu] = &results[..] {
        println!(
            "gpu/cpu time ratios: trace {:.2}, build {:.2}, gather {:.2}, total {:.2}",
            cpu.paths_per_s / gpu.paths_per_s,
            gpu.build_s / cpu.build_s.max(1e-9),
            gpu.gather_s_per_mpix_sample / cpu.gather_s_per_mpix_sample,
            gpu.total_s / cpu.total_s
        );
    }
    Ok(())
}

/// The speed-against-error ladder: every rung on every backend, as DIR/bench.csv and a
/// log-log plot DIR/bench.png.
fn ladder_bench(
    scene: &gpu_photon::Scene,
    scene_path: &std::path::Path,
    s: &RenderSettings,
    backends: &[Backend],
    reference: &std::path::Path,
    dir: &std::path::Path,
) -> Result<()> {
    use gpu_photon::bench::{ladder, ladder_csv, plot, LADDER};
    let reference = Image::read(reference)?;
    std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    println!(
        "speed against error ({}x{}, the reference's size):",
        reference.width, reference.height
    );
    println!(
        "{:<8} {:>8} {:>5} {:>5} {:>10} {:>10} {:>10} {:>24}",
        "backend", "photons", "spp", "k", "seconds", "rmse", "rel_mse", "mean ratio"
    );
    let rows = ladder(scene, s, backends, &reference, &LADDER, |r| {
        let m = r.mean_ratio;
        println!(
            "{:<8} {:>8} {:>5} {:>5} {:>10.2} {:>10.5} {:>10.5} {:>8.4} {:>7.4} {:>7.4}",
            r.backend, r.photons, r.spp, r.k, r.total_s, r.rmse, r.rel_mse, m[0], m[1], m[2]
        );
    })?;
    let csv = dir.join("bench.csv");
    std::fs::write(&csv, ladder_csv(&rows))
        .with_context(|| format!("writing {}", csv.display()))?;
    println!("wrote {}", csv.display());
    let png = dir.join("bench.png");
    let name = scene_path.file_name().map_or_else(
        || scene_path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let title = format!(
        "speed against error: {name}, {}x{}, {} mode",
        reference.width,
        reference.height,
        s.mode.name()
    );
    match plot(&rows, &png, &title) {
        Ok(()) => println!("wrote {}", png.display()),
        Err(e) => eprintln!("warning: no plot: {e}"),
    }
    Ok(())
}

/// Error against the reference after 1, 2, 4, ... passes, with the wall time, per backend.
fn progressive_curve(
    scene: &gpu_photon::Scene,
    s: &RenderSettings,
    backends: &[Backend],
    only: &Option<BackendArg>,
    reference: &std::path::Path,
    passes: u32,
    out: Option<&std::path::Path>,
) -> Result<()> {
    use gpu_photon::progressive::Flow;
    let reference = Image::read(reference)?;
    // The curve renders at the reference's size.
    let s = &RenderSettings {
        width: reference.width,
        height: reference.height,
        ..s.clone()
    };
    let mut csv = String::from(
        "backend,passes,seconds,rmse,rel_mse,mean_ratio_r,mean_ratio_g,mean_ratio_b\n",
    );
    println!("progressive curve against the reference ({passes} passes):");
    println!(
        "{:<8} {:>7} {:>10} {:>10} {:>10} {:>24}",
        "backend", "passes", "seconds", "rmse", "rel_mse", "mean ratio"
    );
    for &b in backends {
        let name = if b == Backend::Cpu { "cpu" } else { "gpu" };
        let start = std::time::Instant::now();
        let mut failure = None;
        let result = gpu_photon::session::render_progressive(
            scene,
            s,
            b,
            Progress::default(),
            0..passes,
            |acc| {
                if acc.count.is_power_of_two() || acc.count == passes {
                    let secs = start.elapsed().as_secs_f64();
                    match diff(&acc.mean(), &reference, 16) {
                        Ok(d) => {
                            let m = d.mean_ratio;
                            println!("{name:<8} {:>7} {secs:>10.2} {:>10.5} {:>10.5} {:>8.4} {:>7.4} {:>7.4}", acc.count, d.rmse, d.rel_mse, m[0], m[1], m[2]);
                            csv.push_str(&format!(
                                "{name},{},{secs:.4},{:.6},{:.6},{:.5},{:.5},{:.5}\n",
                                acc.count, d.rmse, d.rel_mse, m[0], m[1], m[2]
                            ));
                        }
                        Err(e) => {
                            failure = Some(e);
                            return Flow::Stop;
                        }
                    }
                }
                Flow::Continue
            },
        );
        if let Some(e) = failure {
            bail!("{}: {e}", "reference");
        }
        match result {
            Ok(_) => {}
            Err(gpu_photon::Error::Gpu(why)) if only.is_none() => eprintln!("gpu: skipped ({why})"),
            Err(e) => return Err(e.into()),
        }
    }
    if let Some(dir) = out {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
        let path = dir.join("progressive.csv");
        std::fs::write(&path, csv).with_context(|| format!("writing {}", path.display()))?;
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
        println!("[{i}] {} ({}, {})", a.name, a.backend, a.device_type);
        println!("    driver: {}", a.driver);
        println!(
            "    max_storage_buffer_binding_size: {} MiB",
            a.max_storage_buffer_binding_size >> 20
        );
        println!("    max_buffer_size: {} MiB", a.max_buffer_size >> 20);
        println!(
            "    max_storage_buffers_per_shader_stage: {}",
            a.max_storage_buffers_per_shader_stage
        );
        println!(
            "    max_compute_workgroups_per_dimension: {}",
            a.max_compute_workgroups_per_dimension
        );
        println!(
            "    max_compute_invocations_per_workgroup: {}",
            a.max_compute_invocations_per_workgroup
        );
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
        let mut err = ia.clone();
        for (p, q) in err.pixels.iter_mut().zip(&ib.pixels) {
            *p = [0, 1, 2].map(|c| (p[c] - q[c]).abs());
        }
        err.write(path, 0.0)?;
    }
    println!("rmse        {:.6}", d.rmse);
    println!("block_rmse  {:.6} ({block}x{block} blocks)", d.block_rmse);
    println!("rel_mse     {:.6}", d.rel_mse);
    println!(
        "mean_ratio  {:.4} {:.4} {:.4}",
        d.mean_ratio[0], d.mean_ratio[1], d.mean_ratio[2]
    );
    println!("max_error   {:.6}", d.max_error);
    Ok(())
}

/// Mesa's Vulkan drivers print an error on every device creation when XDG_RUNTIME_DIR is
/// unset (headless machines); give them a private directory instead.
fn quiet_headless_vulkan() {
    if std::env::var_os("XDG_RUNTIME_DIR").is_some() {
        return;
    }
    let dir = std::env::temp_dir().join("gpu-photon-runtime");
    if std::fs::create_dir_all(&dir).is_ok() {
        use std::os::unix::fs::PermissionsExt;
        let _ = std::fs::set_permissions(&dir, std::fs::Permissions::from_mode(0o700));
        std::env::set_var("XDG_RUNTIME_DIR", &dir);
    }
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    quiet_headless_vulkan();
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
