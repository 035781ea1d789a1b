//! `lqmc study heinrich-keller`: Heinrich & Keller's §5 (1994). The
//! radiance arriving at every triangle of a scene after up to M
//! reflections, `Σ_{m ≤ M} ⟨T^m L₀, G χ_A⟩` (Eq. 14, RGB), by particle
//! simulation ([`render::integrators::particle_radiance`]) with N
//! = 10^4 … 10^7 particles of each pattern: random (PCG), Halton,
//! scrambled (Faure) Halton, Hammersley (N fixed in advance) and, as an
//! addition, Sobol. A measurement is the set of per-triangle values,
//! `--measure integral` (default) Eq. (14) itself, "the total radiance
//! that reaches A" integrated over the triangle (its arriving flux), or
//! `--measure per-area` that over the triangle's area; two are compared by the paper's area-weighted RGB distance
//! ([`render::integrators::particle_radiance::deviation`]):
//!
//! - per pattern, the mutual deviations between its sampling rates (the
//!   paper's Tables 2–5), the largest count being the pattern's master;
//! - between patterns, the deviations of their masters (Table 6);
//! - the deviation from the pattern's master against N, log–log, with the
//!   fitted rate (least squares of log deviation on log N over the counts
//!   below the master).
//!
//! Outputs in the directory: `table.md`, `table.json` (every measurement's
//! deviations and the particles per second), `convergence.svg`/`.png`, and
//! with `--per-triangle FILE.csv` every triangle's area, radiance per
//! area and integral per pattern and count.
//!
//! Why the integral is the default: the paper defines the quantity of a
//! triangle as the integral (10)–(14), "cumulated for the surface
//! elements". Per area, every triangle counts about equally in the
//! area-weighted norm (a triangle's squared error per area grows as 1/|A|,
//! its weight as |A|), so the many small furniture triangles, whose
//! integrands are mostly discontinuity, rule it and QMC gains little; the
//! integral weights the triangles by their share of the light, as the
//! paper's findings need (measured: docs/studies.md).

use super::equal_time::prepare_output_directory;
use super::error_plot::{ErrorCurve, ErrorPoint, write_error_plot};
use super::formatting::{command_line, format_significant, utc_timestamp};
use crate::error::{CliError, usage};
use crate::json::Json;
use crate::render_command::load_scene_description;
use clap::Args;
use qmc::digital_scramble::DigitalOrder;
use qmc::halton::{Halton, HaltonScramble};
use qmc::hammersley::Hammersley;
use qmc::point_set::PointSet;
use qmc::random::RandomPoints;
use qmc::sobol::Sobol;
use render::integrators::particle_radiance::{ParticleScene, deviation, simulate};
use std::fmt::Write as _;
use std::path::PathBuf;
use std::time::{Instant, SystemTime};

/// The patterns, in the paper's order, Sobol last.
pub const PATTERNS: [&str; 5] = [
    "random",
    "halton",
    "scrambled-halton",
    "hammersley",
    "sobol",
];

/// The paper's particle counts.
pub const DEFAULT_COUNTS: [u64; 4] = [10_000, 100_000, 1_000_000, 10_000_000];

/// What a measurement holds per triangle.
#[derive(clap::ValueEnum, Clone, Copy, Debug, PartialEq, Eq)]
pub enum Measure {
    /// Eq. (14) integrated over the triangle: the flux arriving at it.
    Integral,
    /// Eq. (14) over the triangle's area: its mean arriving radiance.
    PerArea,
}

impl Measure {
    /// The name in the CLI and the outputs.
    pub fn name(self) -> &'static str {
        match self {
            Measure::Integral => "integral",
            Measure::PerArea => "per-area",
        }
    }
}

