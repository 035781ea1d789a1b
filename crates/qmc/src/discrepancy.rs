//! Discrepancy measures: how far the empirical distribution of a point set is
//! from the uniform distribution on the unit cube.
//!
//! They are used to compare constructions and randomizations (a Cranley–Patterson
//! rotation can spoil a net's star discrepancy, a lattice's wrap-around
//! discrepancy survives it) and to tie the lattice search to a measurable
//! quantity.
//!
//! # Point layout
//! Points are passed as one flat, row-major slice `points` together with the
//! number of coordinates per point, `dimensions`: point `i` is
//! `points[i * dimensions .. (i + 1) * dimensions]`. [`flatten_rows`] converts a
//! `&[Vec<f64>]`, [`gather_points`] reads points from any [`PointSet`], and
//! [`point_set_l2_discrepancy`] / [`point_set_star_discrepancy`] do both at once.
//! Coordinates must be finite and lie in the closed cube `[0, 1]` (the closed
//! end is accepted because reference designs such as the point `(1, …, 1)` use it).
//!
//! # Conventions
//! Every function returns the discrepancy itself, never its square.
//! `scipy.stats.qmc.discrepancy` (scipy 1.17) returns the centered, wrap-around
//! and mixture discrepancies *squared* and the L2-star discrepancy after the
//! square root; so `centered_l2_discrepancy(p)^2 == scipy(p, method="CD")` and
//! `l2_star_discrepancy(p) == scipy(p, method="L2-star")` (tested to 1e-10
//! against golden values written by `scripts/golden/discrepancy.py`).
//!
//! The L2 formulas are the closed forms of Warnock (1972) for the L2-star
//! discrepancy and of Hickernell (1998) and Zhou, Fang, Ning (2013, Eqs. 9, 10
//! and 18 of "Mixture discrepancy for quasi-random point sets") for the
//! centered, wrap-around and mixture discrepancies. They cost `O(n² d)`; the
//! double sums use the symmetry of their kernels and compensated (Neumaier)
//! summation.

use crate::point_set::{PointSet, PointSetError, check_request};
use crate::summation::NeumaierSum;

/// The L2-type discrepancies with a closed form, as named by scipy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum L2Discrepancy {
    /// L2 norm of the local discrepancy over boxes anchored at the origin,
    /// `[0, t)` (scipy's `"L2-star"`).
    Star,
    /// Hickernell's centered L2 discrepancy: boxes spanned by a point and the
    /// nearest corner of the cube (scipy's `"CD"`).
    Centered,
    /// Wrap-around (torus) L2 discrepancy: boxes that may wrap around the
    /// boundary; invariant under Cranley–Patterson shifts (scipy's `"WD"`).
    WrapAround,
    /// Mixture discrepancy of Zhou, Fang and Ning, a mix of the centered and
    /// wrap-around kernels (scipy's `"MD"`).
    Mixture,
}

/// Checks the flat point layout and returns the number of points.
fn validate_points(points: &[f64], dimensions: usize) -> Result<usize, PointSetError> {
    if dimensions == 0 {
        return Err(PointSetError::InvalidParameter(
            "discrepancy needs at least one dimension".into(),
        ));
    }
    if points.is_empty() {
        return Err(PointSetError::InvalidParameter(
            "discrepancy needs at least one point".into(),
        ));
    }
    if !points.len().is_multiple_of(dimensions) {
        return Err(PointSetError::InvalidParameter(format!(
            "{} coordinates are not a whole number of {dimensions}-dimensional points",
            points.len()
        )));
    }
    if let Some(position) = points.iter().position(|value| !(0.0..=1.0).contains(value)) {
        return Err(PointSetError::InvalidParameter(format!(
            "coordinate {} of point {} is {}, outside [0, 1]",
            position % dimensions,
            position / dimensions,
            points[position]
        )));
    }
    Ok(points.len() / dimensions)
}

/// Converts points given as rows into the flat row-major layout used here;
/// returns the coordinates and the number of dimensions.
///
/// Errors if there are no rows, a row is empty, or rows differ in length.
pub fn flatten_rows(rows: &[Vec<f64>]) -> Result<(Vec<f64>, usize), PointSetError> {
    let dimensions = rows.first().map_or(0, Vec::len);
    if dimensions == 0 {
        return Err(PointSetError::InvalidParameter(
            "need at least one point with at least one coordinate".into(),
        ));
    }
    let mut flat = Vec::with_capacity(rows.len() * dimensions);
    for (index, row) in rows.iter().enumerate() {
        if row.len() != dimensions {
            return Err(PointSetError::InvalidParameter(format!(
                "point {index} has {} coordinates, point 0 has {dimensions}",
                row.len()
            )));
        }
        flat.extend_from_slice(row);
    }
    Ok((flat, dimensions))
}

