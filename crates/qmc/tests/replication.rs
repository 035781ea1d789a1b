//! Statistical tests of `qmc::replication`: Kollig–Keller Eq. (5) is unbiased and
//! Eq. (6) is an unbiased estimate of its variance.

use qmc::hash::{hash2, to_unit_f64};
use qmc::replication::{
    ReplicationPlan, Replications, RqmcEstimate, estimate_integral, replication_seed,
};
use qmc::{PointSet, PointSetError};

/// Test-only Cranley–Patterson-rotated 2-D Fibonacci lattice: point i is
/// ({i/F_k + Δ_0}, {i F_{k−1}/F_k + Δ_1}), shifts hashed from the seed.
struct ShiftedFibonacci {
    count: u64,
    generator: u64,
    shift: [f64; 2],
}

impl ShiftedFibonacci {
    fn new(seed: u64) -> Self {
        Self {
            count: 34,
            generator: 21,
            shift: [to_unit_f64(hash2(seed, 0)), to_unit_f64(hash2(seed, 1))],
        }
    }
}

impl PointSet for ShiftedFibonacci {
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
            index * self.generator % self.count
        };
        let value = numerator as f64 / self.count as f64 + self.shift[dimension];
        if value >= 1.0 { value - 1.0 } else { value }
    }
}

/// ∫∫ x² e^y dx dy = (e − 1)/3: smooth but not periodic, so the lattice does not
/// integrate it exactly and the replication variance is non-zero.
fn integrand(point: &[f64]) -> f64 {
    point[0] * point[0] * point[1].exp()
}

fn integral() -> f64 {
    (std::f64::consts::E - 1.0) / 3.0
}

fn mean_and_sample_variance(values: &[f64]) -> (f64, f64) {
    let count = values.len() as f64;
    let mean = values.iter().sum::<f64>() / count;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (count - 1.0);
    (mean, variance)
}

#[test]
fn mean_and_variance_estimators_are_unbiased_over_independent_seeds() {
    const SEEDS: u64 = 2000;
    const REPLICATIONS: usize = 4;
    let mut means = Vec::new();
    let mut variance_estimates = Vec::new();
    // d_s = σ̂²_s − (Î_s − I)²: with the integral I known both terms are unbiased
    // for Var(Î), so E[d_s] = 0 exactly and the d_s are i.i.d. over seeds.
    let mut differences = Vec::new();
    for base_seed in 0..SEEDS {
        let plan = ReplicationPlan {
            replication_count: REPLICATIONS,
            points_per_replication: 34,
            dimensions: 2,
            base_seed,
        };
        let estimate =
            estimate_integral(&plan, |seed| Ok(ShiftedFibonacci::new(seed)), integrand).unwrap();
        let variance = estimate.variance_of_mean.unwrap();
        means.push(estimate.mean);
        variance_estimates.push(variance);
        differences.push(variance - (estimate.mean - integral()).powi(2));
    }
    let seeds = SEEDS as f64;
    let (mean_of_means, variance_of_means) = mean_and_sample_variance(&means);
    let (mean_of_variances, variance_of_variances) = mean_and_sample_variance(&variance_estimates);
    let (mean_difference, variance_of_differences) = mean_and_sample_variance(&differences);

    // Eq. (5) is unbiased: its average over seeds is within 5 standard errors.
    let mean_standard_error = (variance_of_means / seeds).sqrt();
    assert!(
        (mean_of_means - integral()).abs() <= 5.0 * mean_standard_error,
        "mean {mean_of_means} vs {} (se {mean_standard_error})",
        integral()
    );

    // Eq. (6) is unbiased: E[d] = 0, tested with d's own standard error.
    let difference_standard_error = (variance_of_differences / seeds).sqrt();
    assert!(
        mean_difference.abs() <= 5.0 * difference_standard_error,
        "E[σ̂²] − E[(Î−I)²] = {mean_difference} (se {difference_standard_error})"
    );
    // The test can see a bias of the size of using 1/r² instead of 1/(r(r−1)),
    // i.e. a relative error of 1/r.
    assert!(5.0 * difference_standard_error < mean_of_variances / REPLICATIONS as f64);

    // Against the empirical variance of Eq. (5) across seeds: the standard
    // deviation of the difference of the two averages is at most the sum of
    // theirs (Cauchy–Schwarz). Var(average of σ̂²) = Var(σ̂²)/S; the sample
    // variance of S values has variance ≈ (μ₄ − σ⁴)/S.
    let fourth_moment = means
        .iter()
        .map(|v| (v - mean_of_means).powi(4))
        .sum::<f64>()
        / seeds;
    let standard_error_of_average = (variance_of_variances / seeds).sqrt();
    let standard_error_of_sample_variance =
        ((fourth_moment - variance_of_means.powi(2)).max(0.0) / seeds).sqrt();
    assert!(
        (mean_of_variances - variance_of_means).abs()
            <= 5.0 * (standard_error_of_average + standard_error_of_sample_variance),
        "average σ̂² {mean_of_variances} vs empirical variance {variance_of_means}"
    );
}

