//! Hero-wavelength sampling: the [`SPECTRUM_SAMPLE_COUNT`] wavelengths a camera
//! path carries, and their probability densities.
//!
//! Each path samples one *hero* wavelength λ₀ from a density p(λ) and derives the
//! others by rotating the primary sample: uᵢ = (u + i/N) mod 1, λᵢ = P⁻¹(uᵢ)
//! (Wilkie et al. 2014, "Hero Wavelength Spectral Sampling"; pbrt-v4 §4.5.4).
//! The N wavelengths are thus stratified in the sample space and each one alone is
//! distributed with density p, so (1/N) Σᵢ f(λᵢ)/p(λᵢ) is an unbiased estimate of
//! ∫ f(λ) dλ with lower variance than N independent samples.
//!
//! The default density is pbrt-v4's visible-wavelength density
//! p(λ) ∝ 1 / cosh²(0.0072 (λ − 538 nm)) on [360 nm, 830 nm] (Pharr, Jakob and
//! Humphreys, *Physically Based Rendering*, 4th ed., §5.4.2), which follows the
//! shape of the CIE luminous efficiency curve with heavy tails. Its CDF and
//! inverse are derived here from ∫ sech²(k t) dt = tanh(k t) / k.

use super::error::{SpectrumError, require_finite};
use super::lanes::{self, Lanes};
use super::sampled_spectrum::SampledSpectrum;

/// How many wavelengths one [`SampledWavelengths`] carries (pbrt-v4's default).
pub const SPECTRUM_SAMPLE_COUNT: usize = 4;

/// Shortest wavelength (nm) the renderer considers visible: the start of the CIE
/// 1931 colour-matching function tables.
pub const VISIBLE_LAMBDA_MIN: f32 = 360.0;

/// Longest wavelength (nm) the renderer considers visible: the end of the CIE
/// 1931 colour-matching function tables.
pub const VISIBLE_LAMBDA_MAX: f32 = 830.0;

/// Steepness k (1/nm) of the visible-wavelength density sech²(k (λ − centre)).
const VISIBLE_DENSITY_STEEPNESS: f64 = 0.0072;

/// Centre (nm) of the visible-wavelength density, near the peak of ȳ (555 nm)
/// pulled towards the blue to cover z̄.
const VISIBLE_DENSITY_CENTRE: f64 = 538.0;

/// tanh(k (λ − centre)) at both ends of the visible range: the CDF of
/// sech²(k (λ − centre)) is proportional to tanh(k (λ − centre)) minus its value at
/// [`VISIBLE_LAMBDA_MIN`]. Literals (tanh(0.0072 (360 − 538)) and
/// tanh(0.0072 (830 − 538)) in f64; a test recomputes them) rather than values
/// computed at run time: every path samples four wavelengths.
fn visible_tanh_at_ends() -> (f64, f64) {
    (VISIBLE_TANH_AT_MIN, VISIBLE_TANH_AT_MAX)
}

/// tanh(k (360 − c)) for k = 0.0072 nm⁻¹, c = 538 nm.
const VISIBLE_TANH_AT_MIN: f64 = -0.856_910_625_469_828;

/// tanh(k (830 − c)) for k = 0.0072 nm⁻¹, c = 538 nm.
const VISIBLE_TANH_AT_MAX: f64 = 0.970_591_346_940_269_8;

/// [`VISIBLE_TANH_AT_MIN`] rounded to f32, for the sampler.
const SAMPLING_TANH_AT_MIN: f32 = -0.856_910_65;

/// The tanh range of the visible interval, [`VISIBLE_TANH_AT_MAX`] −
/// [`VISIBLE_TANH_AT_MIN`], rounded to f32.
const SAMPLING_TANH_RANGE: f32 = 1.827_502;

/// k divided by [`SAMPLING_TANH_RANGE`] (in f64, then rounded to f32): the
/// density's normalisation.
const SAMPLING_PDF_SCALE: f32 = 0.003_939_804;

