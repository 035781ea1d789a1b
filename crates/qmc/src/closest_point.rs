//! The closest point of a rank-1 lattice to a given point on the unit torus,
//! and the Cranley–Patterson shift that moves it there.
//!
//! Local QMC exploration (Tessari, Hanika, Dachsbacher, Section 3 and Alg. 1)
//! finds the lattice point `x_{i*}` closest to the seed path's sample `u` in
//! toroidal Euclidean distance (per dimension `min(|d|, 1 − |d|)`), and uses
//! `Δ = (u − x_{i*}) mod 1` as a Cranley–Patterson shift: the shifted lattice
//! `{x_i + Δ}` contains `u` itself as member `i*`. Because the lattice is a group,
//! every member `y_k = x_k + Δ` of the shifted lattice finds the same shift
//! again (its closest lattice point is `x_k`), which the estimator relies on.
//!
//! Three searches, giving the same answer:
//! - [`closest_point_brute_force`]: all `N` points, abandoning a candidate as soon
//!   as its partial squared distance exceeds the best so far (what the authors'
//!   renderer does; fine for `N` in the hundreds);
//! - [`ClosestPointSearch::closest_index_by_projection_scan`]: the points sorted
//!   once by their first coordinate (for `z₁` a unit, the first coordinates are
//!   exactly `0, 1/N, …, (N−1)/N`), visited outwards from the query's first
//!   coordinate in order of increasing first-coordinate distance, stopping as soon
//!   as that one-dimensional distance alone exceeds the best full distance; the
//!   coordinates are precomputed, so a candidate costs a few flops;
//! - [`ClosestPointSearch::closest_index_by_enumeration`]: the lattice
//!   `{i z / N} + Z^s`, scaled by `N`, is the
//!   integer lattice with basis `(z, N e_2, …, N e_s)` when `z₁ = 1`. That basis is
//!   LLL-reduced once (Lenstra, Lenstra, Lovász 1982, δ = 0.99); a query runs a
//!   Schnorr–Euchner / Fincke–Pohst enumeration of the closest vector whose first
//!   leaf is Babai's nearest-plane solution, so the search radius starts at
//!   Babai's distance and shrinks, and the result is exact.
//!
//! [`ClosestPointSearch::closest_index`] uses whichever of the last two does less
//! work on pseudo-random queries (decided once per lattice, by counting, not
//! timing).
//!
//! Determinism: both searches return the minimum of `(squared distance, index)`
//! in lexicographic order, where the squared distance of an index is always
//! evaluated by the same function ([`toroidal_squared_distance`]) from exact
//! integer residues, so exact ties go to the smallest index in both.

use crate::cbc::greatest_common_divisor;
use crate::hash::{hash3, to_unit_f64};
use crate::lattice::Rank1Lattice;
use crate::point_set::{PointSet, PointSetError};

/// The LLL parameter δ (Lovász condition), the usual choice.
pub const LLL_DELTA: f64 = 0.99;

/// The lattice point closest to a query and the shift that maps it onto the query.
#[derive(Debug, Clone, PartialEq)]
pub struct ClosestPoint {
    /// Index `i*` of the closest lattice point.
    pub index: u64,
    /// Cranley–Patterson shift `Δ_j = (u_j − x_{i*, j}) mod 1`, each in `[0, 1)`.
    pub shift: Vec<f64>,
}

/// Checks that `point` has one coordinate per lattice dimension, each in `[0, 1)`.
fn validate_query(lattice: &Rank1Lattice, point: &[f64]) -> Result<(), PointSetError> {
    if point.len() != lattice.dimensions() {
        return Err(PointSetError::InvalidParameter(format!(
            "query point has {} coordinates for a {}-dimensional lattice",
            point.len(),
            lattice.dimensions()
        )));
    }
    match point.iter().find(|value| !(0.0..1.0).contains(*value)) {
        Some(bad) => Err(PointSetError::InvalidParameter(format!(
            "query coordinates must be in [0, 1), got {bad}"
        ))),
        None => Ok(()),
    }
}

