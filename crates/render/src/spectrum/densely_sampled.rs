//! A spectrum tabulated at every integer wavelength (1 nm steps): constant-time
//! evaluation, used for the CIE tables and to cache expensive spectra.

use super::error::{SpectrumError, require_finite};
use super::padded_table::PaddedTableIndexer;
use super::sampled_spectrum::SampledSpectrum;
use super::wavelengths::SampledWavelengths;

/// Values at λ = `lambda_min`, `lambda_min` + 1, … nm. Evaluation rounds λ to the
/// nearest integer nm (as pbrt-v4 does) and returns 0 outside the table.
///
/// The values are stored with a zero before and after them and looked up with
/// a [`PaddedTableIndexer`], so evaluation has no range test.
#[derive(Debug, Clone, PartialEq)]
pub struct DenselySampledSpectrum {
    indexer: PaddedTableIndexer,
    lambda_min: i32,
    /// The values with one zero at each end.
    padded: Vec<f32>,
}

impl DenselySampledSpectrum {
    /// A table whose first value belongs to `lambda_min` nm, one value per nm.
    /// Fails if `values` is empty or holds a non-finite number, and with
    /// [`SpectrumError::TableOutOfRange`] if it has more than 2²⁰ entries or
    /// `lambda_min` is outside [1, 2²⁰] nm (wavelengths are positive).
    pub fn from_values(lambda_min: i32, values: Vec<f32>) -> Result<Self, SpectrumError> {
        if values.is_empty() {
            return Err(SpectrumError::NoSamples);
        }
        for &value in &values {
            require_finite("tabulated spectrum value", value)?;
        }
        let indexer = PaddedTableIndexer::new(lambda_min, values.len())?;
        Ok(Self {
            indexer,
            lambda_min,
            padded: indexer.pad(&values),
        })
    }

    /// Tabulates `function` (a spectrum's value at λ nm) at every integer
    /// wavelength of [`lambda_min`, `lambda_max`].
    pub fn from_function(
        lambda_min: i32,
        lambda_max: i32,
        function: impl Fn(f32) -> f32,
    ) -> Result<Self, SpectrumError> {
        if lambda_min > lambda_max {
            return Err(SpectrumError::EmptyRange {
                min: f64::from(lambda_min),
                max: f64::from(lambda_max),
            });
        }
        let values = (lambda_min..=lambda_max)
            .map(|lambda| function(lambda as f32))
            .collect();
        Self::from_values(lambda_min, values)
    }

    /// The first tabulated wavelength in nm.
    pub fn lambda_min(&self) -> i32 {
        self.lambda_min
    }

    /// The last tabulated wavelength in nm.
    pub fn lambda_max(&self) -> i32 {
        self.lambda_min + self.values().len() as i32 - 1
    }

    /// The tabulated values, one per nm from [`Self::lambda_min`].
    pub fn values(&self) -> &[f32] {
        &self.padded[1..self.padded.len() - 1]
    }

    /// The value at `lambda` nm (nearest tabulated wavelength; 0 outside).
    #[inline]
    pub fn evaluate(&self, lambda: f32) -> f32 {
        self.indexer.look_up(&self.padded, lambda)
    }

    /// The values at the sampled wavelengths (the four indices computed
    /// together, see [`PaddedTableIndexer::look_up_four`]).
    #[inline]
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        SampledSpectrum::new(
            self.indexer
                .look_up_four(&self.padded, wavelengths.lambdas()),
        )
    }

    /// The largest tabulated value.
    pub fn max_value(&self) -> f32 {
        self.values()
            .iter()
            .copied()
            .fold(f32::NEG_INFINITY, f32::max)
    }

    /// A copy with every value multiplied by `factor`.
    pub fn scaled(&self, factor: f32) -> Self {
        // Only the real values are scaled: the pads stay 0 even for an
        // infinite factor.
        let values: Vec<f32> = self.values().iter().map(|value| value * factor).collect();
        Self {
            indexer: self.indexer,
            lambda_min: self.lambda_min,
            padded: self.indexer.pad(&values),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evaluates_the_nearest_integer_wavelength_and_zero_outside() {
        let table = DenselySampledSpectrum::from_values(400, vec![1.0, 2.0, 3.0]).unwrap();
        assert_eq!(table.lambda_max(), 402);
        assert_eq!(table.evaluate(400.0), 1.0);
        assert_eq!(table.evaluate(401.4), 2.0);
        assert_eq!(table.evaluate(401.6), 3.0);
        assert_eq!(table.evaluate(399.4), 0.0);
        assert_eq!(table.evaluate(402.6), 0.0);
        assert_eq!(table.evaluate(f32::NAN), 0.0);
        assert_eq!(table.max_value(), 3.0);
        assert_eq!(table.scaled(2.0).values(), &[2.0, 4.0, 6.0]);
    }

    #[test]
    fn from_function_tabulates_every_nm() {
        let table = DenselySampledSpectrum::from_function(360, 830, |lambda| lambda * 2.0).unwrap();
        assert_eq!(table.values().len(), 471);
        assert_eq!(table.evaluate(555.0), 1110.0);
        assert!(DenselySampledSpectrum::from_function(500, 400, |_| 0.0).is_err());
    }

    #[test]
    fn rejects_bad_tables() {
        assert_eq!(
            DenselySampledSpectrum::from_values(0, vec![]),
            Err(SpectrumError::NoSamples)
        );
        assert!(DenselySampledSpectrum::from_values(0, vec![f32::NAN]).is_err());
        assert!(matches!(
            DenselySampledSpectrum::from_values(i32::MAX, vec![1.0]),
            Err(SpectrumError::TableOutOfRange { .. })
        ));
        assert!(matches!(
            DenselySampledSpectrum::from_values(0, vec![1.0]),
            Err(SpectrumError::TableOutOfRange { .. })
        ));
        let pads = DenselySampledSpectrum::from_values(400, vec![1.0]).unwrap();
        assert_eq!(pads.scaled(f32::INFINITY).evaluate(401.0), 0.0);
    }
}
