//! Independent uniform random numbers: the Monte Carlo baseline.

use super::{PixelSampler, SampleSource, pixel_sample_key};
use qmc::random::SeekablePcg;

/// Each pixel sample has its own PCG stream (chosen by hashing the seed,
/// pixel and sample index); dimension `d` is the `d`-th number of the stream,
/// reached by stepping when dimensions are asked in order and by seeking
/// otherwise.
#[derive(Debug, Clone)]
pub struct IndependentSampler {
    seed: u64,
    stream: SeekablePcg,
    /// The dimension the stream will produce next.
    next_dimension: usize,
}

impl IndependentSampler {
    /// A sampler whose numbers are determined by `seed`.
    pub fn new(seed: u64) -> Self {
        Self {
            seed,
            stream: SeekablePcg::new(seed, 0),
            next_dimension: 0,
        }
    }
}

impl SampleSource for IndependentSampler {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        if dimension != self.next_dimension {
            self.stream.seek(dimension as u64);
        }
        self.next_dimension = dimension + 1;
        self.stream.next_f32()
    }
}

impl PixelSampler for IndependentSampler {
    fn start_pixel_sample(&mut self, pixel: (u32, u32), sample_index: u64) {
        self.stream = SeekablePcg::new(self.seed, pixel_sample_key(self.seed, pixel, sample_index));
        self.next_dimension = 0;
    }

    fn clone_sampler(&self) -> Box<dyn PixelSampler> {
        Box::new(self.clone())
    }

    fn name(&self) -> String {
        "independent".into()
    }
}
