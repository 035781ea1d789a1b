//! Integer hashing used to derive independent seeds and scrambles from a few
//! integers (a user seed, a replication number, a dimension, a pixel).
//!
//! Everything that needs "an independent random choice per X" hashes X with the
//! seed instead of keeping state, so that results depend only on the seed and
//! not on evaluation order or the number of threads.

/// The SplitMix64 finaliser (Steele, Lea, Flood 2014): a bijection on `u64`
/// with good avalanche, used as the basic mixing step.
#[inline]
pub fn mix64(mut value: u64) -> u64 {
    value = value.wrapping_add(0x9E37_79B9_7F4A_7C15);
    value = (value ^ (value >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    value = (value ^ (value >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    value ^ (value >> 31)
}

/// Hashes two integers into one; not symmetric, so `hash2(a, b) != hash2(b, a)`
/// in general.
#[inline]
pub fn hash2(a: u64, b: u64) -> u64 {
    mix64(mix64(a) ^ b.rotate_left(23) ^ 0x2545_F491_4F6C_DD1D)
}

/// Hashes three integers into one.
#[inline]
pub fn hash3(a: u64, b: u64, c: u64) -> u64 {
    hash2(hash2(a, b), c)
}

/// Maps a 64-bit hash to a uniform `f64` in `[0, 1)` using its top 53 bits.
#[inline]
pub fn to_unit_f64(hash: u64) -> f64 {
    (hash >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// Maps a 64-bit hash to an integer in `0..count`: the high word of their
/// product (uniform up to `count`·2⁻⁶⁴; for shuffles and choices keyed by a
/// hash, where a rejection loop would need a stream of hashes).
#[inline]
pub fn below(hash: u64, count: usize) -> usize {
    ((u128::from(hash) * count as u128) >> 64) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mix64_is_not_identity_and_spreads_bits() {
        assert_ne!(mix64(0), 0);
        let differing = (mix64(1) ^ mix64(2)).count_ones();
        assert!((16..=48).contains(&differing));
    }

    #[test]
    fn unit_values_are_below_one() {
        assert!(to_unit_f64(u64::MAX) < 1.0);
        assert_eq!(to_unit_f64(0), 0.0);
    }
}
