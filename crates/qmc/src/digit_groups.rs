//! Table-driven radical inverses: several digits per step.
//!
//! The radical inverse `Φ_b(i) = Σ_j σ(d_j) b^{-(j+1)}` of an index below 2^32
//! is evaluated `k` digits at a time: dividing by the group `g = b^k` (one
//! multiplication by a precomputed reciprocal, see
//! [`DigitBase`]) splits off the remainder
//! `r < g`, whose `k` digits, mirrored and permuted, are one table entry
//! `T[r] = Σ_{j<k} σ(d_j(r)) b^{k−1−j}`. Accumulating
//! `R ← R·g + T[r]` gives the integer of all mirrored digits, and
//! `Φ = R / g^s` after `s` steps. Both are exact integers below 2^53, so the
//! one floating-point division returns the correctly rounded `Φ`: the same
//! value as any other exact evaluation, whatever `k` is.
//!
//! `k` is the largest with `b^k ≤` [`GROUP_TABLE_LIMIT`]; a permutation `σ`
//! (which must fix 0, as Faure's do, so that the index's leading zero digits
//! contribute nothing) is folded into the table. Plain bases above the limit
//! (`k = 1`, `T[r] = r`) share one identity table, so that every base takes
//! the same branch-free path.
//!
//! Indices of 2^32 and more are split by the largest power `c = b^m ≤ 2^32`:
//! `Φ(i) = Φ(i mod c) + Φ(⌊i / c⌋) / c`, as in
//! [`radical_inverse_in`](crate::radical_inverse::radical_inverse_in).

use crate::radical_inverse::{DigitBase, DigitPermutations, ONE_MINUS_EPSILON_F64};
use std::sync::{Arc, OnceLock};

/// `(k, b^k)`: the digits per step and the group for `base`, the largest
/// `k ≥ 1` with `b^k ≤` [`GROUP_TABLE_LIMIT`] (or `k = 1`).
fn group_size(base: u32) -> (u32, u64) {
    let b = base as u64;
    let mut digits_per_group = 1;
    let mut group = b;
    while group * b <= GROUP_TABLE_LIMIT as u64 {
        group *= b;
        digits_per_group += 1;
    }
    (digits_per_group, group)
}

/// The largest table: `b^k ≤ 4096` entries of 2 bytes, 8 KiB at most per
/// base: seven digits per step in base 3, five in base 5, four in base 7,
/// three up to base 13 and two up to base 61, so that indices below 4096 take
/// at most two steps in the first 18 dimensions. (1024 entries cost 12 % more
/// instructions per sample in the benchmark's 16 dimensions; sequential
/// indices touch few cache lines of the larger tables.)
pub const GROUP_TABLE_LIMIT: u32 = 4096;

/// The constants and the table of one base for [`DigitGroups::radical_inverse`].
#[derive(Debug, Clone, PartialEq)]
pub struct DigitGroups {
    base: DigitBase,
    /// `k`: digits per step.
    digits_per_group: u32,
    /// `g = b^k`.
    group: u64,
    /// `⌈2^64 / g⌉`, which divides indices below 2^32 by `g`.
    group_reciprocal: u64,
    /// `g` as a float, to build the denominator `g^s` exactly.
    group_f64: f64,
    /// `T[r]` for `r < g` (possibly longer: the shared identity table).
    entries: Arc<[u16]>,
}

/// The length of the shared identity table: every base of the Halton
/// sequence (the largest is 8161) and more.
const SHARED_IDENTITY_LENGTH: usize = 8192;

/// `T[r] = r` for plain bases with one digit per step, built once.
fn shared_identity() -> &'static Arc<[u16]> {
    static IDENTITY: OnceLock<Arc<[u16]>> = OnceLock::new();
    IDENTITY.get_or_init(|| (0..SHARED_IDENTITY_LENGTH as u16).collect())
}

impl DigitGroups {
    /// The plain radical inverse in `base` (at least 3: base 2 is a bit
    /// reversal).
    pub fn plain(base: DigitBase) -> Self {
        Self::with_digit_map(base, None)
    }

    /// The radical inverse with every digit `d` replaced by
    /// `permutation[d]`; `permutation` is a permutation of `0..base` with
    /// `permutation[0] = 0` (such as Faure's).
    ///
    /// # Panics
    /// If `permutation` is not of length `base` or does not fix 0 (a
    /// programming error: the permutations come from this crate).
    pub fn permuted(base: DigitBase, permutation: &[u16]) -> Self {
        assert_eq!(permutation.len(), base.base as usize, "one digit per base");
        assert_eq!(permutation[0], 0, "the permutation must fix 0");
        Self::with_digit_map(base, Some(permutation))
    }

