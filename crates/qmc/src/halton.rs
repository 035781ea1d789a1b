//! The Halton sequence, plain and scrambled, with per-pixel enumeration.
//!
//! Dimension `j` is the radical inverse in the `j`-th prime base (2, 3, 5, …),
//! for up to [`PRIME_COUNT`] dimensions. Scrambles ([`HaltonScramble`]):
//! - `None`: the plain sequence;
//! - `Faure`: Faure's (1992) digit permutations, the "scrambled Halton" of
//!   Kollig & Keller (2002) and of Grünschloß, Raab & Keller (2012); bases 2
//!   and 3 are left unpermuted (σ₂ and σ₃ are the identity);
//! - `RandomPermutation`: an independent random permutation per dimension and
//!   digit position (drawn from the seed);
//! - `Owen`: nested uniform (Owen) scrambling in each base, from the seed;
//! - `FaureShifted`: Faure's permutations followed by a random digital shift
//!   in base b per digit position (from the seed): every point uniform, the
//!   Faure sequence's stratification kept, and as fast as `Faure` (base 2 is
//!   an XOR with a random word, bases from 3 on read one table per step,
//!   [`crate::digit_groups::PositionalDigitGroups`]). The renderer's
//!   randomized Halton sampler.
//!
//! Plain and Faure coordinates, the renderer's, are the fast ones: base 2 is a
//! bit reversal read through byte tables, and bases from 3 on take several
//! digits per step from a table with the permutation folded in
//! ([`crate::digit_groups`]); both give bit for bit the values of the
//! digit-by-digit functions of [`crate::radical_inverse`].
//!
//! [`PixelEnumeration`] finds the global indices of the samples whose first
//! two coordinates, scaled to raster units, fall in a given pixel
//! (Grünschloß, Raab & Keller 2012, "Enumerating quasi-Monte Carlo point
//! sequences in elementary intervals").

use crate::digit_groups::{DigitGroups, PositionalDigitGroups};
use crate::digital_scramble::reversed_bits_to_unit;
use crate::faure::faure_permutation;
use crate::hash::hash2;
use crate::point_set::{PointSet, PointSetError};
use crate::primes::PRIME_COUNT;
use crate::radical_inverse::{
    DigitBase, DigitPermutations, ONE_MINUS_EPSILON_F64, owen_scrambled_leading_digits_preimage,
    owen_scrambled_radical_inverse, prime_digit_bases, radical_inverse_in,
};

/// How the digits of each Halton dimension are scrambled.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum HaltonScramble {
    /// The plain radical inverses.
    None,
    /// Faure's deterministic permutations (the seed is ignored).
    Faure,
    /// Independent random digit permutations per dimension and digit position.
    RandomPermutation,
    /// Owen's nested uniform scrambling.
    Owen,
    /// Faure's permutations, then a random digital shift in base b per
    /// dimension and digit position ([`DigitPermutations::shifted`]).
    FaureShifted,
}

/// How one dimension's coordinates are computed.
#[derive(Debug, Clone)]
enum Coordinate {
    /// Base 2, plain or Faure (σ₂ is the identity): a bit reversal.
    BitReversal,
    /// Plain or Faure-permuted (a permutation fixing 0) in a base of at
    /// least 3, several digits per step from a table.
    Grouped(DigitGroups),
    /// One permutation per digit position.
    PerPosition(DigitPermutations),
    /// Owen scrambling with this dimension's seed.
    Owen(DigitBase, u64),
    /// Base 2 with a random digital shift (σ₂ is the identity): the index's
    /// bits XOR `mask` (the shifts of digits 1 to 32), plus `tail` (the
    /// shifted leading zeros past digit 32) for indices below 2^32.
    ShiftedBitReversal {
        mask: u32,
        tail: f64,
        permutations: DigitPermutations,
    },
    /// A permutation per digit position in a base of at least 3, several
    /// digits per step from one table per step.
    PositionalGrouped(PositionalDigitGroups),
}

/// The Halton sequence in `dimensions` dimensions with a scramble.
#[derive(Debug, Clone)]
pub struct Halton {
    scramble: HaltonScramble,
    coordinates: Vec<Coordinate>,
}

