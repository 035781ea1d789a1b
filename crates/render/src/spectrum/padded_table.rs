//! Branch-free look-ups in tables tabulated at every integer wavelength: the
//! table gets one zero entry before its first and after its last value, and a
//! wavelength is turned into an index that is clamped onto those zeros when it
//! lies outside the table (or is NaN, or not positive), so evaluation is a few
//! f32 instructions and one load with no branch.

use super::error::SpectrumError;
use super::lanes;

/// The largest first wavelength (nm) and the largest number of entries a
/// padded table may have (2²⁰): every wavelength offset inside such a table is
/// then exact in f32 (below 2²⁴), which [`PaddedTableIndexer::index`] relies on.
const PADDED_TABLE_LIMIT: usize = 1 << 20;

/// Maps wavelengths to indices into a table with one zero pad at each end:
/// index 0 and `len + 1` are the pads, index i in 1..=len holds the value at
/// `lambda_min + i − 1` nm.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PaddedTableIndexer {
    /// `lambda_min − 1` in f32: the wavelength of the leading pad.
    leading_pad_lambda: f32,
    /// `len + 1` in f32: the index of the trailing pad.
    trailing_pad_index: f32,
}

impl PaddedTableIndexer {
    /// The indexer of a table whose first value belongs to `lambda_min` nm with
    /// `len` values, one per nm. Fails with [`SpectrumError::TableOutOfRange`]
    /// if the table is empty, longer than 2²⁰ entries, or does not start at a
    /// wavelength in [1, 2²⁰] nm.
    pub(crate) fn new(lambda_min: i32, len: usize) -> Result<Self, SpectrumError> {
        let start_in_range = usize::try_from(lambda_min)
            .is_ok_and(|start| (1..=PADDED_TABLE_LIMIT).contains(&start));
        if len == 0 || len > PADDED_TABLE_LIMIT || !start_in_range {
            return Err(SpectrumError::TableOutOfRange {
                lambda_min: i64::from(lambda_min),
                len,
            });
        }
        Ok(Self {
            leading_pad_lambda: (lambda_min - 1) as f32,
            trailing_pad_index: (len + 1) as f32,
        })
    }

    /// The number of entries of the padded table: the real ones and two pads
    /// (the tests check [`Self::index`] against it).
    #[cfg(test)]
    pub(crate) fn padded_len(&self) -> usize {
        self.trailing_pad_index as usize + 1
    }

    /// The padded-table index for `lambda` nm: the nearest integer wavelength
    /// (rounded as λ + ½ truncated, as pbrt-v4's `DenselySampledSpectrum`)
    /// minus `lambda_min − 1`, or a pad if that is outside the table or λ is
    /// not positive (NaN included). Always at most `len + 1`.
    ///
    /// All in f32 so that four look-ups vectorise: λ + ½ − (lambda_min − 1) is
    /// exact whenever it is ≥ 0 and below 2²⁴ (an integer subtracted from a
    /// larger f32 with a spacing ≤ 1), so truncating it gives the same index as
    /// truncating λ + ½ first; values below 0 (λ below the table, not positive
    /// or NaN) select the leading pad and values above `len + 1` the trailing
    /// one.
    #[inline]
    pub(crate) fn index(&self, lambda: f32) -> usize {
        self.clamped_index(lambda) as usize
    }

    /// [`Self::index`] of four wavelengths at once, written lane by lane so
    /// that the compiler computes the four indices with four-wide SSE
    /// instructions (the conversion through `i32`, exact for the clamped
    /// values, vectorises where `f32 as usize` does not).
    #[inline]
    pub(crate) fn indices(&self, lambdas: &[f32; 4]) -> [usize; 4] {
        let mut clamped = [0i32; 4];
        for (clamped, &lambda) in clamped.iter_mut().zip(lambdas) {
            *clamped = self.clamped_index(lambda) as i32;
        }
        clamped.map(|index| index as usize)
    }

    /// The entry of `padded` (a table made by [`Self::pad`]) for `lambda` nm.
    #[inline]
    pub(crate) fn look_up<T: Copy + Default>(&self, padded: &[T], lambda: f32) -> T {
        // The index is always inside the padded table, so `get` never fails.
        padded.get(self.index(lambda)).copied().unwrap_or_default()
    }

    /// [`Self::look_up`] of four wavelengths, their indices computed together
    /// (see [`Self::indices`]).
    #[inline]
    pub(crate) fn look_up_four<T: Copy + Default>(
        &self,
        padded: &[T],
        lambdas: &[f32; 4],
    ) -> [T; 4] {
        let mut entries = [T::default(); 4];
        for (entry, index) in entries.iter_mut().zip(self.indices(lambdas)) {
            // The index is always inside the padded table.
            *entry = padded.get(index).copied().unwrap_or_default();
        }
        entries
    }

