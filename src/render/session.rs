//! The render session: a backend renderer built once per render (BVH, lights, photon plan,
//! pipelines), then asked for pass after pass. Single, progressive and sliced renders are
//! written once over that contract ([`PassRenderer`]), and `--backend auto` is decided in one
//! place ([`open`]).

use crate::error::{Error, Result};
use crate::render::film::Image;
use crate::render::progressive::{pass_settings, Accumulator, Flow};
use crate::render::report::{Progress, RenderReport};
use crate::scene::Scene;
use crate::settings::{validate, RenderSettings};
use std::ops::Range;
use std::path::Path;
use std::time::Instant;

pub use crate::render::report::PassRenderer;

/// Which backend renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// Rayon and kd-trees (`crate::integrators::cpu`): the reference.
    Cpu,
    /// WGSL compute kernels through wgpu (`crate::integrators::gpu`).
    Gpu,
}

/// Which backend the caller asks for: one of them, or `Auto` (see [`open`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BackendChoice {
    /// The faster backend on this machine, by the measured rule of `crate::render::calibration`.
    Auto,
    /// The CPU backend.
    Cpu,
    /// The GPU backend; its failures are errors.
    Gpu,
}

impl From<Backend> for BackendChoice {
    fn from(b: Backend) -> Self {
        match b {
            Backend::Cpu => BackendChoice::Cpu,
            Backend::Gpu => BackendChoice::Gpu,
        }
    }
}

/// The renderer of `backend` for a render of `scene` with `settings`, built once.
fn open_backend<'s>(
    backend: Backend,
    scene: &'s Scene,
    settings: &RenderSettings,
) -> Result<Box<dyn PassRenderer + 's>> {
    // Before anything of the render is allocated.
    crate::render::budget::check(scene, settings, backend == Backend::Cpu)?;
    if backend == Backend::Gpu && settings.adaptive > 1 {
        crate::warning::warn(format!(
            "adaptive sampling (adaptive {}) is the CPU backend's only: the GPU renders {} \
             samples in every pixel",
            settings.adaptive, settings.spp
        ));
    }
    Ok(match backend {
        Backend::Cpu => Box::new(crate::integrators::cpu::CpuRenderer::new(scene, settings)?),
        Backend::Gpu => Box::new(crate::integrators::gpu::GpuRenderer::new(scene, settings)?),
    })
}

/// The renderer the caller's choice gives, built once for a render of `scene` with
/// `settings`. The one rule for `Auto` (`crate::render::calibration`): the GPU when, on this adapter,
/// it rendered the calibration scene faster than the CPU (measured once, then read from the
/// cache file), else the CPU with a one-line warning on stderr; without an adapter, the CPU
/// with a warning; a GPU that fails to open or fails its first pass (`Error::Gpu`) also gives
/// way to the CPU with a warning. Scenes with participating media choose as any other.
pub fn open<'s>(
    choice: BackendChoice,
    scene: &'s Scene,
    settings: &RenderSettings,
) -> Result<Box<dyn PassRenderer + 's>> {
    match choice {
        BackendChoice::Cpu => open_backend(Backend::Cpu, scene, settings),
        BackendChoice::Gpu => open_backend(Backend::Gpu, scene, settings),
        BackendChoice::Auto => match crate::integrators::gpu::renderer::unsupported(scene)
            .map_or_else(auto_rule, Err)
        {
            Err(why) => {
                crate::warning::warn(format!("{why}; rendering on the CPU"));
                open_backend(Backend::Cpu, scene, settings)
            }
            Ok(_) => match open_backend(Backend::Gpu, scene, settings) {
                Ok(gpu) => Ok(Box::new(Fallback {
                    scene,
                    settings: settings.clone(),
                    inner: gpu,
                    may_fall_back: true,
                })),
                Err(Error::Gpu(why)) => fall_back(&why, scene, settings),
                Err(e) => Err(e),
            },
        },
    }
}

/// `Ok` when `Auto` should render on the GPU; else why not (see [`open`]).
fn auto_rule() -> std::result::Result<(), String> {
    use crate::render::calibration::{cache_file, key, read, write};
    let adapter = crate::integrators::gpu::preferred_adapter()?;
    let key = key(&adapter.name, &adapter.driver);
    let file = cache_file();
    let c = match file.as_deref().and_then(|f| read(f, &key)) {
        Some(c) => c,
        None => {
            let c = calibrate(key).map_err(|e| format!("the calibration render failed ({e})"))?;
            if let Some(f) = &file {
                let _ = write(f, &c);
            }
            c
        }
    };
    if c.gpu_is_faster() {
        return Ok(());
    }
    let at = file.map_or(String::new(), |f| {
        format!("; measured once, kept in {}", f.display())
    });
    Err(format!(
        "on {} the CPU backend is faster ({:.3} s against {:.3} s for the calibration pass{at})",
        adapter.name, c.cpu_seconds, c.gpu_seconds
    ))
}

