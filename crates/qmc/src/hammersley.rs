//! The Hammersley point set: `N` points whose first coordinate is `i / N` and
//! whose other coordinates are the Halton sequence's (bases 2, 3, 5, …),
//! plain or scrambled as in [`HaltonScramble`].
//!
//! Kollig & Keller's "scrambled Hammersley" is the Faure-scrambled variant;
//! Heinrich & Keller compare the plain one with Halton and random points.

use crate::halton::{Halton, HaltonScramble};
use crate::point_set::{PointSet, PointSetError};
use crate::primes::PRIME_COUNT;

/// The Hammersley point set of `point_count` points in `dimensions` dimensions.
#[derive(Debug, Clone)]
pub struct Hammersley {
    point_count: u64,
    inverse_point_count: f64,
    /// Dimensions 1.. of the set are dimensions 0.. of this sequence.
    halton: Halton,
}

impl Hammersley {
    /// The set of `point_count ≥ 1` points in `1 ≤ dimensions ≤ PRIME_COUNT + 1`
    /// dimensions; `scramble` and `seed` apply to the Halton coordinates.
    pub fn new(
        point_count: u64,
        dimensions: usize,
        scramble: HaltonScramble,
        seed: u64,
    ) -> Result<Self, PointSetError> {
        if point_count == 0 {
            return Err(PointSetError::InvalidParameter(
                "a Hammersley set needs at least one point".into(),
            ));
        }
        if dimensions == 0 || dimensions > PRIME_COUNT + 1 {
            return Err(PointSetError::TooManyDimensions {
                requested: dimensions,
                supported: PRIME_COUNT + 1,
            });
        }
        Ok(Self {
            point_count,
            inverse_point_count: 1.0 / point_count as f64,
            halton: Halton::new(dimensions - 1, scramble, seed)?,
        })
    }
}

impl PointSet for Hammersley {
    fn dimensions(&self) -> usize {
        self.halton.dimensions() + 1
    }

    fn len(&self) -> Option<u64> {
        Some(self.point_count)
    }

    #[inline]
    fn sample(&self, index: u64, dimension: usize) -> f64 {
        debug_assert!(index < self.point_count);
        if dimension == 0 {
            index as f64 * self.inverse_point_count
        } else {
            self.halton.sample(index, dimension - 1)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_coordinate_is_index_over_count_and_second_van_der_corput() {
        let set = Hammersley::new(8, 3, HaltonScramble::None, 0).unwrap();
        assert_eq!(set.len(), Some(8));
        assert_eq!(set.dimensions(), 3);
        let vdc = [0.0, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875];
        for (index, &value) in vdc.iter().enumerate() {
            assert_eq!(set.sample(index as u64, 0), index as f64 / 8.0);
            assert_eq!(set.sample(index as u64, 1), value);
        }
    }

    #[test]
    fn two_dimensional_set_of_power_of_two_size_is_a_zero_net() {
        // The 2-D Hammersley set with N = 2^m points is a (0, m, 2)-net in
        // base 2: every elementary interval of area 1/N holds one point.
        let m = 6u32;
        let n = 1u64 << m;
        let set = Hammersley::new(n, 2, HaltonScramble::None, 0).unwrap();
        for split in 0..=m {
            let (columns, rows) = (1u64 << split, 1u64 << (m - split));
            let mut counts = vec![0u32; n as usize];
            for index in 0..n {
                let column = (set.sample(index, 0) * columns as f64) as u64;
                let row = (set.sample(index, 1) * rows as f64) as u64;
                counts[(row * columns + column) as usize] += 1;
            }
            assert!(counts.iter().all(|&c| c == 1));
        }
    }

    #[test]
    fn invalid_parameters_are_errors() {
        assert!(Hammersley::new(0, 2, HaltonScramble::None, 0).is_err());
        assert!(Hammersley::new(4, 0, HaltonScramble::None, 0).is_err());
        assert!(Hammersley::new(4, PRIME_COUNT + 2, HaltonScramble::None, 0).is_err());
    }
}
