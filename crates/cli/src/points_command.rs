//! `lqmc points`: print points of any sequence or point set of the `qmc`
//! crate, optionally with discrepancies, as JSON, per pixel, or as a plot.

use crate::error::{CliError, usage};
use crate::json::Json;
use clap::{Args, ValueEnum};
use qmc::PointSet;
use qmc::catalog::{self, Scramble, Sequence};
use qmc::digital_scramble::DigitalOrder;
use qmc::discrepancy::{self, L2Discrepancy};
use qmc::halton::{Halton, HaltonScramble, PixelEnumeration};
use std::io::{BufWriter, Write};

/// The sequences, as command-line values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SequenceName {
    Halton,
    Hammersley,
    Sobol,
    Niederreiter,
    Lattice,
    Random,
}

/// The scrambles, as command-line values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ScrambleName {
    /// No randomization.
    None,
    /// Faure's permutations (halton, hammersley).
    Faure,
    /// Random digit permutations (halton, hammersley).
    Permute,
    /// Owen scrambling: nested uniform for halton/hammersley, hash-based for
    /// sobol/niederreiter.
    Owen,
    /// Exact nested uniform scrambling, one random bit per node (sobol,
    /// niederreiter).
    Nested,
    /// Random digital shift (sobol, niederreiter).
    Xor,
    /// Linear matrix scrambling with a digital shift (sobol, niederreiter).
    Lms,
    /// Cranley–Patterson rotation (any).
    Shift,
}

/// The enumeration order of the base-2 sequences.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum OrderName {
    /// Point i uses the binary digits of i.
    Natural,
    /// Point i uses the Gray code of i (scipy's order).
    Gray,
}

/// Arguments of `lqmc points`.
#[derive(Args, Debug)]
pub struct PointsArgs {
    /// The sequence or point set.
    #[arg(value_enum)]
    pub sequence: SequenceName,
    /// Number of points to print.
    #[arg(long)]
    pub count: u64,
    /// Dimensions per point.
    #[arg(long, default_value_t = 2)]
    pub dims: usize,
    /// Index of the first point (indices start at 0).
    #[arg(long, default_value_t = 0)]
    pub start: u64,
    /// Number of points of a finite set (hammersley, lattice); default
    /// start + count.
    #[arg(long)]
    pub size: Option<u64>,
    /// Randomization or scramble.
    #[arg(long, value_enum, default_value_t = ScrambleName::None)]
    pub scramble: ScrambleName,
    /// Seed of the randomization (and of random points).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Enumeration order of sobol and niederreiter.
    #[arg(long, value_enum, default_value_t = OrderName::Natural)]
    pub order: OrderName,
    /// Print the samples of this pixel (Halton only): X,Y.
    #[arg(long, value_parser = parse_pair, requires = "resolution")]
    pub pixel: Option<(u32, u32)>,
    /// Image resolution for --pixel: W,H.
    #[arg(long, value_parser = parse_pair)]
    pub resolution: Option<(u32, u32)>,
    /// Also compute the L2-star, centered, wrap-around and mixture L2
    /// discrepancies (and the exact star discrepancy for up to 2 dimensions).
    #[arg(long)]
    pub discrepancy: bool,
    /// Print one JSON object instead of CSV lines.
    #[arg(long)]
    pub json: bool,
    /// Write an SVG plot: the 2-D projection of the points beside a lattice's
    /// local exploration and a random walk's (the LQMC paper's Fig. 2).
    #[arg(long, value_name = "FILE.svg")]
    pub plot: Option<std::path::PathBuf>,
}

/// Parses `A,B` (or `AxB`) into two unsigned integers.
pub fn parse_pair(text: &str) -> Result<(u32, u32), String> {
    let (a, b) = text
        .split_once([',', 'x'])
        .ok_or_else(|| format!("expected two numbers like 3,4, got '{text}'"))?;
    let parse = |s: &str| {
        s.trim()
            .parse::<u32>()
            .map_err(|_| format!("expected two non-negative integers like 3,4, got '{text}'"))
    };
    Ok((parse(a)?, parse(b)?))
}

