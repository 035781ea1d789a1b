//! The arguments of `lqmc render`: the scene and integrator, sampling,
//! replications and output, and the integrators' own option groups
//! ([`crate::integrator_options`]).

use crate::integrator_options::{IntegratorArgs, PathArgs, PathTracerArgs};
use crate::named_values::NamedValues;
use clap::Args;
use render::integrators::IntegratorKind;
use render::replication::{ErrorMeasure, PixelRegion};
use render::sampler::{Randomization, SamplerKind};
use std::path::PathBuf;

/// Help headings of the general option groups.
mod headings {
    pub const SAMPLING: &str = "Sampling options";
    pub const REPLICATIONS: &str = "Replication options";
    pub const OUTPUT: &str = "Output options";
}

/// The integrators by name, each with its help line, from the renderer's
/// registry.
pub fn integrator_names() -> NamedValues<IntegratorKind> {
    NamedValues::with_help(IntegratorKind::ALL, IntegratorKind::help)
}

/// The samplers by name, each with its help line, from the renderer's
/// table.
fn sampler_names() -> NamedValues<SamplerKind> {
    NamedValues::with_help(SamplerKind::ALL, SamplerKind::help)
}

/// The randomizations by name, each with its help line, from the
/// renderer's table.
fn randomization_names() -> NamedValues<Randomization> {
    NamedValues::with_help(Randomization::ALL, Randomization::help)
}

/// Arguments of `lqmc render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene: a Mitsuba 3 XML (`.xml`) or pbrt-v4 (`.pbrt`) file, or
    /// `builtin:NAME` (see `lqmc scenes`); default builtin:cornell-box.
    pub scene: Option<String>,
    /// The integrator (default: volpath for scenes with participating
    /// media, light for Mitsuba files that ask for `ptracer`, else path).
    #[arg(long, value_name = "NAME", value_parser = integrator_names())]
    pub integrator: Option<IntegratorKind>,
    /// Worker threads (default: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Image resolution WxH (default: the scene's).
    #[arg(long, value_parser = crate::points_command::parse_pair)]
    pub resolution: Option<(u32, u32)>,
    /// A scene-file parameter, NAME=VALUE (Mitsuba's `$NAME`, as
    /// `mitsuba -D`); may be repeated.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_definition)]
    pub define: Vec<(String, String)>,
    /// The sampler.
    #[arg(long, value_name = "SAMPLER", value_parser = sampler_names(), default_value = "halton", help_heading = headings::SAMPLING)]
    pub sampler: SamplerKind,
    /// Samples per pixel (default: the scene's suggestion, else 16).
    #[arg(long, help_heading = headings::SAMPLING)]
    pub spp: Option<u64>,
    /// Render for this many seconds (with --spp: at most that many samples).
    #[arg(long, value_name = "SECONDS", help_heading = headings::SAMPLING)]
    pub time: Option<f64>,
    /// Each pixel's samples are independent replications of this many
    /// points (Kollig & Keller's m), one per pass; the EXR's variance layer
    /// is then estimated from them (Eq. 6). Samplers: independent, sobol,
    /// lattice, hammersley, padded, latin-supercube.
    #[arg(long, value_name = "M", help_heading = headings::SAMPLING)]
    pub pattern_size: Option<u64>,
    /// Seed of every random choice; with the default `--randomize seeded`
    /// also of the sampler's randomization (different seeds give
    /// independent renders with every sampler).
    #[arg(long, default_value_t = 0, help_heading = headings::SAMPLING)]
    pub seed: u64,
    /// Whether the seed randomizes the QMC samplers: `seeded` (Halton's
    /// digital shifts, Sobol's Owen scrambles and the lattice's shifts keyed
    /// by the seed) or `none` (the deterministic sequences: Halton as in the
    /// LQMC paper; the seed reaches only pseudo-random numbers).
    #[arg(long, value_name = "RANDOMIZE", value_parser = randomization_names(), default_value = "seeded", help_heading = headings::SAMPLING)]
    pub randomize: Randomization,
    /// Render R independent replications (whole renders whose seeds
    /// derive from --seed), each of spp / R samples per pixel, and write
    /// their mean with the variance of the mean from their spread; works
    /// for every integrator and sampler. With --pattern-size: Kollig &
    /// Keller's replications inside one render, spp = R × the pattern size.
    #[arg(long, value_name = "R", help_heading = headings::REPLICATIONS)]
    pub replications: Option<u64>,
    /// Render only replication I (0 ≤ I < R) of the R replications
    /// `--replications R` would render: spp / R samples per pixel with
    /// replication I's seed, to an EXR file that `lqmc merge` combines
    /// with the others (a farm's array job).
    #[arg(long, value_name = "I/R", value_parser = crate::replications::parse_replication, help_heading = headings::REPLICATIONS)]
    pub replication: Option<(u64, u64)>,
    /// Render replications (of spp / R samples per pixel, R from
    /// --replications, default 4, the least rendered) until the estimated
    /// relative standard error of the image's mean luminance (or of
    /// --target-region's) is at most E (0.01 is 1 %), or --time runs out.
    #[arg(long, value_name = "E", help_heading = headings::REPLICATIONS)]
    pub target_error: Option<f64>,
    /// The pixels whose mean luminance the error is measured over:
    /// x,y,width,height (default: the whole image).
    #[arg(long, value_name = "X,Y,W,H", value_parser = crate::replications::parse_region, help_heading = headings::REPLICATIONS)]
    pub target_region: Option<PixelRegion>,
    /// With --target-error: render at most this many replications
    /// (default 1000).
    #[arg(long, value_name = "N", help_heading = headings::REPLICATIONS)]
    pub max_replications: Option<u64>,
    /// The error --target-error stops on: `mean` (the relative standard
    /// error of the region's mean luminance; default) or `rmse` (the
    /// expected relative RMSE of the region's pixels, the per-pixel noise).
    #[arg(long, value_name = "mean|rmse", value_parser = NamedValues::new(ErrorMeasure::ALL), help_heading = headings::REPLICATIONS)]
    pub error_measure: Option<ErrorMeasure>,
    /// Output image (.exr, .pfm or .png); a PNG is also written beside an
    /// EXR or PFM.
    #[arg(short, long, default_value = "render.exr", help_heading = headings::OUTPUT)]
    pub output: PathBuf,
    /// Exposure of the PNG in stops.
    #[arg(long, default_value_t = 0.0, help_heading = headings::OUTPUT)]
    pub exposure: f32,
    /// Print nothing but errors: no progress bar, no report, no warnings.
    #[arg(long, help_heading = headings::OUTPUT)]
    pub quiet: bool,
    /// Show the image in the viewer tev while it renders, over tev's TCP
    /// protocol (`--tev` alone: tev's default address, 127.0.0.1:14158).
    #[arg(long, value_name = "HOST:PORT", num_args = 0..=1, default_missing_value = crate::tev::DEFAULT_ADDRESS, help_heading = headings::OUTPUT)]
    pub tev: Option<String>,
    #[command(flatten)]
    pub path: PathArgs,
    #[command(flatten)]
    pub path_tracer: PathTracerArgs,
    #[command(flatten)]
    pub integrators: IntegratorArgs,
}

/// Parses `NAME=VALUE` of `--define`.
pub fn parse_definition(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, value)) if !name.is_empty() => Ok((name.to_string(), value.to_string())),
        _ => Err(format!("expected NAME=VALUE, got '{text}'")),
    }
}
