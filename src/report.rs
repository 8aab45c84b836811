//! What a render reports back (per-phase timings, photon counts, GPU bound counters) and
//! the progress bars it shows while it runs.

use std::time::{Duration, Instant};

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
