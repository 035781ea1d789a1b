//! Component-by-component (CBC) construction of rank-1 lattice generators.
//!
//! The quality measure is the squared worst-case error of the lattice rule in the
//! weighted Korobov space with smoothness α = 2 and product weights `γ_j`
//! (the figure of merit P₂):
//!
//! `e²(z) = −1 + (1/N) Σ_{k=0}^{N−1} Π_j (1 + γ_j ω({k z_j / N}))`,
//! with `ω(x) = 2π² (x² − x + 1/6)`.
//!
//! CBC fixes `z₁ = 1` and picks each further component to minimise `e²` with the
//! earlier components fixed (Sloan & Reztsov 2002; Kuo 2003 shows it reaches the
//! optimal convergence order). Two implementations:
//! - [`fast_cbc`] for prime `N` (Nuyens & Cools 2006, "Fast algorithms for
//!   component-by-component construction of rank-1 lattice rules in shift-invariant
//!   reproducing kernel Hilbert spaces"): ordering candidates and sample indices by
//!   powers of a primitive root makes the matrix `ω(k z / N)` circulant, so one
//!   dimension costs one FFT convolution, `O(N log N)`. As `ω(x) = ω(1 − x)` and
//!   `g^((N−1)/2) ≡ −1`, the circulant has period `(N−1)/2`, so only half the
//!   candidates (and a half-length convolution) are needed.
//! - [`plain_cbc`] for any `N`: every unit candidate (`gcd(z, N) = 1`, and only
//!   `z ≤ N/2` by the same symmetry) is evaluated directly, `O(N²)` per dimension.
//!
//! Ties between candidates are common (`z` and `N − z`, or generators related by
//! a unit multiplier and a permutation of dimensions). Both implementations
//! resolve them the same deterministic way: among candidates whose error is
//! within a relative [`TIE_TOLERANCE`] of the minimum, the smallest `z` wins.

use std::f64::consts::PI;
use std::sync::Arc;

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

use crate::lattice::Rank1Lattice;
use crate::point_set::PointSetError;

/// Relative tolerance within which two candidate errors count as a tie (the FFT
/// evaluates errors to about `1e-15` relative; genuine differences are far larger).
pub const TIE_TOLERANCE: f64 = 1e-11;

/// Largest `N` accepted by the CBC constructions (memory `O(N)`, time at least
/// `O(s N log N)`): `2^32`.
pub const MAX_CBC_POINTS: u64 = 1 << 32;

/// The Korobov-space kernel for α = 2, `ω(x) = 2π² (x² − x + 1/6)`, the
/// Bernoulli polynomial `B₂` scaled by `2π²`; `x` in `[0, 1]`.
#[inline]
pub fn korobov_kernel(x: f64) -> f64 {
    2.0 * PI * PI * (x * x - x + 1.0 / 6.0)
}

/// Product weights `γ_j` of the weighted Korobov space: how much dimension `j`
/// matters. Smaller weights let CBC care less about that dimension's projections.
#[derive(Debug, Clone, PartialEq)]
pub enum ProductWeights {
    /// The same weight for every dimension.
    Constant(f64),
    /// One weight per dimension; dimension `j` uses entry `j`.
    PerDimension(Vec<f64>),
}

impl ProductWeights {
    /// The weights the LQMC authors used: `γ_j = 1/s` for an `s`-dimensional
    /// lattice (`s = 0` is treated as 1).
    pub fn lqmc_default(dimensions: usize) -> Self {
        Self::Constant(1.0 / dimensions.max(1) as f64)
    }

    /// Weight of `dimension` (the last given weight repeats past the end of a
    /// per-dimension list; [`ProductWeights::validate`] rejects lists that are
    /// too short for a construction).
    pub fn weight(&self, dimension: usize) -> f64 {
        match self {
            Self::Constant(weight) => *weight,
            Self::PerDimension(weights) => weights[dimension.min(weights.len() - 1)],
        }
    }

