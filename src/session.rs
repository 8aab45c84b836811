//! The render session: a backend renderer built once per render (BVH, lights, photon plan,
//! pipelines), then asked for pass after pass. Single, progressive and sliced renders are
//! written once over that contract.

use crate::error::{Error, Result};
use crate::film::Image;
use crate::report::{Progress, RenderReport};
use crate::scene::Scene;
use crate::settings::{validate, RenderSettings};

/// Which backend renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    Cpu,
    Gpu,
}

/// The one contract between the session and a backend: built once per render from the scene
/// and the render's settings, then asked for passes. `pass` is the RNG's pass index and
/// `settings` that pass's settings (the render's own for a classic render; for a progressive
/// pass, `progressive::pass_settings`, which only shrinks the radii and sets `k = 0`).
pub trait PassRenderer {
    /// Renders pass `pass` and returns its image.
    fn pass(&mut self, pass: u32, settings: &RenderSettings, progress: &Progress) -> Result<Image>;
    /// Timings and counts of every pass so far (phases of the same name summed).
    fn report(&mut self) -> Result<RenderReport>;
}

/// Renders `scene` with `settings` on `backend`: one classic pass, or with
/// `settings.pass_range` the mean of those progressive passes.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    backend: Backend,
    progress: Progress,
) -> Result<(Image, RenderReport)> {
    validate(settings)?;
    if let Some((a, b)) = settings.pass_range {
        let (acc, report) = render_progressive(scene, settings, backend, progress, a..b, |_| {
            crate::progressive::Flow::Continue
        })?;
        return Ok((acc.mean(), report));
    }
    match backend {
        Backend::Cpu => {
            let (img, mut report) = crate::cpu::render(scene, settings, 0, &progress);
            report.backend = format!("cpu ({} threads)", rayon::current_num_threads());
            Ok((img, report))
        }
        Backend::Gpu => {
            let mut r = crate::gpu::GpuRenderer::new(scene, settings)?;
            let image = r.pass(0, settings, &progress)?;
            Ok((image, r.report()?))
        }
    }
}

/// Progressive passes `passes` (see `crate::progressive`), accumulated into a running mean;
/// `on_pass` sees the accumulator after every pass and may stop early (time budget, Ctrl-C).
pub fn render_progressive(
    scene: &Scene,
    settings: &RenderSettings,
    backend: Backend,
    progress: Progress,
    passes: std::ops::Range<u32>,
    mut on_pass: impl FnMut(&crate::progressive::Accumulator) -> crate::progressive::Flow,
) -> Result<(crate::progressive::Accumulator, RenderReport)> {
    use crate::progressive::{pass_settings, Accumulator, Flow};
    validate(settings)?;
    if !(settings.alpha > 0.0 && settings.alpha < 1.0) {
        return Err(Error::Setting {
            field: "alpha",
            message: format!("{} is outside (0, 1)", settings.alpha),
        });
    }
    if passes.is_empty() {
        return Err(Error::Setting {
            field: "pass-range",
            message: format!("{}..{} holds no pass", passes.start, passes.end),
        });
    }
    let mut acc = Accumulator::new(settings.width, settings.height, passes.start);
    let bar = progress.bar(passes.len() as u64, "passes");
    let quiet = Progress { enabled: false };
    let report = match backend {
        Backend::Cpu => {
            let mut report = RenderReport {
                backend: format!("cpu ({} threads)", rayon::current_num_threads()),
                ..Default::default()
            };
            for p in passes {
                let (img, r) =
                    crate::cpu::render(scene, &pass_settings(scene, settings, p), p, &quiet);
                report.absorb(&r);
                acc.add(&img);
                bar.inc(1);
                if on_pass(&acc) == Flow::Stop {
                    break;
                }
            }
            report
        }
        Backend::Gpu => {
            let mut r = crate::gpu::GpuRenderer::new(scene, settings)?;
            for p in passes {
                let img = r.pass(p, &pass_settings(scene, settings, p), &quiet)?;
                acc.add(&img);
                bar.inc(1);
                if on_pass(&acc) == Flow::Stop {
                    break;
                }
            }
            r.report()?
        }
    };
    bar.finish_and_clear();
    Ok((acc, report))
}
