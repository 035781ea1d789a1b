//! `LightSource` (`point`, `spot`, `distant`, `infinite`), `AreaLightSource
//! "diffuse"` and `MakeNamedMedium "homogeneous"`.
//!
//! pbrt-v4 normalises every light spectrum to luminance 1 before applying
//! `scale` (RGB values: only the colour space's illuminant, see
//! [`super::spectrum_values::light_normalisation`]), and `power` (point,
//! spot and area lights; in the renderer's luminance units) or
//! `illuminance` (distant and uniform infinite lights) set the brightness: point lights
//! divide the power by 4π, spot lights by 2π((1 − cos θ_start) + (cos θ_start
//! − cos θ_end)/2), area lights by π·area (twice that if two-sided),
//! uniform infinite lights divide the illuminance by π. Defaults: spectra are
//! the colour space's illuminant (D65, luminance 1; the renderer's RGB
//! (1, 1, 1)), `from` (0,0,0), `to` (0,0,1), spot `coneangle` 30°,
//! `conedelta` 5°.

use super::graphics_state::AreaLight;
use super::parameters::{ParameterList, Position};
use super::parser::Loader;
use super::spectrum_values::{light_normalisation, scaled};
use crate::scene::description::{
    EnvironmentProjection, LightDescription, MediumCoefficients, MediumDescription,
    PhaseDescription, SpectrumDescription, SpotFalloff,
};
use crate::scene::loader::SceneFileError;
use glam::{Affine3A, DVec3, Mat3, Vec3};
use std::f32::consts::PI;

/// The colour space's illuminant: D65 at luminance 1.
fn illuminant() -> SpectrumDescription {
    SpectrumDescription::Rgb([1.0, 1.0, 1.0])
}

impl Loader {
    /// A light's spectrum `name` (default D65) and its normalised `scale`.
    fn light_spectrum(
        &self,
        parameters: &ParameterList,
        name: &str,
        position: &Position,
    ) -> Result<(SpectrumDescription, f32), SceneFileError> {
        let spectrum = self
            .spectrum_parameter(parameters, name)?
            .unwrap_or_else(illuminant);
        let scale = parameters.float("scale", 1.0)?;
        if scale.is_nan() || scale < 0.0 {
            return Err(position.error(format!(
                "\"float scale\" must not be negative, found {scale}"
            )));
        }
        let normalisation = light_normalisation(&spectrum, position)?;
        Ok((spectrum, scale * normalisation))
    }