impl Halton {
    /// The sequence in `dimensions ≤ PRIME_COUNT` dimensions. `seed` chooses
    /// the random permutations of `RandomPermutation` and `Owen`; each
    /// dimension's randomness is `hash(seed, dimension)`.
    pub fn new(
        dimensions: usize,
        scramble: HaltonScramble,
        seed: u64,
    ) -> Result<Self, PointSetError> {
        if dimensions > PRIME_COUNT {
            return Err(PointSetError::TooManyDimensions {
                requested: dimensions,
                supported: PRIME_COUNT,
            });
        }
        let coordinates = prime_digit_bases()[..dimensions]
            .iter()
            .enumerate()
            .map(|(dimension, &base)| {
                let dimension_seed = hash2(seed, dimension as u64);
                match scramble {
                    HaltonScramble::None | HaltonScramble::Faure if base.base == 2 => {
                        Coordinate::BitReversal
                    }
                    HaltonScramble::None => Coordinate::Grouped(DigitGroups::plain(base)),
                    HaltonScramble::Faure if base.base == 3 => {
                        Coordinate::Grouped(DigitGroups::plain(base))
                    }
                    HaltonScramble::Faure => Coordinate::Grouped(DigitGroups::permuted(
                        base,
                        &faure_permutation(base.base),
                    )),
                    HaltonScramble::RandomPermutation => {
                        Coordinate::PerPosition(DigitPermutations::random(base, dimension_seed))
                    }
                    HaltonScramble::Owen => Coordinate::Owen(base, dimension_seed),
                    HaltonScramble::FaureShifted => {
                        // σ₂ and σ₃ are the identity.
                        let permutations = DigitPermutations::shifted(
                            base,
                            &faure_permutation(base.base),
                            dimension_seed,
                        );
                        if base.base == 2 {
                            // Digit k of the index is bit k; its shift is σ_k(0).
                            let mask = (0..32).fold(0u32, |mask, position| {
                                mask | (permutations.permutation(position)[0] as u32) << position
                            });
                            Coordinate::ShiftedBitReversal {
                                mask,
                                tail: permutations.zero_tail(32),
                                permutations,
                            }
                        } else {
                            Coordinate::PositionalGrouped(PositionalDigitGroups::new(permutations))
                        }
                    }
                }
            })
            .collect();
        Ok(Self {
            scramble,
            coordinates,
        })
    }

    /// The scramble this sequence was built with.
    pub fn scramble(&self) -> HaltonScramble {
        self.scramble
    }

    /// The base of `dimension`.
    pub fn base(&self, dimension: usize) -> u32 {
        match &self.coordinates[dimension] {
            Coordinate::BitReversal => 2,
            Coordinate::Grouped(groups) => groups.base().base,
            Coordinate::PerPosition(permutations) => permutations.base().base,
            Coordinate::Owen(base, _) => base.base,
            Coordinate::ShiftedBitReversal { .. } => 2,
            Coordinate::PositionalGrouped(groups) => groups.permutations().base().base,
        }
    }

    /// The residue modulo `base^digits.len()` of the indices whose coordinate
    /// in `dimension` has the leading base-`b` digits `digits`
    /// (most significant first): the inverse of the scramble on the
    /// index's lowest digits.
    fn leading_digits_preimage(&self, dimension: usize, digits: &[u32]) -> u64 {
        let b = self.base(dimension) as u64;
        let inverse = |wanted: u32, permuted: &dyn Fn(u32) -> u32| -> u64 {
            (0..b as u32)
                .position(|digit| permuted(digit) == wanted)
                .expect("digit permutations are bijections") as u64
        };
        let mut residue = 0;
        let mut power = 1;
        for (position, &wanted) in digits.iter().enumerate() {
            let digit = match &self.coordinates[dimension] {
                Coordinate::Owen(base, seed) => {
                    return owen_scrambled_leading_digits_preimage(base, *seed, digits);
                }
                Coordinate::BitReversal => wanted as u64,
                Coordinate::Grouped(groups) => {
                    inverse(wanted, &|digit| groups.permuted_digit(digit))
                }
                Coordinate::PerPosition(permutations)
                | Coordinate::ShiftedBitReversal { permutations, .. } => {
                    inverse(wanted, &|digit| {
                        permutations.permutation(position)[digit as usize] as u32
                    })
                }
                Coordinate::PositionalGrouped(groups) => inverse(wanted, &|digit| {
                    groups.permutations().permutation(position)[digit as usize] as u32
                }),
            };
            residue += digit * power;
            power *= b;
        }
        residue
    }
}

