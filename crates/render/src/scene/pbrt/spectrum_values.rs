//! Spectral parameters: `rgb` triples, `blackbody` temperatures and
//! `spectrum` values (inline wavelength–value pairs, one of pbrt-v4's named
//! spectra such as `metal-Cu-eta`, or a file of pairs), and pbrt-v4's
//! photometric normalisation of light spectra.

use super::parameters::{Parameter, ParameterList, Position, Values};
use super::parser::{Loader, parse_number};
use crate::scene::description::SpectrumDescription;
use crate::scene::loader::SceneFileError;
use crate::scene::spectra::{SpectrumUsage, build_spectrum};
use crate::spectrum::{CIE_LAMBDA_MAX, CIE_LAMBDA_MIN, CIE_Y_INTEGRAL, cie_y};

impl Loader {
    /// The spectrum a spectral parameter (`rgb`, `blackbody`, `spectrum`) holds.
    pub fn spectrum_of(
        &self,
        parameter: &Parameter,
    ) -> Result<SpectrumDescription, SceneFileError> {
        let error = |message: String| {
            parameter
                .position
                .error(format!("parameter {}: {message}", parameter.describe()))
        };
        match (parameter.type_name, parameter.spectrum_values()) {
            ("rgb", Values::Numbers(v)) if v.len() == 3 => {
                let rgb = [v[0] as f32, v[1] as f32, v[2] as f32];
                if rgb.iter().any(|c| !(c.is_finite() && *c >= 0.0)) {
                    return Err(error(format!(
                        "expected three non-negative finite numbers, found {v:?}"
                    )));
                }
                Ok(SpectrumDescription::Rgb(rgb))
            }
            ("rgb", values) => Err(error(format!(
                "expected three numbers, found {}",
                describe_count(values)
            ))),
            ("blackbody", Values::Numbers(v)) if v.len() == 1 => {
                if !(v[0] > 0.0 && v[0].is_finite()) {
                    return Err(error(format!(
                        "expected a positive temperature in kelvin, found {}",
                        v[0]
                    )));
                }
                Ok(SpectrumDescription::Blackbody {
                    temperature: v[0] as f32,
                })
            }
            ("blackbody", values) => Err(error(format!(
                "expected one temperature, found {}",
                describe_count(values)
            ))),
            ("spectrum", Values::Numbers(v)) => sampled_from_pairs(v).map_err(&error),
            ("spectrum", Values::Strings(names)) if names.len() == 1 => {
                self.spectrum_from_name(&names[0], &parameter.position)
            }
            ("spectrum", _) => Err(error(
                "expected wavelength-value pairs, or one named spectrum or file".into(),
            )),
            (other, _) => Err(error(format!(
                "has type '{other}' but a spectrum ('rgb', 'spectrum' or 'blackbody') is needed"
            ))),
        }
    }

    /// A named spectrum (`"spectrum eta" "metal-Au-eta"`) or a file of
    /// wavelength-value pairs. A name that is not an existing file and has no
    /// extension or directory is taken as one of pbrt-v4's named spectra
    /// (resolved when the scene is built).
    fn spectrum_from_name(
        &self,
        name: &str,
        position: &Position,
    ) -> Result<SpectrumDescription, SceneFileError> {
        let path = self.resolve(name, position);
        if path.is_file() {
            let text = std::fs::read_to_string(&path).map_err(|source| {
                position.error(format!(
                    "cannot read the spectrum file {}: {source}",
                    path.display()
                ))
            })?;
            let mut numbers = Vec::new();
            for (index, line) in text.lines().enumerate() {
                let content = line.split('#').next().unwrap_or("");
                for word in content.split(|c: char| c.is_whitespace() || c == ',') {
                    if word.is_empty() {
                        continue;
                    }
                    numbers.push(parse_number(word).ok_or_else(|| SceneFileError::Syntax {
                        file: path.clone(),
                        line: index as u32 + 1,
                        message: format!("expected a number in the spectrum file, found '{word}'"),
                    })?);
                }
            }
            return sampled_from_pairs(&numbers).map_err(|message| SceneFileError::Syntax {
                file: path.clone(),
                line: 1,
                message,
            });
        }
        if name.contains('.') || name.contains('/') || name.contains('\\') {
            return Err(position.error(format!(
                "spectrum file \"{name}\" not found (looked for {})",
                path.display()
            )));
        }
        Ok(SpectrumDescription::Named(name.to_string()))
    }

    /// The spectrum of parameter `name` if present and spectral (an error if
    /// it has another type).
    pub fn spectrum_parameter(
        &self,
        parameters: &ParameterList,
        name: &str,
    ) -> Result<Option<SpectrumDescription>, SceneFileError> {
        match parameters.find(name) {
            None => Ok(None),
            Some(p) => self.spectrum_of(p).map(Some),
        }
    }
}

fn describe_count(values: &Values) -> String {
    match values {
        Values::Numbers(v) => format!("{} numbers", v.len()),
        Values::Strings(v) => format!("{} strings", v.len()),
        Values::Bools(v) => format!("{} booleans", v.len()),
    }
}

