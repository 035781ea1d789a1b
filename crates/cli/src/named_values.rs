//! Command-line values from the renderer's own tables of names (e.g.
//! [`render::integrators::IntegratorKind::ALL`]): clap checks the name,
//! lists the possible values in `--help` and in its error, and hands over
//! the renderer's value. The names live once, beside the values, so the
//! command line mirrors no enum by hand.

use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use std::ffi::OsStr;

/// A value parser for the values of `names`: (value, name, help line).
#[derive(Clone)]
pub struct NamedValues<T> {
    names: Vec<(T, &'static str, Option<&'static str>)>,
}

impl<T: Copy + Send + Sync + 'static> NamedValues<T> {
    /// The values of a table of (value, name) pairs.
    pub fn new(names: impl IntoIterator<Item = (T, &'static str)>) -> Self {
        Self {
            names: names
                .into_iter()
                .map(|(value, name)| (value, name, None))
                .collect(),
        }
    }

    /// The values of a table of (value, name) pairs, each with the help
    /// line `help` gives it.
    pub fn with_help(
        names: impl IntoIterator<Item = (T, &'static str)>,
        help: impl Fn(T) -> &'static str,
    ) -> Self {
        Self {
            names: names
                .into_iter()
                .map(|(value, name)| (value, name, Some(help(value))))
                .collect(),
        }
    }

    fn possible(&self) -> impl Iterator<Item = PossibleValue> + '_ {
        self.names.iter().map(|(_, name, help)| {
            let value = PossibleValue::new(*name);
            match help {
                Some(help) => value.help(*help),
                None => value,
            }
        })
    }
}

impl<T: Copy + Send + Sync + 'static> TypedValueParser for NamedValues<T> {
    type Value = T;

    fn parse_ref(
        &self,
        command: &clap::Command,
        argument: Option<&clap::Arg>,
        value: &OsStr,
    ) -> Result<T, clap::Error> {
        // clap's own check, for its error message with the possible values.
        let name =
            PossibleValuesParser::new(self.possible()).parse_ref(command, argument, value)?;
        Ok(self
            .names
            .iter()
            .find(|(_, known, _)| *known == name)
            .map(|(value, ..)| *value)
            .expect("the possible values are the table's names"))
    }

    fn possible_values(&self) -> Option<Box<dyn Iterator<Item = PossibleValue> + '_>> {
        Some(Box::new(self.possible()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::{Arg, Command};

    fn command() -> Command {
        Command::new("test").arg(
            Arg::new("mode")
                .long("mode")
                .value_parser(NamedValues::new([(1u8, "one"), (2, "two")])),
        )
    }

    #[test]
    fn names_become_their_values_and_others_are_refused_with_the_list() {
        let matches = command().try_get_matches_from(["test", "--mode", "two"]);
        assert_eq!(matches.unwrap().get_one::<u8>("mode"), Some(&2));
        let error = command()
            .try_get_matches_from(["test", "--mode", "three"])
            .unwrap_err()
            .to_string();
        assert!(
            error.contains("three") && error.contains("one, two"),
            "{error}"
        );
    }
}