impl PointSet for Halton {
    fn dimensions(&self) -> usize {
        self.coordinates.len()
    }

    fn len(&self) -> Option<u64> {
        None
    }

    #[inline]
    fn sample(&self, index: u64, dimension: usize) -> f64 {
        match &self.coordinates[dimension] {
            Coordinate::Grouped(groups) => groups.radical_inverse(index),
            Coordinate::BitReversal => bit_reversal_radical_inverse(index),
            Coordinate::PositionalGrouped(groups) => groups.radical_inverse(index),
            Coordinate::ShiftedBitReversal { mask, tail, .. } if index <= u32::MAX as u64 => {
                (reversed_bits_to_unit(index as u32 ^ mask) + tail).min(ONE_MINUS_EPSILON_F64)
            }
            scrambled => scrambled_radical_inverse(scrambled, index),
        }
    }
}

/// The randomly permuted and Owen-scrambled coordinates, called rather than
/// inlined so that the fast paths of [`Halton::sample`] need no saved
/// registers.
#[inline(never)]
fn scrambled_radical_inverse(coordinate: &Coordinate, index: u64) -> f64 {
    match coordinate {
        Coordinate::PerPosition(permutations) => permutations.radical_inverse(index),
        Coordinate::Owen(base, seed) => owen_scrambled_radical_inverse(base, *seed, index),
        Coordinate::ShiftedBitReversal { permutations, .. } => permutations.radical_inverse(index),
        Coordinate::PositionalGrouped(groups) => groups.radical_inverse(index),
        Coordinate::Grouped(groups) => groups.radical_inverse(index),
        Coordinate::BitReversal => bit_reversal_radical_inverse(index),
    }
}

/// The base-2 radical inverse: the index's bits mirrored about the radix
/// point. Below 2^32 the exact value is the index's bits read as digits
/// least significant first (byte tables, no bit reversal); above, the same
/// value as [`radical_inverse_in`].
#[inline(always)]
fn bit_reversal_radical_inverse(index: u64) -> f64 {
    if index <= u32::MAX as u64 {
        reversed_bits_to_unit(index as u32)
    } else {
        large_index_bit_reversal(index)
    }
}

/// [`bit_reversal_radical_inverse`] of indices from 2^32 on, out of line.
#[inline(never)]
fn large_index_bit_reversal(index: u64) -> f64 {
    radical_inverse_in(&prime_digit_bases()[0], index)
}

/// Enumerates the Halton samples that fall in each pixel of an image.
///
/// With `2^a ≥ width` and `3^b ≥ height`, the first two Halton coordinates
/// scaled by `(2^a, 3^b)` are raster coordinates; sample `i` lies in pixel
/// `(x, y)` iff its first `a` base-2 digits give `x` and its first `b` base-3
/// digits give `y`. Those depend only on `i mod 2^a` and `i mod 3^b`, so the
/// pixel's samples are `offset(x, y) + j · 2^a 3^b` with the offset from the
/// Chinese remainder theorem. Works for every scramble of [`Halton`]: the
/// scramble's digit permutations are inverted to find the residues.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelEnumeration {
    /// Image width and height in pixels.
    pub resolution: (u32, u32),
    /// `a` and `b`: digits of base 2 and of base 3 per pixel coordinate.
    pub digits: (u32, u32),
    /// `(2^a, 3^b)`: the factors from the unit square to raster units.
    pub scale: (u64, u64),
    /// `2^a · 3^b`: the distance between consecutive samples of one pixel.
    pub increment: u64,
}

