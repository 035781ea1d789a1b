//! Radical inverses in prime bases: plain, digit-permuted and Owen-scrambled.
//!
//! The radical inverse of an index `i = Σ_k d_k b^k` in base `b` mirrors its
//! digits about the radix point: `Φ_b(i) = Σ_k d_k b^{-(k+1)}`. The Halton
//! sequence uses one prime base per dimension; the scrambled variants replace
//! each digit `d_k` by `σ_k(d_k)` for digit permutations `σ_k`.
//!
//! These functions are the straightforward evaluations; [`crate::halton`]
//! evaluates plain and Faure-permuted coordinates faster, with the same
//! values, through [`crate::digit_groups`].
//!
//! All functions take the full 64-bit index range: digits are extracted in
//! integers (no overflow, no loss), and the results are strictly below 1 in
//! both `f64` and `f32`.

use crate::hash::{below, hash2, mix64};
use crate::primes::{PRIME_COUNT, PRIMES};
use std::sync::OnceLock;

/// The largest `f64` below 1.
pub const ONE_MINUS_EPSILON_F64: f64 = 1.0 - f64::EPSILON / 2.0;
/// The largest `f32` below 1.
pub const ONE_MINUS_EPSILON_F32: f32 = 1.0 - f32::EPSILON / 2.0;

/// A digit base with the constants that make digit extraction fast.
///
/// Division by a base uses Lemire, Kaser & Kurz (2019, "Faster remainder by
/// direct computation"): for a 32-bit dividend `n`, a divisor `d < 2^32` and
/// `M = ⌈2^64 / d⌉`, `⌊n / d⌋ = ⌊M·n / 2^64⌋` exactly: a multiplication
/// instead of a division. Digits are taken two at a time (dividing by `b²`),
/// which halves the dependent chain of multiplications. Indices of 2^32 and
/// more are first split by the largest power of `b` below 2^32 with one
/// hardware division.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DigitBase {
    /// The base `b ≥ 2`.
    pub base: u32,
    /// `⌈2^64 / b⌉`.
    reciprocal: u64,
    /// `b²`.
    base_squared: u64,
    /// `⌈2^64 / b²⌉`.
    reciprocal_squared: u64,
    /// The largest power `b^k ≤ 2^32`, which splits 64-bit indices.
    chunk: u64,
    /// `1 / chunk`.
    inverse_chunk: f64,
    /// `1 / b` in double precision.
    pub inverse: f64,
    /// The number of base-`b` digits that keep `b^k ≤ 2^64`, i.e. the digits a
    /// 64-bit index can have; also enough digits for double precision.
    pub digit_count: u32,
}

/// `(n / d, n % d)` for `n < 2^32` and `reciprocal = ⌈2^64 / d⌉`.
#[inline(always)]
fn divide_32(n: u64, divisor: u64, reciprocal: u64) -> (u64, u64) {
    debug_assert!(n <= u32::MAX as u64);
    let quotient = ((reciprocal as u128 * n as u128) >> 64) as u64;
    (quotient, n - quotient * divisor)
}

impl DigitBase {
    /// Digit-extraction constants for `2 ≤ base < 65536`.
    pub const fn new(base: u32) -> Self {
        assert!(base >= 2 && base < 65536, "digit bases are in 2..65536");
        let mut digit_count = 0;
        let mut power: u128 = 1;
        while power < (1u128 << 64) {
            power *= base as u128;
            digit_count += 1;
        }
        let mut chunk = base as u64;
        while chunk * (base as u64) <= 1u64 << 32 {
            chunk *= base as u64;
        }
        let base_squared = base as u64 * base as u64;
        Self {
            base,
            reciprocal: (u64::MAX / base as u64).wrapping_add(1),
            base_squared,
            reciprocal_squared: (u64::MAX / base_squared).wrapping_add(1),
            chunk,
            inverse_chunk: 1.0 / chunk as f64,
            inverse: 1.0 / base as f64,
            digit_count,
        }
    }

