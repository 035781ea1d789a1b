//! `lqmc study kollig-keller`: Kollig & Keller's Sect. 6 on a built-in
//! scene of its kind. A master image from a long BDPT run, then the L2
//! error of BDPT against it at n = 1 … 128 samples per pixel (and so per
//! technique: every sample evaluates every strategy once) for Monte Carlo,
//! quasi-Monte Carlo sequences and randomized QMC point sets:
//!
//! - the error of one image is its RMSE against the master over pixels and
//!   channels, with the master's own variance (estimated from its
//!   replications, Eq. 6) taken out of the mean squared error: `e² = MSE −
//!   mean master variance`, so that the master's noise does not flatten the
//!   curves at large n;
//! - a randomized method's error at n is the root of the mean of `e²` over
//!   the seeds (independent replications); a deterministic one (QMC, or a
//!   method whose only randomness is the seed's pseudo-random numbers past
//!   its dimensions) is rendered once;
//! - the convergence rate is the least-squares slope of log e against log n;
//! - Fig. 9's bars: the samples the method needs for the error MC reaches
//!   with n samples, relative to n, from the power-law fits of both curves,
//!   averaged geometrically over MC's counts ([`samples_relative_to_mc`]).
//!
//! With fewer samples than a method's pattern size m, the pattern is the
//! n-point set (one replication); past it, n / m replications of m points.

use super::equal_time::{prepare_output_directory, write_failure};
use super::error_plot::{ErrorCurve, ErrorPoint, write_error_plot};
use super::formatting::{command_line, format_significant, utc_timestamp};
use crate::error::{CliError, usage};
use crate::integrator_options::default_heuristic;
use crate::json::Json;
use crate::render_command::{build_scene, load_scene_description};
use clap::Args;
use render::image::{Image, write_exr};
use render::integrators::bdpt::BdptSettings;
use render::integrators::{IntegratorKind, IntegratorSettings};
use render::renderer::{RenderSettings, render};
use render::sampler::{Randomization, SamplerKind};
use render::scene::Scene;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::SystemTime;

/// Arguments of `lqmc study kollig-keller`.
#[derive(Args, Debug)]
pub struct KolligKellerArgs {
    /// The scene: `office` (k_max = 3, no eye connections) or
    /// `glass-sphere-box` (k_max = 6), the built-in scenes of the paper's
    /// kind; any other `builtin:NAME` or scene file with --max-depth.
    #[arg(long, default_value = "office")]
    pub scene: String,
    /// Image resolution WxH (default 64x48).
    #[arg(long, value_parser = crate::points_command::parse_pair)]
    pub resolution: Option<(u32, u32)>,
    /// k_max, the maximum path length in segments (default: 3 for office,
    /// 6 otherwise).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// Leave out the eye-connection techniques (default: for office, as the
    /// paper does).
    #[arg(long)]
    pub skip_eye_connections: Option<bool>,
    /// Samples per pixel of the master image (independent sampler, in
    /// replications of 16 for its variance).
    #[arg(long, default_value_t = 2048)]
    pub master_spp: u64,
    /// Samples per pixel to measure (default: 1, 2, 3, 4, 6, 8, 12, 16, 24,
    /// 32, 48, 64, 96, 128).
    #[arg(long, value_delimiter = ',')]
    pub counts: Option<Vec<u64>>,
    /// Seeds (independent replications) per randomized method and count.
    #[arg(long, default_value_t = 8)]
    pub seeds: u64,
    /// The methods, comma-separated (default: all; see `Method::ALL`).
    #[arg(long, value_delimiter = ',')]
    pub methods: Option<Vec<String>>,
    /// Worker threads (default: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Keep every render's image in OUTPUT/images.
    #[arg(long)]
    pub keep_images: bool,
    /// No progress output.
    #[arg(long)]
    pub quiet: bool,
    /// Output directory: master.exr, table.md, table.json, convergence and
    /// samples-relative-to-mc plots (SVG and PNG).
    #[arg(long, short = 'o')]
    pub output: PathBuf,
}

