//! The options of the Metropolis integrators (pssmlt, erpt, mmlt) and their
//! settings from them (defaults: Kelemen et al. 2002, pbrt-v4 and Mitsuba;
//! see `render::integrators::pssmlt`). Which of them each integrator reads
//! is the ownership table's ([`super::ownership`]).

use super::headings;
use crate::error::{CliError, usage};
use crate::named_values::NamedValues;
use clap::{Args, ValueEnum};
use render::integrators::erpt::ErptSettings;
use render::integrators::markov_chain::ChainSettings;
use render::integrators::mmlt::MmltSettings;
use render::integrators::pssmlt::{MltBase, PssmltSettings};
use render::sampler::{MutationSettings, SmallStep};

/// The small-step kernels of `--mlt-kernel`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum MltKernel {
    /// Kelemen et al.'s exponential steps, s1 = 1/1024, s2 = 1/64.
    Kelemen,
    /// pbrt-v4's Gaussian steps of standard deviation --mlt-sigma.
    Gaussian,
}

/// Per-dimension factors on the small steps, `D=S,...`.
#[derive(Debug, Clone, PartialEq)]
pub struct StepScales(Vec<(usize, f32)>);

/// Options of the Metropolis integrators.
#[derive(Args, Debug, Default)]
#[command(next_help_heading = headings::METROPOLIS)]
pub struct MetropolisArgs {
    /// pssmlt: the path sampler the chains drive, `path` (the path tracer,
    /// volumetric in scenes with media; default) or `bdpt` (every BDPT
    /// strategy).
    #[arg(long, value_name = "path|bdpt", value_parser = NamedValues::new(MltBase::ALL))]
    pub mlt_base: Option<MltBase>,
    /// The probability of a large step (default 0.3).
    #[arg(long, value_name = "P")]
    pub mlt_large_step: Option<f32>,
    /// The small-step kernel, `kelemen` (exponential, s1 = 1/1024, s2 =
    /// 1/64; default) or `gaussian` (pbrt-v4's, --mlt-sigma).
    #[arg(long, value_name = "kelemen|gaussian", value_enum)]
    pub mlt_kernel: Option<MltKernel>,
    /// The Gaussian kernel's standard deviation (default 0.01).
    #[arg(long, value_name = "SIGMA")]
    pub mlt_sigma: Option<f32>,
    /// Bootstrap samples for the normalisation and the chains' starts
    /// (default 100000).
    #[arg(long, value_name = "N")]
    pub mlt_bootstrap: Option<u64>,
    /// pssmlt, mmlt: the number of chains (default 1000).
    #[arg(long, value_name = "N")]
    pub mlt_chains: Option<u64>,
    /// Per-dimension factors on the small steps, `D=S` pairs (dimension of
    /// the layout, factor), comma-separated, e.g. `0=4,1=4` for steps four
    /// times larger on the image plane (ERPT's steps per dimension, as the
    /// LQMC paper matches them to its tiles).
    #[arg(long, value_name = "D=S,...", value_parser = parse_step_scales)]
    pub mlt_step_scale: Option<StepScales>,
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

impl MetropolisArgs {
    /// PSSMLT's settings.
    pub fn pssmlt_settings(&self) -> Result<PssmltSettings, CliError> {
        let mut settings = PssmltSettings::default();
        if let Some(base) = self.mlt_base {
            settings.base = base;
        }
        if let Some(spp) = positive_count(self.mlt_direct_spp, "--mlt-direct-spp")? {
            if settings.base != MltBase::Path {
                return Err(usage("--mlt-direct-spp is for --mlt-base path"));
            }
            settings.direct_samples_per_pixel = Some(spp);
        }
        settings.chains = self.chain_settings(settings.chains)?;
        Ok(settings)
    }

