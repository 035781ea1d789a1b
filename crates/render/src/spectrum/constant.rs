//! A spectrum with the same value at every wavelength.

use super::error::{SpectrumError, require_finite};
use super::sampled_spectrum::SampledSpectrum;
use super::wavelengths::SampledWavelengths;

/// The value `c` at every wavelength (e.g. a grey albedo or an IOR without
/// dispersion).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConstantSpectrum {
    value: f32,
}

impl ConstantSpectrum {
    /// The spectrum with value `value` everywhere; fails if it is not finite.
    pub fn new(value: f32) -> Result<Self, SpectrumError> {
        Ok(Self {
            value: require_finite("constant spectrum value", value)?,
        })
    }

    /// The value at `lambda` nm (the same for every λ).
    pub fn evaluate(&self, _lambda: f32) -> f32 {
        self.value
    }

    /// The value at the sampled wavelengths.
    pub fn sample(&self, _wavelengths: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::splat(self.value)
    }

    /// The largest value: the constant itself.
    pub fn max_value(&self) -> f32 {
        self.value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn is_constant_and_validated() {
        let spectrum = ConstantSpectrum::new(0.5).unwrap();
        let wavelengths = SampledWavelengths::sample_visible(0.3);
        assert_eq!(spectrum.sample(&wavelengths), SampledSpectrum::splat(0.5));
        assert_eq!(spectrum.evaluate(400.0), 0.5);
        assert!(ConstantSpectrum::new(f32::INFINITY).is_err());
    }
}