    /// `LightSource`.
    pub fn light_source(
        &mut self,
        kind: &str,
        parameters: &ParameterList,
        position: &Position,
    ) -> Result<(), SceneFileError> {
        let ctm = self.state.ctm;
        let light = match kind {
            "point" => {
                let (intensity, mut scale) = self.light_spectrum(parameters, "I", position)?;
                if let Some(power) = parameters.optional_float("power")?.filter(|&p| p > 0.0) {
                    scale *= power / (4.0 * PI);
                }
                let from = parameters.point3("from", [0.0; 3])?;
                LightDescription::Point {
                    position: ctm.transform_point3(vector(from)).as_vec3(),
                    intensity: scaled(intensity, scale),
                }
            }
            "spot" => {
                let (intensity, mut scale) = self.light_spectrum(parameters, "I", position)?;
                let cone_angle = parameters.float("coneangle", 30.0)?;
                let cone_delta = parameters.float("conedelta", 5.0)?;
                if !(cone_angle > 0.0 && cone_angle <= 180.0 && cone_delta >= 0.0) {
                    return Err(position.error(format!(
                        "LightSource \"spot\": expected 0 < coneangle ≤ 180 and conedelta ≥ 0, found {cone_angle} and {cone_delta}"
                    )));
                }
                let falloff_start = (cone_angle - cone_delta).max(0.0);
                if let Some(power) = parameters.optional_float("power")?.filter(|&p| p > 0.0) {
                    let cos_start = falloff_start.to_radians().cos();
                    let cos_end = cone_angle.to_radians().cos();
                    scale *= power / (2.0 * PI * ((1.0 - cos_start) + (cos_start - cos_end) / 2.0));
                }
                let from = vector(parameters.point3("from", [0.0; 3])?);
                let to = vector(parameters.point3("to", [0.0, 0.0, 1.0])?);
                let axis = (to - from).try_normalize().ok_or_else(|| {
                    position.error("LightSource \"spot\": \"from\" and \"to\" must differ")
                })?;
                let frame = frame_from_z(axis.as_vec3());
                let light_to_world = Affine3A::from_mat3_translation(frame, from.as_vec3());
                LightDescription::Spot {
                    to_world: Affine3A::from_mat4(ctm.as_mat4()) * light_to_world,
                    intensity: scaled(intensity, scale),
                    cutoff_degrees: cone_angle,
                    falloff_start_degrees: falloff_start,
                    falloff: SpotFalloff::PbrtSmoothstep,
                    texture: None,
                }
            }
            "distant" => {
                let (irradiance, mut scale) = self.light_spectrum(parameters, "L", position)?;
                if let Some(illuminance) = parameters
                    .optional_float("illuminance")?
                    .filter(|&e| e > 0.0)
                {
                    scale *= illuminance;
                }
                let from = vector(parameters.point3("from", [0.0; 3])?);
                let to = vector(parameters.point3("to", [0.0, 0.0, 1.0])?);
                let direction = ctm
                    .transform_vector3(to - from)
                    .try_normalize()
                    .ok_or_else(|| {
                        position.error("LightSource \"distant\": \"from\" and \"to\" must differ")
                    })?;
                LightDescription::Directional {
                    direction: direction.as_vec3(),
                    irradiance: scaled(irradiance, scale),
                }
            }
            "infinite" => {
                let filename = parameters.string("filename")?;
                if parameters.has("portal") {
                    parameters.find("portal");
                    self.warn(
                        position,
                        "LightSource \"infinite\": portals are not supported and are ignored",
                    );
                }
                match filename {
                    Some(filename) => {
                        if parameters.has("L") {
                            return Err(position.error(
                                "LightSource \"infinite\": give either \"L\" or \"filename\", not both",
                            ));
                        }
                        let path = self.resolve(&filename, position);
                        if !path.is_file() {
                            return Err(position.error(format!(
                                "LightSource \"infinite\": environment map \"{filename}\" not found (looked for {})",
                                path.display()
                            )));
                        }
                        let scale = parameters.float("scale", 1.0)?;
                        if parameters.optional_float("illuminance")?.is_some() {
                            self.warn(position, "LightSource \"infinite\": \"illuminance\" is not supported with an image; \"scale\" alone is used");
                        }
                        LightDescription::EnvironmentMap {
                            filename: path,
                            projection: EnvironmentProjection::PbrtEqualArea,
                            to_world: Affine3A::from_mat4(ctm.as_mat4()),
                            scale,
                        }
                    }
                    None => {
                        let (radiance, mut scale) =
                            self.light_spectrum(parameters, "L", position)?;
                        if let Some(illuminance) = parameters
                            .optional_float("illuminance")?
                            .filter(|&e| e > 0.0)
                        {
                            scale *= illuminance / PI;
                        }
                        LightDescription::ConstantEnvironment {
                            radiance: scaled(radiance, scale),
                        }
                    }
                }
            }
            other => {
                self.warn(
                    position,
                    format!("LightSource \"{other}\" is not supported and is skipped"),
                );
                for parameter in &parameters.parameters {
                    parameters.find(&parameter.name);
                }
                return Ok(());
            }
        };
        if self.current_object.is_some() {
            self.warn(
                position,
                "LightSource inside an object definition is added once, untransformed by instances",
            );
        }
        self.lights.push(light);
        Ok(())
    }

    /// `AreaLightSource`: shapes that follow in the same attribute block emit.
    pub fn area_light_source(
        &mut self,
        kind: &str,
        parameters: &ParameterList,
        position: &Position,
    ) -> Result<(), SceneFileError> {
        if kind != "diffuse" {
            self.warn(
                position,
                format!("AreaLightSource \"{kind}\" is not supported; the shapes that follow do not emit"),
            );
            for parameter in &parameters.parameters {
                parameters.find(&parameter.name);
            }
            self.state.area_light = None;
            return Ok(());
        }
        if parameters.string("filename")?.is_some() {
            self.warn(position, "AreaLightSource \"diffuse\": image emission (\"filename\") is not supported; \"L\" is used");
        }
        let (radiance, scale) = self.light_spectrum(parameters, "L", position)?;
        let power = parameters.optional_float("power")?.filter(|&p| p > 0.0);
        let two_sided = parameters.bool("twosided", false)?;
        self.state.area_light = Some(AreaLight {
            radiance,
            scale,
            power,
            two_sided,
            position: position.clone(),
        });
        Ok(())
    }