/// Reads points `start .. start + count` (first `dimensions` coordinates each)
/// of `set` into the flat row-major layout.
///
/// Errors if the set has too few dimensions or points (see [`check_request`]).
pub fn gather_points(
    set: &dyn PointSet,
    start: u64,
    count: u64,
    dimensions: usize,
) -> Result<Vec<f64>, PointSetError> {
    check_request(set, start, count, dimensions)?;
    let total = usize::try_from(count)
        .ok()
        .and_then(|count| count.checked_mul(dimensions))
        .ok_or_else(|| PointSetError::InvalidParameter("too many points to gather".into()))?;
    let mut flat = vec![0.0; total];
    if dimensions > 0 {
        for (offset, row) in flat.chunks_exact_mut(dimensions).enumerate() {
            set.point(start + offset as u64, row);
        }
    }
    Ok(flat)
}

/// `(Σ_i Π_k single(x_ik), Σ_i Σ_j Π_k pair(x_ik, x_jk))` for a kernel `pair`
/// symmetric in its arguments (only `i ≤ j` is evaluated).
fn kernel_sums(
    points: &[f64],
    dimensions: usize,
    single: impl Fn(f64) -> f64,
    pair: impl Fn(f64, f64) -> f64,
) -> (f64, f64) {
    let rows: Vec<&[f64]> = points.chunks_exact(dimensions).collect();
    let mut single_sum = NeumaierSum::default();
    let mut diagonal_sum = NeumaierSum::default();
    let mut off_diagonal_sum = NeumaierSum::default();
    for (i, row_i) in rows.iter().enumerate() {
        single_sum.add(row_i.iter().map(|&x| single(x)).product());
        diagonal_sum.add(row_i.iter().map(|&x| pair(x, x)).product());
        let mut row_sum = NeumaierSum::default();
        for row_j in &rows[i + 1..] {
            row_sum.add(
                row_i
                    .iter()
                    .zip(row_j.iter())
                    .map(|(&a, &b)| pair(a, b))
                    .product(),
            );
        }
        off_diagonal_sum.add(row_sum.total());
    }
    (
        single_sum.total(),
        diagonal_sum.total() + 2.0 * off_diagonal_sum.total(),
    )
}

/// Square root of a squared discrepancy, treating tiny negative round-off as 0.
fn root(squared: f64) -> f64 {
    squared.max(0.0).sqrt()
}

/// L2-star discrepancy by Warnock's formula:
/// `T² = 3^-d − (2^(1−d)/n) Σ_i Π_k (1 − x_ik²) + (1/n²) Σ_i Σ_j Π_k (1 − max(x_ik, x_jk))`.
///
/// Equals scipy's `discrepancy(method="L2-star")` (which already takes the root).
pub fn l2_star_discrepancy(points: &[f64], dimensions: usize) -> Result<f64, PointSetError> {
    let count = validate_points(points, dimensions)? as f64;
    let d = dimensions as i32;
    let (single, pairs) = kernel_sums(points, dimensions, |x| 1.0 - x * x, |a, b| 1.0 - a.max(b));
    Ok(root(
        3f64.powi(-d) - 2f64.powi(1 - d) / count * single + pairs / (count * count),
    ))
}

/// Centered L2 discrepancy (Hickernell 1998; Zhou et al. 2013, Eq. 9):
/// `CD² = (13/12)^d − (2/n) Σ_i Π_k (1 + |x−½|/2 − |x−½|²/2)
///  + (1/n²) Σ_i Σ_j Π_k (1 + |x_ik−½|/2 + |x_jk−½|/2 − |x_ik−x_jk|/2)`.
///
/// scipy's `discrepancy(method="CD")` is the square of this value.
pub fn centered_l2_discrepancy(points: &[f64], dimensions: usize) -> Result<f64, PointSetError> {
    let count = validate_points(points, dimensions)? as f64;
    let (single, pairs) = kernel_sums(
        points,
        dimensions,
        |x| {
            let centered = (x - 0.5).abs();
            1.0 + 0.5 * centered - 0.5 * centered * centered
        },
        |a, b| 1.0 + 0.5 * (a - 0.5).abs() + 0.5 * (b - 0.5).abs() - 0.5 * (a - b).abs(),
    );
    Ok(root(
        (13.0f64 / 12.0).powi(dimensions as i32) - 2.0 / count * single + pairs / (count * count),
    ))
}

