//! The `gpu-photon` command line: render, diff.

use anyhow::{bail, Context, Result};
use clap::{Args, Parser, Subcommand, ValueEnum};
use gpu_photon::film::{diff, Image};
use gpu_photon::render::{render, Backend, Progress};
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
            exposure
        );
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
    let scene = gpu_photon::scene::load(&args.scene)?;
    let mut settings = scene.settings.clone();
    args.apply(&mut settings)?;
    let show = !args.quiet && std::io::stderr().is_terminal();
    let progress = Progress { enabled: show };
    let (image, report) = match args.backend {
        BackendArg::Cpu => render(&scene, &settings, Backend::Cpu, progress)?,
        BackendArg::Gpu => render(&scene, &settings, Backend::Gpu, progress)?,
        BackendArg::Auto => match render(&scene, &settings, Backend::Gpu, progress) {
            Ok(r) => r,
            Err(gpu_photon::Error::Gpu(why)) => {
                eprintln!("warning: GPU backend unavailable ({why}); rendering on the CPU");
                render(&scene, &settings, Backend::Cpu, progress)?
            }
            Err(e) => return Err(e.into()),
        },
    };
    image.write(&args.output, settings.exposure)?;
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
    for b in backends {
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

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match &cli.command {
        Command::Render(args) => run_render(args),
        Command::Adapters => run_adapters(),
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
