//! `gpu-photon render`: its arguments, the one-shot and progressive renders, `--aov` layers.

use crate::{print_warnings, signals, BackendArg};
use anyhow::{bail, Context, Result};
use clap::Args;
use gpu_photon::{
    Aov, Filter, Flow, FresnelMode, Image, LoadOptions, Mode, RenderSettings, Renderer, Sampler,
    Scene, SliceFile, Stop, MAX_PASSES,
};
use std::io::IsTerminal;
use std::path::PathBuf;
use std::time::Instant;

#[derive(Args)]
pub(crate) struct RenderArgs {
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
    #[arg(short = 'D', long, value_name = "NAME=VALUE", value_parser = LoadOptions::parse_define)]
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
    /// Radius of the volume photons' beam estimate (participating media; the first
    /// progressive pass's is at most this).
    #[arg(long)]
    volume_radius: Option<f32>,
    /// Camera samples per pixel (a perfect square gives an n x n jittered grid).
    #[arg(long)]
    spp: Option<u32>,
    /// Shadow rays per area light per camera sample; also single-scattering estimates per
    /// light along a camera segment in a medium.
    #[arg(long)]
    shadow_samples: Option<u32>,
    /// Adaptive sampling: a pixel takes up to N times spp camera samples a pass, by the noise
    /// two pilot images show around it (1: spp everywhere; 0, the default: 16 for passes of
    /// 16 spp or more on 64 x 64 pixels or more, else 1; CPU backend only).
    #[arg(long)]
    adaptive: Option<u32>,
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
    #[arg(long, value_parser = gpu_photon::parse_pass_range)]
    pass_range: Option<(u32, u32)>,
    /// With --passes P: only slice I (0-based) of N of the passes (balanced); `/N` takes I
    /// from SLURM_ARRAY_TASK_ID or JOB_COMPLETION_INDEX.
    #[arg(long, value_name = "I/N", value_parser = gpu_photon::parse_slice)]
    slice: Option<gpu_photon::SliceSpec>,
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
    /// Feature images for denoisers, written as extra layers of the .exr output:
    /// `albedo`, `normal` (camera space) or both, `albedo,normal` (as Cycles' denoising passes).
    #[arg(long, value_name = "LIST", value_parser = parse_aovs)]
    aov: Option<AovList>,
    /// No progress bars or timings.
    #[arg(short, long)]
    quiet: bool,
}

/// `--aov`'s list (a type of its own: clap reads an `Option<Vec<_>>` as repeated values).
#[derive(Clone)]
struct AovList(Vec<Aov>);

fn parse_aovs(text: &str) -> std::result::Result<AovList, String> {
    Aov::parse_list(text)
        .map(AovList)
        .map_err(|e| e.to_string())
}

/// Adds `--aov`'s layers to the image the render wrote.
fn write_aovs(args: &RenderArgs, scene: &Scene, settings: &RenderSettings) -> Result<()> {
    let Some(AovList(aovs)) = &args.aov else {
        return Ok(());
    };
    let images = scene.aovs(settings, aovs, AOV_SAMPLES)?;
    let layers: Vec<(&str, &Image)> = aovs.iter().map(|a| a.name()).zip(&images).collect();
    gpu_photon::add_exr_layers(&args.output, &layers)?;
    Ok(())
}

/// Camera samples per pixel of `--aov`'s feature images.
const AOV_SAMPLES: u32 = 16;

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
            volume_radius
        );
        set!(spp, shadow_samples, caustic_every, seed, width);
        set!(adaptive);
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
            (Some(n), None, _) => Some(gpu_photon::slice_pass_range(n, self.slice)?),
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