/// Toroidal squared distance between `point` and lattice point `index`, summed in
/// dimension order; stops early and returns a value above `bound` as soon as the
/// partial sum exceeds `bound` (pass `f64::INFINITY` for the full distance).
/// Coordinates are the lattice's exact `residue / N` values.
#[inline]
fn bounded_squared_distance(lattice: &Rank1Lattice, index: u64, point: &[f64], bound: f64) -> f64 {
    let point_count = lattice.point_count() as f64;
    let mut sum = 0.0;
    for (dimension, coordinate) in point.iter().enumerate() {
        let lattice_coordinate = lattice.residue(index, dimension) as f64 / point_count;
        let difference = (coordinate - lattice_coordinate).abs();
        let wrapped = difference.min(1.0 - difference);
        sum += wrapped * wrapped;
        if sum > bound {
            return sum;
        }
    }
    sum
}

/// Toroidal squared Euclidean distance between `point` (one coordinate per
/// lattice dimension, in `[0, 1)`) and lattice point `index`:
/// `Σ_j min(|u_j − x_j|, 1 − |u_j − x_j|)²`.
pub fn toroidal_squared_distance(lattice: &Rank1Lattice, index: u64, point: &[f64]) -> f64 {
    bounded_squared_distance(lattice, index, point, f64::INFINITY)
}

/// Writes the Cranley–Patterson shift `Δ_j = (u_j − x_{index, j}) mod 1` into
/// `shift` (one entry per dimension of `point`). Each entry is in `[0, 1)`; a
/// difference that rounds to 1.0 after wrapping becomes 0.0 (the same point of
/// the torus).
pub fn cranley_patterson_shift(
    lattice: &Rank1Lattice,
    index: u64,
    point: &[f64],
    shift: &mut [f64],
) {
    for (dimension, (coordinate, out)) in point.iter().zip(shift.iter_mut()).enumerate() {
        let lattice_coordinate = lattice.sample(index, dimension);
        let mut difference = coordinate - lattice_coordinate;
        if difference < 0.0 {
            difference += 1.0;
            if difference >= 1.0 {
                difference = 0.0;
            }
        }
        *out = difference;
    }
}

fn closest_point_from_index(lattice: &Rank1Lattice, index: u64, point: &[f64]) -> ClosestPoint {
    let mut shift = vec![0.0; point.len()];
    cranley_patterson_shift(lattice, index, point, &mut shift);
    ClosestPoint { index, shift }
}

/// Index of the lattice point closest to `point` on the torus, by brute force over
/// all `N` points with early exit per dimension. Ties go to the smallest index.
pub fn closest_index_brute_force(
    lattice: &Rank1Lattice,
    point: &[f64],
) -> Result<u64, PointSetError> {
    validate_query(lattice, point)?;
    let mut best_index = 0;
    let mut best_distance = f64::INFINITY;
    for index in 0..lattice.point_count() {
        let distance = bounded_squared_distance(lattice, index, point, best_distance);
        if distance < best_distance {
            best_distance = distance;
            best_index = index;
        }
    }
    Ok(best_index)
}

/// The closest lattice point to `point` and its Cranley–Patterson shift, by brute
/// force (see [`closest_index_brute_force`]).
pub fn closest_point_brute_force(
    lattice: &Rank1Lattice,
    point: &[f64],
) -> Result<ClosestPoint, PointSetError> {
    let index = closest_index_brute_force(lattice, point)?;
    Ok(closest_point_from_index(lattice, index, point))
}

