//! A rectangle of pixels that one render thread owns while it renders it:
//! camera samples go into the tile without locking, and the film merges
//! finished tiles ([`super::Film::merge_tile`]).

use super::FilmError;
use super::pixel_statistics::PixelStatistics;

/// A half-open rectangle of pixels: columns `min[0]..max[0]`, rows
/// `min[1]..max[1]`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct PixelBounds {
    /// First column and row (inclusive).
    pub min: [usize; 2],
    /// One past the last column and row.
    pub max: [usize; 2],
}

impl PixelBounds {
    /// Width and height (zero when empty).
    pub fn size(&self) -> [usize; 2] {
        [0, 1].map(|axis| self.max[axis].saturating_sub(self.min[axis]))
    }

    /// Number of pixels.
    pub fn area(&self) -> usize {
        let [width, height] = self.size();
        width * height
    }

    /// Whether `pixel` lies inside.
    pub fn contains(&self, pixel: [usize; 2]) -> bool {
        (0..2).all(|axis| pixel[axis] >= self.min[axis] && pixel[axis] < self.max[axis])
    }

    /// Whether `other` lies entirely inside (an empty `other` always does).
    pub fn contains_bounds(&self, other: &PixelBounds) -> bool {
        other.area() == 0
            || (0..2)
                .all(|axis| other.min[axis] >= self.min[axis] && other.max[axis] <= self.max[axis])
    }
}

impl std::fmt::Display for PixelBounds {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            formatter,
            "[{}, {}) x [{}, {})",
            self.min[0], self.max[0], self.min[1], self.max[1]
        )
    }
}

/// Whether a sample was accumulated or rejected.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SampleOutcome {
    /// The sample was added.
    Accepted,
    /// The sample had a NaN or infinite value (or position), or a negative
    /// or non-finite weight; it was counted and not written.
    Rejected,
}

/// Per-pixel accumulators for a rectangle of the film, owned by one thread.
#[derive(Debug, Clone)]
pub struct FilmTile {
    bounds: PixelBounds,
    pixels: Vec<PixelStatistics>,
    rejected_samples: u64,
}

impl FilmTile {
    /// An empty tile covering `bounds` (normally made by
    /// [`super::Film::new_tile`], which checks the bounds against the film).
    pub fn new(bounds: PixelBounds) -> Self {
        Self {
            bounds,
            pixels: vec![PixelStatistics::default(); bounds.area()],
            rejected_samples: 0,
        }
    }

    /// The pixels this tile covers.
    pub fn bounds(&self) -> PixelBounds {
        self.bounds
    }

    /// Adds a camera sample of value `rgb` and filter weight `weight` to
    /// `pixel` (film coordinates), the pixel it was generated for. A sample
    /// with a NaN or infinite channel, or a negative or non-finite weight,
    /// is rejected and counted. A pixel outside the tile is an error.
    pub fn add_sample(
        &mut self,
        pixel: [usize; 2],
        rgb: [f32; 3],
        weight: f32,
    ) -> Result<SampleOutcome, FilmError> {
        if !self.bounds.contains(pixel) {
            return Err(FilmError::PixelOutsideTile {
                pixel,
                bounds: self.bounds,
            });
        }
        let valid =
            rgb.iter().all(|value| value.is_finite()) && weight >= 0.0 && weight.is_finite();
        if !valid {
            self.rejected_samples += 1;
            return Ok(SampleOutcome::Rejected);
        }
        let width = self.bounds.size()[0];
        let index = (pixel[1] - self.bounds.min[1]) * width + (pixel[0] - self.bounds.min[0]);
        self.pixels[index].add(rgb.map(f64::from), weight as f64);
        Ok(SampleOutcome::Accepted)
    }

    /// Number of samples rejected so far.
    pub fn rejected_samples(&self) -> u64 {
        self.rejected_samples
    }

    /// The statistics of `pixel` (film coordinates), if inside the tile.
    pub fn pixel(&self, pixel: [usize; 2]) -> Option<&PixelStatistics> {
        if !self.bounds.contains(pixel) {
            return None;
        }
        let width = self.bounds.size()[0];
        self.pixels
            .get((pixel[1] - self.bounds.min[1]) * width + (pixel[0] - self.bounds.min[0]))
    }

    /// The pixels' statistics, row-major within the tile.
    pub(crate) fn pixels(&self) -> &[PixelStatistics] {
        &self.pixels
    }
}
