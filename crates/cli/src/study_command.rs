//! `lqmc study`: experiments that render a scene many times in this process
//! and report error measures, plots and crops (see [`crate::study`]). Each
//! study is a subcommand: `equal-time`, `kollig-keller`,
//! `heinrich-keller` and `lattice-structure`.

use crate::error::CliError;
use crate::study::equal_time::{self, EqualTimeArgs};
use crate::study::heinrich_keller::{self, HeinrichKellerArgs};
use crate::study::kollig_keller::{self, KolligKellerArgs};
use crate::study::lattice_structure::{self, LatticeStructureArgs};
use clap::{ArgMatches, Args, Subcommand};

/// Arguments of `lqmc study`.
#[derive(Args, Debug)]
pub struct StudyArgs {
    #[command(subcommand)]
    pub study: StudyName,
}

/// The studies.
#[derive(Subcommand, Debug)]
pub enum StudyName {
    /// Render each integrator K times with the same time budget (and
    /// smaller ones) and compare with a reference: tables of RMSE, relative
    /// MSE, MAD, mean bias and flicker, an error-versus-time plot and crops.
    EqualTime(Box<EqualTimeArgs>),
    /// Kollig & Keller's Sect. 6: BDPT's L2 error against a master image
    /// for n = 1 … 128 samples per pixel and technique with MC, QMC
    /// sequences and randomized QMC point sets; convergence plots (Figs. 7,
    /// 8), samples relative to MC (Fig. 9), fitted rates.
    KolligKeller(Box<KolligKellerArgs>),
    /// Heinrich & Keller's §5: radiance per triangle by particle simulation
    /// with random, Halton, scrambled Halton, Hammersley and Sobol points;
    /// mutual deviations of sampling rates (Tables 2–5) and of the
    /// patterns' masters (Table 6), convergence plot, fitted rates.
    HeinrichKeller(Box<HeinrichKellerArgs>),
    /// LQMC's error with each lattice scramble (none, image, all) against
    /// a reference: the radially averaged power spectrum of the error, its
    /// largest off-axis peak over the median at that radius, the
    /// autocorrelation over small lags, RMSE; tables, a spectrum plot,
    /// crops.
    LatticeStructure(Box<LatticeStructureArgs>),
}

/// Runs `lqmc study`; `matches` are its arguments as clap parsed them.
pub fn run(args: &StudyArgs, matches: &ArgMatches) -> Result<(), CliError> {
    let study_matches = matches
        .subcommand()
        .map_or(matches, |(_, arguments)| arguments);
    match &args.study {
        StudyName::EqualTime(arguments) => equal_time::run(arguments, study_matches),
        StudyName::KolligKeller(arguments) => kollig_keller::run(arguments),
        StudyName::HeinrichKeller(arguments) => heinrich_keller::run(arguments),
        StudyName::LatticeStructure(arguments) => lattice_structure::run(arguments, study_matches),
    }
}
