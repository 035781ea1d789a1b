//! Contributions to arbitrary pixels (light tracing, the `t = 1`
//! strategies of BDPT, Metropolis, LQMC splats), gathered per work unit.
//!
//! A [`SplatBuffer`] is a list of `(raster position, RGB)` that one work
//! unit fills without locking; the film applies the reconstruction filter
//! and adds the list to its splat image in [`super::Film::merge_splats`].
//! Merging the buffers of fixed work units in a fixed order gives
//! bit-identical images whatever the number of threads.

use super::film_tile::SampleOutcome;

/// One splat: an RGB contribution at a continuous raster position (pixel
/// `(x, y)` covers `[x, x + 1) × [y, y + 1)`, its centre is at
/// `(x + 0.5, y + 0.5)`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Splat {
    /// Continuous raster position, in pixels.
    pub raster_position: [f32; 2],
    /// The contribution (before the film's splat scale).
    pub rgb: [f32; 3],
}

/// The splats of one work unit, in the order they were made.
#[derive(Debug, Clone, Default)]
pub struct SplatBuffer {
    splats: Vec<Splat>,
    rejected_samples: u64,
}

impl SplatBuffer {
    /// An empty buffer.
    pub fn new() -> Self {
        Self::default()
    }

    /// Records a splat; rejects (and counts) NaN or infinite positions or
    /// values. Positions outside the film are kept (the film ignores the
    /// pixels they do not reach).
    pub fn add(&mut self, raster_position: [f32; 2], rgb: [f32; 3]) -> SampleOutcome {
        if raster_position
            .iter()
            .chain(&rgb)
            .all(|value| value.is_finite())
        {
            self.splats.push(Splat {
                raster_position,
                rgb,
            });
            SampleOutcome::Accepted
        } else {
            self.rejected_samples += 1;
            SampleOutcome::Rejected
        }
    }

    /// The recorded splats, in order.
    pub fn splats(&self) -> &[Splat] {
        &self.splats
    }

    /// Number of recorded splats.
    pub fn len(&self) -> usize {
        self.splats.len()
    }

    /// Whether no splat was recorded.
    pub fn is_empty(&self) -> bool {
        self.splats.is_empty()
    }

    /// Number of splats rejected as non-finite.
    pub fn rejected_samples(&self) -> u64 {
        self.rejected_samples
    }

    /// Counts `count` more rejected samples (made elsewhere and dropped,
    /// e.g. a Markov chain's proposal), so that the film reports them.
    pub fn add_rejected(&mut self, count: u64) {
        self.rejected_samples += count;
    }

    /// Multiplies the values of the splats from index `first` on by
    /// `factor`.
    pub fn scale_from(&mut self, first: usize, factor: f32) {
        for splat in self.splats.iter_mut().skip(first) {
            splat.rgb = splat.rgb.map(|value| value * factor);
        }
    }

    /// Empties the buffer (keeping its memory) for the next work unit.
    pub fn clear(&mut self) {
        self.splats.clear();
        self.rejected_samples = 0;
    }
}