impl PixelEnumeration {
    /// The enumeration for a `width × height` image (both at least 1).
    pub fn new(width: u32, height: u32) -> Result<Self, PointSetError> {
        if width == 0 || height == 0 {
            return Err(PointSetError::InvalidParameter(format!(
                "the resolution {width}x{height} has no pixels"
            )));
        }
        let (mut digits_x, mut scale_x) = (0u32, 1u64);
        while scale_x < width as u64 {
            scale_x *= 2;
            digits_x += 1;
        }
        let (mut digits_y, mut scale_y) = (0u32, 1u64);
        while scale_y < height as u64 {
            scale_y *= 3;
            digits_y += 1;
        }
        Ok(Self {
            resolution: (width, height),
            digits: (digits_x, digits_y),
            scale: (scale_x, scale_y),
            increment: scale_x * scale_y,
        })
    }

    /// The global index of the `sample`-th sample of pixel `(x, y)` in `halton`.
    ///
    /// Returns an error for pixels outside the image, for a sequence with
    /// fewer than two dimensions, or if the index would exceed 64 bits.
    pub fn sample_index(
        &self,
        halton: &Halton,
        pixel: (u32, u32),
        sample: u64,
    ) -> Result<u64, PointSetError> {
        if pixel.0 >= self.resolution.0 || pixel.1 >= self.resolution.1 {
            return Err(PointSetError::InvalidParameter(format!(
                "pixel ({}, {}) is outside the {}x{} image",
                pixel.0, pixel.1, self.resolution.0, self.resolution.1
            )));
        }
        if halton.dimensions() < 2 {
            return Err(PointSetError::InvalidParameter(
                "per-pixel enumeration needs at least two dimensions".into(),
            ));
        }
        let offset = self.pixel_offset(halton, pixel);
        sample
            .checked_mul(self.increment)
            .and_then(|step| step.checked_add(offset))
            .ok_or(PointSetError::TooManyPoints {
                requested: sample,
                supported: (u64::MAX - offset) / self.increment,
            })
    }

    /// The index of the first sample of `pixel` (below `increment`).
    pub fn pixel_offset(&self, halton: &Halton, pixel: (u32, u32)) -> u64 {
        let digits_of = |value: u32, base: u32, count: u32| -> Vec<u32> {
            // Most significant first: the digits of the raster coordinate.
            let mut digits = vec![0u32; count as usize];
            let mut remaining = value;
            for slot in digits.iter_mut().rev() {
                *slot = remaining % base;
                remaining /= base;
            }
            digits
        };
        let residue_x = halton.leading_digits_preimage(0, &digits_of(pixel.0, 2, self.digits.0));
        let residue_y = halton.leading_digits_preimage(1, &digits_of(pixel.1, 3, self.digits.1));
        chinese_remainder(residue_x, self.scale.0, residue_y, self.scale.1)
    }

    /// The first-sample offsets of every pixel of the image for `halton`,
    /// tabulated per column and per row (see [`PixelOffsetTable`]).
    pub fn offset_table(&self, halton: &Halton) -> PixelOffsetTable {
        let (m, n) = self.scale;
        let product = m as u128 * n as u128;
        let m_inverse = modular_inverse_general(m % n, n) as u128;
        let n_inverse = modular_inverse_general(n % m, m) as u128;
        let digits_of = |value: u32, base: u32, count: u32| -> Vec<u32> {
            let mut digits = vec![0u32; count as usize];
            let mut remaining = value;
            for slot in digits.iter_mut().rev() {
                *slot = remaining % base;
                remaining /= base;
            }
            digits
        };
        // The two terms of `chinese_remainder`, each reduced mod m·n.
        let columns = (0..self.resolution.0)
            .map(|x| {
                let a = halton.leading_digits_preimage(0, &digits_of(x, 2, self.digits.0));
                (a as u128 * n as u128 % product * n_inverse % product) as u64
            })
            .collect();
        let rows = (0..self.resolution.1)
            .map(|y| {
                let b = halton.leading_digits_preimage(1, &digits_of(y, 3, self.digits.1));
                (b as u128 * m as u128 % product * m_inverse % product) as u64
            })
            .collect();
        PixelOffsetTable {
            columns,
            rows,
            increment: self.increment,
        }
    }

