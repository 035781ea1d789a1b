//! Independent replications of a render and the error estimate they give
//! (Kollig & Keller, Eqs. 5–6), for every integrator and sampler.
//!
//! A render of `r` replications is the mean of `r` whole renders that
//! differ only in their seed: replication `i` renders with
//! [`replication_seed`]`(seed, i)`, which randomizes the sampler (a digital
//! shift of Halton, Owen scrambles of Sobol, shifts of the lattice), the
//! Metropolis chains and their bootstrap, VCM's light passes: the
//! replications are independent and identically distributed, so the
//! per-pixel `s² / r` of their images is an unbiased estimate of the
//! variance of the mean, whatever correlation a replication has inside
//! (QMC points, splats, Markov chains, a shared normalisation, VCM's merges).
//!
//! The same replication can be rendered by another process — `lqmc render
//! --replication i/r` on a farm — and [`ReplicationAccumulator`] merges the
//! parts: it takes the replications' 32-bit images in index order, so a
//! merge of parts equals the render of the same replications in one
//! process bit for bit.
//!
//! The image's error is summarised by the relative standard error of the
//! mean luminance of a region (the whole image by default): the standard
//! deviation of the replications' region means over `√r`, divided by their
//! mean. It is computed from the replications' region means, not from the
//! per-pixel variances, because the pixels of one replication are
//! correlated (one randomization of a QMC sequence, a Metropolis
//! normalisation, VCM's shared light paths).

use crate::image::Image;
use crate::integrators::RenderError;
use crate::renderer::{RenderOutput, RenderSettings, RenderStatistics, render_observed};
use crate::scene::Scene;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// The seed of replication `index` of a render seeded with `seed`:
/// replication 0 is the render of `seed` itself (a render of one
/// replication is the plain render), the others hash the seed with their
/// index, so that the replications of two seeds do not overlap.
pub fn replication_seed(seed: u64, index: u64) -> u64 {
    if index == 0 {
        seed
    } else {
        qmc::hash::hash2(seed, index)
    }
}

/// A rectangle of pixels: `[x, y, width, height]`, with `(x, y)` its top
/// left pixel (row 0 is the top row).
pub type PixelRegion = [usize; 4];

pub use crate::spectrum::linear_srgb_luminance_f64 as luminance;

/// What went wrong adding a replication.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ReplicationError {
    /// A replication's image has another size than the others.
    #[error(
        "replication {index} is {width}x{height}, the others {expected_width}x{expected_height}"
    )]
    Resolution {
        index: u64,
        width: usize,
        height: usize,
        expected_width: usize,
        expected_height: usize,
    },
    /// The region is empty or reaches outside the image.
    #[error(
        "the region {x},{y},{width},{height} is not inside the {image_width}x{image_height} image (or is empty)",
        x = region[0], y = region[1], width = region[2], height = region[3]
    )]
    Region {
        region: PixelRegion,
        image_width: usize,
        image_height: usize,
    },
    /// A replication index was added twice.
    #[error("replication {0} is given twice")]
    Duplicate(u64),
}

/// The estimated error of a render of replications.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorEstimate {
    /// The replications it comes from.
    pub replications: u64,
    /// The mean luminance of the region (the estimate's value).
    pub region_mean: f64,
    /// The estimated standard error of that mean: the standard deviation
    /// of the replications' region means over `√r` (0 with one replication).
    pub standard_error: f64,
    /// The root mean square over the region's pixel channels of the
    /// estimated standard error of the pixel value, over the region's mean
    /// pixel channel value: the expected relative RMSE of the region's
    /// pixels (what `lqmc compare` measures against a reference).
    pub pixel_relative_error: f64,
}

/// Which error a render to a target stops on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ErrorMeasure {
    /// The relative standard error of the region's mean luminance.
    #[default]
    Mean,
    /// The expected relative RMSE of the region's pixels
    /// ([`ErrorEstimate::pixel_relative_error`]).
    PixelRmse,
}

impl ErrorMeasure {
    /// Both, with their command-line names.
    pub const ALL: [(ErrorMeasure, &'static str); 2] = [
        (ErrorMeasure::Mean, "mean"),
        (ErrorMeasure::PixelRmse, "rmse"),
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(measure, _)| *measure == self)
            .unwrap()
            .1
    }
}

