//! Speed of base-2 digital sequences and their randomizations, per coordinate.
//!
//! Every benchmark evaluates 4096 points × 16 dimensions by index through
//! `PointSet::sample` (the way the renderer asks for coordinates), so
//! ns per sample and dimension = reported time / 65536.

use divan::{Bencher, black_box};
use qmc::PointSet;
use qmc::digital_scramble::{DigitalOrder, DigitalScramble, Scrambled};
use qmc::niederreiter::Niederreiter;
use qmc::sobol::Sobol;

const POINTS: u64 = 4096;
const DIMENSIONS: usize = 16;
const SEED: u64 = 0x5EED;

fn main() {
    divan::main();
}

/// Sums every coordinate of the 4096 × 16 block so nothing is optimised away.
fn sum_block(set: &dyn PointSet) -> f64 {
    let mut sum = 0.0;
    for index in 0..POINTS {
        for dimension in 0..DIMENSIONS {
            sum += set.sample(black_box(index), dimension);
        }
    }
    sum
}

fn sobol() -> Sobol {
    Sobol::new(DIMENSIONS, DigitalOrder::GrayCode).unwrap()
}

#[divan::bench]
fn sobol_plain(bencher: Bencher) {
    let set = sobol();
    bencher.bench(|| sum_block(&set));
}

#[divan::bench(args = [
    DigitalScramble::None,
    DigitalScramble::XorShift,
    DigitalScramble::HashOwen,
    DigitalScramble::NestedUniform,
    DigitalScramble::LinearMatrix,
])]
fn sobol_scrambled(bencher: Bencher, scramble: DigitalScramble) {
    let set = Scrambled::new(sobol(), scramble, SEED);
    bencher.bench(|| sum_block(&set));
}

#[divan::bench]
fn niederreiter_plain(bencher: Bencher) {
    let set = Niederreiter::new(DIMENSIONS, DigitalOrder::GrayCode).unwrap();
    bencher.bench(|| sum_block(&set));
}

#[divan::bench]
fn sobol_gray_code_walker(bencher: Bencher) {
    let set = sobol();
    bencher.bench(|| {
        let mut walker = set.gray_code_walker(0);
        let mut sum = 0u64;
        for _ in 0..POINTS {
            sum += walker
                .current()
                .iter()
                .map(|&bits| u64::from(bits))
                .sum::<u64>();
            walker.advance();
        }
        sum
    });
}

#[divan::bench(args = [2usize, 16, 1000, 21201])]
fn sobol_construction(dimensions: usize) -> Sobol {
    Sobol::new(black_box(dimensions), DigitalOrder::GrayCode).unwrap()
}
