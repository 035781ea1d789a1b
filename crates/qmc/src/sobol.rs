//! The Sobol sequence in base 2 with the Joe–Kuo direction numbers.
//!
//! Dimension `j` has 32 direction numbers `v_1 … v_32` (32-bit words, `v_k = m_k / 2^k`
//! with odd `m_k < 2^k`, its last nonzero digit is digit `k`); coordinate `j` of point `i` is the XOR of the `v_k`
//! for the set bits `k − 1` of `i` (natural order) or of the Gray code
//! `i ^ (i >> 1)` (Gray-code order, as in scipy and most libraries). The first
//! `2^m` points are the same set in both orders, for every `m`.
//!
//! Direction numbers: S. Joe and F. Y. Kuo, "Constructing Sobol sequences with
//! better two-dimensional projections", SIAM J. Sci. Comput. 30 (2008), file
//! `new-joe-kuo-6.21201` (vendored in `crates/qmc/data/sobol/` with its licence
//! notice). Dimension 0 is the van der Corput sequence (all `m_k = 1`), dimension
//! `j ≥ 1` is line `j` of the file. From the primitive polynomial
//! `x^s + a_1 x^{s−1} + … + a_{s−1} x + 1` and initial `m_1 … m_s`,
//! `v_k = m_k · 2^{32−k}` for `k ≤ s` and, for `k > s`,
//! `v_k = v_{k−s} ⊕ (v_{k−s} >> s) ⊕ ⊕_{i=1}^{s−1} a_i v_{k−i}` (Bratley & Fox 1988,
//! as described by Joe & Kuo).
//!
//! Only the lines of the requested dimensions are parsed, at construction: a
//! `Sobol::new(2, …)` does not pay for the 21201 dimensions of the file.

pub use crate::digital_scramble::DigitalOrder;
use crate::digital_scramble::{DigitalSequence, bits_to_unit, xor_columns};
use crate::point_set::{PointSet, PointSetError};

/// The Joe–Kuo file, one line per dimension 2 … 21201 after a header line.
const JOE_KUO_DIRECTION_NUMBERS: &str = include_str!("../data/sobol/new-joe-kuo-6.21201");

/// Number of dimensions available: the implicit first one plus 21200 file lines.
pub const MAX_DIMENSIONS: usize = 21201;

/// Number of points (indices `0 .. 2^32`): the direction numbers have 32 digits.
pub const MAX_POINTS: u64 = 1 << 32;

/// The Sobol sequence in `dimensions` dimensions, points `0 .. 2^32`.
///
/// `len()` is `None` (an extensible sequence), but indices must stay below
/// [`MAX_POINTS`] = 2^32: larger indices are a caller error (checked by a debug
/// assertion; in release builds only the low 32 bits of the index are used).
#[derive(Debug, Clone)]
pub struct Sobol {
    direction_numbers: Vec<[u32; 32]>,
    /// For the first [`TABLED_DIMENSIONS`] dimensions: the XOR of the columns
    /// selected by every value of each byte of the *index*, so a sample costs
    /// four lookups instead of up to 32 XORs (4 KiB per dimension). The order
    /// is folded into the columns (see [`index_columns`]), so no Gray code is
    /// computed per sample.
    byte_tables: Vec<ByteTables>,
    /// The same tables for the bit-reversed direction numbers, which give the
    /// reversed digits that hash-based Owen scrambling starts from.
    reversed_byte_tables: Vec<ByteTables>,
    order: DigitalOrder,
}

/// Number of leading dimensions evaluated with byte tables (see [`Sobol`]); the
/// others XOR direction numbers bit by bit. Chosen so that tables stay small
/// (at most 256 KiB) while covering the dimensions a renderer uses most.
pub const TABLED_DIMENSIONS: usize = 64;

