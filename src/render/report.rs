//! The contract between a render session and a backend ([`PassRenderer`]), what a render
//! reports back (per-phase timings, photon counts, GPU bound counters) and the progress bars
//! it shows while it runs. It sits below both backends and the session, so each of them
//! imports it and none imports the other.

use crate::error::Result;
use crate::render::film::Image;
use crate::settings::RenderSettings;
use std::path::Path;
use std::time::{Duration, Instant};

/// The one contract between the session and a backend: built once per render from the scene
/// and the render's settings, then asked for passes. `pass` is the RNG's pass index and
/// `settings` that pass's settings (the render's own for a classic render; for a progressive
/// pass, `progressive::pass_settings`, which only shrinks the radii and sets `k = 0`).
/// `crate::render::session` re-exports it.
pub trait PassRenderer {
    /// Renders pass `pass` and returns its image.
    fn pass(&mut self, pass: u32, settings: &RenderSettings, progress: &Progress) -> Result<Image>;
    /// Timings and counts of every pass so far (phases of the same name summed).
    fn report(&mut self) -> Result<RenderReport>;
}

/// Timings and counts of one render.
#[derive(Clone, Debug, Default)]
pub struct RenderReport {
    /// Wall time per phase, in the order the phases first ran.
    pub phases: Vec<(&'static str, Duration)>,
    /// Device time per GPU kernel (its entry point's name), in the order the kernels first
    /// ran: only where a `bench` render (`RenderSettings::timed_phases`) ran on a device with
    /// timestamp queries; each lies within its phase.
    pub kernels: Vec<(&'static str, Duration)>,
    /// Photons each map's paths stored (before the map's filter), by
    /// [`MapKind`](crate::integrators::plan::MapKind) slot; the last pass's.
    pub stored: [usize; 2],
    /// Photons the paths stored in media (the volume map's); the last pass's.
    pub volume_stored: usize,
    /// Which backend ran, in words.
    pub backend: String,
    /// GPU bound counters (photon overflow, loop budget, gather truncation), if on the GPU.
    pub gpu_stats: Vec<u32>,
    /// Photon batches the pass was split into (GPU: one storage binding per map).
    pub batches: u32,
    /// CPU fixed-radius searches whose radius held more photons than a search may read,
    /// narrowed to the nearest (`cpu::density`); summed over passes.
    pub narrowed: u64,
}

impl RenderReport {
    /// The count of photons map `kind`'s paths stored.
    pub fn stored_mut(&mut self, kind: crate::integrators::plan::MapKind) -> &mut usize {
        &mut self.stored[kind as usize]
    }

    /// Records a phase that started at `since`.
    pub fn phase(&mut self, name: &'static str, since: Instant) {
        self.phases.push((name, since.elapsed()));
    }

    /// Records a phase that took `d` (timed elsewhere, e.g. on the device).
    pub fn phase_took(&mut self, name: &'static str, d: Duration) {
        self.phases.push((name, d));
    }

    /// The sum of all phases.
    pub fn total(&self) -> Duration {
        self.phases.iter().map(|p| p.1).sum()
    }

    /// Records that GPU kernel `name` took `d` on the device (summed with earlier runs of it).
    pub fn kernel_took(&mut self, name: &'static str, d: Duration) {
        match self.kernels.iter_mut().find(|k| k.0 == name) {
            Some(k) => k.1 += d,
            None => self.kernels.push((name, d)),
        }
    }

    /// Adds a later pass's report: phases (and kernels) of the same name summed, bound counters summed,
    /// the photon counts of the later pass, the most batches, and its backend if this report
    /// names none yet.
    pub fn absorb(&mut self, other: &RenderReport) {
        for &(name, d) in &other.phases {
            match self.phases.iter_mut().find(|p| p.0 == name) {
                Some(p) => p.1 += d,
                None => self.phases.push((name, d)),
            }
        }
        for &(name, d) in &other.kernels {
            self.kernel_took(name, d);
        }
        self.stored = other.stored;
        self.volume_stored = other.volume_stored;
        self.batches = self.batches.max(other.batches);
        self.narrowed += other.narrowed;
        if self.backend.is_empty() {
            self.backend = other.backend.clone();
        }
        if self.gpu_stats.len() < other.gpu_stats.len() {
            self.gpu_stats.resize(other.gpu_stats.len(), 0);
        }
        for (s, o) in self.gpu_stats.iter_mut().zip(&other.gpu_stats) {
            *s += o;
        }
    }
}

impl RenderReport {
    /// The warning (shown even with `--quiet`) when a GPU render hit one of its bounds: its
    /// image is not what the settings ask for.
    pub fn incomplete_warning(&self, output: &Path) -> Option<String> {
        let [overflow, budget, truncated, ..] = self.gpu_stats[..] else {
            return None;
        };
        (overflow + budget + truncated > 0).then(|| format!(
            "warning: {}: the GPU image is incomplete ({overflow} photons dropped, {budget} invocations out of loop budget, {truncated} searches truncated); lower --k, --radius or --initial-radius, or use --backend cpu",
            output.display()
        ))
    }

    /// What `render` prints after a classic render to `output` with `s`: size, samples,
    /// mode and backend, photon counts, batches and GPU bounds when they matter, and the
    /// phases with their total.
    pub fn summary(&self, output: &Path, s: &RenderSettings) -> Vec<String> {
        let mut lines = vec![
            format!(
                "{}: {}x{}, {} spp, mode {}, backend {}",
                output.display(),
                s.width,
                s.height,
                s.spp,
                s.mode.name(),
                self.backend
            ),
            format!(
                "  photons stored: {}",
                crate::integrators::plan::MapKind::ALL
                    .map(|k| format!("{} {}", self.stored[k as usize], k.name()))
                    .join(", ")
                    + &match self.volume_stored {
                        0 => String::new(),
                        n => format!(", {n} volume"),
                    }
            ),
        ];
        if self.batches > 1 {
            lines.push(format!(
                "  photon maps split into {} batches (one storage binding each); counts are the last batch's",
                self.batches
            ));
        }
        lines.extend(self.bound_lines());
        lines.extend(self.phase_lines(16));
        lines.push(format!(
            "  {:<16} {:>9.3} s",
            "total",
            self.total().as_secs_f64()
        ));
        lines
    }

    /// The bounds a render hit, a line each where they matter: the GPU's counters, and the
    /// CPU's fixed-radius searches narrowed where photons were denser than a search may read.
    pub fn bound_lines(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if let [overflow, budget, truncated, ..] = self.gpu_stats[..] {
            lines.push(format!("  gpu bounds hit: {overflow} photons dropped (buffer full), {budget} invocations out of loop budget, {truncated} truncated searches"));
        }
        if self.narrowed > 0 {
            lines.push(format!(
                "  dense searches: {} read a smaller radius or only their nearest photons (their radius held more than a search may read); a smaller --initial-radius avoids it",
                self.narrowed
            ));
        }
        lines
    }

    /// One line per phase, its name padded to `width`.
    pub fn phase_lines(&self, width: usize) -> Vec<String> {
        self.phases
            .iter()
            .map(|(name, d)| format!("  {name:<width$} {:>9.3} s", d.as_secs_f64()))
            .collect()
    }
}

/// Shows progress bars on stderr when enabled.
#[derive(Clone, Copy, Debug, Default)]
pub struct Progress {
    /// Whether bars are drawn (off for `--quiet` and when stderr is not a terminal).
    pub enabled: bool,
}

impl Progress {
    /// A bar of `len` steps labelled `what` (hidden when disabled).
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
