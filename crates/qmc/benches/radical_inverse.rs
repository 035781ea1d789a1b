//! Nanoseconds per sample and dimension of the radical-inverse generators
//! (Halton in every scramble, Hammersley) and of the pseudo-random ones.
//!
//! Each benchmark computes `POINTS × DIMENSIONS` coordinates per iteration:
//! divide divan's time by 65,536 for ns per sample and dimension.

use divan::{Bencher, black_box};
use qmc::PointSet;
use qmc::halton::{Halton, HaltonScramble};
use qmc::hammersley::Hammersley;
use qmc::random::{MersenneTwister, RandomPoints, SeekablePcg};

const POINTS: u64 = 4096;
const DIMENSIONS: usize = 16;

fn main() {
    divan::main();
}

fn sum_all(set: &dyn PointSet, first_index: u64) -> f64 {
    let mut sum = 0.0;
    for index in first_index..first_index + POINTS {
        for dimension in 0..DIMENSIONS {
            sum += set.sample(index, dimension);
        }
    }
    sum
}

/// Indices start at 0 (`small`) or at 2^32 + 12345 (`large`, as for the
/// per-pixel indices of a large image at many samples per pixel).
#[divan::bench(args = ["none", "faure", "permute", "owen"], consts = [0, 4_294_979_641])]
fn halton<const FIRST_INDEX: u64>(bencher: Bencher, scramble: &str) {
    let scramble = match scramble {
        "none" => HaltonScramble::None,
        "faure" => HaltonScramble::Faure,
        "permute" => HaltonScramble::RandomPermutation,
        _ => HaltonScramble::Owen,
    };
    let set = Halton::new(DIMENSIONS, scramble, 1).unwrap();
    bencher.bench(|| sum_all(black_box(&set), black_box(FIRST_INDEX)));
}

#[divan::bench]
fn hammersley_faure(bencher: Bencher) {
    let set = Hammersley::new(POINTS, DIMENSIONS, HaltonScramble::Faure, 1).unwrap();
    bencher.bench(|| sum_all(black_box(&set), 0));
}

#[divan::bench]
fn random_points_random_access(bencher: Bencher) {
    let set = RandomPoints::new(DIMENSIONS, 1);
    bencher.bench(|| sum_all(black_box(&set), 0));
}

#[divan::bench]
fn random_points_whole_point(bencher: Bencher) {
    let set = RandomPoints::new(DIMENSIONS, 1);
    bencher.bench(|| {
        let mut buffer = [0.0; DIMENSIONS];
        let mut sum = 0.0;
        for index in 0..POINTS {
            set.point(black_box(index), &mut buffer);
            sum += buffer.iter().sum::<f64>();
        }
        sum
    });
}

#[divan::bench]
fn pcg_stream(bencher: Bencher) {
    bencher.bench(|| {
        let mut generator = SeekablePcg::new(black_box(1), 2);
        (0..POINTS as usize * DIMENSIONS)
            .map(|_| generator.next_f64())
            .sum::<f64>()
    });
}

#[divan::bench]
fn mersenne_twister(bencher: Bencher) {
    bencher.bench(|| {
        let mut generator = MersenneTwister::new(black_box(5489));
        (0..POINTS as usize * DIMENSIONS)
            .map(|_| generator.next_f64())
            .sum::<f64>()
    });
}
