//! The per-pixel randomness of the samplers that use the same point set in
//! every pixel and decorrelate pixels by randomizing it per pixel (a
//! Cranley–Patterson shift, an Owen scrambling): a seed per pixel from which
//! each dimension's randomization is hashed, and a PCG stream per pixel
//! sample for the dimensions (or sample indices) the point set does not cover.
//!
//! With a pattern size `m` (Kollig & Keller's replications, Eq. 5) the
//! samples of a pixel are `r` replications of `m` points: sample `j` is point
//! `j mod m` of replication `⌊j / m⌋`, and every replication of every pixel
//! has its own randomization, independent of the others.

use super::{Randomization, pixel_part_of_key, sample_key_in_pixel};
use qmc::hash::{hash2, hash3};
use qmc::random::SeekablePcg;

/// The current pixel sample's randomization; [`PixelRandomization::start`]
/// moves it to a new pixel sample.
#[derive(Debug, Clone)]
pub(crate) struct PixelRandomization {
    /// The seed of the PCG streams.
    seed: u64,
    /// The seed of the per-pixel scrambles or shifts: `seed`, or 0 without
    /// randomization.
    scramble_seed: u64,
    /// Points per replication, if the samples are replications.
    pattern_size: Option<u64>,
    pixel_seed: u64,
    index: u64,
    fallback: SeekablePcg,
}

/// Hashed with a pixel's key and a replication number into the
/// replication's randomization.
const REPLICATION_TAG: u64 = 0x5245_504C_4943_4154;

impl PixelRandomization {
    /// The randomization chosen by `seed`, before any pixel sample starts.
    /// With [`Randomization::None`] the per-pixel scrambles are those of
    /// seed 0 and only the PCG streams follow `seed`.
    /// With `pattern_size` `m`, sample `j` is point `j mod m` of replication
    /// `⌊j / m⌋`, each replication randomized on its own; without, the pixel's
    /// samples are the points of one randomization.
    pub(crate) fn new(seed: u64, randomization: Randomization, pattern_size: Option<u64>) -> Self {
        Self {
            seed,
            scramble_seed: randomization.scramble_seed(seed),
            pattern_size: pattern_size.map(|size| size.max(1)),
            pixel_seed: 0,
            index: 0,
            fallback: SeekablePcg::new(seed, 0),
        }
    }

    /// Moves to sample `sample_index` of `pixel`.
    pub(crate) fn start(&mut self, pixel: (u32, u32), sample_index: u64) {
        // The pixel seed is the pixel part of the sample's key (and the
        // replication's, with replications).
        self.pixel_seed = pixel_part_of_key(self.scramble_seed, pixel);
        self.index = sample_index;
        if let Some(size) = self.pattern_size {
            self.index = sample_index % size;
            self.pixel_seed = hash3(self.pixel_seed, REPLICATION_TAG, sample_index / size);
        }
        let stream_pixel_part = if self.scramble_seed == self.seed {
            self.pixel_seed
        } else {
            pixel_part_of_key(self.seed, pixel)
        };
        self.fallback = SeekablePcg::new(
            self.seed,
            sample_key_in_pixel(stream_pixel_part, sample_index),
        );
    }

    /// The index of the current sample's point: within its pixel, or within
    /// its replication.
    #[inline]
    pub(crate) fn index(&self) -> u64 {
        self.index
    }

    /// The seed of the current pixel's (and replication's) randomization:
    /// every random choice of a pixel's point set is hashed from it.
    #[inline]
    pub(crate) fn pixel_seed(&self) -> u64 {
        self.pixel_seed
    }

    /// 64 random bits for `dimension` in the current pixel, the same for
    /// every sample of the pixel (so all its samples share one randomization
    /// of the point set).
    #[inline]
    pub(crate) fn dimension_hash(&self, dimension: usize) -> u64 {
        hash2(self.pixel_seed, dimension as u64)
    }

    /// The current pixel sample's pseudo-random number for `dimension`, for
    /// dimensions and indices beyond the point set.
    #[inline]
    pub(crate) fn fallback(&mut self, dimension: usize) -> f32 {
        self.fallback.seek(dimension as u64);
        self.fallback.next_f32()
    }
}
