//! The plots of the studies, written as SVG and as PNG (the same drawing on
//! two plotters backends): error curves (the error-versus-time plot of
//! `equal-time`, RMSE against the time budget, both axes logarithmic, one
//! line per integrator through the medians over the seeds, with bars from
//! the smallest to the largest seed's RMSE; `kollig-keller`'s error against
//! samples) and bar charts (`kollig-keller`'s samples relative to MC).

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

/// One integrator's error at one budget.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorPoint {
    /// The budget: seconds, or samples per pixel.
    pub x: f64,
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

/// The axis descriptions of a plot.
#[derive(Clone, Copy)]
struct Axes<'a> {
    x: &'a str,
    y: &'a str,
}

/// Writes the plot of `curves` titled `title`, its axes described by
/// `x_description` and `y_description`, to `svg` and to `png`.
pub fn write_error_plot(
    svg: &Path,
    png: &Path,
    title: &str,
    x_description: &str,
    y_description: &str,
    curves: &[ErrorCurve],
) -> Result<(), CliError> {
    let axes = Axes {
        x: x_description,
        y: y_description,
    };
    write_both(
        svg,
        png,
        |root| draw_error_plot(root, title, axes, curves),
        |root| draw_error_plot(root, title, axes, curves),
    )
}

/// Writes a bar chart of `bars` (label, value) titled `title`, the values
/// described by `y_description`, to `svg` and to `png`.
pub fn write_bar_plot(
    svg: &Path,
    png: &Path,
    title: &str,
    y_description: &str,
    bars: &[(String, f64)],
) -> Result<(), CliError> {
    write_both(
        svg,
        png,
        |root| draw_bar_plot(root, title, y_description, bars),
        |root| draw_bar_plot(root, title, y_description, bars),
    )
}

/// Draws with `draw_svg` into `svg` and with `draw_png` into `png` (the
/// same drawing: a closure per backend type).
fn write_both(
    svg: &Path,
    png: &Path,
    draw_svg: impl FnOnce(DrawingArea<SVGBackend<'_>, Shift>) -> Result<(), String>,
    draw_png: impl FnOnce(DrawingArea<BitMapBackend<'_>, Shift>) -> Result<(), String>,
) -> Result<(), CliError> {
    register_plot_font()?;
    let failure = |path: &Path, error: String| {
        CliError::Failure(format!("cannot write the plot {}: {error}", path.display()))
    };
    draw_svg(SVGBackend::new(svg, PLOT_SIZE).into_drawing_area())
        .map_err(|error| failure(svg, error))?;
    draw_png(BitMapBackend::new(png, PLOT_SIZE).into_drawing_area())
        .map_err(|error| failure(png, error))
}

/// Draws the bar chart on `root` and presents it: one horizontal bar per
/// label (top to bottom in order), a line at 1.
fn draw_bar_plot<Backend: DrawingBackend>(
    root: DrawingArea<Backend, Shift>,
    title: &str,
    x_description: &str,
    bars: &[(String, f64)],
) -> Result<(), String> {
    let error = |error: DrawingAreaErrorKind<Backend::ErrorType>| error.to_string();
    root.fill(&WHITE).map_err(error)?;
    let high = bars
        .iter()
        .map(|(_, value)| *value)
        .filter(|value| value.is_finite())
        .fold(0.0f64, f64::max)
        .max(1.0)
        * 1.1;
    let count = bars.len().max(1);
    let labels: Vec<String> = bars.iter().map(|(label, _)| label.clone()).collect();
    // Bar i (from the top) spans rows count − i − 1 … count − i.
    let row_of = |index: usize| (count - index - 1) as f64;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, (PLOT_FONT_FAMILY, 18))
        .margin(16)
        .x_label_area_size(44)
        .y_label_area_size(190)
        .build_cartesian_2d(0.0..high, 0.0..count as f64)
        .map_err(error)?;
    chart
        .configure_mesh()
        .disable_y_mesh()
        .x_desc(x_description)
        .y_labels(count * 2 + 1)
        .y_label_formatter(&|value| {
            let row = value.floor();
            let index = count.checked_sub(row as usize + 1);
            match index.and_then(|index| labels.get(index)) {
                Some(label) if (value - row - 0.5).abs() < 0.01 && row >= 0.0 => label.clone(),
                _ => String::new(),
            }
        })
        .x_label_formatter(&|value| axis_label(*value))
        .label_style((PLOT_FONT_FAMILY, 14))
        .axis_desc_style((PLOT_FONT_FAMILY, 15))
        .draw()
        .map_err(error)?;
    chart
        .draw_series(bars.iter().enumerate().map(|(index, (_, value))| {
            let colour = COLOURS[index % COLOURS.len()];
            let row = row_of(index);
            Rectangle::new([(0.0, row + 0.15), (*value, row + 0.85)], colour.filled())
        }))
        .map_err(error)?;
    chart
        .draw_series(LineSeries::new(
            [(1.0, 0.0), (1.0, count as f64)],
            BLACK.stroke_width(1),
        ))
        .map_err(error)?;
    root.present().map_err(error)
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
    axes: Axes<'_>,
    curves: &[ErrorCurve],
) -> Result<(), String> {
    let error = |error: DrawingAreaErrorKind<Backend::ErrorType>| error.to_string();
    root.fill(&WHITE).map_err(error)?;
    let all_points = || curves.iter().flat_map(|curve| curve.points.iter());
    let (x_low, x_high) = logarithmic_range(all_points().map(|point| point.x), 1.25);
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
        .x_desc(axes.x)
        .y_desc(axes.y)
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
                x: point.x * offset,
                ..*point
            })
            .collect();
        chart
            .draw_series(LineSeries::new(
                points.iter().map(|point| (point.x, point.median)),
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
                    .map(|point| Circle::new((point.x, point.median), 4, colour.filled())),
            )
            .map_err(error)?;
        let bars = points
            .iter()
            .filter(|point| point.min > 0.0 && point.max.is_finite())
            .flat_map(|point| {
                let (x, cap) = (point.x, 1.012);
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