/// Density (1/nm) of [`sample_visible_wavelength`] at `lambda` nm; 0 outside
/// [360, 830] nm.
///
/// p(λ) = k / ((tanh(k (830 − c)) − tanh(k (360 − c))) cosh²(k (λ − c))) with
/// k = 0.0072 nm⁻¹ and c = 538 nm, which integrates to 1 over [360, 830].
pub fn visible_wavelength_pdf(lambda: f32) -> f32 {
    if !(VISIBLE_LAMBDA_MIN..=VISIBLE_LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    let k = VISIBLE_DENSITY_STEEPNESS;
    let (at_min, at_max) = visible_tanh_at_ends();
    let cosh = (k * (f64::from(lambda) - VISIBLE_DENSITY_CENTRE)).cosh();
    (k / ((at_max - at_min) * cosh * cosh)) as f32
}

/// Cumulative distribution of [`visible_wavelength_pdf`] at `lambda` nm, clamped
/// to [0, 1] outside the visible range.
pub fn visible_wavelength_cdf(lambda: f32) -> f32 {
    let lambda = lambda.clamp(VISIBLE_LAMBDA_MIN, VISIBLE_LAMBDA_MAX);
    let k = VISIBLE_DENSITY_STEEPNESS;
    let (at_min, at_max) = visible_tanh_at_ends();
    let at_lambda = (k * (f64::from(lambda) - VISIBLE_DENSITY_CENTRE)).tanh();
    ((at_lambda - at_min) / (at_max - at_min)) as f32
}

/// Maps a uniform sample `u` in [0, 1) to a wavelength (nm) in [360, 830]
/// distributed with [`visible_wavelength_pdf`], by inverting the CDF:
/// λ = c + atanh(tanh(k (360 − c)) + u (tanh(k (830 − c)) − tanh(k (360 − c)))) / k.
pub fn sample_visible_wavelength(u: f32) -> f32 {
    sample_visible_wavelength_with_pdf(u).0
}

/// [`sample_visible_wavelength`] and the density there. The density comes
/// from the same tanh value as the wavelength, t = tanh(k (λ − c)), as
/// k (1 − t²) / (tanh(k (830 − c)) − tanh(k (360 − c))) (since
/// 1 / cosh² = 1 − tanh²), which saves the `cosh` of
/// [`visible_wavelength_pdf`]; the two agree to f32 rounding.
///
/// In f32 with atanh t = ln((1 + t) / (1 − t)) / 2: |t| ≤ 0.97 on the visible
/// range, so the wavelength is off the exact inverse by at most about
/// 10⁻³ nm and the density stays the derivative of the map to f32 rounding
/// (the f64 `atanh`, a `log1p` call, was 3 % of a Cornell-box path).
#[inline]
fn sample_visible_wavelength_with_pdf(u: f32) -> (f32, f32) {
    let (lambda, pdf) = sample_visible_wavelengths_with_pdf([u; SPECTRUM_SAMPLE_COUNT]);
    (lambda[0], pdf[0])
}

/// [`sample_visible_wavelength_with_pdf`] for four samples at once, with the
/// four-lane logarithm of [`lanes::ln`] (the wavelength differs from one
/// computed with `f32::ln` by at most a few f32 roundings).
#[inline]
fn sample_visible_wavelengths_with_pdf(u: Lanes) -> (Lanes, Lanes) {
    let mut target = [0.0; SPECTRUM_SAMPLE_COUNT];
    let mut ratio = [0.0; SPECTRUM_SAMPLE_COUNT];
    for index in 0..SPECTRUM_SAMPLE_COUNT {
        target[index] = SAMPLING_TANH_AT_MIN + u[index] * SAMPLING_TANH_RANGE;
        ratio[index] = (1.0 + target[index]) / (1.0 - target[index]);
    }
    let logarithm = lanes::ln(ratio);
    let mut lambda = [0.0; SPECTRUM_SAMPLE_COUNT];
    let mut pdf = [0.0; SPECTRUM_SAMPLE_COUNT];
    for index in 0..SPECTRUM_SAMPLE_COUNT {
        let atanh = 0.5 * logarithm[index];
        let unclamped = VISIBLE_DENSITY_CENTRE as f32 + atanh / VISIBLE_DENSITY_STEEPNESS as f32;
        lambda[index] = lanes::clamp(unclamped, VISIBLE_LAMBDA_MIN, VISIBLE_LAMBDA_MAX);
        pdf[index] = SAMPLING_PDF_SCALE * (1.0 - target[index] * target[index]);
    }
    (lambda, pdf)
}

/// The i-th of N stratified rotations of a primary sample: (u + i/N) mod 1.
fn rotated_sample(u: f32, index: usize) -> f32 {
    let rotated = u + index as f32 / SPECTRUM_SAMPLE_COUNT as f32;
    let wrapped = if rotated >= 1.0 {
        rotated - 1.0
    } else {
        rotated
    };
    // Rounding may land exactly on 1; keep the sample inside [0, 1).
    wrapped.min(1.0 - f32::EPSILON / 2.0)
}

/// Wraps an arbitrary primary sample into [0, 1) (NaN becomes 0).
fn wrap_unit(u: f32) -> f32 {
    if !u.is_finite() {
        return 0.0;
    }
    let wrapped = u - u.floor();
    if wrapped >= 1.0 { 0.0 } else { wrapped }
}

/// The wavelengths (nm) one light path carries and the density each was sampled
/// with. Index 0 is the hero wavelength.
///
/// A pdf of 0 marks a wavelength that no longer contributes (see
/// [`SampledWavelengths::terminate_secondary`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampledWavelengths {
    lambda: [f32; SPECTRUM_SAMPLE_COUNT],
    pdf: [f32; SPECTRUM_SAMPLE_COUNT],
}

