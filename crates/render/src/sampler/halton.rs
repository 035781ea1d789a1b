//! The Halton sampler of the LQMC paper: the Faure-permuted Halton sequence
//! enumerated per pixel (Grünschloß, Raab & Keller 2012) for the first
//! [`HALTON_DIMENSIONS`] dimensions, then MT19937; randomized by the seed
//! with a random digital shift per dimension and digit position.

use super::{PixelSampler, Randomization, SampleSource, pixel_sample_key, to_f32};
use qmc::PointSet;
use qmc::halton::{Halton, HaltonScramble, PixelEnumeration, PixelOffsetTable};
use qmc::hash::hash2;
use qmc::random::MersenneTwister;
use std::sync::Arc;

/// Dimensions served by the Halton sequence; later ones come from a
/// Mersenne Twister seeded per pixel sample, as in the LQMC paper.
pub const HALTON_DIMENSIONS: usize = 256;

/// Hashed with the seed into the seed of the digital shifts.
const HALTON_SHIFT_TAG: u64 = 0x4841_4C54_4F4E_5348;

/// Faure-permuted Halton, per-pixel enumeration.
///
/// Sample `j` of pixel `(x, y)` is the global Halton point
/// `offset(x, y) + j · 2^a 3^b`; its dimensions 0 and 1 (bases 2 and 3,
/// unpermuted) are scaled to raster units and the pixel corner subtracted,
/// so they stratify the pixel. The image-wide sequence is one
/// low-discrepancy sequence, as Kollig & Keller require to avoid
/// correlation between pixels.
///
/// With [`Randomization::Seeded`] every dimension's digits, after Faure's
/// permutation, get a random digital shift in base b per digit position
/// keyed by the seed ([`HaltonScramble::FaureShifted`]): each pixel
/// sample's point is uniform (the film position uniform in its pixel, as
/// the enumeration inverts the shifts of dimensions 0 and 1), every
/// elementary interval keeps its points, and different seeds are
/// independent randomizations. With [`Randomization::None`] the sequence is
/// Faure's alone, as in the paper. Either way the seed chooses the MT19937
/// streams past dimension 256.
#[derive(Debug, Clone)]
pub struct HaltonSampler {
    halton: Arc<Halton>,
    enumeration: PixelEnumeration,
    /// Every pixel's first global index (its offset), tabulated once per
    /// render by column and row.
    offsets: Arc<PixelOffsetTable>,
    seed: u64,
    pixel: (u32, u32),
    index: u64,
    twister_key: u64,
    /// MT19937 numbers for dimensions ≥ 256, generated on demand.
    twister: Option<MersenneTwister>,
    twister_values: Vec<f32>,
}

impl HaltonSampler {
    /// The sampler for an image of `resolution` pixels (each at least 1),
    /// randomized by `seed` as `randomization` says.
    pub fn new(seed: u64, randomization: Randomization, resolution: (u32, u32)) -> Self {
        let halton = match randomization {
            Randomization::None => Halton::new(HALTON_DIMENSIONS, HaltonScramble::Faure, 0),
            // The tag keeps the shifts' hashes apart from the MT19937 keys,
            // which hash the seed with the pixel.
            Randomization::Seeded => Halton::new(
                HALTON_DIMENSIONS,
                HaltonScramble::FaureShifted,
                hash2(seed, HALTON_SHIFT_TAG),
            ),
        }
        .expect("256 Halton dimensions are supported");
        let enumeration = PixelEnumeration::new(resolution.0.max(1), resolution.1.max(1))
            .expect("a non-empty resolution");
        let offsets = Arc::new(enumeration.offset_table(&halton));
        Self {
            halton: Arc::new(halton),
            enumeration,
            offsets,
            seed,
            pixel: (0, 0),
            index: 0,
            twister_key: 0,
            twister: None,
            twister_values: Vec::new(),
        }
    }

    /// The global Halton index of the current sample.
    pub fn global_index(&self) -> u64 {
        self.index
    }
}

impl SampleSource for HaltonSampler {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        match dimension {
            0 => to_f32(
                self.halton.sample(self.index, 0) * self.enumeration.scale.0 as f64
                    - self.pixel.0 as f64,
            ),
            1 => to_f32(
                self.halton.sample(self.index, 1) * self.enumeration.scale.1 as f64
                    - self.pixel.1 as f64,
            ),
            d if d < HALTON_DIMENSIONS => to_f32(self.halton.sample(self.index, d)),
            d => {
                let position = d - HALTON_DIMENSIONS;
                let key = self.twister_key;
                let twister = self
                    .twister
                    .get_or_insert_with(|| MersenneTwister::new((key ^ (key >> 32)) as u32));
                while self.twister_values.len() <= position {
                    self.twister_values.push(twister.next_f32());
                }
                self.twister_values[position]
            }
        }
    }
}

impl PixelSampler for HaltonSampler {
    fn start_pixel_sample(&mut self, pixel: (u32, u32), sample_index: u64) {
        self.pixel = pixel;
        let offset = self.offsets.offset(pixel);
        // Pixels outside the enumeration's resolution cannot occur: the
        // renderer builds the sampler for its image.
        self.index = offset
            .and_then(|offset| {
                sample_index
                    .checked_mul(self.enumeration.increment)?
                    .checked_add(offset)
            })
            .unwrap_or(sample_index);
        self.twister_key = pixel_sample_key(self.seed, pixel, sample_index);
        self.twister = None;
        self.twister_values.clear();
    }

    fn clone_sampler(&self) -> Box<dyn PixelSampler> {
        Box::new(self.clone())
    }

    fn name(&self) -> String {
        "halton".into()
    }
}
