//! Padded replications sampling and Latin supercube sampling: high-dimensional
//! point sets assembled from one low-dimensional basis pattern.
//!
//! Light transport samples a path with a sequence of low-dimensional
//! subproblems (a 2-D area sample, a 2-D scattering direction, a 1-D choice,
//! …). Instead of a high-dimensional low-discrepancy set, *padded replications
//! sampling* (Kollig and Keller 2002, Sect. 4.3, Fig. 3) uses one basis pattern
//! `P` of `m` points in 1 or 2 dimensions for every block of dimensions and
//! randomizes each block independently:
//! point `i` is `(P_i + Δ_1, P_i + Δ_2, …) mod 1` with independent uniform
//! Cranley–Patterson shifts `Δ_k` per block.
//!
//! The same pattern in every block correlates the blocks (Fig. 4 (b)). *Latin
//! supercube sampling* (Owen 1998; Kollig and Keller 2002, Sect. 5, Fig. 4 (c))
//! removes that correlation with an independent uniform random permutation `π_k`
//! of the point indices per block: block `k` of point `i` is `P_{π_k(i)}` (then
//! shifted by `Δ_k` when randomized).
//!
//! Every random choice of block `k` comes from the hash of
//! `(seed, replication, k)`, so a set depends only on its arguments. With the
//! Cranley–Patterson randomization every point is uniform on the unit cube and
//! sets with different seeds or replication numbers are independent, which is
//! what [`crate::replication`] needs for unbiased estimates.

use std::sync::Arc;

use crate::hash::{hash2, hash3, to_unit_f64};
use crate::point_set::{PointSet, PointSetError};

/// Hash tag separating the shift stream of a block from its permutation stream.
const SHIFT_TAG: u64 = 0x5348_4946_5431;
/// Hash tag of the permutation stream of a block.
const PERMUTATION_TAG: u64 = 0x5045_524D_5554;

/// How the dimensions of a padded point are grouped into blocks, each filled
/// from the basis pattern.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct BlockLayout {
    block_sizes: Vec<usize>,
}

impl BlockLayout {
    /// Blocks of the given sizes, in order: `[2, 2, 1]` makes dimensions 0–1,
    /// 2–3 and 4. Errors if there are no blocks or a block is empty.
    pub fn from_sizes(block_sizes: Vec<usize>) -> Result<Self, PointSetError> {
        if block_sizes.is_empty() {
            return Err(PointSetError::InvalidParameter(
                "a block layout needs at least one block".into(),
            ));
        }
        if block_sizes.contains(&0) {
            return Err(PointSetError::InvalidParameter(
                "every block needs at least one dimension".into(),
            ));
        }
        Ok(Self { block_sizes })
    }

    /// `dimensions` split into blocks of `block_size`; the last block is
    /// shorter when `block_size` does not divide `dimensions`. Errors if either
    /// is zero.
    pub fn uniform(block_size: usize, dimensions: usize) -> Result<Self, PointSetError> {
        if block_size == 0 || dimensions == 0 {
            return Err(PointSetError::InvalidParameter(
                "block size and dimensions must be at least 1".into(),
            ));
        }
        let mut block_sizes = vec![block_size; dimensions / block_size];
        if !dimensions.is_multiple_of(block_size) {
            block_sizes.push(dimensions % block_size);
        }
        Self::from_sizes(block_sizes)
    }

    /// The size of each block, in order.
    pub fn block_sizes(&self) -> &[usize] {
        &self.block_sizes
    }

    /// Number of blocks.
    pub fn block_count(&self) -> usize {
        self.block_sizes.len()
    }

    /// Total number of dimensions, the sum of the block sizes.
    pub fn dimensions(&self) -> usize {
        self.block_sizes.iter().sum()
    }
}

/// How each block of a padded set is randomized.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BlockRandomization {
    /// Independent uniform Cranley–Patterson shift per block (the default):
    /// block `k` becomes `(P + Δ_k) mod 1`.
    #[default]
    CranleyPatterson,
    /// No shift: the basis pattern as is (Latin supercube permutations still
    /// apply). Deterministic padded replications repeat one pattern in every block.
    None,
}

