//! The sigmoid-of-a-quadratic reflectance model of Jakob and Hanika (2019),
//! "A Low-Dimensional Function Space for Efficient Spectral Upsampling",
//! Computer Graphics Forum 38(2): s(λ) = S(c₀ λ² + c₁ λ + c₂) with the algebraic
//! sigmoid S(x) = 1/2 + x / (2 √(1 + x²)).
//!
//! Three coefficients give smooth spectra in (0, 1) that can be as saturated as
//! real reflectances (the quadratic lets the spectrum be a bump or a dip) and
//! cost a handful of flops per wavelength.

use super::lanes;
use super::sampled_spectrum::SampledSpectrum;
use super::wavelengths::{
    SPECTRUM_SAMPLE_COUNT, SampledWavelengths, VISIBLE_LAMBDA_MAX, VISIBLE_LAMBDA_MIN,
};

/// The algebraic sigmoid S(x) = 1/2 + x / (2 √(1 + x²)), mapping ℝ onto (0, 1);
/// S(±∞) = 1 or 0 (used for exactly black and exactly white reflectances).
#[inline]
pub fn algebraic_sigmoid(x: f32) -> f32 {
    // Clamping the argument to ±2⁶⁰ keeps x² (2¹²⁰ at most) finite, and at
    // ±2⁶⁰ the formula already rounds to exactly 1 or 0; so infinities (exactly
    // black and white reflectances) and huge finite arguments need no branch,
    // and the four wavelengths of [`RgbSigmoidPolynomial::sample`] vectorise.
    // (Before, x² overflowed for |x| > 2⁶⁴ and such x gave 1/2.) NaN gives 0.
    let x = lanes::clamp(x, -SIGMOID_ARGUMENT_LIMIT, SIGMOID_ARGUMENT_LIMIT);
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

/// 2⁶⁰: the largest |x| [`algebraic_sigmoid`] computes with (see there).
const SIGMOID_ARGUMENT_LIMIT: f32 = 1_152_921_504_606_846_976.0;

/// Coefficients of s(λ) = S(c₀ λ² + c₁ λ + c₂), with λ in nm.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RgbSigmoidPolynomial {
    /// Coefficient of λ² (nm⁻²).
    pub c0: f32,
    /// Coefficient of λ (nm⁻¹).
    pub c1: f32,
    /// Constant term.
    pub c2: f32,
}

impl RgbSigmoidPolynomial {
    /// The model with the given coefficients.
    pub const fn new(c0: f32, c1: f32, c2: f32) -> Self {
        Self { c0, c1, c2 }
    }

    /// The constant reflectance `value` in [0, 1]: c₀ = c₁ = 0 and
    /// c₂ = S⁻¹(value) = (value − 1/2) / √(value (1 − value)), which is ±∞ at 0 and 1.
    pub fn constant(value: f32) -> Self {
        let c2 = if value <= 0.0 {
            f32::NEG_INFINITY
        } else if value >= 1.0 {
            f32::INFINITY
        } else {
            (value - 0.5) / (value * (1.0 - value)).sqrt()
        };
        Self::new(0.0, 0.0, c2)
    }

    /// The reflectance at `lambda` nm, in [0, 1]. (Horner's rule with plain
    /// multiplications and additions: `mul_add` is a library call on the
    /// default x86-64 target, which has no FMA instruction.)
    #[inline]
    pub fn evaluate(&self, lambda: f32) -> f32 {
        algebraic_sigmoid((self.c0 * lambda + self.c1) * lambda + self.c2)
    }

    /// The reflectances at the sampled wavelengths (equal to
    /// [`Self::evaluate`] at each; one 4-wide evaluation).
    #[inline]
    pub fn sample(&self, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        let lambdas = wavelengths.lambdas();
        let mut values = [0.0; SPECTRUM_SAMPLE_COUNT];
        for (value, &lambda) in values.iter_mut().zip(lambdas) {
            *value = self.evaluate(lambda);
        }
        SampledSpectrum::new(values)
    }

    /// The largest value over the visible range [360, 830] nm: S is increasing,
    /// so the maximum is at an end of the range or at the vertex of the quadratic.
    pub fn max_value(&self) -> f32 {
        let mut result = self
            .evaluate(VISIBLE_LAMBDA_MIN)
            .max(self.evaluate(VISIBLE_LAMBDA_MAX));
        if self.c0 != 0.0 {
            let vertex = -self.c1 / (2.0 * self.c0);
            if (VISIBLE_LAMBDA_MIN..=VISIBLE_LAMBDA_MAX).contains(&vertex) {
                result = result.max(self.evaluate(vertex));
            }
        }
        result
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigmoid_limits_and_symmetry() {
        assert_eq!(algebraic_sigmoid(0.0), 0.5);
        assert_eq!(algebraic_sigmoid(f32::INFINITY), 1.0);
        assert_eq!(algebraic_sigmoid(f32::NEG_INFINITY), 0.0);
        assert_eq!(algebraic_sigmoid(f32::MAX), 1.0);
        assert_eq!(algebraic_sigmoid(-f32::MAX), 0.0);
        assert_eq!(algebraic_sigmoid(SIGMOID_ARGUMENT_LIMIT), 1.0);
        assert_eq!(algebraic_sigmoid(1e20), 1.0);
        assert_eq!(algebraic_sigmoid(f32::NAN), 0.0);
        for x in [0.1_f32, 1.0, 10.0, 1000.0] {
            assert!((algebraic_sigmoid(x) + algebraic_sigmoid(-x) - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn constant_inverts_the_sigmoid() {
        for value in [0.0_f32, 0.01, 0.25, 0.5, 0.9, 1.0] {
            let model = RgbSigmoidPolynomial::constant(value);
            for lambda in [360.0, 555.0, 830.0] {
                assert!((model.evaluate(lambda) - value).abs() < 1e-6);
            }
        }
    }

    #[test]
    fn max_value_finds_an_interior_bump() {
        // x(λ) = −(λ − 550)²/1000 + 2 peaks at 550 nm.
        let model = RgbSigmoidPolynomial::new(-1e-3, 1.1, -300.5);
        let peak = algebraic_sigmoid(2.0);
        assert!((model.evaluate(550.0) - peak).abs() < 1e-4);
        assert!((model.max_value() - peak).abs() < 1e-4);
    }
}
