//! Base-2 digital sequences and their randomizations.
//!
//! A *digital sequence* in base 2 (Sobol, Niederreiter) produces each coordinate as
//! a 32-bit integer whose bits are the base-2 digits of the coordinate, most
//! significant digit first: the coordinate is `bits · 2^-32`. Working on the bits
//! makes the randomizations below cheap and exact.
//!
//! Randomizations ([`DigitalScramble`]) act on the 32 digits of a coordinate. Each
//! is built from a `seed: u64`; the randomness of every dimension is derived by
//! hashing `(seed, dimension)` with [`crate::hash`], so a randomized sequence depends
//! only on its seed. All of them keep the (t, m, s)-net and (t, s)-sequence
//! properties of the sequence they randomize, and all but [`DigitalScramble::None`]
//! make every single point uniformly distributed in `[0, 1)^s` (on the grid of
//! multiples of 2^-32), so estimators become unbiased.
//!
//! - random digital shift: XOR with a random 32-bit word per dimension;
//! - hash-based Owen scrambling (Laine & Karras 2011; Burley 2020, "Practical
//!   Hash-based Owen Scrambling", JCGT 9(4)): reverse the bits, apply a hash in
//!   which every bit depends only on lower bits, reverse back. Fast, a nested
//!   scramble whose flips are not fully independent;
//! - exact nested uniform scrambling (Owen 1995): digit `j` is flipped by a random
//!   bit drawn for the node of the binary tree given by the `j` preceding digits,
//!   from a strong hash (SplitMix64). Slow, reference quality;
//! - linear matrix scrambling (Matoušek 1998): a random nonsingular
//!   lower-triangular binary matrix times the digit vector, plus a digital shift.

use crate::hash::{hash2, hash3, mix64};
use crate::point_set::PointSet;

/// `2^-32`: the value of the least significant of the 32 digits.
pub const BITS_TO_UNIT: f64 = 1.0 / 4_294_967_296.0;

/// The coordinate `bits · 2^-32` in `[0, 1)` (exact in `f64`).
#[inline]
pub fn bits_to_unit(bits: u32) -> f64 {
    f64::from(bits) * BITS_TO_UNIT
}

/// `bits_to_unit(reversed_bits.reverse_bits())`, the coordinate of digits
/// given least significant first, without reversing them: byte `j` of
/// `reversed_bits` holds the digits `8j + 1 … 8j + 8` in reverse, worth
/// `rev8(byte) · 2^{−8(j+1)}`; the four table values have disjoint digits, so
/// their sum is exact. (A 32-bit reversal costs about 15 instructions on
/// x86-64; this costs four lookups.)
#[inline]
pub fn reversed_bits_to_unit(reversed_bits: u32) -> f64 {
    let tables = &REVERSED_BYTE_VALUES;
    (tables[0][(reversed_bits & 0xff) as usize] + tables[1][(reversed_bits >> 8 & 0xff) as usize])
        + (tables[2][(reversed_bits >> 16 & 0xff) as usize]
            + tables[3][(reversed_bits >> 24) as usize])
}

/// `REVERSED_BYTE_VALUES[j][v] = rev8(v) · 2^{−8(j+1)}` for [`reversed_bits_to_unit`]
/// (8 KiB, built at compile time).
static REVERSED_BYTE_VALUES: [[f64; 256]; 4] = reversed_byte_values();

const fn reversed_byte_values() -> [[f64; 256]; 4] {
    let mut tables = [[0.0; 256]; 4];
    let mut position = 0;
    while position < 4 {
        let scale = 1.0 / (1u64 << (8 * (position + 1))) as f64;
        let mut byte = 0;
        while byte < 256 {
            tables[position][byte] = (byte as u8).reverse_bits() as f64 * scale;
            byte += 1;
        }
        position += 1;
    }
    tables
}

/// The order in which the points of a digital sequence are enumerated.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DigitalOrder {
    /// Point `i` uses the binary digits of `i` itself.
    Natural,
    /// Point `i` uses the digits of the Gray code `i ^ (i >> 1)` (Antonov & Saleev
    /// 1979): consecutive points differ by one generator column. scipy's and GSL's
    /// order. The first `2^m` points are the same set in both orders.
    GrayCode,
}