/// Closest-point search in an LLL-reduced basis of a rank-1 lattice, built once
/// per lattice and then queried any number of times (immutable, `Send + Sync`).
#[derive(Debug, Clone, PartialEq)]
pub struct ClosestPointSearch {
    lattice: Rank1Lattice,
    /// Rows: the reduced basis of the scaled lattice `{i z} + N Z^s` (integers).
    basis: Vec<Vec<i64>>,
    /// Gram–Schmidt vectors `b*_i` of the reduced basis.
    orthogonal: Vec<Vec<f64>>,
    /// Squared norms `‖b*_i‖²`.
    orthogonal_norms: Vec<f64>,
    /// `mu[i][j] = ⟨b_i, b*_j⟩ / ‖b*_j‖²` for `j < i`.
    mu: Vec<Vec<f64>>,
    /// `z₁⁻¹ mod N`: maps the first coordinate of a lattice vector to its index.
    index_multiplier: u64,
    /// The coordinates `residue / N` of every point, `N × s` row-major (the exact
    /// values [`toroidal_squared_distance`] computes).
    coordinates: Vec<f64>,
    /// `index_by_first_residue[r]` is the index of the point whose first
    /// coordinate is `r / N`.
    index_by_first_residue: Vec<u64>,
    /// Whether `closest_index` enumerates (else the projection scan); see
    /// `uses_enumeration`.
    use_enumeration: bool,
}

/// Number of pseudo-random queries used to decide between enumeration and the
/// projection scan when a [`ClosestPointSearch`] is built.
pub const CALIBRATION_QUERIES: u64 = 32;

/// Work of one enumeration node relative to one projection-scan candidate, an
/// estimate from what each does: a node updates the projected centre (a dot
/// product over the levels above it) and recurses, a candidate reads a few
/// precomputed coordinates and usually abandons after one or two. The choice
/// only affects speed (both searches are exact); `closest_*` in
/// `benches/lattice.rs` measure both.
const ENUMERATION_NODE_COST: u64 = 4;

impl ClosestPointSearch {
    /// Prepares the search for `lattice`: its first generator component must be a
    /// unit modulo `N` (`gcd(z₁, N) = 1`, true for CBC and Fibonacci lattices where
    /// `z₁ = 1`) and `N` at most 2^31 (so integer basis entries stay exact).
    pub fn new(lattice: Rank1Lattice) -> Result<Self, PointSetError> {
        let point_count = lattice.point_count();
        let first = lattice.generator()[0];
        if point_count > 1 << 31 {
            return Err(PointSetError::InvalidParameter(format!(
                "reduced-basis closest-point search supports up to 2^31 points, got {point_count}"
            )));
        }
        if greatest_common_divisor(first, point_count) != 1 {
            return Err(PointSetError::InvalidParameter(format!(
                "first generator component {first} is not a unit modulo {point_count}"
            )));
        }
        let first_inverse = modular_inverse(first, point_count);
        // Normalise so the first component is 1: w = z · z₁⁻¹ generates the same points.
        let dimensions = lattice.dimensions();
        let normalised: Vec<i64> = lattice
            .generator()
            .iter()
            .map(|component| {
                ((u128::from(*component) * u128::from(first_inverse)) % u128::from(point_count))
                    as i64
            })
            .collect();
        let mut basis = vec![normalised];
        for dimension in 1..dimensions {
            let mut row = vec![0i64; dimensions];
            row[dimension] = point_count as i64;
            basis.push(row);
        }
        lll_reduce(&mut basis, LLL_DELTA);
        let (orthogonal, orthogonal_norms, mu) = gram_schmidt(&basis);
        let mut coordinates = Vec::with_capacity(point_count as usize * dimensions);
        let mut index_by_first_residue = vec![0; point_count as usize];
        for index in 0..point_count {
            for dimension in 0..dimensions {
                coordinates.push(lattice.residue(index, dimension) as f64 / point_count as f64);
            }
            index_by_first_residue[lattice.residue(index, 0) as usize] = index;
        }
        let mut search = Self {
            lattice,
            basis,
            orthogonal,
            orthogonal_norms,
            mu,
            index_multiplier: first_inverse,
            coordinates,
            index_by_first_residue,
            use_enumeration: true,
        };
        let (mut enumeration_nodes, mut scan_candidates) = (0, 0);
        for query in 0..CALIBRATION_QUERIES {
            let point: Vec<f64> = (0..dimensions)
                .map(|dimension| to_unit_f64(hash3(0x1a77_1ce5, query, dimension as u64)))
                .collect();
            enumeration_nodes += search.enumerate_closest(&point)?.1;
            scan_candidates += search.scan_closest(&point).1;
        }
        search.use_enumeration = enumeration_nodes * ENUMERATION_NODE_COST < scan_candidates;
        Ok(search)
    }

