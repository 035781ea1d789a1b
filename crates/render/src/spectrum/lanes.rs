//! Four-lane elementary functions for the wavelength sampler: one call works on
//! all [`SPECTRUM_SAMPLE_COUNT`] wavelengths of a path, written as plain loops
//! over arrays of four `f32` with no branches so that the compiler turns each
//! step into one SSE instruction instead of four calls to the C library; and
//! the NaN-to-minimum [`clamp`] that the spectrum code uses where a clamp must
//! vectorise.

use super::wavelengths::SPECTRUM_SAMPLE_COUNT;

/// Four `f32` lanes, one per sampled wavelength.
pub(crate) type Lanes = [f32; SPECTRUM_SAMPLE_COUNT];

/// ln 2 split into a high part with trailing zero bits (so that
/// `exponent * LN_2_HIGH` is exact for the exponents of f32) and the rest,
/// as in Cephes' `logf` (Moshier, Cephes Math Library, `logf.c`).
const LN_2_HIGH: f32 = 0.693_359_4;
/// ln 2 − [`LN_2_HIGH`] (Cephes `logf.c`).
const LN_2_LOW: f32 = -2.121_944_4e-4;

/// √½ in f32: mantissas are reduced to [√½, √2) so that |s| below stays under
/// 0.172.
const SQRT_HALF: f32 = std::f32::consts::FRAC_1_SQRT_2;

/// Bits of the f32 exponent field.
const EXPONENT_MASK: u32 = 0x7f80_0000;

/// Lane-wise natural logarithm of positive, finite, normal numbers.
///
/// x = 2ᵉ m with m in [√½, √2); then ln x = e ln 2 + ln m and
/// ln m = 2 atanh(s) with s = (m − 1) / (m + 1), |s| < 0.172, from the series
/// atanh s = s + s³/3 + s⁵/5 + s⁷/7 + s⁹/9 + … (truncation error below
/// 2 s¹¹/11 < 10⁻⁹ relative). Measured against `f32::ln` on [2⁻⁸, 2⁸] the
/// relative error is below 3·10⁻⁷ (see the tests). Inputs that are zero,
/// negative, subnormal, infinite or NaN give meaningless but finite-or-NaN
/// values, never a panic; the sampler only passes numbers in about
/// [0.015, 66].
#[inline]
pub(crate) fn ln(x: Lanes) -> Lanes {
    let mut result = [0.0; SPECTRUM_SAMPLE_COUNT];
    for (result, &x) in result.iter_mut().zip(&x) {
        let bits = x.to_bits();
        // m in [1, 2) with the unbiased exponent e.
        let mantissa = f32::from_bits((bits & !EXPONENT_MASK) | 0x3f80_0000);
        let exponent = ((bits & EXPONENT_MASK) >> 23) as i32 - 127;
        // Move m ≥ √2 to m / 2 with e + 1, so that m lies in [√½, √2).
        let high = mantissa >= 2.0 * SQRT_HALF;
        let mantissa = if high { 0.5 * mantissa } else { mantissa };
        let exponent = (exponent + i32::from(high)) as f32;
        let s = (mantissa - 1.0) / (mantissa + 1.0);
        let s2 = s * s;
        let series =
            ((((s2 * (1.0 / 9.0) + 1.0 / 7.0) * s2 + 1.0 / 5.0) * s2 + 1.0 / 3.0) * s2) * s;
        // 2 s + 2 s (s²/3 + …), adding the small terms first.
        let ln_mantissa = 2.0 * s + 2.0 * series;
        *result = exponent * LN_2_LOW + ln_mantissa + exponent * LN_2_HIGH;
    }
    result
}

/// `value` clamped to [`min`, `max`] as a maximum then a minimum, each in the
/// form of the SSE `maxps`/`minps` instructions (`a > b ? a : b`, which
/// picks `b` when `a` is NaN): NaN becomes `min`, and unlike `f32::clamp` it
/// never panics (with `min > max` the result is `max`). Used where a clamp
/// must vectorise without a NaN test.
#[inline(always)]
pub(crate) fn clamp(value: f32, min: f32, max: f32) -> f32 {
    let above = if value > min { value } else { min };
    if above < max { above } else { max }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Relative error of [`ln`] against `f32::ln`, with an absolute floor near
    /// x = 1 where ln x itself goes to 0.
    fn error(x: f32) -> f64 {
        let lanes = ln([x; SPECTRUM_SAMPLE_COUNT]);
        let exact = f64::from(x).ln();
        let got = f64::from(lanes[0]);
        assert!(lanes.iter().all(|&lane| lane == lanes[0]));
        (got - exact).abs() / exact.abs().max(1e-3)
    }

    #[test]
    fn matches_the_library_logarithm() {
        // Every 64th f32 in [2⁻⁸, 2⁸], which covers the sampler's [0.015, 66].
        let start = (1.0f32 / 256.0).to_bits();
        let end = 256.0f32.to_bits();
        let mut worst = (0.0, 0.0f32);
        for bits in (start..=end).step_by(64) {
            let x = f32::from_bits(bits);
            let error = error(x);
            if error > worst.0 {
                worst = (error, x);
            }
        }
        assert!(
            worst.0 <= 3e-7,
            "worst relative error {} at {}",
            worst.0,
            worst.1
        );
    }

    #[test]
    fn exact_at_powers_of_two_and_one() {
        assert_eq!(ln([1.0; 4]), [0.0; 4]);
        let values = ln([2.0, 0.5, 4.0, 0.25]);
        let expected = [2.0f32.ln(), 0.5f32.ln(), 4.0f32.ln(), 0.25f32.ln()];
        for (value, expected) in values.iter().zip(expected) {
            assert!((value - expected).abs() <= 1e-7, "{value} vs {expected}");
        }
    }

    #[test]
    fn lanes_are_independent() {
        let x = [0.015, 1.5, 7.0, 66.0];
        let values = ln(x);
        for (value, x) in values.iter().zip(x) {
            assert!((value - x.ln()).abs() <= 3e-7 * x.ln().abs(), "{x}");
        }
    }

    #[test]
    fn clamp_sends_nan_to_the_minimum() {
        assert_eq!(clamp(0.5, 0.0, 1.0), 0.5);
        assert_eq!(clamp(-2.0, 0.0, 1.0), 0.0);
        assert_eq!(clamp(f32::INFINITY, 0.0, 1.0), 1.0);
        assert_eq!(clamp(f32::NAN, 0.0, 1.0), 0.0);
        assert_eq!(clamp(0.5, 3.0, 1.0), 1.0);
    }

    #[test]
    fn bad_inputs_do_not_panic() {
        let values = ln([0.0, -1.0, f32::NAN, f32::INFINITY]);
        assert_eq!(values.len(), 4);
    }
}