impl DigitalOrder {
    /// The digit vector (as a word) that point `index` multiplies the generator
    /// matrices with: `index` or its Gray code.
    #[inline]
    pub fn selector(self, index: u64) -> u64 {
        match self {
            DigitalOrder::Natural => index,
            DigitalOrder::GrayCode => index ^ (index >> 1),
        }
    }
}

/// A generator matrix times a digit vector over GF(2): the XOR of the `columns`
/// selected by the set bits of `selector` (bit `k` selects `columns[k]`).
#[inline]
pub fn xor_columns(columns: &[u32; 32], selector: u32) -> u32 {
    // Branch-free (a mask per column) so that the loop neither mispredicts on the
    // number of set bits nor stops the compiler from vectorising it.
    let mut bits = 0;
    for (k, column) in columns.iter().enumerate() {
        bits ^= column & 0u32.wrapping_sub(selector >> k & 1);
    }
    bits
}

/// A base-2 digital sequence or net whose coordinates are 32-bit integers.
///
/// Coordinate `dimension` of point `index` is `sample_bits(index, dimension) · 2^-32`.
/// The same validity rules as [`PointSet::sample`] apply to the arguments.
pub trait DigitalSequence: Send + Sync {
    /// Number of dimensions; dimensions `0..dimensions()` are valid.
    fn dimensions(&self) -> usize;

    /// Number of points of a finite net, `None` for an extensible sequence.
    fn len(&self) -> Option<u64>;

    /// True for a net of no points (never the case for the sequences here).
    fn is_empty(&self) -> bool {
        self.len() == Some(0)
    }

    /// The 32 base-2 digits of coordinate `dimension` of point `index`, most
    /// significant digit in the most significant bit.
    fn sample_bits(&self, index: u64, dimension: usize) -> u32;

    /// `sample_bits(index, dimension).reverse_bits()`: the digits with the
    /// most significant one in the least significant bit, the order in which
    /// [`hash_owen_scramble`] works. Sequences that can produce it directly
    /// (Sobol, from reversed tables) override it to save a bit reversal.
    #[inline]
    fn sample_bits_reversed(&self, index: u64, dimension: usize) -> u32 {
        self.sample_bits(index, dimension).reverse_bits()
    }

    /// `Some(sample_bits(index, dimension))` when the sequence has the digits
    /// at hand in a few instructions (Sobol's tabled dimensions), `None`
    /// otherwise (the default). [`Scrambled`] takes its inlined fast paths
    /// only on `Some`; the slow case is one call that the fast case does not
    /// pay for (no registers saved around it).
    #[inline]
    fn cheap_bits(&self, _index: u64, _dimension: usize) -> Option<u32> {
        None
    }

    /// The same for `sample_bits_reversed(index, dimension)`.
    #[inline]
    fn cheap_bits_reversed(&self, _index: u64, _dimension: usize) -> Option<u32> {
        None
    }
}

impl<T: DigitalSequence + ?Sized> DigitalSequence for Box<T> {
    fn dimensions(&self) -> usize {
        (**self).dimensions()
    }
    fn len(&self) -> Option<u64> {
        (**self).len()
    }
    fn sample_bits(&self, index: u64, dimension: usize) -> u32 {
        (**self).sample_bits(index, dimension)
    }
    fn sample_bits_reversed(&self, index: u64, dimension: usize) -> u32 {
        (**self).sample_bits_reversed(index, dimension)
    }
    fn cheap_bits(&self, index: u64, dimension: usize) -> Option<u32> {
        (**self).cheap_bits(index, dimension)
    }
    fn cheap_bits_reversed(&self, index: u64, dimension: usize) -> Option<u32> {
        (**self).cheap_bits_reversed(index, dimension)
    }
}

/// Which randomization [`Scrambled`] applies to the digits of every coordinate.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum DigitalScramble {
    /// No randomization: the deterministic sequence (the seed is ignored).
    None,
    /// Random digital shift: XOR with a random 32-bit word per dimension.
    XorShift,
    /// Hash-based Owen scrambling after Burley (2020), see [`hash_owen_scramble`].
    HashOwen,
    /// Exact nested uniform (Owen 1995) scrambling, see [`nested_uniform_scramble`].
    NestedUniform,
    /// Matoušek's linear matrix scrambling plus a digital shift, see
    /// [`LinearMatrixScramble`].
    LinearMatrix,
}