impl ErrorEstimate {
    /// The relative standard error of the region's mean, `standard_error /
    /// |region_mean|` (infinite for a black region).
    pub fn relative_error(&self) -> f64 {
        if self.region_mean == 0.0 {
            f64::INFINITY
        } else {
            self.standard_error / self.region_mean.abs()
        }
    }

    /// True when it comes from at least two replications.
    pub fn is_estimated(&self) -> bool {
        self.replications >= 2
    }

    /// The relative error by `measure`.
    pub fn relative(&self, measure: ErrorMeasure) -> f64 {
        match measure {
            ErrorMeasure::Mean => self.relative_error(),
            ErrorMeasure::PixelRmse => self.pixel_relative_error,
        }
    }
}

/// The mean and variance of the mean of replication images, and the
/// replications' region means (see the module docs). Images are added in
/// the order of their replication index; the arithmetic depends only on
/// the images and that order.
#[derive(Debug, Clone)]
pub struct ReplicationAccumulator {
    width: usize,
    height: usize,
    region: PixelRegion,
    /// Running mean per pixel and channel (Welford).
    mean: Vec<[f64; 3]>,
    /// Running sum of squared deviations per pixel and channel.
    squared_deviations: Vec<[f64; 3]>,
    /// Per replication, in the order added: its index and region mean
    /// luminance.
    replications: Vec<(u64, f64)>,
}

impl ReplicationAccumulator {
    /// An accumulator for `width × height` images whose error is measured
    /// over `region` (the whole image if `None`).
    pub fn new(
        width: usize,
        height: usize,
        region: Option<PixelRegion>,
    ) -> Result<Self, ReplicationError> {
        let region = region.unwrap_or([0, 0, width, height]);
        let [x, y, region_width, region_height] = region;
        if region_width == 0
            || region_height == 0
            || x.checked_add(region_width).is_none_or(|end| end > width)
            || y.checked_add(region_height).is_none_or(|end| end > height)
        {
            return Err(ReplicationError::Region {
                region,
                image_width: width,
                image_height: height,
            });
        }
        Ok(Self {
            width,
            height,
            region,
            mean: vec![[0.0; 3]; width * height],
            squared_deviations: vec![[0.0; 3]; width * height],
            replications: Vec::new(),
        })
    }

    /// Adds the image of replication `index`.
    pub fn add(&mut self, index: u64, image: &Image) -> Result<(), ReplicationError> {
        if image.width() != self.width || image.height() != self.height {
            return Err(ReplicationError::Resolution {
                index,
                width: image.width(),
                height: image.height(),
                expected_width: self.width,
                expected_height: self.height,
            });
        }
        if self.replications.iter().any(|(known, _)| *known == index) {
            return Err(ReplicationError::Duplicate(index));
        }
        let count = (self.replications.len() + 1) as f64;
        for ((mean, squared), pixel) in self
            .mean
            .iter_mut()
            .zip(&mut self.squared_deviations)
            .zip(image.pixels())
        {
            for channel in 0..3 {
                let value = f64::from(pixel[channel]);
                let deviation = value - mean[channel];
                mean[channel] += deviation / count;
                squared[channel] += deviation * (value - mean[channel]);
            }
        }
        let [x0, y0, region_width, region_height] = self.region;
        let mut sum = 0.0;
        for y in y0..y0 + region_height {
            for pixel in &image.pixels()[y * self.width + x0..y * self.width + x0 + region_width] {
                sum += luminance(pixel.map(f64::from));
            }
        }
        self.replications
            .push((index, sum / (region_width * region_height) as f64));
        Ok(())
    }

    /// Replications added.
    pub fn count(&self) -> u64 {
        self.replications.len() as u64
    }

    /// The indices of the replications added, in order.
    pub fn indices(&self) -> Vec<u64> {
        self.replications.iter().map(|(index, _)| *index).collect()
    }

    /// The replications' region mean luminances, in the order added.
    pub fn region_means(&self) -> Vec<f64> {
        self.replications.iter().map(|(_, mean)| *mean).collect()
    }

    /// The mean of the replications' images: the render.
    pub fn mean_image(&self) -> Image {
        self.to_image(self.mean.iter().map(|mean| mean.map(|value| value as f32)))
    }

