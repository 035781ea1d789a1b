//! Errors raised when a shading frame, a BSDF or a material is built from bad
//! input.
//!
//! Materials are validated once, when a scene is loaded
//! ([`super::Material::validate`]); building and evaluating BSDFs at every hit
//! then never fails.

use thiserror::Error;

use crate::spectrum::SampledSpectrum;

/// What was wrong with the input to a shading-frame, BSDF or material
/// constructor.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum MaterialError {
    /// A vector that must give a direction was zero, NaN or infinite.
    #[error("{what} must be a finite non-zero vector, got {vector:?}")]
    InvalidDirection {
        /// Which input was wrong.
        what: &'static str,
        /// The offending vector.
        vector: [f32; 3],
    },
    /// A sampled spectral value was NaN, infinite or out of its range.
    #[error("{what} must be {requirement}, got {value}")]
    InvalidValue {
        /// Which input was wrong.
        what: &'static str,
        /// What the value must be ("finite and non-negative", …).
        requirement: &'static str,
        /// The offending value.
        value: f32,
    },
    /// A spectrum took a NaN, infinite or out-of-range value in the visible
    /// range.
    #[error("{what} must be {requirement}, got {value} at {lambda} nm")]
    InvalidSpectrumValue {
        /// Which input was wrong.
        what: &'static str,
        /// What the value must be ("finite and non-negative", …).
        requirement: &'static str,
        /// The offending value.
        value: f32,
        /// The wavelength (nm) where it occurred.
        lambda: f32,
    },
    /// A relative index of refraction was not strictly positive.
    #[error("a relative index of refraction must be > 0, got {value}")]
    NonPositiveIndexOfRefraction {
        /// The offending value.
        value: f32,
    },
}

/// Returns the spectrum if every component is finite and non-negative,
/// otherwise [`MaterialError::InvalidValue`] naming the first bad component.
pub(crate) fn require_finite_non_negative(
    what: &'static str,
    spectrum: SampledSpectrum,
) -> Result<SampledSpectrum, MaterialError> {
    match spectrum
        .values()
        .iter()
        .find(|value| !(value.is_finite() && **value >= 0.0))
    {
        Some(&value) => Err(MaterialError::InvalidValue {
            what,
            requirement: "finite and non-negative",
            value,
        }),
        None => Ok(spectrum),
    }
}