impl DigitalScramble {
    /// Every variant, in declaration order (handy for tests and command lines).
    pub const ALL: [DigitalScramble; 5] = [
        DigitalScramble::None,
        DigitalScramble::XorShift,
        DigitalScramble::HashOwen,
        DigitalScramble::NestedUniform,
        DigitalScramble::LinearMatrix,
    ];
}

/// Tags that keep the random streams of the different randomizations apart, so
/// e.g. the XOR shift and the Owen scramble drawn from one seed are independent.
const XOR_SHIFT_TAG: u64 = 0x5853_4849_4654_0001;
const HASH_OWEN_TAG: u64 = 0x484F_5745_4E00_0002;
const NESTED_UNIFORM_TAG: u64 = 0x4E55_5343_5200_0003;
const LINEAR_MATRIX_TAG: u64 = 0x4C4D_5300_0000_0004;

/// The random 32-bit word of `dimension` for the randomization with `tag`.
#[inline]
fn dimension_word(seed: u64, dimension: usize, tag: u64) -> u32 {
    (hash3(seed, dimension as u64, tag) >> 32) as u32
}

/// Hash-based Owen scrambling of the 32 digits in `bits` with a 32-bit `seed`.
///
/// The formula is Burley (2020), "Practical Hash-based Owen Scrambling", JCGT 9(4),
/// listing 1/2 (an improved Laine–Karras permutation): reverse the bits so the
/// most significant digit becomes the least significant, then
/// `x += seed; x ^= x·0x6c50b47c; x ^= x·0xb82f1e52; x ^= x·0xc7afe638; x ^= x·0x8d22f6e6`
/// (wrapping), then reverse back. Addition and `x ^= x·even` only let a bit depend
/// on less significant bits, i.e. (after the reversal) each output digit is the
/// input digit flipped by a function of the *preceding* digits: a nested scramble,
/// so net properties are kept exactly. Because `seed` is uniform, a single
/// scrambled coordinate is exactly uniform on the 2^32 grid.
#[inline]
pub fn hash_owen_scramble(bits: u32, seed: u32) -> u32 {
    hash_owen_scramble_reversed(bits.reverse_bits(), seed)
}

/// [`hash_owen_scramble`] of the digits given already reversed
/// (`reversed_bits = bits.reverse_bits()`); returns the scrambled digits in
/// the normal order.
#[inline]
pub fn hash_owen_scramble_reversed(reversed_bits: u32, seed: u32) -> u32 {
    hash_owen_permutation(reversed_bits, seed).reverse_bits()
}

/// [`hash_owen_scramble_reversed`] without the final reversal: the scrambled
/// digits, least significant first (for [`reversed_bits_to_unit`]).
#[inline]
pub fn hash_owen_permutation(reversed_bits: u32, seed: u32) -> u32 {
    let mut x = reversed_bits;
    x = x.wrapping_add(seed);
    x ^= x.wrapping_mul(0x6c50_b47c);
    x ^= x.wrapping_mul(0xb82f_1e52);
    x ^= x.wrapping_mul(0xc7af_e638);
    x ^= x.wrapping_mul(0x8d22_f6e6);
    x
}

/// The SplitMix64 increment (golden-ratio gamma), which makes the node hashes of
/// [`nested_uniform_scramble`] consecutive outputs of a SplitMix64 stream.
const SPLITMIX_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// Exact nested uniform scrambling (Owen 1995) of the 32 digits in `bits`.
///
/// Digit `j` (0 = most significant) is flipped by one random bit attached to the
/// node of the binary tree reached by the `j` preceding input digits; the node is
/// numbered like a heap, `2^j + prefix`, and its bit is the top bit of
/// `mix64(key + node · γ)`, i.e. output `node` of a SplitMix64 generator seeded
/// with `key` (Steele, Lea, Flood 2014). Every node has its own independent bit up
/// to the quality of SplitMix64, which is what Owen's scrambling asks for. Costs 32
/// hashes per coordinate: use [`hash_owen_scramble`] when speed matters.
#[inline]
pub fn nested_uniform_scramble(bits: u32, key: u64) -> u32 {
    let mut flips = 0u32;
    for level in 0..32u32 {
        let prefix = if level == 0 {
            0
        } else {
            u64::from(bits >> (32 - level))
        };
        let node = (1u64 << level) | prefix;
        let flip = (mix64(key.wrapping_add(node.wrapping_mul(SPLITMIX_GAMMA))) >> 63) as u32;
        flips |= flip << (31 - level);
    }
    bits ^ flips
}

