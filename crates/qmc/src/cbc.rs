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
//! - [`fast_cbc_power_of_two`] for `N = 2^k` (Nuyens & Cools 2006, "Fast
//!   component-by-component construction of rank-1 lattice rules with a
//!   non-prime number of points"): the units are `±5^j`, and splitting the sample
//!   indices by their 2-adic valuation gives one circulant (an FFT convolution
//!   over the powers of 5) per block, `O(N log N)` in all.
//! - [`plain_cbc`] for any `N`: every unit candidate (`gcd(z, N) = 1`, and only
//!   `z ≤ N/2` by the same symmetry) is evaluated directly, `O(N²)` per dimension.
//!
//! Ties between candidates are common (`z` and `N − z`, or generators related by
//! a unit multiplier and a permutation of dimensions). Both implementations
//! resolve them the same deterministic way: among candidates whose error is
//! within a relative [`TIE_TOLERANCE`] of the minimum, the smallest `z` wins.
//! The fast constructions shortlist candidates by their FFT estimates and
//! re-evaluate the shortlist by direct summation, so FFT rounding never decides
//! a tie and they choose and report exactly as [`plain_cbc`] does.
//!
//! Numerics: `e²` is tiny next to the `1 + …` products it is the mean of (about
//! `10^−10` at `N = 2^16`), so all evaluations carry `Π (1 + γ_j ω_j) − 1` (the
//! "excess") and build `e²` up dimension by dimension, never subtracting 1 from
//! `1 + e²`.

use std::f64::consts::PI;
use std::sync::Arc;

use rustfft::FftPlanner;
use rustfft::num_complex::Complex;

use crate::lattice::Rank1Lattice;
use crate::point_set::PointSetError;
use crate::summation::NeumaierSum;

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
/// `e²` is far smaller than the `1 + …` terms it is the mean of (about `N^−2`
/// for one dimension), so summing `Π_j (1 + γ_j ω_j)` and subtracting 1 would
/// lose most digits. Instead `Π_j (1 + a_j) − 1 = Σ_j a_j + r` is split: the
/// linear part sums in closed form, `Σ_k ω({k z / N}) = g² π² / (3N)` with
/// `g = gcd(z, N)` (the sum of `B₂` over `N/g` equidistant points, repeated `g`
/// times), and only the higher-order remainder `r` is summed numerically.
///
/// Returns NaN if `point_count` is 0 or fewer weights than components are given.
pub fn squared_worst_case_error(point_count: u64, generator: &[u64], weights: &[f64]) -> f64 {
    if point_count == 0 || weights.len() < generator.len() {
        return f64::NAN;
    }
    let inverse_count = 1.0 / point_count as f64;
    let linear: f64 = generator
        .iter()
        .zip(weights)
        .map(|(component, weight)| {
            let common = greatest_common_divisor(component % point_count, point_count) as f64;
            weight * common * common * unit_kernel_sum(point_count)
        })
        .sum();
    let mut remainder_sum = NeumaierSum::default();
    for index in 0..point_count {
        // excess = Π (1 + a_j) − 1, remainder = excess − Σ a_j, both built up
        // without cancellation.
        let mut excess = 0.0;
        let mut remainder = 0.0;
        for (component, weight) in generator.iter().zip(weights) {
            let residue = (u128::from(index) * u128::from(*component)) % u128::from(point_count);
            let term = weight * korobov_kernel(residue as f64 * inverse_count);
            remainder += term * excess;
            excess += term * (1.0 + excess);
        }
        remainder_sum.add(remainder);
    }
    (linear + remainder_sum.total()) * inverse_count
}

