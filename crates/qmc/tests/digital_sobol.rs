//! Sobol sequence against scipy, its order conventions and its net properties.

#[path = "golden/sobol_scipy.rs"]
mod golden;

use qmc::PointSet;
use qmc::digital_scramble::DigitalSequence;
use qmc::sobol::{DigitalOrder, MAX_DIMENSIONS, Sobol};

mod common;
use common::is_zero_m_two_net;

fn assert_rows_equal<const W: usize>(
    sobol: &Sobol,
    start: u64,
    dimensions: &[usize],
    rows: &[[u32; W]],
) {
    for (offset, row) in rows.iter().enumerate() {
        let index = start + offset as u64;
        for (column, &dimension) in dimensions.iter().enumerate() {
            assert_eq!(
                sobol.sample_bits(index, dimension),
                row[column],
                "point {index}, dimension {dimension}"
            );
        }
    }
}

#[test]
fn matches_scipy_in_eight_dimensions() {
    let sobol = Sobol::new(8, DigitalOrder::GrayCode).unwrap();
    let dimensions: Vec<usize> = (0..8).collect();
    assert_rows_equal(&sobol, 0, &dimensions, golden::SOBOL_D8_FIRST_64);
    assert_rows_equal(&sobol, 1000, &dimensions, golden::SOBOL_D8_FROM_1000);
    // The f64 coordinates are the same integers times 2^-32, exactly.
    for (index, row) in golden::SOBOL_D8_FIRST_64.iter().enumerate() {
        for (dimension, &bits) in row.iter().enumerate() {
            assert_eq!(
                sobol.sample(index as u64, dimension),
                f64::from(bits) / 4_294_967_296.0
            );
        }
    }
}

#[test]
fn matches_scipy_at_large_indices() {
    let sobol = Sobol::new(2, DigitalOrder::GrayCode).unwrap();
    assert_rows_equal(&sobol, (1 << 31) - 2, &[0, 1], golden::SOBOL_D2_FROM_2POW31);
    assert_rows_equal(&sobol, (1 << 32) - 4, &[0, 1], golden::SOBOL_D2_LAST);
    // The last point of the 2^32 is still strictly below one.
    assert!(sobol.sample((1 << 32) - 1, 1) < 1.0);
}

#[test]
fn matches_scipy_in_all_21201_dimensions() {
    let sobol = Sobol::new(MAX_DIMENSIONS, DigitalOrder::GrayCode).unwrap();
    let dimensions = golden::SOBOL_HIGH_DIMENSIONS;
    assert_rows_equal(&sobol, 0, &dimensions, golden::SOBOL_D21201_FIRST_8);
    assert_rows_equal(
        &sobol,
        123_456,
        &dimensions,
        golden::SOBOL_D21201_FROM_123456,
    );
}

#[test]
fn natural_and_gray_code_orders_give_the_same_first_two_to_the_m_points() {
    let natural = Sobol::new(10, DigitalOrder::Natural).unwrap();
    let gray = Sobol::new(10, DigitalOrder::GrayCode).unwrap();
    for m in 0..=10u32 {
        let collect = |sobol: &Sobol| {
            let mut points: Vec<Vec<u32>> = (0..1u64 << m)
                .map(|index| (0..10).map(|d| sobol.sample_bits(index, d)).collect())
                .collect();
            points.sort();
            points
        };
        assert_eq!(collect(&natural), collect(&gray), "m = {m}");
    }
    // ... while the orders themselves differ.
    assert_ne!(natural.sample_bits(2, 0), gray.sample_bits(2, 0));
}

#[test]
fn first_two_dimensions_form_zero_m_two_nets() {
    for order in [DigitalOrder::Natural, DigitalOrder::GrayCode] {
        let sobol = Sobol::new(2, order).unwrap();
        for m in 0..=14 {
            let points: Vec<(u32, u32)> = (0..1u64 << m)
                .map(|index| (sobol.sample_bits(index, 0), sobol.sample_bits(index, 1)))
                .collect();
            assert!(is_zero_m_two_net(&points, m), "{order:?}, m = {m}");
            // Consecutive blocks of 2^m points are nets too ((0, 2)-sequence).
            let block: Vec<(u32, u32)> = (5u64 << m..6u64 << m)
                .map(|index| (sobol.sample_bits(index, 0), sobol.sample_bits(index, 1)))
                .collect();
            assert!(is_zero_m_two_net(&block, m), "{order:?}, m = {m}, block 5");
        }
    }
}

#[test]
fn every_dimension_is_a_zero_one_sequence() {
    // Each one-dimensional projection has one point in every interval of 2^-m.
    let sobol = Sobol::new(300, DigitalOrder::GrayCode).unwrap();
    let m = 10;
    for dimension in 0..300 {
        let mut seen = vec![false; 1 << m];
        for index in 0..1u64 << m {
            let cell = (sobol.sample_bits(index, dimension) >> (32 - m)) as usize;
            assert!(
                !std::mem::replace(&mut seen[cell], true),
                "dimension {dimension}"
            );
        }
    }
}

#[test]
fn construction_of_few_dimensions_is_cheap() {
    // Only the requested lines are parsed: building a 2-dimensional sequence many
    // times must not scan the whole 1.9 MB file each time. (A loose bound that only
    // catches an accidental full parse per construction.)
    let start = std::time::Instant::now();
    for _ in 0..1000 {
        std::hint::black_box(Sobol::new(2, DigitalOrder::GrayCode).unwrap());
    }
    assert!(start.elapsed().as_secs_f64() < 1.0, "{:?}", start.elapsed());
}