    /// The largest power `c = b^k ≤ 2^32` and `1 / c`: splitting a 64-bit
    /// index by `c` leaves a low part below 2^32.
    pub(crate) fn chunk(&self) -> (u64, f64) {
        (self.chunk, self.inverse_chunk)
    }

    /// `(n / b, n % b)`.
    #[inline(always)]
    pub fn divide(&self, n: u64) -> (u64, u32) {
        if n <= u32::MAX as u64 {
            let (quotient, digit) = divide_32(n, self.base as u64, self.reciprocal);
            (quotient, digit as u32)
        } else {
            let base = self.base as u64;
            (n / base, (n % base) as u32)
        }
    }

    /// `Σ_k map(d_k) b^{-(k+1)}` for an index `n < 2^32` and a digit map
    /// with `map(0) = 0`, taking two digits per step.
    #[inline(always)]
    fn small_radical_inverse(&self, n: u64, map: impl Fn(u64) -> u64) -> f64 {
        let base = self.base as u64;
        let mut remaining = n;
        let mut reversed = 0u64;
        let mut power = 1u64;
        while remaining != 0 {
            let (quotient, pair) = divide_32(remaining, self.base_squared, self.reciprocal_squared);
            let (high, low) = divide_32(pair, base, self.reciprocal);
            // A final single digit gives high = 0: a trailing zero digit of the
            // reversed number, which does not change its value.
            reversed = reversed * self.base_squared + map(low) * base + map(high);
            power *= self.base_squared;
            remaining = quotient;
        }
        reversed as f64 / power as f64
    }

    /// The same for any 64-bit index: `Φ(n) = Φ(n mod c) + Φ(n / c) / c` with
    /// `c = b^k` the chunk, since the low `k` digits of `n` are those of `n mod c`.
    #[inline(always)]
    fn mapped_radical_inverse(&self, n: u64, map: impl Fn(u64) -> u64 + Copy) -> f64 {
        if n <= u32::MAX as u64 {
            self.small_radical_inverse(n, map)
        } else {
            // One hardware division: measured faster than the 128-bit
            // multiplication on this project's machine (21 ns against 13 ns
            // per coordinate for indices above 2^32).
            let (high, low) = (n / self.chunk, n % self.chunk);
            self.small_radical_inverse(low, map)
                + self.mapped_radical_inverse(high, map) * self.inverse_chunk
        }
    }
}

/// The digit bases of the first [`PRIME_COUNT`] primes, built once.
pub fn prime_digit_bases() -> &'static [DigitBase; PRIME_COUNT] {
    static BASES: OnceLock<[DigitBase; PRIME_COUNT]> = OnceLock::new();
    BASES.get_or_init(|| std::array::from_fn(|i| DigitBase::new(PRIMES[i])))
}

/// The radical inverse of `index` in the `base_index`-th prime base
/// (`base_index = 0` is base 2), for `base_index < PRIME_COUNT`.
#[inline]
pub fn radical_inverse(base_index: usize, index: u64) -> f64 {
    radical_inverse_in(&prime_digit_bases()[base_index], index)
}

/// As [`radical_inverse`], in single precision and strictly below 1.
#[inline]
pub fn radical_inverse_f32(base_index: usize, index: u64) -> f32 {
    (radical_inverse(base_index, index) as f32).min(ONE_MINUS_EPSILON_F32)
}

/// The radical inverse of `index` in the given base.
///
/// Digits are accumulated in an integer, so for indices below 2^32 the
/// result is one correctly rounded division whenever `b^k < 2^53`.
#[inline]
pub fn radical_inverse_in(base: &DigitBase, index: u64) -> f64 {
    if base.base == 2 {
        // Bit reversal is the base-2 radical inverse; the conversion rounds to
        // 53 bits and may round up to 2^64, hence the clamp.
        return (index.reverse_bits() as f64 * (1.0 / 18_446_744_073_709_551_616.0))
            .min(ONE_MINUS_EPSILON_F64);
    }
    base.mapped_radical_inverse(index, |digit| digit)
        .min(ONE_MINUS_EPSILON_F64)
}