/// Matoušek's (1998) linear matrix scrambling of one dimension: a random
/// lower-triangular 32×32 binary matrix with ones on the diagonal (hence
/// nonsingular) applied to the digit vector, followed by a random digital shift.
///
/// Output digit `k` (1 = most significant) is `x_k + Σ_{j<k} L_kj x_j + e_k` mod 2,
/// so the first `k` output digits are a bijection of the first `k` input digits and
/// net properties are kept. The matrix is stored as four tables of 256 words (the
/// images of every value of each input byte, 4 KiB), so applying it costs four
/// lookups.
#[derive(Clone)]
pub struct LinearMatrixScramble {
    byte_tables: Box<[[u32; 256]; 4]>,
    shift: u32,
}

impl LinearMatrixScramble {
    /// Draws the matrix and shift of `dimension` from `seed`.
    pub fn new(seed: u64, dimension: usize) -> Self {
        let dimension_key = hash3(seed, dimension as u64, LINEAR_MATRIX_TAG);
        // columns[b]: image of the input digit at bit position b (0 = least
        // significant): the diagonal bit plus random bits at less significant
        // positions (the digits further down the lower-triangular column).
        let mut columns = [0u32; 32];
        for (bit, column) in columns.iter_mut().enumerate() {
            let random = (hash2(dimension_key, bit as u64) >> 32) as u32;
            let below_diagonal = if bit == 0 { 0 } else { (1u32 << bit) - 1 };
            *column = (1u32 << bit) | (random & below_diagonal);
        }
        let mut byte_tables = Box::new([[0u32; 256]; 4]);
        for (byte_position, table) in byte_tables.iter_mut().enumerate() {
            for (byte, entry) in table.iter_mut().enumerate() {
                *entry = (0..8)
                    .filter(|bit| byte >> bit & 1 == 1)
                    .fold(0, |image, bit| image ^ columns[8 * byte_position + bit]);
            }
        }
        let shift = (hash2(dimension_key, 32) >> 32) as u32;
        Self { byte_tables, shift }
    }

    /// Applies the matrix and the shift to the digits in `bits`.
    #[inline]
    pub fn apply(&self, bits: u32) -> u32 {
        let tables = &*self.byte_tables;
        tables[0][(bits & 0xff) as usize]
            ^ tables[1][(bits >> 8 & 0xff) as usize]
            ^ tables[2][(bits >> 16 & 0xff) as usize]
            ^ tables[3][(bits >> 24) as usize]
            ^ self.shift
    }
}

/// Per-dimension randomness, precomputed at construction so that sampling only
/// looks it up.
enum PreparedScramble {
    None,
    XorShift(Vec<u32>),
    HashOwen(Vec<u32>),
    NestedUniform(Vec<u64>),
    LinearMatrix(Vec<LinearMatrixScramble>),
}

/// A digital sequence with one of the [`DigitalScramble`] randomizations applied
/// to every coordinate; coordinates stay exact multiples of 2^-32 (no random fill
/// of lower bits).
///
/// The per-dimension shifts, seeds and matrices of all `sequence.dimensions()`
/// dimensions are computed in [`Scrambled::new`] (4 KiB per dimension for
/// [`DigitalScramble::LinearMatrix`], at most 8 bytes otherwise).
pub struct Scrambled<S: DigitalSequence> {
    sequence: S,
    scramble: DigitalScramble,
    seed: u64,
    prepared: PreparedScramble,
}

impl<S: DigitalSequence> Scrambled<S> {
    /// Randomizes `sequence` with `scramble`, all randomness derived from `seed`.
    pub fn new(sequence: S, scramble: DigitalScramble, seed: u64) -> Self {
        let dimensions = sequence.dimensions();
        let prepared = match scramble {
            DigitalScramble::None => PreparedScramble::None,
            DigitalScramble::XorShift => PreparedScramble::XorShift(
                (0..dimensions)
                    .map(|dimension| dimension_word(seed, dimension, XOR_SHIFT_TAG))
                    .collect(),
            ),
            DigitalScramble::HashOwen => PreparedScramble::HashOwen(
                (0..dimensions)
                    .map(|dimension| dimension_word(seed, dimension, HASH_OWEN_TAG))
                    .collect(),
            ),
            DigitalScramble::NestedUniform => PreparedScramble::NestedUniform(
                (0..dimensions)
                    .map(|dimension| hash3(seed, dimension as u64, NESTED_UNIFORM_TAG))
                    .collect(),
            ),
            DigitalScramble::LinearMatrix => PreparedScramble::LinearMatrix(
                (0..dimensions)
                    .map(|dimension| LinearMatrixScramble::new(seed, dimension))
                    .collect(),
            ),
        };
        Self {
            sequence,
            scramble,
            seed,
            prepared,
        }
    }

