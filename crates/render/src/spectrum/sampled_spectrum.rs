//! A spectral quantity (radiance, reflectance, throughput, …) known at the
//! [`SPECTRUM_SAMPLE_COUNT`] wavelengths of a [`super::SampledWavelengths`].
//!
//! Arithmetic is component-wise: component i always belongs to wavelength i, so
//! two spectra may only be combined if they were sampled at the same wavelengths.

use std::ops::{
    Add, AddAssign, Div, DivAssign, Index, IndexMut, Mul, MulAssign, Neg, Sub, SubAssign,
};

use super::lanes;
use super::wavelengths::SPECTRUM_SAMPLE_COUNT;

/// Values of a spectral quantity at the wavelengths a path carries.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct SampledSpectrum {
    values: [f32; SPECTRUM_SAMPLE_COUNT],
}

impl SampledSpectrum {
    /// A spectrum with the given per-wavelength values.
    pub const fn new(values: [f32; SPECTRUM_SAMPLE_COUNT]) -> Self {
        Self { values }
    }

    /// A spectrum with the same value at every wavelength.
    pub const fn splat(value: f32) -> Self {
        Self {
            values: [value; SPECTRUM_SAMPLE_COUNT],
        }
    }

    /// The zero spectrum (no light, full absorption).
    pub const fn zero() -> Self {
        Self::splat(0.0)
    }

    /// The per-wavelength values.
    pub const fn values(&self) -> &[f32; SPECTRUM_SAMPLE_COUNT] {
        &self.values
    }

    /// Whether every component is exactly zero, so a path carrying this
    /// throughput can stop.
    pub fn is_black(&self) -> bool {
        self.values.iter().all(|&value| value == 0.0)
    }

    /// The largest component.
    pub fn max_component(&self) -> f32 {
        self.values
            .iter()
            .copied()
            .fold(f32::NEG_INFINITY, f32::max)
    }

    /// The smallest component.
    pub fn min_component(&self) -> f32 {
        self.values.iter().copied().fold(f32::INFINITY, f32::min)
    }

    /// The mean of the components (e.g. for Russian roulette probabilities).
    pub fn average(&self) -> f32 {
        self.values.iter().sum::<f32>() / SPECTRUM_SAMPLE_COUNT as f32
    }

    /// Component-wise `self / divisor`, with 0 wherever the divisor is 0. This is
    /// how estimates are divided by wavelength pdfs: a wavelength with pdf 0 (a
    /// terminated secondary wavelength) contributes nothing.
    ///
    /// Lane-wise: all four quotients are computed (a zero divisor gives an
    /// infinity or NaN there, which is then discarded) and the zero lanes are
    /// selected away, so the compiler emits one division, one comparison and
    /// one mask instead of four branches.
    #[inline]
    pub fn safe_div(&self, divisor: &SampledSpectrum) -> SampledSpectrum {
        self.zip(divisor, |value, divisor| {
            let quotient = value / divisor;
            if divisor != 0.0 { quotient } else { 0.0 }
        })
    }

    /// Component-wise `self / divisor`, or 0 everywhere if the divisor is 0.
    pub fn safe_div_scalar(&self, divisor: f32) -> SampledSpectrum {
        if divisor == 0.0 {
            Self::zero()
        } else {
            self.map(|value| value / divisor)
        }
    }

    /// Component-wise eˣ (Beer–Lambert transmittance from optical depth).
    pub fn exp(&self) -> SampledSpectrum {
        self.map(f32::exp)
    }

    /// Component-wise square root; negative components give 0 instead of NaN.
    pub fn sqrt(&self) -> SampledSpectrum {
        self.map(|value| value.max(0.0).sqrt())
    }

    /// Component-wise clamp to [`min`, `max`] (NaN components become `min`),
    /// lane-wise by [`lanes::clamp`] (no NaN test; unlike `f32::clamp` it
    /// never panics: if `min > max` every component becomes `max`).
    #[inline]
    pub fn clamp(&self, min: f32, max: f32) -> SampledSpectrum {
        self.map(|value| lanes::clamp(value, min, max))
    }

    /// Component-wise max(value, 0), e.g. after a subtraction that may undershoot.
    pub fn clamp_zero(&self) -> SampledSpectrum {
        self.map(|value| value.max(0.0))
    }

    /// Whether any component is NaN (for debug assertions in integrators).
    pub fn has_nan(&self) -> bool {
        self.values.iter().any(|value| value.is_nan())
    }

    /// Applies `function` to every component.
    #[inline]
    pub fn map(&self, function: impl Fn(f32) -> f32) -> SampledSpectrum {
        // An indexed loop: `array::map` did not inline in the path tracer's
        // profile.
        let mut values = self.values;
        for value in values.iter_mut() {
            *value = function(*value);
        }
        Self::new(values)
    }

    /// Combines two spectra component by component.
    #[inline]
    pub fn zip(
        &self,
        other: &SampledSpectrum,
        function: impl Fn(f32, f32) -> f32,
    ) -> SampledSpectrum {
        let mut values = self.values;
        for (value, other) in values.iter_mut().zip(other.values) {
            *value = function(*value, other);
        }
        Self::new(values)
    }
}

impl Index<usize> for SampledSpectrum {
    type Output = f32;
    fn index(&self, index: usize) -> &f32 {
        &self.values[index]
    }
}

impl IndexMut<usize> for SampledSpectrum {
    fn index_mut(&mut self, index: usize) -> &mut f32 {
        &mut self.values[index]
    }
}