impl Sobol {
    /// The first `dimensions` dimensions (1 ≤ `dimensions` ≤ [`MAX_DIMENSIONS`]) of
    /// the Sobol sequence, enumerated in `order`.
    pub fn new(dimensions: usize, order: DigitalOrder) -> Result<Self, PointSetError> {
        if dimensions == 0 {
            return Err(PointSetError::InvalidParameter(
                "a Sobol sequence needs at least one dimension".into(),
            ));
        }
        if dimensions > MAX_DIMENSIONS {
            return Err(PointSetError::TooManyDimensions {
                requested: dimensions,
                supported: MAX_DIMENSIONS,
            });
        }
        let mut direction_numbers = Vec::with_capacity(dimensions);
        direction_numbers.push(std::array::from_fn(|k| 1u32 << (31 - k)));
        for line in JOE_KUO_DIRECTION_NUMBERS
            .lines()
            .skip(1)
            .take(dimensions - 1)
        {
            direction_numbers.push(parse_line(line)?);
        }
        if direction_numbers.len() != dimensions {
            return Err(PointSetError::InvalidParameter(
                "the vendored Joe–Kuo file has fewer lines than expected".into(),
            ));
        }
        let byte_tables = direction_numbers
            .iter()
            .take(TABLED_DIMENSIONS)
            .map(|numbers| byte_tables_of(&index_columns(numbers, order)))
            .collect();
        let reversed_byte_tables = direction_numbers
            .iter()
            .take(TABLED_DIMENSIONS)
            .map(|numbers| byte_tables_of(&index_columns(numbers, order).map(u32::reverse_bits)))
            .collect();
        Ok(Self {
            direction_numbers,
            byte_tables,
            reversed_byte_tables,
            order,
        })
    }

    /// The enumeration order.
    pub fn order(&self) -> DigitalOrder {
        self.order
    }

    /// The 32 direction numbers `v_1 … v_32` of `dimension`.
    pub fn direction_numbers(&self, dimension: usize) -> &[u32; 32] {
        &self.direction_numbers[dimension]
    }

    /// The digits of a dimension without byte tables, one column at a time;
    /// called rather than inlined, which keeps the tabled path free of saved
    /// registers.
    #[inline(never)]
    fn untabled_bits(&self, index: u64, dimension: usize) -> u32 {
        xor_columns(
            &self.direction_numbers[dimension],
            self.order.selector(index) as u32,
        )
    }

    /// A cursor over consecutive points in Gray-code order starting at `start`
    /// (whatever [`Sobol::order`] is): each step costs one XOR per dimension.
    pub fn gray_code_walker(&self, start: u64) -> GrayCodeWalker<'_> {
        let gray_code = start ^ (start >> 1);
        let current = self
            .direction_numbers
            .iter()
            .map(|numbers| xor_columns(numbers, gray_code as u32))
            .collect();
        GrayCodeWalker {
            sobol: self,
            index: start,
            current,
        }
    }
}

/// The generator columns that the bits of the index itself select in `order`.
///
/// In Gray-code order, bit `j` of the selector `g = i ⊕ (i >> 1)` is
/// `i_j ⊕ i_{j+1}`, so `Σ_j g_j v_j = Σ_k i_k (v_k ⊕ v_{k−1})` (with
/// `v_{−1} = 0`): the Gray code is a change of columns, made once here.
fn index_columns(direction_numbers: &[u32; 32], order: DigitalOrder) -> [u32; 32] {
    match order {
        DigitalOrder::Natural => *direction_numbers,
        DigitalOrder::GrayCode => std::array::from_fn(|k| {
            direction_numbers[k] ^ if k == 0 { 0 } else { direction_numbers[k - 1] }
        }),
    }
}

/// Four lookups in byte tables: the XOR of the columns selected by `selector`.
#[inline(always)]
fn look_up_bytes(tables: &ByteTables, selector: u32) -> u32 {
    let tables = &tables.tables;
    tables[0][(selector & 0xff) as usize]
        ^ tables[1][(selector >> 8 & 0xff) as usize]
        ^ tables[2][(selector >> 16 & 0xff) as usize]
        ^ tables[3][(selector >> 24) as usize]
}

/// The four tables of XORs of direction numbers selected by each byte value
/// (of the selector word, byte 0 least significant).
/// The four byte tables of one dimension, followed by padding.
///
/// Without padding the tables of consecutive dimensions would lie exactly
/// 4 KiB apart: the same entry of every dimension's table would map to the
/// same set of a 4 KiB-way first-level cache (48 KiB, 12 ways on this
/// project's machine), and 16 dimensions evaluated in turn would evict one
/// another (4 misses per sample in `cachegrind`, about twice the time). 320
/// bytes (5 cache lines, coprime to the 64 sets) shift each dimension to
/// other sets.
#[derive(Debug, Clone)]
#[repr(C)]
struct ByteTables {
    tables: [[u32; 256]; 4],
    _padding: [u32; BYTE_TABLE_PADDING],
}

