//! Statistics for the sampling tests: Pearson's chi-square goodness-of-fit
//! test and the special functions behind its p-value.
//!
//! The sampling routines of the renderer (filters, wavelengths, BSDFs,
//! shapes) are checked by histogramming many samples and comparing the counts
//! with those their densities predict. This module is the one implementation
//! of that comparison, so that every test judges a fit the same way:
//!
//! - [`chi_square_test`] merges bins, in order, until each merged bin expects
//!   at least [`MINIMUM_EXPECTED_COUNT`] samples (the usual condition for the
//!   chi-square approximation to hold), then returns the statistic, the degrees
//!   of freedom and the p-value;
//! - [`chi_square_survival`] is the p-value of a given statistic;
//! - [`regularized_gamma_q`] and [`ln_gamma`] are the special functions these
//!   need (Numerical Recipes, 3rd ed., sections 6.1 and 6.2).

use std::f64::consts::PI;

/// Bins are merged until each merged bin expects at least this many samples.
pub const MINIMUM_EXPECTED_COUNT: f64 = 5.0;

/// The outcome of [`chi_square_test`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ChiSquareResult {
    /// Pearson's statistic `Σ (observed − expected)² / expected` over the
    /// merged bins; infinite when samples fell where none were expected.
    pub statistic: f64,
    /// The number of merged bins minus one (at least 1).
    pub degrees_of_freedom: usize,
    /// The probability of a statistic at least this large if the samples do
    /// follow the expected distribution; small values reject the fit.
    pub p_value: f64,
}

/// Pearson's chi-square goodness-of-fit test of `observed` counts against the
/// `expected` counts of the same bins.
///
/// Bins are merged in order (each into the next) until the merged bin expects
/// at least [`MINIMUM_EXPECTED_COUNT`] samples; a remainder at the end that
/// still expects fewer is kept as a bin of its own. Samples in a bin that
/// expects none are impossible under the tested distribution, so they give an
/// infinite statistic and a p-value of 0.
///
/// # Panics
///
/// If the slices differ in length or an expected count is negative or not
/// finite.
pub fn chi_square_test(observed: &[u64], expected: &[f64]) -> ChiSquareResult {
    assert_eq!(
        observed.len(),
        expected.len(),
        "observed and expected counts must describe the same bins"
    );
    let mut statistic = 0.0;
    let mut merged_bins = 0usize;
    let mut impossible_samples = false;
    let (mut pending_observed, mut pending_expected) = (0.0f64, 0.0f64);
    for (&count, &mean) in observed.iter().zip(expected) {
        assert!(
            mean.is_finite() && mean >= 0.0,
            "expected count {mean} must be finite and non-negative"
        );
        impossible_samples |= mean == 0.0 && count > 0;
        pending_observed += count as f64;
        pending_expected += mean;
        if pending_expected >= MINIMUM_EXPECTED_COUNT {
            statistic += pearson_term(pending_observed, pending_expected);
            merged_bins += 1;
            pending_observed = 0.0;
            pending_expected = 0.0;
        }
    }
    if pending_expected > 0.0 {
        statistic += pearson_term(pending_observed, pending_expected);
        merged_bins += 1;
    }
    let degrees_of_freedom = merged_bins.saturating_sub(1).max(1);
    if impossible_samples {
        return ChiSquareResult {
            statistic: f64::INFINITY,
            degrees_of_freedom,
            p_value: 0.0,
        };
    }
    ChiSquareResult {
        statistic,
        degrees_of_freedom,
        p_value: chi_square_survival(statistic, degrees_of_freedom),
    }
}

/// One bin's contribution `(observed − expected)² / expected` to Pearson's
/// statistic.
fn pearson_term(observed: f64, expected: f64) -> f64 {
    let difference = observed - expected;
    difference * difference / expected
}

/// `P(X ≥ statistic)` for `X` chi-square distributed with
/// `degrees_of_freedom` degrees of freedom: `Q(k/2, statistic/2)`.
pub fn chi_square_survival(statistic: f64, degrees_of_freedom: usize) -> f64 {
    regularized_gamma_q(degrees_of_freedom as f64 / 2.0, statistic / 2.0)
}