    /// The first two coordinates of sample `index` in raster units.
    pub fn raster_position(&self, halton: &Halton, index: u64) -> (f64, f64) {
        (
            halton.sample(index, 0) * self.scale.0 as f64,
            halton.sample(index, 1) * self.scale.1 as f64,
        )
    }
}

/// [`PixelEnumeration::pixel_offset`] of every pixel for one sequence: the
/// offset is the Chinese remainder of a residue that depends on the column
/// alone and one that depends on the row alone, so each of its two terms
/// is tabulated once per column and once per row, and a pixel's offset is
/// one addition modulo `2^a 3^b` (the inversion of the leading digits and
/// the modular inverses cost about 1,800 instructions per pixel sample
/// otherwise).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct PixelOffsetTable {
    columns: Vec<u64>,
    rows: Vec<u64>,
    increment: u64,
}

impl PixelOffsetTable {
    /// The offset of `pixel`, equal to [`PixelEnumeration::pixel_offset`];
    /// `None` outside the image.
    #[inline]
    pub fn offset(&self, pixel: (u32, u32)) -> Option<u64> {
        let column = *self.columns.get(pixel.0 as usize)?;
        let row = *self.rows.get(pixel.1 as usize)?;
        // Both terms are below the increment, so their sum is below twice it.
        let sum = column as u128 + row as u128;
        let increment = self.increment as u128;
        Some(if sum >= increment {
            sum - increment
        } else {
            sum
        } as u64)
    }
}

/// The `x` in `0..m·n` with `x ≡ a (mod m)` and `x ≡ b (mod n)`, for coprime
/// `m` and `n`.
fn chinese_remainder(a: u64, m: u64, b: u64, n: u64) -> u64 {
    let product = m as u128 * n as u128;
    let m_inverse = modular_inverse_general(m % n, n) as u128;
    let n_inverse = modular_inverse_general(n % m, m) as u128;
    // x = a·n·(n⁻¹ mod m) + b·m·(m⁻¹ mod n)  (mod m·n)
    let x = (a as u128 * n as u128 % product * n_inverse
        + b as u128 * m as u128 % product * m_inverse)
        % product;
    x as u64
}