    fn with_digit_map(base: DigitBase, permutation: Option<&[u16]>) -> Self {
        assert!(base.base >= 3, "base 2 is a bit reversal, not a table");
        let b = base.base as u64;
        let (digits_per_group, group) = group_size(base.base);
        let entries: Arc<[u16]> = if permutation.is_none() && digits_per_group == 1 {
            if group as usize <= SHARED_IDENTITY_LENGTH {
                shared_identity().clone()
            } else {
                (0..base.base as u16).collect()
            }
        } else {
            let map = |digit: u64| permutation.map_or(digit, |p| p[digit as usize] as u64);
            (0..group)
                .map(|value| {
                    // Mirror the k digits of `value`, least significant first.
                    let (mut remaining, mut mirrored) = (value, 0u64);
                    for _ in 0..digits_per_group {
                        mirrored = mirrored * b + map(remaining % b);
                        remaining /= b;
                    }
                    mirrored as u16
                })
                .collect()
        };
        Self {
            base,
            digits_per_group,
            group,
            group_reciprocal: (u64::MAX / group).wrapping_add(1),
            group_f64: group as f64,
            entries,
        }
    }

    /// The base.
    pub fn base(&self) -> &DigitBase {
        &self.base
    }

    /// `σ(digit)`: the image of one digit under the folded permutation.
    pub fn permuted_digit(&self, digit: u32) -> u32 {
        // A one-digit value mirrors to σ(d)·b^{k−1}.
        self.entries[digit as usize] as u32 / self.base.base.pow(self.digits_per_group - 1)
    }

    /// The (permuted) radical inverse of `index`, below 1.
    #[inline]
    pub fn radical_inverse(&self, index: u64) -> f64 {
        if index <= u32::MAX as u64 {
            // Below 2^32 the value is at most 1 − b^{−n} with b^n < 2^45:
            // far from rounding up to 1.
            self.radical_inverse_32(index as u32)
        } else {
            self.radical_inverse_64(index).min(ONE_MINUS_EPSILON_F64)
        }
    }

    /// `Φ(i) = Φ(i mod c) + Φ(⌊i / c⌋) / c`, unclamped.
    #[inline(never)]
    fn radical_inverse_64(&self, index: u64) -> f64 {
        if index <= u32::MAX as u64 {
            return self.radical_inverse_32(index as u32);
        }
        let (chunk, inverse_chunk) = self.base.chunk();
        let (high, low) = (index / chunk, index % chunk);
        self.radical_inverse_32(low as u32) + self.radical_inverse_64(high) * inverse_chunk
    }

    /// The radical inverse of a 32-bit index, correctly rounded: `R / g^s`
    /// with the mirrored digits `R` accumulated group by group.
    #[inline(always)]
    fn radical_inverse_32(&self, index: u32) -> f64 {
        let entries = &*self.entries;
        let mut remaining = index as u64;
        let mut mirrored = 0u64;
        let mut denominator = 1.0f64;
        // At least one step (index 0 gives 0 / g = 0), so the loop needs one
        // test per step.
        loop {
            // ⌊n / g⌋ = ⌊⌈2^64 / g⌉ · n / 2^64⌋ for n < 2^32 (Lemire et al. 2019).
            let quotient = ((self.group_reciprocal as u128 * remaining as u128) >> 64) as u64;
            let remainder = remaining - quotient * self.group;
            mirrored = mirrored * self.group + entries[remainder as usize] as u64;
            denominator *= self.group_f64;
            remaining = quotient;
            if remaining == 0 {
                break;
            }
        }
        // Both are integers below 2^53 (g^s < 2^32·g): exact in f64, and the
        // signed conversion is one instruction.
        mirrored as i64 as f64 / denominator
    }
}