impl SequenceName {
    fn sequence(self) -> Sequence {
        match self {
            SequenceName::Halton => Sequence::Halton,
            SequenceName::Hammersley => Sequence::Hammersley,
            SequenceName::Sobol => Sequence::Sobol,
            SequenceName::Niederreiter => Sequence::Niederreiter,
            SequenceName::Lattice => Sequence::Lattice,
            SequenceName::Random => Sequence::Random,
        }
    }
}

impl ScrambleName {
    fn scramble(self) -> Scramble {
        match self {
            ScrambleName::None => Scramble::None,
            ScrambleName::Faure => Scramble::Faure,
            ScrambleName::Permute => Scramble::Permute,
            ScrambleName::Owen => Scramble::Owen,
            ScrambleName::Nested => Scramble::NestedUniform,
            ScrambleName::Xor => Scramble::Xor,
            ScrambleName::Lms => Scramble::LinearMatrix,
            ScrambleName::Shift => Scramble::Shift,
        }
    }
}

/// The points to print: their global indices and coordinates (row-major),
/// plus the unit-cube coordinates the discrepancies are computed on.
struct Selection {
    indices: Vec<u64>,
    points: Vec<f64>,
    unit_points: Vec<f64>,
}

/// Runs `lqmc points`.
pub fn run(args: &PointsArgs) -> Result<(), CliError> {
    if args.count == 0 {
        return Err(usage("--count must be at least 1"));
    }
    if args.dims == 0 {
        return Err(usage("--dims must be at least 1"));
    }
    let sequence = args.sequence.sequence();
    if args.dims > sequence.max_dimensions() {
        return Err(usage(format!(
            "{} supports at most {} dimensions, {} requested",
            sequence.name(),
            sequence.max_dimensions(),
            args.dims
        )));
    }
    let end = args
        .start
        .checked_add(args.count)
        .ok_or_else(|| usage("--start + --count exceeds 2^64"))?;
    if end > sequence.max_points() {
        return Err(usage(format!(
            "{} has {} points; indices up to {} requested",
            sequence.name(),
            sequence.max_points(),
            end - 1
        )));
    }
    if args.count.saturating_mul(args.dims as u64) > 100_000_000 {
        return Err(usage("at most 10^8 coordinates can be printed at once"));
    }
    let selection = match (args.pixel, args.resolution) {
        (Some(pixel), Some(resolution)) => pixel_selection(args, pixel, resolution)?,
        (None, Some(_)) => return Err(usage("--resolution goes with --pixel")),
        _ => plain_selection(args, sequence, end)?,
    };
    let discrepancies = if args.discrepancy {
        Some(compute_discrepancies(&selection.unit_points, args.dims)?)
    } else {
        None
    };
    if let Some(path) = &args.plot {
        crate::plot::write_points_plot(path, &selection.unit_points, args.dims, args.seed)?;
    }
    let stdout = std::io::stdout();
    let mut out = BufWriter::new(stdout.lock());
    let written = if args.json {
        let mut pairs = vec![
            ("sequence", Json::String(sequence.name().to_string())),
            ("dims", Json::Integer(args.dims as u64)),
            ("indices", Json::integers(&selection.indices)),
            (
                "points",
                Json::Array(
                    selection
                        .points
                        .chunks(args.dims)
                        .map(Json::numbers)
                        .collect(),
                ),
            ),
        ];
        if let Some(values) = &discrepancies {
            pairs.push((
                "discrepancy",
                Json::Object(
                    values
                        .iter()
                        .map(|(name, value)| (name.to_string(), Json::Number(*value)))
                        .collect(),
                ),
            ));
        }
        writeln!(out, "{}", Json::object(pairs).render())
    } else {
        write_csv(&mut out, &selection.points, args.dims).and_then(|()| {
            for (name, value) in discrepancies.iter().flatten() {
                writeln!(out, "# {name}: {value:?}")?;
            }
            Ok(())
        })
    };
    match written.and_then(|()| out.flush()) {
        // A reader that stops early (`| head`) is not an error.
        Err(error) if error.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        result => {
            result.map_err(|error| CliError::Failure(format!("cannot write to stdout: {error}")))
        }
    }
}