    /// The lattice searched.
    pub fn lattice(&self) -> &Rank1Lattice {
        &self.lattice
    }

    /// The LLL-reduced basis (rows) of the lattice scaled by `N`.
    pub fn reduced_basis(&self) -> &[Vec<i64>] {
        &self.basis
    }

    /// Index of the lattice point closest to `point` on the torus; ties go to the
    /// smallest index. Uses whichever of enumeration and the projection scan was
    /// found cheaper for this lattice at construction ([`Self::uses_enumeration`]);
    /// both return the same index as [`closest_index_brute_force`].
    pub fn closest_index(&self, point: &[f64]) -> Result<u64, PointSetError> {
        if self.use_enumeration {
            self.closest_index_by_enumeration(point)
        } else {
            self.closest_index_by_projection_scan(point)
        }
    }

    /// Whether [`Self::closest_index`] enumerates in the reduced basis (true) or
    /// runs the projection scan (false). Decided at construction by counting work
    /// (deterministic, not timed) on [`CALIBRATION_QUERIES`] pseudo-random
    /// queries: enumeration nodes, weighted by their relative cost, against
    /// projection-scan candidates.
    pub fn uses_enumeration(&self) -> bool {
        self.use_enumeration
    }

    /// Index of the closest lattice point by the projection scan (always,
    /// regardless of [`Self::uses_enumeration`]); exact, ties to the smallest
    /// index.
    pub fn closest_index_by_projection_scan(&self, point: &[f64]) -> Result<u64, PointSetError> {
        validate_query(&self.lattice, point)?;
        Ok(self.scan_closest(point).0)
    }

    /// The projection scan and the number of candidates whose distance it
    /// evaluated (at least in part).
    ///
    /// Residues `r` of the first coordinate are taken from both ends of the arc
    /// not yet visited, always the end nearer to the query's first coordinate
    /// `u₁`. The first one taken is `round(u₁ N)`, within half a spacing of `u₁`;
    /// after it, the unvisited arc lies on the far side of the circle, where the
    /// circular distance to `u₁` rises from both ends towards the antipode, so
    /// its smaller end is its minimum. Once that one-dimensional squared distance
    /// exceeds the best full squared distance, no unvisited point can be closer
    /// (nor tie), and the scan stops.
    fn scan_closest(&self, point: &[f64]) -> (u64, u64) {
        let point_count = self.index_by_first_residue.len();
        let dimensions = point.len();
        let scale = point_count as f64;
        let first = point[0];
        // The same arithmetic as `bounded_squared_distance` for dimension 0.
        let first_term = |residue: usize| {
            let difference = (first - residue as f64 / scale).abs();
            let wrapped = difference.min(1.0 - difference);
            wrapped * wrapped
        };
        let centre = ((first * scale).round() as usize) % point_count;
        let mut upper = centre;
        let mut lower = (centre + point_count - 1) % point_count;
        let mut upper_term = first_term(upper);
        let mut lower_term = first_term(lower);
        let mut best_index = u64::MAX;
        let mut best_distance = f64::INFINITY;
        let mut visited = 0;
        while visited < point_count as u64 {
            let (residue, term) = if upper_term <= lower_term {
                let taken = (upper, upper_term);
                upper = if upper + 1 == point_count {
                    0
                } else {
                    upper + 1
                };
                upper_term = first_term(upper);
                taken
            } else {
                let taken = (lower, lower_term);
                lower = if lower == 0 {
                    point_count - 1
                } else {
                    lower - 1
                };
                lower_term = first_term(lower);
                taken
            };
            if term > best_distance {
                break;
            }
            visited += 1;
            let index = self.index_by_first_residue[residue];
            let row = &self.coordinates[index as usize * dimensions..][..dimensions];
            let mut sum = term;
            let mut abandoned = false;
            for (coordinate, lattice_coordinate) in point[1..].iter().zip(&row[1..]) {
                let difference = (coordinate - lattice_coordinate).abs();
                let wrapped = difference.min(1.0 - difference);
                sum += wrapped * wrapped;
                if sum > best_distance {
                    abandoned = true;
                    break;
                }
            }
            if !abandoned && (sum < best_distance || (sum == best_distance && index < best_index)) {
                best_distance = sum;
                best_index = index;
            }
        }
        (best_index, visited)
    }