/// Arguments of `lqmc study heinrich-keller`.
#[derive(Args, Debug)]
pub struct HeinrichKellerArgs {
    /// The scene: `builtin:heinrich-keller` (a furnished room of 276
    /// triangles, the paper's kind) or any scene of diffuse triangle meshes.
    #[arg(default_value = "builtin:heinrich-keller")]
    pub scene: String,
    /// M, the reflections (the Neumann series is truncated after T^M).
    #[arg(long, default_value_t = 4)]
    pub bounces: usize,
    /// Particle counts N, comma-separated, ascending (1e4 and the like
    /// accepted); the largest is every pattern's master.
    #[arg(long, value_delimiter = ',', value_parser = parse_count)]
    pub counts: Option<Vec<u64>>,
    /// Patterns, comma-separated (default: all of random, halton,
    /// scrambled-halton, hammersley, sobol).
    #[arg(long, value_delimiter = ',')]
    pub patterns: Option<Vec<String>>,
    /// Per triangle: `integral` (Eq. 14 integrated over the triangle, the
    /// paper's quantity) or `per-area` (that over the triangle's area).
    #[arg(long, value_enum, default_value_t = Measure::Integral)]
    pub measure: Measure,
    /// The random pattern's seed.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Writes every triangle's area, radiance per area and integral per
    /// pattern and count.
    #[arg(long, value_name = "FILE.csv")]
    pub per_triangle: Option<PathBuf>,
    /// Worker threads (default: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
    /// Output directory: table.md, table.json, convergence.svg and .png.
    #[arg(short = 'o', long)]
    pub output: PathBuf,
}

/// A count such as `10000`, `1e4` or `2.5e6`.
pub fn parse_count(text: &str) -> Result<u64, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a particle count"))?;
    if !((1.0..=1e12).contains(&value) && value.fract() == 0.0) {
        return Err(format!("`{text}` is not a particle count from 1 to 1e12"));
    }
    Ok(value as u64)
}

/// The point set of `pattern` for `count` particles in `dimensions`.
fn point_set(
    pattern: &str,
    count: u64,
    dimensions: usize,
    seed: u64,
) -> Result<Box<dyn PointSet + Sync>, CliError> {
    let failure = |error: qmc::point_set::PointSetError| CliError::Failure(error.to_string());
    Ok(match pattern {
        "random" => Box::new(RandomPoints::new(dimensions, seed)),
        "halton" => Box::new(Halton::new(dimensions, HaltonScramble::None, 0).map_err(failure)?),
        "scrambled-halton" => {
            Box::new(Halton::new(dimensions, HaltonScramble::Faure, 0).map_err(failure)?)
        }
        "hammersley" => {
            Box::new(Hammersley::new(count, dimensions, HaltonScramble::None, 0).map_err(failure)?)
        }
        "sobol" => Box::new(Sobol::new(dimensions, DigitalOrder::Natural).map_err(failure)?),
        other => {
            return Err(usage(format!(
                "--patterns: unknown pattern `{other}` (known: {})",
                PATTERNS.join(", ")
            )));
        }
    })
}

/// One pattern's measurements, by count.
struct PatternResult {
    name: String,
    /// Per count: every triangle's radiance per area.
    radiances: Vec<Vec<[f64; 3]>>,
    /// Per count: every triangle's integral (arriving flux).
    integrals: Vec<Vec<[f64; 3]>>,
    /// Per count: particles per second.
    rates: Vec<f64>,
}

/// The least-squares slope of log y on log x.
pub fn fitted_rate(points: &[(f64, f64)]) -> Option<f64> {
    let logs: Vec<(f64, f64)> = points
        .iter()
        .filter(|(x, y)| *x > 0.0 && *y > 0.0)
        .map(|(x, y)| (x.ln(), y.ln()))
        .collect();
    if logs.len() < 2 {
        return None;
    }
    let n = logs.len() as f64;
    let mean_x = logs.iter().map(|p| p.0).sum::<f64>() / n;
    let mean_y = logs.iter().map(|p| p.1).sum::<f64>() / n;
    let covariance: f64 = logs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    let variance: f64 = logs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    (variance > 0.0).then(|| covariance / variance)
}

