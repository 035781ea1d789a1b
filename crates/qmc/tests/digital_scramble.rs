//! Randomized digital sequences: net properties survive every scramble, single
//! points become uniform, and everything is a function of the seed.

use proptest::prelude::*;
use qmc::PointSet;
use qmc::digital_scramble::{DigitalOrder, DigitalScramble, DigitalSequence, Scrambled};
use qmc::niederreiter::Niederreiter;
use qmc::sobol::Sobol;

mod common;
use common::is_zero_m_two_net;

fn first_two_dimensions<S: DigitalSequence>(set: &S, start: u64, m: u32) -> Vec<(u32, u32)> {
    (start..start + (1 << m))
        .map(|index| (set.sample_bits(index, 0), set.sample_bits(index, 1)))
        .collect()
}

fn scramble_strategy() -> impl Strategy<Value = DigitalScramble> {
    prop::sample::select(DigitalScramble::ALL.to_vec())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn scrambled_sobol_keeps_the_zero_m_two_net_property(
        seed in any::<u64>(),
        scramble in scramble_strategy(),
        block in 0u64..16,
    ) {
        let sobol = Sobol::new(2, DigitalOrder::GrayCode).unwrap();
        let scrambled = Scrambled::new(sobol, scramble, seed);
        for m in [1, 4, 7, 10] {
            let points = first_two_dimensions(&scrambled, block << m, m);
            prop_assert!(is_zero_m_two_net(&points, m), "{:?} m = {}", scramble, m);
        }
    }

    #[test]
    fn scrambled_niederreiter_keeps_the_zero_m_two_net_property(
        seed in any::<u64>(),
        scramble in scramble_strategy(),
    ) {
        let sequence = Niederreiter::new(2, DigitalOrder::Natural).unwrap();
        let scrambled = Scrambled::new(sequence, scramble, seed);
        for m in [3, 8] {
            let points = first_two_dimensions(&scrambled, 0, m);
            prop_assert!(is_zero_m_two_net(&points, m), "{:?} m = {}", scramble, m);
        }
    }

    #[test]
    fn scrambled_values_are_deterministic_and_below_one(
        seed in any::<u64>(),
        scramble in scramble_strategy(),
        index in 0u64..(1 << 32),
        dimension in 0usize..6,
    ) {
        let make = || Scrambled::new(Sobol::new(6, DigitalOrder::GrayCode).unwrap(), scramble, seed);
        let (a, b) = (make(), make());
        prop_assert_eq!(a.sample_bits(index, dimension), b.sample_bits(index, dimension));
        let value = a.sample(index, dimension);
        prop_assert!((0.0..1.0).contains(&value));
        prop_assert_eq!(value, f64::from(a.sample_bits(index, dimension)) / 4_294_967_296.0);
    }
}

#[test]
fn the_largest_coordinate_is_strictly_below_one() {
    assert!(qmc::digital_scramble::bits_to_unit(u32::MAX) < 1.0);
}

#[test]
fn different_seeds_give_different_points() {
    for scramble in &DigitalScramble::ALL[1..] {
        let a = Scrambled::new(Sobol::new(3, DigitalOrder::GrayCode).unwrap(), *scramble, 1);
        let b = Scrambled::new(Sobol::new(3, DigitalOrder::GrayCode).unwrap(), *scramble, 2);
        let differing = (0..64u64)
            .filter(|&i| a.sample_bits(i, 2) != b.sample_bits(i, 2))
            .count();
        assert!(differing > 60, "{scramble:?}: {differing}");
    }
}

/// Each randomized scramble makes a single coordinate uniform on [0, 1): over
/// `seeds` independent seeds, the means of x and x² must be within 5 standard
/// errors of 1/2 and 1/3 (Var x = 1/12, Var x² = 1/5 − 1/9 = 4/45).
#[test]
fn randomized_coordinates_are_uniform_over_seeds() {
    let seeds = 4096u64;
    let sobol = Sobol::new(4, DigitalOrder::GrayCode).unwrap();
    for scramble in &DigitalScramble::ALL[1..] {
        for (index, dimension) in [(0u64, 0usize), (1, 1), (77, 3), (1 << 20, 2)] {
            let (mut sum, mut sum_of_squares) = (0.0, 0.0);
            for seed in 0..seeds {
                let x = Scrambled::new(sobol.clone(), *scramble, seed).sample(index, dimension);
                sum += x;
                sum_of_squares += x * x;
            }
            let n = seeds as f64;
            let mean_error = (sum / n - 0.5).abs() / (1.0 / 12.0 / n).sqrt();
            let square_error = (sum_of_squares / n - 1.0 / 3.0).abs() / (4.0 / 45.0 / n).sqrt();
            assert!(
                mean_error < 5.0 && square_error < 5.0,
                "{scramble:?} point {index} dim {dimension}: {mean_error:.2}σ, {square_error:.2}σ"
            );
        }
    }
}

/// Owen scrambling (both variants) makes two points that share their first `k`
/// digits in a coordinate but differ in digit `k + 1` fall in opposite halves of
/// their common interval of length 2^-k, and otherwise independent: in particular
/// the point with the first digit 0 and the one with digit 1 (points 0 and 1 of
/// the sequence) land in different halves of [0, 1) for every seed, and each is
/// in the lower half for about half of the seeds.
#[test]
fn owen_scrambles_keep_halves_apart_and_pick_them_at_random() {
    let sobol = Sobol::new(2, DigitalOrder::GrayCode).unwrap();
    for scramble in [DigitalScramble::HashOwen, DigitalScramble::NestedUniform] {
        let seeds = 2000u64;
        let mut lower = 0u64;
        for seed in 0..seeds {
            let scrambled = Scrambled::new(sobol.clone(), scramble, seed);
            let (a, b) = (scrambled.sample_bits(0, 1), scrambled.sample_bits(1, 1));
            assert_ne!(a >> 31, b >> 31);
            lower += u64::from(a >> 31 == 0);
        }
        // Binomial(2000, 1/2): standard deviation √500 ≈ 22.4; allow 5σ.
        let deviation = (lower as f64 - 1000.0).abs();
        assert!(deviation < 5.0 * 500f64.sqrt(), "{scramble:?}: {lower}");
    }
}

/// `PointSet::sample` takes inlined table paths for Sobol's first
/// `TABLED_DIMENSIONS` dimensions (hash-based Owen without bit reversals);
/// they must give exactly the coordinates of the digits, in every scramble,
/// order and dimension, tabled or not.
#[test]
fn fast_sample_paths_equal_the_scrambled_digits() {
    use qmc::digital_scramble::bits_to_unit;
    use qmc::sobol::TABLED_DIMENSIONS;
    let dimensions = TABLED_DIMENSIONS + 2;
    for order in [DigitalOrder::Natural, DigitalOrder::GrayCode] {
        for scramble in DigitalScramble::ALL {
            let scrambled = Scrambled::new(Sobol::new(dimensions, order).unwrap(), scramble, 77);
            let mut state = 0x9E37_79B9_7F4A_7C15u64;
            for step in 0..300u64 {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1);
                for index in [step, state >> 32] {
                    for dimension in (0..dimensions).step_by(7).chain([dimensions - 1]) {
                        assert_eq!(
                            scrambled.sample(index, dimension).to_bits(),
                            bits_to_unit(scrambled.sample_bits(index, dimension)).to_bits(),
                            "{order:?} {scramble:?} index {index} dimension {dimension}"
                        );
                    }
                }
            }
        }
    }
}
