//! SVG plots of point sets: the requested points' 2-D projection beside a
//! local exploration like the LQMC paper's Fig. 2 — a rank-1 lattice,
//! Cranley–Patterson-shifted so that a seed point is a member and scaled into
//! the seed's tile, next to a Markov chain of uniform random steps in
//! `[−1/√N, 1/√N]` (tile units) starting from the same seed.

use crate::error::CliError;
use plotters::prelude::*;
use qmc::PointSet;
use qmc::cbc::{ProductWeights, cbc};
use qmc::closest_point::ClosestPointSearch;
use qmc::random::SeekablePcg;
use std::path::Path;

/// Lattice points used for the local exploration panel.
const EXPLORATION_POINTS: u64 = 127;
/// Tiles per dimension of the exploration panel.
const TILES_PER_DIMENSION: f64 = 4.0;

/// Writes the two-panel plot of `points` (row-major, `dims` coordinates each,
/// in the unit cube) to `path`.
pub fn write_points_plot(
    path: &Path,
    points: &[f64],
    dims: usize,
    seed: u64,
) -> Result<(), CliError> {
    let failure = |error: &dyn std::fmt::Display| {
        CliError::Failure(format!("cannot write the plot {}: {error}", path.display()))
    };
    crate::plot_font::register_plot_font()?;
    let count = points.len() / dims;
    let projection: Vec<(f64, f64)> = points
        .chunks(dims)
        .enumerate()
        .map(|(i, p)| {
            if dims >= 2 {
                (p[0], p[1])
            } else {
                (p[0], (i as f64 + 0.5) / count as f64)
            }
        })
        .collect();
    // Explore around the point nearest the centre, which shows best.
    let seed_point = projection
        .iter()
        .copied()
        .min_by(|a, b| {
            let distance = |p: &(f64, f64)| (p.0 - 0.5).powi(2) + (p.1 - 0.5).powi(2);
            distance(a).total_cmp(&distance(b))
        })
        .unwrap_or((0.5, 0.5));
    let (lattice_points, walk) = local_exploration(seed_point, seed)?;

    let root = SVGBackend::new(path, (1000, 520)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| failure(&e))?;
    let (left, right) = root.split_horizontally(500);

    let mut chart = ChartBuilder::on(&left)
        .caption(
            if dims >= 2 {
                format!("{count} points, dimensions 0 and 1")
            } else {
                format!("{count} points, dimension 0 against index")
            },
            (crate::plot_font::PLOT_FONT_FAMILY, 18),
        )
        .margin(12)
        .x_label_area_size(28)
        .y_label_area_size(36)
        .build_cartesian_2d(0.0..1.0, 0.0..1.0)
        .map_err(|e| failure(&e))?;
    chart.configure_mesh().draw().map_err(|e| failure(&e))?;
    chart
        .draw_series(
            projection
                .iter()
                .map(|&(x, y)| Circle::new((x, y), 2, BLUE.filled())),
        )
        .map_err(|e| failure(&e))?;

    // The right panel shows the seed's tile, outlined on the left.
    let tile = |v: f64| (v * TILES_PER_DIMENSION).floor() / TILES_PER_DIMENSION;
    let (x0, y0) = (tile(seed_point.0), tile(seed_point.1));
    let width = 1.0 / TILES_PER_DIMENSION;
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(x0, y0), (x0 + width, y0 + width)],
            BLACK.stroke_width(1),
        )))
        .map_err(|e| failure(&e))?;
    chart
        .draw_series(std::iter::once(Cross::new(
            seed_point,
            6,
            BLACK.stroke_width(2),
        )))
        .map_err(|e| failure(&e))?;
    let mut chart = ChartBuilder::on(&right)
        .caption(
            format!("local exploration: lattice N = {EXPLORATION_POINTS} vs random walk"),
            (crate::plot_font::PLOT_FONT_FAMILY, 18),
        )
        .margin(12)
        .x_label_area_size(28)
        .y_label_area_size(44)
        .build_cartesian_2d(x0..x0 + width, y0..y0 + width)
        .map_err(|e| failure(&e))?;
    chart.configure_mesh().draw().map_err(|e| failure(&e))?;
    chart
        .draw_series(
            walk.windows(2)
                .filter(|pair| {
                    // Do not draw steps that wrap around the tile.
                    (pair[0].0 - pair[1].0).abs() < width / 2.0
                        && (pair[0].1 - pair[1].1).abs() < width / 2.0
                })
                .map(|pair| PathElement::new(vec![pair[0], pair[1]], BLUE.mix(0.4))),
        )
        .map_err(|e| failure(&e))?
        .label("random walk")
        .legend(|(x, y)| PathElement::new(vec![(x, y), (x + 16, y)], BLUE));
    chart
        .draw_series(
            lattice_points
                .iter()
                .map(|&(x, y)| Circle::new((x, y), 3, RGBColor(230, 120, 0).filled())),
        )
        .map_err(|e| failure(&e))?
        .label("shifted lattice")
        .legend(|(x, y)| Circle::new((x + 8, y), 3, RGBColor(230, 120, 0).filled()));
    chart
        .draw_series(std::iter::once(Cross::new(
            seed_point,
            6,
            BLACK.stroke_width(2),
        )))
        .map_err(|e| failure(&e))?
        .label("seed")
        .legend(|(x, y)| Cross::new((x + 8, y), 5, BLACK));
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .draw()
        .map_err(|e| failure(&e))?;
    root.present().map_err(|e| failure(&e))
}

/// The points of the local lattice exploration around `seed_point` (in its
/// tile, in unit-square coordinates) and the random walk from it.
#[allow(clippy::type_complexity)]
fn local_exploration(
    seed_point: (f64, f64),
    seed: u64,
) -> Result<(Vec<(f64, f64)>, Vec<(f64, f64)>), CliError> {
    let lattice = cbc(EXPLORATION_POINTS, 2, &ProductWeights::lqmc_default(2))?.lattice;
    let search = ClosestPointSearch::new(lattice.clone())?;
    // Tile-local coordinates of the seed; the lattice shifted by the closest
    // point's Cranley–Patterson shift contains it.
    let to_local = |v: f64| (v * TILES_PER_DIMENSION).fract();
    let local = [to_local(seed_point.0), to_local(seed_point.1)];
    let closest = search.closest_point(&local)?;
    let origin = (
        (seed_point.0 * TILES_PER_DIMENSION).floor(),
        (seed_point.1 * TILES_PER_DIMENSION).floor(),
    );
    let to_global = |x: f64, y: f64| {
        (
            (origin.0 + x) / TILES_PER_DIMENSION,
            (origin.1 + y) / TILES_PER_DIMENSION,
        )
    };
    let lattice_points = (0..EXPLORATION_POINTS)
        .map(|i| {
            let x =
                qmc::cranley_patterson::shift_modulo_one(lattice.sample(i, 0), closest.shift[0]);
            let y =
                qmc::cranley_patterson::shift_modulo_one(lattice.sample(i, 1), closest.shift[1]);
            to_global(x, y)
        })
        .collect();
    let step = 1.0 / (EXPLORATION_POINTS as f64).sqrt();
    let mut random = SeekablePcg::new(seed, 0x57A1_4B1E);
    let mut position = local;
    let mut walk = vec![to_global(position[0], position[1])];
    for _ in 1..EXPLORATION_POINTS {
        for coordinate in position.iter_mut() {
            let delta = (2.0 * random.next_f64() - 1.0) * step;
            *coordinate = (*coordinate + delta).rem_euclid(1.0);
        }
        walk.push(to_global(position[0], position[1]));
    }
    Ok((lattice_points, walk))
}
