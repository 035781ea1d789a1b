//! Pearson's chi-square goodness-of-fit test for the sampling tests: bins
//! with expected count below 5 are merged (in order, into the next bin)
//! and the p-value comes from the regularised upper incomplete gamma
//! function `Q(k/2, χ²/2)` (Numerical Recipes, 3rd ed., section 6.2: the
//! series for `x < a + 1`, the continued fraction otherwise).

/// The p-value of observing `observed` counts when `expected` are the
/// expected counts of the same bins (same length, expected ≥ 0).
pub fn chi_square_p_value(observed: &[u64], expected: &[f64]) -> f64 {
    assert_eq!(observed.len(), expected.len());
    const MINIMUM_EXPECTED: f64 = 5.0;
    let mut statistic = 0.0;
    let mut merged_bins = 0usize;
    let (mut pending_observed, mut pending_expected) = (0.0f64, 0.0f64);
    for (&count, &mean) in observed.iter().zip(expected) {
        pending_observed += count as f64;
        pending_expected += mean;
        if pending_expected >= MINIMUM_EXPECTED {
            let difference = pending_observed - pending_expected;
            statistic += difference * difference / pending_expected;
            merged_bins += 1;
            pending_observed = 0.0;
            pending_expected = 0.0;
        }
    }
    if pending_expected > 0.0 || pending_observed > 0.0 {
        if pending_expected == 0.0 {
            return 0.0; // samples where none may fall
        }
        let difference = pending_observed - pending_expected;
        statistic += difference * difference / pending_expected;
        merged_bins += 1;
    }
    let degrees_of_freedom = merged_bins.saturating_sub(1).max(1);
    upper_regularized_gamma_half_integer(degrees_of_freedom, statistic / 2.0)
}

/// `ln Γ(k/2)` for a positive integer `k`, by the recurrence
/// `Γ(a + 1) = a Γ(a)` from `Γ(1) = 1` and `Γ(1/2) = √π` (exact enough for
/// the degrees of freedom of these tests, with no approximation).
fn log_gamma_half_integer(twice_a: usize) -> f64 {
    let mut a = if twice_a.is_multiple_of(2) { 1.0 } else { 0.5 };
    let mut log_gamma = if twice_a.is_multiple_of(2) {
        0.0
    } else {
        0.5 * std::f64::consts::PI.ln()
    };
    while 2.0 * a < twice_a as f64 {
        log_gamma += a.ln();
        a += 1.0;
    }
    log_gamma
}

/// `Q(a, x) = Γ(a, x) / Γ(a)` for `a = twice_a / 2`.
fn upper_regularized_gamma_half_integer(twice_a: usize, x: f64) -> f64 {
    let a = twice_a as f64 / 2.0;
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefactor = -x + a * x.ln() - log_gamma_half_integer(twice_a);
    if x < a + 1.0 {
        // P(a, x) = e^{-x} x^a / Γ(a+1) Σ xⁿ / ((a+1)…(a+n)).
        let mut term = 1.0 / a;
        let mut sum = term;
        let mut denominator = a;
        for _ in 0..10_000 {
            denominator += 1.0;
            term *= x / denominator;
            sum += term;
            if term < sum * 1e-16 {
                break;
            }
        }
        1.0 - sum * log_prefactor.exp()
    } else {
        // Continued fraction for Q by the modified Lentz method.
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for index in 1..10_000 {
            let an = -(index as f64) * (index as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        log_prefactor.exp() * h
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chi_square_survival_matches_reference_values() {
        // Chi-square survival function values from scipy.stats.chi2.sf(x, k).
        let references = [
            (1, 3.841_458_820_694_124, 0.05),
            (2, 2.0, 0.367_879_441_171_442_3),
            (10, 10.0, 0.440_493_285_065_212_2),
            (399, 450.0, 0.039_451_165_086_979_65),
            (5, 0.5, 0.992_123_293_232_629_6),
        ];
        for (k, x, expected) in references {
            let value = upper_regularized_gamma_half_integer(k, x / 2.0);
            assert!(
                (value - expected).abs() < 1e-9 * expected,
                "k={k} x={x}: {value}"
            );
        }
    }
}