/// The radical inverse with a digit permutation that fixes 0 (such as
/// Faure's): `Σ_k σ(d_k) b^{-(k+1)}`, where `permutation[d] = σ(d)` and
/// `σ(0) = 0`, so only the index's own digits contribute.
#[inline]
pub fn permuted_radical_inverse_fixing_zero(
    base: &DigitBase,
    permutation: &[u16],
    index: u64,
) -> f64 {
    debug_assert_eq!(permutation.len(), base.base as usize);
    debug_assert_eq!(permutation[0], 0);
    base.mapped_radical_inverse(index, |digit| permutation[digit as usize] as u64)
        .min(ONE_MINUS_EPSILON_F64)
}

/// One digit permutation per digit position of a base: the radical inverse
/// `Σ_k σ_k(d_k) b^{-(k+1)}` over all [`DigitBase::digit_count`] positions.
///
/// Since `σ_k(0)` need not be 0, the index's leading zero digits are permuted
/// too; their contribution, the same for every index with `k` digits, is
/// precomputed as `zero_tail[k] = Σ_{j≥k} σ_j(0) b^{-(j+1)}`.
#[derive(Debug, Clone, PartialEq)]
pub struct DigitPermutations {
    base: DigitBase,
    /// `digit_count` permutations of `0..base`, concatenated.
    permutations: Vec<u16>,
    zero_tail: Vec<f64>,
}

impl DigitPermutations {
    /// Random permutations: one Fisher–Yates shuffle per digit position,
    /// driven by hashes of `seed` and the position, so the permutations
    /// depend on the seed only.
    pub fn random(base: DigitBase, seed: u64) -> Self {
        let width = base.base as usize;
        let mut permutations = Vec::with_capacity(width * base.digit_count as usize);
        for position in 0..base.digit_count as u64 {
            let start = permutations.len();
            permutations.extend(0..base.base as u16);
            let permutation = &mut permutations[start..];
            let mut state = hash2(seed, position);
            for i in (1..width).rev() {
                state = mix64(state);
                let j = below(state, i + 1);
                permutation.swap(i, j);
            }
        }
        Self::from_concatenated(base, permutations)
    }

    /// A fixed permutation `σ` followed by a random digital shift in base
    /// `b`: digit position `k` maps `d ↦ (σ(d) + s_k) mod b` with `s_k`
    /// uniform in `0..b`, drawn from hashes of `seed` and the position.
    /// The shifts make every digit of a coordinate, leading zeros included,
    /// uniform and independent of the other positions, so each point is
    /// uniform on `[0, 1)` (on the grid of `b^-digit_count`); a shift per
    /// position is a bijection of each position's digits, so every
    /// elementary interval `[a b^-k, (a+1) b^-k)` maps onto one of the same
    /// size and the sequence's stratification is kept. (The random digital
    /// shift in base b of L'Ecuyer & Lemieux 2002, "Recent advances in
    /// randomized quasi-Monte Carlo methods", applied after `σ`.)
    pub fn shifted(base: DigitBase, permutation: &[u16], seed: u64) -> Self {
        assert_eq!(permutation.len(), base.base as usize, "one digit per base");
        let b = base.base as u64;
        let mut permutations = Vec::with_capacity(base.base as usize * base.digit_count as usize);
        for position in 0..base.digit_count as u64 {
            let shift = ((hash2(seed, position) >> 32) * b) >> 32;
            // (σ(d) + s) mod b with one comparison: both are below b.
            permutations.extend(permutation.iter().map(|&digit| {
                let shifted = digit as u64 + shift;
                (if shifted >= b { shifted - b } else { shifted }) as u16
            }));
        }
        Self::from_concatenated(base, permutations)
    }

    /// The permutations of every digit position, concatenated, with their
    /// zero tails.
    fn from_concatenated(base: DigitBase, permutations: Vec<u16>) -> Self {
        let width = base.base as usize;
        let mut zero_tail = vec![0.0; base.digit_count as usize + 1];
        for position in (0..base.digit_count as usize).rev() {
            let scale = base.inverse.powi(position as i32 + 1);
            zero_tail[position] =
                zero_tail[position + 1] + permutations[position * width] as f64 * scale;
        }
        Self {
            base,
            permutations,
            zero_tail,
        }
    }