/// `Σ_{k=0}^{N−1} ω({k z / N})` for a unit `z` (`gcd(z, N) = 1`): the residues
/// `k z mod N` run through `0..N`, and `Σ_k B₂(k/N) = B₂(0) / N = 1/(6N)`, so the
/// sum is `2π² / (6N) = π² / (3N)`.
fn unit_kernel_sum(point_count: u64) -> f64 {
    PI * PI / (3.0 * point_count as f64)
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

/// Largest number of FFT-shortlisted candidates the fast constructions
/// re-evaluate directly per dimension (`O(N)` each); genuine ties come in small
/// groups (`z` and its images under the lattice's symmetries), so 32 is ample.
const MAX_REFINED_CANDIDATES: usize = 32;

/// Factor by which the shortlist window of the fast constructions exceeds the
/// typical rounding error of an FFT convolution, `ε log2(L) ‖x‖₂ ‖c‖₂ / √L`
/// (measured errors are about 0.6 times that).
const FFT_ERROR_SAFETY: f64 = 16.0;

/// The tie rule for FFT-estimated errors. Every candidate whose estimate is within
/// twice (`estimate_uncertainty` + the tie tolerance) of the smallest estimate is
/// re-evaluated with `evaluate` (direct summation, at most
/// [`MAX_REFINED_CANDIDATES`], best estimates first), and [`choose_candidate`]
/// picks among those. The FFT's rounding (relative `10^−11` of `e²` at `N = 2^16`
/// in two dimensions, larger than [`TIE_TOLERANCE`]) then cannot decide ties, and
/// the fast constructions choose and report exactly as [`plain_cbc`] does.
fn choose_refined(
    estimates: impl Iterator<Item = (u64, f64)>,
    estimate_uncertainty: f64,
    evaluate: impl Fn(u64) -> f64,
) -> (u64, f64) {
    let mut shortlist: Vec<(u64, f64)> = estimates.collect();
    let minimum = shortlist
        .iter()
        .map(|(_, error)| *error)
        .fold(f64::INFINITY, f64::min);
    let threshold = minimum + 2.0 * (estimate_uncertainty + TIE_TOLERANCE * minimum.abs());
    shortlist.retain(|(_, error)| *error <= threshold);
    shortlist.sort_by(|left, right| left.1.total_cmp(&right.1).then(left.0.cmp(&right.0)));
    shortlist.truncate(MAX_REFINED_CANDIDATES);
    choose_candidate(
        shortlist
            .into_iter()
            .map(|(candidate, _)| (candidate, evaluate(candidate))),
    )
}

/// Typical absolute rounding error of a length-`length` circular convolution by
/// FFT of vectors with Euclidean norms `input_norm` and `kernel_norm`.
fn convolution_rounding(length: usize, input_norm: f64, kernel_norm: f64) -> f64 {
    let levels = (length.max(2) as f64).log2();
    f64::EPSILON * levels * input_norm * kernel_norm / (length as f64).sqrt()
}

/// `Σ_k excess[k] ω({k z / N})` by direct summation in `O(N)`, in one fixed
/// order, so every construction gets bit-identical sums for equal inputs.
/// `kernel_value(r)` is `ω(r / N)`; `candidate < N`.
fn direct_excess_kernel_sum(
    excess: &[f64],
    candidate: u64,
    kernel_value: impl Fn(usize) -> f64,
) -> f64 {
    let count = excess.len();
    let step = candidate as usize;
    let mut sum = NeumaierSum::default();
    let mut residue = 0usize;
    for value in excess {
        sum.add(value * kernel_value(residue));
        residue += step;
        if residue >= count {
            residue -= count;
        }
    }
    sum.total()
}

/// `e²` after adding a dimension with weight `γ` and candidate `z`, from the
/// previous `e²`: with `excess[k] = Π_{earlier j} (1 + γ_j ω_j(k)) − 1`,
/// `e²_new = (1/N) Σ_k (1 + excess[k]) (1 + γ ω({k z / N})) − 1
///         = e²_previous + (γ/N) (Σ_k ω({k z / N}) + Σ_k excess[k] ω({k z / N}))`,
/// and the first inner sum is `π²/(3N)` for every unit `z`. Working with the
/// excess instead of the products avoids subtracting 1 from `1 + e²`, which
/// would cost about `−log10(e²)` of the 16 digits (e² is `10^−10` at `N = 2^16`).
#[inline]
fn error_with_candidate(
    previous_error: f64,
    weight: f64,
    kernel_sum: f64,
    excess_kernel_sum: f64,
    inverse_count: f64,
) -> f64 {
    previous_error + weight * (kernel_sum + excess_kernel_sum) * inverse_count
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
    let kernel_sum = unit_kernel_sum(point_count);
    // excess[k] = Π over chosen dimensions of (1 + γ_j ω(k z_j mod N / N)) − 1.
    let mut excess = vec![0.0; count];
    let mut generator = Vec::with_capacity(dimensions);
    let mut squared_errors = Vec::with_capacity(dimensions);
    let mut previous_error = 0.0;
    let units: Vec<u64> = (1..=point_count / 2)
        .filter(|candidate| greatest_common_divisor(*candidate, point_count) == 1)
        .collect();
    for dimension in 0..dimensions {
        let weight = weights.weight(dimension);
        // See `error_with_candidate`: e² = e²_previous + γ (π²/(3N) + Σ_k excess[k] ω) / N.
        let evaluate = |candidate: u64| {
            let sum = direct_excess_kernel_sum(&excess, candidate, |residue| kernel[residue]);
            error_with_candidate(previous_error, weight, kernel_sum, sum, inverse_count)
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
        include_component(&mut excess, &kernel, weight, chosen);
        previous_error = error;
        generator.push(chosen);
        squared_errors.push(error);
    }
    Ok(CbcLattice {
        lattice: Rank1Lattice::new(point_count, generator)?,
        squared_errors,
    })
}

/// Fast CBC for a prime `N ≥ 3` (Nuyens & Cools 2006): per dimension one
/// half-length circular convolution by FFT, `O(N log N)`. Powers of two
/// `N = 2^k`, `2 ≤ k ≤ 32`, are handed to [`fast_cbc_power_of_two`]; any other
/// `N` is an error (use [`cbc`] or [`plain_cbc`]). Deterministic ties as
/// described in the module documentation, so it picks the same generator as
/// [`plain_cbc`] unless two candidates differ by less than the FFT's rounding.
pub fn fast_cbc(
    point_count: u64,
    dimensions: usize,
    weights: &ProductWeights,
) -> Result<CbcLattice, PointSetError> {
    validate_construction(point_count, dimensions, weights)?;
    if point_count >= 4 && point_count.is_power_of_two() {
        return fast_cbc_power_of_two(point_count, dimensions, weights);
    }
    if point_count < 3 || !is_prime(point_count) {
        return Err(PointSetError::InvalidParameter(format!(
            "fast CBC needs an odd prime or a power of two (at least 4) number of points, \
             got {point_count}"
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
    let kernel_norm = euclidean_norm(&kernel_spectrum);
    forward.process(&mut kernel_spectrum);

    let kernel_sum = unit_kernel_sum(point_count);
    // excess[k] = Π over chosen dimensions of (1 + γ_j ω(k z_j mod N / N)) − 1.
    let mut excess = vec![0.0; count];
    let mut generator = Vec::with_capacity(dimensions);
    let mut squared_errors = Vec::with_capacity(dimensions);
    let mut previous_error = 0.0;
    let mut buffer = vec![Complex::new(0.0, 0.0); half];
    for dimension in 0..dimensions {
        let weight = weights.weight(dimension);
        let (chosen, error) = if dimension == 0 {
            // All excesses are 0: the same arithmetic as plain CBC's z = 1.
            let error =
                error_with_candidate(previous_error, weight, kernel_sum, 0.0, inverse_count);
            (1, error)
        } else {
            // Σ_k excess[k] ω(k z / N) = excess[0] ω(0) + Σ_{k≠0} excess[k] ω(k z / N).
            // With z = g^b and k = g^(-a): k z = g^(b-a), a cyclic convolution over the
            // units. excess[k] = excess[N-k] and g^half = -1, so fold to length `half`.
            for (a, slot) in buffer.iter_mut().enumerate() {
                // k = g^(-a) = g^((N-1-a) mod (N-1)); x[k] + x[-k] = 2 x[k].
                let exponent = (count - 1 - a) % (count - 1);
                *slot = Complex::new(2.0 * excess[powers[exponent] as usize], 0.0);
            }
            let input_norm = euclidean_norm(&buffer);
            forward.process(&mut buffer);
            for (value, spectrum) in buffer.iter_mut().zip(&kernel_spectrum) {
                *value *= spectrum;
            }
            inverse.process(&mut buffer);
            let normalisation = 1.0 / half as f64;
            let constant = excess[0] * kernel[0];
            let estimates = (0..half).map(|b| {
                // z = g^b and N - z = g^(b+half) give the same error: report the smaller.
                let candidate = powers[b].min(point_count - powers[b]);
                let convolution = buffer[b].re * normalisation;
                let sum = constant + convolution;
                (
                    candidate,
                    error_with_candidate(previous_error, weight, kernel_sum, sum, inverse_count),
                )
            });
            let uncertainty = FFT_ERROR_SAFETY
                * weight
                * inverse_count
                * convolution_rounding(half, input_norm, kernel_norm);
            choose_refined(estimates, uncertainty, |candidate| {
                let sum = direct_excess_kernel_sum(&excess, candidate, |residue| kernel[residue]);
                error_with_candidate(previous_error, weight, kernel_sum, sum, inverse_count)
            })
        };
        include_component(&mut excess, &kernel, weight, chosen);
        previous_error = error;
        generator.push(chosen);
        squared_errors.push(error);
    }
    Ok(CbcLattice {
        lattice: Rank1Lattice::new(point_count, generator)?,
        squared_errors,
    })
}

/// Multiplies the chosen component into the running products: with
/// `excess[k] = Π_j (1 + γ_j ω({k z_j / N})) − 1` over the components so far,
/// the new component `z` (weight `γ`) makes it
/// `excess[k] + γ ω({k z / N}) (1 + excess[k])`, where `kernel[r] = ω(r / N)`.
fn include_component(excess: &mut [f64], kernel: &[f64], weight: f64, chosen: u64) {
    let count = excess.len();
    let mut residue = 0usize;
    for value in excess.iter_mut() {
        *value += weight * kernel[residue] * (1.0 + *value);
        residue += chosen as usize;
        if residue >= count {
            residue -= count;
        }
    }
}

/// CBC with the fastest applicable algorithm: [`fast_cbc`] for odd prime `N`,
/// [`fast_cbc_power_of_two`] for `N = 2^k` with `k ≥ 2`, [`plain_cbc`] otherwise.
pub fn cbc(
    point_count: u64,
    dimensions: usize,
    weights: &ProductWeights,
) -> Result<CbcLattice, PointSetError> {
    if point_count >= 4 && point_count.is_power_of_two() {
        fast_cbc_power_of_two(point_count, dimensions, weights)
    } else if point_count >= 3 && is_prime(point_count) {
        fast_cbc(point_count, dimensions, weights)
    } else {
        plain_cbc(point_count, dimensions, weights)
    }
}

/// One block of [`fast_cbc_power_of_two`]: the sample indices `k = 2^shift · u`
/// with `u` odd, i.e. a unit modulo `M = N / 2^shift` (`M ≥ 8`).
///
/// The units modulo `M` are `±5^a mod M`, `0 ≤ a < M/4` (5 has order `M/4`
/// modulo `2^j`, `j ≥ 3`; Gauss, Disquisitiones Arithmeticae §90). For a
/// candidate `z = 5^b mod N`, `{k z / N} = {u z / M}`, and by the symmetry
/// `ω(x) = ω(1 − x)` (and `p[k] = p[N − k]`) the block's part of the sum is
/// `Σ_a 2 p[2^shift · (5^a mod M)] · ω((5^(a+b) mod M) / M)`: a circulant of
/// length `M/4` in the exponents, done as one cyclic convolution by FFT.
struct PowerOfTwoBlock {
    /// `log2(N / M)`: the 2-adic valuation of the block's sample indices.
    shift: u32,
    /// `M / 4`, the circulant's length (a power of two, at least 2).
    length: usize,
    forward: Arc<dyn rustfft::Fft<f64>>,
    inverse: Arc<dyn rustfft::Fft<f64>>,
    /// FFT of `c[t] = ω((5^t mod M) / M)`, `t = 0..M/4`.
    kernel_spectrum: Vec<Complex<f64>>,
    /// `‖c‖₂`, for the rounding estimate.
    kernel_norm: f64,
}

/// Fast CBC for `N = 2^k`, `2 ≤ k ≤ 32` (Nuyens & Cools 2006, "Fast
/// component-by-component construction of rank-1 lattice rules with a non-prime
/// number of points", J. Complexity 22): `O(N log N)` work per dimension.
///
/// The candidates are the units `z = ±5^b mod N`; `z` and `N − z` give the same
/// error, so only `z = 5^b`, `0 ≤ b < N/4`, are evaluated and each is reported
/// as `min(z, N − z)` for the tie rule. The sample indices `k ≠ 0` are split by
/// their 2-adic valuation into blocks (see [`PowerOfTwoBlock`]), each a cyclic
/// convolution over the powers of 5; the blocks with `N / 2^m ≤ 4` (indices
/// `N/4`, `N/2`, `3N/4`) and `k = 0` do not depend on `z` and are summed
/// directly. `N = 4` (where the only candidate is 1) goes to [`plain_cbc`].
/// Ties as described in the module documentation.
pub fn fast_cbc_power_of_two(
    point_count: u64,
    dimensions: usize,
    weights: &ProductWeights,
) -> Result<CbcLattice, PointSetError> {
    validate_construction(point_count, dimensions, weights)?;
    if point_count < 4 || !point_count.is_power_of_two() {
        return Err(PointSetError::InvalidParameter(format!(
            "power-of-two fast CBC needs N = 2^k with 2 ≤ k ≤ 32, got {point_count}"
        )));
    }
    if point_count <= 4 {
        return plain_cbc(point_count, dimensions, weights);
    }
    let count = point_count as usize;
    let mask = point_count - 1;
    let log2_count = point_count.trailing_zeros();
    let quarter = count / 4;
    let inverse_count = 1.0 / point_count as f64;
    // powers[t] = 5^t mod N, t = 0..N/4 (fits in u32 since N ≤ 2^32).
    let mut powers = Vec::with_capacity(quarter);
    let mut power = 1u64;
    for _ in 0..quarter {
        powers.push(power as u32);
        power = (power * 5) & mask;
    }
    // Blocks from the smallest (M = 8) to the largest (M = N), so the running
    // sum over blocks can be extended periodically as the lengths double.
    let mut planner = FftPlanner::<f64>::new();
    let blocks: Vec<PowerOfTwoBlock> = (0..=log2_count - 3)
        .rev()
        .map(|shift| {
            let modulus = point_count >> shift;
            let length = (modulus / 4) as usize;
            let block_mask = modulus - 1;
            let forward = planner.plan_fft_forward(length);
            let inverse = planner.plan_fft_inverse(length);
            let modulus_inverse = 1.0 / modulus as f64;
            let mut kernel_spectrum: Vec<Complex<f64>> = powers[..length]
                .iter()
                .map(|power| {
                    let residue = u64::from(*power) & block_mask;
                    Complex::new(korobov_kernel(residue as f64 * modulus_inverse), 0.0)
                })
                .collect();
            let kernel_norm = euclidean_norm(&kernel_spectrum);
            forward.process(&mut kernel_spectrum);
            PowerOfTwoBlock {
                shift,
                length,
                forward,
                inverse,
                kernel_spectrum,
                kernel_norm,
            }
        })
        .collect();

    let kernel_sum = unit_kernel_sum(point_count);
    // excess[k] = Π over chosen dimensions of (1 + γ_j ω(k z_j mod N / N)) − 1.
    let mut excess = vec![0.0; count];
    let mut generator = Vec::with_capacity(dimensions);
    let mut squared_errors = Vec::with_capacity(dimensions);
    let mut previous_error = 0.0;
    let mut buffer = vec![Complex::new(0.0, 0.0); quarter];
    let mut block_sums: Vec<f64> = Vec::with_capacity(quarter);
    for dimension in 0..dimensions {
        let weight = weights.weight(dimension);
        let (chosen, error) = if dimension == 0 {
            // All excesses are 0: the same arithmetic as plain CBC's z = 1.
            let error =
                error_with_candidate(previous_error, weight, kernel_sum, 0.0, inverse_count);
            (1, error)
        } else {
            // Σ_k excess[k] ω({k z / N}) is a z-independent part (k = 0, N/4, N/2, 3N/4;
            // excess[N/4] = excess[3N/4] and ω(1/4) = ω(3/4)) plus one convolution per block.
            let constant = excess[0] * korobov_kernel(0.0)
                + excess[count / 2] * korobov_kernel(0.5)
                + 2.0 * excess[count / 4] * korobov_kernel(0.25);
            block_sums.clear();
            block_sums.push(constant);
            let mut rounding = 0.0;
            for block in &blocks {
                let block_mask = (point_count >> block.shift) - 1;
                let length = block.length;
                let values = &mut buffer[..length];
                for (t, slot) in values.iter_mut().enumerate() {
                    // k = 2^shift · (5^(−t) mod M); the factor 2 folds in k' = N − k.
                    let exponent = (length - t) & (length - 1);
                    let unit = u64::from(powers[exponent]) & block_mask;
                    let k = (unit << block.shift) as usize;
                    *slot = Complex::new(2.0 * excess[k], 0.0);
                }
                rounding += convolution_rounding(length, euclidean_norm(values), block.kernel_norm);
                block.forward.process(values);
                for (value, spectrum) in values.iter_mut().zip(&block.kernel_spectrum) {
                    *value *= spectrum;
                }
                block.inverse.process(values);
                // The smaller blocks have periods dividing `length`: repeat them.
                while block_sums.len() < length {
                    block_sums.extend_from_within(..);
                }
                let normalisation = 1.0 / length as f64;
                for (sum, value) in block_sums.iter_mut().zip(values.iter()) {
                    *sum += value.re * normalisation;
                }
            }
            let estimates = powers.iter().zip(&block_sums).map(|(power, sum)| {
                // z = 5^b and N − z = −5^b give the same error: report the smaller.
                let power = u64::from(*power);
                let candidate = power.min(point_count - power);
                (
                    candidate,
                    error_with_candidate(previous_error, weight, kernel_sum, *sum, inverse_count),
                )
            });
            let uncertainty = FFT_ERROR_SAFETY * weight * inverse_count * rounding;
            choose_refined(estimates, uncertainty, |candidate| {
                let sum = direct_excess_kernel_sum(&excess, candidate, |residue| {
                    korobov_kernel(residue as f64 * inverse_count)
                });
                error_with_candidate(previous_error, weight, kernel_sum, sum, inverse_count)
            })
        };
        let mut residue = 0u64;
        for value in excess.iter_mut() {
            *value += weight * korobov_kernel(residue as f64 * inverse_count) * (1.0 + *value);
            residue = (residue + chosen) & mask;
        }
        previous_error = error;
        generator.push(chosen);
        squared_errors.push(error);
    }
    Ok(CbcLattice {
        lattice: Rank1Lattice::new(point_count, generator)?,
        squared_errors,
    })
}

/// Euclidean norm of a complex vector.
fn euclidean_norm(values: &[Complex<f64>]) -> f64 {
    values
        .iter()
        .map(|value| value.norm_sqr())
        .sum::<f64>()
        .sqrt()
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
        assert!(fast_cbc(12, 2, &weights).is_err());
        assert!(fast_cbc(8, 2, &weights).is_ok());
        assert!(fast_cbc(2, 2, &weights).is_err());
        assert!(plain_cbc(1, 2, &weights).is_err());
        assert!(plain_cbc(7, 0, &weights).is_err());
        assert!(cbc(7, 2, &ProductWeights::Constant(-1.0)).is_err());
        assert!(cbc(7, 3, &ProductWeights::PerDimension(vec![1.0, 1.0])).is_err());
        assert!(cbc(7, 2, &ProductWeights::Constant(f64::NAN)).is_err());
        assert!(cbc(2, 3, &weights).is_ok());
    }
}
