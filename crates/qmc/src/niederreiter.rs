//! The Niederreiter sequence in base 2 (Bratley, Fox & Niederreiter 1992).
//!
//! Dimension `j` uses the `j`-th irreducible polynomial `p` over GF(2), the
//! polynomials ordered by degree and, within a degree, by their coefficient bits
//! read as an integer: x, x+1, x²+x+1, x³+x+1, x³+x²+1, …. With `e = deg p`, row
//! `r` of the generator matrix (output digit `r`, 0 = most significant) is built
//! from `Q = r div e`, `u = r mod e` and the power `b = p^{Q+1}` of degree
//! `m = e(Q+1)`: let `v_0, v_1, …` be the sequence with `v_t = 0` for `t < eQ`,
//! `v_t = 1` for `eQ ≤ t < m`, and the linear recurrence of characteristic
//! polynomial `b` afterwards, `v_k = Σ_{t<m} b_t v_{k−m+t}` (mod 2). Then the
//! matrix entry in row `r`, column `c` (input digit `c`, 0 = least significant bit
//! of the index) is `v_{c+u}`. These are the coefficients of the Laurent
//! expansion of `y(x)/p(x)^{Q+1}` for the polynomial `y` fixed by the initial
//! values (Niederreiter 1988, §3; BFN 1992, §2.3 and §3.3, which leaves the values
//! `v_{eQ+1} … v_{m−1}` free; they are set to 1 here, the choice that reproduces
//! the published reference output).
//!
//! The t-value of the first `s` dimensions is `Σ_j (deg p_j − 1)`: dimensions 0 and 1
//! form a (0, 2)-sequence, while the t-value grows quickly with `s`.
//!
//! Checked against the output of GSL's `gsl_qrng_niederreiter_2` (only its output
//! is used, as test data); GSL stops at 12 dimensions, this module supports
//! [`MAX_DIMENSIONS`] = 226, all irreducible polynomials of degree ≤ 10 (beyond
//! that a single coordinate is only a (9, 1)-sequence or worse; use Sobol for
//! high dimensions).

use crate::digital_scramble::{DigitalOrder, DigitalSequence, bits_to_unit, xor_columns};
use crate::point_set::{PointSet, PointSetError};

/// Largest polynomial degree used; see [`MAX_DIMENSIONS`].
pub const MAX_POLYNOMIAL_DEGREE: u32 = 10;

/// Number of dimensions: the number of irreducible polynomials over GF(2) of
/// degree 1 … [`MAX_POLYNOMIAL_DEGREE`] (2 + 1 + 2 + 3 + 6 + 9 + 18 + 30 + 56 + 99).
pub const MAX_DIMENSIONS: usize = 226;

/// Number of points (indices `0 .. 2^32`): the matrices have 32 columns.
pub const MAX_POINTS: u64 = 1 << 32;

/// The base-2 Niederreiter sequence in `dimensions` dimensions.
///
/// `len()` is `None`, but indices must stay below [`MAX_POINTS`] (a debug
/// assertion checks; release builds use the low 32 bits of the index).
#[derive(Debug, Clone)]
pub struct Niederreiter {
    /// Per dimension, the 32 generator-matrix columns as words (output digit `r`
    /// in bit `31 − r`).
    columns: Vec<[u32; 32]>,
    polynomials: Vec<u64>,
    order: DigitalOrder,
}

impl Niederreiter {
    /// The first `dimensions` dimensions (1 ≤ `dimensions` ≤ [`MAX_DIMENSIONS`]),
    /// enumerated in `order` ([`DigitalOrder::GrayCode`] reproduces GSL).
    pub fn new(dimensions: usize, order: DigitalOrder) -> Result<Self, PointSetError> {
        if dimensions == 0 {
            return Err(PointSetError::InvalidParameter(
                "a Niederreiter sequence needs at least one dimension".into(),
            ));
        }
        if dimensions > MAX_DIMENSIONS {
            return Err(PointSetError::TooManyDimensions {
                requested: dimensions,
                supported: MAX_DIMENSIONS,
            });
        }
        let polynomials = irreducible_polynomials(dimensions);
        let columns = polynomials.iter().map(|&p| generator_columns(p)).collect();
        Ok(Self {
            columns,
            polynomials,
            order,
        })
    }

    /// The enumeration order.
    pub fn order(&self) -> DigitalOrder {
        self.order
    }

    /// The irreducible polynomial of `dimension`, coefficient of `x^k` in bit `k`.
    pub fn polynomial(&self, dimension: usize) -> u64 {
        self.polynomials[dimension]
    }

    /// The 32 generator-matrix columns of `dimension` (column `c` multiplies index
    /// digit `c`; output digit `r` is bit `31 − r`).
    pub fn generator_columns(&self, dimension: usize) -> &[u32; 32] {
        &self.columns[dimension]
    }
}

/// Degree of a nonzero polynomial over GF(2) stored as bits.
fn degree(polynomial: u64) -> u32 {
    63 - polynomial.leading_zeros()
}

