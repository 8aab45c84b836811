//! Backend-neutral render orchestration: which photon maps a scene and mode need, the photon
//! budgets, progress reporting and per-phase timings.

use crate::error::{Error, Result};
use crate::film::Image;
use crate::geometry::Aabb;
use crate::light::{scalar_power, specular_bounds, split_budget};
use crate::photon::{Budget, Photon};
use crate::scene::Scene;
use crate::settings::{Mode, RenderSettings, MAX_K, MAX_RESOLUTION};
use std::time::{Duration, Instant};

/// Which backend renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    Cpu,
    Gpu,
}

/// Timings and counts of one render.
#[derive(Clone, Debug, Default)]
pub struct RenderReport {
    pub phases: Vec<(&'static str, Duration)>,
    /// Photons stored by the global paths (before filtering by mode).
    pub global_stored: usize,
    /// Photons stored in the caustic map.
    pub caustic_stored: usize,
    /// Which backend ran, in words.
    pub backend: String,
    /// GPU bound counters (photon overflow, loop budget, gather truncation), if on the GPU.
    pub gpu_stats: Vec<u32>,
    /// Photon batches the pass was split into (GPU: one storage binding per map).
    pub batches: u32,
}

impl RenderReport {
    /// Records a phase that started at `since`.
    pub fn phase(&mut self, name: &'static str, since: Instant) {
        self.phases.push((name, since.elapsed()));
    }
    pub fn total(&self) -> Duration {
        self.phases.iter().map(|p| p.1).sum()
    }
    /// Adds another report's phases (summing phases of the same name) and counts.
    pub fn absorb(&mut self, other: &RenderReport) {
        for &(name, d) in &other.phases {
            match self.phases.iter_mut().find(|p| p.0 == name) {
                Some(p) => p.1 += d,
                None => self.phases.push((name, d)),
            }
        }
        self.global_stored = other.global_stored;
        self.caustic_stored = other.caustic_stored;
        self.batches = self.batches.max(other.batches);
    }
}

/// Shows progress bars on stderr when enabled.
#[derive(Clone, Copy, Debug, Default)]
pub struct Progress {
    pub enabled: bool,
}

impl Progress {
    pub fn bar(&self, len: u64, what: &str) -> indicatif::ProgressBar {
        if !self.enabled {
            return indicatif::ProgressBar::hidden();
        }
        let bar = indicatif::ProgressBar::new(len);
        if let Ok(style) = indicatif::ProgressStyle::with_template(
            "{msg:>14} [{bar:40}] {pos}/{len} {elapsed_precise} eta {eta}",
        ) {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(what.to_string());
        bar
    }
}

/// Pilot photons per light that estimate how often caustic emission hits the specular bounds.
pub const PILOT_PHOTONS: u32 = 4096;
/// Caustic attempts per light are capped at this multiple of its caustic photon count.
pub const MAX_AIM_FACTOR: f64 = 256.0;

/// The photon maps a render needs: only what the scene and mode use.
#[derive(Clone, Debug)]
pub struct MapPlan {
    pub mode: Mode,
    /// Global paths per light (`None`: no global map in this mode).
    pub global: Option<Budget>,
    /// Caustic attempts per light and the bounds they aim at (`None`: no specular surface,
    /// no caustic photons asked for, or a mode that does not use them).
    pub caustic: Option<(Budget, Vec<Aabb>)>,
}

impl MapPlan {
    pub fn new(scene: &Scene, s: &RenderSettings) -> Self {
        let uses_global = matches!(s.mode, Mode::Photon | Mode::Direct | Mode::GlobalOnly);
        let uses_caustic = matches!(s.mode, Mode::Photon | Mode::Direct | Mode::CausticOnly);
        let global =
            (uses_global && !scene.lights.is_empty()).then(|| Budget::split(scene, s.photons));
        let bounds = specular_bounds(scene);
        let caustic = (uses_caustic
            && s.caustic_photons > 0
            && !bounds.is_empty()
            && !scene.lights.is_empty())
        .then(|| {
            let powers: Vec<f64> = scene.lights.iter().map(|l| scalar_power(l.power)).collect();
            let wanted = split_budget(&powers, s.caustic_photons);
            let table = crate::light::LightTable::new(scene);
            let attempts = wanted
                .iter()
                .enumerate()
                .map(|(l, &n)| {
                    if n == 0 {
                        return 0;
                    }
                    let frac =
                        aim_fraction(scene, &table, l, &bounds, s.seed).max(1.0 / MAX_AIM_FACTOR);
                    ((n as f64 / frac).ceil()).min(u32::MAX as f64 / 4.0) as u32
                })
                .collect();
            (Budget::from_counts(scene, attempts), bounds)
        });
        MapPlan {
            mode: s.mode,
            global,
            caustic,
        }
    }