impl Neg for SampledSpectrum {
    type Output = SampledSpectrum;
    fn neg(self) -> SampledSpectrum {
        self.map(|value| -value)
    }
}

/// Implements a component-wise binary operator between spectra, and between a
/// spectrum and a scalar, plus the assigning form.
macro_rules! component_wise_operator {
    ($trait:ident, $method:ident, $assign_trait:ident, $assign_method:ident, $op:tt) => {
        impl $trait for SampledSpectrum {
            type Output = SampledSpectrum;
            fn $method(self, other: SampledSpectrum) -> SampledSpectrum {
                self.zip(&other, |a, b| a $op b)
            }
        }
        impl $trait<f32> for SampledSpectrum {
            type Output = SampledSpectrum;
            fn $method(self, scalar: f32) -> SampledSpectrum {
                self.map(|a| a $op scalar)
            }
        }
        impl $assign_trait for SampledSpectrum {
            fn $assign_method(&mut self, other: SampledSpectrum) {
                *self = *self $op other;
            }
        }
        impl $assign_trait<f32> for SampledSpectrum {
            fn $assign_method(&mut self, scalar: f32) {
                *self = *self $op scalar;
            }
        }
    };
}

component_wise_operator!(Add, add, AddAssign, add_assign, +);
component_wise_operator!(Sub, sub, SubAssign, sub_assign, -);
component_wise_operator!(Mul, mul, MulAssign, mul_assign, *);
component_wise_operator!(Div, div, DivAssign, div_assign, /);

impl Mul<SampledSpectrum> for f32 {
    type Output = SampledSpectrum;
    fn mul(self, spectrum: SampledSpectrum) -> SampledSpectrum {
        spectrum * self
    }
}

impl Add<SampledSpectrum> for f32 {
    type Output = SampledSpectrum;
    fn add(self, spectrum: SampledSpectrum) -> SampledSpectrum {
        spectrum + self
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const A: SampledSpectrum = SampledSpectrum::new([1.0, 2.0, 3.0, 4.0]);
    const B: SampledSpectrum = SampledSpectrum::new([2.0, 0.0, -1.0, 0.5]);

    #[test]
    fn arithmetic_is_component_wise() {
        assert_eq!((A + B).values(), &[3.0, 2.0, 2.0, 4.5]);
        assert_eq!((A - B).values(), &[-1.0, 2.0, 4.0, 3.5]);
        assert_eq!((A * B).values(), &[2.0, 0.0, -3.0, 2.0]);
        assert_eq!((A / 2.0).values(), &[0.5, 1.0, 1.5, 2.0]);
        assert_eq!((2.0 * A).values(), &[2.0, 4.0, 6.0, 8.0]);
        assert_eq!((A + 1.0).values(), &[2.0, 3.0, 4.0, 5.0]);
        assert_eq!((-A).values(), &[-1.0, -2.0, -3.0, -4.0]);
        let mut c = A;
        c *= B;
        c += 1.0;
        c -= A;
        c /= 2.0;
        assert_eq!(c.values(), &[1.0, -0.5, -2.5, -0.5]);
    }

    #[test]
    fn safe_division_gives_zero_for_zero_divisors() {
        assert_eq!(A.safe_div(&B).values(), &[0.5, 0.0, -3.0, 8.0]);
        assert!(A.safe_div_scalar(0.0).is_black());
        assert_eq!(A.safe_div_scalar(4.0).values(), &[0.25, 0.5, 0.75, 1.0]);
        assert!((A / B)[1].is_infinite());
        let zeros = SampledSpectrum::new([0.0, -0.0, 1.0, f32::INFINITY]);
        let divided = SampledSpectrum::splat(0.0).safe_div(&zeros);
        assert_eq!(divided.values(), &[0.0, 0.0, 0.0, 0.0]);
        assert!(!divided.has_nan());
    }

    #[test]
    fn reductions_and_functions() {
        assert_eq!(A.max_component(), 4.0);
        assert_eq!(B.min_component(), -1.0);
        assert_eq!(A.average(), 2.5);
        assert!(SampledSpectrum::zero().is_black());
        assert!(!B.is_black());
        assert_eq!(B.clamp(0.0, 1.0).values(), &[1.0, 0.0, 0.0, 0.5]);
        assert_eq!(B.clamp_zero().values(), &[2.0, 0.0, 0.0, 0.5]);
        assert_eq!(
            SampledSpectrum::new([4.0, 9.0, -1.0, 0.0]).sqrt().values(),
            &[2.0, 3.0, 0.0, 0.0]
        );
        let exp = SampledSpectrum::new([0.0, 1.0, -1.0, 2.0]).exp();
        for (value, expected) in
            exp.values()
                .iter()
                .zip([1.0_f32, 1.0_f32.exp(), (-1.0_f32).exp(), 2.0_f32.exp()])
        {
            assert!((value - expected).abs() < 1e-6);
        }
        assert!(SampledSpectrum::new([f32::NAN, 0.0, 0.0, 0.0]).has_nan());
        assert_eq!(
            SampledSpectrum::new([f32::NAN, 0.0, 0.0, 0.0]).clamp(0.0, 1.0)[0],
            0.0
        );
        let infinite = SampledSpectrum::new([f32::INFINITY, f32::NEG_INFINITY, 0.5, f32::NAN]);
        assert_eq!(infinite.clamp(-1.0, 2.0).values(), &[2.0, -1.0, 0.5, -1.0]);
        // Reversed bounds give `max`, not a panic.
        assert_eq!(A.clamp(3.0, 1.0).values(), &[1.0; 4]);
    }
}
