//! A fixed workload for counting instructions per sample and dimension
//! (host timings on a shared machine are noisy; instruction counts are not).
//!
//! `cargo run --release -p qmc --example sample_cost -- GENERATOR REPETITIONS`
//! draws `REPETITIONS` times the benchmarks' block of 4096 points × 16
//! dimensions through `&dyn PointSet::sample` and prints the sum. Run it under
//! `valgrind --tool=callgrind` with two repetition counts: the difference of
//! the instruction counts divided by 65,536 × the difference of the
//! repetitions is the cost of one coordinate, construction excluded.
//! With a third argument `time`, prints the minimum and the median time
//! per sample and dimension over the repetitions instead.
//! Generators: `halton-none`, `halton-faure`, `halton-permute`, `sobol`,
//! `sobol-hash-owen`, `sobol-xor-shift`, `sobol-linear-matrix`.

use qmc::PointSet;
use qmc::digital_scramble::{DigitalOrder, DigitalScramble, Scrambled};
use qmc::halton::{Halton, HaltonScramble};
use qmc::sobol::Sobol;
use std::hint::black_box;

const POINTS: u64 = 4096;
const DIMENSIONS: usize = 16;

fn sum_all(set: &dyn PointSet) -> f64 {
    let mut sum = 0.0;
    for index in 0..POINTS {
        for dimension in 0..DIMENSIONS {
            sum += set.sample(black_box(index), dimension);
        }
    }
    sum
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut arguments = std::env::args().skip(1);
    let generator = arguments.next().unwrap_or_else(|| "halton-none".into());
    let repetitions: u32 = arguments.next().unwrap_or_else(|| "1".into()).parse()?;
    let set: Box<dyn PointSet> = match generator.as_str() {
        "halton-none" => Box::new(Halton::new(DIMENSIONS, HaltonScramble::None, 1)?),
        "halton-faure" => Box::new(Halton::new(DIMENSIONS, HaltonScramble::Faure, 1)?),
        "halton-permute" => Box::new(Halton::new(
            DIMENSIONS,
            HaltonScramble::RandomPermutation,
            1,
        )?),
        "sobol" => Box::new(Sobol::new(DIMENSIONS, DigitalOrder::GrayCode)?),
        "sobol-hash-owen" => Box::new(Scrambled::new(
            Sobol::new(DIMENSIONS, DigitalOrder::GrayCode)?,
            DigitalScramble::HashOwen,
            0x5EED,
        )),
        "sobol-xor-shift" => Box::new(Scrambled::new(
            Sobol::new(DIMENSIONS, DigitalOrder::GrayCode)?,
            DigitalScramble::XorShift,
            0x5EED,
        )),
        "sobol-linear-matrix" => Box::new(Scrambled::new(
            Sobol::new(DIMENSIONS, DigitalOrder::GrayCode)?,
            DigitalScramble::LinearMatrix,
            0x5EED,
        )),
        other => return Err(format!("unknown generator {other:?}").into()),
    };
    let timed = arguments.next().as_deref() == Some("time");
    let mut total = 0.0;
    let mut nanoseconds = Vec::with_capacity(repetitions as usize);
    for _ in 0..repetitions {
        let start = std::time::Instant::now();
        total += sum_all(black_box(&*set));
        nanoseconds.push(start.elapsed().as_nanos() as f64 / (POINTS as f64 * DIMENSIONS as f64));
    }
    if timed {
        // The minimum is the least disturbed by other processes.
        nanoseconds.sort_by(f64::total_cmp);
        let median = nanoseconds[nanoseconds.len() / 2];
        println!(
            "{generator}: ns per sample and dimension: min {:.2}, median {median:.2}",
            nanoseconds[0]
        );
    } else {
        println!("{generator}: {total}");
    }
    Ok(())
}
