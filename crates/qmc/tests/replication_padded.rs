//! Tests of `qmc::padded` (padded replications and Latin supercube sampling)
//! and of its use with `qmc::replication`.

use std::sync::Arc;

use qmc::PointSet;
use qmc::padded::{BlockLayout, BlockRandomization, PaddedPointSet, Padding};
use qmc::replication::{ReplicationPlan, estimate_integral};

/// Test-only 2-D Hammersley basis pattern: (i/m, radical inverse of i in base 2).
struct Hammersley {
    count: u64,
}

impl PointSet for Hammersley {
    fn dimensions(&self) -> usize {
        2
    }
    fn len(&self) -> Option<u64> {
        Some(self.count)
    }
    fn sample(&self, index: u64, dimension: usize) -> f64 {
        if dimension == 0 {
            index as f64 / self.count as f64
        } else {
            index.reverse_bits() as f64 * (1.0 / 18_446_744_073_709_551_616.0)
        }
    }
}

fn basis(count: u64) -> Arc<dyn PointSet> {
    Arc::new(Hammersley { count })
}

fn shifted(value: f64, shift: f64) -> f64 {
    let sum = value + shift;
    if sum >= 1.0 { sum - 1.0 } else { sum }
}

#[test]
fn padded_block_projection_is_the_shifted_pattern() {
    let pattern = basis(16);
    let layout = BlockLayout::from_sizes(vec![2, 2, 1, 2]).unwrap();
    let set = PaddedPointSet::padded_replications(
        pattern.clone(),
        layout,
        BlockRandomization::CranleyPatterson,
        42,
        3,
    )
    .unwrap();
    assert_eq!(set.dimensions(), 7);
    let mut dimension = 0;
    for block in 0..4 {
        let shift = set.block_shift(block).unwrap();
        for (coordinate, &delta) in shift.iter().enumerate() {
            assert!((0.0..1.0).contains(&delta));
            for index in 0..16 {
                assert_eq!(
                    set.sample(index, dimension),
                    shifted(pattern.sample(index, coordinate), delta),
                    "block {block} coordinate {coordinate} point {index}"
                );
            }
            dimension += 1;
        }
    }
    // Different blocks, replications and seeds get different shifts.
    assert_ne!(set.block_shift(0), set.block_shift(1));
    let other_replication = PaddedPointSet::padded_replications(
        pattern.clone(),
        BlockLayout::uniform(2, 7).unwrap(),
        BlockRandomization::CranleyPatterson,
        42,
        4,
    )
    .unwrap();
    assert_ne!(set.block_shift(0), other_replication.block_shift(0));
}

#[test]
fn latin_supercube_block_is_the_pattern_permuted_then_shifted() {
    let pattern = basis(32);
    for randomization in [
        BlockRandomization::None,
        BlockRandomization::CranleyPatterson,
    ] {
        let set = PaddedPointSet::latin_supercube(
            pattern.clone(),
            BlockLayout::uniform(2, 6).unwrap(),
            randomization,
            7,
            0,
        )
        .unwrap();
        assert_eq!(set.padding(), Padding::LatinSupercube);
        for block in 0..3 {
            let permutation = set.block_permutation(block).unwrap();
            let shift = set.block_shift(block).unwrap();
            let mut block_points = Vec::new();
            let mut shifted_pattern = Vec::new();
            for index in 0..32u64 {
                let basis_index = u64::from(permutation[index as usize]);
                let point: Vec<f64> = (0..2).map(|c| set.sample(index, 2 * block + c)).collect();
                let expected: Vec<f64> = (0..2)
                    .map(|c| shifted(pattern.sample(basis_index, c), shift[c]))
                    .collect();
                assert_eq!(point, expected);
                block_points.push(point);
                shifted_pattern.push(
                    (0..2)
                        .map(|c| shifted(pattern.sample(index, c), shift[c]))
                        .collect(),
                );
            }
            // Same multiset of points as the shifted pattern.
            let key = |p: &Vec<f64>| (p[0].to_bits(), p[1].to_bits());
            block_points.sort_by_key(key);
            shifted_pattern.sort_by_key(key);
            assert_eq!(block_points, shifted_pattern);
        }
        // The permutations of different blocks differ (probability 1 − 3/32!).
        assert_ne!(set.block_permutation(0), set.block_permutation(1));
    }
}

/// Sample correlation of paired values.
fn correlation(pairs: &[(f64, f64)]) -> f64 {
    let count = pairs.len() as f64;
    let mean_x = pairs.iter().map(|p| p.0).sum::<f64>() / count;
    let mean_y = pairs.iter().map(|p| p.1).sum::<f64>() / count;
    let covariance: f64 = pairs.iter().map(|p| (p.0 - mean_x) * (p.1 - mean_y)).sum();
    let variance_x: f64 = pairs.iter().map(|p| (p.0 - mean_x).powi(2)).sum();
    let variance_y: f64 = pairs.iter().map(|p| (p.1 - mean_y).powi(2)).sum();
    covariance / (variance_x * variance_y).sqrt()
}

