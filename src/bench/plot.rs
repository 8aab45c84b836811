//! The ladder's plot: RMSE against wall time, log-log, one curve per backend and mode
//! (plotters).

use crate::bench::LadderRow;

/// Where the plot's font is looked for (Debian's fonts-dejavu-core).
pub const PLOT_FONT: &str = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";

/// Plots RMSE against wall time, log-log, one curve per backend and mode , as a PNG.
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
    let mut curves: Vec<(&str, crate::settings::Mode)> = Vec::new();
    for r in rows {
        if !curves.contains(&(r.backend, r.mode)) {
            curves.push((r.backend, r.mode));
        }
    }
    const COLOURS: [RGBColor; 6] = [BLUE, RED, GREEN, MAGENTA, CYAN, BLACK];
    for (i, &(name, mode)) in curves.iter().enumerate() {
        let colour = COLOURS[i % COLOURS.len()];
        let pts: Vec<(f64, f64)> = rows
            .iter()
            .filter(|r| r.backend == name && r.mode == mode)
            .map(|r| (r.total_s, r.rmse))
            .collect();
        chart
            .draw_series(LineSeries::new(pts.clone(), colour.stroke_width(2)))
            .map_err(|e| err(&e))?
            .label(format!("{name}, {}", mode.name()))
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
