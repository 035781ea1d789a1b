//! Base-2 Niederreiter sequence against GSL's output and its t-values.

#[path = "golden/sobol_niederreiter_gsl.rs"]
mod golden;

use qmc::PointSet;
use qmc::digital_scramble::{DigitalOrder, DigitalSequence};
use qmc::niederreiter::{MAX_DIMENSIONS, Niederreiter};

#[test]
fn matches_the_reference_values() {
    // docs/qmc.md, "Reference values": GSL 2.7.1, Gray-code order, 12 dimensions.
    let sequence = Niederreiter::new(12, DigitalOrder::GrayCode).unwrap();
    assert!((0..12).all(|d| sequence.sample(0, d) == 0.0));
    let second = [0.5, 0.5, 0.75, 0.875, 0.875, 0.9375];
    let third = [0.75, 0.25, 0.3125, 0.140625];
    for (d, value) in second.iter().enumerate() {
        assert_eq!(sequence.sample(1, d), *value);
    }
    for (d, value) in third.iter().enumerate() {
        assert_eq!(sequence.sample(2, d), *value);
    }
}

#[test]
fn matches_gsl_in_twelve_dimensions() {
    let sequence = Niederreiter::new(12, DigitalOrder::GrayCode).unwrap();
    let blocks = [
        (0u64, golden::NIEDERREITER_D12_FIRST_128),
        (1024, golden::NIEDERREITER_D12_FROM_1024),
    ];
    for (start, rows) in blocks {
        for (offset, row) in rows.iter().enumerate() {
            let index = start + offset as u64;
            for (dimension, &gsl) in row.iter().enumerate() {
                // GSL keeps 31 digits; the 32nd is ours alone.
                assert_eq!(
                    sequence.sample_bits(index, dimension) >> 1,
                    gsl,
                    "point {index}, dimension {dimension}"
                );
            }
        }
    }
}

/// Number of points of `points` (digits per coordinate) in every elementary
/// interval with `digits[j]` leading digits in coordinate `j`, if all intervals
/// hold the same number; `None` otherwise.
fn equal_count_per_box(points: &[Vec<u32>], digits: &[u32]) -> Option<usize> {
    let total: u32 = digits.iter().sum();
    let mut counts = vec![0usize; 1 << total];
    for point in points {
        let cell = point.iter().zip(digits).fold(0usize, |cell, (&x, &k)| {
            let part = if k == 0 { 0 } else { (x >> (32 - k)) as usize };
            (cell << k) | part
        });
        counts[cell] += 1;
    }
    let first = counts[0];
    counts.iter().all(|&c| c == first).then_some(first)
}

/// All ways to write `total` as an ordered sum of `parts` nonnegative integers.
fn compositions(total: u32, parts: usize) -> Vec<Vec<u32>> {
    if parts == 1 {
        return vec![vec![total]];
    }
    (0..=total)
        .flat_map(|first| {
            compositions(total - first, parts - 1)
                .into_iter()
                .map(move |mut rest| {
                    rest.insert(0, first);
                    rest
                })
        })
        .collect()
}

/// True iff `points` (2^m of them) form a (t, m, s)-net in base 2.
fn is_net(points: &[Vec<u32>], m: u32, t: u32) -> bool {
    let dimensions = points[0].len();
    compositions(m - t, dimensions)
        .iter()
        .all(|digits| equal_count_per_box(points, digits) == Some(1 << t))
}

fn points(sequence: &Niederreiter, start: u64, count: u64, dimensions: &[usize]) -> Vec<Vec<u32>> {
    (start..start + count)
        .map(|i| {
            dimensions
                .iter()
                .map(|&d| sequence.sample_bits(i, d))
                .collect()
        })
        .collect()
}

#[test]
fn t_value_is_the_sum_of_degrees_minus_one() {
    // Dimensions 0 … 3 have degrees 1, 1, 2, 3: t = 0 + 0 + 1 + 2 = 3.
    let sequence = Niederreiter::new(4, DigitalOrder::GrayCode).unwrap();
    for (dimensions, t) in [
        (&[0, 1][..], 0),
        (&[0, 1, 2][..], 1),
        (&[0, 1, 2, 3][..], 3),
    ] {
        for m in t..=10 {
            for block in [0u64, 3] {
                let net = points(&sequence, block << m, 1 << m, dimensions);
                assert!(is_net(&net, m, t), "{dimensions:?}, m = {m}, block {block}");
            }
        }
    }
}

#[test]
fn every_dimension_stratifies_with_its_own_t_value() {
    // A single coordinate with a polynomial of degree e is an (e − 1, 1)-sequence.
    let sequence = Niederreiter::new(MAX_DIMENSIONS, DigitalOrder::Natural).unwrap();
    let m = 14;
    for dimension in 0..MAX_DIMENSIONS {
        let t = 63 - sequence.polynomial(dimension).leading_zeros() - 1;
        let column = points(&sequence, 0, 1 << m, &[dimension]);
        assert_eq!(
            equal_count_per_box(&column, &[m - t]),
            Some(1 << t),
            "dimension {dimension}"
        );
        assert!(
            column
                .iter()
                .all(|p| (f64::from(p[0]) / 4_294_967_296.0) < 1.0)
        );
    }
}

#[test]
fn natural_and_gray_code_orders_agree_on_blocks() {
    let natural = Niederreiter::new(6, DigitalOrder::Natural).unwrap();
    let gray = Niederreiter::new(6, DigitalOrder::GrayCode).unwrap();
    let dimensions: Vec<usize> = (0..6).collect();
    for m in [0, 3, 9] {
        let mut a = points(&natural, 0, 1 << m, &dimensions);
        let mut b = points(&gray, 0, 1 << m, &dimensions);
        a.sort();
        b.sort();
        assert_eq!(a, b, "m = {m}");
    }
}