#[test]
fn blocks_are_independent_across_seeds() {
    // For a fixed point index, the coordinates of two blocks over S seeds are
    // independent; then the sample correlation has mean 0 and standard
    // deviation 1/sqrt(S − 1): allow 5 of those.
    const SEEDS: u64 = 2000;
    let bound = 5.0 / ((SEEDS - 1) as f64).sqrt();
    let layout = BlockLayout::uniform(2, 6).unwrap();
    for (padding, randomization) in [
        (Padding::Replications, BlockRandomization::CranleyPatterson),
        (
            Padding::LatinSupercube,
            BlockRandomization::CranleyPatterson,
        ),
        (Padding::LatinSupercube, BlockRandomization::None),
    ] {
        for (index, first_dimension, second_dimension) in [(3u64, 0, 2), (11, 1, 5), (0, 0, 4)] {
            let pairs: Vec<(f64, f64)> = (0..SEEDS)
                .map(|seed| {
                    let set = PaddedPointSet::new(
                        basis(16),
                        layout.clone(),
                        padding,
                        randomization,
                        seed,
                        0,
                    )
                    .unwrap();
                    (
                        set.sample(index, first_dimension),
                        set.sample(index, second_dimension),
                    )
                })
                .collect();
            let rho = correlation(&pairs);
            assert!(
                rho.abs() <= bound,
                "{padding:?} {randomization:?} point {index}: correlation {rho} > {bound}"
            );
        }
    }
}

#[test]
fn latin_supercube_decorrelates_blocks_within_a_set() {
    // Unrandomized padded replications repeat the pattern: correlation 1.
    // Pairing fixed values by a uniform random permutation gives a sample
    // correlation with mean exactly 0 and variance 1/(m − 1); the average over
    // S independent sets has standard deviation 1/sqrt(S (m − 1)).
    const SEEDS: u64 = 400;
    const POINTS: u64 = 32;
    let layout = BlockLayout::uniform(2, 4).unwrap();
    let within_set_correlation = |set: &PaddedPointSet| {
        let pairs: Vec<(f64, f64)> = (0..POINTS)
            .map(|index| (set.sample(index, 0), set.sample(index, 2)))
            .collect();
        correlation(&pairs)
    };
    let padded = PaddedPointSet::padded_replications(
        basis(POINTS),
        layout.clone(),
        BlockRandomization::None,
        0,
        0,
    )
    .unwrap();
    assert!((within_set_correlation(&padded) - 1.0).abs() < 1e-12);

    let average = (0..SEEDS)
        .map(|seed| {
            let set = PaddedPointSet::latin_supercube(
                basis(POINTS),
                layout.clone(),
                BlockRandomization::None,
                seed,
                0,
            )
            .unwrap();
            within_set_correlation(&set)
        })
        .sum::<f64>()
        / SEEDS as f64;
    let bound = 5.0 / ((SEEDS * (POINTS - 1)) as f64).sqrt();
    assert!(average.abs() <= bound, "{average} > {bound}");
}

/// ∏_j (1 + (x_j − 1/2)) over [0,1)^8 integrates to 1.
fn product_integrand(point: &[f64]) -> f64 {
    point.iter().map(|x| 0.5 + x).product()
}

#[test]
fn replicated_padded_sets_estimate_an_eight_dimensional_integral_without_bias() {
    const SEEDS: u64 = 500;
    let shared_basis = basis(16);
    let layout = BlockLayout::uniform(2, 8).unwrap();
    for padding in [Padding::Replications, Padding::LatinSupercube] {
        let mut means = Vec::new();
        let mut differences = Vec::new();
        for base_seed in 0..SEEDS {
            let plan = ReplicationPlan {
                replication_count: 8,
                points_per_replication: 16,
                dimensions: 8,
                base_seed,
            };
            let estimate = estimate_integral(
                &plan,
                |seed| {
                    PaddedPointSet::new(
                        shared_basis.clone(),
                        layout.clone(),
                        padding,
                        BlockRandomization::CranleyPatterson,
                        seed,
                        0,
                    )
                },
                product_integrand,
            )
            .unwrap();
            means.push(estimate.mean);
            // E[σ̂²] = Var(Î) = E[(Î − 1)²]: the difference has mean 0.
            differences.push(estimate.variance_of_mean.unwrap() - (estimate.mean - 1.0).powi(2));
        }
        let seeds = SEEDS as f64;
        let mean_and_standard_error = |values: &[f64]| {
            let mean = values.iter().sum::<f64>() / seeds;
            let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (seeds - 1.0);
            (mean, (variance / seeds).sqrt())
        };
        let (mean, mean_error) = mean_and_standard_error(&means);
        assert!(
            (mean - 1.0).abs() <= 5.0 * mean_error,
            "{padding:?}: mean {mean} ± {mean_error}"
        );
        let (difference, difference_error) = mean_and_standard_error(&differences);
        assert!(
            difference.abs() <= 5.0 * difference_error,
            "{padding:?}: variance bias {difference} ± {difference_error}"
        );
    }
}