/// Runs `lqmc study heinrich-keller`.
pub fn run(args: &HeinrichKellerArgs) -> Result<(), CliError> {
    let mut counts = args
        .counts
        .clone()
        .unwrap_or_else(|| DEFAULT_COUNTS.to_vec());
    if counts.is_empty() {
        return Err(usage("--counts needs at least one particle count"));
    }
    counts.sort_unstable();
    counts.dedup();
    let patterns: Vec<String> = args
        .patterns
        .clone()
        .unwrap_or_else(|| PATTERNS.iter().map(|name| name.to_string()).collect());
    if args.bounces > 64 {
        return Err(usage("--bounces must be at most 64"));
    }
    let description = load_scene_description(&args.scene, &[], None, args.quiet)?;
    let scene = ParticleScene::new(&description)
        .map_err(|error| usage(format!("{}: {error}", args.scene)))?;
    prepare_output_directory(&args.output)?;
    let dimensions = 2 * args.bounces + 4;
    let threads = if args.threads == 0 {
        std::thread::available_parallelism().map_or(1, |count| count.get())
    } else {
        args.threads
    };
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|error| CliError::Failure(error.to_string()))?;
    let areas = scene.areas().to_vec();
    let started = SystemTime::now();
    let mut results = Vec::new();
    for pattern in &patterns {
        // Validates the name before any simulation.
        point_set(pattern, 1, dimensions, args.seed)?;
    }
    for pattern in &patterns {
        let mut radiances = Vec::new();
        let mut integrals = Vec::new();
        let mut rates = Vec::new();
        for &count in &counts {
            let points = point_set(pattern, count, dimensions, args.seed)?;
            let clock = Instant::now();
            let table = pool.install(|| simulate(&scene, points.as_ref(), count, args.bounces));
            let seconds = clock.elapsed().as_secs_f64();
            let rate = count as f64 / seconds.max(1e-9);
            if !args.quiet {
                println!(
                    "{pattern}: {count} particles in {seconds:.2} s ({:.2} M particles/s, {:.1} M rays/s, {threads} threads)",
                    rate / 1e6,
                    table.rays as f64 / seconds.max(1e-9) / 1e6
                );
            }
            radiances.push(table.radiances(&areas));
            integrals.push(table.total_fluxes());
            rates.push(rate);
        }
        results.push(PatternResult {
            name: pattern.clone(),
            radiances,
            integrals,
            rates,
        });
    }
    write_outputs(args, &counts, &areas, &results, started)
}

impl PatternResult {
    /// Per count, the measurement of `measure`.
    fn measurements(&self, measure: Measure) -> &[Vec<[f64; 3]>] {
        match measure {
            Measure::Integral => &self.integrals,
            Measure::PerArea => &self.radiances,
        }
    }
}