/// How the blocks are assembled from the basis pattern.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Padding {
    /// Padded replications sampling: block `k` of point `i` is `P_i` (the default).
    #[default]
    Replications,
    /// Latin supercube sampling: block `k` of point `i` is `P_{π_k(i)}` with an
    /// independent uniform random permutation `π_k` per block.
    LatinSupercube,
}

/// A finite `s`-dimensional point set of `m` points built from an `m`-point
/// basis pattern by padded replications or Latin supercube sampling.
pub struct PaddedPointSet {
    basis: Arc<dyn PointSet>,
    layout: BlockLayout,
    padding: Padding,
    randomization: BlockRandomization,
    point_count: u64,
    /// For every dimension: its block and its coordinate within the block.
    dimension_origin: Vec<(usize, usize)>,
    /// Cranley–Patterson shift of every dimension (0 when not randomized).
    shifts: Vec<f64>,
    /// Index permutation of every block (Latin supercube only; empty otherwise).
    permutations: Vec<Vec<u32>>,
}

impl PaddedPointSet {
    /// Padded replications sampling (Kollig–Keller Sect. 4.3) of `basis`.
    /// See [`PaddedPointSet::new`].
    pub fn padded_replications(
        basis: impl Into<Arc<dyn PointSet>>,
        layout: BlockLayout,
        randomization: BlockRandomization,
        seed: u64,
        replication: u64,
    ) -> Result<Self, PointSetError> {
        Self::new(
            basis,
            layout,
            Padding::Replications,
            randomization,
            seed,
            replication,
        )
    }

    /// Latin supercube sampling (Owen 1998; Kollig–Keller Sect. 5) of `basis`.
    /// See [`PaddedPointSet::new`].
    pub fn latin_supercube(
        basis: impl Into<Arc<dyn PointSet>>,
        layout: BlockLayout,
        randomization: BlockRandomization,
        seed: u64,
        replication: u64,
    ) -> Result<Self, PointSetError> {
        Self::new(
            basis,
            layout,
            Padding::LatinSupercube,
            randomization,
            seed,
            replication,
        )
    }

    /// Pads the finite basis pattern `basis` (its `m` points, its first
    /// `size` dimensions for a block of `size`) to `layout.dimensions()`
    /// dimensions. Block `k`'s shift and permutation are derived from
    /// `hash3(seed, replication, k)`. A shared basis is passed as an
    /// `Arc<dyn PointSet>`, an owned one as a `Box<dyn PointSet>`.
    ///
    /// Errors if the basis is infinite or empty, has fewer dimensions than the
    /// largest block, or (Latin supercube) has more than 2^32 points.
    pub fn new(
        basis: impl Into<Arc<dyn PointSet>>,
        layout: BlockLayout,
        padding: Padding,
        randomization: BlockRandomization,
        seed: u64,
        replication: u64,
    ) -> Result<Self, PointSetError> {
        let basis = basis.into();
        let point_count = match basis.len() {
            Some(0) => {
                return Err(PointSetError::InvalidParameter(
                    "the basis pattern has no points".into(),
                ));
            }
            Some(count) => count,
            None => {
                return Err(PointSetError::InvalidParameter(
                    "the basis pattern must be a finite point set".into(),
                ));
            }
        };
        let largest_block = layout.block_sizes().iter().copied().max().unwrap_or(0);
        if largest_block > basis.dimensions() {
            return Err(PointSetError::TooManyDimensions {
                requested: largest_block,
                supported: basis.dimensions(),
            });
        }
        if padding == Padding::LatinSupercube && point_count > 1u64 << 32 {
            return Err(PointSetError::TooManyPoints {
                requested: point_count,
                supported: 1u64 << 32,
            });
        }

        let mut dimension_origin = Vec::with_capacity(layout.dimensions());
        let mut shifts = Vec::with_capacity(layout.dimensions());
        let mut permutations = Vec::new();
        for (block, &size) in layout.block_sizes().iter().enumerate() {
            let block_seed = hash3(seed, replication, block as u64);
            for coordinate in 0..size {
                dimension_origin.push((block, coordinate));
                shifts.push(match randomization {
                    BlockRandomization::CranleyPatterson => {
                        to_unit_f64(hash3(block_seed, SHIFT_TAG, coordinate as u64))
                    }
                    BlockRandomization::None => 0.0,
                });
            }
            if padding == Padding::LatinSupercube {
                permutations.push(random_permutation(
                    point_count,
                    hash2(block_seed, PERMUTATION_TAG),
                ));
            }
        }
        Ok(Self {
            basis,
            layout,
            padding,
            randomization,
            point_count,
            dimension_origin,
            shifts,
            permutations,
        })
    }