/// Product of two polynomials over GF(2) (carry-less multiplication); the caller
/// keeps the degree of the product below 64.
fn multiply(a: u64, b: u64) -> u64 {
    (0..64)
        .filter(|bit| b >> bit & 1 == 1)
        .fold(0, |product, bit| product ^ (a << bit))
}

/// Remainder of `a` divided by `b` over GF(2).
fn remainder(mut a: u64, b: u64) -> u64 {
    let divisor_degree = degree(b);
    while a != 0 && degree(a) >= divisor_degree {
        a ^= b << (degree(a) - divisor_degree);
    }
    a
}

/// The first `count` irreducible polynomials over GF(2) in order of degree, then
/// of value; `count` ≤ [`MAX_DIMENSIONS`].
fn irreducible_polynomials(count: usize) -> Vec<u64> {
    let mut found = Vec::with_capacity(count);
    let mut candidate = 2u64;
    while found.len() < count {
        let half_degree = degree(candidate) / 2;
        // A reducible polynomial has an irreducible factor of degree ≤ half its own.
        let reducible = found
            .iter()
            .take_while(|&&factor| degree(factor) <= half_degree)
            .any(|&factor| remainder(candidate, factor) == 0);
        if !reducible {
            found.push(candidate);
        }
        candidate += 1;
    }
    found
}

/// The 32 generator-matrix columns for the irreducible `polynomial` (see the
/// module documentation for the construction).
fn generator_columns(polynomial: u64) -> [u32; 32] {
    let e = degree(polynomial) as usize;
    let mut columns = [0u32; 32];
    let mut power = 1u64; // p^Q, then p^{Q+1}
    // v_{c+u} is needed for c < 32, u < e.
    let mut sequence = [0u8; 32 + MAX_POLYNOMIAL_DEGREE as usize];
    let needed = 32 + e - 1;
    for row in 0..32 {
        let u = row % e;
        if u == 0 {
            let lower_degree = degree(power) as usize; // e·Q
            power = multiply(power, polynomial);
            let m = degree(power) as usize; // e·(Q+1)
            for (t, value) in sequence.iter_mut().enumerate().take(needed) {
                *value = if t < lower_degree {
                    0
                } else if t < m {
                    1
                } else {
                    0 // filled in below
                };
            }
            for k in m..needed {
                let mut value = 0;
                for t in 0..m {
                    if power >> t & 1 == 1 {
                        value ^= sequence[k - m + t];
                    }
                }
                sequence[k] = value;
            }
        }
        for (column, word) in columns.iter_mut().enumerate() {
            *word |= u32::from(sequence[column + u]) << (31 - row);
        }
    }
    columns
}

impl DigitalSequence for Niederreiter {
    fn dimensions(&self) -> usize {
        self.columns.len()
    }

    fn len(&self) -> Option<u64> {
        None
    }

    #[inline]
    fn sample_bits(&self, index: u64, dimension: usize) -> u32 {
        debug_assert!(index < MAX_POINTS, "Niederreiter index {index} ≥ 2^32");
        xor_columns(&self.columns[dimension], self.order.selector(index) as u32)
    }
}

impl PointSet for Niederreiter {
    fn dimensions(&self) -> usize {
        self.columns.len()
    }

    fn len(&self) -> Option<u64> {
        None
    }

    #[inline]
    fn sample(&self, index: u64, dimension: usize) -> f64 {
        bits_to_unit(self.sample_bits(index, dimension))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn polynomials_are_ordered_by_degree_then_value() {
        let sequence = Niederreiter::new(MAX_DIMENSIONS, DigitalOrder::GrayCode).unwrap();
        let first: Vec<u64> = (0..8).map(|d| sequence.polynomial(d)).collect();
        assert_eq!(
            first,
            [0b10, 0b11, 0b111, 0b1011, 0b1101, 0b10011, 0b11001, 0b11111]
        );
        let last = sequence.polynomial(MAX_DIMENSIONS - 1);
        assert_eq!(degree(last), MAX_POLYNOMIAL_DEGREE);
        // The next one would be x^11 + x^2 + 1, of degree 11.
        assert_eq!(
            irreducible_polynomials(MAX_DIMENSIONS + 1)[MAX_DIMENSIONS],
            0b1000_0000_0101
        );
    }

    #[test]
    fn first_dimension_is_van_der_corput() {
        let sequence = Niederreiter::new(1, DigitalOrder::Natural).unwrap();
        for index in 0..64u64 {
            assert_eq!(
                sequence.sample_bits(index, 0),
                (index as u32).reverse_bits()
            );
        }
    }

    #[test]
    fn rejects_bad_dimension_counts() {
        assert!(Niederreiter::new(0, DigitalOrder::GrayCode).is_err());
        assert!(Niederreiter::new(MAX_DIMENSIONS + 1, DigitalOrder::GrayCode).is_err());
    }
}