/// Inline wavelength–value pairs with increasing wavelengths.
fn sampled_from_pairs(numbers: &[f64]) -> Result<SpectrumDescription, String> {
    if numbers.len() < 2 || !numbers.len().is_multiple_of(2) {
        return Err(format!(
            "expected wavelength-value pairs, found {} numbers",
            numbers.len()
        ));
    }
    let wavelengths: Vec<f32> = numbers.iter().step_by(2).map(|&v| v as f32).collect();
    let values: Vec<f32> = numbers
        .iter()
        .skip(1)
        .step_by(2)
        .map(|&v| v as f32)
        .collect();
    if wavelengths
        .windows(2)
        .any(|w| w[0].partial_cmp(&w[1]) != Some(std::cmp::Ordering::Less))
    {
        return Err("the wavelengths of a spectrum must increase".into());
    }
    if values.iter().any(|v| !v.is_finite()) {
        return Err("spectrum values must be finite".into());
    }
    Ok(SpectrumDescription::Sampled {
        wavelengths,
        values,
    })
}

/// The luminance Y of a spectrum in the renderer's normalisation
/// (Σ_λ S(λ) ȳ(λ) / ∫ȳ over 360–830 nm in 1 nm steps; the constant 1 has Y = 1).
pub fn luminance(
    spectrum: &SpectrumDescription,
    position: &Position,
) -> Result<f64, SceneFileError> {
    let built = build_spectrum(spectrum, SpectrumUsage::Illuminant, "light spectrum")
        .map_err(|error| position.error(error.to_string()))?;
    let y = cie_y();
    let sum: f64 = (CIE_LAMBDA_MIN..=CIE_LAMBDA_MAX)
        .map(|lambda| {
            f64::from(built.evaluate(lambda as f32)) * f64::from(y.evaluate(lambda as f32))
        })
        .sum();
    Ok(sum / f64::from(CIE_Y_INTEGRAL))
}

/// pbrt-v4's light normalisation: every light's spectrum is divided by its
/// luminance, so that `scale` (and `power`) set the light's brightness and
/// the spectrum only its colour — except RGB values, whose spectrum is the
/// RGB's sigmoid times the colour space's illuminant and of which only the
/// illuminant is normalised (pbrt-v4 `SpectrumToPhotometric`). The
/// renderer's RGB illuminant spectra are already D65 at luminance 1, so RGB
/// stays as it is. Returns the factor to multiply the spectrum by.
pub fn light_normalisation(
    spectrum: &SpectrumDescription,
    position: &Position,
) -> Result<f32, SceneFileError> {
    match spectrum {
        SpectrumDescription::Rgb(_) => Ok(1.0),
        other => {
            let y = luminance(other, position)?;
            if y > 0.0 && y.is_finite() {
                Ok((1.0 / y) as f32)
            } else {
                Err(position
                    .error("a light spectrum has no luminance (it is zero over the visible range)"))
            }
        }
    }
}

/// `spectrum` times `factor`, without a wrapper when the factor is 1.
pub fn scaled(spectrum: SpectrumDescription, factor: f32) -> SpectrumDescription {
    if factor == 1.0 {
        spectrum
    } else {
        match spectrum {
            SpectrumDescription::Constant(value) => SpectrumDescription::Constant(value * factor),
            SpectrumDescription::Scaled { scale, spectrum } => SpectrumDescription::Scaled {
                scale: scale * factor,
                spectrum,
            },
            other => SpectrumDescription::Scaled {
                scale: factor,
                spectrum: Box::new(other),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;
    use std::sync::Arc;

    fn position() -> Position {
        Position {
            file: Arc::from(Path::new("scene.pbrt")),
            line: 3,
        }
    }

    #[test]
    fn blackbody_and_constant_lights_get_unit_luminance() {
        for spectrum in [
            SpectrumDescription::Blackbody {
                temperature: 3000.0,
            },
            SpectrumDescription::Constant(2.0),
        ] {
            let factor = light_normalisation(&spectrum, &position()).unwrap();
            let normalised = scaled(spectrum, factor);
            let y = luminance(&normalised, &position()).unwrap();
            assert!((y - 1.0).abs() < 1e-4, "{normalised:?}: {y}");
        }
        assert_eq!(
            light_normalisation(&SpectrumDescription::Rgb([1.0, 2.0, 3.0]), &position()).unwrap(),
            1.0
        );
    }

    #[test]
    fn pairs_must_increase_and_pair_up() {
        assert!(sampled_from_pairs(&[400.0, 1.0, 500.0]).is_err());
        assert!(sampled_from_pairs(&[500.0, 1.0, 400.0, 1.0]).is_err());
        assert_eq!(
            sampled_from_pairs(&[400.0, 1.0, 500.0, 2.0]).unwrap(),
            SpectrumDescription::Sampled {
                wavelengths: vec![400.0, 500.0],
                values: vec![1.0, 2.0]
            }
        );
    }
}
