//! Turning the scene description's [`SpectrumDescription`]s into
//! [`Spectrum`]s, according to what the quantity is ([`SpectrumUsage`]).

use super::SceneError;
use super::description::SpectrumDescription;
use crate::spectrum::{
    BlackbodyNormalisation, BlackbodySpectrum, CIE_LAMBDA_MAX, CIE_LAMBDA_MIN, ConstantSpectrum,
    PiecewiseLinearSpectrum, RgbAlbedoSpectrum, RgbIlluminantSpectrum, RgbUnboundedSpectrum,
    Spectrum, d65_illuminant,
};

/// What a spectral quantity is: it decides how an RGB triple is lifted to a
/// spectrum (Jakob–Hanika sigmoid for reflectances, scaled sigmoid for
/// unbounded quantities, scaled sigmoid times D65 for illuminants).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpectrumUsage {
    /// A reflectance or transmittance in [0, 1].
    Albedo,
    /// A non-negative quantity that may exceed 1 (η, κ, σ).
    Unbounded,
    /// Emitted radiance, intensity or irradiance.
    Illuminant,
}

fn parameter_error(what: &str, error: impl std::fmt::Display) -> SceneError {
    SceneError::Parameter {
        what: what.to_string(),
        message: error.to_string(),
    }
}

/// The spectrum a description stands for, used as `usage`; `what` names the
/// parameter in errors.
pub fn build_spectrum(
    description: &SpectrumDescription,
    usage: SpectrumUsage,
    what: &str,
) -> Result<Spectrum, SceneError> {
    let error = |e| parameter_error(what, e);
    Ok(match description {
        SpectrumDescription::Rgb(rgb) => match usage {
            SpectrumUsage::Albedo => {
                Spectrum::RgbAlbedo(RgbAlbedoSpectrum::new(*rgb).map_err(error)?)
            }
            SpectrumUsage::Unbounded => {
                Spectrum::RgbUnbounded(RgbUnboundedSpectrum::new(*rgb).map_err(error)?)
            }
            SpectrumUsage::Illuminant => {
                Spectrum::RgbIlluminant(RgbIlluminantSpectrum::new(*rgb).map_err(error)?)
            }
        },
        SpectrumDescription::Constant(value) => {
            Spectrum::Constant(ConstantSpectrum::new(*value).map_err(error)?)
        }
        SpectrumDescription::Sampled {
            wavelengths,
            values,
        } => {
            if wavelengths.len() != values.len() {
                return Err(parameter_error(
                    what,
                    format!(
                        "{} wavelengths but {} values",
                        wavelengths.len(),
                        values.len()
                    ),
                ));
            }
            let samples: Vec<(f32, f32)> = wavelengths
                .iter()
                .copied()
                .zip(values.iter().copied())
                .collect();
            Spectrum::PiecewiseLinear(PiecewiseLinearSpectrum::new(&samples).map_err(error)?)
        }
        SpectrumDescription::Named(name) => named_spectrum(name)
            .ok_or_else(|| parameter_error(what, format!("unknown named spectrum '{name}'")))?,
        SpectrumDescription::Blackbody { temperature } => Spectrum::Blackbody(
            BlackbodySpectrum::new(*temperature, BlackbodyNormalisation::PeakOne).map_err(error)?,
        ),
        SpectrumDescription::Scaled { scale, spectrum } => {
            if !(scale.is_finite() && *scale >= 0.0) {
                return Err(parameter_error(
                    what,
                    format!("scale must be finite and non-negative, got {scale}"),
                ));
            }
            let inner = build_spectrum(spectrum, usage, what)?;
            match inner {
                Spectrum::Constant(constant) => Spectrum::Constant(
                    ConstantSpectrum::new(constant.evaluate(0.0) * scale).map_err(error)?,
                ),
                other => Spectrum::DenselySampled(
                    other
                        .to_densely_sampled(CIE_LAMBDA_MIN, CIE_LAMBDA_MAX)
                        .map_err(error)?
                        .scaled(*scale),
                ),
            }
        }
    })
}

/// Spectra known by name (pbrt-v4's named spectra). Loaders map their own
/// names (e.g. Mitsuba's conductor `material` strings) onto these.
pub fn named_spectrum(name: &str) -> Option<Spectrum> {
    match name {
        "stdillum-D65" => Some(Spectrum::DenselySampled(d65_illuminant().clone())),
        _ => None,
    }
}
