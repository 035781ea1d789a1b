//! Rank-1 lattice benchmarks: coordinate evaluation (plain and Cranley–Patterson
//! shifted), CBC construction and the closest-point searches.
//!
//! Run with `cargo bench -p qmc --bench lattice`. Per-sample times are the
//! median iteration time divided by the item count shown by divan.

use divan::counter::ItemsCount;
use divan::{Bencher, black_box};
use qmc::PointSet;
use qmc::cbc::{ProductWeights, fast_cbc, plain_cbc};
use qmc::closest_point::closest_index_brute_force;
use qmc::cranley_patterson::CranleyPatterson;
use qmc::hash::{hash3, to_unit_f64};
use qmc::lattice_table::lqmc_lattice_entry;

fn main() {
    divan::main();
}

/// All 313 points × 21 dimensions of the largest LQMC lattice, one `sample` call each.
#[divan::bench]
fn points_313x21(bencher: Bencher) {
    let lattice = lqmc_lattice_entry(313, 21).unwrap().lattice();
    bencher.counter(ItemsCount::new(313usize * 21)).bench(|| {
        let mut sum = 0.0;
        for index in 0..black_box(313u64) {
            for dimension in 0..21 {
                sum += lattice.sample(index, dimension);
            }
        }
        sum
    });
}

/// The same with a Cranley–Patterson shift.
#[divan::bench]
fn shifted_points_313x21(bencher: Bencher) {
    let lattice = lqmc_lattice_entry(313, 21).unwrap().lattice().clone();
    let shifted = CranleyPatterson::from_seed(lattice, 7);
    bencher.counter(ItemsCount::new(313usize * 21)).bench(|| {
        let mut sum = 0.0;
        for index in 0..black_box(313u64) {
            for dimension in 0..21 {
                sum += shifted.sample(index, dimension);
            }
        }
        sum
    });
}

#[divan::bench(args = [97, 313])]
fn fast_cbc_21_dimensions(bencher: Bencher, point_count: u64) {
    let weights = ProductWeights::lqmc_default(21);
    bencher.bench(|| fast_cbc(black_box(point_count), 21, &weights).unwrap());
}

#[divan::bench(args = [97, 313])]
fn plain_cbc_21_dimensions(bencher: Bencher, point_count: u64) {
    let weights = ProductWeights::lqmc_default(21);
    bencher.bench(|| plain_cbc(black_box(point_count), 21, &weights).unwrap());
}

const QUERIES: u64 = 64;

fn queries(dimensions: usize) -> Vec<Vec<f64>> {
    (0..QUERIES)
        .map(|query| {
            (0..dimensions)
                .map(|dimension| to_unit_f64(hash3(99, query, dimension as u64)))
                .collect()
        })
        .collect()
}

/// `(N, s̄)`: the dof-spheres explorations (N = 23, s̄ = 2–4; NEE N = 7), then
/// larger sets and dimension counts of the LQMC table.
const CLOSEST_CASES: [(u64, usize); 10] = [
    (7, 4),
    (23, 2),
    (23, 3),
    (23, 4),
    (23, 8),
    (97, 5),
    (97, 12),
    (313, 5),
    (313, 12),
    (313, 21),
];

/// Brute-force closest point, per query (64 random queries per iteration).
#[divan::bench(args = CLOSEST_CASES)]
fn closest_brute_force(bencher: Bencher, (point_count, dimensions): (u64, usize)) {
    let lattice = lqmc_lattice_entry(point_count, dimensions)
        .unwrap()
        .lattice();
    let points = queries(dimensions);
    bencher.counter(ItemsCount::new(QUERIES)).bench(|| {
        points
            .iter()
            .map(|point| closest_index_brute_force(lattice, black_box(point)).unwrap())
            .sum::<u64>()
    });
}

/// Reduced-basis (LLL + enumeration) closest point, per query.
#[divan::bench(args = CLOSEST_CASES)]
fn closest_reduced_basis(bencher: Bencher, (point_count, dimensions): (u64, usize)) {
    let search = lqmc_lattice_entry(point_count, dimensions)
        .unwrap()
        .closest_point_search();
    let points = queries(dimensions);
    bencher.counter(ItemsCount::new(QUERIES)).bench(|| {
        points
            .iter()
            .map(|point| {
                search
                    .closest_index_by_enumeration(black_box(point))
                    .unwrap()
            })
            .sum::<u64>()
    });
}

/// Projection scan over the points sorted by their first coordinate, per query.
#[divan::bench(args = CLOSEST_CASES)]
fn closest_projection_scan(bencher: Bencher, (point_count, dimensions): (u64, usize)) {
    let search = lqmc_lattice_entry(point_count, dimensions)
        .unwrap()
        .closest_point_search();
    let points = queries(dimensions);
    bencher.counter(ItemsCount::new(QUERIES)).bench(|| {
        points
            .iter()
            .map(|point| {
                search
                    .closest_index_by_projection_scan(black_box(point))
                    .unwrap()
            })
            .sum::<u64>()
    });
}

/// What the LQMC lattice step calls: `ClosestPointSearch::closest_point_into`
/// (the automatic choice, then the shift), per query.
#[divan::bench(args = CLOSEST_CASES)]
fn closest_point_and_shift(bencher: Bencher, (point_count, dimensions): (u64, usize)) {
    let search = lqmc_lattice_entry(point_count, dimensions)
        .unwrap()
        .closest_point_search();
    let points = queries(dimensions);
    let mut shift = vec![0.0; dimensions];
    bencher.counter(ItemsCount::new(QUERIES)).bench_local(|| {
        points
            .iter()
            .map(|point| {
                search
                    .closest_point_into(black_box(point), &mut shift)
                    .unwrap()
            })
            .sum::<u64>()
    });
}

/// `ClosestPointSearch::closest_index`: enumeration or the projection scan,
/// whichever the construction-time work count predicts cheaper.
#[divan::bench(args = CLOSEST_CASES)]
fn closest_automatic(bencher: Bencher, (point_count, dimensions): (u64, usize)) {
    let search = lqmc_lattice_entry(point_count, dimensions)
        .unwrap()
        .closest_point_search();
    let points = queries(dimensions);
    bencher.counter(ItemsCount::new(QUERIES)).bench(|| {
        points
            .iter()
            .map(|point| search.closest_index(black_box(point)).unwrap())
            .sum::<u64>()
    });
}

/// Fast CBC for N = 2^16 points, 21 dimensions (the power-of-two algorithm:
/// one FFT convolution per 2-adic block and dimension).
#[divan::bench]
fn fast_cbc_power_of_two_65536x21(bencher: Bencher) {
    let weights = ProductWeights::lqmc_default(21);
    bencher.bench(|| fast_cbc(black_box(1 << 16), 21, &weights).unwrap());
}
