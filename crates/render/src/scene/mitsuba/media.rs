//! Mitsuba's `homogeneous` medium: `sigma_t` (default 1), `albedo`
//! (default 0.75), `scale` (default 1) and a `phase` function (`isotropic`,
//! the default, or `hg` with `g`, default 0.8).

use super::super::description::{
    MediumCoefficients, MediumDescription, PhaseDescription, SpectrumDescription,
};
use super::super::loader::SceneFileError;
use super::values::Properties;
use super::xml::Element;
use super::{Loader, NamedObject};

impl Loader {
    /// Reads a `<medium>` (or the `<ref>` of one): its index in the
    /// description's media, or `None` (with a warning) for a medium type
    /// that is not supported.
    pub(super) fn medium(&mut self, element: &Element) -> Result<Option<usize>, SceneFileError> {
        if element.tag == "ref" {
            return match self.referenced(element)? {
                NamedObject::Medium(index) => Ok(Some(index)),
                other => Err(element.location.error(format!(
                    "expected a reference to a medium, got a {}",
                    other.kind()
                ))),
            };
        }
        let properties = Properties::new(element);
        if properties.plugin_type() != "homogeneous" {
            self.warn(
                element,
                format!(
                    "medium type '{}' is not supported (only 'homogeneous'): it is left out",
                    properties.plugin_type()
                ),
            );
            self.register(element, NamedObject::Other("unsupported medium".into()))?;
            return Ok(None);
        }
        let sigma_t = self
            .spectrum_parameter(&properties, "sigma_t")?
            .unwrap_or(SpectrumDescription::Constant(1.0));
        let albedo = self
            .spectrum_parameter(&properties, "albedo")?
            .unwrap_or(SpectrumDescription::Constant(0.75));
        let scale = properties.float("scale", 1.0)?;
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(element.location.error(format!(
                "medium scale {scale} must be finite and non-negative"
            )));
        }
        properties.ignore(&["sample_emitters"]);
        let mut phase = PhaseDescription::Isotropic;
        for object in &properties.objects {
            if object.tag != "phase" {
                self.warn(
                    object,
                    format!("<{}> inside <medium> is ignored", object.tag),
                );
                continue;
            }
            let phase_properties = Properties::new(object);
            phase = match phase_properties.plugin_type() {
                "isotropic" => PhaseDescription::Isotropic,
                "hg" => {
                    let g = phase_properties.float("g", 0.8)?;
                    if !(g > -1.0 && g < 1.0) {
                        return Err(object
                            .location
                            .error(format!("hg phase function: g = {g} must be in (-1, 1)")));
                    }
                    PhaseDescription::HenyeyGreenstein { g }
                }
                other => {
                    self.warn(
                        object,
                        format!("phase function '{other}' is not supported: isotropic is used"),
                    );
                    PhaseDescription::Isotropic
                }
            };
            self.finish(&phase_properties);
        }
        self.finish(&properties);
        let index = self.description.media.len();
        self.description.media.push(MediumDescription {
            coefficients: MediumCoefficients::AlbedoExtinction { albedo, sigma_t },
            scale,
            phase,
        });
        self.register(element, NamedObject::Medium(index))?;
        Ok(Some(index))
    }
}