    /// λ + ½ − (`lambda_min` − 1) clamped to [0, `len` + 1] in f32, NaN to 0
    /// (see [`Self::index`] for why this is exact), by [`lanes::clamp`].
    #[inline(always)]
    fn clamped_index(&self, lambda: f32) -> f32 {
        let shifted = (lambda + 0.5) - self.leading_pad_lambda;
        lanes::clamp(shifted, 0.0, self.trailing_pad_index)
    }

    /// `values` with a zero (`T::default()`) before and after, in the layout
    /// [`Self::index`] expects. `values.len()` must be the `len` given to
    /// [`Self::new`].
    pub(crate) fn pad<T: Copy + Default>(&self, values: &[T]) -> Vec<T> {
        let mut padded = Vec::with_capacity(values.len() + 2);
        padded.push(T::default());
        padded.extend_from_slice(values);
        padded.push(T::default());
        padded
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn indices_round_to_the_nearest_nm_and_pad_outside() {
        let indexer = PaddedTableIndexer::new(400, 3).unwrap();
        assert_eq!(indexer.padded_len(), 5);
        assert_eq!(indexer.index(400.0), 1);
        assert_eq!(indexer.index(401.4), 2);
        assert_eq!(indexer.index(401.6), 3);
        assert_eq!(indexer.index(402.4), 3);
        assert_eq!(indexer.index(399.4), 0);
        assert_eq!(indexer.index(399.5), 1);
        assert_eq!(indexer.index(402.6), 4);
        assert_eq!(indexer.index(1e30), 4);
        assert_eq!(indexer.index(f32::INFINITY), 4);
        assert_eq!(indexer.index(-5.0), 0);
        assert_eq!(indexer.index(f32::NAN), 0);
        assert_eq!(indexer.index(f32::NEG_INFINITY), 0);
        assert_eq!(indexer.index(0.0), 0);
        let lambdas = [399.4, 401.6, f32::NAN, 1e30];
        assert_eq!(
            indexer.indices(&lambdas),
            lambdas.map(|lambda| indexer.index(lambda))
        );
    }

    #[test]
    fn matches_integer_rounding_over_the_visible_range() {
        let indexer = PaddedTableIndexer::new(360, 471).unwrap();
        let mut lambda = 340.0f32;
        while lambda < 850.0 {
            let nearest = (lambda + 0.5) as i64 - 360;
            let expected = if (0..471).contains(&nearest) {
                nearest as usize + 1
            } else if nearest < 0 {
                0
            } else {
                472
            };
            assert_eq!(indexer.index(lambda), expected, "{lambda}");
            lambda = f32::from_bits(lambda.to_bits() + 97);
        }
    }

    #[test]
    fn extreme_tables_index_without_overflow() {
        let high = PaddedTableIndexer::new(1 << 20, 1 << 20).unwrap();
        assert_eq!(high.index(f32::MAX), (1 << 20) + 1);
        assert_eq!(high.index(1_048_576.0), 1);
        assert_eq!(high.index(2_097_151.0), 1 << 20);
        let low = PaddedTableIndexer::new(1, 1).unwrap();
        assert_eq!(low.index(0.25), 0);
        assert_eq!(low.index(1.0), 1);
        assert_eq!(low.index(-f32::MAX), 0);
        for lambda in [0.1f32, 1.0, 1e10, f32::NAN, -f32::MAX, f32::MAX] {
            assert!(high.index(lambda) < high.padded_len());
            assert!(low.index(lambda) < low.padded_len());
        }
    }

    #[test]
    fn padding_surrounds_the_values_with_zeros() {
        let indexer = PaddedTableIndexer::new(1, 2).unwrap();
        assert_eq!(indexer.pad(&[5.0f32, 6.0]), vec![0.0, 5.0, 6.0, 0.0]);
    }

    #[test]
    fn out_of_range_tables_are_errors() {
        assert_eq!(
            PaddedTableIndexer::new(360, 0),
            Err(SpectrumError::TableOutOfRange {
                lambda_min: 360,
                len: 0
            })
        );
        assert!(PaddedTableIndexer::new(0, 1).is_err());
        assert!(PaddedTableIndexer::new(-5, 10).is_err());
        assert!(PaddedTableIndexer::new(i32::MAX, 1).is_err());
        assert!(PaddedTableIndexer::new(i32::MIN, 1).is_err());
        assert!(PaddedTableIndexer::new(1, (1 << 20) + 1).is_err());
        assert!(PaddedTableIndexer::new(1, usize::MAX).is_err());
        assert!(PaddedTableIndexer::new(1 << 20, 1 << 20).is_ok());
    }
}
