//! Options that belong to integrators: each integrator's own options in a
//! clap group under its help heading, the settings each integrator gets from
//! them, and the rule ([`ownership`]) that an option given to an integrator
//! that does not read it is an error, not silence.

pub mod bidirectional;
pub mod lqmc;
pub mod metropolis;
pub mod ownership;

use crate::error::CliError;
use bidirectional::{BdptArgs, VcmArgs};
use clap::{Args, ValueEnum};
use lqmc::LqmcArgs;
use metropolis::MetropolisArgs;
use render::integrators::{IntegratorKind, IntegratorSettings, MisHeuristic};

/// The help headings of the option groups.
pub mod headings {
    /// Options of the paths every integrator builds.
    pub const PATH: &str = "Path options";
    /// Options of the camera-path tracers path and volpath.
    pub const PATH_TRACER: &str = "Path tracer options (path, volpath; lqmc's seeds)";
    /// Options of LQMC.
    pub const LQMC: &str = "LQMC options";
    /// Options of BDPT.
    pub const BDPT: &str = "BDPT options";
    /// Options of the Metropolis integrators.
    pub const METROPOLIS: &str = "Metropolis options (pssmlt, erpt, mmlt)";
    /// Options of VCM.
    pub const VCM: &str = "VCM options";
}

/// The MIS heuristics, as command-line values.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum HeuristicName {
    Power,
    Balance,
}

/// Options of the paths every integrator builds: depth, Russian roulette and
/// the MIS heuristic.
#[derive(Args, Debug, Default)]
#[command(next_help_heading = headings::PATH)]
pub struct PathArgs {
    /// Maximum path depth in segments, Mitsuba's convention: 1 shows
    /// emitters only, 2 adds direct light (default: the scene's, else 6).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// The path depth from which Russian roulette may end paths, Mitsuba's
    /// `rr_depth` convention (default: the scene's — a Mitsuba file's
    /// `rr_depth`, 5 if it names none — else 3).
    #[arg(long, value_name = "DEPTH")]
    pub rr_depth: Option<u32>,
    /// Multiple importance sampling heuristic (default: balance for bdpt
    /// and vcm, as Kollig & Keller and SmallVCM use; power for the others,
    /// as pbrt-v4 and Mitsuba). volpath weighs its techniques and
    /// wavelengths by the balance heuristic always; light tracing has no
    /// MIS.
    #[arg(long, value_enum)]
    pub mis: Option<HeuristicName>,
}

impl PathArgs {
    /// The MIS heuristic `--mis` names, else `kind`'s default.
    pub fn heuristic(&self, kind: IntegratorKind) -> MisHeuristic {
        match self.mis {
            Some(HeuristicName::Power) => MisHeuristic::Power,
            Some(HeuristicName::Balance) => MisHeuristic::Balance,
            None => default_heuristic(kind),
        }
    }
}

/// Options of the camera-path tracers (path, volpath) and LQMC's seeds.
#[derive(Args, Debug, Default)]
#[command(next_help_heading = headings::PATH_TRACER)]
pub struct PathTracerArgs {
    /// Place each sample uniformly in its pixel and splat it over the
    /// pixels of the scene's filter (Mitsuba's film) instead of
    /// importance-sampling the filter (pbrt-v4's, the default). LQMC: its
    /// seeds too (its explored members are always splatted).
    #[arg(long)]
    pub splat_film: bool,
}

/// The options of the integrators with settings of their own.
#[derive(Args, Debug, Default)]
pub struct IntegratorArgs {
    #[command(flatten)]
    pub lqmc: LqmcArgs,
    #[command(flatten)]
    pub bdpt: BdptArgs,
    #[command(flatten)]
    pub metropolis: MetropolisArgs,
    #[command(flatten)]
    pub vcm: VcmArgs,
}

impl IntegratorArgs {
    /// The integrator `kind` with its settings from its options (the
    /// others' options are [`ownership`]'s to refuse).
    pub fn settings(&self, kind: IntegratorKind) -> Result<IntegratorSettings, CliError> {
        Ok(match kind {
            IntegratorKind::Lqmc => IntegratorSettings::Lqmc(self.lqmc.settings()?),
            IntegratorKind::Bdpt => IntegratorSettings::Bdpt(self.bdpt.settings()),
            IntegratorKind::Pssmlt => {
                IntegratorSettings::Pssmlt(self.metropolis.pssmlt_settings()?)
            }
            IntegratorKind::Erpt => IntegratorSettings::Erpt(self.metropolis.erpt_settings()?),
            IntegratorKind::Mmlt => IntegratorSettings::Mmlt(self.metropolis.mmlt_settings()?),
            IntegratorKind::Vcm => IntegratorSettings::Vcm(self.vcm.settings()?),
            other => other.into(),
        })
    }
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
