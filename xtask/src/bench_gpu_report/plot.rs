//! The log-log plot of ms per step against bodies, one line per engine.

use super::*;

/// Colour per engine (Tableau colours).
pub(super) fn engine_color(engine: &str) -> RGBColor {
    match engine {
        "tumble-gpu" => RGBColor(214, 39, 40),
        "tumble-hybrid" => RGBColor(255, 127, 14),
        "tumble-cpu" => RGBColor(148, 103, 189),
        "rapier3d" => RGBColor(31, 119, 180),
        "nexus" => RGBColor(44, 160, 44),
        _ => RGBColor(127, 127, 127),
    }
}

/// Milliseconds per step against bodies, log-log, one line per engine.
pub(super) fn plot(path: &Path, rows: &[Row], nexus: &[Row]) -> Result<(), String> {
    register_plot_font();
    let mut engines: Vec<&str> = Vec::new();
    let points: Vec<(&str, f64, f64)> = rows
        .iter()
        .chain(nexus)
        .filter_map(|r| {
            let ms = r.median_ms.filter(|&m| m > 0.0)?;
            (r.bodies > 0).then_some((r.engine.as_str(), r.bodies as f64, ms))
        })
        .collect();
    for (e, ..) in &points {
        if !engines.contains(e) {
            engines.push(e);
        }
    }
    if points.is_empty() {
        println!("no timed rows: no plot");
        return Ok(());
    }
    let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
    for &(_, x, y) in &points {
        x0 = x0.min(x);
        x1 = x1.max(x);
        y0 = y0.min(y);
        y1 = y1.max(y);
    }
    let (x0, x1) = (x0 / 2.0, x1 * 2.0);
    let (y0, y1) = (y0 / 2.0, y1 * 2.0);
    let root = BitMapBackend::new(path, (1000, 700)).into_drawing_area();
    let err = |e: DrawingAreaErrorKind<_>| format!("plotting {}: {e}", path.display());
    root.fill(&WHITE).map_err(err)?;
    let mut chart = ChartBuilder::on(&root)
        .caption("wall time per step against bodies", (PLOT_FONT, 24))
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d((x0..x1).log_scale(), (y0..y1).log_scale())
        .map_err(err)?;
    chart
        .configure_mesh()
        .x_desc("bodies")
        .y_desc("ms per step (median)")
        .label_style((PLOT_FONT, 16))
        .draw()
        .map_err(err)?;
    for engine in engines {
        let color = engine_color(engine);
        let mut line: Vec<(f64, f64)> = points
            .iter()
            .filter(|p| p.0 == engine)
            .map(|p| (p.1, p.2))
            .collect();
        line.sort_by(|a, b| a.0.total_cmp(&b.0));
        chart
            .draw_series(LineSeries::new(line.clone(), color.stroke_width(2)))
            .map_err(err)?
            .label(engine)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        chart
            .draw_series(line.into_iter().map(|p| Circle::new(p, 4, color.filled())))
            .map_err(err)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .label_font((PLOT_FONT, 16))
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(err)?;
    root.present().map_err(err)?;
    Ok(())
}
