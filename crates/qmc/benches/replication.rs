//! Nanoseconds per sample and dimension of padded replications sampling and
//! Latin supercube sampling (Kollig & Keller §4.3 and §5) of a 2-D
//! Hammersley basis pattern, and of a Cranley–Patterson-rotated Halton set.
//!
//! Each iteration computes 4096 points × 16 dimensions: divide by 65,536.

use divan::{Bencher, black_box};
use qmc::PointSet;
use qmc::cranley_patterson::CranleyPatterson;
use qmc::halton::{Halton, HaltonScramble};
use qmc::hammersley::Hammersley;
use qmc::padded::{BlockLayout, BlockRandomization, PaddedPointSet};

const POINTS: u64 = 4096;
const DIMENSIONS: usize = 16;

fn main() {
    divan::main();
}

fn sum_all(set: &dyn PointSet) -> f64 {
    let mut sum = 0.0;
    for index in 0..POINTS {
        for dimension in 0..DIMENSIONS {
            sum += set.sample(index, dimension);
        }
    }
    sum
}

fn basis() -> Box<dyn PointSet> {
    Box::new(Hammersley::new(POINTS, 2, HaltonScramble::None, 0).unwrap())
}

#[divan::bench]
fn padded_replications(bencher: Bencher) {
    let layout = BlockLayout::uniform(2, DIMENSIONS).unwrap();
    let set = PaddedPointSet::padded_replications(
        basis(),
        layout,
        BlockRandomization::CranleyPatterson,
        1,
        0,
    )
    .unwrap();
    bencher.bench(|| sum_all(black_box(&set)));
}

#[divan::bench]
fn latin_supercube(bencher: Bencher) {
    let layout = BlockLayout::uniform(2, DIMENSIONS).unwrap();
    let set = PaddedPointSet::latin_supercube(
        basis(),
        layout,
        BlockRandomization::CranleyPatterson,
        1,
        0,
    )
    .unwrap();
    bencher.bench(|| sum_all(black_box(&set)));
}

#[divan::bench]
fn halton_cranley_patterson(bencher: Bencher) {
    let set =
        CranleyPatterson::from_seed(Halton::new(DIMENSIONS, HaltonScramble::None, 0).unwrap(), 1);
    bencher.bench(|| sum_all(black_box(&set)));
}
