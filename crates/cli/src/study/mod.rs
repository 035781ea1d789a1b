//! The studies of `lqmc study`: experiments that render one scene many
//! times, in this process, with several integrators, seeds and budgets,
//! and report error measures, plots and crops. This module holds what the
//! studies share: the scene and render options and the list of integrators.

pub mod crops;
pub mod entry_options;
pub mod equal_time;
pub mod error_plot;
pub mod error_structure;
pub mod formatting;
pub mod heinrich_keller;
pub mod kollig_keller;
pub mod lattice_structure;
pub mod measures;
pub mod study_renders;

use crate::error::{CliError, usage};
use crate::integrator_options::IntegratorArgs;
use crate::render_command::parse_definition;
use clap::Args;
use render::integrators::IntegratorKind;
use render::sampler::SamplerKind;

/// The scene and the options of every render of a study.
#[derive(Args, Debug)]
pub struct StudySceneArgs {
    /// The scene: a Mitsuba 3 XML (`.xml`) or pbrt-v4 (`.pbrt`) file, or
    /// `builtin:NAME` (see `lqmc scenes`).
    pub scene: String,
    /// Image resolution WxH (default: the scene's).
    #[arg(long, value_parser = crate::points_command::parse_pair)]
    pub resolution: Option<(u32, u32)>,
    /// Worker threads of every render (default: all cores).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Maximum path depth in segments, Mitsuba's convention (default: the
    /// scene's, else 6).
    #[arg(long)]
    pub max_depth: Option<u32>,
    /// The path depth from which Russian roulette may end paths, Mitsuba's
    /// `rr_depth` convention (default: the scene's, else 3).
    #[arg(long, value_name = "DEPTH")]
    pub rr_depth: Option<u32>,
    /// A scene-file parameter, NAME=VALUE (Mitsuba's `$NAME`); may be
    /// repeated.
    #[arg(short = 'D', long = "define", value_name = "NAME=VALUE", value_parser = parse_definition)]
    pub define: Vec<(String, String)>,
    /// Options of the entries' integrators, each read by the entries of
    /// the integrators it belongs to.
    #[command(flatten)]
    pub integrators: IntegratorArgs,
}

impl StudySceneArgs {
    /// Checks the options that need no scene.
    pub fn validate(&self) -> Result<(), CliError> {
        if self.max_depth == Some(0) {
            return Err(usage("--max-depth must be at least 1"));
        }
        validate_integrator_args(&self.integrators)
    }

    /// The worker threads a render gets: `--threads`, or all cores for 0.
    pub fn effective_threads(&self) -> usize {
        if self.threads == 0 {
            std::thread::available_parallelism().map_or(1, |count| count.get())
        } else {
            self.threads
        }
    }
}

/// Refuses the integrator options a study has no use for.
pub fn validate_integrator_args(options: &IntegratorArgs) -> Result<(), CliError> {
    if options.lqmc.density.is_some() {
        return Err(usage(
            "--density is for `lqmc render`: a study writes no density images",
        ));
    }
    if options.bdpt.strategy_images.is_some() {
        return Err(usage(
            "--strategy-images is for `lqmc render`: a study writes no strategy images",
        ));
    }
    Ok(())
}

/// One entry of `--integrators`: an integrator with a sampler.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct IntegratorEntry {
    /// The entry as written, e.g. `path:sobol`.
    pub requested: String,
    /// The integrator (after [`Self::resolve_path_tracer`], the one used).
    pub integrator: IntegratorKind,
    /// The sampler (default Halton).
    pub sampler: SamplerKind,
    /// path, volpath: splat each sample over its filter's pixels
    /// (`--splat-film`, written `:splat` after the entry).
    pub splat_film: bool,
    /// The entry's own integrator options, written in brackets after it
    /// (`lqmc[--class-selection fixed]`), as words; they apply to this
    /// entry only, after the study's (see [`entry_options`]).
    pub options: Vec<String>,
}

impl IntegratorEntry {
    /// `path` stands for the scene's path tracer: volpath in scenes with
    /// participating media (as `lqmc render` chooses), path elsewhere.
    pub fn resolve_path_tracer(&mut self, scene_has_media: bool) {
        if self.integrator == IntegratorKind::Path && scene_has_media {
            self.integrator = IntegratorKind::VolPath;
        }
    }