/// The inverse of `value` modulo `modulus` by the extended Euclidean
/// algorithm (1 for modulus 1); `value` and `modulus` must be coprime.
fn modular_inverse_general(value: u64, modulus: u64) -> u64 {
    if modulus == 1 {
        return 0;
    }
    let (mut old_r, mut r) = (value as i128, modulus as i128);
    let (mut old_s, mut s) = (1i128, 0i128);
    while r != 0 {
        let quotient = old_r / r;
        (old_r, r) = (r, old_r - quotient * r);
        (old_s, s) = (s, old_s - quotient * s);
    }
    old_s.rem_euclid(modulus as i128) as u64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn plain_halton_first_points() {
        let halton = Halton::new(3, HaltonScramble::None, 0).unwrap();
        let expected = [
            [0.0, 0.0, 0.0],
            [0.5, 1.0 / 3.0, 0.2],
            [0.25, 2.0 / 3.0, 0.4],
            [0.75, 1.0 / 9.0, 0.6],
        ];
        for (index, point) in expected.iter().enumerate() {
            for (dimension, &value) in point.iter().enumerate() {
                assert!((halton.sample(index as u64, dimension) - value).abs() < 1e-15);
            }
        }
    }

    /// The table-driven evaluation against the simple digit-by-digit
    /// references of `radical_inverse`, bit for bit, in every dimension.
    #[test]
    fn plain_and_faure_match_the_reference_radical_inverses() {
        use crate::radical_inverse::permuted_radical_inverse_fixing_zero;
        let plain = Halton::new(PRIME_COUNT, HaltonScramble::None, 0).unwrap();
        let faure = Halton::new(PRIME_COUNT, HaltonScramble::Faure, 0).unwrap();
        let mut indices: Vec<u64> = (0..64).collect();
        let mut state = 11u64;
        for shift in [0, 8, 20, 32, 40] {
            for _ in 0..8 {
                state = crate::hash::mix64(state);
                indices.push(state >> shift);
            }
        }
        indices.extend([u32::MAX as u64, u32::MAX as u64 + 1, u64::MAX]);
        for (dimension, base) in prime_digit_bases().iter().enumerate() {
            let permutation = if base.base <= 3 {
                (0..base.base as u16).collect()
            } else {
                faure_permutation(base.base)
            };
            for &index in &indices {
                assert_eq!(
                    plain.sample(index, dimension).to_bits(),
                    radical_inverse_in(base, index).to_bits(),
                    "plain, dimension {dimension}, index {index}"
                );
                assert_eq!(
                    faure.sample(index, dimension).to_bits(),
                    permuted_radical_inverse_fixing_zero(base, &permutation, index).to_bits(),
                    "Faure, dimension {dimension}, index {index}"
                );
            }
        }
    }

    #[test]
    fn too_many_dimensions_is_an_error() {
        assert!(Halton::new(PRIME_COUNT + 1, HaltonScramble::None, 0).is_err());
        assert!(Halton::new(PRIME_COUNT, HaltonScramble::Faure, 0).is_ok());
    }

    #[test]
    fn faure_keeps_bases_two_and_three_and_permutes_five() {
        let plain = Halton::new(3, HaltonScramble::None, 0).unwrap();
        let faure = Halton::new(3, HaltonScramble::Faure, 0).unwrap();
        for index in 0..100 {
            assert_eq!(plain.sample(index, 0), faure.sample(index, 0));
            assert_eq!(plain.sample(index, 1), faure.sample(index, 1));
        }
        // σ₅ = (0, 3, 2, 1, 4): index 1 has digit 1 → 3/5.
        assert!((faure.sample(1, 2) - 0.6).abs() < 1e-15);
        assert!((faure.sample(3, 2) - 0.2).abs() < 1e-15);
    }

    #[test]
    fn chinese_remainder_solves_both_congruences() {
        for (m, n) in [(8u64, 27u64), (1, 9), (16, 1), (1024, 729)] {
            for a in [0, 1, m / 2, m - 1].into_iter().filter(|&a| a < m) {
                for b in [0, 1, n / 2, n - 1].into_iter().filter(|&b| b < n) {
                    let x = chinese_remainder(a, m, b, n);
                    assert!(x < m * n);
                    assert_eq!(x % m, a);
                    assert_eq!(x % n, b);
                }
            }
        }
    }

    #[test]
    fn every_pixel_sample_lands_in_its_pixel_for_every_scramble() {
        for scramble in [
            HaltonScramble::None,
            HaltonScramble::Faure,
            HaltonScramble::RandomPermutation,
            HaltonScramble::Owen,
            HaltonScramble::FaureShifted,
        ] {
            let halton = Halton::new(4, scramble, 1234).unwrap();
            for (width, height) in [(1u32, 1u32), (7, 5), (16, 9), (33, 28)] {
                let enumeration = PixelEnumeration::new(width, height).unwrap();
                for y in 0..height {
                    for x in 0..width {
                        for sample in 0..3 {
                            let index = enumeration.sample_index(&halton, (x, y), sample).unwrap();
                            let (rx, ry) = enumeration.raster_position(&halton, index);
                            assert_eq!(
                                (rx.floor() as u32, ry.floor() as u32),
                                (x, y),
                                "{scramble:?} {width}x{height} sample {sample}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn pixel_offsets_partition_the_first_increment() {
        // Each index below 2^a 3^b belongs to exactly one pixel of the
        // 2^a × 3^b raster.
        let halton = Halton::new(2, HaltonScramble::None, 0).unwrap();
        let enumeration = PixelEnumeration::new(8, 9).unwrap();
        let mut seen = vec![false; enumeration.increment as usize];
        for y in 0..9 {
            for x in 0..8 {
                let offset = enumeration.pixel_offset(&halton, (x, y));
                assert!(!seen[offset as usize]);
                seen[offset as usize] = true;
            }
        }
        assert!(seen.iter().all(|&s| s));
    }

    #[test]
    fn the_offset_table_equals_the_pixel_offsets() {
        for scramble in [
            HaltonScramble::None,
            HaltonScramble::Faure,
            HaltonScramble::RandomPermutation,
            HaltonScramble::Owen,
            HaltonScramble::FaureShifted,
        ] {
            let halton = Halton::new(4, scramble, 17).unwrap();
            for (width, height) in [(1, 1), (5, 7), (37, 29)] {
                let enumeration = PixelEnumeration::new(width, height).unwrap();
                let table = enumeration.offset_table(&halton);
                for y in 0..height {
                    for x in 0..width {
                        assert_eq!(
                            table.offset((x, y)),
                            Some(enumeration.pixel_offset(&halton, (x, y))),
                            "{scramble:?} {width}x{height} ({x}, {y})"
                        );
                    }
                }
                assert_eq!(table.offset((width, 0)), None);
                assert_eq!(table.offset((0, height)), None);
            }
        }
    }

    #[test]
    fn pixel_outside_image_is_an_error() {
        let halton = Halton::new(2, HaltonScramble::None, 0).unwrap();
        let enumeration = PixelEnumeration::new(4, 4).unwrap();
        assert!(enumeration.sample_index(&halton, (4, 0), 0).is_err());
        assert!(PixelEnumeration::new(0, 3).is_err());
    }

    /// The shifted coordinates are those of the digit-by-digit evaluation of
    /// the same per-position permutations, in bases 2, 3 and larger.
    #[test]
    fn faure_shifted_matches_its_digit_permutations() {
        let halton = Halton::new(40, HaltonScramble::FaureShifted, 5).unwrap();
        for dimension in [0usize, 1, 2, 7, 39] {
            let base = prime_digit_bases()[dimension];
            let permutations = DigitPermutations::shifted(
                base,
                &faure_permutation(base.base),
                hash2(5, dimension as u64),
            );
            for index in (0..500u64).chain([u32::MAX as u64, u32::MAX as u64 + 3, u64::MAX]) {
                let expected = permutations.radical_inverse(index);
                let value = halton.sample(index, dimension);
                assert!(
                    (value - expected).abs() <= 4.0 * f64::EPSILON,
                    "dimension {dimension} index {index}: {value} vs {expected}"
                );
            }
        }
    }

    /// Over seeds, a fixed point of the shifted sequence is uniform: the
    /// mean of `n` seeds' values has standard error `√(1/(12 n))`, and the
    /// first `b²` points still fall one in each interval of length `b^-2`.
    #[test]
    fn faure_shifted_points_are_uniform_over_seeds_and_stratified() {
        let n = 4000u64;
        let dimensions = [0usize, 1, 4, 12];
        let indices = [0u64, 1, 12345];
        let mut sums = [[0.0f64; 3]; 4];
        for seed in 0..n {
            let halton = Halton::new(13, HaltonScramble::FaureShifted, seed).unwrap();
            for (sum, &dimension) in sums.iter_mut().zip(&dimensions) {
                for (value, &index) in sum.iter_mut().zip(&indices) {
                    *value += halton.sample(index, dimension);
                }
            }
        }
        let standard_error = (1.0 / (12.0 * n as f64)).sqrt();
        for (sum, dimension) in sums.iter().zip(dimensions) {
            for (value, index) in sum.iter().zip(indices) {
                let mean = value / n as f64;
                assert!(
                    (mean - 0.5).abs() < 5.0 * standard_error,
                    "dimension {dimension} index {index}: mean {mean}"
                );
            }
        }
        let halton = Halton::new(13, HaltonScramble::FaureShifted, 9).unwrap();
        for dimension in dimensions {
            let count = (halton.base(dimension) as u64).pow(2);
            let mut cells = vec![0u32; count as usize];
            for index in 0..count {
                cells[(halton.sample(index, dimension) * count as f64) as usize] += 1;
            }
            assert!(cells.iter().all(|&c| c == 1), "dimension {dimension}");
        }
    }

    #[test]
    fn faure_shifted_seeds_differ() {
        let a = Halton::new(8, HaltonScramble::FaureShifted, 1).unwrap();
        let b = Halton::new(8, HaltonScramble::FaureShifted, 2).unwrap();
        let c = Halton::new(8, HaltonScramble::FaureShifted, 1).unwrap();
        for dimension in 0..8 {
            assert_ne!(a.sample(3, dimension), b.sample(3, dimension));
            assert_eq!(a.sample(3, dimension), c.sample(3, dimension));
        }
    }
}
