//! Per-scene plots of error against cost: for every Tumble series (solver x backend x warm
//! start) a line through its iteration or substep counts, and rapier3d's points beside them.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::fonts::{PLOT_FONT, register_plot_font};
use crate::grid::{BackendChoice, Solver};

/// Errors smaller than this are drawn at this value, in meters: a log axis cannot show zero,
/// and 10 micrometers is below anything a game or robot can see.
pub const ERROR_FLOOR_M: f64 = 1e-5;
/// Step times smaller than this are drawn at this value, in milliseconds (log axis).
pub const TIME_FLOOR_MS: f64 = 1e-3;
/// Colour per solver and warm start (Tableau colours, distinguishable on white and under the
/// common colour-vision deficiencies); the backend is told apart by line dash and marker.
fn solver_color(solver: Solver, warm: bool) -> RGBColor {
    match (solver, warm) {
        (Solver::Baumgarte, true) => RGBColor(31, 119, 180),
        (Solver::Baumgarte, false) => RGBColor(23, 190, 207),
        (Solver::SoftStep, true) => RGBColor(214, 39, 40),
        (Solver::SoftStep, false) => RGBColor(255, 127, 14),
        (Solver::SoftStepRelaxFriction, true) => RGBColor(44, 160, 44),
        (Solver::SoftStepRelaxFriction, false) => RGBColor(152, 223, 138),
    }
}
/// Plot size in pixels of the two panels side by side; the legend strip is added below.
const PANELS: (u32, u32) = (1400, 600);
/// Height of one legend row, and legend entries per row.
const LEGEND_ROW: u32 = 26;
const LEGEND_COLUMNS: usize = 4;

/// One configuration's result on one scene, as plotted.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotPoint {
    /// Tumble's solver, backend and warm start; `None` for rapier3d (drawn as crosses).
    pub tumble: Option<(Solver, BackendChoice, bool)>,
    /// Iterations or substeps, written next to the point.
    pub effort: u32,
    /// Median milliseconds per step.
    pub ms_per_step: f64,
    /// Maximum penetration over the run, in meters.
    pub max_penetration: f64,
    /// Maximum horizontal drift over the run, in meters.
    pub max_drift: f64,
}

/// A Tumble series: solver, backend, warm start.
type SeriesKey = (Solver, BackendChoice, bool);

fn series_label((solver, backend, warm): SeriesKey) -> String {
    format!(
        "{} {}{}",
        solver.name(),
        backend.name(),
        if warm { "" } else { " cold" }
    )
}

/// Which error a panel shows.
#[derive(Clone, Copy)]
enum Panel {
    Penetration,
    Drift,
}

impl Panel {
    fn value(self, p: &PlotPoint) -> f64 {
        match self {
            Panel::Penetration => p.max_penetration,
            Panel::Drift => p.max_drift,
        }
        .max(ERROR_FLOOR_M)
    }

    fn title(self) -> &'static str {
        match self {
            Panel::Penetration => "max penetration (m)",
            Panel::Drift => "max horizontal drift (m)",
        }
    }
}

/// Writes `<stem>.png` and `<stem>.svg` into `dir` for `scene`'s points.
pub fn plot_scene(dir: &Path, stem: &str, scene: &str, points: &[PlotPoint]) -> Result<(), String> {
    register_plot_font();
    let keys = series_keys(points);
    let entries = keys.len() + usize::from(points.iter().any(|p| p.tumble.is_none()));
    let rows = entries.div_ceil(LEGEND_COLUMNS) as u32;
    let size = (PANELS.0, PANELS.1 + rows * LEGEND_ROW + LEGEND_ROW);
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    draw(
        BitMapBackend::new(&png, size).into_drawing_area(),
        scene,
        points,
        &keys,
    )
    .and_then(|()| {
        draw(
            SVGBackend::new(&svg, size).into_drawing_area(),
            scene,
            points,
            &keys,
        )
    })
    .map_err(|e| format!("plotting {scene}: {e}"))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    scene: &str,
    points: &[PlotPoint],
    keys: &[SeriesKey],
) -> Result<(), String>
where
    DB::ErrorType: 'static,
{
    let err = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(err)?;
    let root = root
        .titled(
            &format!("{scene}: error against cost per step (lower left is better)"),
            (PLOT_FONT, 24),
        )
        .map_err(err)?;
    let (top, legend) = root.split_vertically(PANELS.1 - 40);
    let panels = top.split_evenly((1, 2));
    for (area, panel) in panels.iter().zip([Panel::Penetration, Panel::Drift]) {
        draw_panel(area, panel, points, keys).map_err(err)?;
    }
    draw_legend(&legend, points, keys).map_err(err)?;
    root.present().map_err(err)
}

/// The Tumble series present, in legend order: by solver, warm before cold, then backend.
fn series_keys(points: &[PlotPoint]) -> Vec<SeriesKey> {
    let mut keys: Vec<SeriesKey> = points.iter().filter_map(|p| p.tumble).collect();
    keys.sort_by_key(|&(solver, backend, warm)| (solver, !warm, backend));
    keys.dedup();
    keys
}

