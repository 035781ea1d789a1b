//! Mitsuba's emitters: `area` (inside a shape), `point`, `spot`,
//! `directional`, `constant` and `envmap`. RGB values of emitters are
//! illuminants relative to D65 (the scene build decides); defaults are
//! Mitsuba's (unit radiance, intensity or irradiance; a spot's cutoff of 20°
//! with a beam width of ¾ of it).

use super::super::description::{
    EnvironmentProjection, LightDescription, SpectrumDescription, SpotFalloff, TextureDescription,
};
use super::super::loader::SceneFileError;
use super::values::Properties;
use super::xml::Element;
use super::{Loader, NamedObject};
use glam::{Affine3A, Vec3};

impl Loader {
    /// An emitter's spectral parameter (default 1).
    fn emitted(
        &mut self,
        properties: &Properties,
        name: &str,
    ) -> Result<SpectrumDescription, SceneFileError> {
        Ok(self
            .spectrum_parameter(properties, name)?
            .unwrap_or(SpectrumDescription::Rgb([1.0; 3])))
    }

    /// The radiance of an `area` emitter nested in a shape, or `None` (with
    /// a warning) when it cannot be represented.
    pub(super) fn area_emitter(
        &mut self,
        element: &Element,
    ) -> Result<Option<SpectrumDescription>, SceneFileError> {
        let properties = Properties::new(element);
        if properties.plugin_type() != "area" {
            self.warn(
                element,
                format!(
                    "emitter '{}' inside a shape is not supported (only 'area'): it is left out",
                    properties.plugin_type()
                ),
            );
            return Ok(None);
        }
        let radiance = match self.texture_parameter(&properties, "radiance")? {
            None => SpectrumDescription::Rgb([1.0; 3]),
            Some(TextureDescription::Constant(spectrum)) => spectrum,
            Some(_) => {
                self.warn(
                    element,
                    "textured area emitters are not supported: this emitter is left out",
                );
                self.finish(&properties);
                self.register(element, NamedObject::AreaEmitter(None))?;
                return Ok(None);
            }
        };
        self.finish(&properties);
        self.register(element, NamedObject::AreaEmitter(Some(radiance.clone())))?;
        Ok(Some(radiance))
    }

    /// Reads a top-level `<emitter>`.
    pub(super) fn emitter(&mut self, element: &Element) -> Result<(), SceneFileError> {
        let properties = Properties::new(element);
        let kind = properties.plugin_type();
        let to_world = properties.optional_transform("to_world")?;
        let light = match kind {
            "point" => {
                let position = match properties.optional_vector("position")? {
                    Some(position) => position,
                    None => to_world.map_or(Vec3::ZERO, |m| m.translation.into()),
                };
                LightDescription::Point {
                    position,
                    intensity: self.emitted(&properties, "intensity")?,
                }
            }
            "spot" => {
                let cutoff = properties.float("cutoff_angle", 20.0)?;
                let beam_width = properties.float("beam_width", cutoff * 0.75)?;
                if !(cutoff > 0.0 && cutoff <= 90.0 && beam_width >= 0.0) {
                    return Err(element.location.error(format!(
                        "spot: cutoff_angle {cutoff} must be in (0, 90] degrees and beam_width {beam_width} non-negative"
                    )));
                }
                let texture = self.texture_parameter(&properties, "texture")?;
                LightDescription::Spot {
                    to_world: to_world.unwrap_or(Affine3A::IDENTITY),
                    intensity: self.emitted(&properties, "intensity")?,
                    cutoff_degrees: cutoff,
                    falloff_start_degrees: beam_width.min(cutoff),
                    falloff: SpotFalloff::MitsubaLinearAngle,
                    texture,
                }
            }
            "directional" => {
                let direction = match properties.optional_vector("direction")? {
                    Some(direction) => direction,
                    None => to_world.map_or(Vec3::Z, |m| m.transform_vector3(Vec3::Z)),
                };
                let direction = direction.normalize_or_zero();
                if direction == Vec3::ZERO {
                    return Err(element.location.error("directional: the direction is zero"));
                }
                LightDescription::Directional {
                    direction,
                    irradiance: self.emitted(&properties, "irradiance")?,
                }
            }
            "constant" => LightDescription::ConstantEnvironment {
                radiance: self.emitted(&properties, "radiance")?,
            },
            "envmap" => {
                let name = properties
                    .optional_string("filename")?
                    .ok_or_else(|| element.location.error("envmap needs a 'filename' string"))?;
                let filename = self.resolve(element, name, "environment map")?;
                LightDescription::EnvironmentMap {
                    filename,
                    projection: EnvironmentProjection::MitsubaEquirectangular,
                    to_world: to_world.unwrap_or(Affine3A::IDENTITY),
                    scale: properties.float("scale", 1.0)?,
                }
            }
            "area" if element.attribute("id").is_some() => {
                // Defined for a shape's `<ref>` (Mitsuba's Cornell box does this).
                let _ = self.area_emitter(element)?;
                return Ok(());
            }
            "area" => {
                return Err(element.location.error(
                    "an 'area' emitter must be nested in the <shape> it covers, or have an id that a shape refers to",
                ));
            }
            other => {
                self.warn(
                    element,
                    format!("emitter type '{other}' is not supported: it is left out"),
                );
                return Ok(());
            }
        };
        self.finish(&properties);
        self.register(element, NamedObject::Other("emitter".into()))?;
        self.description.lights.push(light);
        Ok(())
    }
}