    /// The name in tables and legends: the integrator used, with the
    /// sampler unless it is Halton, and `:splat` for a splatting film
    /// (`volpath`, `path:sobol`, `path:splat`).
    pub fn label(&self) -> String {
        let mut label = self.integrator.name().to_string();
        if self.sampler != SamplerKind::Halton {
            label = format!("{label}:{}", self.sampler.name());
        }
        if self.splat_film {
            label.push_str(":splat");
        }
        if !self.options.is_empty() {
            label = format!("{label}[{}]", self.options.join(" "));
        }
        label
    }

    /// The label as a file-name part: letters, digits, dots and
    /// underscores kept, every other run of characters one `-`
    /// (`path-sobol`, `lqmc-class-selection-fixed`).
    pub fn file_stem(&self) -> String {
        let mut stem = String::new();
        for character in self.label().chars() {
            if character.is_ascii_alphanumeric() || character == '.' || character == '_' {
                stem.push(character);
            } else if !stem.ends_with('-') {
                stem.push('-');
            }
        }
        stem.trim_matches('-').to_string()
    }
}

/// Names of the known integrators, for error messages.
fn known_integrators() -> String {
    IntegratorKind::ALL
        .iter()
        .map(|(_, name)| *name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Names of the known samplers, for error messages.
fn known_samplers() -> String {
    SamplerKind::ALL
        .iter()
        .map(|(_, name)| *name)
        .collect::<Vec<_>>()
        .join(", ")
}

/// Parses `--integrators`: comma-separated `NAME[:SAMPLER][:splat]`
/// entries, any integrator and sampler the renderer has; `:splat` (path
/// and volpath) splats each sample over its filter's pixels as
/// `--splat-film` does.
pub fn parse_integrator_list(list: &str) -> Result<Vec<IntegratorEntry>, CliError> {
    let entries = split_entries(list)?
        .into_iter()
        .map(str::trim)
        .filter(|entry| !entry.is_empty())
        .map(parse_integrator_entry)
        .collect::<Result<Vec<_>, CliError>>()?;
    if entries.is_empty() {
        return Err(usage(format!(
            "--integrators needs at least one NAME[:SAMPLER][:splat] (integrators: {}; samplers: {})",
            known_integrators(),
            known_samplers()
        )));
    }
    Ok(entries)
}

/// The entries of `--integrators`: split at the commas outside brackets
/// (an entry's options may hold commas, as `--explore aperture,image`).
fn split_entries(list: &str) -> Result<Vec<&str>, CliError> {
    let mut entries = Vec::new();
    let (mut depth, mut start) = (0usize, 0usize);
    for (index, character) in list.char_indices() {
        match character {
            '[' => depth += 1,
            ']' => {
                depth = depth.checked_sub(1).ok_or_else(|| {
                    usage(format!(
                        "--integrators: `{list}` closes a bracket it did not open"
                    ))
                })?;
            }
            ',' if depth == 0 => {
                entries.push(&list[start..index]);
                start = index + 1;
            }
            _ => {}
        }
    }
    if depth != 0 {
        return Err(usage(format!(
            "--integrators: `{list}` leaves a bracket open"
        )));
    }
    entries.push(&list[start..]);
    Ok(entries)
}

/// One `NAME[:SAMPLER][:splat][[OPTIONS]]` entry of `--integrators`.
fn parse_integrator_entry(entry: &str) -> Result<IntegratorEntry, CliError> {
    let (head, options) = match entry.split_once('[') {
        Some((head, rest)) => {
            let options = rest.strip_suffix(']').ok_or_else(|| {
                usage(format!(
                    "--integrators: `{entry}`: the options in brackets come last, NAME[:SAMPLER][:splat][OPTIONS]"
                ))
            })?;
            let words: Vec<String> = options.split_whitespace().map(str::to_string).collect();
            if words.is_empty() {
                return Err(usage(format!(
                    "--integrators: `{entry}`: empty brackets (leave them out for the study's options)"
                )));
            }
            (head.trim(), words)
        }
        None => (entry, Vec::new()),
    };
    let mut parts = head.split(':');
    let name = parts.next().unwrap_or_default();
    let integrator = IntegratorKind::from_name(name).ok_or_else(|| {
        usage(format!(
            "--integrators: unknown integrator `{name}` (known: {})",
            known_integrators()
        ))
    })?;
    let mut sampler = None;
    let mut splat_film = false;
    for part in parts {
        if part == "splat" && !splat_film {
            if !matches!(
                integrator,
                IntegratorKind::Path | IntegratorKind::VolPath | IntegratorKind::Lqmc
            ) {
                return Err(usage(format!(
                    "--integrators: `{entry}`: `:splat` is for path, volpath and lqmc (the others choose their film themselves)"
                )));
            }
            splat_film = true;
        } else if sampler.is_none() && !splat_film {
            sampler = Some(SamplerKind::from_name(part).ok_or_else(|| {
                usage(format!(
                    "--integrators: unknown sampler `{part}` in `{entry}` (known: {}; `:splat` comes last)",
                    known_samplers()
                ))
            })?);
        } else {
            return Err(usage(format!(
                "--integrators: `{entry}` is not NAME[:SAMPLER][:splat]"
            )));
        }
    }
    Ok(IntegratorEntry {
        requested: entry.to_string(),
        integrator,
        sampler: sampler.unwrap_or(SamplerKind::Halton),
        splat_film,
        options,
    })
}

/// Refuses two entries that render the same integrator with the same
/// sampler (e.g. `path,volpath` in a scene with media).
pub fn check_distinct(entries: &[IntegratorEntry]) -> Result<(), CliError> {
    for (index, entry) in entries.iter().enumerate() {
        if let Some(earlier) = entries[..index]
            .iter()
            .find(|earlier| earlier.label() == entry.label())
        {
            return Err(usage(format!(
                "--integrators: `{}` and `{}` both render {}",
                earlier.requested,
                entry.requested,
                entry.label()
            )));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn entries_carry_their_own_options_in_brackets() {
        let entries = parse_integrator_list(
            "path,lqmc[--class-selection fixed],lqmc:sobol[--explore aperture,image --breakup 1]",
        )
        .unwrap();
        assert_eq!(entries.len(), 3);
        assert!(entries[0].options.is_empty());
        assert_eq!(entries[1].options, ["--class-selection", "fixed"]);
        assert_eq!(entries[1].label(), "lqmc[--class-selection fixed]");
        assert_eq!(entries[1].file_stem(), "lqmc-class-selection-fixed");
        assert_eq!(entries[2].sampler, SamplerKind::Sobol);
        assert_eq!(
            entries[2].options,
            ["--explore", "aperture,image", "--breakup", "1"]
        );
        assert_eq!(
            entries[2].file_stem(),
            "lqmc-sobol-explore-aperture-image-breakup-1"
        );
        for bad in ["lqmc[--stats", "lqmc]", "lqmc[]", "lqmc[--stats]:sobol"] {
            assert!(parse_integrator_list(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn integrator_lists_parse_with_samplers() {
        let entries = parse_integrator_list("path, lqmc,path:sobol,light:independent").unwrap();
        let labels: Vec<String> = entries.iter().map(IntegratorEntry::label).collect();
        assert_eq!(labels, ["path", "lqmc", "path:sobol", "light:independent"]);
        assert_eq!(entries[2].file_stem(), "path-sobol");
        assert_eq!(entries[2].requested, "path:sobol");
    }

    #[test]
    fn splatting_film_entries() {
        let entries =
            parse_integrator_list("path:splat,path:sobol:splat,volpath,lqmc:splat").unwrap();
        let labels: Vec<String> = entries.iter().map(IntegratorEntry::label).collect();
        assert_eq!(
            labels,
            ["path:splat", "path:sobol:splat", "volpath", "lqmc:splat"]
        );
        assert!(entries[0].splat_film && entries[1].splat_film && !entries[2].splat_film);
        assert!(entries[3].splat_film);
        assert_eq!(entries[1].sampler, SamplerKind::Sobol);
        assert_eq!(entries[0].file_stem(), "path-splat");
        for bad in [
            "bdpt:splat",
            "path:splat:sobol",
            "path:splat:splat",
            "path:sobol:halton",
        ] {
            assert!(parse_integrator_list(bad).is_err(), "{bad}");
        }
    }

    #[test]
    fn unknown_names_are_usage_errors_listing_the_known_ones() {
        let Err(CliError::Usage(message)) = parse_integrator_list("path,sppm") else {
            panic!("sppm is not an integrator");
        };
        assert!(message.contains("sppm") && message.contains("path, volpath, lqmc, light, bdpt"));
        let Err(CliError::Usage(message)) = parse_integrator_list("path:owen") else {
            panic!("owen is not a sampler");
        };
        assert!(message.contains("owen") && message.contains("halton"));
        assert!(parse_integrator_list(",").is_err());
    }

    #[test]
    fn path_means_volpath_in_scenes_with_media() {
        let mut entries = parse_integrator_list("path,volpath").unwrap();
        for entry in &mut entries {
            entry.resolve_path_tracer(false);
        }
        assert!(check_distinct(&entries).is_ok());
        for entry in &mut entries {
            entry.resolve_path_tracer(true);
        }
        assert_eq!(entries[0].label(), "volpath");
        assert!(check_distinct(&entries).is_err());
    }
}
