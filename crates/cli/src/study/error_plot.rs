//! The error-versus-time plot of a study: RMSE against the time budget, both
//! axes logarithmic, one line per integrator through the medians over the
//! seeds, with bars from the smallest to the largest seed's RMSE. Written
//! as SVG and as PNG (the same drawing on two plotters backends).

use super::formatting::format_significant;
use crate::error::CliError;
use crate::plot_font::{PLOT_FONT_FAMILY, register_plot_font};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::Path;

/// The size of the plot in pixels.
const PLOT_SIZE: (u32, u32) = (800, 560);

/// Line colours, one per integrator in order (repeated past the end).
const COLOURS: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// One integrator's error at one time budget.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorPoint {
    /// The time budget in seconds.
    pub seconds: f64,
    /// The median over the seeds.
    pub median: f64,
    /// The smallest seed's error.
    pub min: f64,
    /// The largest seed's error.
    pub max: f64,
}

/// One line of the plot.
#[derive(Debug, Clone, PartialEq)]
pub struct ErrorCurve {
    /// The legend's name.
    pub label: String,
    /// The points, by budget.
    pub points: Vec<ErrorPoint>,
}

/// Writes the plot of `curves` titled `title` to `svg` and to `png`.
pub fn write_error_plot(
    svg: &Path,
    png: &Path,
    title: &str,
    curves: &[ErrorCurve],
) -> Result<(), CliError> {
    register_plot_font()?;
    let failure = |path: &Path, error: String| {
        CliError::Failure(format!("cannot write the plot {}: {error}", path.display()))
    };
    draw_error_plot(
        SVGBackend::new(svg, PLOT_SIZE).into_drawing_area(),
        title,
        curves,
    )
    .map_err(|error| failure(svg, error))?;
    draw_error_plot(
        BitMapBackend::new(png, PLOT_SIZE).into_drawing_area(),
        title,
        curves,
    )
    .map_err(|error| failure(png, error))
}

/// The range of a logarithmic axis holding `values` (the positive, finite
/// ones), widened by `margin` on either side.
fn logarithmic_range(values: impl Iterator<Item = f64>, margin: f64) -> (f64, f64) {
    let (low, high) = values
        .filter(|value| value.is_finite() && *value > 0.0)
        .fold((f64::INFINITY, 0.0f64), |(low, high), value| {
            (low.min(value), high.max(value))
        });
    if high > 0.0 {
        (low / margin, high * margin)
    } else {
        (1e-3, 1.0)
    }
}

/// An axis label: 3 significant digits without trailing zeros (`0.1`).
fn axis_label(value: f64) -> String {
    let text = format_significant(value, 3);
    if text.contains('.') && !text.contains('e') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text
    }
}

/// Draws the plot on `root` and presents it (writes the file).
fn draw_error_plot<Backend: DrawingBackend>(
    root: DrawingArea<Backend, Shift>,
    title: &str,
    curves: &[ErrorCurve],
) -> Result<(), String> {
    let error = |error: DrawingAreaErrorKind<Backend::ErrorType>| error.to_string();
    root.fill(&WHITE).map_err(error)?;
    let all_points = || curves.iter().flat_map(|curve| curve.points.iter());
    let (x_low, x_high) = logarithmic_range(all_points().map(|point| point.seconds), 1.25);
    let (y_low, y_high) = logarithmic_range(
        all_points().flat_map(|point| [point.min, point.median, point.max]),
        1.5,
    );
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (PLOT_FONT_FAMILY, 18))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(70)
        .build_cartesian_2d((x_low..x_high).log_scale(), (y_low..y_high).log_scale())
        .map_err(error)?;
    chart
        .configure_mesh()
        .x_desc("seconds per render")
        .y_desc("RMSE (median over seeds; bars: min to max)")
        .x_label_formatter(&|value| axis_label(*value))
        .y_label_formatter(&|value| axis_label(*value))
        .label_style((PLOT_FONT_FAMILY, 14))
        .axis_desc_style((PLOT_FONT_FAMILY, 15))
        .draw()
        .map_err(error)?;
    for (index, curve) in curves.iter().enumerate() {
        let colour = COLOURS[index % COLOURS.len()];
        // Spread the curves by a few percent in time so that their bars do
        // not hide each other.
        let offset = 1.0 + 0.025 * (index as f64 - (curves.len() as f64 - 1.0) / 2.0);
        let points: Vec<ErrorPoint> = curve
            .points
            .iter()
            .filter(|point| point.median.is_finite() && point.median > 0.0)
            .map(|point| ErrorPoint {
                seconds: point.seconds * offset,
                ..*point
            })
            .collect();
        chart
            .draw_series(LineSeries::new(
                points.iter().map(|point| (point.seconds, point.median)),
                colour.stroke_width(2),
            ))
            .map_err(error)?
            .label(curve.label.clone())
            .legend(move |(x, y)| {
                PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2))
            });
        chart
            .draw_series(
                points
                    .iter()
                    .map(|point| Circle::new((point.seconds, point.median), 4, colour.filled())),
            )
            .map_err(error)?;
        let bars = points
            .iter()
            .filter(|point| point.min > 0.0 && point.max.is_finite())
            .flat_map(|point| {
                let (x, cap) = (point.seconds, 1.012);
                [
                    vec![(x, point.min), (x, point.max)],
                    vec![(x / cap, point.min), (x * cap, point.min)],
                    vec![(x / cap, point.max), (x * cap, point.max)],
                ]
            })
            .map(|line| PathElement::new(line, colour.stroke_width(1)));
        chart.draw_series(bars).map_err(error)?;
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .label_font((PLOT_FONT_FAMILY, 14))
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(error)?;
    root.present().map_err(error)
}