/// One sampling method of the study.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Method {
    /// The name in tables, legends and `--methods`.
    pub name: &'static str,
    /// The sampler.
    pub sampler: SamplerKind,
    /// Whether the seed randomizes the points.
    pub randomization: Randomization,
    /// The pattern size m of the replications (`None`: one set of n
    /// points, or the sequence).
    pub pattern_size: Option<u64>,
    /// Whether renders with different seeds are independent replications
    /// (else the method is rendered once per count).
    pub randomized: bool,
}

impl Method {
    /// The paper's methods (Figs. 7–9).
    pub const ALL: [Method; 11] = [
        Method::new("mc", SamplerKind::Independent, true, None),
        Method::new("qmc-halton", SamplerKind::Halton, false, None),
        Method::new(
            "qmc-niederreiter",
            SamplerKind::GlobalNiederreiter,
            false,
            None,
        ),
        Method::new("qmc-sobol", SamplerKind::GlobalSobol, false, None),
        Method::new(
            "rqmc-hammersley-16",
            SamplerKind::Hammersley,
            true,
            Some(16),
        ),
        Method::new(
            "rqmc-hammersley-32",
            SamplerKind::Hammersley,
            true,
            Some(32),
        ),
        Method::new("rqmc-padded-16", SamplerKind::Padded, true, Some(16)),
        Method::new("rqmc-padded-32", SamplerKind::Padded, true, Some(32)),
        Method::new("rqmc-owen-sobol", SamplerKind::Sobol, true, None),
        Method::new("latin-supercube", SamplerKind::LatinSupercube, false, None),
        Method::new(
            "rqmc-latin-supercube-16",
            SamplerKind::LatinSupercube,
            true,
            Some(16),
        ),
    ];

    const fn new(
        name: &'static str,
        sampler: SamplerKind,
        randomized_points: bool,
        pattern_size: Option<u64>,
    ) -> Self {
        Method {
            name,
            sampler,
            randomization: if randomized_points {
                Randomization::Seeded
            } else {
                Randomization::None
            },
            pattern_size,
            // Deterministic Latin supercube points still have random
            // permutations: its renders are replications too.
            randomized: randomized_points || matches!(sampler, SamplerKind::LatinSupercube),
        }
    }

    /// The pattern size of a render of `n` samples per pixel.
    fn pattern_size_at(&self, n: u64) -> Option<u64> {
        match self.sampler {
            SamplerKind::Hammersley
            | SamplerKind::Padded
            | SamplerKind::LatinSupercube
            | SamplerKind::Sobol => Some(self.pattern_size.unwrap_or(n).min(n)),
            _ => None,
        }
    }
}

/// The default sample counts: powers of two and the values between.
const DEFAULT_COUNTS: [u64; 14] = [1, 2, 3, 4, 6, 8, 12, 16, 24, 32, 48, 64, 96, 128];

/// One method's measured errors.
#[derive(Debug, Clone)]
pub struct MethodResult {
    /// The method's name.
    pub name: String,
    /// Per count: the count and the per-seed squared errors `e²`.
    pub squared_errors: Vec<(u64, Vec<f64>)>,
}

impl MethodResult {
    /// Per count, the error: the root of the mean squared error over seeds.
    pub fn errors(&self) -> Vec<(u64, f64)> {
        self.squared_errors
            .iter()
            .map(|(count, squares)| {
                let mean = squares.iter().sum::<f64>() / squares.len().max(1) as f64;
                (*count, mean.max(0.0).sqrt())
            })
            .collect()
    }
}

/// The least-squares slope of log e against log n (the convergence rate;
/// NaN with fewer than two positive errors).
pub fn convergence_rate(errors: &[(u64, f64)]) -> f64 {
    power_law_fit(errors).1
}