    /// The closest lattice point to `point` (as [`Self::closest_index`]); writes
    /// its Cranley–Patterson shift into `shift` (one entry per dimension) without
    /// allocating.
    pub fn closest_point_into(
        &self,
        point: &[f64],
        shift: &mut [f64],
    ) -> Result<u64, PointSetError> {
        if shift.len() != point.len() {
            return Err(PointSetError::InvalidParameter(format!(
                "shift has {} entries for a {}-dimensional query",
                shift.len(),
                point.len()
            )));
        }
        let index = self.closest_index(point)?;
        cranley_patterson_shift(&self.lattice, index, point, shift);
        Ok(index)
    }

    /// Index of the closest lattice point by exact closest-vector enumeration in
    /// the reduced basis (always, regardless of [`Self::uses_enumeration`]).
    pub fn closest_index_by_enumeration(&self, point: &[f64]) -> Result<u64, PointSetError> {
        self.enumerate_closest(point).map(|(index, _)| index)
    }

    /// Enumeration result and the number of tree nodes visited.
    fn enumerate_closest(&self, point: &[f64]) -> Result<(u64, u64), PointSetError> {
        validate_query(&self.lattice, point)?;
        let dimensions = point.len();
        let scale = self.lattice.point_count() as f64;
        // Target in the scaled lattice, in Gram–Schmidt coordinates.
        let target: Vec<f64> = point.iter().map(|value| value * scale).collect();
        let target_coordinates: Vec<f64> = self
            .orthogonal
            .iter()
            .zip(&self.orthogonal_norms)
            .map(|(vector, norm)| dot(&target, vector) / norm)
            .collect();
        let mut state = EnumerationState {
            coefficients: vec![0i64; dimensions],
            best_index: 0,
            best_distance: f64::INFINITY,
            bound: f64::INFINITY,
            scale_squared: scale * scale,
            visited_nodes: 0,
        };
        self.enumerate(dimensions - 1, 0.0, &target_coordinates, point, &mut state);
        Ok((state.best_index, state.visited_nodes))
    }

    /// The closest lattice point to `point` and its Cranley–Patterson shift.
    pub fn closest_point(&self, point: &[f64]) -> Result<ClosestPoint, PointSetError> {
        let index = self.closest_index(point)?;
        Ok(closest_point_from_index(&self.lattice, index, point))
    }

    /// Depth-first enumeration of coefficient `level` (levels run from the last
    /// basis vector down to the first), visiting values nearest the projected
    /// centre first, so the first leaf is Babai's nearest-plane point.
    fn enumerate(
        &self,
        level: usize,
        partial: f64,
        target_coordinates: &[f64],
        point: &[f64],
        state: &mut EnumerationState,
    ) {
        let mut center = target_coordinates[level];
        for above in level + 1..state.coefficients.len() {
            center -= self.mu[above][level] * state.coefficients[above] as f64;
        }
        let norm = self.orthogonal_norms[level];
        // Schnorr–Euchner order: integers by increasing distance from the centre,
        // alternating sides; the first value beyond the bound (which shrinks as
        // better leaves are found) ends this level, as all later ones are farther.
        let mut upper = center.round();
        let mut lower = upper - 1.0;
        loop {
            let upper_offset = upper - center;
            let lower_offset = center - lower;
            let value = if upper_offset <= lower_offset {
                upper += 1.0;
                upper - 1.0
            } else {
                lower -= 1.0;
                lower + 1.0
            };
            let offset = center - value;
            let distance = partial + offset * offset * norm;
            if distance > state.bound {
                break;
            }
            state.coefficients[level] = value as i64;
            state.visited_nodes += 1;
            if level == 0 {
                self.visit_leaf(point, state);
            } else {
                self.enumerate(level - 1, distance, target_coordinates, point, state);
            }
        }
    }

