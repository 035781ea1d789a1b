//! Thermal emission: Planck's law for the spectral radiance of a black body.

use super::error::SpectrumError;
use super::sampled_spectrum::SampledSpectrum;
use super::wavelengths::SampledWavelengths;

/// Speed of light in vacuum, m/s (exact, SI 2019).
const SPEED_OF_LIGHT: f64 = 299_792_458.0;
/// Planck constant, J·s (exact, SI 2019).
const PLANCK: f64 = 6.626_070_15e-34;
/// Boltzmann constant, J/K (exact, SI 2019).
const BOLTZMANN: f64 = 1.380_649e-23;
/// Wien's displacement constant b, m·K (CODATA 2018): the radiance peaks at b / T.
pub const WIEN_DISPLACEMENT: f64 = 2.897_771_955e-3;

/// Spectral radiance of a black body at `temperature` kelvin and wavelength
/// `lambda_nm` nm, in W·sr⁻¹·m⁻²·m⁻¹ (Planck's law):
/// B(λ, T) = 2 h c² / (λ⁵ (exp(h c / (λ k T)) − 1)). Returns 0 for T ≤ 0 or λ ≤ 0.
pub fn planck(lambda_nm: f64, temperature: f64) -> f64 {
    if temperature <= 0.0 || lambda_nm <= 0.0 {
        return 0.0;
    }
    let lambda = lambda_nm * 1e-9;
    let exponent = PLANCK * SPEED_OF_LIGHT / (lambda * BOLTZMANN * temperature);
    2.0 * PLANCK * SPEED_OF_LIGHT * SPEED_OF_LIGHT / (lambda.powi(5) * exponent.exp_m1())
}

/// How a [`BlackbodySpectrum`] is scaled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BlackbodyNormalisation {
    /// Divide by the radiance at the Wien peak, so the maximum over all λ is 1
    /// and the spectrum gives the *colour* of the emitter; its brightness is set
    /// separately (pbrt-v4's behaviour, the default).
    #[default]
    PeakOne,
    /// Absolute spectral radiance in W·sr⁻¹·m⁻²·nm⁻¹.
    SpectralRadiancePerNm,
}

/// The emission spectrum of a black body at a given temperature.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BlackbodySpectrum {
    temperature: f64,
    scale: f64,
}

impl BlackbodySpectrum {
    /// A black body at `temperature` kelvin, scaled as `normalisation` says.
    /// Fails unless the temperature is finite and > 0.
    pub fn new(
        temperature: f32,
        normalisation: BlackbodyNormalisation,
    ) -> Result<Self, SpectrumError> {
        let temperature = f64::from(temperature);
        if !temperature.is_finite() {
            return Err(SpectrumError::NotFinite {
                what: "blackbody temperature",
                value: temperature,
            });
        }
        if temperature <= 0.0 {
            return Err(SpectrumError::NonPositiveTemperature {
                kelvin: temperature,
            });
        }
        let scale = match normalisation {
            BlackbodyNormalisation::PeakOne => {
                1.0 / planck(Self::peak_wavelength_of(temperature), temperature)
            }
            // Per metre → per nanometre.
            BlackbodyNormalisation::SpectralRadiancePerNm => 1e-9,
        };
        Ok(Self { temperature, scale })
    }

    /// Wavelength (nm) of maximal radiance at `temperature` kelvin (Wien's
    /// displacement law λ_max = b / T).
    pub fn peak_wavelength_of(temperature: f64) -> f64 {
        WIEN_DISPLACEMENT / temperature * 1e9
    }

    /// The temperature in kelvin.
    pub fn temperature(&self) -> f32 {
        self.temperature as f32
    }

    /// The value at `lambda` nm.
    pub fn evaluate(&self, lambda: f32) -> f32 {
        (planck(f64::from(lambda), self.temperature) * self.scale) as f32
    }

    /// The values at the sampled wavelengths.
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::new(wavelengths.lambdas().map(|lambda| self.evaluate(lambda)))
    }

    /// The largest value over all wavelengths (at the Wien peak).
    pub fn max_value(&self) -> f32 {
        (planck(Self::peak_wavelength_of(self.temperature), self.temperature) * self.scale) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_temperatures() {
        assert!(BlackbodySpectrum::new(0.0, BlackbodyNormalisation::PeakOne).is_err());
        assert!(BlackbodySpectrum::new(-10.0, BlackbodyNormalisation::PeakOne).is_err());
        assert!(BlackbodySpectrum::new(f32::NAN, BlackbodyNormalisation::PeakOne).is_err());
    }

    #[test]
    fn peak_follows_wien_and_is_one() {
        for temperature in [3000.0_f32, 4500.0, 5778.0, 6500.0] {
            let spectrum =
                BlackbodySpectrum::new(temperature, BlackbodyNormalisation::PeakOne).unwrap();
            // Locate the maximum on a 0.01 nm grid around the prediction.
            let predicted = BlackbodySpectrum::peak_wavelength_of(f64::from(temperature));
            let mut best = (0.0, f64::NEG_INFINITY);
            for step in -5000..=5000 {
                let lambda = predicted + f64::from(step) * 0.01;
                let value = planck(lambda, f64::from(temperature));
                if value > best.1 {
                    best = (lambda, value);
                }
            }
            assert!(
                (best.0 - predicted).abs() <= 0.011,
                "T {temperature}: peak {} vs {predicted}",
                best.0
            );
            assert!((spectrum.evaluate(predicted as f32) - 1.0).abs() < 1e-6);
            assert!((spectrum.max_value() - 1.0).abs() < 1e-6);
            assert!(spectrum.evaluate(predicted as f32 - 50.0) < 1.0);
            assert!(spectrum.evaluate(predicted as f32 + 50.0) < 1.0);
        }
    }

    #[test]
    fn absolute_radiance_matches_a_reference_value() {
        // B(500 nm, 5000 K) = 2hc²/λ⁵ / (exp(hc/λkT) − 1) ≈ 1.2107e13 W·sr⁻¹·m⁻³,
        // hc/(λkT) = 5.7551 (evaluated in f64 from the SI constants).
        let x: f64 = PLANCK * SPEED_OF_LIGHT / (500e-9 * BOLTZMANN * 5000.0);
        assert!((x - 5.7551).abs() < 1e-3);
        let spectrum =
            BlackbodySpectrum::new(5000.0, BlackbodyNormalisation::SpectralRadiancePerNm).unwrap();
        let per_nm = f64::from(spectrum.evaluate(500.0));
        assert!((per_nm / 1.2107e4 - 1.0).abs() < 1e-3, "{per_nm}");
    }
}