    /// Checks that weights exist for `dimensions` dimensions and are finite and
    /// positive.
    pub fn validate(&self, dimensions: usize) -> Result<(), PointSetError> {
        let bad = |weight: f64| !(weight.is_finite() && weight > 0.0);
        match self {
            Self::Constant(weight) if bad(*weight) => Err(PointSetError::InvalidParameter(
                format!("product weight must be finite and positive, got {weight}"),
            )),
            Self::PerDimension(weights) if weights.len() < dimensions => {
                Err(PointSetError::InvalidParameter(format!(
                    "{} product weights given for {dimensions} dimensions",
                    weights.len()
                )))
            }
            Self::PerDimension(weights) => match weights.iter().find(|weight| bad(**weight)) {
                Some(weight) => Err(PointSetError::InvalidParameter(format!(
                    "product weight must be finite and positive, got {weight}"
                ))),
                None => Ok(()),
            },
            Self::Constant(_) => Ok(()),
        }
    }
}

/// The outcome of a CBC construction.
#[derive(Debug, Clone, PartialEq)]
pub struct CbcLattice {
    /// The constructed lattice (its generator starts with 1).
    pub lattice: Rank1Lattice,
    /// `squared_errors[d]` is `e²` of the projection onto the first `d + 1`
    /// dimensions, as evaluated during the construction; the last entry is the
    /// lattice's error.
    pub squared_errors: Vec<f64>,
}

impl CbcLattice {
    /// `e²` of the full lattice.
    pub fn squared_error(&self) -> f64 {
        *self.squared_errors.last().expect("at least one dimension")
    }
}

/// Squared worst-case error `e²(z)` of the rank-1 lattice with `point_count`
/// points and `generator`, in the Korobov space with α = 2 and product weights
/// `weights[j]` (one per generator component; `weights` may be longer), by
/// direct summation in `O(N s)`. Residues are computed exactly in integers.
///
/// Returns NaN if `point_count` is 0 or fewer weights than components are given.
pub fn squared_worst_case_error(point_count: u64, generator: &[u64], weights: &[f64]) -> f64 {
    if point_count == 0 || weights.len() < generator.len() {
        return f64::NAN;
    }
    let inverse_count = 1.0 / point_count as f64;
    let mut sum = 0.0;
    for index in 0..point_count {
        let mut product = 1.0;
        for (component, weight) in generator.iter().zip(weights) {
            let residue = (u128::from(index) * u128::from(*component)) % u128::from(point_count);
            product *= 1.0 + weight * korobov_kernel(residue as f64 * inverse_count);
        }
        sum += product;
    }
    sum * inverse_count - 1.0
}

fn validate_construction(
    point_count: u64,
    dimensions: usize,
    weights: &ProductWeights,
) -> Result<(), PointSetError> {
    if !(2..=MAX_CBC_POINTS).contains(&point_count) {
        return Err(PointSetError::InvalidParameter(format!(
            "CBC construction needs between 2 and 2^32 points, got {point_count}"
        )));
    }
    if dimensions == 0 {
        return Err(PointSetError::InvalidParameter(
            "CBC construction needs at least one dimension".to_string(),
        ));
    }
    weights.validate(dimensions)
}

/// Picks the candidate with the smallest error; ties (within [`TIE_TOLERANCE`])
/// go to the smallest candidate. `candidates` yields `(z, e²)`.
fn choose_candidate(candidates: impl Iterator<Item = (u64, f64)>) -> (u64, f64) {
    let all: Vec<(u64, f64)> = candidates.collect();
    let minimum = all
        .iter()
        .map(|(_, error)| *error)
        .fold(f64::INFINITY, f64::min);
    let threshold = minimum + TIE_TOLERANCE * minimum.abs();
    all.into_iter()
        .filter(|(_, error)| *error <= threshold)
        .min_by_key(|(candidate, _)| *candidate)
        .expect("at least one candidate")
}

/// Kernel values `ω(k / N)` for `k = 0..N`.
fn kernel_table(point_count: u64) -> Vec<f64> {
    let inverse_count = 1.0 / point_count as f64;
    (0..point_count)
        .map(|k| korobov_kernel(k as f64 * inverse_count))
        .collect()
}

