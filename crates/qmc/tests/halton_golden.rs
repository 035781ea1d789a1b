//! The Halton sequence against values printed by scipy and qmcpy
//! (`scripts/golden/halton.py`).

use qmc::PointSet;
use qmc::halton::{Halton, HaltonScramble};

#[allow(dead_code)]
mod golden {
    include!("golden/halton.rs");
}

/// Plain radical inverses are correctly rounded for small indices; allow one
/// unit in the last place against other implementations' rounding.
fn assert_close(actual: f64, expected: f64, context: &str) {
    assert!(
        (actual - expected).abs() <= 2.0 * f64::EPSILON * expected.max(f64::MIN_POSITIVE),
        "{context}: {actual} vs {expected}"
    );
}

#[test]
fn matches_scipy_first_64_points_in_12_dimensions() {
    let dimensions = golden::SCIPY_DIMENSIONS;
    let halton = Halton::new(dimensions, HaltonScramble::None, 0).unwrap();
    for (flat, &expected) in golden::SCIPY_HALTON_12D_64.iter().enumerate() {
        let (index, dimension) = (flat / dimensions, flat % dimensions);
        let actual = halton.sample(index as u64, dimension);
        assert_close(actual, expected, &format!("point {index} dim {dimension}"));
    }
}

#[test]
fn matches_scipy_in_all_1024_bases() {
    let halton = Halton::new(1024, HaltonScramble::None, 0).unwrap();
    for (flat, &expected) in golden::SCIPY_HALTON_1024D_FROM_1000.iter().enumerate() {
        let (index, dimension) = (1000 + flat / 1024, flat % 1024);
        let actual = halton.sample(index as u64, dimension);
        assert_close(actual, expected, &format!("point {index} dim {dimension}"));
    }
}

#[test]
fn matches_qmcpy_first_32_points_in_6_dimensions() {
    let halton = Halton::new(6, HaltonScramble::None, 0).unwrap();
    for (flat, &expected) in golden::QMCPY_HALTON_6D_32.iter().enumerate() {
        let (index, dimension) = (flat / 6, flat % 6);
        let actual = halton.sample(index as u64, dimension);
        assert_close(actual, expected, &format!("point {index} dim {dimension}"));
    }
}
