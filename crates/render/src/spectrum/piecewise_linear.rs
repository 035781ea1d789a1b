//! A spectrum given by (wavelength, value) samples joined by straight lines: the
//! form of most measured data (indices of refraction, reflectances, emission
//! spectra of lamps).

use super::error::{SpectrumError, require_finite};
use super::sampled_spectrum::SampledSpectrum;
use super::wavelengths::SampledWavelengths;

/// Linear interpolation between samples at strictly increasing wavelengths;
/// 0 outside [first wavelength, last wavelength] (as in pbrt-v4).
#[derive(Debug, Clone, PartialEq)]
pub struct PiecewiseLinearSpectrum {
    lambdas: Vec<f32>,
    values: Vec<f32>,
}

impl PiecewiseLinearSpectrum {
    /// Builds the spectrum from `(wavelength nm, value)` pairs. Fails if there are
    /// none, if a number is not finite, or if the wavelengths do not increase
    /// strictly.
    pub fn new(samples: &[(f32, f32)]) -> Result<Self, SpectrumError> {
        if samples.is_empty() {
            return Err(SpectrumError::NoSamples);
        }
        for &(lambda, value) in samples {
            require_finite("tabulated wavelength", lambda)?;
            require_finite("tabulated spectrum value", value)?;
        }
        for pair in samples.windows(2) {
            if pair[1].0 <= pair[0].0 {
                return Err(SpectrumError::WavelengthsNotIncreasing {
                    previous: f64::from(pair[0].0),
                    next: f64::from(pair[1].0),
                });
            }
        }
        Ok(Self {
            lambdas: samples.iter().map(|sample| sample.0).collect(),
            values: samples.iter().map(|sample| sample.1).collect(),
        })
    }

    /// Builds the spectrum from interleaved data `[λ₀, v₀, λ₁, v₁, …]`, the
    /// layout of most published tables.
    pub fn from_interleaved(data: &[f32]) -> Result<Self, SpectrumError> {
        if !data.len().is_multiple_of(2) {
            return Err(SpectrumError::OddInterleavedLength { len: data.len() });
        }
        let pairs: Vec<(f32, f32)> = data
            .chunks_exact(2)
            .map(|pair| (pair[0], pair[1]))
            .collect();
        Self::new(&pairs)
    }

    /// The tabulated wavelengths in nm.
    pub fn lambdas(&self) -> &[f32] {
        &self.lambdas
    }

    /// The tabulated values.
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The interpolated value at `lambda` nm; 0 outside the tabulated range.
    pub fn evaluate(&self, lambda: f32) -> f32 {
        let first = self.lambdas[0];
        let last = self.lambdas[self.lambdas.len() - 1];
        if !(first..=last).contains(&lambda) {
            return 0.0;
        }
        // Index of the first tabulated wavelength > lambda, so the segment is
        // [upper − 1, upper]; at lambda == last this is len, clamp to the last segment.
        let upper = self
            .lambdas
            .partition_point(|&tabulated| tabulated <= lambda);
        if upper >= self.lambdas.len() {
            return self.values[self.values.len() - 1];
        }
        let lower = upper - 1;
        let t = (lambda - self.lambdas[lower]) / (self.lambdas[upper] - self.lambdas[lower]);
        self.values[lower] + t * (self.values[upper] - self.values[lower])
    }

    /// The values at the sampled wavelengths.
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::new(wavelengths.lambdas().map(|lambda| self.evaluate(lambda)))
    }

    /// The largest tabulated value (the maximum of a piecewise-linear function
    /// lies at a sample).
    pub fn max_value(&self) -> f32 {
        self.values
            .iter()
            .copied()
            .fold(f32::NEG_INFINITY, f32::max)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_linearly_and_is_zero_outside() {
        let spectrum =
            PiecewiseLinearSpectrum::new(&[(400.0, 1.0), (500.0, 3.0), (600.0, 2.0)]).unwrap();
        assert_eq!(spectrum.evaluate(400.0), 1.0);
        assert_eq!(spectrum.evaluate(450.0), 2.0);
        assert_eq!(spectrum.evaluate(500.0), 3.0);
        assert_eq!(spectrum.evaluate(575.0), 2.25);
        assert_eq!(spectrum.evaluate(600.0), 2.0);
        assert_eq!(spectrum.evaluate(399.0), 0.0);
        assert_eq!(spectrum.evaluate(601.0), 0.0);
        assert_eq!(spectrum.max_value(), 3.0);
        let single = PiecewiseLinearSpectrum::new(&[(500.0, 7.0)]).unwrap();
        assert_eq!(single.evaluate(500.0), 7.0);
        assert_eq!(single.evaluate(501.0), 0.0);
    }

    #[test]
    fn interleaved_layout() {
        let spectrum =
            PiecewiseLinearSpectrum::from_interleaved(&[400.0, 1.0, 500.0, 3.0]).unwrap();
        assert_eq!(spectrum.lambdas(), &[400.0, 500.0]);
        assert_eq!(spectrum.values(), &[1.0, 3.0]);
        assert_eq!(
            PiecewiseLinearSpectrum::from_interleaved(&[400.0, 1.0, 500.0]),
            Err(SpectrumError::OddInterleavedLength { len: 3 })
        );
    }

    #[test]
    fn rejects_bad_samples() {
        assert_eq!(
            PiecewiseLinearSpectrum::new(&[]),
            Err(SpectrumError::NoSamples)
        );
        assert!(PiecewiseLinearSpectrum::new(&[(500.0, 1.0), (500.0, 2.0)]).is_err());
        assert!(PiecewiseLinearSpectrum::new(&[(500.0, 1.0), (400.0, 2.0)]).is_err());
        assert!(PiecewiseLinearSpectrum::new(&[(500.0, f32::NAN)]).is_err());
    }
}
