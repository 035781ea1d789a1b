//! The variance layer of a splatting render (LQMC, and the path tracers
//! with `splat_film`): the estimated variance of each pixel's mean, from
//! the images of the render's progressions.
//!
//! LQMC splats every member into other pixels (and a splatting path tracer
//! every sample over its filter's pixels), so a pixel's value is not a
//! mean of its own samples and the film's per-pixel sample variance says
//! nothing about it. What is a mean of identically distributed terms is the
//! image as a whole: a render of `M` samples per pixel is the mean of the `M`
//! progression images `I_k` (progression `k` = sample `k` of every pixel,
//! with its own tile jitter; each `I_k` is the splat sum of that
//! progression, at one sample per pixel). This module keeps, per pixel and
//! channel, the running mean and sum of squared deviations of the `I_k`
//! (Welford's update) and reports `s² / M`, with `s²` the unbiased sample
//! variance of the `I_k`.
//!
//! When the progressions are independent — the `independent` sampler, whose
//! numbers are a separate pseudo-random stream per pixel sample, with
//! LQMC's own choices (tile jitter, breakup draw, dimension scrambling)
//! hashed from the sample index — the `I_k` of a pixel are independent and
//! identically distributed, so `E[s²] = Var(I_k)` and `s² / M` is an
//! unbiased estimate of `Var(Ī) = Var(I_k) / M`, the variance of the pixel's
//! value. With a QMC seed sampler (Halton, the default) the progressions
//! are not independent; `s² / M` then treats them as if they were, as the
//! path tracer's film variance does for its samples (for QMC points, whose
//! errors tend to cancel, it usually overestimates).
//!
//! The renderer runs these integrators one progression per pass; after each pass the
//! progression's image is the change of the film's splat sums (so splats
//! are filtered once, by the film). Only complete progressions count: a
//! progression cut short by a time budget or an interruption is left out
//! of the variance (its splats are in the image).
//!
//! The same statistics serve Kollig & Keller's replications (Eqs. 5–6):
//! with a pattern size `m` the driver renders one replication (`m` samples
//! per pixel) per pass and ends it here as a progression of `m` samples,
//! whose image is the change of each pixel's camera-sample mean plus the
//! change of its splat sums over `m`. The replications of a randomized
//! point set are independent, so `s² / r` is then the unbiased estimate of
//! Eq. (6), for any integrator.

use crate::film::Film;
use crate::image::Image;

/// Per-pixel statistics of the progression images of a splatting render.
#[derive(Debug, Clone)]
pub struct ProgressionVariance {
    resolution: [usize; 2],
    /// The film's splat sums at the end of the previous progression.
    previous: Vec<[f64; 3]>,
    /// The film's weighted camera-sample sums and weight sums at the end of
    /// the previous progression.
    previous_camera: Vec<([f64; 3], f64)>,
    /// Running mean of the finished progressions' images.
    mean: Vec<[f64; 3]>,
    /// Running sum of squared deviations from the mean.
    squared_deviations: Vec<[f64; 3]>,
    progressions: u64,
    /// Per finished progression, its image's mean luminance.
    image_means: Vec<f64>,
}

impl ProgressionVariance {
    /// Statistics for an image of `resolution` pixels, no progression yet.
    pub fn new(resolution: [usize; 2]) -> Self {
        let pixel_count = resolution[0] * resolution[1];
        Self {
            resolution,
            previous: vec![[0.0; 3]; pixel_count],
            previous_camera: vec![([0.0; 3], 0.0); pixel_count],
            mean: vec![[0.0; 3]; pixel_count],
            squared_deviations: vec![[0.0; 3]; pixel_count],
            progressions: 0,
            image_means: Vec::new(),
        }
    }

    /// Ends a progression of one sample per pixel whose splats `film` has
    /// just merged: its image is the change of the film's splat sums since
    /// the previous call, and joins the statistics if `complete` (else it
    /// is dropped).
    pub fn end_progression(&mut self, film: &Film, complete: bool) {
        self.end_progression_of(film, complete, 1);
    }