    /// `MakeNamedMedium`: homogeneous media (pbrt-v4's defaults: RGB
    /// σa = (0.0011, 0.0024, 0.014), σs = (2.55, 3.21, 3.77), `scale` 1,
    /// `g` 0).
    pub fn make_named_medium(
        &mut self,
        name: &str,
        parameters: &ParameterList,
        position: &Position,
    ) -> Result<(), SceneFileError> {
        let kind = parameters.string("type")?.ok_or_else(|| {
            position.error(format!(
                "MakeNamedMedium \"{name}\": expected a \"string type\" parameter"
            ))
        })?;
        if kind != "homogeneous" {
            self.warn(
                position,
                format!("MakeNamedMedium \"{name}\": medium type \"{kind}\" is not supported; shapes that name it see vacuum"),
            );
            for parameter in &parameters.parameters {
                parameters.find(&parameter.name);
            }
            return Ok(());
        }
        if parameters.string("preset")?.is_some() {
            self.warn(
                position,
                "MakeNamedMedium: \"preset\" is not supported; sigma_a and sigma_s are used",
            );
        }
        if parameters.has("Le") {
            parameters.find("Le");
            parameters.float("Lescale", 1.0)?;
            self.warn(
                position,
                "MakeNamedMedium: emissive media (\"Le\") are not supported",
            );
        }
        let sigma_a = self
            .spectrum_parameter(parameters, "sigma_a")?
            .unwrap_or(SpectrumDescription::Rgb([0.0011, 0.0024, 0.014]));
        let sigma_s = self
            .spectrum_parameter(parameters, "sigma_s")?
            .unwrap_or(SpectrumDescription::Rgb([2.55, 3.21, 3.77]));
        let scale = parameters.float("scale", 1.0)?;
        let g = parameters.float("g", 0.0)?;
        if !(g > -1.0 && g < 1.0) {
            return Err(position.error(format!(
                "MakeNamedMedium \"{name}\": \"float g\" must be in (-1, 1), found {g}"
            )));
        }
        let medium = MediumDescription {
            coefficients: MediumCoefficients::AbsorptionScattering { sigma_a, sigma_s },
            scale,
            phase: if g == 0.0 {
                PhaseDescription::Isotropic
            } else {
                PhaseDescription::HenyeyGreenstein { g }
            },
        };
        self.media.push(medium);
        let index = self.media.len() - 1;
        if self.named_media.insert(name.to_string(), index).is_some() {
            self.warn(position, format!("medium \"{name}\" redefined"));
        }
        Ok(())
    }
}

fn vector(p: [f32; 3]) -> DVec3 {
    DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64)
}

/// An orthonormal frame whose third axis is `z` (Duff et al. 2017's
/// branchless construction).
fn frame_from_z(z: Vec3) -> Mat3 {
    let sign = 1.0f32.copysign(z.z);
    let a = -1.0 / (sign + z.z);
    let b = z.x * z.y * a;
    let x = Vec3::new(1.0 + sign * z.x * z.x * a, sign * b, -sign * z.x);
    let y = Vec3::new(b, sign + z.y * z.y * a, -z.y);
    Mat3::from_cols(x, y, z)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn frames_are_orthonormal() {
        for z in [Vec3::Z, -Vec3::Z, Vec3::new(1.0, 2.0, -3.0).normalize()] {
            let frame = frame_from_z(z);
            assert!((frame.x_axis.dot(frame.y_axis)).abs() < 1e-6);
            assert!((frame.x_axis.length() - 1.0).abs() < 1e-6);
            assert!((frame.y_axis.length() - 1.0).abs() < 1e-6);
            assert!((frame.z_axis - z).length() < 1e-6);
        }
    }
}