/// The least-squares fit `log e = log a + b log n`: `(a, b)` (NaN with
/// fewer than two positive errors).
pub fn power_law_fit(errors: &[(u64, f64)]) -> (f64, f64) {
    let points: Vec<(f64, f64)> = errors
        .iter()
        .filter(|(_, error)| *error > 0.0 && error.is_finite())
        .map(|(count, error)| ((*count as f64).ln(), error.ln()))
        .collect();
    if points.len() < 2 {
        return (f64::NAN, f64::NAN);
    }
    let count = points.len() as f64;
    let mean_x = points.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = points.iter().map(|p| p.1).sum::<f64>() / count;
    let covariance: f64 = points.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    let variance: f64 = points.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let slope = covariance / variance;
    ((mean_y - slope * mean_x).exp(), slope)
}

/// Fig. 9: the samples a method with errors `errors` needs for the error
/// MC reaches, relative to MC's samples. Both curves are the power-law fits
/// of their measurements (single points are noisy: a few seeds each), and
/// the ratio `n_method(e_MC(n)) / n` is averaged geometrically over MC's
/// measured counts n (for power laws the ratio at the geometric middle of
/// the counts). NaN if either fit fails.
pub fn samples_relative_to_mc(errors: &[(u64, f64)], mc: &[(u64, f64)]) -> f64 {
    let (mc_scale, mc_rate) = power_law_fit(mc);
    let (scale, rate) = power_law_fit(errors);
    if !(mc_rate < 0.0 && rate < 0.0) {
        return f64::NAN;
    }
    let log_ratios: Vec<f64> = mc
        .iter()
        .map(|(count, _)| {
            let log_count = (*count as f64).ln();
            let log_mc_error = mc_scale.ln() + mc_rate * log_count;
            (log_mc_error - scale.ln()) / rate - log_count
        })
        .collect();
    (log_ratios.iter().sum::<f64>() / log_ratios.len() as f64).exp()
}

/// The mean squared error of `image` against `master`, less the master's
/// mean variance.
fn squared_error(image: &Image, master: &Image, master_variance: f64) -> f64 {
    let mut sum = 0.0;
    let mut count = 0usize;
    for (pixel, reference) in image.pixels().iter().zip(master.pixels()) {
        for channel in 0..3 {
            let difference = f64::from(pixel[channel]) - f64::from(reference[channel]);
            if difference.is_finite() {
                sum += difference * difference;
                count += 1;
            }
        }
    }
    sum / count.max(1) as f64 - master_variance
}

/// The study's scene settings.
struct Setup<'a> {
    scene: &'a Scene,
    integrator: IntegratorSettings,
    max_depth: u32,
    threads: usize,
    stop: &'a AtomicBool,
}

impl Setup<'_> {
    fn render(
        &self,
        sampler: SamplerKind,
        randomization: Randomization,
        pattern_size: Option<u64>,
        samples_per_pixel: u64,
        seed: u64,
    ) -> Result<(Image, Image), CliError> {
        let settings = RenderSettings {
            integrator: self.integrator.clone(),
            sampler,
            pattern_size,
            samples_per_pixel,
            seed,
            randomization,
            max_depth: self.max_depth,
            heuristic: default_heuristic(IntegratorKind::Bdpt),
            threads: self.threads,
            ..RenderSettings::default()
        };
        let output = render(self.scene, &settings, self.stop, &|_, _| {})
            .map_err(|error| CliError::Failure(error.to_string()))?;
        if self.stop.load(Ordering::Relaxed) {
            return Err(CliError::Failure("interrupted".into()));
        }
        Ok((output.image(), output.variance_image()))
    }
}