    /// `Σ_{k ≥ position} σ_k(0) b^{-(k+1)}`: the value the permuted leading
    /// zeros from digit `position` on add (0 from `digit_count` on).
    pub fn zero_tail(&self, position: usize) -> f64 {
        self.zero_tail.get(position).copied().unwrap_or(0.0)
    }

    /// The number of digit positions that carry a permutation.
    pub fn position_count(&self) -> usize {
        self.base.digit_count as usize
    }

    /// The base.
    pub fn base(&self) -> &DigitBase {
        &self.base
    }

    /// The permutation of digit position `position`.
    pub fn permutation(&self, position: usize) -> &[u16] {
        let width = self.base.base as usize;
        &self.permutations[position * width..(position + 1) * width]
    }

    /// The permuted radical inverse of `index`.
    #[inline]
    pub fn radical_inverse(&self, index: u64) -> f64 {
        let width = self.base.base as usize;
        let mut remaining = index;
        let mut value = 0.0;
        let mut scale = self.base.inverse;
        let mut position = 0;
        while remaining != 0 {
            let (quotient, digit) = self.base.divide(remaining);
            value += self.permutations[position * width + digit as usize] as f64 * scale;
            scale *= self.base.inverse;
            remaining = quotient;
            position += 1;
        }
        (value + self.zero_tail[position]).min(ONE_MINUS_EPSILON_F64)
    }
}

/// The affine digit permutation `d ↦ (a·d + c) mod b`, `a ≠ 0`, of the node
/// hashed to `node_hash` in an Owen scramble.
///
/// Random affine maps over the prime field GF(b) send every digit to a
/// uniform digit and every pair of distinct digits to a uniform pair of
/// distinct digits. Owen's uniformity and variance results for nested
/// scrambling depend only on these one- and two-digit distributions (Owen
/// 1997; Matoušek 1998 on random linear scrambling), so they hold with this
/// cheap family; for b = 2 it is the full symmetric group and the scramble is
/// exactly Owen's.
#[inline(always)]
fn affine_digit_permutation(base: u32, node_hash: u64) -> (u64, u64) {
    let base = base as u64;
    let multiplier = 1 + (((node_hash & 0xFFFF_FFFF) * (base - 1)) >> 32);
    let offset = ((node_hash >> 32) * base) >> 32;
    (multiplier, offset)
}

