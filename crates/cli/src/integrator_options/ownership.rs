//! Which integrators read each integrator-specific option, and the one rule
//! built on it: an option given to an integrator that does not read it is
//! an error (exit status 2) naming the option, the integrator and the
//! integrators that read it, not an option silently ignored.
//!
//! The table says who reads an option, as the settings code does: every
//! integrator reads `--max-depth` and `--rr-depth`, so they are not in it;
//! `--mis` is read by those that weigh techniques by the chosen heuristic
//! (volpath weighs techniques and wavelengths by the balance heuristic
//! always, light tracing has no MIS); `--pattern-size` by those whose
//! pixel samples come from the sampler (pssmlt's and mmlt's chains draw
//! their own numbers); `--splat-film` by path, volpath and lqmc (whose
//! seeds otherwise land as the path tracer's camera samples); `--sampler`
//! and `--randomize` by every integrator but mmlt, whose chains draw every
//! number of their own.
//!
//! Two options are read only under conditions, checked once the scene is
//! loaded by [`check_conditional_options`]: pssmlt reads the sampler only
//! for its direct-light pass (`--mlt-direct-spp`), and in a scene with
//! participating media the volume walks of lqmc, erpt and pssmlt over
//! paths weigh by the balance heuristic whatever `--mis` says.

use crate::error::{CliError, usage};
use clap::ArgMatches;
use clap::parser::ValueSource;
use render::integrators::IntegratorKind;
use render::integrators::pssmlt::MltBase;

const LQMC: &[IntegratorKind] = &[IntegratorKind::Lqmc];
const BDPT: &[IntegratorKind] = &[IntegratorKind::Bdpt];
const VCM: &[IntegratorKind] = &[IntegratorKind::Vcm];
const PSSMLT: &[IntegratorKind] = &[IntegratorKind::Pssmlt];
const ERPT: &[IntegratorKind] = &[IntegratorKind::Erpt];
/// The integrators that run chains of their own (`--mlt-chains`).
const CHAIN_RENDERERS: &[IntegratorKind] = &[IntegratorKind::Pssmlt, IntegratorKind::Mmlt];
/// The integrators that mutate paths by Metropolis steps.
const METROPOLIS: &[IntegratorKind] = &[
    IntegratorKind::Pssmlt,
    IntegratorKind::Erpt,
    IntegratorKind::Mmlt,
];
/// The camera-path tracers and LQMC, whose film `--splat-film` changes.
const CAMERA_SAMPLE_FILMS: &[IntegratorKind] = &[
    IntegratorKind::Path,
    IntegratorKind::VolPath,
    IntegratorKind::Lqmc,
];
/// The integrators that weigh their techniques by the MIS heuristic chosen.
const MIS_USERS: &[IntegratorKind] = &[
    IntegratorKind::Path,
    IntegratorKind::Lqmc,
    IntegratorKind::Bdpt,
    IntegratorKind::Pssmlt,
    IntegratorKind::Erpt,
    IntegratorKind::Mmlt,
    IntegratorKind::Vcm,
];
/// The integrators whose pixel samples come from the sampler's points.
const PIXEL_SAMPLE_USERS: &[IntegratorKind] = &[
    IntegratorKind::Path,
    IntegratorKind::VolPath,
    IntegratorKind::Lqmc,
    IntegratorKind::Light,
    IntegratorKind::Bdpt,
    IntegratorKind::Erpt,
    IntegratorKind::Vcm,
];

/// The integrators that draw numbers from the render's sampler.
const SAMPLER_USERS: &[IntegratorKind] = &[
    IntegratorKind::Path,
    IntegratorKind::VolPath,
    IntegratorKind::Lqmc,
    IntegratorKind::Light,
    IntegratorKind::Bdpt,
    IntegratorKind::Pssmlt,
    IntegratorKind::Erpt,
    IntegratorKind::Vcm,
];

