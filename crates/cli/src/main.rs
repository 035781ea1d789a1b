//! The `lqmc` command: rendering, point sets and lattices; comparison and
//! studies as the project grows.
//!
//! Exit status: 0 on success, 2 for bad input (one line on stderr), 1 when an
//! operation fails for another reason (e.g. a file cannot be written).

mod compare_command;
mod error;
mod integrator_options;
mod json;
mod lattice_command;
mod live_view;
mod merge_command;
mod named_values;
mod plot;
mod plot_font;
mod points_command;
mod render_command;
mod replications;
mod study;
mod study_command;
mod tev;

use clap::{ArgMatches, CommandFactory, FromArgMatches, Parser, Subcommand};
use std::process::ExitCode;

/// What `lqmc --help` says first; the commands are appended from the
/// subcommands themselves ([`command`]).
const ABOUT: &str = "Quasi-Monte Carlo light transport: sampling tools and renderer";

#[derive(Parser, Debug)]
#[command(name = "lqmc", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Render a scene to EXR (or PFM) and PNG.
    Render(Box<render_command::RenderArgs>),
    /// Merge replication parts (`lqmc render --replication I/R`) into
    /// their mean with the variance of the mean and the error estimate.
    Merge(merge_command::MergeArgs),
    /// List the built-in scenes.
    Scenes,
    /// Compare an image with a reference: RMSE, relative MSE, mean absolute
    /// deviation, difference of means, and a per-pixel z-test with a
    /// variance image.
    Compare(compare_command::CompareArgs),
    /// Print points of a sequence or point set (CSV or JSON), with
    /// discrepancies and plots.
    Points(points_command::PointsArgs),
    /// Build a rank-1 lattice by component-by-component construction and
    /// print its generator and squared worst-case error.
    Lattice(lattice_command::LatticeArgs),
    /// Studies that render a scene many times and compare integrators:
    /// `equal-time`, `kollig-keller`, `heinrich-keller`.
    Study(study_command::StudyArgs),
}

/// The command line, its about text naming every command.
fn command() -> clap::Command {
    let command = Cli::command();
    let names: Vec<&str> = command
        .get_subcommands()
        .map(clap::Command::get_name)
        .collect();
    let about = format!("{ABOUT}: {}", names.join(", "));
    command.about(about)
}

/// The arguments of the subcommand, as clap parsed them (which options the
/// user gave).
fn subcommand_matches(matches: &ArgMatches) -> &ArgMatches {
    matches
        .subcommand()
        .map_or(matches, |(_, arguments)| arguments)
}

fn main() -> ExitCode {
    let parsed = command()
        .try_get_matches()
        .and_then(|matches| Cli::from_arg_matches(&matches).map(|cli| (cli, matches)));
    let (cli, matches) = match parsed {
        Ok(parsed) => parsed,
        Err(error) => return error::report_clap_error(error),
    };
    let matches = subcommand_matches(&matches);
    let result = match cli.command {
        Command::Render(args) => render_command::run(&args, matches),
        Command::Merge(args) => merge_command::run(&args),
        Command::Scenes => render_command::list_scenes(),
        Command::Compare(args) => compare_command::run(&args),
        Command::Points(args) => points_command::run(&args),
        Command::Lattice(args) => lattice_command::run(&args),
        Command::Study(args) => study_command::run(&args, matches),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(error) => error.report(),
    }
}

#[cfg(test)]
mod tests {
    /// clap's own checks of every command's definition (unique ids, valid
    /// defaults and headings).
    #[test]
    fn the_command_line_is_consistent() {
        super::command().debug_assert();
    }
}
