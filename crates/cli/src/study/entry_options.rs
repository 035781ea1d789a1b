//! The options an entry of a study's `--integrators` carries in brackets,
//! `lqmc[--class-selection fixed]`: the integrator options of the study's
//! command line with the entry's own after them, so that one study can
//! compare modes of one integrator. Each of the entry's options must be
//! one its integrator reads; an option both give once-only (such as
//! `--breakup`) is refused, as on a command line.

use super::IntegratorEntry;
use crate::error::{CliError, usage};
use crate::integrator_options::IntegratorArgs;
use crate::integrator_options::ownership::check_entry_options;
use clap::parser::ValueSource;
use clap::{ArgMatches, Args, Command, FromArgMatches};
use std::ffi::OsString;

/// The integrator options alone, as a command without a binary name.
fn integrator_options_command() -> Command {
    IntegratorArgs::augment_args(
        Command::new("integrator options")
            .no_binary_name(true)
            .disable_help_flag(true),
    )
}

/// The integrator options given on the study's command line (`matches`),
/// as words again.
fn given_words(matches: &ArgMatches) -> Vec<OsString> {
    let command = integrator_options_command();
    let mut words = Vec::new();
    for argument in command.get_arguments() {
        let id = argument.get_id().as_str();
        let Some(long) = argument.get_long() else {
            continue;
        };
        if !matches.ids().any(|known| known.as_str() == id)
            || matches.value_source(id) != Some(ValueSource::CommandLine)
        {
            continue;
        }
        if argument.get_action().takes_values() {
            for occurrence in matches.get_raw_occurrences(id).into_iter().flatten() {
                words.push(OsString::from(format!("--{long}")));
                words.extend(occurrence.map(OsString::from));
            }
        } else {
            words.push(OsString::from(format!("--{long}")));
        }
    }
    words
}

/// A clap error as one line, for the entry `entry`.
fn entry_error(entry: &IntegratorEntry, error: &clap::Error) -> CliError {
    let text = error.to_string();
    let first = text.lines().next().unwrap_or_default();
    usage(format!(
        "--integrators: `{}`: {}",
        entry.requested,
        first.strip_prefix("error: ").unwrap_or(first)
    ))
}

/// The integrator options of `entry`: the study's (`matches`, its command
/// line as clap parsed it) followed by the entry's own.
pub fn entry_integrator_args(
    matches: &ArgMatches,
    entry: &IntegratorEntry,
) -> Result<IntegratorArgs, CliError> {
    let command = integrator_options_command();
    let own = command
        .clone()
        .try_get_matches_from(&entry.options)
        .map_err(|error| entry_error(entry, &error))?;
    check_entry_options(&own, &entry.requested, entry.integrator)?;
    let mut words = given_words(matches);
    words.extend(entry.options.iter().map(OsString::from));
    let merged = command
        .try_get_matches_from(words)
        .map_err(|error| entry_error(entry, &error))?;
    IntegratorArgs::from_arg_matches(&merged).map_err(|error| entry_error(entry, &error))
}