    /// The block layout.
    pub fn layout(&self) -> &BlockLayout {
        &self.layout
    }

    /// Padded replications or Latin supercube.
    pub fn padding(&self) -> Padding {
        self.padding
    }

    /// The randomization applied to each block.
    pub fn randomization(&self) -> BlockRandomization {
        self.randomization
    }

    /// The basis pattern.
    pub fn basis(&self) -> &Arc<dyn PointSet> {
        &self.basis
    }

    /// The block of `dimension` and its coordinate within the block, or
    /// `None` past the last dimension.
    pub fn block_of_dimension(&self, dimension: usize) -> Option<(usize, usize)> {
        self.dimension_origin.get(dimension).copied()
    }

    /// The Cranley–Patterson shift `Δ_k` of block `block` (all zeros without
    /// randomization), or `None` past the last block.
    pub fn block_shift(&self, block: usize) -> Option<&[f64]> {
        let start: usize = self.layout.block_sizes().get(..block)?.iter().sum();
        let size = *self.layout.block_sizes().get(block)?;
        Some(&self.shifts[start..start + size])
    }

    /// The index permutation `π_k` of block `block` (Latin supercube only):
    /// block `block` of point `i` is basis point `π_k[i]`.
    pub fn block_permutation(&self, block: usize) -> Option<&[u32]> {
        self.permutations.get(block).map(Vec::as_slice)
    }
}

impl PointSet for PaddedPointSet {
    fn dimensions(&self) -> usize {
        self.dimension_origin.len()
    }

    fn len(&self) -> Option<u64> {
        Some(self.point_count)
    }

    fn sample(&self, index: u64, dimension: usize) -> f64 {
        debug_assert!(index < self.point_count, "point index out of range");
        let (block, coordinate) = self.dimension_origin[dimension];
        let basis_index = match self.padding {
            Padding::Replications => index,
            Padding::LatinSupercube => u64::from(self.permutations[block][index as usize]),
        };
        let value = self.basis.sample(basis_index, coordinate) + self.shifts[dimension];
        // Both terms are in [0, 1): one subtraction reduces mod 1, exactly.
        if value >= 1.0 { value - 1.0 } else { value }
    }
}

/// A uniform random permutation of `0..count` (`count ≤ 2^32`) by Fisher–Yates,
/// drawing from the counter-based stream `hash2(stream_seed, k)`.
pub fn random_permutation(count: u64, stream_seed: u64) -> Vec<u32> {
    let mut permutation = Vec::new();
    random_permutation_into(count, stream_seed, &mut permutation);
    permutation
}

/// [`random_permutation`] written into `permutation` (its old contents
/// replaced), for callers that draw many and keep the allocation.
pub fn random_permutation_into(count: u64, stream_seed: u64, permutation: &mut Vec<u32>) {
    permutation.clear();
    permutation.extend((0..count).map(|index| index as u32));
    let mut counter = 0u64;
    let mut next = || {
        counter += 1;
        hash2(stream_seed, counter)
    };
    for last in (1..permutation.len()).rev() {
        let chosen = uniform_below(last as u64 + 1, &mut next) as usize;
        permutation.swap(last, chosen);
    }
}