    /// The sequence being randomized.
    pub fn sequence(&self) -> &S {
        &self.sequence
    }

    /// The randomization applied.
    pub fn scramble(&self) -> DigitalScramble {
        self.scramble
    }

    /// The seed all randomness was derived from.
    pub fn seed(&self) -> u64 {
        self.seed
    }
}

impl<S: DigitalSequence> DigitalSequence for Scrambled<S> {
    fn dimensions(&self) -> usize {
        self.sequence.dimensions()
    }

    fn len(&self) -> Option<u64> {
        self.sequence.len()
    }

    #[inline]
    fn sample_bits(&self, index: u64, dimension: usize) -> u32 {
        if let PreparedScramble::HashOwen(seeds) = &self.prepared {
            return hash_owen_scramble_reversed(
                self.sequence.sample_bits_reversed(index, dimension),
                seeds[dimension],
            );
        }
        let bits = self.sequence.sample_bits(index, dimension);
        match &self.prepared {
            PreparedScramble::None | PreparedScramble::HashOwen(_) => bits,
            PreparedScramble::XorShift(shifts) => bits ^ shifts[dimension],
            PreparedScramble::NestedUniform(keys) => nested_uniform_scramble(bits, keys[dimension]),
            PreparedScramble::LinearMatrix(matrices) => matrices[dimension].apply(bits),
        }
    }
}

impl<S: DigitalSequence> PointSet for Scrambled<S> {
    fn dimensions(&self) -> usize {
        self.sequence.dimensions()
    }

    fn len(&self) -> Option<u64> {
        self.sequence.len()
    }

    #[inline]
    fn sample(&self, index: u64, dimension: usize) -> f64 {
        // The hash-based Owen scramble first: a compare, not a jump table,
        // and no registers saved.
        if let PreparedScramble::HashOwen(seeds) = &self.prepared
            && let Some(reversed_bits) = self.sequence.cheap_bits_reversed(index, dimension)
        {
            // No bit reversal on either side of the hash.
            return reversed_bits_to_unit(hash_owen_permutation(reversed_bits, seeds[dimension]));
        }
        self.sample_other_scrambles(index, dimension)
    }
}

impl<S: DigitalSequence> Scrambled<S> {
    /// [`PointSet::sample`] for the scrambles but the hash-based Owen one
    /// (and for it where the sequence has no cheap reversed digits).
    #[inline(never)]
    fn sample_other_scrambles(&self, index: u64, dimension: usize) -> f64 {
        match &self.prepared {
            PreparedScramble::None => {
                if let Some(bits) = self.sequence.cheap_bits(index, dimension) {
                    return bits_to_unit(bits);
                }
            }
            PreparedScramble::XorShift(shifts) => {
                if let Some(bits) = self.sequence.cheap_bits(index, dimension) {
                    return bits_to_unit(bits ^ shifts[dimension]);
                }
            }
            PreparedScramble::LinearMatrix(matrices) => {
                if let Some(bits) = self.sequence.cheap_bits(index, dimension) {
                    return bits_to_unit(matrices[dimension].apply(bits));
                }
            }
            PreparedScramble::HashOwen(_) | PreparedScramble::NestedUniform(_) => {}
        }
        self.sample_by_digits(index, dimension)
    }