/// Draws a backend's marker (CPU circle, GPU triangle, hybrid square) centred on `at`.
fn marker<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    at: (i32, i32),
    backend: BackendChoice,
    color: RGBAColor,
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let style = color.filled();
    match backend {
        BackendChoice::Cpu => area.draw(&Circle::new(at, 4, style)),
        BackendChoice::Gpu => area.draw(&TriangleMarker::new(at, 6, style)),
        BackendChoice::Hybrid => area.draw(&Rectangle::new(
            [(at.0 - 4, at.1 - 4), (at.0 + 4, at.1 + 4)],
            style,
        )),
    }
}

/// Dash length and gap in pixels per backend: CPU solid, GPU long dashes, hybrid short ones.
fn dash(backend: BackendChoice) -> Option<(u32, u32)> {
    match backend {
        BackendChoice::Cpu => None,
        BackendChoice::Gpu => Some((10, 5)),
        BackendChoice::Hybrid => Some((3, 4)),
    }
}

/// The legend: a strip under both panels, one entry per series.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    points: &[PlotPoint],
    keys: &[SeriesKey],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let (width, _) = area.dim_in_pixel();
    let column = (width as i32 - 80) / LEGEND_COLUMNS as i32;
    let origin = |i: usize| {
        (
            40 + (i % LEGEND_COLUMNS) as i32 * column,
            10 + (i / LEGEND_COLUMNS) as i32 * LEGEND_ROW as i32,
        )
    };
    for (i, &key) in keys.iter().enumerate() {
        let (x, y) = origin(i);
        let color = solver_color(key.0, key.2).to_rgba();
        let ends = [(x, y), (x + 36, y)];
        match dash(key.1) {
            None => area.draw(&PathElement::new(ends.to_vec(), color.stroke_width(2)))?,
            Some((on, off)) => {
                let mut s = x;
                while s < x + 36 {
                    let e = (s + on as i32).min(x + 36);
                    area.draw(&PathElement::new(
                        vec![(s, y), (e, y)],
                        color.stroke_width(2),
                    ))?;
                    s = e + off as i32;
                }
            }
        }
        marker(area, (x + 18, y), key.1, color)?;
        area.draw(&Text::new(
            series_label(key),
            (x + 46, y - 8),
            (PLOT_FONT, 15),
        ))?;
    }
    if points.iter().any(|p| p.tumble.is_none()) {
        let (x, y) = origin(keys.len());
        area.draw(&Cross::new((x + 18, y), 6, BLACK.stroke_width(2)))?;
        area.draw(&Text::new("rapier3d", (x + 46, y - 8), (PLOT_FONT, 15)))?;
    }
    Ok(())
}

/// A tick label. Log-axis ticks are a single digit times a power of ten, so one significant
/// digit is exact: `0.005`, `0.2`, `3`, `120`; below a millimetre (or a microsecond)
/// scientific notation stays short: `5e-5`.
fn tick_label(v: f64) -> String {
    if v >= 1e-3 {
        // Rounding guards against 0.1 being stored as 0.0999...
        let decimals = (-(v * (1.0 + 1e-9)).log10().floor()).max(0.0) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.0e}")
    }
}

