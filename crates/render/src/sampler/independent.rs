//! Independent uniform random numbers: the Monte Carlo baseline.

use super::{PixelSampler, SampleSource, pixel_part_of_key, sample_key_in_pixel};
use qmc::hash::mix64;
use qmc::random::u32_to_unit_f32;

/// The increment of SplitMix64's state (2⁶⁴ / φ, odd), the "golden gamma"
/// of Steele, Lea and Flood (2014).
const SPLITMIX_GAMMA: u64 = 0x9E37_79B9_7F4A_7C15;

/// Each pixel sample has its own stream of numbers, keyed by hashing the
/// seed, the pixel and the sample index; dimension `d` is output `d + 1` of
/// SplitMix64 (Steele, Lea and Flood 2014, "Fast splittable pseudorandom
/// number generators") started at that key: the finaliser
/// [`qmc::hash::mix64`] of `key + d γ`. The generator is counter-based, so
/// any dimension costs the same dozen instructions in any order (a seekable
/// PCG stream needed a logarithmic jump for every out-of-order dimension,
/// which is most of them in a path's dimension layout). SplitMix64 passes
/// BigCrush; the top 24 bits of each output make the `f32`.
#[derive(Debug, Clone)]
pub struct IndependentSampler {
    seed: u64,
    /// The key of the current pixel sample.
    key: u64,
    /// The pixel of the current sample and the part of its key that does
    /// not depend on the sample index (see [`IndependentSampler::pixel_part`]).
    pixel: Option<((u32, u32), u64)>,
}

impl IndependentSampler {
    /// A sampler whose numbers are determined by `seed`.
    pub fn new(seed: u64) -> Self {
        Self {
            seed,
            key: seed,
            pixel: None,
        }
    }

    /// [`pixel_part_of_key`] of `pixel`. A tile renders the samples of a pass pixel by pixel, so the part is
    /// kept and computed again only when the pixel changes: that saves two
    /// of the key's four SplitMix64 finalisers for all but the first sample
    /// of each pixel (about 26 instructions per path).
    #[inline]
    fn pixel_part(&mut self, pixel: (u32, u32)) -> u64 {
        match self.pixel {
            Some((kept, part)) if kept == pixel => part,
            _ => {
                let part = pixel_part_of_key(self.seed, pixel);
                self.pixel = Some((pixel, part));
                part
            }
        }
    }
}

impl SampleSource for IndependentSampler {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        let counter = self
            .key
            .wrapping_add((dimension as u64).wrapping_mul(SPLITMIX_GAMMA));
        u32_to_unit_f32((mix64(counter) >> 32) as u32)
    }
}

impl PixelSampler for IndependentSampler {
    #[inline]
    fn start_pixel_sample(&mut self, pixel: (u32, u32), sample_index: u64) {
        // `pixel_sample_key` with its pixel part kept.
        self.key = sample_key_in_pixel(self.pixel_part(pixel), sample_index);
    }

    fn clone_sampler(&self) -> Box<dyn PixelSampler> {
        Box::new(self.clone())
    }

    fn name(&self) -> String {
        "independent".into()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::layout;
    use crate::statistics::chi_square_test;

    /// Pairs of dimensions a path uses together (film, lens, a vertex's
    /// direction and light position, neighbours across blocks) fill the unit
    /// square uniformly: a chi-square test on a 16 × 16 grid over many pixel
    /// samples (independent numbers make the counts multinomial).
    #[test]
    fn dimension_pairs_are_uniform_and_independent() {
        let mut sampler = IndependentSampler::new(11);
        let samples = 40_000u64;
        let pairs = [
            (layout::FILM, layout::FILM + 1),
            (layout::WAVELENGTH, layout::vertex(0, 0)),
            (
                layout::vertex(0, layout::SCATTER_DIRECTION),
                layout::vertex(0, layout::SCATTER_DIRECTION + 1),
            ),
            (
                layout::vertex(2, layout::LIGHT_POSITION),
                layout::vertex(2, layout::LIGHT_SELECTION),
            ),
            (layout::vertex(0, 0), layout::vertex(1, 0)),
            (7, 300),
        ];
        const CELLS: usize = 16;
        for (first, second) in pairs {
            let mut counts = vec![0u64; CELLS * CELLS];
            for index in 0..samples {
                sampler.start_pixel_sample(((index % 97) as u32, (index / 97) as u32), index % 3);
                let x = (sampler.get(first) * CELLS as f32) as usize;
                let y = (sampler.get(second) * CELLS as f32) as usize;
                counts[y * CELLS + x] += 1;
            }
            let expected = vec![samples as f64 / (CELLS * CELLS) as f64; CELLS * CELLS];
            let result = chi_square_test(&counts, &expected);
            assert!(
                result.p_value > 1e-4,
                "dimensions {first}, {second}: {result:?}"
            );
        }
    }

    /// The key built from the kept pixel part equals the full hash of the
    /// seed, pixel and index, whatever order pixels and indices come in.
    #[test]
    fn kept_pixel_part_gives_the_full_key() {
        let seed = 9;
        let mut sampler = IndependentSampler::new(seed);
        for (pixel, index) in [
            ((1, 2), 0),
            ((1, 2), 1),
            ((3, 2), 1),
            ((1, 2), 5),
            ((1, 2), 5),
        ] {
            sampler.start_pixel_sample(pixel, index);
            assert_eq!(
                sampler.key,
                crate::sampler::pixel_sample_key(seed, pixel, index)
            );
        }
    }

    #[test]
    fn consecutive_pixel_samples_are_uncorrelated() {
        // The correlation of a dimension between neighbouring sample indices
        // of a pixel has standard deviation 1/sqrt(n) for independent numbers.
        let mut sampler = IndependentSampler::new(5);
        let n = 20_000u64;
        let values: Vec<f64> = (0..=n)
            .map(|index| {
                sampler.start_pixel_sample((3, 3), index);
                f64::from(sampler.get(layout::vertex(1, layout::SCATTER_DIRECTION))) - 0.5
            })
            .collect();
        let covariance: f64 = values.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / n as f64;
        let correlation = covariance * 12.0;
        assert!(
            correlation.abs() < 5.0 / (n as f64).sqrt(),
            "correlation {correlation}"
        );
    }
}
