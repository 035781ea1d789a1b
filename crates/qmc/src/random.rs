//! Pseudo-random numbers: a seekable PCG stream per pixel and sample, the
//! Mersenne Twister MT19937 (which the LQMC paper uses past the 256 Halton
//! dimensions), and independent uniform random points as a [`PointSet`].

use crate::hash::{hash2, mix64};
use crate::point_set::PointSet;
use rand_core::Rng;
use rand_mt::Mt;
use rand_pcg::Pcg32;

/// Converts 32 random bits to a uniform `f32` in `[0, 1)` (top 24 bits).
#[inline]
pub fn u32_to_unit_f32(bits: u32) -> f32 {
    (bits >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// Converts 64 random bits to a uniform `f64` in `[0, 1)` (top 53 bits).
#[inline]
pub fn u64_to_unit_f64(bits: u64) -> f64 {
    (bits >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
}

/// A PCG32 generator (O'Neill 2014, XSH-RR output on a 64-bit LCG) that can
/// jump to any position of its stream in O(log n) steps, so that every pixel
/// and sample can have its own reproducible stream, independent of the order
/// in which they are computed.
#[derive(Debug, Clone)]
pub struct SeekablePcg {
    generator: Pcg32,
    start: Pcg32,
}

impl SeekablePcg {
    /// The stream chosen by `(seed, stream)`; different streams use different
    /// LCG increments, so they are distinct sequences, not offsets of one.
    pub fn new(seed: u64, stream: u64) -> Self {
        let generator = Pcg32::new(mix64(seed), hash2(seed, stream));
        Self {
            start: generator.clone(),
            generator,
        }
    }

    /// Moves to `position` numbers after the start of the stream.
    pub fn seek(&mut self, position: u64) {
        self.generator = self.start.clone();
        self.generator.advance(position);
    }

    /// Skips `count` numbers.
    pub fn advance(&mut self, count: u64) {
        self.generator.advance(count);
    }

    /// The next 32 random bits.
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        self.generator.next_u32()
    }

    /// The next uniform `f32` in `[0, 1)` (one number of the stream).
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        u32_to_unit_f32(self.next_u32())
    }

    /// The next uniform `f64` in `[0, 1)` (two numbers of the stream).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        let high = self.next_u32() as u64;
        let low = self.next_u32() as u64;
        u64_to_unit_f64((high << 32) | low)
    }
}

/// The Mersenne Twister MT19937 (Matsumoto & Nishimura 1998).
#[derive(Debug, Clone)]
pub struct MersenneTwister {
    generator: Mt,
}

impl MersenneTwister {
    /// The generator with the standard 32-bit seeding (`init_genrand`).
    pub fn new(seed: u32) -> Self {
        Self {
            generator: Mt::new(seed),
        }
    }

    /// The next 32 random bits (`genrand_int32`).
    #[inline]
    pub fn next_u32(&mut self) -> u32 {
        self.generator.next_u32()
    }

    /// The next uniform `f32` in `[0, 1)`.
    #[inline]
    pub fn next_f32(&mut self) -> f32 {
        u32_to_unit_f32(self.next_u32())
    }

    /// The next uniform `f64` in `[0, 1)` with 53-bit resolution from two
    /// outputs (`genrand_res53` of the reference implementation).
    #[inline]
    pub fn next_f64(&mut self) -> f64 {
        let a = (self.next_u32() >> 5) as f64;
        let b = (self.next_u32() >> 6) as f64;
        (a * 67_108_864.0 + b) * (1.0 / 9_007_199_254_740_992.0)
    }
}

/// Independent uniform random points: coordinate `d` of point `i` is the
/// `d`-th number of the PCG stream `(seed, i)`, so any coordinate can be
/// drawn directly and the set is the same whatever the evaluation order.
#[derive(Debug, Clone)]
pub struct RandomPoints {
    dimensions: usize,
    seed: u64,
}

impl RandomPoints {
    /// Random points with `dimensions` coordinates from `seed`.
    pub fn new(dimensions: usize, seed: u64) -> Self {
        Self { dimensions, seed }
    }
}

impl PointSet for RandomPoints {
    fn dimensions(&self) -> usize {
        self.dimensions
    }

    fn len(&self) -> Option<u64> {
        None
    }

    fn sample(&self, index: u64, dimension: usize) -> f64 {
        let mut stream = SeekablePcg::new(self.seed, index);
        stream.advance(2 * dimension as u64);
        stream.next_f64()
    }

    fn point(&self, index: u64, out: &mut [f64]) {
        let mut stream = SeekablePcg::new(self.seed, index);
        for value in out.iter_mut() {
            *value = stream.next_f64();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mersenne_twister_reference_output() {
        // The reference implementation's first output for seed 5489 is 3499211612;
        // the 10000th is 4123659995 (C++ std::mt19937 requirement).
        let mut generator = MersenneTwister::new(5489);
        assert_eq!(generator.next_u32(), 3_499_211_612);
        for _ in 1..9999 {
            generator.next_u32();
        }
        assert_eq!(generator.next_u32(), 4_123_659_995);
    }

    #[test]
    fn seeking_equals_stepping() {
        let mut stepped = SeekablePcg::new(7, 3);
        let values: Vec<u32> = (0..100).map(|_| stepped.next_u32()).collect();
        let mut sought = SeekablePcg::new(7, 3);
        for position in [0usize, 1, 17, 99, 50] {
            sought.seek(position as u64);
            assert_eq!(sought.next_u32(), values[position]);
        }
    }

    #[test]
    fn streams_differ() {
        let mut first = SeekablePcg::new(1, 0);
        let mut second = SeekablePcg::new(1, 1);
        let a: Vec<u32> = (0..4).map(|_| first.next_u32()).collect();
        let b: Vec<u32> = (0..4).map(|_| second.next_u32()).collect();
        assert_ne!(a, b);
    }

    #[test]
    fn random_points_are_order_independent_and_uniform() {
        let points = RandomPoints::new(5, 11);
        let mut buffer = [0.0; 5];
        points.point(42, &mut buffer);
        for (dimension, &value) in buffer.iter().enumerate() {
            assert_eq!(points.sample(42, dimension), value);
        }
        // Mean of n uniforms: standard error √(1/(12 n)).
        let n = 50_000;
        let mean = (0..n).map(|i| points.sample(i, 3)).sum::<f64>() / n as f64;
        assert!((mean - 0.5).abs() < 5.0 * (1.0 / (12.0 * n as f64)).sqrt());
    }

    #[test]
    fn unit_conversions_stay_below_one() {
        assert!(u32_to_unit_f32(u32::MAX) < 1.0);
        assert!(u64_to_unit_f64(u64::MAX) < 1.0);
    }
}
