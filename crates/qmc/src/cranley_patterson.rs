//! Cranley–Patterson rotation (Cranley & Patterson 1976): every point of a set
//! is translated by one shift vector modulo one, `y_i = {x_i + Δ}`.
//!
//! A uniformly random shift makes every point uniformly distributed while the
//! set keeps its structure on the torus (a shifted lattice is a lattice coset),
//! which gives unbiased randomized QMC estimates. LQMC uses the rotation with a
//! *chosen* shift: the one that moves the closest lattice point onto the seed
//! path's sample (see [`crate::closest_point`]).

use crate::hash::{hash2, to_unit_f64};
use crate::point_set::{PointSet, PointSetError};

/// The largest `f64` below one, `1 − 2^−53`.
pub const ONE_MINUS_EPSILON: f64 = 1.0 - f64::EPSILON / 2.0;

/// `(x + shift) mod 1` for `x, shift` in `[0, 1)` (debug-asserted), strictly
/// below one.
///
/// The rounded sum lies in `[0, 2)`; one is subtracted when it reaches one,
/// which is exact in that range. When the exact sum lies just below one but
/// rounds to 1.0, the result is therefore 0.0, not 1.0: on the unit torus that
/// is within half an ulp of the exact value, and it keeps the result in `[0, 1)`.
#[inline]
pub fn shift_modulo_one(x: f64, shift: f64) -> f64 {
    debug_assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&shift));
    let sum = x + shift;
    if sum >= 1.0 { sum - 1.0 } else { sum }
}

/// A point set rotated by a fixed shift vector, one shift component per dimension.
#[derive(Debug, Clone, PartialEq)]
pub struct CranleyPatterson<P: PointSet> {
    inner: P,
    shift: Vec<f64>,
}

impl<P: PointSet> CranleyPatterson<P> {
    /// Rotates `inner` by a pseudo-random shift derived from `seed`: component `j`
    /// is `to_unit_f64(hash2(seed, j))`, so it depends only on the seed and the
    /// dimension.
    pub fn from_seed(inner: P, seed: u64) -> Self {
        let shift = (0..inner.dimensions())
            .map(|dimension| to_unit_f64(hash2(seed, dimension as u64)))
            .collect();
        Self { inner, shift }
    }

    /// Rotates `inner` by the given shift: one component per dimension of
    /// `inner`, each in `[0, 1)`.
    pub fn with_shift(inner: P, shift: Vec<f64>) -> Result<Self, PointSetError> {
        if shift.len() != inner.dimensions() {
            return Err(PointSetError::InvalidParameter(format!(
                "shift has {} components for a {}-dimensional point set",
                shift.len(),
                inner.dimensions()
            )));
        }
        if let Some(bad) = shift.iter().find(|value| !(0.0..1.0).contains(*value)) {
            return Err(PointSetError::InvalidParameter(format!(
                "shift components must be in [0, 1), got {bad}"
            )));
        }
        Ok(Self { inner, shift })
    }

    /// The shift vector.
    pub fn shift(&self) -> &[f64] {
        &self.shift
    }

    /// The unshifted point set.
    pub fn inner(&self) -> &P {
        &self.inner
    }
}

impl<P: PointSet> PointSet for CranleyPatterson<P> {
    fn dimensions(&self) -> usize {
        self.inner.dimensions()
    }

    fn len(&self) -> Option<u64> {
        self.inner.len()
    }

    #[inline]
    fn sample(&self, index: u64, dimension: usize) -> f64 {
        shift_modulo_one(self.inner.sample(index, dimension), self.shift[dimension])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::lattice::Rank1Lattice;

    #[test]
    fn shift_modulo_one_stays_below_one() {
        assert_eq!(shift_modulo_one(0.25, 0.5), 0.75);
        assert_eq!(shift_modulo_one(0.75, 0.5), 0.25);
        assert_eq!(shift_modulo_one(0.5, 0.5), 0.0);
        assert!(shift_modulo_one(ONE_MINUS_EPSILON, ONE_MINUS_EPSILON) < 1.0);
        // 0.5 + (0.5 − 2^−54) rounds to 1.0 in f64: the result wraps to 0.
        assert_eq!(shift_modulo_one(0.5, 0.5 - f64::EPSILON / 4.0), 0.0);
        let tiny = shift_modulo_one(1e-300, ONE_MINUS_EPSILON);
        assert_eq!(tiny, ONE_MINUS_EPSILON);
    }

    #[test]
    fn with_shift_validates() {
        let lattice = Rank1Lattice::new(7, vec![1, 3]).unwrap();
        assert!(CranleyPatterson::with_shift(lattice.clone(), vec![0.1]).is_err());
        assert!(CranleyPatterson::with_shift(lattice.clone(), vec![0.1, 1.0]).is_err());
        assert!(CranleyPatterson::with_shift(lattice.clone(), vec![0.1, f64::NAN]).is_err());
        assert!(CranleyPatterson::with_shift(lattice, vec![0.1, 0.0]).is_ok());
    }

    #[test]
    fn seeded_shift_depends_only_on_seed() {
        let lattice = Rank1Lattice::new(23, vec![1, 7, 5]).unwrap();
        let first = CranleyPatterson::from_seed(lattice.clone(), 42);
        let second = CranleyPatterson::from_seed(lattice.clone(), 42);
        let other = CranleyPatterson::from_seed(lattice, 43);
        assert_eq!(first.shift(), second.shift());
        assert_ne!(first.shift(), other.shift());
        assert_eq!(first.len(), Some(23));
        assert_eq!(first.dimensions(), 3);
    }
}