    /// Whether a photon of the global paths belongs in the global map of this mode: `direct`
    /// drops direct photons (shadow rays do that light); both main modes drop L S+ D photons
    /// when the caustic map carries them.
    pub fn keep_in_global(&self, p: &Photon) -> bool {
        let caustic_elsewhere = self.caustic.is_some() && p.is_caustic();
        match self.mode {
            Mode::Photon => !caustic_elsewhere,
            Mode::Direct => p.depth() > 0 && !caustic_elsewhere,
            _ => true,
        }
    }
}

/// Fraction of light `l`'s emissions that enter `bounds`, from pilot photons (a
/// deterministic function of the scene and seed).
fn aim_fraction(
    scene: &Scene,
    table: &crate::light::LightTable,
    l: usize,
    bounds: &[Aabb],
    seed: u32,
) -> f64 {
    use crate::rng::{Rng, Stream};
    let hits = (0..PILOT_PHOTONS)
        .filter(|&i| {
            let mut rng = Rng::new(seed, Stream::Pilot, l as u32, i);
            let e = table.emit(
                scene,
                l,
                [rng.next(), rng.next(), rng.next(), rng.next(), rng.next()],
            );
            crate::light::aims_at(bounds, e.origin, e.dir)
        })
        .count();
    hits as f64 / PILOT_PHOTONS as f64
}

/// Checks settings that the command line or API may have set out of range.
pub fn validate(s: &RenderSettings) -> Result<()> {
    let bad = |field: &'static str, message: String| Err(Error::Setting { field, message });
    if s.width == 0 || s.height == 0 || s.width > MAX_RESOLUTION || s.height > MAX_RESOLUTION {
        return bad(
            "width/height",
            format!("{}x{} is outside 1..={MAX_RESOLUTION}", s.width, s.height),
        );
    }
    if s.k == 0 || s.k > MAX_K {
        return bad("k", format!("{} is outside 1..={MAX_K}", s.k));
    }
    if !(s.radius.is_finite() && s.radius > 0.0) {
        return bad(
            "radius",
            format!("{} must be positive and finite", s.radius),
        );
    }
    if !(s.caustic_radius.is_finite() && s.caustic_radius > 0.0) {
        return bad(
            "caustic-radius",
            format!("{} must be positive and finite", s.caustic_radius),
        );
    }
    if s.spp == 0 || s.spp > 65_536 {
        return bad("spp", format!("{} is outside 1..=65536", s.spp));
    }
    if s.shadow_samples == 0 || s.shadow_samples > 1024 {
        return bad(
            "shadow-samples",
            format!("{} is outside 1..=1024", s.shadow_samples),
        );
    }
    if s.photons == 0 {
        return bad("photons", "must be at least 1".into());
    }
    if !s.exposure.is_finite() {
        return bad("exposure", "must be finite".into());
    }
    Ok(())
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
        Backend::Gpu => crate::gpu::render(scene, settings, 0, &progress),
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
            let list: Vec<(u32, RenderSettings)> = passes
                .map(|p| (p, pass_settings(scene, settings, p)))
                .collect();
            crate::gpu::render::render_passes(scene, &list, &quiet, |img| {
                acc.add(img);
                bar.inc(1);
                on_pass(&acc)
            })?
        }
    };
    bar.finish_and_clear();
    Ok((acc, report))
}
