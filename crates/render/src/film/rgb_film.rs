//! The film: per-pixel accumulation of camera samples and a separate splat
//! image, as pbrt-v4's `RGBFilm` (`AddSample`, `AddSplat`,
//! `GetPixelRGB(splatScale)`), with per-pixel variance estimates.

use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use super::FilmError;
use super::film_tile::{FilmTile, PixelBounds, SampleOutcome};
use super::filter::Filter;
use super::pixel_statistics::PixelStatistics;
use super::splat_buffer::SplatBuffer;
use crate::image::{
    Image, ImageError, ImageFormat, Metadata, VARIANCE_LAYER, write_exr, write_image,
};

/// Splats of a separable filter over at most this many pixels per axis
/// evaluate one factor per row and column (radius below 3.5 pixels).
const SEPARABLE_SPLAT_WIDTH: usize = 8;

/// Where a camera sample for a pixel goes, from filter importance sampling.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraSamplePosition {
    /// Continuous raster position: pixel centre plus the filter offset.
    pub raster_position: [f32; 2],
    /// The filter weight to pass to [`FilmTile::add_sample`].
    pub weight: f32,
}

impl CameraSamplePosition {
    /// The position of a camera sample of `pixel` placed by sampling
    /// `filter` with `u` around the pixel's centre (what
    /// [`Film::camera_sample_position`] does with the film's filter).
    #[inline]
    pub fn new(filter: &Filter, pixel: [usize; 2], u: [f32; 2]) -> Self {
        let sample = filter.sample(u);
        Self {
            raster_position: [0, 1].map(|axis| pixel[axis] as f32 + 0.5 + sample.offset[axis]),
            weight: sample.weight,
        }
    }
}

/// An RGB film.
///
/// Camera samples: a render thread takes a [`FilmTile`] from
/// [`Film::new_tile`], adds each sample to the pixel it was generated for
/// (filter importance sampling: see [`Film::camera_sample_position`]), and
/// hands the tile back to [`Film::merge_tile`]. Splats: a work unit fills a
/// [`SplatBuffer`] and hands it to [`Film::merge_splats`], or calls the
/// thread-safe [`Film::add_splat`]. The final pixel is
/// `Σ wᵢ Lᵢ / Σ wᵢ + splat_scale · splat`, as pbrt-v4's `RGBFilm`.
///
/// Determinism: merging the same tiles and splat buffers in the same order
/// gives bit-identical results, however many threads produced them.
/// [`Film::add_splat`] adds atomically in whatever order threads arrive, and
/// floating-point addition is not associative, so images that use it are
/// not bit-reproducible across runs or thread counts (only up to rounding).
#[derive(Debug)]
pub struct Film {
    resolution: [usize; 2],
    filter: Filter,
    pixels: Vec<PixelStatistics>,
    /// `f64` bit patterns of the splat image, so that `add_splat` can add
    /// with compare-exchange.
    splats: Vec<[AtomicU64; 3]>,
    nonfinite_samples: AtomicU64,
    /// The variance of each pixel's value estimated by the driver from
    /// batches: independent replications (Kollig & Keller's Eq. 6), or the
    /// passes of a splatting integrator.
    batch_variance: Option<Image>,
    /// Per batch, its image's mean luminance.
    batch_image_means: Vec<f64>,
}

/// Adds `value` to the `f64` stored as bits in `cell`, atomically.
fn atomic_add_f64(cell: &AtomicU64, value: f64) {
    let mut current = cell.load(Ordering::Relaxed);
    loop {
        let updated = (f64::from_bits(current) + value).to_bits();
        match cell.compare_exchange_weak(current, updated, Ordering::Relaxed, Ordering::Relaxed) {
            Ok(_) => return,
            Err(actual) => current = actual,
        }
    }
}