/// Wrap-around L2 discrepancy (Hickernell 1998; Zhou et al. 2013, Eq. 10):
/// `WD² = −(4/3)^d + (1/n²) Σ_i Σ_j Π_k (3/2 − |x_ik−x_jk| (1 − |x_ik−x_jk|))`.
///
/// scipy's `discrepancy(method="WD")` is the square of this value.
pub fn wrap_around_l2_discrepancy(points: &[f64], dimensions: usize) -> Result<f64, PointSetError> {
    let count = validate_points(points, dimensions)? as f64;
    let (_, pairs) = kernel_sums(
        points,
        dimensions,
        |_| 0.0,
        |a, b| {
            let distance = (a - b).abs();
            1.5 - distance * (1.0 - distance)
        },
    );
    Ok(root(
        pairs / (count * count) - (4.0f64 / 3.0).powi(dimensions as i32),
    ))
}

/// Mixture L2 discrepancy (Zhou, Fang, Ning 2013, Eq. 18):
/// `MD² = (19/12)^d − (2/n) Σ_i Π_k (5/3 − |x−½|/4 − |x−½|²/4)
///  + (1/n²) Σ_i Σ_j Π_k (15/8 − |x_ik−½|/4 − |x_jk−½|/4 − 3|x_ik−x_jk|/4 + |x_ik−x_jk|²/2)`.
///
/// scipy's `discrepancy(method="MD")` is the square of this value.
pub fn mixture_l2_discrepancy(points: &[f64], dimensions: usize) -> Result<f64, PointSetError> {
    let count = validate_points(points, dimensions)? as f64;
    let (single, pairs) = kernel_sums(
        points,
        dimensions,
        |x| {
            let centered = (x - 0.5).abs();
            5.0 / 3.0 - 0.25 * centered - 0.25 * centered * centered
        },
        |a, b| {
            let distance = (a - b).abs();
            15.0 / 8.0 - 0.25 * (a - 0.5).abs() - 0.25 * (b - 0.5).abs() - 0.75 * distance
                + 0.5 * distance * distance
        },
    );
    Ok(root(
        (19.0f64 / 12.0).powi(dimensions as i32) - 2.0 / count * single + pairs / (count * count),
    ))
}

/// The L2 discrepancy of the given kind (not squared), see the functions per kind.
pub fn l2_discrepancy(
    kind: L2Discrepancy,
    points: &[f64],
    dimensions: usize,
) -> Result<f64, PointSetError> {
    match kind {
        L2Discrepancy::Star => l2_star_discrepancy(points, dimensions),
        L2Discrepancy::Centered => centered_l2_discrepancy(points, dimensions),
        L2Discrepancy::WrapAround => wrap_around_l2_discrepancy(points, dimensions),
        L2Discrepancy::Mixture => mixture_l2_discrepancy(points, dimensions),
    }
}

/// The L2 discrepancy of points `start .. start + count` of `set` in its first
/// `dimensions` dimensions.
pub fn point_set_l2_discrepancy(
    kind: L2Discrepancy,
    set: &dyn PointSet,
    start: u64,
    count: u64,
    dimensions: usize,
) -> Result<f64, PointSetError> {
    let points = gather_points(set, start, count, dimensions)?;
    l2_discrepancy(kind, &points, dimensions)
}

/// Exact star discrepancy `D*_n = sup_{t ∈ [0,1]^d} |#{x_i ∈ [0, t)}/n − t_1⋯t_d|`
/// for `d ≤ 2`; errors for `d > 2` (the problem is NP-hard in general).
///
/// Box conventions: the supremum over half-open anchored boxes `[0, t)` equals
/// the supremum over closed boxes `[0, t]` and is the larger of two maxima over
/// the finite grid of *critical* corners `t`, whose coordinates are point
/// coordinates or 1:
/// - closed boxes, `#{x_i ∈ [0, t]}/n − vol(t)` (too many points: shrinking `t`
///   until a face touches a point only helps), and
/// - open boxes, `vol(t) − #{x_i ∈ [0, t)}/n` (too few points: growing `t`
///   until a face touches a point or reaches 1 only helps).
///
/// For `d = 1` this is the closed form over sorted points
/// `max_i max(i/n − x_(i), x_(i) − (i−1)/n)` (`O(n log n)`). For `d = 2` a sweep
/// over the sorted first coordinates keeps a histogram over the ranks of the
/// second coordinates and evaluates both box kinds at all `O(n²)` critical
/// corners by prefix sums: `O(n²)` time after an `O(n log n)` sort, `O(n)` memory.
pub fn star_discrepancy(points: &[f64], dimensions: usize) -> Result<f64, PointSetError> {
    let count = validate_points(points, dimensions)?;
    match dimensions {
        1 => Ok(star_discrepancy_1d(points)),
        2 => Ok(star_discrepancy_2d(points, count)),
        _ => Err(PointSetError::TooManyDimensions {
            requested: dimensions,
            supported: 2,
        }),
    }
}