/// Writes table.md, table.json, the plot and the CSV.
fn write_outputs(
    args: &HeinrichKellerArgs,
    counts: &[u64],
    areas: &[f64],
    results: &[PatternResult],
    started: SystemTime,
) -> Result<(), CliError> {
    let write = |name: &str, text: &str| {
        let path = args.output.join(name);
        std::fs::write(&path, text)
            .map_err(|error| CliError::Failure(format!("cannot write {}: {error}", path.display())))
    };
    let last = counts.len() - 1;
    let mut markdown = String::new();
    let _ = writeln!(
        markdown,
        "# Heinrich & Keller: radiance per triangle by particle simulation\n\n`{}` ({}), M = {}, {} triangles, measure {} ({}).\n",
        command_line(),
        utc_timestamp(started),
        args.bounces,
        areas.len(),
        args.measure.name(),
        match args.measure {
            Measure::Integral => "Eq. 14 integrated over each triangle",
            Measure::PerArea => "Eq. 14 over each triangle's area",
        }
    );
    let mut json_patterns = Vec::new();
    let mut curves = Vec::new();
    for result in results {
        let measurements = result.measurements(args.measure);
        let _ = writeln!(
            markdown,
            "## {}: mutual deviation of sampling rates\n",
            result.name
        );
        let mut header = "| N |".to_string();
        let mut rule = "|---|".to_string();
        for &count in &counts[..last] {
            let _ = write!(header, " {count} |");
            rule.push_str("---|");
        }
        let _ = writeln!(markdown, "{header}\n{rule}");
        let mut matrix = Vec::new();
        for (row, count) in counts.iter().enumerate().skip(1) {
            let mut line = format!("| {count} |");
            let mut values = Vec::new();
            for column in 0..last {
                if column < row {
                    let value = deviation(&measurements[row], &measurements[column], areas);
                    let _ = write!(line, " {} |", format_significant(value, 6));
                    values.push(value);
                } else {
                    line.push_str(" – |");
                }
            }
            let _ = writeln!(markdown, "{line}");
            matrix.push(Json::numbers(&values));
        }
        let from_master: Vec<(f64, f64)> = (0..last)
            .map(|index| {
                (
                    counts[index] as f64,
                    deviation(&measurements[index], &measurements[last], areas),
                )
            })
            .collect();
        let rate = fitted_rate(&from_master);
        let _ = writeln!(
            markdown,
            "\nDeviation from the master (N = {}) ∝ N^{}; particles per second {}.\n",
            counts[last],
            rate.map_or("—".to_string(), |rate| format_significant(rate, 3)),
            result
                .rates
                .iter()
                .map(|rate| format_significant(*rate, 3))
                .collect::<Vec<_>>()
                .join(", ")
        );
        curves.push(ErrorCurve {
            label: result.name.clone(),
            points: from_master
                .iter()
                .map(|&(x, y)| ErrorPoint {
                    x,
                    median: y,
                    min: y,
                    max: y,
                })
                .collect(),
        });
        json_patterns.push(Json::object(vec![
            ("name", Json::String(result.name.clone())),
            ("mutual_deviations", Json::Array(matrix)),
            (
                "deviation_from_master",
                Json::numbers(&from_master.iter().map(|p| p.1).collect::<Vec<_>>()),
            ),
            (
                "fitted_rate",
                rate.map_or(Json::String("none".into()), Json::Number),
            ),
            ("particles_per_second", Json::numbers(&result.rates)),
        ]));
    }
    let _ = writeln!(
        markdown,
        "## Deviation of the patterns' masters (N = {})\n\n| M | M' | deviation |\n|---|---|---|",
        counts[last]
    );
    let mut between = Vec::new();
    for (index, first) in results.iter().enumerate() {
        for second in &results[index + 1..] {
            let value = deviation(
                &first.measurements(args.measure)[last],
                &second.measurements(args.measure)[last],
                areas,
            );
            let _ = writeln!(
                markdown,
                "| {} | {} | {} |",
                first.name,
                second.name,
                format_significant(value, 6)
            );
            between.push(Json::object(vec![
                ("first", Json::String(first.name.clone())),
                ("second", Json::String(second.name.clone())),
                ("deviation", Json::Number(value)),
            ]));
        }
    }
    write("table.md", &markdown)?;
    let json = Json::object(vec![
        ("command", Json::String(command_line())),
        ("scene", Json::String(args.scene.clone())),
        ("bounces", Json::Integer(args.bounces as u64)),
        ("measure", Json::String(args.measure.name().into())),
        ("counts", Json::integers(counts)),
        ("patterns", Json::Array(json_patterns)),
        ("between_masters", Json::Array(between)),
    ]);
    write("table.json", &json.render())?;
    if counts.len() >= 2 {
        write_error_plot(
            &args.output.join("convergence.svg"),
            &args.output.join("convergence.png"),
            "Deviation from the master, per pattern",
            "particles N",
            "area-weighted RGB deviation",
            &curves,
        )?;
    }
    if let Some(path) = &args.per_triangle {
        let mut csv = String::from(
            "pattern,particles,triangle,area,r,g,b,integral_r,integral_g,integral_b\n",
        );
        for result in results {
            for (count_index, &count) in counts.iter().enumerate() {
                let integrals = &result.integrals[count_index];
                for (triangle, value) in result.radiances[count_index].iter().enumerate() {
                    let integral = integrals[triangle];
                    let _ = writeln!(
                        csv,
                        "{},{count},{triangle},{},{},{},{},{},{},{}",
                        result.name,
                        areas[triangle],
                        value[0],
                        value[1],
                        value[2],
                        integral[0],
                        integral[1],
                        integral[2]
                    );
                }
            }
        }
        std::fs::write(path, csv).map_err(|error| {
            CliError::Failure(format!("cannot write {}: {error}", path.display()))
        })?;
    }
    Ok(())
}