/// `P(T ≥ t)` for `T` Student-t distributed with `degrees_of_freedom`
/// degrees of freedom, `t ≥ 0`: the density
/// `Γ((ν+1)/2) / (√(νπ) Γ(ν/2)) (1 + x²/ν)^{−(ν+1)/2}` integrated over
/// `[t, ∞)` by Simpson's rule after the substitution `x = t / u`, which maps
/// the tail onto `u ∈ (0, 1]` (the integrand vanishes as `u → 0` for
/// `ν ≥ 1`). Accurate to about 1e-9 for `t ≥ 1`; `t < 1` uses the
/// symmetry `P(T ≥ t) = 1/2 − P(0 ≤ T < t)` with the same rule on `[0, t]`.
pub fn student_t_survival(t: f64, degrees_of_freedom: f64) -> f64 {
    let nu = degrees_of_freedom;
    let normalisation = (ln_gamma((nu + 1.0) / 2.0) - ln_gamma(nu / 2.0)).exp()
        / (nu * std::f64::consts::PI).sqrt();
    let density = |x: f64| normalisation * (1.0 + x * x / nu).powf(-(nu + 1.0) / 2.0);
    const INTERVALS: usize = 4000;
    let simpson = |integrand: &dyn Fn(f64) -> f64, start: f64, end: f64| {
        let step = (end - start) / INTERVALS as f64;
        let mut sum = integrand(start) + integrand(end);
        for i in 1..INTERVALS {
            let weight = if i % 2 == 1 { 4.0 } else { 2.0 };
            sum += weight * integrand(start + i as f64 * step);
        }
        sum * step / 3.0
    };
    if t >= 1.0 {
        let tail = |u: f64| {
            if u <= 0.0 {
                0.0
            } else {
                density(t / u) * t / (u * u)
            }
        };
        simpson(&tail, 0.0, 1.0)
    } else {
        0.5 - simpson(&density, 0.0, t.max(0.0))
    }
}

/// The `t` with `P(|T| ≥ t) = probability` for Student's t with
/// `degrees_of_freedom` degrees of freedom (bisection on
/// [`student_t_survival`]), for `0 < probability < 1`.
pub fn student_t_two_sided_critical(probability: f64, degrees_of_freedom: f64) -> f64 {
    let (mut low, mut high) = (0.0f64, 1e4f64);
    for _ in 0..200 {
        let middle = 0.5 * (low + high);
        if 2.0 * student_t_survival(middle, degrees_of_freedom) > probability {
            low = middle;
        } else {
            high = middle;
        }
    }
    0.5 * (low + high)
}

/// Relative size of the last term (series) or correction (continued fraction)
/// at which [`regularized_gamma_q`] stops.
const GAMMA_CONVERGENCE: f64 = 1e-16;
/// More iterations than either expansion needs for the arguments of these
/// tests; a bound so that a bad argument cannot loop forever.
const GAMMA_MAX_ITERATIONS: usize = 10_000;

/// The regularised upper incomplete gamma function
/// `Q(a, x) = Γ(a, x) / Γ(a)` for `a > 0`, `x ≥ 0`.
///
/// For `x < a + 1` it sums the power series of `P(a, x) = 1 − Q(a, x)`, which
/// converges quickly there; otherwise it evaluates the continued fraction of
/// `Q` by the modified Lentz method.
pub fn regularized_gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefactor = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        // P(a, x) = e^{-x} x^a / Γ(a + 1) · Σₙ xⁿ / ((a + 1)…(a + n)).
        let mut term = 1.0 / a;
        let mut sum = term;
        let mut denominator = a;
        for _ in 0..GAMMA_MAX_ITERATIONS {
            denominator += 1.0;
            term *= x / denominator;
            sum += term;
            if term.abs() < sum.abs() * GAMMA_CONVERGENCE {
                break;
            }
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        // Q(a, x) = e^{-x} x^a / Γ(a) ·
        //   1 / (x + 1 − a − 1·(1 − a) / (x + 3 − a − 2·(2 − a) / (x + 5 − a − …))).
        const TINY: f64 = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / TINY;
        let mut d = 1.0 / b;
        let mut fraction = d;
        for index in 1..GAMMA_MAX_ITERATIONS {
            let numerator = -(index as f64) * (index as f64 - a);
            b += 2.0;
            d = numerator * d + b;
            if d.abs() < TINY {
                d = TINY;
            }
            c = b + numerator / c;
            if c.abs() < TINY {
                c = TINY;
            }
            d = 1.0 / d;
            let correction = d * c;
            fraction *= correction;
            if (correction - 1.0).abs() < GAMMA_CONVERGENCE {
                break;
            }
        }
        log_prefactor.exp() * fraction
    }
}

