//! Throughput benchmark: the same scene and settings on each available backend, timed per
//! phase, medians over several runs (`gpu-photon bench`).

use crate::error::Result;
use crate::report::{Progress, RenderReport};
use crate::scene::Scene;
use crate::session::{render, Backend};
use crate::settings::RenderSettings;

/// Median throughput of one backend.
#[derive(Clone, Debug)]
pub struct Throughput {
    pub backend: String,
    /// Photon paths traced per second (global + caustic paths over the trace phase).
    pub paths_per_s: f64,
    /// Seconds to build the photon maps' search structures (kd-trees or hash grids).
    pub build_s: f64,
    /// Gather seconds per megapixel at one sample per pixel.
    pub gather_s_per_mpix_sample: f64,
    /// Whole render, seconds.
    pub total_s: f64,
}

fn phase(r: &RenderReport, names: &[&str]) -> f64 {
    r.phases
        .iter()
        .filter(|p| names.contains(&p.0))
        .map(|p| p.1.as_secs_f64())
        .sum()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

/// Renders `runs` times on `backend` and returns the medians.
pub fn throughput(
    scene: &Scene,
    s: &RenderSettings,
    backend: Backend,
    runs: usize,
) -> Result<Throughput> {
    let plan = crate::plan::MapPlan::new(scene, s);
    let paths = plan.global.as_ref().map_or(0, |b| b.total()) as f64
        + plan.caustic.as_ref().map_or(0, |c| c.0.total()) as f64;
    let msamples = s.width as f64 * s.height as f64 * s.spp as f64 / 1e6;
    let mut rows = Vec::new();
    let mut name = String::new();
    for _ in 0..runs.max(1) {
        let (_, r) = render(scene, s, backend, Progress::default())?;
        name = r.backend.clone();
        rows.push((
            paths / phase(&r, &["trace photons"]).max(1e-9),
            phase(&r, &["build kd-trees", "build grids"]),
            phase(&r, &["gather"]) / msamples.max(1e-12),
            r.total().as_secs_f64(),
        ));
    }
    Ok(Throughput {
        backend: name,
        paths_per_s: median(rows.iter().map(|r| r.0).collect()),
        build_s: median(rows.iter().map(|r| r.1).collect()),
        gather_s_per_mpix_sample: median(rows.iter().map(|r| r.2).collect()),
        total_s: median(rows.iter().map(|r| r.3).collect()),
    })
}

/// One run of the speed-against-error ladder.
#[derive(Clone, Debug)]
pub struct LadderRow {
    pub backend: &'static str,
    pub photons: u32,
    pub spp: u32,
    pub k: u32,
    /// Wall seconds per phase.
    pub phases: Vec<(&'static str, f64)>,
    pub total_s: f64,
    pub rmse: f64,
    pub rel_mse: f64,
    pub mean_ratio: [f64; 3],
}

/// The ladder's rungs: (photon paths, samples per pixel, K), cheap to expensive.
pub const LADDER: [(u32, u32, u32); 5] = [
    (25_000, 1, 50),
    (50_000, 4, 50),
    (100_000, 4, 100),
    (200_000, 16, 100),
    (400_000, 64, 100),
];

/// Renders `scene` at each rung on each backend and measures it against `reference`.
pub fn ladder(
    scene: &Scene,
    base: &RenderSettings,
    backends: &[Backend],
    reference: &crate::film::Image,
    rungs: &[(u32, u32, u32)],
    mut on_row: impl FnMut(&LadderRow),
) -> Result<Vec<LadderRow>> {
    let mut rows = Vec::new();
    for &b in backends {
        for &(photons, spp, k) in rungs {
            let s = RenderSettings {
                photons,
                spp,
                k,
                width: reference.width,
                height: reference.height,
                ..base.clone()
            };
            let (img, r) = render(scene, &s, b, Progress::default())?;
            let d = crate::film::diff(&img, reference, 16).map_err(|m| crate::Error::Setting {
                field: "reference",
                message: m,
            })?;
            let row = LadderRow {
                backend: if b == Backend::Cpu { "cpu" } else { "gpu" },
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
    let mut out = String::from("backend,photons,spp,k,trace_s,build_s,gather_s,total_s,rmse,rel_mse,mean_ratio_r,mean_ratio_g,mean_ratio_b\n");
    for r in rows {
        let ph = |names: &[&str]| {
            r.phases
                .iter()
                .filter(|p| names.contains(&p.0))
                .map(|p| p.1)
                .sum::<f64>()
        };
        out.push_str(&format!(
            "{},{},{},{},{:.4},{:.4},{:.4},{:.4},{:.6},{:.6},{:.5},{:.5},{:.5}\n",
            r.backend,
            r.photons,
            r.spp,
            r.k,
            ph(&["trace photons"]),
            ph(&["build kd-trees", "build grids"]),
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

/// Where the plot's font is looked for (Debian's fonts-dejavu-core).
pub const PLOT_FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Plots RMSE against wall time, log-log, one curve per backend, as a PNG.
pub fn plot(
    rows: &[LadderRow],
    path: &std::path::Path,
    title: &str,
) -> std::result::Result<(), String> {
    use plotters::prelude::*;
    let font = std::fs::read(PLOT_FONT)
        .map_err(|e| format!("{PLOT_FONT}: {e} (install fonts-dejavu-core)"))?;
    plotters::style::register_font(
        "sans-serif",
        FontStyle::Normal,
        Box::leak(font.into_boxed_slice()),
    )
    .map_err(|_| format!("{PLOT_FONT}: not a usable font"))?;
    let (mut t0, mut t1, mut e0, mut e1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for r in rows {
        t0 = t0.min(r.total_s);
        t1 = t1.max(r.total_s);
        e0 = e0.min(r.rmse);
        e1 = e1.max(r.rmse);
    }
    if rows.is_empty() {
        return Err("no runs to plot".into());
    }
    let root = BitMapBackend::new(path, (800, 560)).into_drawing_area();
    let err = |e: &dyn std::fmt::Display| e.to_string();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 22))
        .margin(16)
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(
            (t0 * 0.7..t1 * 1.4).log_scale(),
            (e0 * 0.7..e1 * 1.4).log_scale(),
        )
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("wall time (s)")
        .y_desc("RMSE against the reference")
        .label_style(("sans-serif", 15))
        .draw()
        .map_err(|e| err(&e))?;
    for (name, colour) in [("cpu", BLUE), ("gpu", RED)] {
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.backend == name)
            .map(|r| (r.total_s, r.rmse))
            .collect();
        if pts.is_empty() {
            continue;
        }
        chart
            .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(name)
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        chart
            .draw_series(pts.iter().map(|&p| Circle::new(p, 4, colour.filled())))
            .map_err(|e| err(&e))?;
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .label_font(("sans-serif", 15))
        .draw()
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))?;
    Ok(())
}