/// Plain CBC for any `N ≥ 2`: evaluates every unit candidate `z ≤ N/2`
/// (`gcd(z, N) = 1`) directly, `O(N²)` work per dimension. Deterministic ties
/// as described in the module documentation.
pub fn plain_cbc(
    point_count: u64,
    dimensions: usize,
    weights: &ProductWeights,
) -> Result<CbcLattice, PointSetError> {
    validate_construction(point_count, dimensions, weights)?;
    let count = point_count as usize;
    let kernel = kernel_table(point_count);
    let inverse_count = 1.0 / point_count as f64;
    // products[k] = Π over chosen dimensions of (1 + γ_j ω(k z_j mod N / N)).
    let mut products = vec![1.0; count];
    let mut generator = Vec::with_capacity(dimensions);
    let mut squared_errors = Vec::with_capacity(dimensions);
    let units: Vec<u64> = (1..=point_count / 2)
        .filter(|candidate| greatest_common_divisor(*candidate, point_count) == 1)
        .collect();
    for dimension in 0..dimensions {
        let weight = weights.weight(dimension);
        let evaluate = |candidate: u64| {
            let mut sum = 0.0;
            let mut residue = 0usize;
            for product in &products {
                sum += product * (1.0 + weight * kernel[residue]);
                residue += candidate as usize;
                if residue >= count {
                    residue -= count;
                }
            }
            sum * inverse_count - 1.0
        };
        let (chosen, error) = if dimension == 0 {
            (1, evaluate(1))
        } else {
            choose_candidate(
                units
                    .iter()
                    .map(|candidate| (*candidate, evaluate(*candidate))),
            )
        };
        let mut residue = 0usize;
        for product in products.iter_mut() {
            *product *= 1.0 + weight * kernel[residue];
            residue += chosen as usize;
            if residue >= count {
                residue -= count;
            }
        }
        generator.push(chosen);
        squared_errors.push(error);
    }
    Ok(CbcLattice {
        lattice: Rank1Lattice::new(point_count, generator)?,
        squared_errors,
    })
}

/// Fast CBC for a prime `N ≥ 3` (Nuyens & Cools 2006): per dimension one
/// half-length circular convolution by FFT, `O(N log N)`. Deterministic ties as
/// described in the module documentation, so it picks the same generator as
/// [`plain_cbc`] unless two candidates differ by less than the FFT's rounding.
pub fn fast_cbc(
    point_count: u64,
    dimensions: usize,
    weights: &ProductWeights,
) -> Result<CbcLattice, PointSetError> {
    validate_construction(point_count, dimensions, weights)?;
    if point_count < 3 || !is_prime(point_count) {
        return Err(PointSetError::InvalidParameter(format!(
            "fast CBC needs an odd prime number of points, got {point_count}"
        )));
    }
    let count = point_count as usize;
    let half = (count - 1) / 2;
    let generator_root = primitive_root(point_count)?;
    // powers[m] = g^m mod N for m = 0..N-1 (the candidates in primitive-root order).
    let mut powers = Vec::with_capacity(count - 1);
    let mut power = 1u64;
    for _ in 0..count - 1 {
        powers.push(power);
        power = power * generator_root % point_count;
    }
    let kernel = kernel_table(point_count);
    let inverse_count = 1.0 / point_count as f64;

    // Circulant first column c[m] = ω(g^m / N), m in 0..half (period (N-1)/2).
    let mut planner = FftPlanner::<f64>::new();
    let forward: Arc<dyn rustfft::Fft<f64>> = planner.plan_fft_forward(half);
    let inverse: Arc<dyn rustfft::Fft<f64>> = planner.plan_fft_inverse(half);
    let mut kernel_spectrum: Vec<Complex<f64>> = (0..half)
        .map(|m| Complex::new(kernel[powers[m] as usize], 0.0))
        .collect();
    forward.process(&mut kernel_spectrum);

    let mut products = vec![1.0; count];
    let mut generator = Vec::with_capacity(dimensions);
    let mut squared_errors = Vec::with_capacity(dimensions);
    let mut buffer = vec![Complex::new(0.0, 0.0); half];
    for dimension in 0..dimensions {
        let weight = weights.weight(dimension);
        let (chosen, error) = if dimension == 0 {
            let sum: f64 = products
                .iter()
                .enumerate()
                .map(|(k, product)| product * (1.0 + weight * kernel[k]))
                .sum();
            (1, sum * inverse_count - 1.0)
        } else {
            // Σ_k p[k] (1 + γ ω(k z / N)) = Σ_k p[k] + γ p[0] ω(0) + γ Σ_{k≠0} p[k] ω(k z / N).
            // With z = g^b and k = g^(-a): k z = g^(b-a), a cyclic convolution over the
            // units. p[k] = p[N-k] and g^half = -1, so fold to length `half`.
            let total: f64 = products.iter().sum();
            for (a, slot) in buffer.iter_mut().enumerate() {
                // k = g^(-a) = g^((N-1-a) mod (N-1)); p[k] + p[-k] = 2 p[k].
                let exponent = (count - 1 - a) % (count - 1);
                *slot = Complex::new(2.0 * products[powers[exponent] as usize], 0.0);
            }
            forward.process(&mut buffer);
            for (value, spectrum) in buffer.iter_mut().zip(&kernel_spectrum) {
                *value *= spectrum;
            }
            inverse.process(&mut buffer);
            let normalisation = 1.0 / half as f64;
            let constant = total + weight * products[0] * kernel[0];
            choose_candidate((0..half).map(|b| {
                // z = g^b and N - z = g^(b+half) give the same error: report the smaller.
                let candidate = powers[b].min(point_count - powers[b]);
                let convolution = buffer[b].re * normalisation;
                (
                    candidate,
                    (constant + weight * convolution) * inverse_count - 1.0,
                )
            }))
        };
        let mut residue = 0usize;
        for product in products.iter_mut() {
            *product *= 1.0 + weight * kernel[residue];
            residue += chosen as usize;
            if residue >= count {
                residue -= count;
            }
        }
        generator.push(chosen);
        squared_errors.push(error);
    }
    Ok(CbcLattice {
        lattice: Rank1Lattice::new(point_count, generator)?,
        squared_errors,
    })
}

