//! `lqmc render` and `lqmc scenes`: render a scene to EXR and PNG.

/// Prints a line to stdout, ignoring a closed pipe (e.g. `| head`): results
/// are already written to files or complete, so there is nothing to report.
macro_rules! say {
    ($($argument:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($argument)*);
    }};
}

use crate::error::{CliError, usage};
use crate::replications::{ReplicationOptions, ReplicationRequest, replication_request};
use clap::{Args, ValueEnum};
use indicatif::{ProgressBar, ProgressStyle};
use render::image::{Metadata, write_png};
use render::integrators::{IntegratorKind, IntegratorSettings, MisHeuristic};
use render::renderer::{RenderSettings, RenderStatistics, render_observed};
use render::sampler::{Randomization, SamplerKind};
use render::scene::Scene;
use render::scene::builtin::{BUILTIN_SCENES, DEFAULT_SCENE, builtin_scene};
use render::scene::description::SceneDescription;
use render::scene::loader::{LoadOptions, load_scene_file};
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

/// The integrators, as command-line values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum IntegratorName {
    /// Path tracing with next-event estimation and MIS.
    Path,
    /// Volumetric path tracing (participating media).
    Volpath,
    /// Local quasi-Monte Carlo exploration (Halton-seeded path tracing).
    Lqmc,
    /// Light tracing: paths from the lights connected to the camera.
    Light,
    /// Bidirectional path tracing (every connection of a camera and a light
    /// subpath, balance heuristic by default).
    Bdpt,
    /// Primary-sample-space Metropolis light transport (Kelemen et al.
    /// 2002) over path tracing or BDPT (--mlt-base).
    Pssmlt,
    /// Energy redistribution path tracing (Cline et al. 2005): path-traced
    /// seeds, short Metropolis chains from each.
    Erpt,
    /// Multiplexed Metropolis light transport (Hachisuka et al. 2014):
    /// chains per path depth, one BDPT strategy per sample.
    Mmlt,
    /// Vertex connection and merging (Georgiev et al. 2012): BDPT and
    /// progressive photon mapping under one MIS (--vcm-mode).
    Vcm,
}

impl IntegratorName {
    /// The renderer's integrator of this name.
    pub fn kind(self) -> IntegratorKind {
        match self {
            IntegratorName::Path => IntegratorKind::Path,
            IntegratorName::Volpath => IntegratorKind::VolPath,
            IntegratorName::Lqmc => IntegratorKind::Lqmc,
            IntegratorName::Light => IntegratorKind::Light,
            IntegratorName::Bdpt => IntegratorKind::Bdpt,
            IntegratorName::Pssmlt => IntegratorKind::Pssmlt,
            IntegratorName::Erpt => IntegratorKind::Erpt,
            IntegratorName::Mmlt => IntegratorKind::Mmlt,
            IntegratorName::Vcm => IntegratorKind::Vcm,
        }
    }
}

/// The samplers, as command-line values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum SamplerName {
    /// Faure-permuted Halton, per-pixel enumeration (LQMC's).
    Halton,
    /// Owen-scrambled Sobol per pixel.
    Sobol,
    /// Independent random numbers (SplitMix64 of the pixel sample and dimension).
    Independent,
    /// Randomized rank-1 lattice (CBC, N = spp rounded up to a power of two).
    Lattice,
    /// The image-wide Sobol sequence, a consecutive block per pixel
    /// (Owen-scrambled by the seed unless --randomize none).
    GlobalSobol,
    /// The image-wide Niederreiter sequence (base 2), a consecutive block
    /// per pixel (Owen-scrambled by the seed unless --randomize none).
    GlobalNiederreiter,
    /// Faure-scrambled Hammersley set of --pattern-size points (else spp),
    /// a Cranley–Patterson rotation per pixel and replication.
    Hammersley,
    /// Padded replications of the 2-D Hammersley pattern (Kollig & Keller).
    Padded,
    /// Latin supercube samples of the 2-D Hammersley pattern (unshifted
    /// with --randomize none).
    LatinSupercube,
}

impl SamplerName {
    /// The renderer's sampler of this name.
    pub fn kind(self) -> SamplerKind {
        match self {
            SamplerName::Halton => SamplerKind::Halton,
            SamplerName::Sobol => SamplerKind::Sobol,
            SamplerName::Independent => SamplerKind::Independent,
            SamplerName::Lattice => SamplerKind::Lattice,
            SamplerName::GlobalSobol => SamplerKind::GlobalSobol,
            SamplerName::GlobalNiederreiter => SamplerKind::GlobalNiederreiter,
            SamplerName::Hammersley => SamplerKind::Hammersley,
            SamplerName::Padded => SamplerKind::Padded,
            SamplerName::LatinSupercube => SamplerKind::LatinSupercube,
        }
    }
}

/// Whether `--seed` randomizes the QMC samplers, as command-line values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum RandomizeName {
    /// The seed randomizes every sampler: Halton's digits get a random
    /// digital shift, Sobol's per-pixel Owen scrambles and the lattice's
    /// per-pixel shifts are keyed by it. Renders with different seeds are
    /// independent replications.
    Seeded,
    /// Deterministic QMC points: Faure-permuted Halton as in the LQMC
    /// paper, Sobol's and the lattice's per-pixel scrambles and shifts of
    /// seed 0; the seed changes only pseudo-random numbers.
    None,
}

/// The MIS heuristics, as command-line values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum HeuristicName {
    Power,
    Balance,
}

