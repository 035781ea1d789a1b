//! Mitsuba's `<integrator>`: its type is recorded as a hint (the command
//! line chooses the integrator) and its `max_depth` becomes the scene's
//! suggested depth (−1, Mitsuba's default, means unlimited: `u32::MAX`).
//! `direct` is depth 2 (emitters and direct light). `moment` and other
//! wrappers are looked through to their nested integrator. A type this
//! renderer does not know (Bitterli's files name `path_guiding_integrator`)
//! is a warning; its `max_depth` is still used. Its `rr_depth` (Mitsuba's
//! default 5 where the file names none) becomes the scene's suggested
//! Russian-roulette depth, so a Mitsuba scene renders with Mitsuba's settings.

use super::super::loader::SceneFileError;
use super::Loader;
use super::values::Properties;
use super::xml::Element;

/// The integrator types whose images this renderer's path tracer matches
/// in expectation.
const KNOWN: &[&str] = &["path", "volpath", "volpathmis", "direct", "ptracer"];

/// Mitsuba 3's `rr_depth` where an integrator names none (its `path`,
/// `volpath`, `volpathmis` and `ptracer` plugins' documented default).
const MITSUBA_DEFAULT_RR_DEPTH: u32 = 5;

impl Loader {
    /// Reads an `<integrator>`.
    pub(super) fn integrator(&mut self, element: &Element) -> Result<(), SceneFileError> {
        let properties = Properties::new(element);
        let kind = properties.plugin_type();
        if matches!(kind, "moment" | "aov") {
            properties.ignore(&["aovs"]);
            self.finish(&properties);
            let nested: Vec<&Element> = properties
                .objects
                .iter()
                .copied()
                .filter(|object| object.tag == "integrator")
                .collect();
            return match nested.first() {
                Some(inner) => self.integrator(inner),
                None => {
                    self.warn(
                        element,
                        format!("integrator '{kind}' has no nested integrator"),
                    );
                    Ok(())
                }
            };
        }
        if !KNOWN.contains(&kind) {
            self.warn(
                element,
                format!(
                    "unknown integrator '{kind}': the command line's integrator is used (its max_depth is kept)"
                ),
            );
        }
        let max_depth = match properties.optional_integer("max_depth")? {
            Some(-1) | None => u32::MAX,
            Some(depth) if depth >= 1 => u32::try_from(depth).unwrap_or(u32::MAX),
            Some(depth) => {
                return Err(element.location.error(format!(
                    "max_depth {depth} must be -1 (unlimited) or at least 1"
                )));
            }
        };
        self.description.max_depth = Some(if kind == "direct" { 2 } else { max_depth });
        let russian_roulette_depth = match properties.optional_integer("rr_depth")? {
            None => MITSUBA_DEFAULT_RR_DEPTH,
            Some(depth) if depth >= 1 => u32::try_from(depth).unwrap_or(u32::MAX),
            Some(depth) => {
                return Err(element
                    .location
                    .error(format!("rr_depth {depth} must be at least 1")));
            }
        };
        self.description.russian_roulette_depth = Some(russian_roulette_depth);
        self.description.integrator = Some(kind.to_string());
        properties.ignore(&[
            "hide_emitters",
            "emitter_samples",
            "bsdf_samples",
            "shading_samples",
            "samples_per_pass",
            "timeout",
        ]);
        self.finish(&properties);
        Ok(())
    }
}