impl Film {
    /// A black film of `resolution = [width, height]` pixels (both
    /// positive) reconstructing with `filter`.
    pub fn new(resolution: [usize; 2], filter: Filter) -> Result<Self, FilmError> {
        let pixel_count = resolution[0].checked_mul(resolution[1]);
        let Some(pixel_count) = pixel_count.filter(|&count| count > 0) else {
            return Err(FilmError::InvalidResolution { resolution });
        };
        Ok(Self {
            resolution,
            filter,
            pixels: vec![PixelStatistics::default(); pixel_count],
            splats: (0..pixel_count)
                .map(|_| [0.0f64; 3].map(|zero| AtomicU64::new(zero.to_bits())))
                .collect(),
            nonfinite_samples: AtomicU64::new(0),
            batch_variance: None,
            batch_image_means: Vec::new(),
        })
    }

    /// Records the variance of each pixel's value estimated from batches
    /// of the render (set by the drivers: see [`Self::batch_variance`]).
    /// `image_means` are the batches' image mean luminances.
    pub fn set_batch_variance(&mut self, variance: Image, image_means: Vec<f64>) {
        self.batch_variance = Some(variance);
        self.batch_image_means = image_means;
    }

    /// Per batch of [`Self::batch_variance`], its image's mean luminance
    /// (empty without batches): their spread is the image mean's error.
    pub fn batch_image_means(&self) -> &[f64] {
        &self.batch_image_means
    }

    /// The variance of each pixel's value estimated from batches of the
    /// render, when the driver made them: independent replications
    /// (`pattern_size`), or the passes of an integrator whose every
    /// contribution is a splat, for which the per-pixel sample variance
    /// says nothing.
    pub fn batch_variance(&self) -> Option<&Image> {
        self.batch_variance.as_ref()
    }

    /// The splat sums, one per pixel (row-major).
    pub(crate) fn splat_sums(&self) -> Vec<[f64; 3]> {
        self.splats
            .iter()
            .map(|splat| {
                splat
                    .each_ref()
                    .map(|cell| f64::from_bits(cell.load(Ordering::Relaxed)))
            })
            .collect()
    }

    /// Replaces the splat sums with `sums`, one per pixel (row-major).
    pub(crate) fn set_splat_sums(&mut self, sums: &[[f64; 3]]) {
        for (splat, sum) in self.splats.iter_mut().zip(sums) {
            for (cell, value) in splat.iter_mut().zip(sum) {
                *cell.get_mut() = value.to_bits();
            }
        }
    }

    /// Adds already filtered splat sums, one per pixel (row-major), and a
    /// count of dropped non-finite splats: what [`Film::merge_splats`]
    /// would have added for splats filtered elsewhere with
    /// [`Film::for_each_splat_pixel`].
    pub(crate) fn add_splat_sums(&mut self, sums: &[[f64; 3]], rejected_samples: u64) {
        for (splat, sum) in self.splats.iter_mut().zip(sums) {
            for (cell, value) in splat.iter_mut().zip(sum) {
                let cell = cell.get_mut();
                *cell = (f64::from_bits(*cell) + value).to_bits();
            }
        }
        *self.nonfinite_samples.get_mut() += rejected_samples;
    }

    /// `[width, height]` in pixels.
    pub fn resolution(&self) -> [usize; 2] {
        self.resolution
    }

    /// The reconstruction filter.
    pub fn filter(&self) -> &Filter {
        &self.filter
    }

    /// All pixels of the film.
    pub fn pixel_bounds(&self) -> PixelBounds {
        PixelBounds {
            min: [0, 0],
            max: self.resolution,
        }
    }

    /// The film cut into tiles of at most `tile_size × tile_size` pixels,
    /// row by row from the top left: a fixed order for deterministic
    /// merging.
    pub fn tile_bounds(&self, tile_size: usize) -> Result<Vec<PixelBounds>, FilmError> {
        if tile_size == 0 {
            return Err(FilmError::InvalidTileSize);
        }
        let [width, height] = self.resolution;
        let mut tiles = Vec::new();
        for y in (0..height).step_by(tile_size) {
            for x in (0..width).step_by(tile_size) {
                tiles.push(PixelBounds {
                    min: [x, y],
                    max: [(x + tile_size).min(width), (y + tile_size).min(height)],
                });
            }
        }
        Ok(tiles)
    }