/// Arguments of `lqmc render`.
#[derive(Args, Debug)]
pub struct RenderArgs {
    /// The scene: a Mitsuba 3 XML (`.xml`) or pbrt-v4 (`.pbrt`) file, or
    /// `builtin:NAME` (see `lqmc scenes`); default builtin:cornell-box.
    pub scene: Option<String>,
    /// The integrator (default: volpath for scenes with participating
    /// media, else path).
    #[arg(long, value_enum)]
    pub integrator: Option<IntegratorName>,
    /// The sampler.
    #[arg(long, value_enum, default_value_t = SamplerName::Halton)]
    pub sampler: SamplerName,
    /// Samples per pixel (default: the scene's suggestion, else 16).
    #[arg(long)]
    pub spp: Option<u64>,
    /// Render for this many seconds (with --spp: at most that many samples).
    #[arg(long, value_name = "SECONDS")]
    pub time: Option<f64>,
    /// Each pixel's samples are independent replications of this many
    /// points (Kollig & Keller's m), one per pass; the EXR's variance layer
    /// is then estimated from them (Eq. 6). Samplers: independent, sobol,
    /// lattice, hammersley, padded, latin-supercube.
    #[arg(long, value_name = "M")]
    pub pattern_size: Option<u64>,
    /// Render R independent replications (whole renders whose seeds
    /// derive from --seed), each of spp / R samples per pixel, and write
    /// their mean with the variance of the mean from their spread; works
    /// for every integrator and sampler. With --pattern-size: Kollig &
    /// Keller's replications inside one render, spp = R × the pattern size.
    #[arg(long, value_name = "R")]
    pub replications: Option<u64>,
    /// Render only replication I (0 ≤ I < R) of the R replications
    /// `--replications R` would render: spp / R samples per pixel with
    /// replication I's seed, to an EXR file that `lqmc merge` combines
    /// with the others (a farm's array job).
    #[arg(long, value_name = "I/R", value_parser = crate::replications::parse_replication)]
    pub replication: Option<(u64, u64)>,
    /// Render replications (of spp / R samples per pixel, R from
    /// --replications, default 4, the least rendered) until the estimated
    /// relative standard error of the image's mean luminance (or of
    /// --target-region's) is at most E (0.01 is 1 %), or --time runs out.
    #[arg(long, value_name = "E")]
    pub target_error: Option<f64>,
    /// The pixels whose mean luminance the error is measured over:
    /// x,y,width,height (default: the whole image).
    #[arg(long, value_name = "X,Y,W,H", value_parser = crate::replications::parse_region)]
    pub target_region: Option<[usize; 4]>,
    /// With --target-error: render at most this many replications
    /// (default 1000).
    #[arg(long, value_name = "N")]
    pub max_replications: Option<u64>,
    /// The error --target-error stops on: `mean` (the relative standard
    /// error of the region's mean luminance; default) or `rmse` (the
    /// expected relative RMSE of the region's pixels, the per-pixel noise).
    #[arg(long, value_name = "mean|rmse")]
    pub error_measure: Option<String>,
    /// Seed of every random choice; with the default `--randomize seeded`
    /// also of the sampler's randomization (different seeds give
    /// independent renders with every sampler).
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Whether the seed randomizes the QMC samplers: `seeded` (Halton's
    /// digital shifts, Sobol's Owen scrambles and the lattice's shifts keyed
    /// by the seed) or `none` (the deterministic sequences: Halton as in the
    /// LQMC paper; the seed reaches only pseudo-random numbers).
    #[arg(long, value_enum, default_value_t = RandomizeName::Seeded)]
    pub randomize: RandomizeName,
    /// Worker threads (default: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Image resolution WxH (default: the scene's).
    #[arg(long, value_parser = crate::points_command::parse_pair)]
    pub resolution: Option<(u32, u32)>,
    /// Maximum path depth in segments, Mitsuba's convention: 1 shows emitters
    /// only, 2 adds direct light (default: the scene's, else 6).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// bdpt: leave out the strategies that connect light subpath vertices
    /// to the camera (light tracing, t = 1), as Kollig & Keller do for
    /// OFFICE.
    #[arg(long)]
    pub bdpt_skip_eye_connections: bool,
    /// bdpt: write one weighted image per strategy to DIR/s{s}_t{t}.exr
    /// (s light and t camera vertices; they sum to the image), as pbrt-v4's
    /// `visualizestrategies`.
    #[arg(long, value_name = "DIR")]
    pub strategy_images: Option<PathBuf>,
    /// Multiple importance sampling heuristic (default: balance for bdpt,
    /// as Kollig & Keller use; power for the others, as pbrt-v4 and
    /// Mitsuba).
    #[arg(long, value_enum)]
    pub mis: Option<HeuristicName>,
    /// The path depth from which Russian roulette may end paths, Mitsuba's
    /// `rr_depth` convention (default: the scene's — a Mitsuba file's
    /// `rr_depth`, 5 if it names none — else 3).
    #[arg(long, value_name = "DEPTH")]
    pub rr_depth: Option<u32>,
    /// path, volpath: place each sample uniformly in its pixel and splat it
    /// over the pixels of the scene's filter (Mitsuba's film) instead of
    /// importance-sampling the filter (pbrt-v4's, the default); LQMC always
    /// splats, so this is its like-for-like baseline.
    #[arg(long)]
    pub splat_film: bool,
    /// Output image (.exr, .pfm or .png); a PNG is also written beside an
    /// EXR or PFM.
    #[arg(short, long, default_value = "render.exr")]
    pub output: PathBuf,
    /// Exposure of the PNG in stops.
    #[arg(long, default_value_t = 0.0)]
    pub exposure: f32,
    /// No progress bar.
    #[arg(long)]
    pub quiet: bool,
    /// Show the image in the viewer tev while it renders, over tev's TCP
    /// protocol (`--tev` alone: tev's default address, 127.0.0.1:14158).
    #[arg(long, value_name = "HOST:PORT", num_args = 0..=1, default_missing_value = crate::tev::DEFAULT_ADDRESS)]
    pub tev: Option<String>,
    /// A scene-file parameter, NAME=VALUE (Mitsuba's `$NAME`, as
    /// `mitsuba -D`); may be repeated.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_definition)]
    pub define: Vec<(String, String)>,
    #[command(flatten)]
    pub lqmc: LqmcArgs,
    #[command(flatten)]
    pub mlt: MltArgs,
    #[command(flatten)]
    pub vcm: VcmArgs,
}

/// Options of vertex connection and merging (defaults SmallVCM's; see
/// `render::integrators::vcm`).
#[derive(Args, Debug, Default)]
pub struct VcmArgs {
    /// vcm: the techniques, `vcm` (connections and merges; default), `bpt`
    /// (connections only), `bpm` (merges with MIS) or `ppm` (merges at the
    /// first non-specular vertex, no MIS).
    #[arg(long, value_name = "vcm|bpt|bpm|ppm")]
    pub vcm_mode: Option<String>,
    /// vcm: the first iteration's merging radius as a fraction of the
    /// scene's bounding-sphere radius (default 0.003).
    #[arg(long, value_name = "FRACTION")]
    pub vcm_radius: Option<f32>,
    /// vcm: the radius reduction's alpha, r_i = r_1 i^((alpha-1)/2), in
    /// (0, 1] (default 0.75).
    #[arg(long, value_name = "ALPHA")]
    pub vcm_alpha: Option<f32>,
}

impl VcmArgs {
    /// Whether any option is given.
    pub fn any(&self) -> bool {
        self.vcm_mode.is_some() || self.vcm_radius.is_some() || self.vcm_alpha.is_some()
    }
}

/// VCM's settings from the options.
pub fn vcm_settings(args: &VcmArgs) -> Result<render::integrators::vcm::VcmSettings, CliError> {
    use render::integrators::vcm::{VcmMode, VcmSettings};
    let mut settings = VcmSettings::default();
    if let Some(name) = &args.vcm_mode {
        settings.mode = VcmMode::from_name(name)
            .ok_or_else(|| usage(format!("--vcm-mode: `{name}` is not vcm, bpt, bpm or ppm")))?;
    }
    if let Some(fraction) = args.vcm_radius {
        if !(fraction > 0.0 && fraction.is_finite()) {
            return Err(usage(format!(
                "--vcm-radius must be a positive fraction, got {fraction}"
            )));
        }
        settings.radius_fraction = fraction;
    }
    if let Some(alpha) = args.vcm_alpha {
        if !(alpha > 0.0 && alpha <= 1.0) {
            return Err(usage(format!("--vcm-alpha must be in (0, 1], got {alpha}")));
        }
        settings.alpha = alpha;
    }
    Ok(settings)
}

/// Options of the Metropolis integrators (defaults: Kelemen et al. 2002,
/// pbrt-v4 and Mitsuba; see `render::integrators::pssmlt`).
#[derive(Args, Debug, Default)]
pub struct MltArgs {
    /// pssmlt: the path sampler the chains drive, `path` (the path tracer,
    /// volumetric in scenes with media; default) or `bdpt` (every BDPT
    /// strategy).
    #[arg(long, value_name = "path|bdpt")]
    pub mlt_base: Option<String>,
    /// Metropolis: the probability of a large step (default 0.3).
    #[arg(long, value_name = "P")]
    pub mlt_large_step: Option<f32>,
    /// Metropolis: the small-step kernel, `kelemen` (exponential, s1 =
    /// 1/1024, s2 = 1/64; default) or `gaussian` (pbrt-v4's, --mlt-sigma).
    #[arg(long, value_name = "kelemen|gaussian")]
    pub mlt_kernel: Option<String>,
    /// Metropolis: the Gaussian kernel's standard deviation (default 0.01).
    #[arg(long, value_name = "SIGMA")]
    pub mlt_sigma: Option<f32>,
    /// Metropolis: bootstrap samples for the normalisation and the chains'
    /// starts (default 100000).
    #[arg(long, value_name = "N")]
    pub mlt_bootstrap: Option<u64>,
    /// pssmlt: the number of chains (default 1000).
    #[arg(long, value_name = "N")]
    pub mlt_chains: Option<u64>,
    /// Metropolis: per-dimension factors on the small steps, `D=S` pairs
    /// (dimension of the layout, factor), comma-separated, e.g. `0=4,1=4`
    /// for steps four times larger on the image plane (ERPT's steps per
    /// dimension, as the LQMC paper matches them to its tiles).
    #[arg(long, value_name = "D=S,...")]
    pub mlt_step_scale: Option<String>,
    /// pssmlt over path: render the direct light (paths of 1 and 2
    /// segments) separately with the path tracer at N samples per pixel
    /// (the render's sampler), the chains only paths of 3 segments and more
    /// (Mitsuba's `directSamples`; default: off, the chains render all).
    #[arg(long, value_name = "N")]
    pub mlt_direct_spp: Option<u64>,
    /// erpt: mutations per chain (default 100, Mitsuba's).
    #[arg(long, value_name = "L")]
    pub erpt_chain_length: Option<u64>,
    /// erpt: chains per seed on average (default 1, Mitsuba's).
    #[arg(long, value_name = "C")]
    pub erpt_chains_per_sample: Option<f64>,
}

impl MltArgs {
    /// Whether any option is given.
    pub fn any(&self) -> bool {
        self.mlt_base.is_some()
            || self.mlt_large_step.is_some()
            || self.mlt_kernel.is_some()
            || self.mlt_sigma.is_some()
            || self.mlt_bootstrap.is_some()
            || self.mlt_chains.is_some()
            || self.mlt_step_scale.is_some()
            || self.mlt_direct_spp.is_some()
            || self.erpt_chain_length.is_some()
            || self.erpt_chains_per_sample.is_some()
    }
}

/// The mutation settings from the options, over `defaults`.
fn mutation_settings(
    args: &MltArgs,
    defaults: render::sampler::MutationSettings,
) -> Result<render::sampler::MutationSettings, CliError> {
    use render::sampler::SmallStep;
    let mut mutation = defaults;
    if let Some(probability) = args.mlt_large_step {
        if !(0.0..=1.0).contains(&probability) {
            return Err(usage(format!(
                "--mlt-large-step must be a probability in [0, 1], got {probability}"
            )));
        }
        mutation.large_step_probability = probability;
    }
    match args.mlt_kernel.as_deref() {
        None | Some("kelemen") => {
            if args.mlt_sigma.is_some() {
                return Err(usage("--mlt-sigma is for --mlt-kernel gaussian"));
            }
        }
        Some("gaussian") => {
            let sigma = args.mlt_sigma.unwrap_or(0.01);
            if !(sigma > 0.0 && sigma.is_finite()) {
                return Err(usage(format!("--mlt-sigma must be positive, got {sigma}")));
            }
            mutation.small_step = SmallStep::Gaussian { sigma };
        }
        Some(other) => {
            return Err(usage(format!(
                "--mlt-kernel: `{other}` is not kelemen or gaussian"
            )));
        }
    }
    if let Some(list) = &args.mlt_step_scale {
        for entry in list.split(',') {
            let parsed = entry.split_once('=').and_then(|(dimension, scale)| {
                Some((
                    dimension.trim().parse::<usize>().ok()?,
                    scale.trim().parse::<f32>().ok()?,
                ))
            });
            match parsed {
                Some((dimension, scale))
                    if dimension < 4096 && scale > 0.0 && scale.is_finite() =>
                {
                    if mutation.step_scales.len() <= dimension {
                        mutation.step_scales.resize(dimension + 1, 1.0);
                    }
                    mutation.step_scales[dimension] = scale;
                }
                _ => {
                    return Err(usage(format!(
                        "--mlt-step-scale: `{entry}` is not DIMENSION=FACTOR (a dimension below 4096, a positive factor)"
                    )));
                }
            }
        }
    }
    Ok(mutation)
}

/// `value` if it is at least 1 (a count given as `option`).
fn positive_count(value: Option<u64>, option: &str) -> Result<Option<u64>, CliError> {
    match value {
        Some(0) => Err(usage(format!("{option} must be at least 1"))),
        other => Ok(other),
    }
}

/// The chain options shared by pssmlt and mmlt (mutations, bootstrap,
/// chains) over `defaults`.
fn chain_settings(
    args: &MltArgs,
    defaults: render::integrators::markov_chain::ChainSettings,
) -> Result<render::integrators::markov_chain::ChainSettings, CliError> {
    let mut chains = defaults;
    chains.mutation = mutation_settings(args, chains.mutation)?;
    if let Some(count) = positive_count(args.mlt_bootstrap, "--mlt-bootstrap")? {
        chains.bootstrap_samples = count;
    }
    if let Some(count) = positive_count(args.mlt_chains, "--mlt-chains")? {
        chains.chains = count;
    }
    Ok(chains)
}

/// MMLT's settings from the options.
pub fn mmlt_settings(args: &MltArgs) -> Result<render::integrators::mmlt::MmltSettings, CliError> {
    if args.mlt_base.is_some() || args.mlt_direct_spp.is_some() {
        return Err(usage(
            "--mlt-base and --mlt-direct-spp are for pssmlt (MMLT always runs over BDPT)",
        ));
    }
    if args.erpt_chain_length.is_some() || args.erpt_chains_per_sample.is_some() {
        return Err(usage("the --erpt-* options are for --integrator erpt"));
    }
    let mut settings = render::integrators::mmlt::MmltSettings::default();
    settings.chains = chain_settings(args, settings.chains)?;
    Ok(settings)
}

/// ERPT's settings from the options.
pub fn erpt_settings(args: &MltArgs) -> Result<render::integrators::erpt::ErptSettings, CliError> {
    let mut settings = render::integrators::erpt::ErptSettings::default();
    if args.mlt_base.is_some() || args.mlt_chains.is_some() || args.mlt_direct_spp.is_some() {
        return Err(usage(
            "--mlt-base, --mlt-chains and --mlt-direct-spp are for pssmlt (ERPT's seeds are path-traced; --erpt-chains-per-sample sets its chains)",
        ));
    }
    settings.mutation = mutation_settings(args, settings.mutation)?;
    if let Some(count) = positive_count(args.mlt_bootstrap, "--mlt-bootstrap")? {
        settings.bootstrap_samples = count;
    }
    if let Some(length) = positive_count(args.erpt_chain_length, "--erpt-chain-length")? {
        settings.chain_length = length;
    }
    if let Some(chains) = args.erpt_chains_per_sample {
        if !(chains > 0.0 && chains.is_finite()) {
            return Err(usage(format!(
                "--erpt-chains-per-sample must be positive, got {chains}"
            )));
        }
        settings.chains_per_sample = chains;
    }
    Ok(settings)
}

/// PSSMLT's settings from the options.
pub fn pssmlt_settings(
    args: &MltArgs,
) -> Result<render::integrators::pssmlt::PssmltSettings, CliError> {
    use render::integrators::pssmlt::{MltBase, PssmltSettings};
    let mut settings = PssmltSettings::default();
    if let Some(name) = &args.mlt_base {
        settings.base = MltBase::ALL
            .iter()
            .find(|(_, known)| known == name)
            .map(|(base, _)| *base)
            .ok_or_else(|| usage(format!("--mlt-base: `{name}` is not path or bdpt")))?;
    }
    if args.erpt_chain_length.is_some() || args.erpt_chains_per_sample.is_some() {
        return Err(usage("the --erpt-* options are for --integrator erpt"));
    }
    if let Some(spp) = positive_count(args.mlt_direct_spp, "--mlt-direct-spp")? {
        if settings.base != MltBase::Path {
            return Err(usage("--mlt-direct-spp is for --mlt-base path"));
        }
        settings.direct_samples_per_pixel = Some(spp);
    }
    settings.chains = chain_settings(args, settings.chains)?;
    Ok(settings)
}

/// Options of `--integrator lqmc` (defaults: the paper's and the authors'
/// renderer's; see `render::integrators::lqmc::settings`).
#[derive(Args, Debug, Default)]
pub struct LqmcArgs {
    /// LQMC: explored effects, a comma-separated list of aperture,
    /// wavelength, time, image, direction (default
    /// aperture,wavelength,image,direction).
    #[arg(long, value_name = "LIST")]
    pub explore: Option<String>,
    /// LQMC: the breakup vertex, a number (0: the camera), `k` for the
    /// full path (the light vertex sampled again) or `cdf` for the
    /// roughness CDF (default cdf, which includes b = k).
    #[arg(long, value_name = "B|k|cdf")]
    pub breakup: Option<String>,
    /// LQMC: lattice size N ∈ {7, 23, 97, 313} of a class (normal, caustic,
    /// dof, nee), e.g. `normal=23`; may be repeated.
    #[arg(long, value_name = "CLASS=N")]
    pub lattice_size: Vec<String>,
    /// LQMC: tiles per lens dimension of a class, e.g. `caustic=4`.
    #[arg(long, value_name = "CLASS=K")]
    pub aperture_tiles: Vec<String>,
    /// LQMC: tiles across the image width of a class, e.g. `normal=24`.
    #[arg(long, value_name = "CLASS=K")]
    pub image_tiles: Vec<String>,
    /// LQMC: tiles per outgoing-direction dimension of a class.
    #[arg(long, value_name = "CLASS=K")]
    pub direction_tiles: Vec<String>,
    /// LQMC: tiles per wavelength dimension (default 1).
    #[arg(long, value_name = "K")]
    pub wavelength_tiles: Option<u32>,
    /// LQMC: tiles per time dimension (default 1).
    #[arg(long, value_name = "K")]
    pub time_tiles: Option<u32>,
    /// LQMC: tiles across the image width when the camera is inside a
    /// medium, for every class (default 12).
    #[arg(long, value_name = "K")]
    pub medium_image_tiles: Option<u32>,
    /// LQMC: a class whose paths are splatted without exploration; may be
    /// repeated.
    #[arg(long, value_name = "CLASS")]
    pub skip_class: Vec<String>,
    /// LQMC: a class to explore that is not explored by default (normal,
    /// dof, nee; only caustic paths are explored by default, see README
    /// "LQMC at equal time"); may be repeated. `--explore-class normal
    /// --explore-class dof` gives the paper's classes.
    #[arg(long, value_name = "CLASS")]
    pub explore_class: Vec<String>,
    /// LQMC: also explore breakups whose only explored dimension is the
    /// wavelength (b = 0 with a pinhole camera).
    #[arg(long)]
    pub explore_wavelength_alone: bool,
    /// LQMC: also explore the camera vertex (b = 0) of paths whose first
    /// hit is in focus (not depth-of-field paths).
    #[arg(long)]
    pub explore_camera_in_focus: bool,
    /// LQMC: no tile jitter.
    #[arg(long)]
    pub no_jitter: bool,
    /// LQMC: no lattice dimension scrambling.
    #[arg(long)]
    pub no_scramble: bool,
    /// LQMC: print explorations per class, set sizes, failures and the
    /// closest-point search time.
    #[arg(long)]
    pub stats: bool,
    /// LQMC: write the sample density per class to this EXR (splatted
    /// members per pixel and sample: normal, caustic, depth of field as R,
    /// G, B; next-event paths in the layer `nee`), the paper's Fig. 11.
    #[arg(long, value_name = "FILE.exr")]
    pub density: Option<PathBuf>,
}

/// The LQMC class called `name`.
fn parse_class(name: &str) -> Result<render::integrators::lqmc::PathClass, CliError> {
    render::integrators::lqmc::PathClass::ALL
        .into_iter()
        .find(|class| class.name() == name)
        .ok_or_else(|| {
            usage(format!(
                "unknown LQMC class `{name}` (expected normal, caustic, dof or nee)"
            ))
        })
}

/// Parses `CLASS=VALUE`.
fn parse_class_value(
    option: &str,
    text: &str,
) -> Result<(render::integrators::lqmc::PathClass, u32), CliError> {
    let (name, value) = text
        .split_once('=')
        .ok_or_else(|| usage(format!("--{option}: expected CLASS=VALUE, got `{text}`")))?;
    let value: u32 = value
        .parse()
        .ok()
        .filter(|value| *value > 0)
        .ok_or_else(|| usage(format!("--{option}: `{value}` is not a positive integer")))?;
    Ok((parse_class(name)?, value))
}

/// The LQMC settings from the command line.
pub fn lqmc_settings(args: &LqmcArgs) -> Result<render::integrators::lqmc::LqmcSettings, CliError> {
    use render::integrators::lqmc::{BreakupChoice, ExploredEffects, LqmcSettings};
    let mut settings = LqmcSettings::default();
    if let Some(list) = &args.explore {
        settings.effects =
            ExploredEffects::parse(list).map_err(|error| usage(format!("--explore: {error}")))?;
    }
    if let Some(breakup) = &args.breakup {
        settings.breakup = if breakup == "cdf" {
            BreakupChoice::Roughness
        } else if breakup == "k" {
            BreakupChoice::FullPath
        } else {
            BreakupChoice::Fixed(breakup.parse().map_err(|_| {
                usage(format!(
                    "--breakup: expected a vertex number, `k` (the full path) or `cdf`, got `{breakup}`"
                ))
            })?)
        };
    }
    for text in &args.lattice_size {
        let (class, size) = parse_class_value("lattice-size", text)?;
        if !qmc::lattice_table::LQMC_LATTICE_SIZES.contains(&(size as u64)) {
            return Err(usage(format!(
                "--lattice-size: N must be one of 7, 23, 97, 313, got {size}"
            )));
        }
        settings.class_parameters_mut(class).lattice_size = size as u64;
    }
    for text in &args.aperture_tiles {
        let (class, tiles) = parse_class_value("aperture-tiles", text)?;
        settings.class_parameters_mut(class).aperture_tiles = tiles;
    }
    for text in &args.image_tiles {
        let (class, tiles) = parse_class_value("image-tiles", text)?;
        settings.class_parameters_mut(class).image_tiles = tiles;
    }
    for text in &args.direction_tiles {
        let (class, tiles) = parse_class_value("direction-tiles", text)?;
        settings.class_parameters_mut(class).direction_tiles = tiles;
    }
    for name in &args.explore_class {
        settings.class_parameters_mut(parse_class(name)?).explore = true;
    }
    for name in &args.skip_class {
        settings.class_parameters_mut(parse_class(name)?).explore = false;
    }
    settings.explore_wavelength_alone = args.explore_wavelength_alone;
    settings.explore_camera_in_focus = args.explore_camera_in_focus;
    if let Some(tiles) = args.wavelength_tiles {
        settings.wavelength_tiles = tiles.max(1);
    }
    if let Some(tiles) = args.time_tiles {
        settings.time_tiles = tiles.max(1);
    }
    if let Some(tiles) = args.medium_image_tiles {
        settings.medium_image_tiles = tiles.max(1);
    }
    settings.jitter_tiles = !args.no_jitter;
    settings.scramble_dimensions = !args.no_scramble;
    settings.gather_density = args.density.is_some();
    Ok(settings)
}

/// Parses `NAME=VALUE` of `--define`.
pub fn parse_definition(text: &str) -> Result<(String, String), String> {
    match text.split_once('=') {
        Some((name, value)) if !name.is_empty() => Ok((name.to_string(), value.to_string())),
        _ => Err(format!("expected NAME=VALUE, got '{text}'")),
    }
}

/// Runs `lqmc scenes`.
pub fn list_scenes() -> Result<(), CliError> {
    for (name, description) in BUILTIN_SCENES {
        say!("builtin:{name:<18} {description}");
    }
    Ok(())
}

/// Loads the scene SCENE names: `builtin:NAME`, or a Mitsuba 3 / pbrt-v4
/// file with the `-D` parameter `definitions`; `resolution` (WxH) replaces
/// the camera's. The loader's warnings go to stderr unless `quiet`.
pub fn load_scene_description(
    scene_name: &str,
    definitions: &[(String, String)],
    resolution: Option<(u32, u32)>,
    quiet: bool,
) -> Result<SceneDescription, CliError> {
    let mut description = match scene_name.strip_prefix("builtin:") {
        Some(name) => builtin_scene(name).ok_or_else(|| {
            let names: Vec<&str> = BUILTIN_SCENES.iter().map(|(n, _)| *n).collect();
            usage(format!(
                "unknown built-in scene '{name}' (known: {})",
                names.join(", ")
            ))
        })?,
        None if Path::new(scene_name).exists() => {
            let options = LoadOptions {
                parameters: definitions.to_vec(),
            };
            let loaded = load_scene_file(Path::new(scene_name), &options)
                .map_err(|error| usage(error.to_string()))?;
            for warning in &loaded.warnings {
                if !quiet {
                    eprintln!("lqmc: warning: {warning}");
                }
            }
            loaded.description
        }
        None => {
            return Err(usage(format!(
                "no scene '{scene_name}': not a file, and built-in scenes are named builtin:NAME (default builtin:{DEFAULT_SCENE})"
            )));
        }
    };
    if let Some((width, height)) = resolution {
        if width == 0 || height == 0 {
            return Err(usage("--resolution needs a width and height of at least 1"));
        }
        description.camera.resolution = [width, height];
    }
    Ok(description)
}

/// Builds the renderable scene of `description` (`scene_name` names it in
/// errors).
pub fn build_scene(scene_name: &str, description: &SceneDescription) -> Result<Scene, CliError> {
    Scene::build(description).map_err(|error| usage(format!("{scene_name}: {error}")))
}

/// The integrator `lqmc render` uses when none is named: volpath for scenes
/// with participating media, light tracing for Mitsuba files that ask for
/// `ptracer`, else path.
pub fn default_integrator(description: &SceneDescription, scene: &Scene) -> IntegratorKind {
    if scene.has_media() {
        IntegratorKind::VolPath
    } else if description.integrator.as_deref() == Some("ptracer") {
        // Mitsuba's light tracer.
        IntegratorKind::Light
    } else {
        IntegratorKind::Path
    }
}

/// The path tracer for `scene`: volpath where it has participating media,
/// else path (what "path tracing" means in comparisons and references).
pub fn default_path_tracer(scene: &Scene) -> IntegratorKind {
    if scene.has_media() {
        IntegratorKind::VolPath
    } else {
        IntegratorKind::Path
    }
}

/// The integrator `kind` with its settings; LQMC's come from `lqmc`, the
/// Metropolis integrators' from `mlt`.
pub fn integrator_settings(
    kind: IntegratorKind,
    lqmc: &LqmcArgs,
    mlt: &MltArgs,
    vcm: &VcmArgs,
) -> Result<IntegratorSettings, CliError> {
    if vcm.any() && kind != IntegratorKind::Vcm {
        return Err(usage(format!(
            "the --vcm-* options are for --integrator vcm, not {}",
            kind.name()
        )));
    }
    Ok(match kind {
        IntegratorKind::Vcm => IntegratorSettings::Vcm(vcm_settings(vcm)?),
        IntegratorKind::Lqmc => IntegratorSettings::Lqmc(lqmc_settings(lqmc)?),
        IntegratorKind::Pssmlt => IntegratorSettings::Pssmlt(pssmlt_settings(mlt)?),
        IntegratorKind::Erpt => IntegratorSettings::Erpt(erpt_settings(mlt)?),
        IntegratorKind::Mmlt => IntegratorSettings::Mmlt(mmlt_settings(mlt)?),
        other => other.into(),
    })
}

/// The MIS heuristic of an integrator when `--mis` names none: the balance
/// heuristic for BDPT (Kollig & Keller's) and VCM (SmallVCM's), the power
/// heuristic otherwise.
pub fn default_heuristic(kind: IntegratorKind) -> MisHeuristic {
    match kind {
        IntegratorKind::Bdpt | IntegratorKind::Vcm => MisHeuristic::Balance,
        _ => MisHeuristic::Power,
    }
}

/// A time budget in seconds from the option `option`: positive and finite.
pub fn parse_time_budget(option: &str, seconds: f64) -> Result<Duration, CliError> {
    if seconds > 0.0 && seconds.is_finite() {
        Ok(Duration::from_secs_f64(seconds))
    } else {
        Err(usage(format!(
            "{option} must be a positive number of seconds, got {seconds}"
        )))
    }
}

/// What one render is asked for on the command line; [`Self::settings`]
/// fills in the scene's suggestions and the defaults where it says nothing.
#[derive(Debug, Clone)]
pub struct RenderRequest {
    /// The integrator with its settings.
    pub integrator: IntegratorSettings,
    /// The sampler.
    pub sampler: SamplerKind,
    /// Points per replication, if each pixel's samples are replications.
    pub pattern_size: Option<u64>,
    /// Samples per pixel (default: unlimited with a time budget, else the
    /// scene's suggestion, else 16).
    pub samples_per_pixel: Option<u64>,
    /// Stop after this much time.
    pub time_budget: Option<Duration>,
    /// The seed of every random choice.
    pub seed: u64,
    /// Whether the seed randomizes the QMC samplers.
    pub randomization: Randomization,
    /// Maximum path depth (default: the scene's, else 6).
    pub max_depth: Option<u32>,
    /// Russian roulette depth (default: the scene's, else 3).
    pub russian_roulette_depth: Option<u32>,
    /// The MIS heuristic.
    pub heuristic: MisHeuristic,
    /// path, volpath: splat each sample over its filter's pixels.
    pub splat_film: bool,
    /// Worker threads (0: all cores).
    pub threads: usize,
}

impl RenderRequest {
    /// The renderer's settings for `scene`.
    pub fn settings(&self, scene: &Scene) -> RenderSettings {
        let samples_per_pixel = match (self.samples_per_pixel, self.time_budget) {
            (Some(spp), _) => spp,
            // As good as unlimited: the time budget ends the render.
            (None, Some(_)) => u64::MAX / (1 << 32),
            (None, None) => scene.samples_per_pixel.unwrap_or(16),
        };
        RenderSettings {
            integrator: self.integrator.clone(),
            sampler: self.sampler,
            pattern_size: self.pattern_size,
            samples_per_pixel,
            time_budget: self.time_budget,
            seed: self.seed,
            randomization: self.randomization,
            max_depth: self.max_depth.or(scene.max_depth).unwrap_or(6),
            heuristic: self.heuristic,
            russian_roulette_depth: self
                .russian_roulette_depth
                .or(scene.russian_roulette_depth)
                .unwrap_or(3),
            splat_film: self.splat_film,
            threads: self.threads,
            ..RenderSettings::default()
        }
    }
}

/// The metadata `lqmc render` writes into its images: integrator, sampler,
/// whole passes (`spp`), seed, randomization, render time, scene and depths.
pub fn render_metadata(
    scene_name: &str,
    settings: &RenderSettings,
    statistics: &RenderStatistics,
) -> Metadata {
    let seconds = statistics.elapsed.as_secs_f64().max(1e-9);
    let mut metadata = Metadata::new();
    metadata.insert("integrator".into(), settings.integrator.name().into());
    metadata.insert("sampler".into(), settings.sampler.name().into());
    metadata.insert(
        "spp".into(),
        statistics.completed_samples_per_pixel.to_string(),
    );
    metadata.insert("seed".into(), settings.seed.to_string());
    if settings.splat_film {
        metadata.insert("film".into(), "splat".into());
    }
    metadata.insert("randomization".into(), settings.randomization.name().into());
    if let Some(pattern_size) = settings.pattern_size {
        metadata.insert("patternSize".into(), pattern_size.to_string());
        metadata.insert(
            "replications".into(),
            (statistics.completed_samples_per_pixel / pattern_size).to_string(),
        );
    }
    metadata.insert("renderTimeSeconds".into(), format!("{seconds:.3}"));
    metadata.insert("scene".into(), scene_name.to_string());
    metadata.insert("maxDepth".into(), settings.max_depth.to_string());
    metadata.insert(
        "rrDepth".into(),
        settings.russian_roulette_depth.to_string(),
    );
    if let Some(memory) = statistics.memory {
        metadata.insert(
            "peakResidentBytes".into(),
            memory.peak_resident_bytes.to_string(),
        );
        metadata.insert(
            "residentBytesAtStart".into(),
            memory.resident_bytes_at_start.to_string(),
        );
    }
    metadata
}

/// Pixel samples traced per pixel, a partial last pass included (the
/// metadata's `spp` counts the whole passes).
pub fn traced_samples_per_pixel(scene: &Scene, statistics: &RenderStatistics) -> f64 {
    let [width, height] = scene.camera.resolution();
    statistics.samples as f64 / (width as f64 * height as f64)
}

/// The pattern size and samples per pixel that `--pattern-size`,
/// `--replications` and `--spp` ask for together: spp = r × m, any two of
/// them fixing the third (checked for consistency when all three are given).
fn replication_plan(args: &RenderArgs) -> Result<(Option<u64>, Option<u64>), CliError> {
    if args.pattern_size == Some(0) {
        return Err(usage("--pattern-size must be at least 1"));
    }
    if args.replications == Some(0) {
        return Err(usage("--replications must be at least 1"));
    }
    match (args.pattern_size, args.replications, args.spp) {
        (pattern, None, spp) => Ok((pattern, spp)),
        (Some(pattern), Some(replications), spp) => {
            let product = pattern
                .checked_mul(replications)
                .ok_or_else(|| usage("--pattern-size × --replications is too large"))?;
            if spp.is_some_and(|spp| spp != product) {
                return Err(usage(format!(
                    "--spp {} disagrees with --pattern-size {pattern} × --replications \
                     {replications} = {product}",
                    spp.unwrap_or_default()
                )));
            }
            Ok((Some(pattern), Some(product)))
        }
        // Without a pattern size, replications are whole renders
        // ([`crate::replications`]).
        (None, Some(_), spp) => Ok((None, spp)),
    }
}

/// Runs `lqmc render`.
pub fn run(args: &RenderArgs) -> Result<(), CliError> {
    let scene_name = args.scene.as_deref().unwrap_or("builtin:cornell-box");
    let description =
        load_scene_description(scene_name, &args.define, args.resolution, args.quiet)?;
    if args.spp == Some(0) {
        return Err(usage("--spp must be at least 1"));
    }
    let time_budget = args
        .time
        .map(|seconds| parse_time_budget("--time", seconds))
        .transpose()?;
    if args.max_depth == Some(0) {
        return Err(usage("--max-depth must be at least 1"));
    }
    let extension = args
        .output
        .extension()
        .and_then(|e| e.to_str())
        .map(str::to_ascii_lowercase);
    if !matches!(extension.as_deref(), Some("exr" | "pfm" | "png")) {
        return Err(usage(format!(
            "cannot write {}: the output must end in .exr, .pfm or .png",
            args.output.display()
        )));
    }

    let scene = build_scene(scene_name, &description)?;
    let integrator_kind = match args.integrator {
        Some(name) => name.kind(),
        None => default_integrator(&description, &scene),
    };
    if args.mlt.any() && !integrator_kind.is_metropolis() {
        return Err(usage(format!(
            "the --mlt-* and --erpt-* options are for --integrator pssmlt or erpt, not {}",
            integrator_kind.name()
        )));
    }
    let mut integrator = integrator_settings(integrator_kind, &args.lqmc, &args.mlt, &args.vcm)?;
    for (given, option) in [
        (
            args.bdpt_skip_eye_connections,
            "--bdpt-skip-eye-connections",
        ),
        (args.strategy_images.is_some(), "--strategy-images"),
    ] {
        if given && !matches!(integrator, IntegratorSettings::Bdpt(_)) {
            return Err(usage(format!("{option} is an option of --integrator bdpt")));
        }
    }
    if let IntegratorSettings::Bdpt(bdpt) = &mut integrator {
        bdpt.camera_connections = !args.bdpt_skip_eye_connections;
        bdpt.strategy_images = args.strategy_images.is_some();
    }
    if let Some(directory) = &args.strategy_images {
        // Reported before rendering, not after.
        std::fs::create_dir_all(directory).map_err(|error| {
            usage(format!(
                "--strategy-images: cannot create {}: {error}",
                directory.display()
            ))
        })?;
    }
    let (pattern_size, samples_per_pixel) = replication_plan(args)?;
    args.sampler
        .kind()
        .check_pattern_size(pattern_size)
        .map_err(|error| usage(error.to_string()))?;
    let randomization = match args.randomize {
        RandomizeName::Seeded => Randomization::Seeded,
        RandomizeName::None => Randomization::None,
    };
    let replications = replications_of(args, &scene, integrator_kind, randomization)?;
    if replications.is_some() && (args.lqmc.density.is_some() || args.strategy_images.is_some()) {
        return Err(usage(
            "--density and --strategy-images are images of one render: not with replications",
        ));
    }
    if replications
        .as_ref()
        .is_some_and(|request| request.is_part())
        && extension.as_deref() != Some("exr")
    {
        return Err(usage(format!(
            "a replication part is written as EXR (its metadata ties it to its set for lqmc merge), not {}",
            args.output.display()
        )));
    }
    check_writable(&args.output)?;
    let live_view = match &args.tev {
        Some(address) => {
            let [width, height] = scene.camera.resolution();
            let name = args.output.file_name().map_or_else(
                || "lqmc".to_string(),
                |name| name.to_string_lossy().into_owned(),
            );
            Some(
                crate::live_view::LiveView::open(address, &name, width, height)
                    .map_err(|error| usage(format!("--tev: {error}")))?,
            )
        }
        None => None,
    };
    let request = RenderRequest {
        integrator,
        sampler: args.sampler.kind(),
        pattern_size,
        samples_per_pixel: match &replications {
            Some(request) => request.samples_per_replication,
            None => samples_per_pixel,
        },
        time_budget,
        seed: args.seed,
        randomization,
        max_depth: args.max_depth,
        russian_roulette_depth: args.rr_depth,
        heuristic: match args.mis {
            Some(HeuristicName::Power) => MisHeuristic::Power,
            Some(HeuristicName::Balance) => MisHeuristic::Balance,
            None => default_heuristic(integrator_kind),
        },
        splat_film: args.splat_film,
        threads: args.threads,
    };
    let settings = request.settings(&scene);

    let stop = Arc::new(AtomicBool::new(false));
    {
        let stop = stop.clone();
        // A second Ctrl-C while the image is written falls through to the default.
        let _ = ctrlc::set_handler(move || stop.store(true, Ordering::Relaxed));
    }
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        let bar = ProgressBar::new(100);
        bar.set_style(
            ProgressStyle::with_template(
                "{bar:40} {percent:>3}% {elapsed_precise} ETA {eta_precise} {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar
    };
    if let Some(request) = replications {
        return run_replications(
            args,
            scene_name,
            &scene,
            &settings,
            &request,
            &stop,
            &bar,
            extension.as_deref(),
            live_view.as_ref(),
        );
    }
    let started = std::time::Instant::now();
    let progress = |done: u64, total: u64| {
        let fraction = match time_budget {
            Some(budget) if args.spp.is_none() => {
                started.elapsed().as_secs_f64() / budget.as_secs_f64()
            }
            _ => done as f64 / total.max(1) as f64,
        };
        bar.set_position((fraction.min(1.0) * 100.0) as u64);
        let seconds = started.elapsed().as_secs_f64().max(1e-9);
        bar.set_message(format!("{:.3} M samples/s", done as f64 / seconds / 1e6));
    };
    let observe = |film: &render::film::Film, splat_scale: f64| {
        if let Some(view) = &live_view {
            view.show_film(film, splat_scale);
        }
    };
    let observer: Option<render::integrators::FilmObserver<'_>> =
        live_view.as_ref().map(|_| &observe as _);
    let output =
        render_observed(&scene, &settings, &stop, &progress, observer).map_err(render_failure)?;
    bar.finish_and_clear();
    if let Some(view) = &live_view {
        view.show(&output.image(), Some(&output.variance_image()));
    }

    let statistics = output.statistics;
    let metadata = render_metadata(scene_name, &settings, &statistics);
    let spp = traced_samples_per_pixel(&scene, &statistics);
    output
        .write(&args.output, &metadata)
        .map_err(|error| CliError::Failure(error.to_string()))?;
    let mut written = vec![args.output.display().to_string()];
    if let (Some(path), Some(layers)) = (&args.lqmc.density, output.auxiliary_image("density")) {
        let named: Vec<(&str, &render::image::Image)> = layers[1..]
            .iter()
            .map(|(name, image)| (*name, image))
            .collect();
        render::image::write_exr(path, &layers[0].1, &named, &metadata)
            .map_err(|error| CliError::Failure(error.to_string()))?;
        written.push(path.display().to_string());
    }
    if let (Some(directory), Some(layers)) =
        (&args.strategy_images, output.auxiliary_image("strategies"))
    {
        for (name, image) in layers {
            let path = directory.join(format!("{name}.exr"));
            render::image::write_exr(&path, image, &[], &metadata)
                .map_err(|error| CliError::Failure(error.to_string()))?;
        }
        written.push(format!(
            "{} strategy images in {}",
            layers.len(),
            directory.display()
        ));
    }
    if extension.as_deref() != Some("png") {
        let png = args.output.with_extension("png");
        write_png(&png, &output.image(), args.exposure, &metadata)
            .map_err(|error| CliError::Failure(error.to_string()))?;
        written.push(png.display().to_string());
    }
    let stopped = if stop.load(Ordering::Relaxed) {
        " (interrupted)"
    } else if statistics.stopped_early {
        " (time budget reached)"
    } else {
        ""
    };
    let markov_chains = settings.integrator.kind().runs_markov_chains();
    if markov_chains {
        // The chains draw their own numbers: no sampler to name.
        say!(
            "rendered {scene_name} {}x{} with {}: {} mutations per pixel{stopped}",
            scene.camera.resolution()[0],
            scene.camera.resolution()[1],
            settings.integrator.name(),
            statistics.completed_samples_per_pixel,
        );
    } else {
        say!(
            "rendered {scene_name} {}x{} with {} / {}: {:.1} samples per pixel{stopped}",
            scene.camera.resolution()[0],
            scene.camera.resolution()[1],
            settings.integrator.name(),
            settings.sampler.name(),
            spp,
        );
    }
    report_rates(&statistics);
    report_details(args, &settings, &statistics, output.details.as_deref(), "");
    let kind = settings.integrator.kind();
    // What the render's batches are, and whether they are independent.
    let (batches, independent) = if settings.pattern_size.is_some() {
        ("independent replications (Kollig & Keller)", true)
    } else if kind.runs_markov_chains() {
        ("independent groups of chains", true)
    } else if settings.sampler == SamplerKind::Independent {
        ("independent passes", true)
    } else {
        ("passes", false)
    };
    say!(
        "{}",
        crate::replications::describe_single_render_error(
            &output.image(),
            &output.variance_image(),
            &output.batch_image_means,
            batches,
            independent,
        )
    );
    say!("wrote {}", written.join(" and "));
    Ok(())
}

/// The independent replications the options ask for (`None`: one render),
/// checked against the other options.
fn replications_of(
    args: &RenderArgs,
    scene: &Scene,
    integrator: IntegratorKind,
    randomization: Randomization,
) -> Result<Option<ReplicationRequest>, CliError> {
    if args.pattern_size.is_some() {
        if args.replication.is_some() || args.target_error.is_some() {
            return Err(usage(
                "--pattern-size replicates inside one render (Kollig & Keller's passes); --replication and --target-error split the render into whole renders: use one or the other",
            ));
        }
        return Ok(None);
    }
    let request = replication_request(
        &ReplicationOptions {
            replications: args.replications,
            replication: args.replication,
            target_error: args.target_error,
            samples_per_pixel: args.spp,
            timed: args.time.is_some(),
        },
        scene.samples_per_pixel.unwrap_or(16),
    )?;
    if request.is_none() {
        for (given, option) in [
            (args.target_region.is_some(), "--target-region"),
            (args.max_replications.is_some(), "--max-replications"),
            (args.error_measure.is_some(), "--error-measure"),
        ] {
            if given {
                return Err(usage(format!(
                    "{option} is for renders of replications (--replications, --target-error)"
                )));
            }
        }
    }
    if args.max_replications == Some(0) {
        return Err(usage("--max-replications must be at least 1"));
    }
    if request.is_some()
        && randomization == Randomization::None
        && args.sampler.kind() != SamplerKind::Independent
        && !integrator.runs_markov_chains()
    {
        return Err(usage(
            "replications need --randomize seeded: with --randomize none every replication has the same QMC points",
        ));
    }
    if let (Some(region), Some(_)) = (args.target_region, &request) {
        let [width, height] = scene.camera.resolution();
        let [x, y, region_width, region_height] = region;
        if x + region_width > width as usize || y + region_height > height as usize {
            return Err(usage(format!(
                "--target-region {x},{y},{region_width},{region_height} reaches outside the {width}x{height} image"
            )));
        }
    }
    Ok(request)
}

/// Reports an output file that cannot be written before anything is
/// rendered: its directory must exist and take a new file.
fn check_writable(path: &Path) -> Result<(), CliError> {
    let directory = match path.parent() {
        Some(parent) if !parent.as_os_str().is_empty() => parent.to_path_buf(),
        _ => PathBuf::from("."),
    };
    if !directory.is_dir() {
        return Err(usage(format!(
            "cannot write {}: the directory {} does not exist",
            path.display(),
            directory.display()
        )));
    }
    let probe = directory.join(format!(".lqmc-write-check-{}", std::process::id()));
    match std::fs::File::create(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(error) => Err(usage(format!("cannot write {}: {error}", path.display()))),
    }
}

/// Renders the independent replications `request` asks for and writes
/// their mean, the variance of the mean and the error estimate.
#[allow(clippy::too_many_arguments)]
fn run_replications(
    args: &RenderArgs,
    scene_name: &str,
    scene: &Scene,
    settings: &RenderSettings,
    request: &ReplicationRequest,
    stop: &AtomicBool,
    bar: &ProgressBar,
    extension: Option<&str>,
    live_view: Option<&crate::live_view::LiveView>,
) -> Result<(), CliError> {
    use crate::replications::{
        describe_estimate, fingerprint_hash, format_indices, insert_estimate, keys,
        settings_fingerprint,
    };
    use render::replication::{
        ErrorMeasure, ErrorTarget, ReplicationPlan, ReplicationProgress, render_replications,
        replication_seed,
    };
    let measure = match args.error_measure.as_deref() {
        None => ErrorMeasure::default(),
        Some(name) => ErrorMeasure::ALL
            .iter()
            .find(|(_, known)| *known == name)
            .map(|(measure, _)| *measure)
            .ok_or_else(|| usage(format!("--error-measure: `{name}` is not mean or rmse")))?,
    };
    let plan = ReplicationPlan {
        first: request.first,
        count: request.count,
        region: args.target_region,
        target: request.target_error.map(|relative_error| ErrorTarget {
            relative_error,
            measure,
            max_replications: args.max_replications.unwrap_or(1000),
        }),
        time_budget: settings.time_budget,
    };
    let started = std::time::Instant::now();
    let timed = settings.time_budget.is_some()
        && (request.samples_per_replication.is_none() || plan.target.is_some());
    let progress = |state: ReplicationProgress| {
        let fraction = match settings.time_budget {
            Some(budget) if timed => started.elapsed().as_secs_f64() / budget.as_secs_f64(),
            _ => {
                (state.finished as f64
                    + state.samples_done as f64 / state.samples_total.max(1) as f64)
                    / state.planned.max(1) as f64
            }
        };
        bar.set_position((fraction.min(1.0) * 100.0) as u64);
        let error = match state.estimate {
            Some(estimate) => format!(
                ", error ({}) {:.3} %",
                measure.name(),
                100.0 * estimate.relative(measure)
            ),
            None => String::new(),
        };
        let target = match request.target_error {
            Some(target) => format!(" (target {:.3} %)", 100.0 * target),
            None => String::new(),
        };
        bar.set_message(format!(
            "replication {} of {}{error}{target}",
            state.finished + 1,
            state.planned
        ));
    };
    // The first replication as it renders, then the mean of the finished.
    let first_finished = AtomicBool::new(false);
    let observe = |film: &render::film::Film, splat_scale: f64| {
        if let (Some(view), false) = (live_view, first_finished.load(Ordering::Relaxed)) {
            view.show_film(film, splat_scale);
        }
    };
    let observer: Option<render::integrators::FilmObserver<'_>> = live_view.map(|_| &observe as _);
    let mut show_mean = |accumulator: &render::replication::ReplicationAccumulator| {
        first_finished.store(true, Ordering::Relaxed);
        if let Some(view) = live_view {
            view.show(
                &accumulator.mean_image(),
                Some(&accumulator.variance_image()),
            );
        }
    };
    let rendered = render_replications(
        scene,
        settings,
        &plan,
        stop,
        &progress,
        observer,
        &mut show_mean,
    )
    .map_err(render_failure)?;
    bar.finish_and_clear();

    let accumulator = &rendered.accumulator;
    let statistics = rendered.statistics;
    let estimate = accumulator.estimate();
    let [width, height] = scene.camera.resolution();
    let indices = accumulator.indices();
    let mut metadata = render_metadata(scene_name, settings, &statistics);
    metadata.insert(
        keys::SET.into(),
        request
            .set_size
            .map_or_else(|| "open".to_string(), |size| size.to_string()),
    );
    metadata.insert(keys::INDICES.into(), format_indices(&indices));
    metadata.insert(
        keys::SAMPLES_PER_REPLICATION.into(),
        request
            .samples_per_replication
            .map_or_else(|| "time".to_string(), |spp| spp.to_string()),
    );
    if let [index] = indices.as_slice() {
        metadata.insert(
            keys::REPLICATION_SEED.into(),
            replication_seed(settings.seed, *index).to_string(),
        );
    }
    let fingerprint = settings_fingerprint(scene_name, &args.define, [width, height], settings);
    metadata.insert(keys::SETTINGS_HASH.into(), fingerprint_hash(&fingerprint));
    metadata.insert(keys::SETTINGS.into(), fingerprint);
    let region = args
        .target_region
        .unwrap_or([0, 0, width as usize, height as usize]);
    insert_estimate(&mut metadata, &estimate, region);
    let image = accumulator.mean_image();
    // One replication: its own within-render estimate; several: their spread.
    let variance = if accumulator.count() >= 2 {
        accumulator.variance_image()
    } else {
        rendered.last.variance_image()
    };
    let written_error = |error: render::image::ImageError| CliError::Failure(error.to_string());
    match extension {
        Some("exr") => render::image::write_exr(
            &args.output,
            &image,
            &[(render::image::VARIANCE_LAYER, &variance)],
            &metadata,
        )
        .map_err(written_error)?,
        _ => render::image::write_image(&args.output, &image, &metadata).map_err(written_error)?,
    }
    let mut written = vec![args.output.display().to_string()];
    if extension != Some("png") {
        let png = args.output.with_extension("png");
        write_png(&png, &image, args.exposure, &metadata).map_err(written_error)?;
        written.push(png.display().to_string());
    }

    let stopped = if stop.load(Ordering::Relaxed) {
        " (interrupted)"
    } else {
        ""
    };
    let per_replication = request
        .samples_per_replication
        .map_or_else(|| "time-limited".to_string(), |spp| spp.to_string());
    let set = match request.set_size {
        Some(size) if request.is_part() => format!(" of a set of {size}"),
        _ => String::new(),
    };
    say!(
        "rendered {scene_name} {width}x{height} with {} / {}: {} replication{} ({}){set} of {per_replication} samples per pixel, {} in all{stopped}",
        settings.integrator.name(),
        settings.sampler.name(),
        indices.len(),
        if indices.len() == 1 { "" } else { "s" },
        format_indices(&indices),
        statistics.completed_samples_per_pixel,
    );
    if rendered.dropped > 0 {
        say!(
            "{} replication cut short and left out (its samples are not in the image)",
            rendered.dropped
        );
    }
    report_rates(&statistics);
    say!("{}", describe_estimate(&estimate, args.target_region));
    match (request.target_error, rendered.target_reached) {
        (Some(target), Some(true)) => say!(
            "target {:.3} % ({}) reached after {} replications",
            100.0 * target,
            measure.name(),
            indices.len()
        ),
        (Some(target), _) => say!(
            "target {:.3} % ({}) not reached: {:.3} % after {} replications ({})",
            100.0 * target,
            measure.name(),
            100.0 * estimate.relative(measure),
            indices.len(),
            if stop.load(Ordering::Relaxed) {
                "interrupted"
            } else if settings
                .time_budget
                .is_some_and(|budget| statistics.elapsed >= budget)
            {
                "time budget reached"
            } else {
                "--max-replications reached"
            }
        ),
        _ => {}
    }
    report_details(
        args,
        settings,
        &statistics,
        rendered.last.details.as_deref(),
        "last replication: ",
    );
    say!("wrote {}", written.join(" and "));
    Ok(())
}

/// A render's failure as a command-line error: an integrator that cannot
/// render the scene or a sampler that cannot be built is bad input
/// (status 2), anything else a failure.
fn render_failure(error: render::integrators::RenderError) -> CliError {
    match error {
        render::integrators::RenderError::Unsupported(message) => usage(message),
        render::integrators::RenderError::Sampler(error) => usage(error.to_string()),
        other => CliError::Failure(other.to_string()),
    }
}

/// Prints a render's time, samples/s, rays/s, dropped NaN/Inf samples and
/// peak memory.
fn report_rates(statistics: &RenderStatistics) {
    let seconds = statistics.elapsed.as_secs_f64().max(1e-9);
    say!(
        "time {seconds:.3} s, {:.3} M samples/s, {:.3} M rays/s, {} NaN/Inf samples dropped",
        statistics.samples as f64 / seconds / 1e6,
        statistics.rays as f64 / seconds / 1e6,
        statistics.nonfinite_samples,
    );
    if let Some(memory) = statistics.memory {
        say!("{}", memory.describe());
    }
}

/// Prints the integrator's own statistics after `prefix`: with `--stats`,
/// and always for the Metropolis integrators' chains and VCM's iterations
/// and merges.
fn report_details(
    args: &RenderArgs,
    settings: &RenderSettings,
    statistics: &RenderStatistics,
    details: Option<&dyn render::integrators::IntegratorDetails>,
    prefix: &str,
) {
    let kind = settings.integrator.kind();
    let always = kind.is_metropolis() || kind == IntegratorKind::Vcm;
    if let (true, Some(details)) = (args.lqmc.stats || always, details) {
        let threads = if settings.threads == 0 {
            std::thread::available_parallelism().map_or(1, |count| count.get())
        } else {
            settings.threads
        };
        let seconds = statistics.elapsed.as_secs_f64().max(1e-9);
        say!("{prefix}{}", details.report(seconds, threads));
    }
}
