//! Mitsuba's emitters: `area` (inside a shape, with a constant or textured
//! radiance), `point`, `spot`, `directional`, `constant`, `envmap` and
//! `projector`. Constant RGB values of emitters are illuminants relative to
//! D65 (the scene build decides); textures (an area emitter's radiance, a
//! spot's texture, a projector's irradiance) are reflectance-like spectra
//! without D65, as Mitsuba 3 evaluates them. Defaults are Mitsuba's (unit
//! radiance, intensity or irradiance; a spot's cutoff of 20° with a beam
//! width of ¾ of it; a projector's 50 mm lens on 35 mm film).

use super::super::description::{
    EnvironmentProjection, LightDescription, ProjectorFovAxis, SpectrumDescription, SpotFalloff,
    TextureDescription,
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

    /// The radiance of an `area` emitter nested in a shape (a constant or a
    /// texture over the shape's uv), or `None` (with a warning) when it
    /// cannot be represented.
    pub(super) fn area_emitter(
        &mut self,
        element: &Element,
    ) -> Result<Option<TextureDescription>, SceneFileError> {
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
        let radiance = self.texture_parameter(&properties, "radiance")?.unwrap_or(
            TextureDescription::Constant(SpectrumDescription::Rgb([1.0; 3])),
        );
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
            "projector" => {
                let irradiance = self
                    .texture_parameter(&properties, "irradiance")?
                    .unwrap_or(TextureDescription::Constant(SpectrumDescription::Constant(
                        1.0,
                    )));
                let (fov_degrees, fov_axis) = match properties.optional_float("fov")? {
                    Some(fov) => {
                        let axis = match properties.optional_string("fov_axis")?.unwrap_or("x") {
                            "x" => ProjectorFovAxis::X,
                            "y" => ProjectorFovAxis::Y,
                            "diagonal" => ProjectorFovAxis::Diagonal,
                            "smaller" => ProjectorFovAxis::Smaller,
                            "larger" => ProjectorFovAxis::Larger,
                            other => {
                                return Err(element.location.error(format!(
                                    "projector: fov_axis '{other}': expected x, y, diagonal, smaller or larger"
                                )));
                            }
                        };
                        (fov, axis)
                    }
                    // Mitsuba's default: a 50 mm lens on 35 mm film (36 × 24 mm),
                    // the diagonal field of view (measured on Mitsuba 3.9.1:
                    // 39.54° horizontally for a 100 × 67 image).
                    None => {
                        let focal = properties
                            .optional_string("focal_length")?
                            .unwrap_or("50mm");
                        let millimetres = focal
                            .trim()
                            .trim_end_matches("mm")
                            .parse::<f32>()
                            .ok()
                            .filter(|f| *f > 0.0)
                            .ok_or_else(|| {
                                element.location.error(format!(
                                    "projector: focal_length '{focal}': expected a length such as 50mm"
                                ))
                            })?;
                        let diagonal = (36.0f32 * 36.0 + 24.0 * 24.0).sqrt();
                        (
                            2.0 * (diagonal / (2.0 * millimetres)).atan().to_degrees(),
                            ProjectorFovAxis::Diagonal,
                        )
                    }
                };
                if !(fov_degrees > 0.0 && fov_degrees < 180.0) {
                    return Err(element.location.error(format!(
                        "projector: fov {fov_degrees} must be in (0, 180) degrees"
                    )));
                }
                LightDescription::Projector {
                    to_world: to_world.unwrap_or(Affine3A::IDENTITY),
                    irradiance,
                    scale: properties.float("scale", 1.0)?,
                    fov_degrees,
                    fov_axis,
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
