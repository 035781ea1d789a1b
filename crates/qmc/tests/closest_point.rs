//! Exactness of the closest-point searches on every lattice of the LQMC table:
//! the projection scan, the reduced-basis enumeration and the automatic choice
//! return the brute-force point (ties to the smallest index) on the torus, for
//! random queries, queries at lattice points and queries halfway between two
//! points (exact ties).

use proptest::prelude::*;
use qmc::PointSet;
use qmc::closest_point::{closest_index_brute_force, toroidal_squared_distance};
use qmc::hash::{hash3, to_unit_f64};
use qmc::lattice_table::{LQMC_LATTICE_SIZES, LQMC_MAX_DIMENSIONS, lqmc_lattice_entry};

/// Every `(N, s̄)` of the table.
fn table() -> impl Iterator<Item = (u64, usize)> {
    LQMC_LATTICE_SIZES
        .into_iter()
        .flat_map(|size| (1..=LQMC_MAX_DIMENSIONS).map(move |dimensions| (size, dimensions)))
}

/// The searches agree with brute force on `point`; a different index is only
/// allowed for an exact tie, and then never (the tie-break is the same).
fn check(point_count: u64, dimensions: usize, point: &[f64]) -> Result<(), TestCaseError> {
    let entry = lqmc_lattice_entry(point_count, dimensions).unwrap();
    let lattice = entry.lattice();
    let search = entry.closest_point_search();
    let brute = closest_index_brute_force(lattice, point).unwrap();
    let minimum = (0..point_count)
        .map(|index| toroidal_squared_distance(lattice, index, point))
        .fold(f64::INFINITY, f64::min);
    prop_assert_eq!(toroidal_squared_distance(lattice, brute, point), minimum);
    let scan = search.closest_index_by_projection_scan(point).unwrap();
    prop_assert_eq!(
        scan,
        brute,
        "scan, N = {}, s = {}, {:?}",
        point_count,
        dimensions,
        point
    );
    prop_assert_eq!(search.closest_index(point).unwrap(), brute);
    let mut shift = vec![0.0; dimensions];
    prop_assert_eq!(search.closest_point_into(point, &mut shift).unwrap(), brute);
    prop_assert_eq!(&search.closest_point(point).unwrap().shift, &shift);
    let enumerated = search.closest_index_by_enumeration(point).unwrap();
    prop_assert!(
        toroidal_squared_distance(lattice, enumerated, point) <= minimum * (1.0 + 1e-12),
        "enumeration, N = {}, s = {}",
        point_count,
        dimensions
    );
    Ok(())
}

fn hashed_point(seed: u64, sample: u64, dimensions: usize) -> Vec<f64> {
    (0..dimensions)
        .map(|dimension| to_unit_f64(hash3(seed, sample, dimension as u64)))
        .collect()
}

#[test]
fn every_table_entry_agrees_with_brute_force() {
    for (point_count, dimensions) in table() {
        let lattice = lqmc_lattice_entry(point_count, dimensions)
            .unwrap()
            .lattice();
        for sample in 0..40 {
            let point = hashed_point(point_count * 31 + dimensions as u64, sample, dimensions);
            check(point_count, dimensions, &point).unwrap();
        }
        // Lattice points themselves and exact midpoints between two of them
        // (ties: the smaller index must win in every search).
        let mut point = vec![0.0; dimensions];
        let mut other = vec![0.0; dimensions];
        for index in [0, 1, point_count / 2, point_count - 1] {
            lattice.point(index, &mut point);
            check(point_count, dimensions, &point).unwrap();
            lattice.point((index + 1) % point_count, &mut other);
            let midpoint: Vec<f64> = point
                .iter()
                .zip(&other)
                .map(|(a, b)| {
                    // The midpoint on the circle (the shorter arc).
                    let mut difference = b - a;
                    if difference > 0.5 {
                        difference -= 1.0;
                    } else if difference < -0.5 {
                        difference += 1.0;
                    }
                    let value = a + 0.5 * difference;
                    let value = value - value.floor();
                    if value >= 1.0 { 0.0 } else { value }
                })
                .collect();
            check(point_count, dimensions, &midpoint).unwrap();
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// Random `(N, s̄)` of the table and random queries, including coordinates
    /// close to 0 and to 1 (the wrap-around of the torus).
    #[test]
    fn random_queries_agree_with_brute_force(
        size_slot in 0usize..LQMC_LATTICE_SIZES.len(),
        dimensions in 1usize..=LQMC_MAX_DIMENSIONS,
        raw in proptest::collection::vec(0.0f64..1.0, LQMC_MAX_DIMENSIONS),
        near_edge in proptest::collection::vec(any::<bool>(), LQMC_MAX_DIMENSIONS),
    ) {
        let point: Vec<f64> = raw[..dimensions]
            .iter()
            .zip(&near_edge)
            .map(|(value, edge)| if *edge { (value * 1e-3 + 0.9995).fract() } else { *value })
            .collect();
        check(LQMC_LATTICE_SIZES[size_slot], dimensions, &point)?;
    }
}