impl SampledWavelengths {
    /// Samples [`SPECTRUM_SAMPLE_COUNT`] stratified wavelengths from the
    /// visible-wavelength density (the renderer's default).
    ///
    /// `u` should lie in [0, 1); other values are wrapped into it.
    pub fn sample_visible(u: f32) -> Self {
        let u = wrap_unit(u);
        let mut rotated = [0.0; SPECTRUM_SAMPLE_COUNT];
        for (index, rotated) in rotated.iter_mut().enumerate() {
            *rotated = rotated_sample(u, index);
        }
        let (lambda, pdf) = sample_visible_wavelengths_with_pdf(rotated);
        Self { lambda, pdf }
    }

    /// Samples [`SPECTRUM_SAMPLE_COUNT`] stratified wavelengths uniformly in
    /// [`min`, `max`] nm, each with density 1 / (max − min).
    ///
    /// `u` should lie in [0, 1); other values are wrapped into it. Fails if the
    /// range is empty, reversed or not finite.
    pub fn sample_uniform(u: f32, min: f32, max: f32) -> Result<Self, SpectrumError> {
        require_finite("minimum wavelength", min)?;
        require_finite("maximum wavelength", max)?;
        if min >= max {
            return Err(SpectrumError::EmptyRange {
                min: f64::from(min),
                max: f64::from(max),
            });
        }
        let u = wrap_unit(u);
        let width = max - min;
        let mut lambda = [0.0; SPECTRUM_SAMPLE_COUNT];
        for (index, lambda) in lambda.iter_mut().enumerate() {
            *lambda = (min + rotated_sample(u, index) * width).clamp(min, max);
        }
        Ok(Self {
            lambda,
            pdf: [1.0 / width; SPECTRUM_SAMPLE_COUNT],
        })
    }

    /// Builds a set from explicit wavelengths (nm) and densies (1/nm), e.g. to
    /// evaluate spectra at chosen wavelengths in tests or tools.
    pub fn from_parts(
        lambda: [f32; SPECTRUM_SAMPLE_COUNT],
        pdf: [f32; SPECTRUM_SAMPLE_COUNT],
    ) -> Result<Self, SpectrumError> {
        for value in lambda {
            require_finite("wavelength", value)?;
        }
        for value in pdf {
            super::error::require_non_negative("wavelength pdf", value)?;
        }
        Ok(Self { lambda, pdf })
    }

    /// The wavelengths in nm; index 0 is the hero wavelength.
    pub fn lambdas(&self) -> &[f32; SPECTRUM_SAMPLE_COUNT] {
        &self.lambda
    }

    /// The `index`-th wavelength in nm (index < [`SPECTRUM_SAMPLE_COUNT`]).
    pub fn lambda(&self, index: usize) -> f32 {
        self.lambda[index]
    }

    /// The hero wavelength in nm: the one kept by [`Self::terminate_secondary`].
    pub fn hero(&self) -> f32 {
        self.lambda[0]
    }

    /// The density (1/nm) each wavelength was sampled with, as a spectrum so that
    /// estimates can be divided by it.
    pub fn pdf(&self) -> SampledSpectrum {
        SampledSpectrum::new(self.pdf)
    }

    /// Keeps only the hero wavelength, for events whose outcome depends on the
    /// wavelength (dispersion at a refractive interface, say): such a path can
    /// follow one wavelength only.
    ///
    /// The secondary pdfs become 0 (their contributions are dropped by the safe
    /// division in the estimator) and the hero pdf is divided by N. This keeps the
    /// estimator unbiased: the colour estimate always averages over N slots,
    /// (1/N) Σᵢ f(λᵢ)/p(λᵢ). Afterwards only slot 0 contributes, giving
    /// (1/N) f(λ₀) / (p(λ₀)/N) = f(λ₀)/p(λ₀), and λ₀ on its own is distributed with
    /// density p (the rotation uᵢ = u + i/N does not change the marginal law of
    /// λ₀), so its expectation is ∫ f(λ) dλ, the same as before termination. Only
    /// the variance grows: one wavelength carries the whole estimate. Calling it
    /// again does nothing.
    pub fn terminate_secondary(&mut self) {
        if self.secondary_terminated() {
            return;
        }
        for index in 1..SPECTRUM_SAMPLE_COUNT {
            self.pdf[index] = 0.0;
        }
        self.pdf[0] /= SPECTRUM_SAMPLE_COUNT as f32;
    }

