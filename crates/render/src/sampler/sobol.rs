//! The Sobol sampler: each pixel gets its own hash-based Owen scrambling of
//! the Sobol sequence (Burley 2020), indexed by the pixel's sample number.

use super::{PixelSampler, SampleSource, to_f32};
use qmc::digital_scramble::{
    DigitalOrder, DigitalSequence, bits_to_unit, hash_owen_scramble_reversed,
};
use qmc::hash::{hash2, hash3};
use qmc::random::SeekablePcg;
use qmc::sobol::{MAX_POINTS, Sobol};
use std::sync::Arc;

/// Dimensions served by the Sobol sequence; later ones (and sample indices
/// beyond 2^32) come from a PCG stream.
pub const SOBOL_DIMENSIONS: usize = 1024;

/// Owen-scrambled Sobol per pixel.
///
/// Sample `j` of a pixel is Sobol point `j`, every dimension scrambled with
/// its own seed `hash(seed, pixel, dimension)`: each pixel's samples are an
/// independent randomization of the same (t, s)-sequence, so every pixel's
/// estimate is unbiased and its first `2^m` samples keep the net's
/// stratification in every 2-D projection of consecutive Sobol dimensions.
#[derive(Debug, Clone)]
pub struct SobolSampler {
    sobol: Arc<Sobol>,
    seed: u64,
    pixel_seed: u64,
    index: u64,
    fallback: SeekablePcg,
}

impl SobolSampler {
    /// The sampler with randomization chosen by `seed`.
    pub fn new(seed: u64) -> Self {
        let sobol = Sobol::new(SOBOL_DIMENSIONS, DigitalOrder::Natural)
            .expect("1024 Sobol dimensions are supported");
        Self {
            sobol: Arc::new(sobol),
            seed,
            pixel_seed: 0,
            index: 0,
            fallback: SeekablePcg::new(seed, 0),
        }
    }
}

impl SampleSource for SobolSampler {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        if dimension < SOBOL_DIMENSIONS && self.index < MAX_POINTS {
            let scramble_seed = (hash2(self.pixel_seed, dimension as u64) >> 32) as u32;
            let bits = hash_owen_scramble_reversed(
                self.sobol.sample_bits_reversed(self.index, dimension),
                scramble_seed,
            );
            to_f32(bits_to_unit(bits))
        } else {
            self.fallback.seek(dimension as u64);
            self.fallback.next_f32()
        }
    }
}

impl PixelSampler for SobolSampler {
    fn start_pixel_sample(&mut self, pixel: (u32, u32), sample_index: u64) {
        let pixel_key = ((pixel.0 as u64) << 32) | pixel.1 as u64;
        self.pixel_seed = hash2(self.seed, pixel_key);
        self.index = sample_index;
        self.fallback = SeekablePcg::new(self.seed, hash3(self.seed, pixel_key, sample_index));
    }

    fn clone_sampler(&self) -> Box<dyn PixelSampler> {
        Box::new(self.clone())
    }

    fn name(&self) -> String {
        "sobol".into()
    }
}
