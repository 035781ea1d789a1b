//! The rank-1 lattices the LQMC integrator explores with.
//!
//! Tessari, Hanika and Dachsbacher (Section 5, "Local sampling") precompute
//! generators by fast CBC for `N ∈ {7, 23, 97, 313}` and `s̄ = 1, …, 21`
//! explored dimensions, in the Korobov space with α = 2 (P₂) and product weights
//! `γ_j = 1/s̄` (the authors' renderer; see the LQMC implementation notes). Each
//! `(N, s̄)` entry is its own CBC construction (not a projection of the 21-dim
//! one, since the weights depend on `s̄`), built on first use by [`crate::cbc::fast_cbc`]
//! and cached for the life of the program; concurrent first uses are safe
//! (`OnceLock`), and every thread sees the same entry.

use std::sync::OnceLock;

use crate::cbc::{ProductWeights, fast_cbc};
use crate::closest_point::ClosestPointSearch;
use crate::lattice::Rank1Lattice;
use crate::point_set::PointSetError;

/// The lattice sizes of the LQMC paper: 7 (next-event paths), 23 (normal and
/// depth-of-field paths), 97 (caustics), 313 (hard scenes).
pub const LQMC_LATTICE_SIZES: [u64; 4] = [7, 23, 97, 313];

/// The largest number of explored dimensions `s̄` the table holds.
pub const LQMC_MAX_DIMENSIONS: usize = 21;

/// One table entry: the lattice, its closest-point search and its CBC error.
#[derive(Debug)]
pub struct LqmcLatticeEntry {
    search: ClosestPointSearch,
    squared_worst_case_error: f64,
}

impl LqmcLatticeEntry {
    /// The lattice (generator from fast CBC with `γ_j = 1/s̄`, first component 1).
    pub fn lattice(&self) -> &Rank1Lattice {
        self.search.lattice()
    }

    /// The reduced-basis closest-point search for this lattice, prepared once.
    pub fn closest_point_search(&self) -> &ClosestPointSearch {
        &self.search
    }

    /// Squared worst-case error `e²` (P₂, `γ_j = 1/s̄`) of the lattice, as
    /// evaluated by the CBC construction.
    pub fn squared_worst_case_error(&self) -> f64 {
        self.squared_worst_case_error
    }
}

#[allow(clippy::declare_interior_mutable_const)]
const EMPTY_ENTRY: OnceLock<LqmcLatticeEntry> = OnceLock::new();
#[allow(clippy::declare_interior_mutable_const)]
const EMPTY_ROW: [OnceLock<LqmcLatticeEntry>; LQMC_MAX_DIMENSIONS] =
    [EMPTY_ENTRY; LQMC_MAX_DIMENSIONS];

static TABLE: [[OnceLock<LqmcLatticeEntry>; LQMC_MAX_DIMENSIONS]; LQMC_LATTICE_SIZES.len()] =
    [EMPTY_ROW; LQMC_LATTICE_SIZES.len()];

/// The table entry for `point_count ∈ LQMC_LATTICE_SIZES` and
/// `dimensions ∈ 1..=LQMC_MAX_DIMENSIONS`, built on first use.
pub fn lqmc_lattice_entry(
    point_count: u64,
    dimensions: usize,
) -> Result<&'static LqmcLatticeEntry, PointSetError> {
    let size_slot = LQMC_LATTICE_SIZES
        .iter()
        .position(|size| *size == point_count)
        .ok_or_else(|| {
            PointSetError::InvalidParameter(format!(
                "LQMC lattices have {LQMC_LATTICE_SIZES:?} points, not {point_count}"
            ))
        })?;
    if dimensions == 0 {
        return Err(PointSetError::InvalidParameter(
            "LQMC lattices have at least one dimension".to_string(),
        ));
    }
    if dimensions > LQMC_MAX_DIMENSIONS {
        return Err(PointSetError::TooManyDimensions {
            requested: dimensions,
            supported: LQMC_MAX_DIMENSIONS,
        });
    }
    let slot = &TABLE[size_slot][dimensions - 1];
    if let Some(entry) = slot.get() {
        return Ok(entry);
    }
    // Build outside the lock; a racing thread computes the identical entry.
    let constructed = fast_cbc(
        point_count,
        dimensions,
        &ProductWeights::lqmc_default(dimensions),
    )?;
    let squared_worst_case_error = constructed.squared_error();
    let search = ClosestPointSearch::new(constructed.lattice)?;
    Ok(slot.get_or_init(|| LqmcLatticeEntry {
        search,
        squared_worst_case_error,
    }))
}

/// The LQMC lattice with `point_count` points and `dimensions` dimensions (see
/// [`lqmc_lattice_entry`]).
pub fn lqmc_lattice(
    point_count: u64,
    dimensions: usize,
) -> Result<&'static Rank1Lattice, PointSetError> {
    lqmc_lattice_entry(point_count, dimensions).map(LqmcLatticeEntry::lattice)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::point_set::PointSet;

    #[test]
    fn entries_have_requested_shape_and_are_cached() {
        let lattice = lqmc_lattice(97, 5).unwrap();
        assert_eq!(lattice.point_count(), 97);
        assert_eq!(lattice.dimensions(), 5);
        assert_eq!(lattice.generator()[0], 1);
        assert!(std::ptr::eq(lattice, lqmc_lattice(97, 5).unwrap()));
    }

    #[test]
    fn rejects_other_sizes_and_dimensions() {
        assert!(lqmc_lattice(101, 3).is_err());
        assert!(lqmc_lattice(7, 0).is_err());
        assert_eq!(
            lqmc_lattice(7, 22).unwrap_err(),
            PointSetError::TooManyDimensions {
                requested: 22,
                supported: 21
            }
        );
    }

    #[test]
    fn concurrent_first_use_sees_one_entry() {
        let addresses: Vec<usize> = std::thread::scope(|scope| {
            let handles: Vec<_> = (0..4)
                .map(|_| scope.spawn(|| lqmc_lattice(313, 13).unwrap() as *const _ as usize))
                .collect();
            handles
                .into_iter()
                .map(|handle| handle.join().unwrap())
                .collect()
        });
        assert!(addresses.windows(2).all(|pair| pair[0] == pair[1]));
    }
}