/// Times one warm pass of the calibration scene on each backend.
fn calibrate(key: String) -> Result<crate::render::calibration::Calibration> {
    use crate::render::calibration::{calibration_settings, CALIBRATION_SCENE};
    let scene = crate::importers::load_str(CALIBRATION_SCENE, "calibration scene", Path::new("."))?;
    let s = &calibration_settings(&scene.settings);
    let quiet = Progress { enabled: false };
    let time = |b: Backend| -> Result<f64> {
        let mut r = open_backend(b, &scene, s)?;
        r.pass(0, &pass_settings(&scene, s, 0), &quiet)?;
        let t = Instant::now();
        r.pass(1, &pass_settings(&scene, s, 1), &quiet)?;
        Ok(t.elapsed().as_secs_f64())
    };
    let cpu_seconds = time(Backend::Cpu)?;
    let gpu_seconds = match time(Backend::Gpu) {
        Ok(t) => t,
        Err(Error::Gpu(_)) => f64::INFINITY,
        Err(e) => return Err(e),
    };
    Ok(crate::render::calibration::Calibration {
        key,
        cpu_seconds,
        gpu_seconds,
    })
}

/// How long a fall-back to the CPU waits for the GPU to finish what it was given (a hung
/// device is left to itself after that).
const FALLBACK_DRAIN: std::time::Duration = std::time::Duration::from_secs(30);

/// Warns that the GPU failed, lets the device finish what it was given (at most
/// [`FALLBACK_DRAIN`]) and opens the CPU renderer instead.
fn fall_back<'s>(
    why: &str,
    scene: &'s Scene,
    settings: &RenderSettings,
) -> Result<Box<dyn PassRenderer + 's>> {
    crate::warning::warn(format!("GPU backend failed ({why}); rendering on the CPU"));
    crate::integrators::gpu::context::GpuContext::drain_shared(FALLBACK_DRAIN);
    open_backend(Backend::Cpu, scene, settings)
}

/// `Auto` on a GPU: until a pass has succeeded there, a GPU failure hands the render to the
/// CPU (never later, so an image is never a mixture of backends).
struct Fallback<'s> {
    scene: &'s Scene,
    settings: RenderSettings,
    inner: Box<dyn PassRenderer + 's>,
    may_fall_back: bool,
}

impl PassRenderer for Fallback<'_> {
    fn pass(&mut self, pass: u32, settings: &RenderSettings, progress: &Progress) -> Result<Image> {
        match self.inner.pass(pass, settings, progress) {
            Err(Error::Gpu(why)) if self.may_fall_back => {
                self.may_fall_back = false;
                self.inner = fall_back(&why, self.scene, &self.settings)?;
                self.inner.pass(pass, settings, progress)
            }
            r => {
                self.may_fall_back = false;
                r
            }
        }
    }

    fn report(&mut self) -> Result<RenderReport> {
        self.inner.report()
    }
}

/// Renders `scene` with `settings` on `backend`: one classic pass, or with
/// `settings.pass_range` the mean of those progressive passes.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    backend: impl Into<BackendChoice>,
    progress: Progress,
) -> Result<(Image, RenderReport)> {
    validate(settings)?;
    if let Some((a, b)) = settings.pass_range {
        let (acc, report) =
            render_progressive(scene, settings, backend, progress, a..b, |_| Flow::Continue)?;
        return Ok((acc.mean(), report));
    }
    let mut renderer = open(backend.into(), scene, settings)?;
    let image = renderer.pass(0, settings, &progress)?;
    Ok((image, renderer.report()?))
}

/// Progressive passes `passes` (see `crate::render::progressive`), accumulated into a running mean;
/// `on_pass` sees the accumulator after every pass and may stop early (time budget, Ctrl-C).
pub fn render_progressive(
    scene: &Scene,
    settings: &RenderSettings,
    backend: impl Into<BackendChoice>,
    progress: Progress,
    passes: Range<u32>,
    mut on_pass: impl FnMut(&Accumulator) -> Flow,
) -> Result<(Accumulator, RenderReport)> {
    validate(settings)?;
    if passes.is_empty() {
        return Err(Error::Setting {
            field: "pass-range",
            message: format!("{}..{} holds no pass", passes.start, passes.end),
        });
    }
    let mut acc = Accumulator::new(settings.width, settings.height, passes.start);
    let bar = progress.bar(passes.len() as u64, "passes");
    let quiet = Progress { enabled: false };
    let mut renderer = open(backend.into(), scene, settings)?;
    for p in passes {
        let image = renderer.pass(p, &pass_settings(scene, settings, p), &quiet)?;
        acc.add(&image);
        bar.inc(1);
        if on_pass(&acc) == Flow::Stop {
            break;
        }
    }
    bar.finish_and_clear();
    Ok((acc, renderer.report()?))
}