    /// An empty tile for `bounds`, which must lie inside the film.
    pub fn new_tile(&self, bounds: PixelBounds) -> Result<FilmTile, FilmError> {
        if !self.pixel_bounds().contains_bounds(&bounds) {
            return Err(FilmError::TileOutsideFilm {
                bounds,
                resolution: self.resolution,
            });
        }
        Ok(FilmTile::new(bounds))
    }

    /// Filter importance sampling: the raster position of a camera sample
    /// for `pixel` from the 2-D sample `u` (pixel centre plus a filter
    /// offset), and the weight to accumulate it with.
    pub fn camera_sample_position(&self, pixel: [usize; 2], u: [f32; 2]) -> CameraSamplePosition {
        CameraSamplePosition::new(&self.filter, pixel, u)
    }

    /// Adds a finished tile's samples to the film (and its rejected-sample
    /// count to [`Film::nonfinite_samples`]).
    pub fn merge_tile(&mut self, tile: &FilmTile) -> Result<(), FilmError> {
        let bounds = tile.bounds();
        if !self.pixel_bounds().contains_bounds(&bounds) {
            return Err(FilmError::TileOutsideFilm {
                bounds,
                resolution: self.resolution,
            });
        }
        let tile_width = bounds.size()[0];
        for (row_index, row) in tile.pixels().chunks(tile_width.max(1)).enumerate() {
            let start = (bounds.min[1] + row_index) * self.resolution[0] + bounds.min[0];
            for (film_pixel, tile_pixel) in
                self.pixels[start..start + row.len()].iter_mut().zip(row)
            {
                film_pixel.merge(tile_pixel);
            }
        }
        *self.nonfinite_samples.get_mut() += tile.rejected_samples();
        Ok(())
    }

    /// Calls `add` with the index and filter weight of every film pixel
    /// whose centre `c` satisfies `c − p ∈ (−r, r]` per axis for the splat
    /// at `p` (half-open, so that the box filter's pixels tile the plane).
    pub(crate) fn for_each_splat_pixel(&self, position: [f32; 2], add: impl FnMut(usize, f64)) {
        self.for_each_splat_pixel_in_rows(position, 0..self.resolution[1], add);
    }

    /// [`Film::for_each_splat_pixel`] for the pixels in `rows` only.
    #[inline]
    fn for_each_splat_pixel_in_rows(
        &self,
        position: [f32; 2],
        rows: std::ops::Range<usize>,
        mut add: impl FnMut(usize, f64),
    ) {
        let radius = self.filter.radius();
        let mut ranges = [(0usize, 0usize); 2];
        let bounds = [(0, self.resolution[0]), (rows.start, rows.end)];
        for axis in 0..2 {
            let low = (position[axis] as f64 - radius[axis] as f64 - 0.5).floor() + 1.0;
            let high = (position[axis] as f64 + radius[axis] as f64 - 0.5).floor();
            let (first, end) = (bounds[axis].0 as f64, bounds[axis].1 as f64);
            if high < first || low > end - 1.0 {
                return;
            }
            ranges[axis] = (low.max(first) as usize, high.min(end - 1.0) as usize);
        }
        if let Filter::Gaussian(gaussian) = &self.filter
            && ranges
                .iter()
                .all(|(low, high)| high - low < SEPARABLE_SPLAT_WIDTH)
        {
            // The Gaussian is separable: one factor per column and per row
            // (the same values as `evaluate`, which multiplies them).
            let mut factors = [[None; SEPARABLE_SPLAT_WIDTH]; 2];
            for (axis, (range, factors)) in ranges.iter().zip(&mut factors).enumerate() {
                for (pixel, factor) in (range.0..=range.1).zip(factors.iter_mut()) {
                    let offset = (pixel as f64 + 0.5 - position[axis] as f64) as f32;
                    *factor = gaussian.axis_value(axis, offset);
                }
            }
            for (y, row_factor) in (ranges[1].0..=ranges[1].1).zip(factors[1]) {
                let Some(row_factor) = row_factor else {
                    continue;
                };
                for (x, column_factor) in (ranges[0].0..=ranges[0].1).zip(factors[0]) {
                    let Some(column_factor) = column_factor else {
                        continue;
                    };
                    let weight = (column_factor * row_factor) as f32 as f64;
                    if weight != 0.0 {
                        add(y * self.resolution[0] + x, weight);
                    }
                }
            }
            return;
        }
        for y in ranges[1].0..=ranges[1].1 {
            for x in ranges[0].0..=ranges[0].1 {
                let offset = [
                    (x as f64 + 0.5 - position[0] as f64) as f32,
                    (y as f64 + 0.5 - position[1] as f64) as f32,
                ];
                let weight = self.filter.evaluate(offset) as f64;
                if weight != 0.0 {
                    add(y * self.resolution[0] + x, weight);
                }
            }
        }
    }