    /// [`PointSet::sample`] through [`DigitalSequence::sample_bits`]: every
    /// case but the fast one. Called rather than inlined, so that the fast
    /// path saves no registers.
    #[inline(never)]
    fn sample_by_digits(&self, index: u64, dimension: usize) -> f64 {
        bits_to_unit(self.sample_bits(index, dimension))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The van der Corput sequence in base 2 (bit reversal), enough to test the
    /// randomizations without depending on another module.
    struct VanDerCorput;

    impl DigitalSequence for VanDerCorput {
        fn dimensions(&self) -> usize {
            3
        }
        fn len(&self) -> Option<u64> {
            None
        }
        fn sample_bits(&self, index: u64, _dimension: usize) -> u32 {
            (index as u32).reverse_bits()
        }
    }

    /// True iff the values' top `m` digits are all different (one point in each
    /// interval of length 2^-m).
    fn one_per_interval(values: &[u32], m: u32) -> bool {
        let mut seen = vec![false; 1 << m];
        values.iter().all(|&value| {
            let cell = if m == 0 {
                0
            } else {
                (value >> (32 - m)) as usize
            };
            !std::mem::replace(&mut seen[cell], true)
        })
    }

    #[test]
    fn every_scramble_keeps_one_dimensional_stratification() {
        for scramble in DigitalScramble::ALL {
            let scrambled = Scrambled::new(VanDerCorput, scramble, 7);
            for m in 0..=10 {
                let values: Vec<u32> = (0..1u64 << m)
                    .map(|index| scrambled.sample_bits(index, 1))
                    .collect();
                assert!(one_per_interval(&values, m), "{scramble:?} m = {m}");
            }
        }
    }

    #[test]
    fn scrambles_are_bijections_of_the_digits() {
        let matrix = LinearMatrixScramble::new(3, 1);
        let inputs: Vec<u32> = (0..4096u32).map(|i| i.wrapping_mul(0x9E37_79B9)).collect();
        for transform in [
            &(|x| hash_owen_scramble(x, 0x1234_5678)) as &dyn Fn(u32) -> u32,
            &|x| nested_uniform_scramble(x, 99),
            &|x| matrix.apply(x),
        ] {
            let mut outputs: Vec<u32> = inputs.iter().map(|&x| transform(x)).collect();
            outputs.sort_unstable();
            outputs.dedup();
            assert_eq!(outputs.len(), inputs.len());
        }
    }

    #[test]
    fn reversed_bits_to_unit_is_the_reversal_exactly() {
        let mut state = 3u64;
        for bits in [0u32, 1, 0x8000_0000, u32::MAX, 0x1234_5678] {
            assert_eq!(
                reversed_bits_to_unit(bits),
                bits_to_unit(bits.reverse_bits())
            );
        }
        for _ in 0..10_000 {
            state = mix64(state);
            let bits = state as u32;
            assert_eq!(
                reversed_bits_to_unit(bits).to_bits(),
                bits_to_unit(bits.reverse_bits()).to_bits()
            );
        }
    }

    #[test]
    fn hash_owen_sample_matches_its_digits() {
        let scrambled = Scrambled::new(VanDerCorput, DigitalScramble::HashOwen, 5);
        for index in 0..5000 {
            for dimension in 0..3 {
                assert_eq!(
                    scrambled.sample(index, dimension),
                    bits_to_unit(scrambled.sample_bits(index, dimension))
                );
            }
        }
    }

    #[test]
    fn linear_matrix_tables_match_the_bitwise_product() {
        let matrix = LinearMatrixScramble::new(11, 2);
        let shift = matrix.apply(0);
        let columns: Vec<u32> = (0..32).map(|bit| matrix.apply(1 << bit) ^ shift).collect();
        for (bit, column) in columns.iter().enumerate() {
            assert_eq!(column >> bit, 1, "diagonal one, nothing above it");
        }
        let x = 0xDEAD_BEEFu32;
        let expected = (0..32)
            .filter(|bit| x >> bit & 1 == 1)
            .fold(shift, |acc, bit| acc ^ columns[bit]);
        assert_eq!(matrix.apply(x), expected);
    }

    #[test]
    fn none_is_the_identity_and_scrambles_differ_between_dimensions() {
        let plain = Scrambled::new(VanDerCorput, DigitalScramble::None, 1);
        assert_eq!(plain.sample_bits(3, 0), VanDerCorput.sample_bits(3, 0));
        for scramble in &DigitalScramble::ALL[1..] {
            let scrambled = Scrambled::new(VanDerCorput, *scramble, 1);
            assert_ne!(
                scrambled.sample_bits(5, 0),
                scrambled.sample_bits(5, 1),
                "{scramble:?}"
            );
        }
    }
}