/// Runs `lqmc study kollig-keller`.
pub fn run(args: &KolligKellerArgs) -> Result<(), CliError> {
    let counts = args
        .counts
        .clone()
        .unwrap_or_else(|| DEFAULT_COUNTS.to_vec());
    if counts.is_empty() || counts.contains(&0) {
        return Err(usage("--counts must be positive sample counts"));
    }
    if args.seeds == 0 || args.master_spp == 0 {
        return Err(usage("--seeds and --master-spp must be at least 1"));
    }
    let methods: Vec<Method> = match &args.methods {
        None => Method::ALL.to_vec(),
        Some(names) => names
            .iter()
            .map(|name| {
                Method::ALL
                    .iter()
                    .find(|method| method.name == name)
                    .copied()
                    .ok_or_else(|| {
                        usage(format!(
                            "--methods: unknown method `{name}` (known: {})",
                            Method::ALL.map(|method| method.name).join(", ")
                        ))
                    })
            })
            .collect::<Result<_, _>>()?,
    };
    if !methods.iter().any(|method| method.name == "mc") {
        return Err(usage(
            "--methods must include mc: the bars are relative to it",
        ));
    }
    let scene_name = if args.scene.contains(':') || args.scene.contains('.') {
        args.scene.clone()
    } else {
        format!("builtin:{}", args.scene)
    };
    let office = scene_name == "builtin:office";
    let description = load_scene_description(
        &scene_name,
        &[],
        Some(args.resolution.unwrap_or((64, 48))),
        args.quiet,
    )?;
    let scene = build_scene(&scene_name, &description)?;
    let max_depth = args.max_depth.unwrap_or(if office { 3 } else { 6 });
    if max_depth == 0 {
        return Err(usage("--max-depth must be at least 1"));
    }
    let skip_eye_connections = args.skip_eye_connections.unwrap_or(office);
    prepare_output_directory(&args.output)?;
    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::Relaxed));
    }
    let setup = Setup {
        scene: &scene,
        integrator: IntegratorSettings::Bdpt(BdptSettings {
            camera_connections: !skip_eye_connections,
            ..BdptSettings::default()
        }),
        max_depth,
        threads: args.threads,
        stop: &stop,
    };
    let started = utc_timestamp(SystemTime::now());
    let progress = |message: String| {
        if !args.quiet {
            eprintln!("{message}");
        }
    };

    // The master: independent replications of 16, for its variance.
    let master_pattern = 16.min(args.master_spp);
    let master_spp = args.master_spp / master_pattern * master_pattern;
    progress(format!("master: {master_spp} spp"));
    let master_started = std::time::Instant::now();
    let (master, master_variance_image) = setup.render(
        SamplerKind::Independent,
        Randomization::Seeded,
        Some(master_pattern),
        master_spp,
        1 << 40,
    )?;
    let master_seconds = master_started.elapsed().as_secs_f64();
    let master_variance = master_variance_image
        .pixels()
        .iter()
        .flat_map(|pixel| pixel.iter().map(|&value| f64::from(value)))
        .sum::<f64>()
        / (3 * master.pixels().len()) as f64;
    let master_path = args.output.join("master.exr");
    write_exr(
        &master_path,
        &master,
        &[("variance", &master_variance_image)],
        &Default::default(),
    )
    .map_err(|error| write_failure(&master_path, error))?;

    let mut results = Vec::new();
    for method in &methods {
        let seeds = if method.randomized { args.seeds } else { 1 };
        let mut squared_errors = Vec::new();
        for &count in &counts {
            let mut squares = Vec::new();
            for seed in 0..seeds {
                let (image, _) = setup.render(
                    method.sampler,
                    method.randomization,
                    method.pattern_size_at(count),
                    count,
                    seed,
                )?;
                if args.keep_images {
                    let path = args
                        .output
                        .join(format!("images/{}-n{count}-seed{seed}.exr", method.name));
                    write_exr(&path, &image, &[], &Default::default())
                        .map_err(|error| write_failure(&path, error))?;
                }
                squares.push(squared_error(&image, &master, master_variance));
            }
            squared_errors.push((count, squares));
        }
        let result = MethodResult {
            name: method.name.to_string(),
            squared_errors,
        };
        progress(format!(
            "{}: rate {:.3}",
            method.name,
            convergence_rate(&result.errors())
        ));
        results.push(result);
    }

    let summary = Summary {
        scene: scene_name.clone(),
        resolution: [master.width(), master.height()],
        max_depth,
        skip_eye_connections,
        master_spp,
        master_seconds,
        master_variance,
        seeds: args.seeds,
        started,
        command: command_line(),
    };
    write_outputs(&args.output, &summary, &methods, &results)
}