    /// Whether [`Self::terminate_secondary`] has been applied: every secondary
    /// wavelength has pdf 0.
    pub fn secondary_terminated(&self) -> bool {
        self.pdf[1..].iter().all(|&pdf| pdf == 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sampling_constants_match_their_definitions() {
        let k = VISIBLE_DENSITY_STEEPNESS;
        let at_min = (k * (f64::from(VISIBLE_LAMBDA_MIN) - VISIBLE_DENSITY_CENTRE)).tanh();
        let at_max = (k * (f64::from(VISIBLE_LAMBDA_MAX) - VISIBLE_DENSITY_CENTRE)).tanh();
        assert!((at_min - VISIBLE_TANH_AT_MIN).abs() < 1e-15);
        assert!((at_max - VISIBLE_TANH_AT_MAX).abs() < 1e-15);
        assert_eq!(SAMPLING_TANH_AT_MIN, at_min as f32);
        assert_eq!(SAMPLING_TANH_RANGE, (at_max - at_min) as f32);
        assert_eq!(SAMPLING_PDF_SCALE, (k / (at_max - at_min)) as f32);
    }

    #[test]
    fn four_lane_sampler_matches_the_scalar_formula() {
        for step in 0..=1000 {
            let u = step as f32 / 1000.0 * (1.0 - f32::EPSILON);
            let (lambda, pdf) = sample_visible_wavelength_with_pdf(u);
            let target = SAMPLING_TANH_AT_MIN + u * SAMPLING_TANH_RANGE;
            let atanh = 0.5 * ((1.0 + target) / (1.0 - target)).ln();
            let expected = (VISIBLE_DENSITY_CENTRE as f32
                + atanh / VISIBLE_DENSITY_STEEPNESS as f32)
                .clamp(VISIBLE_LAMBDA_MIN, VISIBLE_LAMBDA_MAX);
            assert!(
                (lambda - expected).abs() < 1e-3,
                "u {u}: {lambda} vs {expected}"
            );
            assert_eq!(pdf, SAMPLING_PDF_SCALE * (1.0 - target * target));
        }
    }

    #[test]
    fn cdf_inverts_the_sampler() {
        for step in 0..=1000 {
            let u = step as f32 / 1000.0 * (1.0 - f32::EPSILON);
            let lambda = sample_visible_wavelength(u);
            assert!((VISIBLE_LAMBDA_MIN..=VISIBLE_LAMBDA_MAX).contains(&lambda));
            let back = visible_wavelength_cdf(lambda);
            assert!((back - u).abs() < 2e-5, "u {u} -> {lambda} -> {back}");
        }
        assert_eq!(sample_visible_wavelength(0.0), VISIBLE_LAMBDA_MIN);
        assert!((sample_visible_wavelength(1.0) - VISIBLE_LAMBDA_MAX).abs() < 1e-3);
    }

    #[test]
    fn pdf_is_the_derivative_of_the_cdf() {
        let h = 0.05_f32;
        for step in 1..47 {
            let lambda = VISIBLE_LAMBDA_MIN + step as f32 * 10.0;
            let numeric = (visible_wavelength_cdf(lambda + h) - visible_wavelength_cdf(lambda - h))
                / (2.0 * h);
            let pdf = visible_wavelength_pdf(lambda);
            assert!(
                (numeric - pdf).abs() < 1e-3 * pdf + 1e-6,
                "{lambda}: {numeric} vs {pdf}"
            );
        }
    }

    #[test]
    fn pdf_integrates_to_one() {
        // Composite Simpson rule on 4700 intervals; the integrand is smooth.
        let intervals = 4700;
        let h = f64::from(VISIBLE_LAMBDA_MAX - VISIBLE_LAMBDA_MIN) / intervals as f64;
        let mut sum = 0.0;
        for i in 0..=intervals {
            let lambda = f64::from(VISIBLE_LAMBDA_MIN) + i as f64 * h;
            let weight = if i == 0 || i == intervals {
                1.0
            } else if i % 2 == 1 {
                4.0
            } else {
                2.0
            };
            sum += weight * f64::from(visible_wavelength_pdf(lambda as f32));
        }
        let integral = sum * h / 3.0;
        assert!((integral - 1.0).abs() < 1e-5, "integral {integral}");
        assert_eq!(visible_wavelength_pdf(359.9), 0.0);
        assert_eq!(visible_wavelength_pdf(830.1), 0.0);
    }

    #[test]
    fn matches_pbrt_v4_closed_form() {
        // pbrt-v4 (§5.4.2) publishes the same density with rounded constants:
        // p(λ) = 0.0039398042 / cosh²(0.0072 (λ − 538)).
        for lambda in [360.0_f32, 450.0, 538.0, 700.0, 830.0] {
            let cosh = (0.0072_f64 * (f64::from(lambda) - 538.0)).cosh();
            let published = 0.003_939_804_2_f64 / (cosh * cosh);
            assert!((f64::from(visible_wavelength_pdf(lambda)) - published).abs() < 1e-8);
        }
    }

    #[test]
    fn wavelengths_are_stratified_rotations() {
        let u = 0.37;
        let sampled = SampledWavelengths::sample_visible(u);
        for index in 0..SPECTRUM_SAMPLE_COUNT {
            let expected_u = (u + index as f32 * 0.25).fract();
            let cdf = visible_wavelength_cdf(sampled.lambda(index));
            assert!((cdf - expected_u).abs() < 2e-5);
            let pdf = visible_wavelength_pdf(sampled.lambda(index));
            assert!(
                (sampled.pdf()[index] - pdf).abs() <= 1e-5 * pdf,
                "{} vs {pdf}",
                sampled.pdf()[index]
            );
        }
        assert!(!sampled.secondary_terminated());
    }

    #[test]
    fn uniform_sampling_covers_the_range_in_quarters() {
        let sampled = SampledWavelengths::sample_uniform(0.1, 400.0, 800.0).unwrap();
        let expected = [440.0, 540.0, 640.0, 740.0];
        for (lambda, expected) in sampled.lambdas().iter().zip(expected) {
            assert!((lambda - expected).abs() < 1e-3);
        }
        assert!(sampled.pdf().values().iter().all(|&p| p == 1.0 / 400.0));
        assert!(SampledWavelengths::sample_uniform(0.1, 800.0, 400.0).is_err());
        assert!(SampledWavelengths::sample_uniform(0.1, f32::NAN, 400.0).is_err());
    }

    #[test]
    fn termination_keeps_the_hero_with_a_quarter_pdf() {
        let mut sampled = SampledWavelengths::sample_visible(0.8);
        let hero_pdf = sampled.pdf()[0];
        sampled.terminate_secondary();
        assert!(sampled.secondary_terminated());
        assert_eq!(sampled.pdf()[0], hero_pdf / 4.0);
        assert!(sampled.pdf().values()[1..].iter().all(|&p| p == 0.0));
        sampled.terminate_secondary();
        assert_eq!(sampled.pdf()[0], hero_pdf / 4.0);
    }

    #[test]
    fn sampled_wavelengths_follow_the_density_chi_square() {
        // 200,000 wavelengths from hashed (independent) numbers, in 47 bins
        // of 10 nm, against the counts the f64 CDF predicts.
        let bins = 47;
        let count = 200_000;
        let mut observed = vec![0u64; bins];
        for index in 0..count {
            let u = qmc::hash::to_unit_f64(qmc::hash::hash2(index, 7)) as f32;
            let lambda = sample_visible_wavelength(u.min(1.0 - f32::EPSILON));
            let bin = (((lambda - VISIBLE_LAMBDA_MIN) / 10.0) as usize).min(bins - 1);
            observed[bin] += 1;
        }
        let expected: Vec<f64> = (0..bins)
            .map(|bin| {
                let low = VISIBLE_LAMBDA_MIN + bin as f32 * 10.0;
                let high = if bin + 1 == bins {
                    VISIBLE_LAMBDA_MAX
                } else {
                    low + 10.0
                };
                f64::from(visible_wavelength_cdf(high) - visible_wavelength_cdf(low)) * count as f64
            })
            .collect();
        let result = crate::statistics::chi_square_test(&observed, &expected);
        assert!(result.p_value > 1e-4, "{result:?}");
    }

    #[test]
    fn out_of_range_samples_are_wrapped() {
        assert_eq!(
            SampledWavelengths::sample_visible(1.25),
            SampledWavelengths::sample_visible(0.25)
        );
        let nan = SampledWavelengths::sample_visible(f32::NAN);
        assert!(nan.lambdas().iter().all(|l| l.is_finite()));
    }
}