    /// Maps the lattice vector with the current coefficients to its index and keeps
    /// it if it beats the best `(distance, index)` so far.
    fn visit_leaf(&self, point: &[f64], state: &mut EnumerationState) {
        let point_count = self.lattice.point_count();
        let first_coordinate: i128 = state
            .coefficients
            .iter()
            .zip(&self.basis)
            .map(|(coefficient, row)| i128::from(*coefficient) * i128::from(row[0]))
            .sum();
        let residue = first_coordinate.rem_euclid(i128::from(point_count)) as u64;
        let index = ((u128::from(residue) * u128::from(self.index_multiplier))
            % u128::from(point_count)) as u64;
        let distance = toroidal_squared_distance(&self.lattice, index, point);
        if distance < state.best_distance
            || (distance == state.best_distance && index < state.best_index)
        {
            state.best_distance = distance;
            state.best_index = index;
            // Scaled bound with slack, so vectors tying up to rounding are still
            // visited and the exact tie-break applies.
            state.bound = distance * state.scale_squared * (1.0 + 1e-9) + 1e-9;
        }
    }
}

struct EnumerationState {
    coefficients: Vec<i64>,
    best_index: u64,
    best_distance: f64,
    bound: f64,
    scale_squared: f64,
    visited_nodes: u64,
}

fn dot(left: &[f64], right: &[f64]) -> f64 {
    left.iter().zip(right).map(|(a, b)| a * b).sum()
}

/// `value⁻¹ mod modulus` for a unit `value` (extended Euclid).
fn modular_inverse(value: u64, modulus: u64) -> u64 {
    let (mut old_remainder, mut remainder) = (i128::from(value), i128::from(modulus));
    let (mut old_coefficient, mut coefficient) = (1i128, 0i128);
    while remainder != 0 {
        let quotient = old_remainder / remainder;
        (old_remainder, remainder) = (remainder, old_remainder - quotient * remainder);
        (old_coefficient, coefficient) = (coefficient, old_coefficient - quotient * coefficient);
    }
    old_coefficient.rem_euclid(i128::from(modulus)) as u64
}

/// Gram–Schmidt orthogonalisation of integer rows: `(b*_i, ‖b*_i‖², μ)`.
#[allow(clippy::type_complexity)]
fn gram_schmidt(basis: &[Vec<i64>]) -> (Vec<Vec<f64>>, Vec<f64>, Vec<Vec<f64>>) {
    let count = basis.len();
    let mut orthogonal: Vec<Vec<f64>> = Vec::with_capacity(count);
    let mut norms = Vec::with_capacity(count);
    let mut mu = vec![vec![0.0; count]; count];
    for (row_index, row) in basis.iter().enumerate() {
        let row: Vec<f64> = row.iter().map(|value| *value as f64).collect();
        let mut vector = row.clone();
        for earlier in 0..row_index {
            let coefficient = dot(&row, &orthogonal[earlier]) / norms[earlier];
            mu[row_index][earlier] = coefficient;
            for (entry, component) in vector.iter_mut().zip(&orthogonal[earlier]) {
                *entry -= coefficient * component;
            }
        }
        norms.push(dot(&vector, &vector));
        orthogonal.push(vector);
    }
    (orthogonal, norms, mu)
}