/// The padding after each [`ByteTables`], in words (5 cache lines).
const BYTE_TABLE_PADDING: usize = 80;

fn byte_tables_of(direction_numbers: &[u32; 32]) -> ByteTables {
    let mut tables = [[0u32; 256]; 4];
    for (byte_position, table) in tables.iter_mut().enumerate() {
        for (byte, entry) in table.iter_mut().enumerate() {
            *entry = xor_columns(direction_numbers, (byte as u32) << (8 * byte_position));
        }
    }
    ByteTables {
        tables,
        _padding: [0; BYTE_TABLE_PADDING],
    }
}

/// Parses one line `d s a m_1 … m_s` of the Joe–Kuo file.
fn parse_line(line: &str) -> Result<[u32; 32], PointSetError> {
    let malformed = || PointSetError::InvalidParameter(format!("malformed Joe–Kuo line {line:?}"));
    let mut fields = line
        .split_whitespace()
        .map(|field| field.parse::<u32>().map_err(|_| malformed()));
    let _dimension = fields.next().ok_or_else(malformed)??;
    let degree = fields.next().ok_or_else(malformed)??;
    let inner_coefficients = fields.next().ok_or_else(malformed)??;
    let initial: Vec<u32> = fields.collect::<Result<_, _>>()?;
    if degree == 0 || degree > 31 || initial.len() != degree as usize {
        return Err(malformed());
    }
    Ok(direction_numbers_from(degree, inner_coefficients, &initial))
}

/// The 32 direction numbers from the polynomial degree `degree`, its inner
/// coefficients `a_1 … a_{s−1}` packed most significant first, and `m_1 … m_s`.
fn direction_numbers_from(degree: u32, inner_coefficients: u32, initial: &[u32]) -> [u32; 32] {
    let s = degree as usize;
    let mut numbers = [0u32; 32];
    for (k, &m) in initial.iter().enumerate().take(32) {
        numbers[k] = m << (31 - k);
    }
    for k in s..32 {
        let mut value = numbers[k - s] ^ (numbers[k - s] >> s);
        for i in 1..s {
            if inner_coefficients >> (s - 1 - i) & 1 == 1 {
                value ^= numbers[k - i];
            }
        }
        numbers[k] = value;
    }
    numbers
}

impl DigitalSequence for Sobol {
    fn dimensions(&self) -> usize {
        self.direction_numbers.len()
    }

    fn len(&self) -> Option<u64> {
        None
    }

    #[inline]
    fn sample_bits(&self, index: u64, dimension: usize) -> u32 {
        debug_assert!(index < MAX_POINTS, "Sobol index {index} ≥ 2^32");
        match self.byte_tables.get(dimension) {
            Some(tables) => look_up_bytes(tables, index as u32),
            None => self.untabled_bits(index, dimension),
        }
    }

    #[inline]
    fn sample_bits_reversed(&self, index: u64, dimension: usize) -> u32 {
        debug_assert!(index < MAX_POINTS, "Sobol index {index} ≥ 2^32");
        match self.reversed_byte_tables.get(dimension) {
            Some(tables) => look_up_bytes(tables, index as u32),
            None => self.untabled_bits(index, dimension).reverse_bits(),
        }
    }

    #[inline]
    fn cheap_bits(&self, index: u64, dimension: usize) -> Option<u32> {
        debug_assert!(index < MAX_POINTS, "Sobol index {index} ≥ 2^32");
        self.byte_tables
            .get(dimension)
            .map(|tables| look_up_bytes(tables, index as u32))
    }

    #[inline]
    fn cheap_bits_reversed(&self, index: u64, dimension: usize) -> Option<u32> {
        debug_assert!(index < MAX_POINTS, "Sobol index {index} ≥ 2^32");
        self.reversed_byte_tables
            .get(dimension)
            .map(|tables| look_up_bytes(tables, index as u32))
    }
}

impl PointSet for Sobol {
    fn dimensions(&self) -> usize {
        self.direction_numbers.len()
    }

    fn len(&self) -> Option<u64> {
        None
    }

    #[inline]
    fn sample(&self, index: u64, dimension: usize) -> f64 {
        bits_to_unit(self.sample_bits(index, dimension))
    }
}

