//! Any point set of the `qmc` crate as a sampler: the same points in every
//! pixel, decorrelated between pixels by a per-pixel Cranley–Patterson
//! rotation (a random shift modulo one per pixel and dimension), or, with a
//! pattern size, replications of its first points, one rotation per
//! replication.

use super::pixel_randomization::PixelRandomization;
use super::{PixelSampler, Randomization, SampleSource, to_f32};
use qmc::PointSet;
use qmc::cranley_patterson::shift_modulo_one;
use qmc::hash::to_unit_f64;
use std::sync::Arc;

/// Point `j` of the set for sample `j` of every pixel, shifted per pixel.
/// Dimensions beyond the set's, and indices beyond a finite set's size,
/// come from a PCG stream.
#[derive(Clone)]
pub struct PointSetSampler {
    points: Arc<dyn PointSet>,
    name: String,
    randomization: PixelRandomization,
}

impl PointSetSampler {
    /// A sampler over `points`, named `name` in logs, its per-pixel shifts
    /// keyed by `seed` (by seed 0 with [`Randomization::None`]). With
    /// `pattern_size` `m`, a pixel's samples are replications of the set's
    /// first `m` points, each with its own shift (Kollig & Keller's
    /// Cranley–Patterson replications, Sect. 4.1).
    pub fn new(
        points: Arc<dyn PointSet>,
        name: impl Into<String>,
        seed: u64,
        randomization: Randomization,
        pattern_size: Option<u64>,
    ) -> Self {
        Self {
            points,
            name: name.into(),
            randomization: PixelRandomization::new(seed, randomization, pattern_size),
        }
    }
}

impl SampleSource for PointSetSampler {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        let index = self.randomization.index();
        let in_set =
            dimension < self.points.dimensions() && self.points.len().is_none_or(|len| index < len);
        if in_set {
            let shift = to_unit_f64(self.randomization.dimension_hash(dimension));
            to_f32(shift_modulo_one(
                self.points.sample(index, dimension),
                shift,
            ))
        } else {
            self.randomization.fallback(dimension)
        }
    }
}

impl PixelSampler for PointSetSampler {
    fn start_pixel_sample(&mut self, pixel: (u32, u32), sample_index: u64) {
        self.randomization.start(pixel, sample_index);
    }

    fn clone_sampler(&self) -> Box<dyn PixelSampler> {
        Box::new(self.clone())
    }

    fn name(&self) -> String {
        self.name.clone()
    }
}
