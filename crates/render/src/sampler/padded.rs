//! Padded replications sampling and Latin supercube sampling (Kollig &
//! Keller, Sects. 4.3 and 5): one two-dimensional basis pattern of `m`
//! points for every pair of dimensions `(2k, 2k + 1)` of the primary sample
//! space, which the layout table (`sampler/mod.rs`) arranges so that every
//! 2-D subproblem of a path (a film position, a light point, a direction)
//! is one such pair.
//!
//! The basis pattern is the 2-D Hammersley set `(i/m, φ₂(i))`, except in
//! the wavelength dimension, which takes `φ₃(i)` (the hero wavelength's
//! rotations make that integrand periodic with period 1/4, which base-2
//! points would alias; see the comment in `get`). Point `i` of
//! a replication has, in pair `k`,
//! - padded replications: `(P_i + Δ_k) mod 1`, the same pattern point in
//!   every pair (Fig. 4 (b)), each pair shifted by its own uniform
//!   Cranley–Patterson rotation `Δ_k`;
//! - Latin supercube: `(P_{π_k(i)} + Δ_k) mod 1` with an independent
//!   uniform random permutation `π_k` per pair (Fig. 4 (c)), which removes
//!   the correlation between the pairs; without randomization
//!   ([`Randomization::None`]) there is no shift: Latin supercube samples
//!   from deterministic points (Sect. 5.1), the pattern then centred in its
//!   strata (`(i + ½)/m`, `φ₂(i) + ½/2^⌈log₂ m⌉`).
//!
//! A pixel's samples are replications of `m` points (the pattern size):
//! sample `j` is point `j mod m` of replication `⌊j / m⌋`, and each
//! replication of each pixel has its own shifts and permutations, hashed
//! from the seed, the pixel and the replication. With the shifts every
//! point is uniform and replications are independent: Eqs. (5)–(6) hold.
//! The pattern pads any number of dimensions, so no dimension falls back to
//! pseudo-random numbers.

use super::pixel_randomization::PixelRandomization;
use super::{PixelSampler, Randomization, SampleSource, layout, to_f32};
use qmc::cranley_patterson::shift_modulo_one;
use qmc::hash::{hash2, to_unit_f64};
use qmc::padded::random_permutation_into;
use qmc::radical_inverse::radical_inverse;

/// Hashed with a replication's seed and a pair into the pair's permutation.
const PERMUTATION_TAG: u64 = 0x5045_524D_5554_4531;

/// How the pairs of dimensions are filled from the basis pattern.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Padding {
    /// The same pattern point in every pair (padded replications).
    Replications,
    /// A random permutation of the pattern's points per pair (Latin
    /// supercube).
    LatinSupercube,
}

/// Padded replications or Latin supercube samples of the 2-D Hammersley
/// pattern (see the module docs).
#[derive(Debug, Clone)]
pub struct PaddedSampler {
    pattern_size: u64,
    padding: Padding,
    /// Whether each pair is rotated (always for padded replications: a
    /// pattern repeated unshifted in every pixel would alias).
    shifted: bool,
    randomization: PixelRandomization,
    /// The current replication's permutation of each pair used so far
    /// (Latin supercube), drawn when first needed.
    permutations: Vec<Vec<u32>>,
    drawn: Vec<bool>,
}

impl PaddedSampler {
    /// Replications of `pattern_size ≥ 1` points, padded as `padding` says,
    /// randomized by `seed` as `randomization` says.
    pub fn new(
        pattern_size: u64,
        padding: Padding,
        seed: u64,
        randomization: Randomization,
    ) -> Self {
        let pattern_size = pattern_size.clamp(1, 1 << 32);
        Self {
            pattern_size,
            padding,
            shifted: padding == Padding::Replications || randomization == Randomization::Seeded,
            randomization: PixelRandomization::new(seed, randomization, Some(pattern_size)),
            permutations: Vec::new(),
            drawn: Vec::new(),
        }
    }

    /// The pattern point of pair `pair` for the current sample.
    fn pattern_index(&mut self, pair: usize) -> u64 {
        let index = self.randomization.index();
        if self.padding == Padding::Replications {
            return index;
        }
        if pair >= self.drawn.len() {
            self.drawn.resize(pair + 1, false);
            self.permutations.resize_with(pair + 1, Vec::new);
        }
        if !self.drawn[pair] {
            let key = hash2(
                self.randomization.pixel_seed() ^ PERMUTATION_TAG,
                pair as u64,
            );
            random_permutation_into(self.pattern_size, key, &mut self.permutations[pair]);
            self.drawn[pair] = true;
        }
        u64::from(self.permutations[pair][index as usize])
    }
}

impl SampleSource for PaddedSampler {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        let point = self.pattern_index(dimension / 2);
        // The 2-D Hammersley pattern: i/m, then the van der Corput sequence.
        let first = dimension.is_multiple_of(2);
        let value = if dimension == layout::WAVELENGTH {
            // The hero wavelength's companions are its rotations by
            // multiples of 1/4, so the wavelength integrand has period 1/4:
            // base-2 pattern points, 1/2 and 1/4 apart, would give a pixel's
            // first samples one and the same set of wavelengths. Base 3's
            // radical inverse does not repeat a set (office, 64 seeds: the
            // error at 2, 3, 4 samples 0.358, 0.298, 0.240 with base 2,
            // 0.339, 0.262, 0.196 with base 3).
            radical_inverse(1, point)
        } else if first {
            point as f64 / self.pattern_size as f64
        } else {
            f64::from((point as u32).reverse_bits()) * (1.0 / 4_294_967_296.0)
        };
        let value = if self.shifted {
            shift_modulo_one(
                value,
                to_unit_f64(self.randomization.dimension_hash(dimension)),
            )
        } else {
            // Unshifted points are centred in their strata: point 0 at the
            // corner (0, 0) would sit where the warps of the sample space
            // are singular (a grazing direction, a light's edge) in every
            // pixel.
            let centring = 0.5
                / if first {
                    self.pattern_size
                } else {
                    self.pattern_size.next_power_of_two()
                } as f64;
            // (Modulo one: the wavelength's base-3 points are not on that grid.)
            shift_modulo_one(value, centring)
        };
        to_f32(value)
    }
}

impl PixelSampler for PaddedSampler {
    fn start_pixel_sample(&mut self, pixel: (u32, u32), sample_index: u64) {
        // The pixel seed is keyed by the pixel and the replication.
        let previous = self.randomization.pixel_seed();
        self.randomization.start(pixel, sample_index);
        if self.randomization.pixel_seed() != previous {
            self.drawn.iter_mut().for_each(|drawn| *drawn = false);
        }
    }

    fn clone_sampler(&self) -> Box<dyn PixelSampler> {
        Box::new(Self {
            permutations: Vec::new(),
            drawn: Vec::new(),
            ..self.clone()
        })
    }

    fn name(&self) -> String {
        match self.padding {
            Padding::Replications => "padded".into(),
            Padding::LatinSupercube => "latin-supercube".into(),
        }
    }
}
