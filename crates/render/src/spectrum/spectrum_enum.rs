//! [`Spectrum`]: every kind of spectral distribution the renderer knows, behind
//! one enum so that evaluating one is a match, not a virtual call.

use super::blackbody::BlackbodySpectrum;
use super::constant::ConstantSpectrum;
use super::densely_sampled::DenselySampledSpectrum;
use super::piecewise_linear::PiecewiseLinearSpectrum;
use super::rgb_spectra::{RgbAlbedoSpectrum, RgbIlluminantSpectrum, RgbUnboundedSpectrum};
use super::sampled_spectrum::SampledSpectrum;
use super::wavelengths::SampledWavelengths;

/// A function of wavelength (nm): emission, reflectance, index of refraction, …
#[derive(Debug, Clone, PartialEq)]
pub enum Spectrum {
    /// The same value everywhere.
    Constant(ConstantSpectrum),
    /// Linear interpolation between measured (λ, value) samples.
    PiecewiseLinear(PiecewiseLinearSpectrum),
    /// A 1 nm table.
    DenselySampled(DenselySampledSpectrum),
    /// Planck's law at a temperature.
    Blackbody(BlackbodySpectrum),
    /// A reflectance from RGB in [0, 1].
    RgbAlbedo(RgbAlbedoSpectrum),
    /// A non-negative quantity from RGB that may exceed 1.
    RgbUnbounded(RgbUnboundedSpectrum),
    /// Emission from RGB (relative to D65).
    RgbIlluminant(RgbIlluminantSpectrum),
}

impl Spectrum {
    /// The value at `lambda` nm.
    pub fn evaluate(&self, lambda: f32) -> f32 {
        match self {
            Spectrum::Constant(spectrum) => spectrum.evaluate(lambda),
            Spectrum::PiecewiseLinear(spectrum) => spectrum.evaluate(lambda),
            Spectrum::DenselySampled(spectrum) => spectrum.evaluate(lambda),
            Spectrum::Blackbody(spectrum) => spectrum.evaluate(lambda),
            Spectrum::RgbAlbedo(spectrum) => spectrum.evaluate(lambda),
            Spectrum::RgbUnbounded(spectrum) => spectrum.evaluate(lambda),
            Spectrum::RgbIlluminant(spectrum) => spectrum.evaluate(lambda),
        }
    }

    /// The values at the wavelengths a path carries.
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        match self {
            Spectrum::Constant(spectrum) => spectrum.sample(wavelengths),
            Spectrum::PiecewiseLinear(spectrum) => spectrum.sample(wavelengths),
            Spectrum::DenselySampled(spectrum) => spectrum.sample(wavelengths),
            Spectrum::Blackbody(spectrum) => spectrum.sample(wavelengths),
            Spectrum::RgbAlbedo(spectrum) => spectrum.sample(wavelengths),
            Spectrum::RgbUnbounded(spectrum) => spectrum.sample(wavelengths),
            Spectrum::RgbIlluminant(spectrum) => spectrum.sample(wavelengths),
        }
    }

    /// An upper bound on the value over the visible range (exact for all but
    /// [`Spectrum::RgbIlluminant`]; used e.g. to build light-sampling
    /// distributions).
    pub fn max_value(&self) -> f32 {
        match self {
            Spectrum::Constant(spectrum) => spectrum.max_value(),
            Spectrum::PiecewiseLinear(spectrum) => spectrum.max_value(),
            Spectrum::DenselySampled(spectrum) => spectrum.max_value(),
            Spectrum::Blackbody(spectrum) => spectrum.max_value(),
            Spectrum::RgbAlbedo(spectrum) => spectrum.max_value(),
            Spectrum::RgbUnbounded(spectrum) => spectrum.max_value(),
            Spectrum::RgbIlluminant(spectrum) => spectrum.max_value(),
        }
    }

    /// Tabulates this spectrum at 1 nm over [`lambda_min`, `lambda_max`] for
    /// cheaper evaluation.
    pub fn to_densely_sampled(
        &self,
        lambda_min: i32,
        lambda_max: i32,
    ) -> Result<DenselySampledSpectrum, super::SpectrumError> {
        DenselySampledSpectrum::from_function(lambda_min, lambda_max, |lambda| {
            self.evaluate(lambda)
        })
    }
}

/// Implements `From<T> for Spectrum` for each variant's type.
macro_rules! spectrum_from {
    ($($variant:ident($type:ty)),* $(,)?) => {
        $(impl From<$type> for Spectrum {
            fn from(spectrum: $type) -> Self {
                Spectrum::$variant(spectrum)
            }
        })*
    };
}

spectrum_from!(
    Constant(ConstantSpectrum),
    PiecewiseLinear(PiecewiseLinearSpectrum),
    DenselySampled(DenselySampledSpectrum),
    Blackbody(BlackbodySpectrum),
    RgbAlbedo(RgbAlbedoSpectrum),
    RgbUnbounded(RgbUnboundedSpectrum),
    RgbIlluminant(RgbIlluminantSpectrum),
);

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::BlackbodyNormalisation;

    #[test]
    fn dispatches_to_each_variant() {
        let wavelengths = SampledWavelengths::sample_visible(0.42);
        let spectra: Vec<Spectrum> = vec![
            ConstantSpectrum::new(0.25).unwrap().into(),
            PiecewiseLinearSpectrum::new(&[(360.0, 0.0), (830.0, 1.0)])
                .unwrap()
                .into(),
            DenselySampledSpectrum::from_function(360, 830, |lambda| lambda / 1000.0)
                .unwrap()
                .into(),
            BlackbodySpectrum::new(4000.0, BlackbodyNormalisation::PeakOne)
                .unwrap()
                .into(),
            RgbAlbedoSpectrum::new([0.2, 0.5, 0.8]).unwrap().into(),
            RgbUnboundedSpectrum::new([2.0, 5.0, 8.0]).unwrap().into(),
            RgbIlluminantSpectrum::new([1.0, 0.5, 0.2]).unwrap().into(),
        ];
        for spectrum in &spectra {
            let sampled = spectrum.sample(&wavelengths);
            for (index, &lambda) in wavelengths.lambdas().iter().enumerate() {
                assert_eq!(sampled[index], spectrum.evaluate(lambda));
                assert!(sampled[index] <= spectrum.max_value() * (1.0 + 1e-5));
            }
            let dense = spectrum.to_densely_sampled(360, 830).unwrap();
            assert_eq!(dense.evaluate(500.0), spectrum.evaluate(500.0));
        }
    }
}
