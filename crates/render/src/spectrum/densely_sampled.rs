//! A spectrum tabulated at every integer wavelength (1 nm steps): constant-time
//! evaluation, used for the CIE tables and to cache expensive spectra.

use super::error::{SpectrumError, require_finite};
use super::sampled_spectrum::SampledSpectrum;
use super::wavelengths::{SPECTRUM_SAMPLE_COUNT, SampledWavelengths};

/// Values at λ = `lambda_min`, `lambda_min` + 1, … nm. Evaluation rounds λ to the
/// nearest integer nm (as pbrt-v4 does) and returns 0 outside the table.
#[derive(Debug, Clone, PartialEq)]
pub struct DenselySampledSpectrum {
    lambda_min: i32,
    values: Vec<f32>,
}

impl DenselySampledSpectrum {
    /// A table whose first value belongs to `lambda_min` nm, one value per nm.
    /// Fails if `values` is empty or holds a non-finite number.
    pub fn from_values(lambda_min: i32, values: Vec<f32>) -> Result<Self, SpectrumError> {
        if values.is_empty() {
            return Err(SpectrumError::NoSamples);
        }
        for &value in &values {
            require_finite("tabulated spectrum value", value)?;
        }
        Ok(Self { lambda_min, values })
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
        self.lambda_min + self.values.len() as i32 - 1
    }

    /// The tabulated values, one per nm from [`Self::lambda_min`].
    pub fn values(&self) -> &[f32] {
        &self.values
    }

    /// The value at `lambda` nm (nearest tabulated wavelength; 0 outside).
    #[inline]
    pub fn evaluate(&self, lambda: f32) -> f32 {
        // Rounding by truncation of λ + 0.5 (λ > 0 here) avoids a libm call
        // for `round` on CPUs without SSE4.1, the default target.
        if lambda.is_nan() || lambda <= 0.0 {
            return 0.0;
        }
        let nearest = (lambda + 0.5) as i64;
        let offset = nearest - self.lambda_min as i64;
        if offset >= 0 && (offset as usize) < self.values.len() {
            self.values[offset as usize]
        } else {
            0.0
        }
    }

    /// The values at the sampled wavelengths.
    #[inline]
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        // An indexed loop: `array::map` did not inline in the path tracer.
        let mut values = [0.0; SPECTRUM_SAMPLE_COUNT];
        for (value, &lambda) in values.iter_mut().zip(wavelengths.lambdas()) {
            *value = self.evaluate(lambda);
        }
        SampledSpectrum::new(values)
    }

    /// The largest tabulated value.
    pub fn max_value(&self) -> f32 {
        self.values
            .iter()
            .copied()
            .fold(f32::NEG_INFINITY, f32::max)
    }

    /// A copy with every value multiplied by `factor`.
    pub fn scaled(&self, factor: f32) -> Self {
        Self {
            lambda_min: self.lambda_min,
            values: self.values.iter().map(|value| value * factor).collect(),
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
    }
}