/// CBC with the fastest applicable algorithm: [`fast_cbc`] for odd prime `N`,
/// [`plain_cbc`] otherwise.
pub fn cbc(
    point_count: u64,
    dimensions: usize,
    weights: &ProductWeights,
) -> Result<CbcLattice, PointSetError> {
    if point_count >= 3 && is_prime(point_count) {
        fast_cbc(point_count, dimensions, weights)
    } else {
        plain_cbc(point_count, dimensions, weights)
    }
}

/// Greatest common divisor (Euclid).
pub fn greatest_common_divisor(mut a: u64, mut b: u64) -> u64 {
    while b != 0 {
        (a, b) = (b, a % b);
    }
    a
}

/// Primality by trial division (enough for the `N ≤ 2^32` of CBC).
pub fn is_prime(number: u64) -> bool {
    if number < 2 {
        return false;
    }
    let mut divisor = 2u64;
    while divisor * divisor <= number {
        if number.is_multiple_of(divisor) {
            return false;
        }
        divisor += 1;
    }
    true
}

/// Distinct prime factors of `number ≥ 1`, ascending.
fn distinct_prime_factors(mut number: u64) -> Vec<u64> {
    let mut factors = Vec::new();
    let mut divisor = 2u64;
    while divisor * divisor <= number {
        if number.is_multiple_of(divisor) {
            factors.push(divisor);
            while number.is_multiple_of(divisor) {
                number /= divisor;
            }
        }
        divisor += 1;
    }
    if number > 1 {
        factors.push(number);
    }
    factors
}

/// `base^exponent mod modulus` by square-and-multiply in 128-bit arithmetic.
pub fn power_modulo(base: u64, mut exponent: u64, modulus: u64) -> u64 {
    let modulus = u128::from(modulus);
    let mut result = 1u128 % modulus;
    let mut base = u128::from(base) % modulus;
    while exponent > 0 {
        if exponent & 1 == 1 {
            result = result * base % modulus;
        }
        base = base * base % modulus;
        exponent >>= 1;
    }
    result as u64
}