    /// Ends a progression of `samples` samples per pixel (a replication)
    /// that `film` has just merged: its image is, per pixel, the mean of the
    /// camera samples it added plus its splats over `samples`.
    /// Rows in parallel: per pixel, nothing depends on another pixel.
    #[allow(clippy::needless_range_loop)] // channel indexes parallel arrays
    pub fn end_progression_of(&mut self, film: &Film, complete: bool, samples: u64) {
        use rayon::prelude::*;
        if complete {
            self.progressions += 1;
        }
        let count = self.progressions as f64;
        let splat_scale = 1.0 / samples.max(1) as f64;
        let width = self.resolution[0];
        let luminance_sum: f64 = self
            .previous
            .par_chunks_mut(width)
            .zip(self.previous_camera.par_chunks_mut(width))
            .zip(self.mean.par_chunks_mut(width))
            .zip(self.squared_deviations.par_chunks_mut(width))
            .enumerate()
            .map(|(y, (((previous, previous_camera), mean), squared))| {
                let mut row_luminance = 0.0;
                for x in 0..width {
                    let sums = film.splat(x, y).unwrap_or([0.0; 3]);
                    let camera = film
                        .pixel(x, y)
                        .map(|pixel| (pixel.weighted_sum(), pixel.weight_sum()))
                        .unwrap_or(([0.0; 3], 0.0));
                    if complete {
                        let camera_weight = camera.1 - previous_camera[x].1;
                        let mut values = [0.0; 3];
                        for channel in 0..3 {
                            let camera_mean = if camera_weight != 0.0 {
                                (camera.0[channel] - previous_camera[x].0[channel]) / camera_weight
                            } else {
                                0.0
                            };
                            let value =
                                camera_mean + (sums[channel] - previous[x][channel]) * splat_scale;
                            values[channel] = value;
                            let deviation = value - mean[x][channel];
                            mean[x][channel] += deviation / count;
                            squared[x][channel] += deviation * (value - mean[x][channel]);
                        }
                        row_luminance += crate::spectrum::linear_srgb_luminance_f64(values);
                    }
                    previous[x] = sums;
                    previous_camera[x] = camera;
                }
                row_luminance
            })
            // Summed in row order, not as the threads finish: the same
            // bits for any number of threads.
            .collect::<Vec<f64>>()
            .iter()
            .sum();
        if complete {
            let pixels = (self.resolution[0] * self.resolution[1]).max(1) as f64;
            self.image_means.push(luminance_sum / pixels);
        }
    }

    /// Per finished progression, the mean luminance of its image (the
    /// image mean's error comes from their spread).
    pub fn image_means(&self) -> &[f64] {
        &self.image_means
    }

    /// Number of finished progressions `M`.
    pub fn progressions(&self) -> u64 {
        self.progressions
    }

    /// The mean of the finished progressions' images (the render's image
    /// when every progression finished).
    pub fn mean(&self) -> &[[f64; 3]] {
        &self.mean
    }

    /// Per pixel and channel, `s² / M`: the estimated variance of the mean
    /// of the `M` progression images; zero with fewer than two.
    pub fn variance_of_mean(&self) -> Vec<[f64; 3]> {
        let count = self.progressions as f64;
        self.squared_deviations
            .iter()
            .map(|squared| {
                squared.map(|value| {
                    if self.progressions < 2 {
                        0.0
                    } else {
                        (value / (count - 1.0)).max(0.0) / count
                    }
                })
            })
            .collect()
    }

    /// [`Self::variance_of_mean`] as an image (the EXR's variance layer).
    pub fn variance_image(&self) -> Image {
        let pixels = self
            .variance_of_mean()
            .into_iter()
            .map(|variance| variance.map(|value| value as f32))
            .collect();
        Image::from_pixels(self.resolution[0], self.resolution[1], pixels)
            .unwrap_or_else(|_| unreachable!("width × height pixels"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::film::{BoxFilter, Filter};

    /// Splats of known values at pixel centres with a box filter reproduce
    /// the two-pass sample variance of the values divided by `M`.
    #[test]
    fn matches_the_two_pass_variance_of_the_mean() {
        let filter = Filter::Box(BoxFilter::new([0.5, 0.5]).unwrap());
        let film = Film::new([2, 1], filter).unwrap();
        let values = [1.0, 4.0, 2.5, 7.0, -1.0];
        let mut statistics = ProgressionVariance::new([2, 1]);
        for value in values {
            // Two splats into pixel 0 per progression, none into pixel 1.
            let _ = film.add_splat([0.5, 0.5], [value as f32, 0.0, 2.0 * value as f32]);
            let _ = film.add_splat([0.5, 0.5], [value as f32, 0.0, 0.0]);
            statistics.end_progression(&film, true);
        }
        // A cut-short progression does not count.
        let _ = film.add_splat([0.5, 0.5], [100.0, 100.0, 100.0]);
        statistics.end_progression(&film, false);
        assert_eq!(statistics.progressions(), 5);
        let count = values.len() as f64;
        let sample_variance = |scale: f64| {
            let mean = values.iter().map(|v| scale * v).sum::<f64>() / count;
            values
                .iter()
                .map(|v| (scale * v - mean).powi(2))
                .sum::<f64>()
                / (count - 1.0)
        };
        let variance = statistics.variance_of_mean();
        for (channel, scale) in [2.0, 0.0, 2.0].into_iter().enumerate() {
            let expected = sample_variance(scale) / count;
            assert!(
                (variance[0][channel] - expected).abs() <= 1e-12 * expected.max(1.0),
                "{channel}: {} vs {expected}",
                variance[0][channel]
            );
        }
        assert_eq!(variance[1], [0.0; 3]);
        let mean = values.iter().sum::<f64>() / count;
        assert!((statistics.mean()[0][0] - 2.0 * mean).abs() < 1e-12);
        let image = statistics.variance_image();
        assert_eq!(image.width(), 2);
    }

    #[test]
    fn fewer_than_two_progressions_have_zero_variance() {
        let mut statistics = ProgressionVariance::new([1, 1]);
        assert_eq!(statistics.variance_of_mean(), vec![[0.0; 3]]);
        let film = Film::new([1, 1], Filter::Box(BoxFilter::new([0.5, 0.5]).unwrap())).unwrap();
        statistics.end_progression(&film, true);
        assert_eq!(statistics.variance_of_mean(), vec![[0.0; 3]]);
    }
}