    /// ERPT's settings.
    pub fn erpt_settings(&self) -> Result<ErptSettings, CliError> {
        let mut settings = ErptSettings::default();
        settings.mutation = self.mutation_settings(settings.mutation)?;
        if let Some(count) = positive_count(self.mlt_bootstrap, "--mlt-bootstrap")? {
            settings.bootstrap_samples = count;
        }
        if let Some(length) = positive_count(self.erpt_chain_length, "--erpt-chain-length")? {
            settings.chain_length = length;
        }
        if let Some(chains) = self.erpt_chains_per_sample {
            if !(chains > 0.0 && chains.is_finite()) {
                return Err(usage(format!(
                    "--erpt-chains-per-sample must be positive, got {chains}"
                )));
            }
            settings.chains_per_sample = chains;
        }
        Ok(settings)
    }

    /// MMLT's settings.
    pub fn mmlt_settings(&self) -> Result<MmltSettings, CliError> {
        let mut settings = MmltSettings::default();
        settings.chains = self.chain_settings(settings.chains)?;
        Ok(settings)
    }

    /// The chain options shared by pssmlt and mmlt (mutations, bootstrap,
    /// chains) over `defaults`.
    fn chain_settings(&self, defaults: ChainSettings) -> Result<ChainSettings, CliError> {
        let mut chains = defaults;
        chains.mutation = self.mutation_settings(chains.mutation)?;
        if let Some(count) = positive_count(self.mlt_bootstrap, "--mlt-bootstrap")? {
            chains.bootstrap_samples = count;
        }
        if let Some(count) = positive_count(self.mlt_chains, "--mlt-chains")? {
            chains.chains = count;
        }
        Ok(chains)
    }

    /// The mutation settings over `defaults`.
    fn mutation_settings(&self, defaults: MutationSettings) -> Result<MutationSettings, CliError> {
        let mut mutation = defaults;
        if let Some(probability) = self.mlt_large_step {
            if !(0.0..=1.0).contains(&probability) {
                return Err(usage(format!(
                    "--mlt-large-step must be a probability in [0, 1], got {probability}"
                )));
            }
            mutation.large_step_probability = probability;
        }
        match self.mlt_kernel {
            None | Some(MltKernel::Kelemen) => {
                if self.mlt_sigma.is_some() {
                    return Err(usage("--mlt-sigma is for --mlt-kernel gaussian"));
                }
            }
            Some(MltKernel::Gaussian) => {
                let sigma = self.mlt_sigma.unwrap_or(0.01);
                if !(sigma > 0.0 && sigma.is_finite()) {
                    return Err(usage(format!("--mlt-sigma must be positive, got {sigma}")));
                }
                mutation.small_step = SmallStep::Gaussian { sigma };
            }
        }
        if let Some(StepScales(scales)) = &self.mlt_step_scale {
            for &(dimension, scale) in scales {
                if mutation.step_scales.len() <= dimension {
                    mutation.step_scales.resize(dimension + 1, 1.0);
                }
                mutation.step_scales[dimension] = scale;
            }
        }
        Ok(mutation)
    }
}

/// `value` if it is at least 1 (a count given as `option`).
fn positive_count(value: Option<u64>, option: &str) -> Result<Option<u64>, CliError> {
    match value {
        Some(0) => Err(usage(format!("{option} must be at least 1"))),
        other => Ok(other),
    }
}

/// Parses `D=S,...` of `--mlt-step-scale`.
fn parse_step_scales(list: &str) -> Result<StepScales, String> {
    list.split(',')
        .map(|entry| {
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
                    Ok((dimension, scale))
                }
                _ => Err(format!(
                    "`{entry}` is not DIMENSION=FACTOR (a dimension below 4096, a positive factor)"
                )),
            }
        })
        .collect::<Result<_, _>>()
        .map(StepScales)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn step_scales_are_dimension_factor_pairs() {
        assert_eq!(
            parse_step_scales("0=4, 1=2.5"),
            Ok(StepScales(vec![(0, 4.0), (1, 2.5)]))
        );
        for bad in ["0:4", "0=0", "4096=2", "x=1", "0=4,"] {
            assert!(parse_step_scales(bad).is_err(), "{bad}");
        }
    }
}