/// `ln Γ(x)` for `x > 0` by the Lanczos approximation (g = 7, the nine
/// coefficients published by Godfrey; relative error about 1e-15), with the
/// reflection formula `Γ(x) Γ(1 − x) = π / sin(πx)` below 1/2.
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const COEFFICIENTS: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let mut sum = COEFFICIENTS[0];
    for (index, &coefficient) in COEFFICIENTS.iter().enumerate().skip(1) {
        sum += coefficient / (x + index as f64);
    }
    let t = x + G + 0.5;
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Tabulated two-sided critical values of Student's t: 2.131 (ν = 15,
    /// 5 %), 4.073 (ν = 15, 0.1 %), 2.576 (ν = 10⁶, 1 %: the normal).
    #[test]
    fn student_t_critical_values_match_the_tables() {
        for (probability, dof, expected) in [
            (0.05, 15.0, 2.1314),
            (0.001, 15.0, 4.0728),
            (0.01, 1e6, 2.5758),
        ] {
            let critical = student_t_two_sided_critical(probability, dof);
            assert!(
                (critical - expected).abs() < 2e-3,
                "{critical} vs {expected}"
            );
        }
        assert!((student_t_survival(0.0, 7.0) - 0.5).abs() < 1e-12);
    }

    #[test]
    fn ln_gamma_matches_factorials_and_the_half_integer_value() {
        assert!((ln_gamma(5.0) - 24.0_f64.ln()).abs() < 1e-12);
        assert!((ln_gamma(10.0) - 362_880.0_f64.ln()).abs() < 1e-12);
        assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-12);
    }

    #[test]
    fn regularized_gamma_q_matches_closed_forms() {
        // Q(1, x) = e^{−x} (both expansions).
        for x in [0.3, 0.7, 2.5, 3.0, 7.0] {
            assert!(
                (regularized_gamma_q(1.0, x) - (-x).exp()).abs() < 1e-12,
                "x = {x}"
            );
        }
        // Q(1/2, x) = erfc(√x); erfc(1) = 0.157299207050285.
        assert!((regularized_gamma_q(0.5, 1.0) - 0.157_299_207_050_285).abs() < 1e-10);
        assert!((regularized_gamma_q(100.0, 60.0) - 0.999_999_4).abs() < 1e-6);
    }

    #[test]
    fn chi_square_survival_matches_known_quantiles() {
        // scipy.stats.chi2.sf(x, k).
        let references = [
            (1, 3.841_458_820_694_124, 0.05),
            (2, 2.0, 0.367_879_441_171_442_3),
            (10, 10.0, 0.440_493_285_065_212_2),
            (399, 450.0, 0.039_451_165_086_979_65),
            (5, 0.5, 0.992_123_293_232_629_6),
        ];
        for (k, x, expected) in references {
            let value = chi_square_survival(x, k);
            assert!(
                (value - expected).abs() < 1e-9 * expected,
                "k={k} x={x}: {value}"
            );
        }
        // Abramowitz and Stegun, table 26.8: P(χ²₁ > 3.841) = 0.05,
        // P(χ²₁₀ > 23.209) = 0.01.
        assert!((chi_square_survival(3.841_459, 1) - 0.05).abs() < 1e-6);
        assert!((chi_square_survival(23.209_251, 10) - 0.01).abs() < 1e-6);
        // Medians: χ²₁₀ at 9.341818, χ²₁₀₀ at about 99.3341.
        assert!((chi_square_survival(9.341_818, 10) - 0.5).abs() < 1e-5);
        assert!((chi_square_survival(99.3341, 100) - 0.5).abs() < 1e-4);
        // χ²₁₀₀ survival at 120 = 0.0844067 (scipy; continued-fraction branch).
        assert!((chi_square_survival(120.0, 100) - 0.084_406_7).abs() < 1e-6);
    }

    #[test]
    fn chi_square_test_accepts_a_perfect_fit_and_rejects_a_gross_misfit() {
        let perfect = chi_square_test(&[100, 100, 100, 100], &[100.0; 4]);
        assert_eq!(perfect.statistic, 0.0);
        assert_eq!(perfect.degrees_of_freedom, 3);
        assert!((perfect.p_value - 1.0).abs() < 1e-12);

        let misfit = chi_square_test(&[150, 50, 100, 100], &[100.0; 4]);
        assert!((misfit.statistic - 50.0).abs() < 1e-12);
        assert!(misfit.p_value < 1e-6);
    }

    #[test]
    fn chi_square_test_merges_bins_expecting_fewer_than_five() {
        // Bins 0–2 merge into one expecting 6 (observed 5); bin 3 stands
        // alone; the trailing 2 + 1 remain a bin of their own.
        let result = chi_square_test(&[1, 2, 2, 10, 3, 0], &[2.0, 2.0, 2.0, 10.0, 2.0, 1.0]);
        assert_eq!(result.degrees_of_freedom, 2);
        let expected_statistic = 1.0 / 6.0;
        assert!((result.statistic - expected_statistic).abs() < 1e-12);
        assert!((result.p_value - chi_square_survival(expected_statistic, 2)).abs() < 1e-15);
    }

    #[test]
    fn chi_square_test_rejects_samples_where_none_are_expected() {
        let result = chi_square_test(&[50, 1, 50], &[50.0, 0.0, 51.0]);
        assert_eq!(result.p_value, 0.0);
        assert_eq!(result.statistic, f64::INFINITY);
        // Empty bins that expect nothing are harmless.
        let result = chi_square_test(&[50, 0, 50], &[50.0, 0.0, 50.0]);
        assert_eq!(result.degrees_of_freedom, 1);
        assert!((result.p_value - 1.0).abs() < 1e-12);
    }
}
