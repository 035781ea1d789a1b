//! The lattice step of Alg. 1: map the seed's explored numbers into their
//! tile (`T(ū) = (ū − o)/k`, Eq. 12, on a tile grid jittered once per
//! progression), find the closest lattice point and its Cranley–Patterson
//! shift, and map every shifted lattice point back (`u_j = T⁻¹({r_j + Δ})`,
//! Eq. 3 on the tile). The lattice dimension assigned to each explored
//! dimension may be permuted (the paper's Sec. 5 remedy against visible
//! lattice structure); a permuted rank-1 lattice is again a rank-1 lattice,
//! so its Voronoi cells stay congruent and the shift consistent.

use super::statistics::ClosestPointTiming;
use qmc::PointSet;
use qmc::lattice_table::LqmcLatticeEntry;

/// The explored numbers of every member, `N × s̄` row-major.
#[derive(Debug, Clone, Default)]
pub struct LatticeMembers {
    /// Numbers in `[0, 1)`, one row per lattice point.
    pub numbers: Vec<f64>,
    /// The lattice point the seed is closest to (its own member).
    pub seed_member: usize,
    /// The Cranley–Patterson shift `Δ`, one entry per lattice dimension.
    pub shift: Vec<f64>,
}

/// Tile grid and lattice dimension mapping of one exploration.
#[derive(Debug, Clone, Copy)]
pub struct TileGrid<'a> {
    /// Tiles per explored dimension.
    pub tiles: &'a [u32],
    /// Grid offset per explored dimension, in `[0, 1/k)`.
    pub jitter: &'a [f64],
    /// The lattice dimension of each explored dimension (a permutation).
    pub lattice_dimension: &'a [usize],
}

/// Fraction of `x` in `[0, 1)`. The arguments here lie in `[−1, 2)`, where
/// a comparison replaces `floor` (a library call on x86-64 without SSE4.1)
/// with the same result: `x − floor(x)` is `x + 1`, `x` or `x − 1` there.
#[inline]
fn fraction(x: f64) -> f64 {
    let fraction = if (0.0..1.0).contains(&x) {
        x + 0.0 // −0 − floor(−0) is +0
    } else if (1.0..2.0).contains(&x) {
        x - 1.0
    } else if (-1.0..0.0).contains(&x) {
        x + 1.0
    } else {
        x - x.floor()
    };
    if fraction >= 1.0 { 0.0 } else { fraction }
}

/// Fills `members` with the explored numbers of the exploration of `seed`
/// (the seed's explored numbers, in `[0, 1)`); `timing` measures the
/// closest-point search alone (not the mapping of the members).
#[allow(clippy::needless_range_loop)] // d indexes four parallel arrays
pub fn lattice_members(
    entry: &LqmcLatticeEntry,
    grid: &TileGrid<'_>,
    seed: &[f64],
    query: &mut Vec<f64>,
    members: &mut LatticeMembers,
    timing: &mut ClosestPointTiming,
) -> Result<(), qmc::PointSetError> {
    let dimensions = seed.len();
    query.clear();
    query.resize(dimensions, 0.0);
    let mut tile_index = [0.0f64; qmc::lattice_table::LQMC_MAX_DIMENSIONS];
    for (d, tile_slot) in tile_index.iter_mut().enumerate().take(dimensions) {
        let tiles = grid.tiles[d] as f64;
        let scaled = (seed[d] - grid.jitter[d]) * tiles;
        let tile = scaled.floor();
        *tile_slot = tile;
        query[grid.lattice_dimension[d]] = fraction(scaled - tile).min(1.0 - f64::EPSILON);
    }
    members.shift.clear();
    members.shift.resize(dimensions, 0.0);
    let search = entry.closest_point_search();
    let seed_member = timing.measure(|| search.closest_point_into(query, &mut members.shift))?;
    let lattice = entry.lattice();
    let count = lattice.point_count() as usize;
    members.numbers.clear();
    members.numbers.reserve(count * dimensions);
    members.seed_member = seed_member as usize;
    for j in 0..count {
        for d in 0..dimensions {
            let lattice_dimension = grid.lattice_dimension[d];
            let in_tile = fraction(
                lattice.sample(j as u64, lattice_dimension) + members.shift[lattice_dimension],
            );
            let tiles = grid.tiles[d] as f64;
            let value = fraction(grid.jitter[d] + (tile_index[d] + in_tile) / tiles);
            members.numbers.push(value);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use qmc::lattice_table::lqmc_lattice_entry;

    #[test]
    fn fraction_agrees_with_floor() {
        let mut random = qmc::random::SeekablePcg::new(3, 0);
        let edges = [
            -1.0,
            -0.0,
            0.0,
            1.0,
            2.0,
            1.0 - f64::EPSILON,
            -1e-300,
            3.5,
            -7.25,
        ];
        let values = (0..10_000)
            .map(|_| random.next_f64() * 4.0 - 1.5)
            .chain(edges);
        for x in values {
            let expected = x - x.floor();
            let expected = if expected >= 1.0 { 0.0 } else { expected };
            assert_eq!(fraction(x).to_bits(), expected.to_bits(), "{x}");
        }
    }

    #[test]
    fn the_seed_is_a_member_and_members_stay_in_its_tile() {
        let entry = lqmc_lattice_entry(23, 3).unwrap();
        let tiles = [4, 1, 10];
        let jitter = [0.1, 0.0, 0.05];
        let grid = TileGrid {
            tiles: &tiles,
            jitter: &jitter,
            lattice_dimension: &[2, 0, 1],
        };
        let seed = [0.37, 0.81, 0.999];
        let mut members = LatticeMembers::default();
        let mut timing = ClosestPointTiming::default();
        lattice_members(
            entry,
            &grid,
            &seed,
            &mut Vec::new(),
            &mut members,
            &mut timing,
        )
        .unwrap();
        assert_eq!(timing.searches, 1);
        assert_eq!(members.numbers.len(), 23 * 3);
        let own = &members.numbers[members.seed_member * 3..members.seed_member * 3 + 3];
        for d in 0..3 {
            assert!((own[d] - seed[d]).abs() < 1e-12, "{own:?} vs {seed:?}");
        }
        for row in members.numbers.chunks(3) {
            for d in 0..3 {
                // Same tile as the seed on the jittered grid (mod 1).
                let tile = |x: f64| {
                    ((x - jitter[d]) * tiles[d] as f64)
                        .floor()
                        .rem_euclid(tiles[d] as f64)
                };
                assert_eq!(tile(row[d]), tile(seed[d]));
            }
        }
    }
}