    /// Adds a work unit's splats to the splat image, in the buffer's order,
    /// each spread over the pixels around it with the (normalised) filter,
    /// as pbrt-v4's `RGBFilm::AddSplat`.
    pub fn merge_splats(&mut self, buffer: &SplatBuffer) {
        let mut splats = std::mem::take(&mut self.splats);
        for splat in buffer.splats() {
            let rgb = splat.rgb.map(f64::from);
            self.for_each_splat_pixel(splat.raster_position, |index, weight| {
                for (channel, cell) in splats[index].iter_mut().enumerate() {
                    let value = cell.get_mut();
                    *value = (f64::from_bits(*value) + weight * rgb[channel]).to_bits();
                }
            });
        }
        self.splats = splats;
        *self.nonfinite_samples.get_mut() += buffer.rejected_samples();
    }

    /// [`Film::merge_splats`] for several buffers in order, in parallel
    /// over bands of rows: each band adds, in the buffers' order and each
    /// buffer's order, the part of every splat that falls on its rows, so
    /// every pixel receives the same additions in the same order as from
    /// merging the buffers one after the other (the image is bit-identical
    /// for any number of threads).
    pub fn merge_splat_buffers(&mut self, buffers: &[&SplatBuffer]) {
        use rayon::prelude::*;
        let [width, height] = self.resolution;
        let bands = rayon::current_num_threads().clamp(1, height);
        if bands == 1 {
            for buffer in buffers {
                self.merge_splats(buffer);
            }
            return;
        }
        let band_rows = height.div_ceil(bands);
        let mut splats = std::mem::take(&mut self.splats);
        let film = &*self;
        splats
            .par_chunks_mut(band_rows * width)
            .enumerate()
            .for_each(|(band, cells)| {
                let first_row = band * band_rows;
                let rows = first_row..(first_row + band_rows).min(height);
                let offset = first_row * width;
                for buffer in buffers {
                    for splat in buffer.splats() {
                        let rgb = splat.rgb.map(f64::from);
                        film.for_each_splat_pixel_in_rows(
                            splat.raster_position,
                            rows.clone(),
                            |index, weight| {
                                for (channel, cell) in cells[index - offset].iter_mut().enumerate()
                                {
                                    let value = cell.get_mut();
                                    *value =
                                        (f64::from_bits(*value) + weight * rgb[channel]).to_bits();
                                }
                            },
                        );
                    }
                }
            });
        self.splats = splats;
        *self.nonfinite_samples.get_mut() += buffers
            .iter()
            .map(|buffer| buffer.rejected_samples())
            .sum::<u64>();
    }

