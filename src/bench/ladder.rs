//! The speed-against-error ladder: every rung (photons, samples, K) on every backend, timed
//! and measured against a reference image; and the reference itself when none is given.

use crate::bench::backend_name;
use crate::error::Result;
use crate::render::film::Image;
use crate::render::report::Progress;
use crate::render::session::{render, Backend};
use crate::scene::Scene;
use crate::settings::{Mode, RenderSettings};
use std::path::Path;

/// The settings of the reference a ladder is measured against when none is given: the CPU,
/// progressive, 16 passes of 200,000 photon paths at 16 samples per pixel, the scene's size.
pub fn reference_settings(scene: &Scene) -> RenderSettings {
    RenderSettings {
        photons: 200_000,
        spp: 16,
        pass_range: Some((1000, 1016)),
        ..scene.settings.clone()
    }
}

/// What [`reference_settings`] render, in words ("progressive, 16 passes x 200,000 photons x
/// 16 spp at 256x256").
pub fn describe_reference(rs: &RenderSettings) -> String {
    let passes = rs.pass_range.map_or(1, |(a, b)| b - a);
    format!(
        "progressive, {passes} passes x {} photons x {} spp at {}x{}",
        thousands(rs.photons),
        rs.spp,
        rs.width,
        rs.height
    )
}

fn thousands(n: u32) -> String {
    let digits = n.to_string();
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// Renders the reference of [`reference_settings`] on the CPU and writes it to `path`.
pub fn render_reference(scene: &Scene, path: &Path) -> Result<()> {
    let (img, _) = render(
        scene,
        &reference_settings(scene),
        Backend::Cpu,
        Progress::default(),
    )?;
    img.write(path, 0.0)
}

/// One run of the speed-against-error ladder.
#[derive(Clone, Debug)]
pub struct LadderRow {
    /// "cpu" or "gpu".
    pub backend: &'static str,
    /// The render mode (the technique: `direct` reads the global map at every sample,
    /// `gather` gathers from the radiance cache).
    pub mode: Mode,
    /// Photon paths of the rung.
    pub photons: u32,
    /// Samples per pixel of the rung.
    pub spp: u32,
    /// K of the rung.
    pub k: u32,
    /// Wall seconds per phase.
    pub phases: Vec<(&'static str, f64)>,
    /// Wall seconds of the whole render.
    pub total_s: f64,
    /// RMSE against the reference.
    pub rmse: f64,
    /// Relative MSE against the reference.
    pub rel_mse: f64,
    /// Per-channel ratio of the image mean to the reference's.
    pub mean_ratio: [f64; 3],
}

impl LadderRow {
    /// The header of the ladder's table ([`LadderRow`]'s `Display` gives its rows).
    pub fn header() -> String {
        format!(
            "{:<8} {:<8} {:>8} {:>5} {:>5} {:>10} {:>10} {:>10} {:>24}",
            "backend", "mode", "photons", "spp", "k", "seconds", "rmse", "rel_mse", "mean ratio"
        )
    }
}

impl std::fmt::Display for LadderRow {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let m = self.mean_ratio;
        write!(
            f,
            "{:<8} {:<8} {:>8} {:>5} {:>5} {:>10.2} {:>10.5} {:>10.5} {:>8.4} {:>7.4} {:>7.4}",
            self.backend,
            self.mode.name(),
            self.photons,
            self.spp,
            self.k,
            self.total_s,
            self.rmse,
            self.rel_mse,
            m[0],
            m[1],
            m[2]
        )
    }
}

/// The title of the ladder's plot of `scene_path` rendered at `width` x `height` in `modes`.
pub fn plot_title(scene_path: &Path, width: u32, height: u32, modes: &[Mode]) -> String {
    let name = scene_path.file_name().map_or_else(
        || scene_path.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let modes: Vec<&str> = modes.iter().map(|m| m.name()).collect();
    format!(
        "speed against error: {name}, {width}x{height}, mode {}",
        modes.join(" and ")
    )
}

/// The ladder's rungs: (photon paths, samples per pixel, K), cheap to expensive.
pub const LADDER: [(u32, u32, u32); 5] = [
    (25_000, 1, 50),
    (50_000, 4, 50),
    (100_000, 4, 100),
    (200_000, 16, 100),
    (400_000, 64, 100),
];

/// Renders `scene` at each rung in each of `modes` on each backend and measures it against
/// `reference`.
pub fn ladder(
    scene: &Scene,
    base: &RenderSettings,
    backends: &[Backend],
    modes: &[Mode],
    reference: &Image,
    rungs: &[(u32, u32, u32)],
    mut on_row: impl FnMut(&LadderRow),
) -> Result<Vec<LadderRow>> {
    let mut rows = Vec::new();
    let runs = backends
        .iter()
        .flat_map(|&b| modes.iter().map(move |&m| (b, m)));
    for (b, mode) in runs {
        for &(photons, spp, k) in rungs {
            let s = RenderSettings {
                photons,
                spp,
                k,
                mode,
                width: reference.width,
                height: reference.height,
                ..base.clone()
            };
            let (img, r) = render(scene, &s, b, Progress::default())?;
            let d = crate::render::image_diff::diff(&img, reference, 16).map_err(|m| {
                crate::Error::Setting {
                    field: "reference",
                    message: m,
                }
            })?;
            let row = LadderRow {
                backend: backend_name(b),
                mode,
                photons,
                spp,
                k,
                phases: r.phases.iter().map(|p| (p.0, p.1.as_secs_f64())).collect(),
                total_s: r.total().as_secs_f64(),
                rmse: d.rmse,
                rel_mse: d.rel_mse,
                mean_ratio: d.mean_ratio,
            };
            on_row(&row);
            rows.push(row);
        }
    }
    Ok(rows)
}

/// The ladder as CSV: one header row, one row per run.
pub fn ladder_csv(rows: &[LadderRow]) -> String {
    let mut out = String::from("backend,mode,photons,spp,k,trace_s,build_s,gather_s,total_s,rmse,rel_mse,mean_ratio_r,mean_ratio_g,mean_ratio_b\n");
    for r in rows {
        let ph = |names: &[&str]| {
            r.phases
                .iter()
                .filter(|p| names.contains(&p.0))
                .map(|p| p.1)
                .sum::<f64>()
        };
        out.push_str(&format!(
            "{},{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.6},{:.6},{:.5},{:.5},{:.5}\n",
            r.backend,
            r.mode.name(),
            r.photons,
            r.spp,
            r.k,
            ph(&["trace photons"]),
            ph(&["build kd-trees", "build grids", "build cache"]),
            ph(&["gather"]),
            r.total_s,
            r.rmse,
            r.rel_mse,
            r.mean_ratio[0],
            r.mean_ratio[1],
            r.mean_ratio[2]
        ));
    }
    out
}