/// The radical inverse with a different digit permutation at every digit
/// position ([`DigitPermutations`], e.g. a random digital shift), several
/// digits per step as [`DigitGroups`] does: step `s` reads its own table
/// `T_s[r] = Σ_{j<k} σ_{sk+j}(d_j(r)) b^{k−1−j}`, so indices below 2^32 cost
/// the same few multiplications as the Faure tables, plus one table offset
/// per step and one addition at the end.
///
/// The permutations need not fix 0: the index's leading zero digits inside
/// the last group are mapped by the table, and those past it add
/// `Σ_{p ≥ sk} σ_p(0) b^{-(p+1)}`, kept per step count `s` in units of the
/// last digit (`tails[s]`), so the value is `(R + tails[s]) / g^s`. The tail
/// is not an integer, so unlike [`DigitGroups`] the result is within an ulp
/// of the digit-by-digit [`DigitPermutations::radical_inverse`], not
/// always equal to it. Indices of 2^32 and more are evaluated digit by digit.
#[derive(Debug, Clone, PartialEq)]
pub struct PositionalDigitGroups {
    permutations: DigitPermutations,
    /// `g = b^k`.
    group: u64,
    /// `⌈2^64 / g⌉`.
    group_reciprocal: u64,
    /// `g` as a float.
    group_f64: f64,
    /// `T_s` for every step a 32-bit index can take, concatenated.
    entries: Box<[u16]>,
    /// `tails[s] = g^s Σ_{p ≥ sk} σ_p(0) b^{-(p+1)}` for `s` steps.
    tails: Box<[f64]>,
}

impl PositionalDigitGroups {
    /// The tables of `permutations` (of a base of at least 3).
    pub fn new(permutations: DigitPermutations) -> Self {
        let base = *permutations.base();
        assert!(base.base >= 3, "base 2 is a bit reversal, not a table");
        let b = base.base as u64;
        let (digits_per_group, group) = group_size(base.base);
        // The steps of the largest 32-bit index: ⌈digits / k⌉.
        let mut digits = 0u32;
        let mut remaining = u32::MAX as u64;
        while remaining != 0 {
            remaining /= b;
            digits += 1;
        }
        let steps = digits.div_ceil(digits_per_group) as usize;
        assert!(
            steps * digits_per_group as usize <= permutations.position_count(),
            "a 64-bit index has more digits than a 32-bit one"
        );
        let mut entries = Vec::with_capacity(steps * group as usize);
        let k = digits_per_group as usize;
        // The digits of `value`, least significant first, counted up with
        // carries (no divisions: the tables of 256 bases are built per render).
        let mut digits = vec![0usize; k];
        for step in 0..steps {
            let maps: Vec<&[u16]> = (0..k)
                .map(|j| permutations.permutation(step * k + j))
                .collect();
            digits.fill(0);
            for _ in 0..group {
                // Mirror the k digits, each through its own position's
                // permutation.
                let mirrored = digits
                    .iter()
                    .zip(&maps)
                    .fold(0u64, |mirrored, (&digit, map)| {
                        mirrored * b + map[digit] as u64
                    });
                entries.push(mirrored as u16);
                for digit in digits.iter_mut() {
                    *digit += 1;
                    if *digit < b as usize {
                        break;
                    }
                    *digit = 0;
                }
            }
        }
        let tails = (0..=steps)
            .map(|step| {
                let position = step * digits_per_group as usize;
                permutations.zero_tail(position) * (group as f64).powi(step as i32)
            })
            .collect();
        Self {
            permutations,
            group,
            group_reciprocal: (u64::MAX / group).wrapping_add(1),
            group_f64: group as f64,
            entries: entries.into(),
            tails,
        }
    }

    /// The permutations of every digit position.
    pub fn permutations(&self) -> &DigitPermutations {
        &self.permutations
    }

    /// The permuted radical inverse of `index`, below 1.
    #[inline]
    pub fn radical_inverse(&self, index: u64) -> f64 {
        if index <= u32::MAX as u64 {
            self.radical_inverse_32(index as u32)
        } else {
            self.radical_inverse_64(index)
        }
    }

    /// Indices of 2^32 and more, digit by digit, out of line.
    #[inline(never)]
    fn radical_inverse_64(&self, index: u64) -> f64 {
        self.permutations.radical_inverse(index)
    }