/// Each integrator-specific option (its long name) with the integrators
/// that read it.
pub const OPTION_USERS: &[(&str, &[IntegratorKind])] = &[
    ("mis", MIS_USERS),
    ("sampler", SAMPLER_USERS),
    ("randomize", SAMPLER_USERS),
    ("pattern-size", PIXEL_SAMPLE_USERS),
    ("splat-film", CAMERA_SAMPLE_FILMS),
    ("explore", LQMC),
    ("breakup", LQMC),
    ("lattice-size", LQMC),
    ("aperture-tiles", LQMC),
    ("image-tiles", LQMC),
    ("direction-tiles", LQMC),
    ("wavelength-tiles", LQMC),
    ("time-tiles", LQMC),
    ("medium-image-tiles", LQMC),
    ("skip-class", LQMC),
    ("explore-class", LQMC),
    ("explore-wavelength-alone", LQMC),
    ("explore-camera-in-focus", LQMC),
    ("class-selection", LQMC),
    ("no-jitter", LQMC),
    ("lattice-scramble", LQMC),
    ("stats", LQMC),
    ("density", LQMC),
    ("bdpt-skip-eye-connections", BDPT),
    ("strategy-images", BDPT),
    ("mlt-base", PSSMLT),
    ("mlt-direct-spp", PSSMLT),
    ("mlt-large-step", METROPOLIS),
    ("mlt-kernel", METROPOLIS),
    ("mlt-sigma", METROPOLIS),
    ("mlt-bootstrap", METROPOLIS),
    ("mlt-step-scale", METROPOLIS),
    ("mlt-chains", CHAIN_RENDERERS),
    ("erpt-chain-length", ERPT),
    ("erpt-chains-per-sample", ERPT),
    ("vcm-mode", VCM),
    ("vcm-radius", VCM),
    ("vcm-alpha", VCM),
];

/// The clap id of the option called `--long` (clap's derived ids are the
/// field names).
fn id_of(long: &str) -> String {
    long.replace('-', "_")
}

/// The integrator-specific options given on the command line `matches`
/// holds, with their readers.
fn given(matches: &ArgMatches) -> impl Iterator<Item = (&'static str, &'static [IntegratorKind])> {
    OPTION_USERS.iter().copied().filter(|(long, _)| {
        let id = id_of(long);
        matches.ids().any(|known| known.as_str() == id)
            && matches
                .value_source(&id)
                .is_some_and(|source| source != ValueSource::DefaultValue)
    })
}

/// Whether `--long` was given on the command line `matches` holds.
fn given_option(matches: &ArgMatches, long: &str) -> bool {
    given(matches).any(|(given, _)| given == long)
}

/// `kinds` by name, joined as a list: `pssmlt, erpt and mmlt`.
fn names(kinds: &[IntegratorKind]) -> String {
    let names: Vec<&str> = kinds.iter().map(|kind| kind.name()).collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => names.concat(),
    }
}

/// How the integrator of a render was chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Choice {
    /// By `--integrator`.
    Named,
    /// For the scene, without `--integrator`.
    SceneDefault,
}

/// Refuses an integrator-specific option of `matches` (a render's) that
/// `integrator` does not read.
pub fn check_render_options(
    matches: &ArgMatches,
    integrator: IntegratorKind,
    choice: Choice,
) -> Result<(), CliError> {
    match given(matches).find(|(_, users)| !users.contains(&integrator)) {
        None => Ok(()),
        Some((long, users)) => Err(usage(format!(
            "--{long} is an option of {}, not of {}{}",
            names(users),
            integrator.name(),
            match choice {
                Choice::Named => "",
                Choice::SceneDefault => {
                    " (the integrator this scene renders with by default; choose one with --integrator)"
                }
            }
        ))),
    }
}

