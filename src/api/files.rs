//! Progressive renders split across machines: slice files (a progressive render's running
//! mean, tagged with its pass range and a fingerprint of scene and settings) and their merge;
//! and the adapters the GPU backend can use.

use crate::api::Renderer;
use crate::error::Result;
use crate::render::report::RenderReport;
use crate::settings::RenderSettings;
use std::path::{Path, PathBuf};
use std::time::Duration;

pub use crate::integrators::gpu::context::AdapterSummary as Adapter;
pub use crate::integrators::gpu::{list_adapters as adapters, quiet_headless_vulkan};
pub use crate::render::film::check_output_path;
pub use crate::render::merge::{merge, parse_range as parse_pass_range, MergeSummary};
pub use crate::render::slice::{
    parse_spec as parse_slice, pass_range as slice_pass_range, SliceSpec,
};
pub use crate::settings::MAX_PASSES;

/// Where a progressive render's running mean goes: an EXR (or PNG) whose header records the
/// passes it holds and a fingerprint of the scene file and settings, so that
/// [`merge`] can combine slices rendered anywhere.
pub struct SliceFile {
    output: PathBuf,
    signature: String,
    total: Option<u32>,
    exposure: f32,
}

impl SliceFile {
    /// The slice file `output` of a render of the scene file `scene_path` with `settings`;
    /// `total_passes`: the pass count of the whole render it is part of (`--passes`), when
    /// there is one.
    pub fn new(
        scene_path: &Path,
        output: &Path,
        settings: &RenderSettings,
        total_passes: Option<u32>,
    ) -> Result<SliceFile> {
        Ok(SliceFile {
            output: output.to_path_buf(),
            signature: crate::render::merge::signature(scene_path, settings)?,
            total: total_passes,
            exposure: settings.exposure,
        })
    }

    /// Writes `renderer`'s running mean with the tags of the passes it holds (atomically).
    pub fn write(&self, renderer: &Renderer) -> Result<()> {
        let acc = renderer.accumulator();
        let tags = crate::render::merge::slice_tags(acc, &self.signature, self.total);
        acc.mean().write_tagged(&self.output, self.exposure, &tags)
    }
}

/// What `gpu-photon render` prints after a progressive render to `output`: the passes (and
/// whether they were `interrupted`), size, samples, mode and backend, the estimated noise,
/// then the phases and the `wall` time.
pub fn progressive_summary(
    renderer: &Renderer,
    report: &RenderReport,
    output: &Path,
    interrupted: bool,
    wall: Duration,
) -> Vec<String> {
    let s = renderer.settings();
    let done = renderer.done();
    let why = if interrupted { " (interrupted)" } else { "" };
    let mut lines = vec![format!(
        "{}: passes {}..{}{why}, {}x{}, {} spp per pass, mode {}, backend {}",
        output.display(),
        done.start,
        done.end,
        s.width,
        s.height,
        s.spp,
        s.mode.name(),
        report.backend
    )];
    if let Some(n) = renderer.noise() {
        lines.push(format!(
            "  estimated noise {:.2}% (relative RMS)",
            100.0 * n
        ));
    }
    lines.extend(report.bound_lines());
    lines.extend(report.phase_lines(18));
    lines.push(format!("  {:<18} {:>9.3} s", "wall", wall.as_secs_f64()));
    lines
}
