//! The `gpu-photon` command line: render (render_cmd.rs), bench (bench_cmd.rs), merge, diff,
//! adapters.

use anyhow::{bail, Result};
use clap::{Args, Parser, Subcommand, ValueEnum};
use gpu_photon::{Backend, Image, Warning};
use std::path::PathBuf;
use std::process::ExitCode;

mod bench_cmd;
mod bench_rays_cmd;
mod render_cmd;
mod signals;

use render_cmd::{run_render, RenderArgs};

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
pub(crate) struct BenchArgs {
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
    /// Also write the throughputs as JSON to FILE, with the settings and every adapter's
    /// name, driver, limits and subgroup size.
    #[arg(long, value_name = "FILE")]
    json: Option<PathBuf>,
    /// Ray throughput instead: the renderer's camera, shadow, gather and photon rays at
    /// --width x --height, traced one thread by our BVHs (and Embree when built with the
    /// `embree` feature), in rays per second per core; with `--backend gpu`, on the device by
    /// its binary and its four-wide walk, in rays per second.
    #[arg(long)]
    rays: bool,
    /// With --rays: add a generated displaced sphere of about N triangles to the scene.
    #[arg(long, value_name = "N")]
    mesh: Option<usize>,
}

#[derive(Clone, Copy, ValueEnum)]
enum BackendArg {
    /// The GPU when an adapter is there, else the CPU (with a warning).
    Auto,
    Cpu,
    Gpu,
}

impl BackendArg {
    fn choice(self) -> Backend {
        match self {
            BackendArg::Auto => Backend::Auto,
            BackendArg::Cpu => Backend::Cpu,
            BackendArg::Gpu => Backend::Gpu,
        }
    }
}

/// Prints the library's warnings, as it reports them.
fn print_warnings(warnings: &[Warning]) {
    warnings.iter().for_each(|w| eprintln!("warning: {w}"));
}

fn run_merge(inputs: &[PathBuf], output: &PathBuf, partial: bool) -> Result<()> {
    let s = gpu_photon::merge(inputs, output, partial)?;
    eprintln!("{}: {s}", output.display());
    Ok(())
}

fn run_adapters() -> Result<()> {
    let adapters = gpu_photon::adapters();
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
    let d = match ia.diff(&ib, block) {
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
    // panic in `println!`. SIGXFSZ ignored: a write past a file size limit (`ulimit -f`)
    // then fails with an error naming the image, instead of a core dump.
    #[cfg(unix)]
    unsafe {
        libc::signal(libc::SIGPIPE, libc::SIG_DFL);
        libc::signal(libc::SIGXFSZ, libc::SIG_IGN);
    }
    let cli = Cli::parse();
    gpu_photon::quiet_headless_vulkan();
    let result = match &cli.command {
        Command::Render(args) => run_render(args).map(ExitCode::from),
        Command::Adapters => run_adapters().map(|()| ExitCode::SUCCESS),
        Command::Merge {
            inputs,
            output,
            partial,
        } => run_merge(inputs, output, *partial).map(|()| ExitCode::SUCCESS),
        Command::Bench(args) => bench_cmd::run_bench(args).map(|()| ExitCode::SUCCESS),
        Command::Diff {
            a,
            b,
            block,
            error_image,
        } => run_diff(a, b, *block, error_image.as_ref()).map(|()| ExitCode::SUCCESS),
    };
    match result {
        Ok(code) => code,
        Err(e) => {
            eprintln!("error: {e:#}");
            ExitCode::from(1)
        }
    }
}