/// The Owen-scrambled (nested uniform) radical inverse in base `b`.
///
/// The digit `d_k` is permuted by a random permutation chosen by the node of
/// the digit tree that the index's lower digits `d_0 … d_{k−1}` lead to (its
/// hash chains the digits with `seed`). All digit positions down to double
/// precision are scrambled, including the index's leading zeros.
#[inline]
pub fn owen_scrambled_radical_inverse(base: &DigitBase, seed: u64, index: u64) -> f64 {
    let mut remaining = index;
    let mut value = 0.0;
    let mut scale = base.inverse;
    let mut node = mix64(seed);
    let mut position = 0;
    // Scramble until b^-k is below half an ulp of 1 and the index is exhausted.
    while position < base.digit_count || remaining != 0 {
        let (quotient, digit) = base.divide(remaining);
        let (multiplier, offset) = affine_digit_permutation(base.base, node);
        let permuted = (multiplier * digit as u64 + offset) % base.base as u64;
        value += permuted as f64 * scale;
        scale *= base.inverse;
        remaining = quotient;
        node = mix64(node ^ (digit as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
        position += 1;
        if scale < f64::EPSILON * 0.25 && remaining == 0 {
            break;
        }
    }
    value.min(ONE_MINUS_EPSILON_F64)
}

/// The digits `d_0 … d_{k−1}` of the indices whose Owen-scrambled radical
/// inverse has the leading output digits `target` (`target[0]` most
/// significant), as the residue `Σ d_j b^j` modulo `b^k`. This inverts the
/// scramble digit by digit, walking down the same tree nodes as
/// [`owen_scrambled_radical_inverse`]; per-pixel enumeration uses it.
pub fn owen_scrambled_leading_digits_preimage(base: &DigitBase, seed: u64, target: &[u32]) -> u64 {
    let b = base.base as u64;
    let mut node = mix64(seed);
    let mut residue = 0u64;
    let mut power = 1u64;
    for &wanted in target {
        let (multiplier, offset) = affine_digit_permutation(base.base, node);
        // Solve multiplier·d + offset ≡ wanted (mod b) for d.
        let inverse = modular_inverse(multiplier, b);
        let digit = ((wanted as u64 + b - offset) % b * inverse) % b;
        residue += digit * power;
        power *= b;
        node = mix64(node ^ (digit + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15));
    }
    residue
}

/// The inverse of `value` modulo the prime `modulus` (Fermat's little theorem).
pub(crate) fn modular_inverse(value: u64, modulus: u64) -> u64 {
    let mut result = 1u64;
    let mut power = value % modulus;
    let mut exponent = modulus - 2;
    while exponent > 0 {
        if exponent & 1 == 1 {
            result = result * power % modulus;
        }
        power = power * power % modulus;
        exponent >>= 1;
    }
    result
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Radical inverse by exact rational arithmetic, for checking.
    fn reference_radical_inverse(base: u64, mut index: u64) -> f64 {
        let mut numerator: u128 = 0;
        let mut denominator: u128 = 1;
        while index > 0 {
            numerator = numerator * base as u128 + (index % base) as u128;
            denominator *= base as u128;
            index /= base;
        }
        numerator as f64 / denominator as f64
    }

    #[test]
    fn van_der_corput_matches_scipy_reference() {
        let expected = [0.0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875];
        for (index, &value) in expected.iter().enumerate() {
            assert_eq!(radical_inverse(0, index as u64), value);
        }
    }

    #[test]
    fn base_three_values() {
        let expected = [0.0, 1.0 / 3.0, 2.0 / 3.0, 1.0 / 9.0, 4.0 / 9.0, 7.0 / 9.0];
        for (index, &value) in expected.iter().enumerate() {
            assert!((radical_inverse(1, index as u64) - value).abs() < 1e-16);
        }
    }

    #[test]
    fn fast_division_is_exact() {
        for base_index in [0usize, 1, 2, 10, 100, 1023] {
            let base = prime_digit_bases()[base_index];
            for n in [
                0u64,
                1,
                2,
                12345,
                u32::MAX as u64,
                u32::MAX as u64 + 1,
                u64::MAX,
            ] {
                let (q, d) = base.divide(n);
                assert_eq!(q, n / base.base as u64);
                assert_eq!(d as u64, n % base.base as u64);
            }
        }
    }

    #[test]
    fn exact_for_large_indices_and_below_one() {
        for base_index in [0usize, 1, 5, 500, 1023] {
            let base = PRIMES[base_index] as u64;
            for index in [
                u64::MAX,
                u64::MAX - 1,
                1 << 63,
                3u64.pow(40),
                987_654_321_987,
            ] {
                let value = radical_inverse(base_index, index);
                assert!(value < 1.0);
                // Digits beyond what fits in 128 bits are below double precision.
                let reference = reference_radical_inverse_wide(base, index);
                assert!(
                    (value - reference).abs() <= 4.0 * f64::EPSILON,
                    "base {base} index {index}: {value} vs {reference}"
                );
                assert!(radical_inverse_f32(base_index, index) < 1.0);
            }
        }
    }

    /// Reference for indices whose reversed digits do not fit 128 bits.
    fn reference_radical_inverse_wide(base: u64, mut index: u64) -> f64 {
        let mut value = 0.0f64;
        let mut scale = 1.0 / base as f64;
        while index > 0 {
            value += (index % base) as f64 * scale;
            scale /= base as f64;
            index /= base;
        }
        value
    }

    #[test]
    fn small_indices_match_rational_reference_exactly() {
        for base_index in [1usize, 2, 3, 50] {
            let base = PRIMES[base_index] as u64;
            for index in 0..2000u64 {
                let reference = reference_radical_inverse(base, index);
                assert!((radical_inverse(base_index, index) - reference).abs() <= 2e-16);
            }
        }
    }

    #[test]
    fn faure_permuted_fixing_zero_of_identity_is_plain() {
        let base = prime_digit_bases()[4];
        let identity: Vec<u16> = (0..base.base as u16).collect();
        for index in 0..500 {
            let permuted = permuted_radical_inverse_fixing_zero(&base, &identity, index);
            assert!((permuted - radical_inverse_in(&base, index)).abs() < 1e-15);
        }
    }

    #[test]
    fn random_permutations_are_bijections() {
        let base = prime_digit_bases()[3];
        let permutations = DigitPermutations::random(base, 42);
        for position in 0..base.digit_count as usize {
            let permutation = permutations.permutation(position);
            let mut sorted = permutation.to_vec();
            sorted.sort_unstable();
            assert!(sorted.iter().enumerate().all(|(i, &v)| i == v as usize));
        }
    }

    #[test]
    fn permuted_radical_inverse_matches_digit_by_digit_sum() {
        let base = prime_digit_bases()[1];
        let permutations = DigitPermutations::random(base, 3);
        for index in [0u64, 1, 2, 80, 12345, u32::MAX as u64 + 7, u64::MAX] {
            let mut remaining = index;
            let mut expected = 0.0;
            for position in 0..base.digit_count as usize {
                let digit = (remaining % 3) as usize;
                expected += permutations.permutation(position)[digit] as f64
                    * 3f64.powi(-(position as i32 + 1));
                remaining /= 3;
            }
            let value = permutations.radical_inverse(index);
            assert!(
                (value - expected).abs() < 1e-15,
                "{index}: {value} vs {expected}"
            );
        }
    }

    #[test]
    fn random_permutation_first_digit_stratifies() {
        // The first b points of a randomly permuted radical inverse fall one
        // in each interval [k/b, (k+1)/b).
        let base = prime_digit_bases()[2];
        let permutations = DigitPermutations::random(base, 7);
        let mut seen = [false; 5];
        for index in 0..5 {
            let value = permutations.radical_inverse(index);
            seen[(value * 5.0) as usize] = true;
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn owen_scrambling_keeps_strata_and_inverts() {
        for base_index in [0usize, 1, 3] {
            let base = prime_digit_bases()[base_index];
            let b = base.base as u64;
            let count = b * b;
            let mut cells = vec![0u32; count as usize];
            for index in 0..count {
                let value = owen_scrambled_radical_inverse(&base, 99, index);
                let cell = (value * count as f64) as usize;
                cells[cell] += 1;
                // Invert the two leading output digits of this value.
                let digits = [(cell as u64 / b) as u32, (cell as u64 % b) as u32];
                let residue = owen_scrambled_leading_digits_preimage(&base, 99, &digits);
                assert_eq!(residue, index % count);
            }
            assert!(cells.iter().all(|&c| c == 1));
        }
    }

    #[test]
    fn owen_scrambled_value_is_uniform_over_seeds() {
        // The scrambled value of a fixed index is uniform on [0, 1): mean 1/2,
        // variance 1/12. With n seeds the mean's standard error is √(1/(12 n)).
        let base = prime_digit_bases()[2];
        let n = 20_000;
        let mean: f64 = (0..n)
            .map(|seed| owen_scrambled_radical_inverse(&base, seed, 17))
            .sum::<f64>()
            / n as f64;
        let standard_error = (1.0 / (12.0 * n as f64)).sqrt();
        assert!((mean - 0.5).abs() < 5.0 * standard_error, "mean {mean}");
    }

    #[test]
    fn modular_inverse_is_inverse() {
        for p in [2u64, 3, 5, 7, 8161] {
            for v in 1..p.min(100) {
                assert_eq!(v * modular_inverse(v, p) % p, 1);
            }
        }
    }
}