/// Refuses an option of `matches` (a render's) that `integrator` reads only
/// under a condition the other options or the scene do not meet:
/// `--sampler` or `--randomize` with pssmlt but without its direct-light
/// pass, and `--mis` where a volume walk that always weighs by the balance
/// heuristic renders the scene (`scene_has_media`).
pub fn check_conditional_options(
    matches: &ArgMatches,
    integrator: IntegratorKind,
    scene_has_media: bool,
) -> Result<(), CliError> {
    if integrator == IntegratorKind::Pssmlt
        && !given_option(matches, "mlt-direct-spp")
        && let Some(long) = ["sampler", "randomize"]
            .into_iter()
            .find(|long| given_option(matches, long))
    {
        return Err(usage(format!(
            "--{long} is read by pssmlt only for its direct-light pass (--mlt-direct-spp); \
             its chains draw their own numbers"
        )));
    }
    let path_base = matches
        .get_one::<MltBase>("mlt_base")
        .is_none_or(|base| *base == MltBase::Path);
    let balance_always = match integrator {
        IntegratorKind::Lqmc | IntegratorKind::Erpt => true,
        IntegratorKind::Pssmlt => path_base,
        _ => false,
    };
    if scene_has_media && balance_always && given_option(matches, "mis") {
        return Err(usage(format!(
            "--mis does not apply to {} in a scene with participating media: \
             its volume walk weighs by the balance heuristic, as volpath's does",
            integrator.name()
        )));
    }
    Ok(())
}

/// Refuses an option of `matches` (the options one study entry carries in
/// brackets, `entry`) that its `integrator` does not read.
pub fn check_entry_options(
    matches: &ArgMatches,
    entry: &str,
    integrator: IntegratorKind,
) -> Result<(), CliError> {
    match given(matches).find(|(_, users)| !users.contains(&integrator)) {
        None => Ok(()),
        Some((long, users)) => Err(usage(format!(
            "--integrators: `{entry}`: --{long} is an option of {}, not of {}",
            names(users),
            integrator.name()
        ))),
    }
}

/// Refuses an integrator-specific option of `matches` (a study's) that none
/// of `integrators` reads.
pub fn check_study_options(
    matches: &ArgMatches,
    integrators: &[IntegratorKind],
) -> Result<(), CliError> {
    match given(matches).find(|(_, users)| !users.iter().any(|user| integrators.contains(user))) {
        None => Ok(()),
        Some((long, users)) => Err(usage(format!(
            "--{long} is an option of {}, none of the study's integrators ({})",
            names(users),
            names(integrators)
        ))),
    }
}

#[cfg(test)]
mod tests {
    use super::super::headings;
    use super::*;
    use crate::render_command::arguments::RenderArgs;
    use clap::{Args, Command};

    fn render_command() -> Command {
        RenderArgs::augment_args(Command::new("render"))
    }

    #[test]
    fn every_option_of_the_table_is_an_option_of_render_read_by_some_integrator() {
        let command = render_command();
        for (long, users) in OPTION_USERS {
            let argument = command
                .get_arguments()
                .find(|argument| argument.get_long() == Some(long))
                .unwrap_or_else(|| panic!("--{long} is not an option of lqmc render"));
            assert_eq!(argument.get_id().as_str(), id_of(long), "--{long}");
            assert!(!users.is_empty(), "--{long}");
        }
    }

    /// An option added to an integrator's group without its line in the
    /// table would be silently ignored by the others.
    #[test]
    fn every_option_under_an_integrator_heading_is_in_the_table() {
        let integrator_headings = [
            headings::PATH_TRACER,
            headings::LQMC,
            headings::BDPT,
            headings::METROPOLIS,
            headings::VCM,
        ];
        for argument in render_command().get_arguments() {
            if argument
                .get_help_heading()
                .is_some_and(|heading| integrator_headings.contains(&heading))
            {
                let long = argument.get_long().unwrap();
                assert!(
                    OPTION_USERS.iter().any(|(known, _)| *known == long),
                    "--{long} has no line in OPTION_USERS"
                );
            }
        }
    }

    #[test]
    fn readers_are_listed_by_name() {
        assert_eq!(names(LQMC), "lqmc");
        assert_eq!(names(CHAIN_RENDERERS), "pssmlt and mmlt");
        assert_eq!(names(METROPOLIS), "pssmlt, erpt and mmlt");
    }
}
