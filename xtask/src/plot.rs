//! Per-scene plots of error against cost: for every Tumble series (solver x backend x warm
//! start) a line through its iteration or substep counts, and rapier3d's points beside them.

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::fonts::{PLOT_FONT, register_plot_font};

/// Errors smaller than this are drawn at this value, in meters: a log axis cannot show zero,
/// and 10 micrometers is below anything a game or robot can see.
pub const ERROR_FLOOR_M: f64 = 1e-5;
/// Step times smaller than this are drawn at this value, in milliseconds (log axis).
pub const TIME_FLOOR_MS: f64 = 1e-3;
/// Series colours: the Tableau 10 palette, chosen to stay distinguishable on white and for
/// the common colour-vision deficiencies.
const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];
/// Picture size in pixels: two panels side by side.
const SIZE: (u32, u32) = (1400, 600);

/// One configuration's result on one scene, as plotted.
#[derive(Clone, Debug, PartialEq)]
pub struct PlotPoint {
    /// The series it belongs to (`soft_step cpu`, `rapier3d`, ...).
    pub series: String,
    /// True for rapier3d (drawn as crosses, not joined).
    pub is_rapier: bool,
    /// Iterations or substeps, written next to the point.
    pub effort: u32,
    /// Median milliseconds per step.
    pub ms_per_step: f64,
    /// Maximum penetration over the run, in meters.
    pub max_penetration: f64,
    /// Maximum horizontal drift over the run, in meters.
    pub max_drift: f64,
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
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    draw(
        BitMapBackend::new(&png, SIZE).into_drawing_area(),
        scene,
        points,
    )
    .and_then(|()| {
        draw(
            SVGBackend::new(&svg, SIZE).into_drawing_area(),
            scene,
            points,
        )
    })
    .map_err(|e| format!("plotting {scene}: {e}"))
}

fn draw<DB: DrawingBackend>(
    root: DrawingArea<DB, Shift>,
    scene: &str,
    points: &[PlotPoint],
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
    let panels = root.split_evenly((1, 2));
    for (area, panel) in panels.iter().zip([Panel::Penetration, Panel::Drift]) {
        draw_panel(area, panel, points).map_err(err)?;
    }
    root.present().map_err(err)
}

/// A tick label with about two significant digits: `0.05`, `0.4`, `3`, `120`.
fn short_number(v: f64) -> String {
    if v >= 10.0 {
        format!("{v:.0}")
    } else if v >= 1.0 {
        format!("{v:.1}")
    } else {
        let decimals = (-v.log10()).ceil().max(1.0) as usize + 1;
        format!("{v:.decimals$}")
    }
}

fn series_names(points: &[PlotPoint]) -> Vec<String> {
    let mut names: Vec<String> = points
        .iter()
        .filter(|p| !p.is_rapier)
        .map(|p| p.series.clone())
        .collect();
    names.sort();
    names.dedup();
    names
}

/// The range a log axis needs to show `values` with a little room on both sides.
fn log_range(values: impl Iterator<Item = f64>, floor: f64) -> std::ops::Range<f64> {
    let (lo, hi) = values.fold((f64::INFINITY, 0.0_f64), |(lo, hi), v| {
        (lo.min(v), hi.max(v))
    });
    if !lo.is_finite() {
        return floor..floor * 10.0;
    }
    // A factor of 1.5 on each side keeps points and their labels off the frame.
    let lo = (lo / 1.5).max(floor * 0.5);
    let hi = (hi * 1.5).max(lo * 10.0);
    lo..hi
}

fn draw_panel<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    panel: Panel,
    points: &[PlotPoint],
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
        .x_labels(6)
        .x_label_formatter(&|v| short_number(*v))
        .light_line_style(WHITE)
        .y_label_formatter(&|v| format!("{v:.0e}"))
        .label_style((PLOT_FONT, 14))
        .draw()?;

    for (index, name) in series_names(points).iter().enumerate() {
        let color = PALETTE[index % PALETTE.len()].to_rgba();
        let mut line: Vec<&PlotPoint> = points
            .iter()
            .filter(|p| !p.is_rapier && &p.series == name)
            .collect();
        line.sort_by_key(|p| p.effort);
        let xy = |p: &PlotPoint| (p.ms_per_step.max(TIME_FLOOR_MS), panel.value(p));
        chart
            .draw_series(LineSeries::new(
                line.iter().map(|p| xy(p)),
                color.stroke_width(2),
            ))?
            .label(name.as_str())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
            });
        chart.draw_series(line.iter().map(|p| {
            EmptyElement::at(xy(p))
                + Circle::new((0, 0), 4, color.filled())
                + Text::new(p.effort.to_string(), (6, -14), (PLOT_FONT, 13))
        }))?;
    }
    let rapier: Vec<&PlotPoint> = points.iter().filter(|p| p.is_rapier).collect();
    if !rapier.is_empty() {
        let xy = |p: &PlotPoint| (p.ms_per_step.max(TIME_FLOOR_MS), panel.value(p));
        chart
            .draw_series(rapier.iter().map(|p| {
                EmptyElement::at(xy(p))
                    + Cross::new((0, 0), 6, BLACK.stroke_width(2))
                    + Text::new(p.effort.to_string(), (7, 4), (PLOT_FONT, 13))
            }))?
            .label("rapier3d")
            .legend(|(x, y)| Cross::new((x + 12, y), 6, BLACK.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font((PLOT_FONT, 14))
        .draw()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn point(series: &str, rapier: bool, effort: u32, ms: f64, pen: f64, drift: f64) -> PlotPoint {
        PlotPoint {
            series: series.into(),
            is_rapier: rapier,
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
        let points = vec![
            point("baumgarte cpu", false, 4, 0.2, 0.02, 0.1),
            point("baumgarte cpu", false, 16, 0.6, 0.005, 0.01),
            point("soft_step cpu", false, 1, 0.1, 0.01, 0.0),
            point("soft_step cpu", false, 4, 0.3, 0.002, 0.0),
            point("rapier3d", true, 4, 0.25, 0.001, 0.0005),
        ];
        plot_scene(&dir, "stack", "stack", &points).unwrap();
        let png = std::fs::metadata(dir.join("stack.png")).unwrap();
        // An empty 1400x600 white PNG compresses to a few kB; lines, markers and text push a
        // drawn plot well past that.
        assert!(png.len() > 10_000, "{}", png.len());
        let svg = std::fs::read_to_string(dir.join("stack.svg")).unwrap();
        for name in [
            "baumgarte cpu",
            "soft_step cpu",
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
        let single = log_range(
            [0.0].into_iter().map(|v: f64| v.max(ERROR_FLOOR_M)),
            ERROR_FLOOR_M,
        );
        assert!(single.end >= single.start * 10.0);
        let empty = log_range(std::iter::empty(), ERROR_FLOOR_M);
        assert!(empty.start > 0.0 && empty.end > empty.start);
    }
}
