//! The Sobol sampler: each pixel gets its own hash-based Owen scrambling of
//! the Sobol sequence (Burley 2020), indexed by the pixel's sample number.

use super::pixel_randomization::PixelRandomization;
use super::{PixelSampler, Randomization, SampleSource, to_f32};
use qmc::digital_scramble::{
    DigitalOrder, DigitalSequence, bits_to_unit, hash_owen_scramble_reversed,
};
use qmc::sobol::{MAX_POINTS, Sobol};
use std::sync::Arc;

/// Dimensions served by the Sobol sequence; later ones (and sample indices
/// beyond 2^32) come from a PCG stream.
pub const SOBOL_DIMENSIONS: usize = 1024;

/// Owen-scrambled Sobol per pixel.
///
/// Sample `j` of a pixel is Sobol point `j`, every dimension scrambled with
/// its own seed `hash(seed, pixel, dimension)` (seed 0 with
/// [`Randomization::None`]): each pixel's samples are an
/// independent randomization of the same (t, s)-sequence, so every pixel's
/// estimate is unbiased and its first `2^m` samples keep the net's
/// stratification in every 2-D projection of consecutive Sobol dimensions.
#[derive(Debug, Clone)]
pub struct SobolSampler {
    sobol: Arc<Sobol>,
    randomization: PixelRandomization,
}

impl SobolSampler {
    /// The sampler with randomization chosen by `seed`. With `pattern_size`
    /// `m`, a pixel's samples are replications of the first `m` Sobol
    /// points, each Owen-scrambled on its own (Kollig & Keller, Sect. 4.2).
    pub fn new(seed: u64, randomization: Randomization, pattern_size: Option<u64>) -> Self {
        let sobol = Sobol::new(SOBOL_DIMENSIONS, DigitalOrder::Natural)
            .expect("1024 Sobol dimensions are supported");
        Self {
            sobol: Arc::new(sobol),
            randomization: PixelRandomization::new(seed, randomization, pattern_size),
        }
    }
}

impl SampleSource for SobolSampler {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        let index = self.randomization.index();
        if dimension < SOBOL_DIMENSIONS && index < MAX_POINTS {
            let scramble_seed = (self.randomization.dimension_hash(dimension) >> 32) as u32;
            let bits = hash_owen_scramble_reversed(
                self.sobol.sample_bits_reversed(index, dimension),
                scramble_seed,
            );
            to_f32(bits_to_unit(bits))
        } else {
            self.randomization.fallback(dimension)
        }
    }
}

impl PixelSampler for SobolSampler {
    fn start_pixel_sample(&mut self, pixel: (u32, u32), sample_index: u64) {
        self.randomization.start(pixel, sample_index);
    }

    fn clone_sampler(&self) -> Box<dyn PixelSampler> {
        Box::new(self.clone())
    }

    fn name(&self) -> String {
        "sobol".into()
    }
}