/// The range a log axis needs to show `values`: widened by a fifth on both sides so points
/// stay off the frame, then out to whole decades, so that every axis carries at least two
/// labelled powers of ten (plotters labels a log axis at its decades).
fn log_range(values: impl Iterator<Item = f64>, floor: f64) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !lo.is_finite() {
        return floor..floor * 10.0;
    }
    // Just under the decade, so that plotters (which labels from the first power of ten at or
    // above the start) does not lose the bottom decade to round-off.
    let lo = 10f64.powf((lo.max(floor) / 1.2).log10().floor()) * (1.0 - 1e-9);
    let hi = 10f64.powf((hi.max(floor) * 1.2).log10().ceil());
    lo..hi.max(lo * 10.0)
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: Panel,
    points: &[PlotPoint],
    keys: &[SeriesKey],
) -> Result<(), DrawingAreaErrorKind<DB::ErrorType>> {
    let x_range = log_range(
        points.iter().map(|p| p.ms_per_step.max(TIME_FLOOR_MS)),
        TIME_FLOOR_MS,
    );
    let y_range = log_range(points.iter().map(|p| panel.value(p)), ERROR_FLOOR_M);
    let mut chart = ChartBuilder::on(area)
        .margin(16)
        .caption(panel.title(), (PLOT_FONT, 20))
        .x_label_area_size(48)
        .y_label_area_size(72)
        .build_cartesian_2d(x_range.log_scale(), y_range.log_scale())?;
    chart
        .configure_mesh()
        .x_desc("median ms per step")
        .y_desc(panel.title())
        .x_labels(12)
        .y_labels(12)
        .x_label_formatter(&|v| tick_label(*v))
        .light_line_style(WHITE)
        .y_label_formatter(&|v| tick_label(*v))
        .label_style((PLOT_FONT, 14))
        .draw()?;

    let xy = |p: &PlotPoint| (p.ms_per_step.max(TIME_FLOOR_MS), panel.value(p));
    for &key in keys {
        let color = solver_color(key.0, key.2).to_rgba();
        let mut line: Vec<&PlotPoint> = points.iter().filter(|p| p.tumble == Some(key)).collect();
        line.sort_by_key(|p| p.effort);
        let coords: Vec<(f64, f64)> = line.iter().map(|p| xy(p)).collect();
        match dash(key.1) {
            None => {
                chart.draw_series(LineSeries::new(coords, color.stroke_width(2)))?;
            }
            Some((on, off)) => {
                chart.draw_series(DashedLineSeries::new(
                    coords,
                    on,
                    off,
                    color.stroke_width(2),
                ))?;
            }
        }
        match key.1 {
            BackendChoice::Cpu => {
                chart.draw_series(line.iter().map(|p| Circle::new(xy(p), 4, color.filled())))?;
            }
            BackendChoice::Gpu => {
                chart.draw_series(
                    line.iter()
                        .map(|p| TriangleMarker::new(xy(p), 6, color.filled())),
                )?;
            }
            BackendChoice::Hybrid => {
                chart.draw_series(line.iter().map(|p| {
                    EmptyElement::at(xy(p)) + Rectangle::new([(-4, -4), (4, 4)], color.filled())
                }))?;
            }
        }
        chart.draw_series(line.iter().map(|p| {
            EmptyElement::at(xy(p)) + Text::new(p.effort.to_string(), (6, -14), (PLOT_FONT, 13))
        }))?;
    }
    let rapier: Vec<&PlotPoint> = points.iter().filter(|p| p.tumble.is_none()).collect();
    chart.draw_series(rapier.iter().map(|p| {
        EmptyElement::at(xy(p))
            + Cross::new((0, 0), 6, BLACK.stroke_width(2))
            + Text::new(p.effort.to_string(), (7, 4), (PLOT_FONT, 13))
    }))?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(tumble: Option<SeriesKey>, effort: u32, ms: f64, pen: f64, drift: f64) -> PlotPoint {
        PlotPoint {
            tumble,
            effort,
            ms_per_step: ms,
            max_penetration: pen,
            max_drift: drift,
        }
    }

    #[test]
    fn writes_a_png_and_an_svg_with_every_series_named() {
        let dir = std::env::temp_dir().join(format!("tumble-plot-test-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let b = Some((Solver::Baumgarte, BackendChoice::Cpu, true));
        let s = Some((Solver::SoftStep, BackendChoice::Gpu, false));
        let h = Some((Solver::SoftStep, BackendChoice::Hybrid, true));
        let points = vec![
            point(b, 4, 0.2, 0.02, 0.1),
            point(b, 16, 0.6, 0.005, 0.01),
            point(s, 1, 0.1, 0.01, 0.0),
            point(s, 4, 0.3, 0.002, 0.0),
            point(h, 4, 0.35, 0.003, 0.001),
            point(None, 4, 0.25, 0.001, 0.0005),
        ];
        plot_scene(&dir, "stack", "stack", &points).unwrap();
        let png = std::fs::metadata(dir.join("stack.png")).unwrap();
        // An empty 1400x600 white PNG compresses to a few kB; lines, markers and text push a
        // drawn plot well past that.
        assert!(png.len() > 10_000, "{}", png.len());
        let svg = std::fs::read_to_string(dir.join("stack.svg")).unwrap();
        for name in [
            "baumgarte cpu",
            "soft_step gpu cold",
            "soft_step hybrid",
            "rapier3d",
            "median ms per step",
        ] {
            assert!(svg.contains(name), "{name} missing from the SVG");
        }
        std::fs::remove_dir_all(&dir).ok();
    }

    #[test]
    fn log_range_holds_every_value_and_never_collapses() {
        let r = log_range([0.5, 2.0].into_iter(), ERROR_FLOOR_M);
        assert!(r.start < 0.5 && r.end > 2.0);
        // Whole decades at both ends: 0.1 to 10.
        assert!(
            (r.start - 0.1).abs() < 1e-9 && (r.end - 10.0).abs() < 1e-9,
            "{r:?}"
        );
        let single = log_range(
            [0.0].into_iter().map(|v: f64| v.max(ERROR_FLOOR_M)),
            ERROR_FLOOR_M,
        );
        assert!(single.end >= single.start * 10.0);
        let empty = log_range(std::iter::empty(), ERROR_FLOOR_M);
        assert!(empty.start > 0.0 && empty.end > empty.start);
    }

    #[test]
    fn tick_labels_are_short_and_exact() {
        assert_eq!(tick_label(0.1), "0.1");
        assert_eq!(tick_label(0.005), "0.005");
        assert_eq!(tick_label(3.0), "3");
        assert_eq!(tick_label(200.0), "200");
        assert_eq!(tick_label(5e-5), "5e-5");
    }
}
