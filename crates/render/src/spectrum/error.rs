//! Errors raised when a spectrum or a wavelength sample is built from bad input.

use thiserror::Error;

/// What was wrong with the input to a spectrum constructor.
///
/// Spectra are built once (when a scene is loaded) and evaluated millions of
/// times, so all validation happens in the constructors and evaluation never fails.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum SpectrumError {
    /// A value that must be a finite number was NaN or infinite.
    #[error("{what} must be finite, got {value}")]
    NotFinite {
        /// Which input was wrong.
        what: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A value that must be non-negative was negative.
    #[error("{what} must be non-negative, got {value}")]
    Negative {
        /// Which input was wrong.
        what: &'static str,
        /// The offending value.
        value: f64,
    },
    /// A reflectance (albedo) component was outside [0, 1].
    #[error("albedo component {value} is outside [0, 1]")]
    AlbedoOutOfRange {
        /// The offending component.
        value: f64,
    },
    /// A temperature was not strictly positive.
    #[error("blackbody temperature must be > 0 K, got {kelvin} K")]
    NonPositiveTemperature {
        /// The offending temperature in kelvin.
        kelvin: f64,
    },
    /// A wavelength interval was empty or reversed.
    #[error("wavelength range [{min}, {max}] nm is empty or reversed")]
    EmptyRange {
        /// Lower end in nm.
        min: f64,
        /// Upper end in nm.
        max: f64,
    },
    /// Tabulated data had no entries.
    #[error("a tabulated spectrum needs at least one sample")]
    NoSamples,
    /// Wavelengths of tabulated data were not strictly increasing.
    #[error("tabulated wavelengths must increase strictly: {previous} nm is followed by {next} nm")]
    WavelengthsNotIncreasing {
        /// The earlier wavelength in nm.
        previous: f64,
        /// The later (not larger) wavelength in nm.
        next: f64,
    },
    /// Interleaved (wavelength, value) data had an odd number of entries.
    #[error("interleaved (wavelength, value) data needs an even number of entries, got {len}")]
    OddInterleavedLength {
        /// The number of entries.
        len: usize,
    },
    /// A lookup-table resolution was too small to interpolate.
    #[error("RGB-to-spectrum table resolution must be at least 2, got {resolution}")]
    TableResolutionTooSmall {
        /// The requested resolution.
        resolution: usize,
    },
    /// A table tabulated per nm was empty, too long, or started too far from
    /// 0 nm for its indices to be computed without overflow (see
    /// [`super::DenselySampledSpectrum::from_values`]).
    #[error("a per-nm table of {len} entries from {lambda_min} nm is out of the supported range")]
    TableOutOfRange {
        /// The first tabulated wavelength in nm.
        lambda_min: i64,
        /// The number of entries.
        len: usize,
    },
    /// Stored RGB-to-spectrum table data (see
    /// [`super::RgbToSpectrumTable::from_bytes`]) was malformed.
    #[error("malformed RGB-to-spectrum table data: {reason}")]
    MalformedTableData {
        /// What was wrong.
        reason: String,
    },
}

/// Returns `Ok(value)` if finite, otherwise [`SpectrumError::NotFinite`].
pub(crate) fn require_finite(what: &'static str, value: f32) -> Result<f32, SpectrumError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(SpectrumError::NotFinite {
            what,
            value: f64::from(value),
        })
    }
}

/// Returns `Ok(value)` if finite and non-negative, otherwise the matching error.
pub(crate) fn require_non_negative(what: &'static str, value: f32) -> Result<f32, SpectrumError> {
    require_finite(what, value)?;
    if value < 0.0 {
        Err(SpectrumError::Negative {
            what,
            value: f64::from(value),
        })
    } else {
        Ok(value)
    }
}