/// An unbiased uniform integer in `0..range` (`range ≥ 1`) by Lemire's
/// multiply-and-reject method ("Fast random integer generation in an
/// interval", 2019).
fn uniform_below(range: u64, next: &mut impl FnMut() -> u64) -> u64 {
    let threshold = range.wrapping_neg() % range;
    loop {
        let product = u128::from(next()) * u128::from(range);
        if (product as u64) >= threshold {
            return (product >> 64) as u64;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two-dimensional grid-free test pattern: (i/m, (i·5 mod m)/m).
    struct Pattern {
        count: u64,
    }

    impl PointSet for Pattern {
        fn dimensions(&self) -> usize {
            2
        }
        fn len(&self) -> Option<u64> {
            Some(self.count)
        }
        fn sample(&self, index: u64, dimension: usize) -> f64 {
            let numerator = if dimension == 0 {
                index
            } else {
                index * 5 % self.count
            };
            numerator as f64 / self.count as f64
        }
    }

    #[test]
    fn layouts() {
        assert_eq!(
            BlockLayout::uniform(2, 7).unwrap().block_sizes(),
            &[2, 2, 2, 1]
        );
        assert_eq!(BlockLayout::uniform(2, 8).unwrap().dimensions(), 8);
        assert!(BlockLayout::uniform(0, 8).is_err());
        assert!(BlockLayout::from_sizes(vec![]).is_err());
        assert!(BlockLayout::from_sizes(vec![2, 0]).is_err());
    }

    #[test]
    fn rejects_unusable_bases() {
        let layout = BlockLayout::uniform(3, 6).unwrap();
        let basis: Box<dyn PointSet> = Box::new(Pattern { count: 8 });
        assert!(matches!(
            PaddedPointSet::padded_replications(basis, layout, BlockRandomization::None, 0, 0),
            Err(PointSetError::TooManyDimensions { .. })
        ));
        let empty: Box<dyn PointSet> = Box::new(Pattern { count: 0 });
        assert!(
            PaddedPointSet::latin_supercube(
                empty,
                BlockLayout::uniform(2, 4).unwrap(),
                BlockRandomization::None,
                0,
                0
            )
            .is_err()
        );
    }

    #[test]
    fn permutations_are_permutations_and_uniform_below_is_in_range() {
        for count in [1u64, 2, 3, 17, 100] {
            let mut permutation = random_permutation(count, count * 31);
            permutation.sort_unstable();
            assert!(permutation.iter().copied().eq(0..count as u32));
        }
        let mut state = 0u64;
        let mut next = || {
            state += 1;
            hash2(99, state)
        };
        for range in [1u64, 2, 3, 1000, u64::MAX] {
            assert!(uniform_below(range, &mut next) < range);
        }
    }

    #[test]
    fn unrandomized_padded_replications_repeat_the_pattern() {
        let set = PaddedPointSet::padded_replications(
            Box::new(Pattern { count: 8 }) as Box<dyn PointSet>,
            BlockLayout::from_sizes(vec![2, 1, 2]).unwrap(),
            BlockRandomization::None,
            5,
            0,
        )
        .unwrap();
        assert_eq!(set.dimensions(), 5);
        assert_eq!(set.len(), Some(8));
        let pattern = Pattern { count: 8 };
        for index in 0..8 {
            let expected = [0, 1, 0, 0, 1].map(|coordinate| pattern.sample(index, coordinate));
            let mut point = [0.0; 5];
            set.point(index, &mut point);
            assert_eq!(point, expected);
        }
        assert_eq!(set.block_of_dimension(2), Some((1, 0)));
        assert_eq!(set.block_of_dimension(5), None);
        assert_eq!(set.block_shift(2), Some(&[0.0, 0.0][..]));
        assert_eq!(set.block_permutation(0), None);
    }
}