    #[inline(always)]
    fn radical_inverse_32(&self, index: u32) -> f64 {
        let entries = &*self.entries;
        let group = self.group as usize;
        let mut remaining = index as u64;
        let mut mirrored = 0u64;
        let mut denominator = 1.0f64;
        let mut table = 0usize;
        let mut steps = 0usize;
        loop {
            // ⌊n / g⌋ = ⌊⌈2^64 / g⌉ · n / 2^64⌋ for n < 2^32 (Lemire et al. 2019).
            let quotient = ((self.group_reciprocal as u128 * remaining as u128) >> 64) as u64;
            let remainder = remaining - quotient * self.group;
            mirrored = mirrored * self.group + entries[table + remainder as usize] as u64;
            denominator *= self.group_f64;
            table += group;
            steps += 1;
            remaining = quotient;
            if remaining == 0 {
                break;
            }
        }
        let tail = self.tails[steps];
        ((mirrored as i64 as f64 + tail) / denominator).min(ONE_MINUS_EPSILON_F64)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::faure::faure_permutation;
    use crate::primes::PRIME_COUNT;
    use crate::radical_inverse::{
        DigitPermutations, permuted_radical_inverse_fixing_zero, prime_digit_bases,
        radical_inverse_in,
    };

    /// Indices that exercise every digit count: small ones, powers of the
    /// base and their neighbours, pseudo-random 32-bit and 64-bit ones.
    fn test_indices(base: u64) -> Vec<u64> {
        let mut indices: Vec<u64> = (0..300).collect();
        let mut power = base;
        while let Some(next) = power.checked_mul(base) {
            indices.extend([power - 1, power, power + 1]);
            power = next;
        }
        let mut state = 0x1234_5678_9ABC_DEF0u64;
        for _ in 0..300 {
            state = crate::hash::mix64(state);
            indices.extend([state >> 32, state, state >> 20]);
        }
        indices.extend([u32::MAX as u64, u32::MAX as u64 + 1, u64::MAX]);
        indices
    }

    /// Every base of the Halton sequence: the grouped evaluation gives the
    /// very same values as the digit-pair evaluation of `radical_inverse`.
    #[test]
    fn matches_plain_and_permuted_references_bit_for_bit() {
        for (base_index, base) in prime_digit_bases().iter().enumerate().skip(1) {
            if base_index > 40 && base_index % 37 != 0 && base_index != PRIME_COUNT - 1 {
                continue;
            }
            let plain = DigitGroups::plain(*base);
            let permutation = faure_permutation(base.base);
            let permuted = DigitGroups::permuted(*base, &permutation);
            for index in test_indices(base.base as u64) {
                assert_eq!(
                    plain.radical_inverse(index).to_bits(),
                    radical_inverse_in(base, index).to_bits(),
                    "plain base {} index {index}",
                    base.base
                );
                assert_eq!(
                    permuted.radical_inverse(index).to_bits(),
                    permuted_radical_inverse_fixing_zero(base, &permutation, index).to_bits(),
                    "Faure base {} index {index}",
                    base.base
                );
            }
        }
    }

    #[test]
    fn groups_fit_the_limit_and_keep_the_denominator_exact() {
        for base in prime_digit_bases().iter().skip(1) {
            let groups = DigitGroups::plain(*base);
            assert!(groups.group <= (GROUP_TABLE_LIMIT as u64).max(base.base as u64));
            // The largest denominator, for indices just below 2^32.
            let steps = (u32::MAX as f64).log(groups.group as f64).floor() as u32 + 1;
            assert!((groups.group as u128).pow(steps) < 1u128 << 53);
        }
    }

    #[test]
    fn permuted_digit_recovers_the_permutation() {
        for base_index in [1usize, 2, 3, 4, 10, 11, 100] {
            let base = prime_digit_bases()[base_index];
            let permutation = faure_permutation(base.base);
            let groups = DigitGroups::permuted(base, &permutation);
            for (digit, &image) in permutation.iter().enumerate() {
                assert_eq!(groups.permuted_digit(digit as u32), image as u32);
            }
            assert_eq!(DigitGroups::plain(base).permuted_digit(2), 2);
        }
    }

    /// Positional tables give the digit-by-digit value of the same
    /// permutations (within rounding: the tail is added in floating point).
    #[test]
    fn positional_groups_match_digit_by_digit_permutations() {
        for base_index in [1usize, 2, 3, 5, 17, 40, 100, 255] {
            let base = prime_digit_bases()[base_index];
            let permutation = faure_permutation(base.base);
            for seed in [1u64, 77] {
                let permutations = DigitPermutations::shifted(base, &permutation, seed);
                let groups = PositionalDigitGroups::new(permutations.clone());
                for index in test_indices(base.base as u64) {
                    let expected = permutations.radical_inverse(index);
                    let value = groups.radical_inverse(index);
                    assert!(
                        (value - expected).abs() <= 4.0 * f64::EPSILON && value < 1.0,
                        "base {} index {index}: {value} vs {expected}",
                        base.base
                    );
                }
            }
        }
    }
}