    /// Adds one splat directly, from any thread, with atomic `f64` adds.
    /// Convenient, but the result depends on the order in which threads
    /// arrive, so it is not bit-deterministic across runs or thread counts;
    /// use [`SplatBuffer`]s merged in a fixed order for that.
    pub fn add_splat(&self, raster_position: [f32; 2], rgb: [f32; 3]) -> SampleOutcome {
        if !raster_position
            .iter()
            .chain(&rgb)
            .all(|value| value.is_finite())
        {
            self.nonfinite_samples.fetch_add(1, Ordering::Relaxed);
            return SampleOutcome::Rejected;
        }
        let rgb = rgb.map(f64::from);
        self.for_each_splat_pixel(raster_position, |index, weight| {
            for (channel, cell) in self.splats[index].iter().enumerate() {
                atomic_add_f64(cell, weight * rgb[channel]);
            }
        });
        SampleOutcome::Accepted
    }

    /// Samples and splats rejected for a NaN or infinite value or position,
    /// or a negative or non-finite weight, in merged tiles and buffers and
    /// in [`Film::add_splat`].
    pub fn nonfinite_samples(&self) -> u64 {
        self.nonfinite_samples.load(Ordering::Relaxed)
    }

    /// The statistics of the pixel at column `x`, row `y`.
    pub fn pixel(&self, x: usize, y: usize) -> Option<&PixelStatistics> {
        (x < self.resolution[0] && y < self.resolution[1])
            .then(|| &self.pixels[y * self.resolution[0] + x])
    }

    /// The splat image value of pixel `(x, y)` (before the splat scale).
    pub fn splat(&self, x: usize, y: usize) -> Option<[f64; 3]> {
        (x < self.resolution[0] && y < self.resolution[1]).then(|| {
            self.splats[y * self.resolution[0] + x]
                .each_ref()
                .map(|cell| f64::from_bits(cell.load(Ordering::Relaxed)))
        })
    }

    /// The rendered image: `Σ wᵢ Lᵢ / Σ wᵢ` (black where no weight was
    /// added) plus `splat_scale` times the splat image (for light tracing
    /// typically `1 / samples per pixel`), computed in `f64`, stored as `f32`.
    pub fn image(&self, splat_scale: f64) -> Image {
        let pixels = self
            .pixels
            .iter()
            .zip(&self.splats)
            .map(|(pixel, splat)| {
                let mean = pixel.weighted_mean();
                [0, 1, 2].map(|channel| {
                    let splat = f64::from_bits(splat[channel].load(Ordering::Relaxed));
                    (mean[channel] + splat_scale * splat) as f32
                })
            })
            .collect();
        self.to_image(pixels)
    }

    /// Per pixel and channel, the estimated variance of the pixel mean,
    /// `s² / n` with `s²` the unbiased sample variance of the `n` accepted
    /// camera samples' values (zero where `n < 2`); splats are not included.
    /// See [`PixelStatistics`].
    pub fn variance_image(&self) -> Image {
        let pixels = self
            .pixels
            .iter()
            .map(|pixel| pixel.variance_of_mean().map(|variance| variance as f32))
            .collect();
        self.to_image(pixels)
    }

    /// Accepted camera samples per pixel, row-major, top row first.
    pub fn sample_counts(&self) -> Vec<u64> {
        self.pixels
            .iter()
            .map(PixelStatistics::sample_count)
            .collect()
    }

    /// Writes [`Film::image`] to `path` in the format of its extension; an
    /// EXR file also gets the [`Film::variance_image`] as the layer
    /// [`VARIANCE_LAYER`] (channels `variance.R`, `variance.G`,
    /// `variance.B`).
    pub fn write(
        &self,
        path: impl AsRef<Path>,
        splat_scale: f64,
        metadata: &Metadata,
    ) -> Result<(), ImageError> {
        let path = path.as_ref();
        let image = self.image(splat_scale);
        if ImageFormat::from_path(path)? == ImageFormat::OpenExr {
            write_exr(
                path,
                &image,
                &[(VARIANCE_LAYER, &self.variance_image())],
                metadata,
            )
        } else {
            write_image(path, &image, metadata)
        }
    }

    fn to_image(&self, pixels: Vec<[f32; 3]>) -> Image {
        Image::from_pixels(self.resolution[0], self.resolution[1], pixels)
            .unwrap_or_else(|_| unreachable!("the film has width × height pixels"))
    }
}