/// Renders; returns the exit status (see `run_progressive`).
pub(crate) fn run_render(args: &RenderArgs) -> Result<u8> {
    gpu_photon::check_output_path(&args.output)?;
    let exr = args
        .output
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    if args.aov.is_some() && !exr {
        bail!(
            "--aov writes layers of an .exr image: {} is not one",
            args.output.display()
        );
    }
    let options = LoadOptions {
        camera: args.camera.clone(),
        defines: args.define.clone(),
        env: args.env.clone(),
        env_scale: args.env_scale,
    };
    let scene = Scene::load_with(&args.scene, &options)?;
    print_warnings(scene.warnings());
    let mut settings = scene.settings();
    args.apply(&mut settings)?;
    let show = !args.quiet && std::io::stderr().is_terminal();
    if settings.pass_range.is_some() {
        return run_progressive(args, &scene, &settings, show);
    }
    let mut r = Renderer::new(&scene, &settings, args.backend.choice())?;
    print_warnings(&r.take_warnings());
    r.show_progress_bars(show);
    r.run(&Stop::default(), |_, _| Flow::Continue)?;
    print_warnings(&r.take_warnings());
    let report = r.report()?;
    r.image().write(&args.output, settings.exposure)?;
    write_aovs(args, &scene, &settings)?;
    warn_if_incomplete(&args.output, &report);
    if !args.quiet {
        for line in report.summary(&args.output, &settings) {
            eprintln!("{line}");
        }
    }
    Ok(0)
}

/// A progressive render to a slice file: stops at --time, --noise, Ctrl-C or SIGTERM (after
/// the pass in progress), writes the running mean every --write-every passes and at the end.
/// Returns the exit status: that of the signal which stopped the render short of its planned
/// passes (see `signals::Stop::exit_status`), else 0.
fn run_progressive(
    args: &RenderArgs,
    scene: &Scene,
    settings: &RenderSettings,
    show: bool,
) -> Result<u8> {
    let file = SliceFile::new(&args.scene, &args.output, settings, args.passes)?;
    let started = Instant::now();
    let mut r = Renderer::new(scene, settings, args.backend.choice())?;
    print_warnings(&r.take_warnings());
    r.show_progress_bars(show);
    // From here on a signal finishes the pass in flight; before, it ends the process with
    // nothing done and nothing written.
    signals::install();
    let mut write_error = None;
    r.run(&Stop::default(), |info, r| {
        if let Some(n) = args.write_every {
            if n > 0 && info.done % n == 0 {
                if let Err(e) = file.write(r) {
                    write_error = Some(e);
                    return Flow::Stop;
                }
            }
        }
        let out_of_time = args
            .time
            .is_some_and(|t| started.elapsed().as_secs_f64() >= t);
        let quiet_enough = args.noise.zip(info.noise).is_some_and(|(t, n)| n <= t);
        if out_of_time || quiet_enough || signals::received().is_some() {
            Flow::Stop
        } else {
            Flow::Continue
        }
    })?;
    print_warnings(&r.take_warnings());
    if let Some(e) = write_error {
        return Err(e.into());
    }
    file.write(&r)?;
    write_aovs(args, scene, settings)?;
    let report = r.report()?;
    warn_if_incomplete(&args.output, &report);
    let stopped = signals::received();
    let (done, planned) = (r.done(), r.passes());
    let short = done.end < planned.end;
    if let Some(signal) = stopped {
        // Even with --quiet: a scheduler's log should say what the file holds.
        let of = if planned.end < MAX_PASSES {
            format!(" of {}..{}", planned.start, planned.end)
        } else {
            String::new()
        };
        eprintln!(
            "{}: stopped by {} after passes {}..{}{of}; wrote them",
            args.output.display(),
            signal.name(),
            done.start,
            done.end
        );
    }
    if !args.quiet {
        let wall = started.elapsed();
        let lines =
            gpu_photon::progressive_summary(&r, &report, &args.output, stopped.is_some(), wall);
        lines.iter().for_each(|line| eprintln!("{line}"));
    }
    Ok(match stopped {
        Some(signal) if short => signal.exit_status(),
        _ => 0,
    })
}

/// Warns (even with --quiet) when a GPU render hit one of its bounds.
fn warn_if_incomplete(output: &std::path::Path, report: &gpu_photon::Report) {
    if let Some(warning) = report.incomplete_warning(output) {
        eprintln!("{warning}");
    }
}