    /// Per pixel and channel, `s² / r`: the estimated variance of the mean
    /// (zero with fewer than two replications).
    pub fn variance_image(&self) -> Image {
        let count = self.count();
        self.to_image(self.squared_deviations.iter().map(|squared| {
            squared.map(|value| {
                if count < 2 {
                    0.0
                } else {
                    ((value / (count - 1) as f64).max(0.0) / count as f64) as f32
                }
            })
        }))
    }

    /// The error estimate of the mean so far.
    pub fn estimate(&self) -> ErrorEstimate {
        let count = self.count();
        let means = self.region_means();
        let region_mean = means.iter().sum::<f64>() / count.max(1) as f64;
        let standard_error = if count < 2 {
            0.0
        } else {
            let variance = means
                .iter()
                .map(|mean| (mean - region_mean).powi(2))
                .sum::<f64>()
                / (count - 1) as f64;
            (variance / count as f64).sqrt()
        };
        let pixel_relative_error = if count < 2 {
            0.0
        } else {
            let [x0, y0, region_width, region_height] = self.region;
            let (mut variance_sum, mut value_sum) = (0.0, 0.0);
            for y in y0..y0 + region_height {
                let row = y * self.width + x0..y * self.width + x0 + region_width;
                for (squared, mean) in self.squared_deviations[row.clone()]
                    .iter()
                    .zip(&self.mean[row])
                {
                    variance_sum += squared.iter().sum::<f64>() / (count - 1) as f64 / count as f64;
                    value_sum += mean.iter().sum::<f64>();
                }
            }
            if value_sum == 0.0 {
                f64::INFINITY
            } else {
                variance_sum.max(0.0).sqrt() / value_sum.abs()
                    * ((3 * region_width * region_height) as f64).sqrt()
            }
        };
        ErrorEstimate {
            replications: count,
            region_mean,
            standard_error,
            pixel_relative_error,
        }
    }

    fn to_image(&self, pixels: impl Iterator<Item = [f32; 3]>) -> Image {
        Image::from_pixels(self.width, self.height, pixels.collect())
            .unwrap_or_else(|_| unreachable!("width × height pixels"))
    }
}

/// When a render of replications stops adding them: at a relative
/// standard error (`lqmc render --target-error`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ErrorTarget {
    /// Stop once the estimated relative error is at most this.
    pub relative_error: f64,
    /// Which error.
    pub measure: ErrorMeasure,
    /// Render at most this many replications.
    pub max_replications: u64,
}

/// Which replications to render, and when to stop.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplicationPlan {
    /// The index of the first replication (`--replication i/r` renders
    /// `i` alone).
    pub first: u64,
    /// Replications to render (with a target: at least this many).
    pub count: u64,
    /// The region the error is measured over (default: the image).
    pub region: Option<PixelRegion>,
    /// Add replications until the error falls to this.
    pub target: Option<ErrorTarget>,
    /// The time budget of the whole render. Without a target each
    /// replication gets an equal share; with a target the replications
    /// run until it is spent (the one it cuts short is left out, unless no
    /// other finished).
    pub time_budget: Option<Duration>,
}

/// Where a render of replications stands, for a progress display.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReplicationProgress {
    /// Replications finished.
    pub finished: u64,
    /// Replications planned (with a target: the planned minimum, or the
    /// estimate of how many the target needs).
    pub planned: u64,
    /// The running replication's pixel samples done and total.
    pub samples_done: u64,
    /// Its total.
    pub samples_total: u64,
    /// The error estimate of the finished replications.
    pub estimate: Option<ErrorEstimate>,
}

/// A render of replications: their merged images and what they measured.
pub struct ReplicationRender {
    /// The finished replications' images.
    pub accumulator: ReplicationAccumulator,
    /// The last replication's output (its details and auxiliary images).
    pub last: RenderOutput,
    /// Sums over every replication rendered (dropped ones included):
    /// samples, rays, non-finite samples; the wall-clock time of all; the
    /// whole passes of the kept ones; the largest peak memory.
    pub statistics: RenderStatistics,
    /// Replications cut short and left out.
    pub dropped: u64,
    /// With a target: whether the estimate reached it.
    pub target_reached: Option<bool>,
}

