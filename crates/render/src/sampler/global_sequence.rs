//! One base-2 digital sequence (Sobol or Niederreiter) for the whole image,
//! each pixel taking its own consecutive subsequence: Kollig & Keller's
//! quasi-Monte Carlo bidirectional path tracing (Sect. 3.1), where every
//! pixel must see different light subpaths, which a finite point set
//! repeated in every pixel would not give.

use super::{PixelSampler, Randomization, SampleSource, pixel_sample_key, to_f32};
use qmc::digital_scramble::{DigitalSequence, bits_to_unit, hash_owen_scramble_reversed};
use qmc::hash::hash2;
use qmc::random::SeekablePcg;
use std::sync::Arc;

/// Hashed with the seed into the seed of the sequence's Owen scrambling.
const SEQUENCE_SCRAMBLE_TAG: u64 = 0x474C_4F42_414C_5351;

/// Sample `j` of pixel `p` (row-major number `p`) is point
/// `p · N + j` of the sequence, `N` the samples per pixel rounded up to a
/// power of two (at most the largest power of two with `pixels · N ≤ 2^32`,
/// the sequences' length, which is also `N` under a time budget): a pixel's samples are a block of `N` consecutive points
/// starting at a multiple of `N`, so their first `N` points are a
/// (t, log₂N, s)-net (in dimensions 0 and 1 a (0, log₂N, 2)-net, stratifying
/// the pixel). Samples past `N` (a time budget) and dimensions past the
/// sequence's come from a PCG stream per pixel sample.
///
/// With [`Randomization::Seeded`] the whole sequence is Owen-scrambled
/// (hash-based, one scramble per dimension keyed by the seed), which keeps
/// every net a net and makes each point uniform: renders with different
/// seeds are independent replications. With [`Randomization::None`] it is
/// the deterministic sequence, as the paper's QMC.
#[derive(Clone)]
pub struct GlobalSequenceSampler {
    sequence: Arc<dyn DigitalSequence>,
    name: &'static str,
    /// Per dimension, the Owen scramble's seed (none without randomization).
    scramble_seeds: Option<Arc<[u32]>>,
    block_size: u64,
    width: u64,
    seed: u64,
    index: Option<u64>,
    fallback: SeekablePcg,
}

impl GlobalSequenceSampler {
    /// The sampler over `sequence` (named `name`) for an image of
    /// `width × height` pixels and `samples_per_pixel` samples, randomized
    /// by `seed` as `randomization` says.
    pub fn new(
        sequence: Arc<dyn DigitalSequence>,
        name: &'static str,
        (width, height): (u32, u32),
        samples_per_pixel: u64,
        seed: u64,
        randomization: Randomization,
    ) -> Self {
        let scramble_seeds = match randomization {
            Randomization::Seeded => {
                let key = hash2(seed, SEQUENCE_SCRAMBLE_TAG);
                Some(
                    (0..sequence.dimensions())
                        .map(|dimension| (hash2(key, dimension as u64) >> 32) as u32)
                        .collect(),
                )
            }
            Randomization::None => None,
        };
        // Every pixel's block must fit below 2^32 points: a time budget's
        // unlimited samples per pixel get the largest block that does.
        let pixel_count = (u64::from(width.max(1)) * u64::from(height.max(1))).next_power_of_two();
        let largest_block = ((1u64 << 32) / pixel_count).max(1);
        Self {
            sequence,
            name,
            scramble_seeds,
            block_size: samples_per_pixel
                .clamp(1, largest_block)
                .next_power_of_two()
                .min(largest_block),
            width: u64::from(width.max(1)),
            seed,
            index: None,
            fallback: SeekablePcg::new(seed, 0),
        }
    }
}

impl SampleSource for GlobalSequenceSampler {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        match self.index {
            Some(index) if dimension < self.sequence.dimensions() => {
                let reversed = self.sequence.sample_bits_reversed(index, dimension);
                let bits = match &self.scramble_seeds {
                    Some(seeds) => hash_owen_scramble_reversed(reversed, seeds[dimension]),
                    None => reversed.reverse_bits(),
                };
                to_f32(bits_to_unit(bits))
            }
            _ => {
                self.fallback.seek(dimension as u64);
                self.fallback.next_f32()
            }
        }
    }
}

impl PixelSampler for GlobalSequenceSampler {
    fn start_pixel_sample(&mut self, pixel: (u32, u32), sample_index: u64) {
        let pixel_number = u64::from(pixel.1) * self.width + u64::from(pixel.0);
        // Indices stay below 2^32, the digital sequences' limit.
        self.index = pixel_number
            .checked_mul(self.block_size)
            .map(|start| start + sample_index)
            .filter(|&index| sample_index < self.block_size && index < 1 << 32);
        self.fallback =
            SeekablePcg::new(self.seed, pixel_sample_key(self.seed, pixel, sample_index));
    }

    fn clone_sampler(&self) -> Box<dyn PixelSampler> {
        Box::new(self.clone())
    }

    fn name(&self) -> String {
        self.name.into()
    }
}