/// LLL reduction (Lenstra, Lenstra, Lovász 1982) of a full-rank integer basis
/// given as rows, with parameter `delta`; Gram–Schmidt data in `f64` (exact enough
/// for the small entries of the lattices here), recomputed after each swap.
fn lll_reduce(basis: &mut [Vec<i64>], delta: f64) {
    let count = basis.len();
    if count < 2 {
        return;
    }
    let (_, mut norms, mut mu) = gram_schmidt(basis);
    let mut level = 1;
    while level < count {
        // Size-reduce row `level` against all earlier rows.
        for earlier in (0..level).rev() {
            let quotient = mu[level][earlier].round();
            if quotient != 0.0 {
                let factor = quotient as i64;
                let (head, tail) = basis.split_at_mut(level);
                for (entry, subtrahend) in tail[0].iter_mut().zip(&head[earlier]) {
                    *entry -= factor * subtrahend;
                }
                let (head, tail) = mu.split_at_mut(level);
                for (entry, earlier_mu) in tail[0][..earlier].iter_mut().zip(&head[earlier]) {
                    *entry -= quotient * earlier_mu;
                }
                tail[0][earlier] -= quotient;
            }
        }
        let projected = mu[level][level - 1];
        if norms[level] >= (delta - projected * projected) * norms[level - 1] {
            level += 1;
        } else {
            basis.swap(level, level - 1);
            (_, norms, mu) = gram_schmidt(basis);
            level = (level - 1).max(1);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn modular_inverses() {
        assert_eq!(modular_inverse(3, 7), 5);
        assert_eq!(modular_inverse(1, 313), 1);
        assert_eq!(modular_inverse(10, 313) * 10 % 313, 1);
    }

    #[test]
    fn one_dimension_rounds_to_nearest_multiple() {
        let lattice = Rank1Lattice::new(10, vec![1]).unwrap();
        let search = ClosestPointSearch::new(lattice.clone()).unwrap();
        for (query, expected) in [(0.0, 0), (0.34, 3), (0.96, 0), (0.5, 5), (0.04, 0)] {
            assert_eq!(
                closest_index_brute_force(&lattice, &[query]).unwrap(),
                expected
            );
            assert_eq!(search.closest_index(&[query]).unwrap(), expected, "{query}");
            assert_eq!(
                search.closest_index_by_enumeration(&[query]).unwrap(),
                expected
            );
        }
    }

    #[test]
    fn reduced_basis_spans_the_lattice() {
        let lattice = Rank1Lattice::new(313, vec![1, 136, 41, 7]).unwrap();
        let search = ClosestPointSearch::new(lattice).unwrap();
        // |det| of the scaled lattice basis is N^(s−1); LLL keeps it.
        let (_, norms, _) = gram_schmidt(search.reduced_basis());
        let log_volume: f64 = norms.iter().map(|norm| 0.5 * norm.ln()).sum();
        assert!((log_volume - 3.0 * 313f64.ln()).abs() < 1e-9);
        // Every reduced row is a lattice vector: v ≡ v₁ z (mod N).
        for row in search.reduced_basis() {
            let first = row[0].rem_euclid(313);
            for (component, generator) in row.iter().zip([1i64, 136, 41, 7]) {
                assert_eq!(component.rem_euclid(313), first * generator % 313);
            }
        }
    }

    #[test]
    fn rejects_bad_queries_and_lattices() {
        let lattice = Rank1Lattice::new(7, vec![1, 3]).unwrap();
        assert!(closest_point_brute_force(&lattice, &[0.5]).is_err());
        assert!(closest_point_brute_force(&lattice, &[0.5, 1.0]).is_err());
        assert!(closest_point_brute_force(&lattice, &[0.5, f64::NAN]).is_err());
        let search = ClosestPointSearch::new(lattice).unwrap();
        assert!(search.closest_point(&[-0.1, 0.5]).is_err());
        assert!(ClosestPointSearch::new(Rank1Lattice::new(8, vec![2, 3]).unwrap()).is_err());
    }

    #[test]
    fn unit_first_component_maps_indices_back() {
        let lattice = Rank1Lattice::new(23, vec![5, 7, 11]).unwrap();
        let search = ClosestPointSearch::new(lattice.clone()).unwrap();
        let mut point = [0.0; 3];
        for index in 0..23 {
            lattice.point(index, &mut point);
            assert_eq!(search.closest_index_by_enumeration(&point).unwrap(), index);
        }
    }
}
