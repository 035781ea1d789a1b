//! Spectra from RGB values (textures, scene files): reflectances, unbounded
//! quantities and illuminants, all built on the sigmoid model of
//! [`super::sigmoid`] with coefficients from [`RgbToSpectrumTable`].

use super::cie::d65_illuminant;
use super::densely_sampled::DenselySampledSpectrum;
use super::error::{SpectrumError, require_non_negative};
use super::rgb_to_spectrum_table::RgbToSpectrumTable;
use super::sampled_spectrum::SampledSpectrum;
use super::sigmoid::RgbSigmoidPolynomial;
use super::wavelengths::SampledWavelengths;

/// What a spectral quantity is: it decides how an RGB triple is lifted to a
/// spectrum (Jakob–Hanika sigmoid for reflectances, scaled sigmoid for
/// unbounded quantities, scaled sigmoid times D65 for illuminants: the
/// [`RgbAlbedoSpectrum`], [`RgbUnboundedSpectrum`] and
/// [`RgbIlluminantSpectrum`] of this module).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpectrumUsage {
    /// A reflectance or transmittance in [0, 1].
    Albedo,
    /// A non-negative quantity that may exceed 1 (η, κ, σ).
    Unbounded,
    /// Emitted radiance, intensity or irradiance.
    Illuminant,
}

/// Checks that every component is finite and ≥ 0.
fn require_non_negative_rgb(rgb: [f32; 3]) -> Result<[f32; 3], SpectrumError> {
    for value in rgb {
        require_non_negative("RGB component", value)?;
    }
    Ok(rgb)
}

/// A reflectance (albedo) given as linear sRGB in [0, 1]³: a smooth spectrum in
/// [0, 1] whose colour under D65 is that RGB.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RgbAlbedoSpectrum {
    polynomial: RgbSigmoidPolynomial,
}

impl RgbAlbedoSpectrum {
    /// The reflectance for linear sRGB `rgb` (sRGB table); fails if a component
    /// is outside [0, 1] (use [`RgbUnboundedSpectrum`] for larger values).
    pub fn new(rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        Self::with_table(RgbToSpectrumTable::srgb(), rgb)
    }

    /// As [`Self::new`] with an explicit coefficient table.
    pub fn with_table(table: &RgbToSpectrumTable, rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        for value in require_non_negative_rgb(rgb)? {
            if value > 1.0 {
                return Err(SpectrumError::AlbedoOutOfRange {
                    value: f64::from(value),
                });
            }
        }
        Ok(Self {
            polynomial: table.lookup(rgb),
        })
    }

    /// The underlying sigmoid polynomial.
    pub fn polynomial(&self) -> RgbSigmoidPolynomial {
        self.polynomial
    }

    /// The reflectance at `lambda` nm.
    pub fn evaluate(&self, lambda: f32) -> f32 {
        self.polynomial.evaluate(lambda)
    }

    /// The reflectances at the sampled wavelengths.
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        self.polynomial.sample(wavelengths)
    }

    /// The largest value over the visible range.
    pub fn max_value(&self) -> f32 {
        self.polynomial.max_value()
    }
}

/// A non-negative spectral quantity given as linear sRGB that may exceed 1 (a
/// scattering coefficient, say): scale × sigmoid, with scale = 2 max(r, g, b) and
/// the sigmoid fitted to rgb / scale, whose largest component is 1/2 — the middle
/// of the sigmoid's range, where the model is most flexible (pbrt-v4's choice).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RgbUnboundedSpectrum {
    scale: f32,
    polynomial: RgbSigmoidPolynomial,
}

impl RgbUnboundedSpectrum {
    /// The spectrum for linear sRGB `rgb` (sRGB table); fails if a component is
    /// negative or not finite.
    pub fn new(rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        Self::with_table(RgbToSpectrumTable::srgb(), rgb)
    }