/// What the tables say about the study's setting.
struct Summary {
    scene: String,
    resolution: [usize; 2],
    max_depth: u32,
    skip_eye_connections: bool,
    master_spp: u64,
    master_seconds: f64,
    master_variance: f64,
    seeds: u64,
    started: String,
    command: String,
}

/// One row of the table: the method's name, its error per count, its rate
/// and Fig. 9's samples relative to MC.
type TableRow = (String, Vec<(u64, f64)>, f64, f64);

/// The table rows: per method, errors by count, rate and Fig. 9's ratio.
pub fn table_rows(results: &[MethodResult]) -> Vec<TableRow> {
    let mc = results
        .iter()
        .find(|result| result.name == "mc")
        .map(MethodResult::errors)
        .unwrap_or_default();
    results
        .iter()
        .map(|result| {
            let errors = result.errors();
            let rate = convergence_rate(&errors);
            let relative = samples_relative_to_mc(&errors, &mc);
            (result.name.clone(), errors, rate, relative)
        })
        .collect()
}

fn write_outputs(
    output: &Path,
    summary: &Summary,
    methods: &[Method],
    results: &[MethodResult],
) -> Result<(), CliError> {
    let rows = table_rows(results);
    let counts: Vec<u64> = rows
        .first()
        .map(|row| row.1.iter().map(|(count, _)| *count).collect())
        .unwrap_or_default();
    // Markdown.
    let mut markdown = format!(
        "# Kollig & Keller, Sect. 6: BDPT error against the master\n\n\
         Scene `{}` at {}x{}, k_max = {} segments, eye connections {}; master {} spp \
         (independent, {:.1} s; its mean variance {} is subtracted from every MSE); \
         {} seeds per randomized method. Started {}.\n\nCommand: `{}`\n\n",
        summary.scene,
        summary.resolution[0],
        summary.resolution[1],
        summary.max_depth,
        if summary.skip_eye_connections {
            "omitted"
        } else {
            "used"
        },
        summary.master_spp,
        summary.master_seconds,
        format_significant(summary.master_variance, 3),
        summary.seeds,
        summary.started,
        summary.command
    );
    markdown.push_str("| method | rate | samples relative to MC |");
    for count in &counts {
        markdown.push_str(&format!(" n={count} |"));
    }
    markdown.push_str("\n|---|---|---|");
    markdown.push_str(&"---|".repeat(counts.len()));
    markdown.push('\n');
    for (name, errors, rate, relative) in &rows {
        markdown.push_str(&format!(
            "| {name} | {} | {} |",
            format_significant(*rate, 3),
            if relative.is_finite() {
                format!("{:.0} %", 100.0 * relative)
            } else {
                "n/a".into()
            }
        ));
        for (_, error) in errors {
            markdown.push_str(&format!(" {} |", format_significant(*error, 4)));
        }
        markdown.push('\n');
    }
    let table_md = output.join("table.md");
    std::fs::write(&table_md, &markdown).map_err(|error| write_failure(&table_md, error))?;

    // JSON: everything the tables are computed from.
    let json = Json::object(vec![
        ("scene", Json::String(summary.scene.clone())),
        (
            "resolution",
            Json::integers(&summary.resolution.map(|value| value as u64)),
        ),
        ("max_depth", Json::Integer(u64::from(summary.max_depth))),
        (
            "skip_eye_connections",
            Json::Bool(summary.skip_eye_connections),
        ),
        ("master_spp", Json::Integer(summary.master_spp)),
        ("master_variance", Json::Number(summary.master_variance)),
        ("seeds", Json::Integer(summary.seeds)),
        ("command", Json::String(summary.command.clone())),
        (
            "methods",
            Json::Array(
                rows.iter()
                    .zip(results)
                    .map(|((name, errors, rate, relative), result)| {
                        let method = methods.iter().find(|method| method.name == name);
                        Json::object(vec![
                            ("name", Json::String(name.clone())),
                            (
                                "sampler",
                                Json::String(method.map_or("", |m| m.sampler.name()).into()),
                            ),
                            (
                                "pattern_size",
                                method
                                    .and_then(|m| m.pattern_size)
                                    .map_or(Json::Integer(0), Json::Integer),
                            ),
                            ("rate", Json::Number(*rate)),
                            ("fit_scale", Json::Number(power_law_fit(errors).0)),
                            ("samples_relative_to_mc", Json::Number(*relative)),
                            (
                                "counts",
                                Json::integers(
                                    &errors.iter().map(|(count, _)| *count).collect::<Vec<_>>(),
                                ),
                            ),
                            (
                                "errors",
                                Json::numbers(
                                    &errors.iter().map(|(_, error)| *error).collect::<Vec<_>>(),
                                ),
                            ),
                            (
                                "squared_errors_per_seed",
                                Json::Array(
                                    result
                                        .squared_errors
                                        .iter()
                                        .map(|(_, squares)| Json::numbers(squares))
                                        .collect(),
                                ),
                            ),
                        ])
                    })
                    .collect(),
            ),
        ),
    ]);
    let table_json = output.join("table.json");
    std::fs::write(&table_json, json.render())
        .map_err(|error| write_failure(&table_json, error))?;

    // Figs. 7 and 8: error against samples, log–log.
    let curves: Vec<ErrorCurve> = rows
        .iter()
        .map(|(name, errors, _, _)| ErrorCurve {
            label: name.clone(),
            points: errors
                .iter()
                .map(|&(count, error)| ErrorPoint {
                    x: count as f64,
                    median: error,
                    min: error,
                    max: error,
                })
                .collect(),
        })
        .collect();
    write_error_plot(
        &output.join("convergence.svg"),
        &output.join("convergence.png"),
        &format!("BDPT, {}: L2 error against the master", summary.scene),
        "samples per pixel and technique",
        "L2 error (RMS over seeds)",
        &curves,
    )?;
    // Fig. 9: samples needed relative to MC.
    let bars: Vec<(String, f64)> = rows
        .iter()
        .filter(|(name, _, _, relative)| name != "mc" && relative.is_finite())
        .map(|(name, _, _, relative)| (name.clone(), *relative))
        .collect();
    super::error_plot::write_bar_plot(
        &output.join("samples-relative-to-mc.svg"),
        &output.join("samples-relative-to-mc.png"),
        &format!(
            "BDPT, {}: samples for MC's error, relative to MC",
            summary.scene
        ),
        "samples relative to MC",
        &bars,
    )?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rates_and_relative_samples_of_power_laws() {
        let mc: Vec<(u64, f64)> = [1u64, 2, 4, 8, 16, 32]
            .iter()
            .map(|&n| (n, (n as f64).powf(-0.5)))
            .collect();
        assert!((convergence_rate(&mc) + 0.5).abs() < 1e-12);
        // Half MC's error at every n: a quarter of the samples.
        let better: Vec<(u64, f64)> = mc.iter().map(|&(n, e)| (n, 0.5 * e)).collect();
        let relative = samples_relative_to_mc(&better, &mc);
        assert!((relative - 0.25).abs() < 1e-9, "{relative}");
        assert!((samples_relative_to_mc(&mc, &mc) - 1.0).abs() < 1e-12);
        // A faster rate: e = n^-0.75 reaches n^-0.5 at n^(2/3); over the
        // counts 1 … 32 the geometric mean of n^(2/3) / n is 32^(-1/6).
        let faster: Vec<(u64, f64)> = mc
            .iter()
            .map(|&(n, _)| (n, (n as f64).powf(-0.75)))
            .collect();
        let relative = samples_relative_to_mc(&faster, &mc);
        assert!(
            (relative - 32f64.powf(-1.0 / 6.0)).abs() < 1e-9,
            "{relative}"
        );
    }

    #[test]
    fn pattern_sizes_follow_the_count() {
        let padded = Method::ALL
            .iter()
            .find(|method| method.name == "rqmc-padded-16")
            .unwrap();
        assert_eq!(padded.pattern_size_at(4), Some(4));
        assert_eq!(padded.pattern_size_at(64), Some(16));
        let halton = Method::ALL[1];
        assert_eq!(halton.pattern_size_at(64), None);
        assert!(!halton.randomized);
    }
}
