//! Randomized quasi-Monte Carlo integration by independent replications.
//!
//! A deterministic QMC point set gives no error estimate. Randomizing it `r`
//! times independently (Owen 1998; Kollig and Keller 2002, Sect. 4) turns each
//! replication's average into an unbiased estimate of the integral, and the
//! spread of the `r` averages into an unbiased estimate of the error variance:
//!
//! - mean, Kollig–Keller Eq. (5): `Î = (1/r) Σ_j μ_j` with
//!   `μ_j = (1/m) Σ_i f(x_{i,j})`, `n = r·m` samples in all;
//! - variance of that mean, Eq. (6): `σ̂² = 1/(r(r−1)) Σ_k (μ_k − Î)²`.
//!
//! Both are only valid when the randomization makes **every point of a
//! replication uniformly distributed on the unit cube** (then `E[μ_j] = ∫ f`)
//! and **the `r` replications independent of each other** (then Eq. (6) is
//! unbiased). Cranley–Patterson rotations, random digital shifts and Owen
//! scrambling of one base point set, each with its own seed, qualify; the
//! points *within* a replication need not be independent (that is the point of
//! QMC). Replication `j` is built from the seed [`replication_seed`]`(base_seed, j)`,
//! so results depend only on the base seed.

use crate::hash::hash2;
use crate::point_set::{PointSet, PointSetError, check_request};

/// The seed of replication `replication` of a randomized estimate with
/// `base_seed`: a hash of both, so replications are independent and
/// reproducible.
pub fn replication_seed(base_seed: u64, replication: u64) -> u64 {
    hash2(base_seed, replication)
}

/// How many replications, of how many points, in how many dimensions, from
/// which base seed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ReplicationPlan {
    /// Number `r ≥ 1` of independent replications; `r ≥ 2` for a variance estimate.
    pub replication_count: usize,
    /// Number `m ≥ 1` of points used from each replication (indices `0..m`).
    pub points_per_replication: u64,
    /// Number of coordinates passed to the integrand (`≥ 1`).
    pub dimensions: usize,
    /// Seed from which every replication's seed is hashed.
    pub base_seed: u64,
}

impl ReplicationPlan {
    /// Checks that every count is at least one.
    pub fn validate(&self) -> Result<(), PointSetError> {
        if self.replication_count == 0 {
            return Err(PointSetError::InvalidParameter(
                "replication_count must be at least 1".into(),
            ));
        }
        if self.points_per_replication == 0 {
            return Err(PointSetError::InvalidParameter(
                "points_per_replication must be at least 1".into(),
            ));
        }
        if self.dimensions == 0 {
            return Err(PointSetError::InvalidParameter(
                "dimensions must be at least 1".into(),
            ));
        }
        Ok(())
    }
}

/// A randomized QMC estimate of an integral over the unit cube.
#[derive(Debug, Clone, PartialEq)]
pub struct RqmcEstimate {
    /// The estimate of the integral, Kollig–Keller Eq. (5).
    pub mean: f64,
    /// Unbiased estimate of the variance of `mean`, Eq. (6); `None` for a
    /// single replication, where it is undefined.
    pub variance_of_mean: Option<f64>,
    /// Square root of `variance_of_mean`.
    pub standard_error: Option<f64>,
    /// The average `μ_j` of the integrand over each replication, in order.
    pub replication_means: Vec<f64>,
}

impl RqmcEstimate {
    /// Combines per-replication averages (for callers that evaluate the
    /// replications themselves, e.g. a renderer accumulating per pixel) by
    /// Eqs. (5) and (6). Errors if `replication_means` is empty.
    pub fn from_replication_means(replication_means: Vec<f64>) -> Result<Self, PointSetError> {
        let count = replication_means.len();
        if count == 0 {
            return Err(PointSetError::InvalidParameter(
                "an estimate needs at least one replication".into(),
            ));
        }
        let mean = replication_means.iter().sum::<f64>() / count as f64;
        let variance_of_mean = (count >= 2).then(|| {
            let squared_deviations: f64 = replication_means
                .iter()
                .map(|value| (value - mean) * (value - mean))
                .sum();
            squared_deviations / (count as f64 * (count - 1) as f64)
        });
        Ok(Self {
            mean,
            variance_of_mean,
            standard_error: variance_of_mean.map(f64::sqrt),
            replication_means,
        })
    }
}