/// The exact star discrepancy of points `start .. start + count` of `set` in
/// its first `dimensions ≤ 2` dimensions, see [`star_discrepancy`].
pub fn point_set_star_discrepancy(
    set: &dyn PointSet,
    start: u64,
    count: u64,
    dimensions: usize,
) -> Result<f64, PointSetError> {
    if dimensions > 2 {
        return Err(PointSetError::TooManyDimensions {
            requested: dimensions,
            supported: 2,
        });
    }
    let points = gather_points(set, start, count, dimensions)?;
    star_discrepancy(&points, dimensions)
}

/// Closed form for one dimension; ties need no care since `i/n − x_(i)` is
/// largest at the last and `x_(i) − (i−1)/n` at the first of equal values.
fn star_discrepancy_1d(points: &[f64]) -> f64 {
    let mut sorted = points.to_vec();
    sorted.sort_by(f64::total_cmp);
    let count = sorted.len() as f64;
    sorted
        .iter()
        .enumerate()
        .map(|(index, &x)| {
            let closed_excess = (index + 1) as f64 / count - x;
            let open_deficit = x - index as f64 / count;
            closed_excess.max(open_deficit)
        })
        .fold(0.0, f64::max)
}

/// Sorted distinct values of `values` followed by 1 (if not already present).
fn critical_values(values: impl Iterator<Item = f64>) -> Vec<f64> {
    let mut sorted: Vec<f64> = values.collect();
    sorted.push(1.0);
    sorted.sort_by(f64::total_cmp);
    sorted.dedup();
    sorted
}

/// The `O(n²)` sweep for two dimensions, see [`star_discrepancy`].
fn star_discrepancy_2d(points: &[f64], count: usize) -> f64 {
    let first: Vec<f64> = points.iter().step_by(2).copied().collect();
    let second: Vec<f64> = points.iter().skip(1).step_by(2).copied().collect();
    let first_critical = critical_values(first.iter().copied());
    let second_critical = critical_values(second.iter().copied());
    // Rank of each point's second coordinate among the critical values.
    let second_rank: Vec<usize> = second
        .iter()
        .map(|y| second_critical.partition_point(|value| value < y))
        .collect();
    let mut order: Vec<usize> = (0..count).collect();
    order.sort_by(|&a, &b| first[a].total_cmp(&first[b]));

    let inverse_count = 1.0 / count as f64;
    // histogram[k]: number of swept points whose second coordinate is second_critical[k].
    let mut histogram = vec![0usize; second_critical.len()];
    let mut next = 0;
    let mut discrepancy: f64 = 0.0;
    for &t1 in &first_critical {
        // Open boxes [0, t1) × [0, t2): the histogram holds points with x < t1.
        let mut below = 0usize;
        for (&t2, &in_row) in second_critical.iter().zip(&histogram) {
            discrepancy = discrepancy.max(t1 * t2 - below as f64 * inverse_count);
            below += in_row;
        }
        while next < count && first[order[next]] <= t1 {
            histogram[second_rank[order[next]]] += 1;
            next += 1;
        }
        // Closed boxes [0, t1] × [0, t2]: the histogram holds points with x ≤ t1.
        let mut at_or_below = 0usize;
        for (&t2, &in_row) in second_critical.iter().zip(&histogram) {
            at_or_below += in_row;
            discrepancy = discrepancy.max(at_or_below as f64 * inverse_count - t1 * t2);
        }
    }
    discrepancy
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_layouts() {
        assert!(l2_star_discrepancy(&[], 2).is_err());
        assert!(l2_star_discrepancy(&[0.5], 0).is_err());
        assert!(l2_star_discrepancy(&[0.5, 0.5, 0.5], 2).is_err());
        assert!(centered_l2_discrepancy(&[0.5, 1.5], 2).is_err());
        assert!(mixture_l2_discrepancy(&[0.5, f64::NAN], 2).is_err());
        assert!(wrap_around_l2_discrepancy(&[-0.1], 1).is_err());
        assert!(flatten_rows(&[vec![0.1, 0.2], vec![0.3]]).is_err());
        assert!(flatten_rows(&[]).is_err());
        assert!(matches!(
            star_discrepancy(&[0.5, 0.5, 0.5], 3),
            Err(PointSetError::TooManyDimensions {
                requested: 3,
                supported: 2
            })
        ));
    }

    #[test]
    fn single_centre_point() {
        assert!((star_discrepancy(&[0.5, 0.5], 2).unwrap() - 0.75).abs() < 1e-15);
        assert!((star_discrepancy(&[0.5], 1).unwrap() - 0.5).abs() < 1e-15);
    }
}