#[test]
fn single_replication_gives_a_mean_without_variance() {
    let plan = ReplicationPlan {
        replication_count: 1,
        points_per_replication: 34,
        dimensions: 2,
        base_seed: 9,
    };
    let estimate =
        estimate_integral(&plan, |seed| Ok(ShiftedFibonacci::new(seed)), integrand).unwrap();
    assert_eq!(estimate.variance_of_mean, None);
    assert_eq!(estimate.standard_error, None);
    assert_eq!(estimate.replication_means, vec![estimate.mean]);
}

#[test]
fn replication_j_is_built_from_the_hashed_seed() {
    let plan = ReplicationPlan {
        replication_count: 3,
        points_per_replication: 5,
        dimensions: 1,
        base_seed: 77,
    };
    let mut seeds = Vec::new();
    estimate_integral(
        &plan,
        |seed| {
            seeds.push(seed);
            Ok(ShiftedFibonacci::new(seed))
        },
        |point| point[0],
    )
    .unwrap();
    let expected: Vec<u64> = (0..3).map(|j| replication_seed(77, j)).collect();
    assert_eq!(seeds, expected);
}

#[test]
fn bad_plans_and_sets_are_errors() {
    let plan = ReplicationPlan {
        replication_count: 2,
        points_per_replication: 34,
        dimensions: 2,
        base_seed: 1,
    };
    let factory = |seed| Ok(ShiftedFibonacci::new(seed));
    for bad in [
        ReplicationPlan {
            replication_count: 0,
            ..plan
        },
        ReplicationPlan {
            points_per_replication: 0,
            ..plan
        },
        ReplicationPlan {
            dimensions: 0,
            ..plan
        },
        ReplicationPlan {
            dimensions: 3,
            ..plan
        },
        ReplicationPlan {
            points_per_replication: 35,
            ..plan
        },
    ] {
        assert!(
            estimate_integral(&bad, factory, integrand).is_err(),
            "{bad:?}"
        );
    }
    let failing = estimate_integral(
        &plan,
        |_| -> Result<ShiftedFibonacci, PointSetError> {
            Err(PointSetError::InvalidParameter("no".into()))
        },
        integrand,
    );
    assert_eq!(failing, Err(PointSetError::InvalidParameter("no".into())));
}

#[test]
fn concatenated_replications_match_the_estimate() {
    let plan = ReplicationPlan {
        replication_count: 5,
        points_per_replication: 34,
        dimensions: 2,
        base_seed: 3,
    };
    let all = Replications::new(&plan, |seed| {
        Ok(Box::new(ShiftedFibonacci::new(seed)) as Box<dyn PointSet>)
    })
    .unwrap();
    assert_eq!(all.len(), Some(170));
    assert_eq!(all.replication_count(), 5);
    assert_eq!(all.points_per_replication(), 34);
    let mut point = [0.0; 2];
    let means: Vec<f64> = (0..5u64)
        .map(|j| {
            (0..34u64)
                .map(|i| {
                    all.point(j * 34 + i, &mut point);
                    integrand(&point)
                })
                .sum::<f64>()
                / 34.0
        })
        .collect();
    let direct =
        estimate_integral(&plan, |seed| Ok(ShiftedFibonacci::new(seed)), integrand).unwrap();
    assert_eq!(RqmcEstimate::from_replication_means(means).unwrap(), direct);
    assert_eq!(
        all.replication(2).unwrap().sample(7, 1),
        ShiftedFibonacci::new(replication_seed(3, 2)).sample(7, 1)
    );
    assert!(all.replication(5).is_none());
}