/// Estimates `∫_{[0,1)^s} integrand` with `plan.replication_count` independent
/// randomized replications of a point set.
///
/// `make_replication(seed)` builds replication `j` from
/// `seed = replication_seed(plan.base_seed, j)`; it must randomize so that each
/// point is uniform on the cube and different seeds give independent
/// replications (see the module documentation). Points `0..m` of each
/// replication are passed to `integrand` as slices of `plan.dimensions`
/// coordinates.
///
/// Errors if the plan is invalid, the factory fails, or a replication has
/// fewer than `m` points or `s` dimensions.
pub fn estimate_integral<S, MakeReplication, Integrand>(
    plan: &ReplicationPlan,
    mut make_replication: MakeReplication,
    mut integrand: Integrand,
) -> Result<RqmcEstimate, PointSetError>
where
    S: PointSet,
    MakeReplication: FnMut(u64) -> Result<S, PointSetError>,
    Integrand: FnMut(&[f64]) -> f64,
{
    plan.validate()?;
    let mut point = vec![0.0; plan.dimensions];
    let mut replication_means = Vec::with_capacity(plan.replication_count);
    for replication in 0..plan.replication_count as u64 {
        let set = make_replication(replication_seed(plan.base_seed, replication))?;
        check_request(&set, 0, plan.points_per_replication, plan.dimensions)?;
        let mut sum = 0.0;
        for index in 0..plan.points_per_replication {
            set.point(index, &mut point);
            sum += integrand(&point);
        }
        replication_means.push(sum / plan.points_per_replication as f64);
    }
    RqmcEstimate::from_replication_means(replication_means)
}

/// All replications of a plan as one finite point set of `r·m` points:
/// point `j·m + i` is point `i` of replication `j`.
///
/// Useful when a consumer (a renderer) draws points by a single index but
/// still needs to group them by replication for Eq. (6): the replication of
/// index `k` is `k / m`.
pub struct Replications {
    replications: Vec<Box<dyn PointSet>>,
    points_per_replication: u64,
    dimensions: usize,
}

impl Replications {
    /// Builds the `plan.replication_count` replications with
    /// `make_replication(replication_seed(plan.base_seed, j))`.
    ///
    /// Errors if the plan is invalid, the factory fails, a replication has too
    /// few points or dimensions, or `r·m` overflows `u64`.
    pub fn new<MakeReplication>(
        plan: &ReplicationPlan,
        mut make_replication: MakeReplication,
    ) -> Result<Self, PointSetError>
    where
        MakeReplication: FnMut(u64) -> Result<Box<dyn PointSet>, PointSetError>,
    {
        plan.validate()?;
        (plan.replication_count as u64)
            .checked_mul(plan.points_per_replication)
            .ok_or_else(|| {
                PointSetError::InvalidParameter("replications × points overflows u64".into())
            })?;
        let replications = (0..plan.replication_count as u64)
            .map(|replication| {
                let set = make_replication(replication_seed(plan.base_seed, replication))?;
                check_request(&*set, 0, plan.points_per_replication, plan.dimensions)?;
                Ok(set)
            })
            .collect::<Result<Vec<_>, PointSetError>>()?;
        Ok(Self {
            replications,
            points_per_replication: plan.points_per_replication,
            dimensions: plan.dimensions,
        })
    }

    /// Number of replications `r`.
    pub fn replication_count(&self) -> usize {
        self.replications.len()
    }

    /// Points per replication `m`.
    pub fn points_per_replication(&self) -> u64 {
        self.points_per_replication
    }

    /// Replication `replication` (`< r`) as its own point set.
    pub fn replication(&self, replication: usize) -> Option<&dyn PointSet> {
        self.replications.get(replication).map(|set| &**set)
    }
}

impl PointSet for Replications {
    fn dimensions(&self) -> usize {
        self.dimensions
    }

    fn len(&self) -> Option<u64> {
        Some(self.replications.len() as u64 * self.points_per_replication)
    }

    fn sample(&self, index: u64, dimension: usize) -> f64 {
        let replication = (index / self.points_per_replication) as usize;
        self.replications[replication].sample(index % self.points_per_replication, dimension)
    }

    fn point(&self, index: u64, out: &mut [f64]) {
        let replication = (index / self.points_per_replication) as usize;
        self.replications[replication].point(index % self.points_per_replication, out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn equations_five_and_six_on_known_means() {
        let estimate = RqmcEstimate::from_replication_means(vec![1.0, 2.0, 3.0, 6.0]).unwrap();
        assert_eq!(estimate.mean, 3.0);
        // Squared deviations 4 + 1 + 0 + 9 = 14, divided by r(r−1) = 12.
        assert!((estimate.variance_of_mean.unwrap() - 14.0 / 12.0).abs() < 1e-15);
        assert!((estimate.standard_error.unwrap() - (14.0f64 / 12.0).sqrt()).abs() < 1e-15);
    }

    #[test]
    fn single_replication_has_no_variance() {
        let estimate = RqmcEstimate::from_replication_means(vec![0.25]).unwrap();
        assert_eq!(estimate.mean, 0.25);
        assert_eq!(estimate.variance_of_mean, None);
        assert_eq!(estimate.standard_error, None);
        assert!(RqmcEstimate::from_replication_means(vec![]).is_err());
    }

    #[test]
    fn replication_seeds_differ() {
        assert_ne!(replication_seed(1, 0), replication_seed(1, 1));
        assert_ne!(replication_seed(1, 0), replication_seed(2, 0));
    }
}
