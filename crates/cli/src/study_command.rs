//! `lqmc study`: experiments that render a scene many times in this process
//! and report error measures, plots and crops (see [`crate::study`]). Each
//! study is a subcommand: `equal-time` now; the Kollig–Keller and
//! Heinrich–Keller comparisons will join it.

use crate::error::CliError;
use crate::study::equal_time::{self, EqualTimeArgs};
use clap::{Args, Subcommand};

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
}

/// Runs `lqmc study`.
pub fn run(args: &StudyArgs) -> Result<(), CliError> {
    match &args.study {
        StudyName::EqualTime(arguments) => equal_time::run(arguments),
    }
}