    /// As [`Self::new`] with an explicit coefficient table.
    pub fn with_table(table: &RgbToSpectrumTable, rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        let rgb = require_non_negative_rgb(rgb)?;
        let largest = rgb[0].max(rgb[1]).max(rgb[2]);
        let scale = 2.0 * largest;
        let polynomial = if scale > 0.0 {
            table.lookup(rgb.map(|value| value / scale))
        } else {
            RgbSigmoidPolynomial::constant(0.0)
        };
        Ok(Self { scale, polynomial })
    }

    /// The factor the sigmoid is multiplied by (2 max(r, g, b)).
    pub fn scale(&self) -> f32 {
        self.scale
    }

    /// The value at `lambda` nm.
    pub fn evaluate(&self, lambda: f32) -> f32 {
        self.scale * self.polynomial.evaluate(lambda)
    }

    /// The values at the sampled wavelengths.
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        self.polynomial.sample(wavelengths) * self.scale
    }

    /// The largest value over the visible range.
    pub fn max_value(&self) -> f32 {
        self.scale * self.polynomial.max_value()
    }
}

/// Emission given as linear sRGB: an [`RgbUnboundedSpectrum`] multiplied by the
/// sRGB white, D65 normalised to luminance 1 ([`d65_illuminant`]). The RGB
/// describes the light's colour as a reflectance would under D65, so
/// RGB (1, 1, 1) is exactly D65 with Y = 1 and renders as sRGB ≈ (1, 1, 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RgbIlluminantSpectrum {
    unbounded: RgbUnboundedSpectrum,
    illuminant: &'static DenselySampledSpectrum,
}

impl RgbIlluminantSpectrum {
    /// The emission spectrum for linear sRGB `rgb`; fails if a component is
    /// negative or not finite.
    pub fn new(rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        Self::with_table(RgbToSpectrumTable::srgb(), rgb)
    }

    /// As [`Self::new`] with an explicit coefficient table.
    pub fn with_table(table: &RgbToSpectrumTable, rgb: [f32; 3]) -> Result<Self, SpectrumError> {
        Ok(Self {
            unbounded: RgbUnboundedSpectrum::with_table(table, rgb)?,
            illuminant: d65_illuminant(),
        })
    }

    /// The value at `lambda` nm.
    pub fn evaluate(&self, lambda: f32) -> f32 {
        self.unbounded.evaluate(lambda) * self.illuminant.evaluate(lambda)
    }

    /// The values at the sampled wavelengths.
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        self.unbounded.sample(wavelengths) * self.illuminant.sample(wavelengths)
    }

    /// An upper bound on the value over the visible range (product of the two
    /// factors' maxima).
    pub fn max_value(&self) -> f32 {
        self.unbounded.max_value() * self.illuminant.max_value()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation() {
        assert!(RgbAlbedoSpectrum::new([0.5, 1.2, 0.0]).is_err());
        assert!(RgbAlbedoSpectrum::new([0.5, -0.1, 0.0]).is_err());
        assert!(RgbUnboundedSpectrum::new([5.0, f32::NAN, 0.0]).is_err());
        assert!(RgbIlluminantSpectrum::new([-1.0, 0.0, 0.0]).is_err());
        assert!(RgbUnboundedSpectrum::new([5.0, 2.0, 0.0]).is_ok());
    }

    #[test]
    fn black_and_white_albedo() {
        let white = RgbAlbedoSpectrum::new([1.0; 3]).unwrap();
        let black = RgbAlbedoSpectrum::new([0.0; 3]).unwrap();
        for lambda in [360.0, 450.0, 555.0, 700.0, 830.0] {
            assert_eq!(white.evaluate(lambda), 1.0);
            assert_eq!(black.evaluate(lambda), 0.0);
        }
        let zero = RgbUnboundedSpectrum::new([0.0; 3]).unwrap();
        assert_eq!(zero.evaluate(500.0), 0.0);
    }

    #[test]
    fn unbounded_scale_is_twice_the_largest_component() {
        let spectrum = RgbUnboundedSpectrum::new([3.0, 1.0, 2.0]).unwrap();
        assert_eq!(spectrum.scale(), 6.0);
        let grey = RgbUnboundedSpectrum::new([4.0; 3]).unwrap();
        assert!((grey.evaluate(600.0) - 4.0).abs() < 1e-5);
    }
}