/// Consecutive Sobol points in Gray-code order, made by [`Sobol::gray_code_walker`].
pub struct GrayCodeWalker<'a> {
    sobol: &'a Sobol,
    index: u64,
    current: Vec<u32>,
}

impl GrayCodeWalker<'_> {
    /// Index of the current point.
    pub fn index(&self) -> u64 {
        self.index
    }

    /// Digits of every coordinate of the current point.
    pub fn current(&self) -> &[u32] {
        &self.current
    }

    /// Moves to the next point: the Gray codes of `i` and `i + 1` differ in bit
    /// `trailing_zeros(i + 1)`, so one direction number is XORed per dimension.
    #[inline]
    pub fn advance(&mut self) {
        self.index += 1;
        debug_assert!(self.index < MAX_POINTS, "Sobol index ≥ 2^32");
        let changed = (self.index.trailing_zeros() as usize).min(31);
        for (bits, numbers) in self.current.iter_mut().zip(&self.sobol.direction_numbers) {
            *bits ^= numbers[changed];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_dimension_is_van_der_corput() {
        let sobol = Sobol::new(1, DigitalOrder::Natural).unwrap();
        let expected = [0.0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875];
        for (index, value) in expected.iter().enumerate() {
            assert_eq!(sobol.sample(index as u64, 0), *value);
        }
    }

    #[test]
    fn rejects_bad_dimension_counts() {
        assert!(matches!(
            Sobol::new(0, DigitalOrder::GrayCode),
            Err(PointSetError::InvalidParameter(_))
        ));
        assert_eq!(
            Sobol::new(MAX_DIMENSIONS + 1, DigitalOrder::GrayCode).unwrap_err(),
            PointSetError::TooManyDimensions {
                requested: MAX_DIMENSIONS + 1,
                supported: MAX_DIMENSIONS
            }
        );
    }

    #[test]
    fn direction_numbers_have_their_last_one_at_digit_k() {
        let sobol = Sobol::new(50, DigitalOrder::GrayCode).unwrap();
        for dimension in 0..50 {
            for (k, number) in sobol.direction_numbers(dimension).iter().enumerate() {
                // m_k is odd and below 2^k: digit k is the last nonzero digit.
                assert_eq!(
                    number.trailing_zeros() as usize,
                    31 - k,
                    "dimension {dimension}"
                );
            }
        }
    }

    #[test]
    fn reversed_digits_are_the_reversed_samples() {
        let sobol = Sobol::new(TABLED_DIMENSIONS + 3, DigitalOrder::Natural).unwrap();
        for index in [0u64, 1, 2, 77, 1 << 20, (1 << 32) - 1] {
            for dimension in [0, 1, 5, TABLED_DIMENSIONS - 1, TABLED_DIMENSIONS + 2] {
                assert_eq!(
                    sobol.sample_bits_reversed(index, dimension),
                    sobol.sample_bits(index, dimension).reverse_bits()
                );
            }
        }
    }

    #[test]
    fn tables_match_the_matrix_product_in_both_orders() {
        for order in [DigitalOrder::Natural, DigitalOrder::GrayCode] {
            let sobol = Sobol::new(TABLED_DIMENSIONS, order).unwrap();
            let mut state = 7u64;
            for _ in 0..2000 {
                state = crate::hash::mix64(state);
                let index = state >> 32;
                for dimension in [0, 1, 2, 17, TABLED_DIMENSIONS - 1] {
                    let expected = xor_columns(
                        sobol.direction_numbers(dimension),
                        order.selector(index) as u32,
                    );
                    assert_eq!(sobol.sample_bits(index, dimension), expected, "{order:?}");
                    assert_eq!(
                        sobol.sample_bits_reversed(index, dimension),
                        expected.reverse_bits()
                    );
                }
            }
        }
    }

    #[test]
    fn walker_matches_indexed_gray_code_points() {
        let sobol = Sobol::new(5, DigitalOrder::GrayCode).unwrap();
        let mut walker = sobol.gray_code_walker(1000);
        for _ in 0..300 {
            for dimension in 0..5 {
                assert_eq!(
                    walker.current()[dimension],
                    sobol.sample_bits(walker.index(), dimension)
                );
            }
            walker.advance();
        }
    }
}