/// Renders the replications `plan` asks for with `settings` (its seed the
/// base of [`replication_seed`], its samples per pixel each replication's),
/// calling `progress` during each and `finished` with the accumulator after
/// each (a live view). `stop` ends the render after the replication it
/// interrupts, which is left out unless no other finished.
pub fn render_replications(
    scene: &Scene,
    settings: &RenderSettings,
    plan: &ReplicationPlan,
    stop: &AtomicBool,
    progress: &(dyn Fn(ReplicationProgress) + Sync),
    observer: Option<crate::integrators::FilmObserver<'_>>,
    finished: &mut dyn FnMut(&ReplicationAccumulator),
) -> Result<ReplicationRender, RenderError> {
    let started = Instant::now();
    let [width, height] = scene.camera.resolution();
    let mut accumulator = ReplicationAccumulator::new(width as usize, height as usize, plan.region)
        .map_err(|error| RenderError::Unsupported(error.to_string()))?;
    let mut statistics = RenderStatistics::default();
    let mut last = None;
    let mut dropped = 0;
    let mut target_reached = plan.target.map(|_| false);
    let mut index = plan.first;
    loop {
        let done = accumulator.count();
        let estimate = (done >= 2).then(|| accumulator.estimate());
        if let (Some(target), Some(estimate)) = (plan.target, estimate)
            && done >= plan.count
            && estimate.relative(target.measure) <= target.relative_error
        {
            target_reached = Some(true);
            break;
        }
        let limit = plan
            .target
            .map_or(plan.count, |target| target.max_replications.max(plan.count));
        if done + dropped >= limit || (done > 0 && stop.load(Ordering::Relaxed)) {
            break;
        }
        let remaining = plan
            .time_budget
            .map(|budget| budget.saturating_sub(started.elapsed()));
        if remaining.is_some_and(|time| time.is_zero()) && done > 0 {
            break;
        }
        let planned = match (plan.target, estimate) {
            (Some(target), Some(estimate)) => {
                // r × (error / target)² replications reach the target.
                let needed = done as f64
                    * (estimate.relative(target.measure) / target.relative_error).powi(2);
                (needed.ceil() as u64).clamp(done + 1, limit)
            }
            _ => limit,
        };
        let mut replication_settings = settings.clone();
        replication_settings.seed = replication_seed(settings.seed, index);
        replication_settings.time_budget = match (plan.target, plan.time_budget) {
            (_, None) => settings.time_budget,
            (Some(_), Some(_)) => remaining,
            (None, Some(budget)) => Some(budget / plan.count.max(1) as u32),
        };
        let report = |samples_done: u64, samples_total: u64| {
            progress(ReplicationProgress {
                finished: done,
                planned,
                samples_done,
                samples_total,
                estimate,
            })
        };
        let output = render_observed(scene, &replication_settings, stop, &report, observer)?;
        let output_statistics = output.statistics;
        statistics.samples += output_statistics.samples;
        statistics.rays += output_statistics.rays;
        statistics.nonfinite_samples += output_statistics.nonfinite_samples;
        statistics.memory = [statistics.memory, output_statistics.memory]
            .into_iter()
            .flatten()
            .max_by_key(|memory| memory.peak_resident_bytes);
        // Cut short by Ctrl-C, or by the deadline of a render to a target:
        // not a whole replication.
        let interrupted = stop.load(Ordering::Relaxed)
            || (plan.target.is_some()
                && plan.time_budget.is_some()
                && output_statistics.stopped_early);
        if interrupted && done > 0 {
            dropped += 1;
            statistics.stopped_early = true;
            break;
        }
        statistics.completed_samples_per_pixel += output_statistics.completed_samples_per_pixel;
        statistics.stopped_early |= interrupted;
        accumulator
            .add(index, &output.image())
            .map_err(|error| RenderError::Unsupported(error.to_string()))?;
        finished(&accumulator);
        last = Some(output);
        index += 1;
        if interrupted {
            break;
        }
    }
    statistics.elapsed = started.elapsed();
    if target_reached == Some(false) {
        statistics.stopped_early = true;
    }
    Ok(ReplicationRender {
        accumulator,
        last: last.expect("the first replication is always kept"),
        statistics,
        dropped,
        target_reached,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: &[[f32; 3]], width: usize) -> Image {
        Image::from_pixels(width, values.len() / width, values.to_vec()).unwrap()
    }

    /// The mean and `s² / r` match the two-pass formulas; the region mean
    /// and its standard error come from the replications' region means.
    #[test]
    fn mean_variance_and_region_error_match_two_pass_formulas() {
        let replications = [
            [[1.0, 2.0, 3.0], [0.5, 0.5, 0.5]],
            [[2.0, 2.0, 1.0], [1.5, 0.5, 0.0]],
            [[4.0, 1.0, 2.0], [0.5, 2.5, 1.0]],
        ];
        let mut accumulator = ReplicationAccumulator::new(2, 1, Some([1, 0, 1, 1])).unwrap();
        for (index, pixels) in replications.iter().enumerate() {
            accumulator.add(index as u64, &image(pixels, 2)).unwrap();
        }
        let count = replications.len() as f64;
        let mean_image = accumulator.mean_image();
        let variance_image = accumulator.variance_image();
        for pixel in 0..2 {
            for channel in 0..3 {
                let values: Vec<f64> = replications
                    .iter()
                    .map(|r| f64::from(r[pixel][channel]))
                    .collect();
                let mean = values.iter().sum::<f64>() / count;
                let variance =
                    values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (count - 1.0) / count;
                assert!((f64::from(mean_image.pixels()[pixel][channel]) - mean).abs() < 1e-6);
                assert!(
                    (f64::from(variance_image.pixels()[pixel][channel]) - variance).abs() < 1e-6
                );
            }
        }
        let region: Vec<f64> = replications
            .iter()
            .map(|r| luminance(r[1].map(f64::from)))
            .collect();
        let mean = region.iter().sum::<f64>() / count;
        let error =
            (region.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (count - 1.0) / count).sqrt();
        let estimate = accumulator.estimate();
        assert_eq!(estimate.replications, 3);
        assert!((estimate.region_mean - mean).abs() < 1e-12);
        assert!((estimate.standard_error - error).abs() < 1e-12);
        assert!((estimate.relative_error() - error / mean).abs() < 1e-12);
        // Pixel 1's expected relative RMSE: √(mean channel variance) over
        // its mean channel value.
        let variance = variance_image.pixels()[1].map(f64::from);
        let value = mean_image.pixels()[1].map(f64::from);
        let rmse = (variance.iter().sum::<f64>() / 3.0).sqrt() / (value.iter().sum::<f64>() / 3.0);
        assert!((estimate.pixel_relative_error - rmse).abs() < 1e-6 * rmse);
        assert_eq!(
            estimate.relative(ErrorMeasure::PixelRmse),
            estimate.pixel_relative_error
        );
        assert_eq!(accumulator.indices(), vec![0, 1, 2]);
    }

    #[test]
    fn one_replication_has_no_error_estimate() {
        let mut accumulator = ReplicationAccumulator::new(1, 1, None).unwrap();
        accumulator.add(5, &image(&[[1.0; 3]], 1)).unwrap();
        assert!(!accumulator.estimate().is_estimated());
        assert_eq!(accumulator.variance_image().pixels(), &[[0.0; 3]]);
        assert_eq!(accumulator.mean_image().pixels(), &[[1.0; 3]]);
    }

    #[test]
    fn bad_regions_sizes_and_duplicates_are_errors() {
        assert!(ReplicationAccumulator::new(4, 4, Some([2, 2, 3, 1])).is_err());
        assert!(ReplicationAccumulator::new(4, 4, Some([0, 0, 0, 1])).is_err());
        let mut accumulator = ReplicationAccumulator::new(2, 1, None).unwrap();
        accumulator
            .add(0, &image(&[[1.0; 3], [1.0; 3]], 2))
            .unwrap();
        assert_eq!(
            accumulator.add(0, &image(&[[1.0; 3], [1.0; 3]], 2)),
            Err(ReplicationError::Duplicate(0))
        );
        assert!(matches!(
            accumulator.add(1, &image(&[[1.0; 3]], 1)),
            Err(ReplicationError::Resolution { .. })
        ));
    }

    #[test]
    fn replication_zero_is_the_seed_itself_and_the_others_differ() {
        assert_eq!(replication_seed(7, 0), 7);
        let seeds: std::collections::HashSet<u64> =
            (0..1000).map(|index| replication_seed(7, index)).collect();
        assert_eq!(seeds.len(), 1000);
        assert_ne!(replication_seed(7, 1), replication_seed(8, 1));
    }
}
