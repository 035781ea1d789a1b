//! Any point set of the `qmc` crate as a sampler: the same points in every
//! pixel, decorrelated between pixels by a per-pixel Cranley–Patterson
//! rotation (a random shift modulo one per pixel and dimension).

use super::{PixelSampler, SampleSource, to_f32};
use qmc::PointSet;
use qmc::cranley_patterson::shift_modulo_one;
use qmc::hash::{hash2, hash3, to_unit_f64};
use qmc::random::SeekablePcg;
use std::sync::Arc;

/// Point `j` of the set for sample `j` of every pixel, shifted per pixel.
/// Dimensions beyond the set's, and indices beyond a finite set's size,
/// come from a PCG stream.
#[derive(Clone)]
pub struct PointSetSampler {
    points: Arc<dyn PointSet>,
    name: String,
    seed: u64,
    pixel_seed: u64,
    index: u64,
    fallback: SeekablePcg,
}

impl PointSetSampler {
    /// A sampler over `points`, named `name` in logs.
    pub fn new(points: Arc<dyn PointSet>, name: impl Into<String>, seed: u64) -> Self {
        Self {
            points,
            name: name.into(),
            seed,
            pixel_seed: 0,
            index: 0,
            fallback: SeekablePcg::new(seed, 0),
        }
    }
}

impl SampleSource for PointSetSampler {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        let in_set = dimension < self.points.dimensions()
            && self.points.len().is_none_or(|len| self.index < len);
        if in_set {
            let shift = to_unit_f64(hash2(self.pixel_seed, dimension as u64));
            to_f32(shift_modulo_one(
                self.points.sample(self.index, dimension),
                shift,
            ))
        } else {
            self.fallback.seek(dimension as u64);
            self.fallback.next_f32()
        }
    }
}

impl PixelSampler for PointSetSampler {
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
        self.name.clone()
    }
}