/// The smallest primitive root modulo the prime `prime`: the smallest `g` whose
/// powers run through all of `1..prime`. E.g. 7 → 3, 23 → 5, 97 → 5, 313 → 10.
/// Errors if `prime` is not prime or exceeds 2^32.
pub fn primitive_root(prime: u64) -> Result<u64, PointSetError> {
    if prime > MAX_CBC_POINTS || !is_prime(prime) {
        return Err(PointSetError::InvalidParameter(format!(
            "primitive roots are computed for primes up to 2^32, got {prime}"
        )));
    }
    if prime == 2 {
        return Ok(1);
    }
    let order = prime - 1;
    let factors = distinct_prime_factors(order);
    (2..prime)
        .find(|candidate| {
            factors
                .iter()
                .all(|factor| power_modulo(*candidate, order / factor, prime) != 1)
        })
        .ok_or_else(|| PointSetError::InvalidParameter(format!("no primitive root of {prime}")))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn primitive_roots() {
        assert_eq!(primitive_root(7), Ok(3));
        assert_eq!(primitive_root(23), Ok(5));
        assert_eq!(primitive_root(97), Ok(5));
        assert_eq!(primitive_root(313), Ok(10));
        assert_eq!(primitive_root(2), Ok(1));
        assert_eq!(primitive_root(3), Ok(2));
        assert!(primitive_root(9).is_err());
    }

    #[test]
    fn fast_and_plain_agree_per_dimension() {
        for point_count in [3u64, 5, 7, 11, 23, 31, 97, 101, 313] {
            let weights = ProductWeights::Constant(0.3);
            let fast = fast_cbc(point_count, 8, &weights).unwrap();
            let plain = plain_cbc(point_count, 8, &weights).unwrap();
            for (fast_error, plain_error) in fast.squared_errors.iter().zip(&plain.squared_errors) {
                assert!(
                    (fast_error - plain_error).abs() <= 1e-12 * plain_error.abs(),
                    "N = {point_count}: {fast_error} vs {plain_error}"
                );
            }
        }
    }

    #[test]
    fn reported_error_matches_direct_evaluation() {
        let weights = [1.0, 0.5, 0.25, 0.125, 0.0625, 0.03125];
        for point_count in [7u64, 97, 313] {
            let built = fast_cbc(
                point_count,
                6,
                &ProductWeights::PerDimension(weights.to_vec()),
            )
            .unwrap();
            let generator = built.lattice.generator();
            assert_eq!(generator[0], 1);
            for dimension in 1..=6 {
                let direct =
                    squared_worst_case_error(point_count, &generator[..dimension], &weights);
                let reported = built.squared_errors[dimension - 1];
                assert!(
                    (direct - reported).abs() <= 1e-12 * direct,
                    "{direct} vs {reported}"
                );
            }
        }
    }

    #[test]
    fn error_decreases_with_point_count() {
        let weights = ProductWeights::lqmc_default(5);
        let errors: Vec<f64> = [7u64, 23, 97, 313, 1021]
            .iter()
            .map(|n| cbc(*n, 5, &weights).unwrap().squared_error())
            .collect();
        for pair in errors.windows(2) {
            assert!(pair[1] < pair[0], "{errors:?}");
        }
    }

    #[test]
    fn non_prime_uses_units_only() {
        let built = cbc(64, 4, &ProductWeights::Constant(0.5)).unwrap();
        for component in built.lattice.generator() {
            assert_eq!(component % 2, 1);
        }
        let direct = squared_worst_case_error(64, built.lattice.generator(), &[0.5; 4]);
        assert!((direct - built.squared_error()).abs() <= 1e-12 * direct);
    }

    #[test]
    fn one_dimension_has_known_error() {
        // For z = (1), Σ_k ω(k/N)/N = 2π² B₂-sum = π²/(3N²) (the k/N sum of B₂).
        let error = squared_worst_case_error(10, &[1], &[1.0]);
        let expected = 2.0 * PI * PI / (6.0 * 100.0);
        assert!((error - expected).abs() < 1e-12, "{error} vs {expected}");
    }

    #[test]
    fn invalid_input_is_rejected() {
        let weights = ProductWeights::Constant(1.0);
        assert!(fast_cbc(8, 2, &weights).is_err());
        assert!(fast_cbc(2, 2, &weights).is_err());
        assert!(plain_cbc(1, 2, &weights).is_err());
        assert!(plain_cbc(7, 0, &weights).is_err());
        assert!(cbc(7, 2, &ProductWeights::Constant(-1.0)).is_err());
        assert!(cbc(7, 3, &ProductWeights::PerDimension(vec![1.0, 1.0])).is_err());
        assert!(cbc(7, 2, &ProductWeights::Constant(f64::NAN)).is_err());
        assert!(cbc(2, 3, &weights).is_ok());
    }
}