fn write_csv(out: &mut impl Write, points: &[f64], dims: usize) -> std::io::Result<()> {
    let mut line = String::new();
    for point in points.chunks(dims) {
        line.clear();
        for (i, value) in point.iter().enumerate() {
            if i > 0 {
                line.push(',');
            }
            // Debug formatting is the shortest text that reads back exactly.
            line.push_str(&format!("{value:?}"));
        }
        writeln!(out, "{line}")?;
    }
    Ok(())
}

fn plain_selection(args: &PointsArgs, sequence: Sequence, end: u64) -> Result<Selection, CliError> {
    let size = args.size.unwrap_or(end);
    if sequence.is_finite() && end > size {
        return Err(usage(format!(
            "the {} set has --size {size} points; indices up to {} requested",
            sequence.name(),
            end - 1
        )));
    }
    if sequence.is_finite() && size < 2 && sequence == Sequence::Lattice {
        return Err(usage("a lattice needs at least 2 points (N >= 2)"));
    }
    let order = match args.order {
        OrderName::Natural => DigitalOrder::Natural,
        OrderName::Gray => DigitalOrder::GrayCode,
    };
    let set = catalog::build(
        sequence,
        args.scramble.scramble(),
        order,
        size,
        args.dims,
        args.seed,
    )?;
    let indices: Vec<u64> = (args.start..end).collect();
    let points = gather(set.as_ref(), &indices, args.dims);
    Ok(Selection {
        unit_points: points.clone(),
        indices,
        points,
    })
}

fn pixel_selection(
    args: &PointsArgs,
    pixel: (u32, u32),
    resolution: (u32, u32),
) -> Result<Selection, CliError> {
    if args.sequence != SequenceName::Halton {
        return Err(usage("--pixel enumerates the Halton sequence only"));
    }
    if args.dims < 2 {
        return Err(usage("--pixel needs --dims 2 or more"));
    }
    let scramble = match args.scramble {
        ScrambleName::None => HaltonScramble::None,
        ScrambleName::Faure => HaltonScramble::Faure,
        ScrambleName::Permute => HaltonScramble::RandomPermutation,
        ScrambleName::Owen => HaltonScramble::Owen,
        other => {
            return Err(usage(format!(
                "--pixel works with the Halton scrambles none, faure, permute and owen, not {other:?}"
            )));
        }
    };
    let halton = Halton::new(args.dims, scramble, args.seed)?;
    let enumeration = PixelEnumeration::new(resolution.0, resolution.1)?;
    let indices = (args.start..args.start + args.count)
        .map(|sample| enumeration.sample_index(&halton, pixel, sample))
        .collect::<Result<Vec<u64>, _>>()?;
    let unit_points = gather(&halton, &indices, args.dims);
    let mut points = unit_points.clone();
    for point in points.chunks_mut(args.dims) {
        point[0] *= enumeration.scale.0 as f64;
        point[1] *= enumeration.scale.1 as f64;
    }
    Ok(Selection {
        indices,
        points,
        unit_points,
    })
}

fn gather(set: &dyn PointSet, indices: &[u64], dims: usize) -> Vec<f64> {
    let mut points = vec![0.0; indices.len() * dims];
    for (point, &index) in points.chunks_mut(dims).zip(indices) {
        set.point(index, point);
    }
    points
}

fn compute_discrepancies(
    points: &[f64],
    dims: usize,
) -> Result<Vec<(&'static str, f64)>, CliError> {
    let mut values = vec![
        (
            "l2_star",
            discrepancy::l2_discrepancy(L2Discrepancy::Star, points, dims)?,
        ),
        (
            "centered",
            discrepancy::l2_discrepancy(L2Discrepancy::Centered, points, dims)?,
        ),
        (
            "wrap_around",
            discrepancy::l2_discrepancy(L2Discrepancy::WrapAround, points, dims)?,
        ),
        (
            "mixture",
            discrepancy::l2_discrepancy(L2Discrepancy::Mixture, points, dims)?,
        ),
    ];
    if dims <= 2 {
        values.push(("star", discrepancy::star_discrepancy(points, dims)?));
    }
    Ok(values)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_parse_with_comma_or_x() {
        assert_eq!(parse_pair("3,4"), Ok((3, 4)));
        assert_eq!(parse_pair("640x480"), Ok((640, 480)));
        assert!(parse_pair("3").is_err());
        assert!(parse_pair("-1,2").is_err());
    }
}
