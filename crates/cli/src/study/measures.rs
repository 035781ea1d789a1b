//! Error measures over several seeds' renders of one integrator at one
//! budget, beside those of single images that
//! [`render::image::compare::compare_images`] computes (RMSE, relative MSE,
//! mean absolute deviation).
//!
//! - **Mean bias**: how far the average of the seeds' images is from the
//!   reference on the whole, relative to the reference: with `m̄` the mean
//!   over pixels and the three channels of the per-pixel average of the K
//!   images, and `r̄` that of the reference, (m̄ − r̄) / r̄ — the
//!   channel-averaged mean, as `compare_images`' relative mean difference
//!   (0 when the reference's mean is not positive). Noise averages out over
//!   the pixels and seeds; what stays is the estimator's bias (and the
//!   reference's own error).
//! - **Flicker**: how much a pixel changes from one seed to the next (what
//!   an animation rendered with a new seed per frame would show), relative
//!   to the pixel's brightness: the mean over pixels and channels of
//!   s / √(r² + ε), with s the standard deviation of the pixel's value across
//!   the K seeds (denominator K − 1), r the reference's value and ε
//!   [`RELATIVE_MSE_EPSILON`], the offset of the relative MSE (so flicker² is
//!   on the scale of the relative MSE). Undefined (NaN) for fewer than two
//!   seeds.
//!
//! Both use only the pixels where the reference and every image are finite
//! (`compare_images` too leaves non-finite pixels out).

use render::image::Image;
use render::image::compare::RELATIVE_MSE_EPSILON;

/// The median of values and their range.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spread {
    /// The median (the mean of the two middle values for an even count).
    pub median: f64,
    /// The smallest value.
    pub min: f64,
    /// The largest value.
    pub max: f64,
}

/// The median and range of `values` (NaN for none).
pub fn spread(values: &[f64]) -> Spread {
    if values.is_empty() {
        return Spread {
            median: f64::NAN,
            min: f64::NAN,
            max: f64::NAN,
        };
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    let middle = sorted.len() / 2;
    let median = if sorted.len() % 2 == 1 {
        sorted[middle]
    } else {
        0.5 * (sorted[middle - 1] + sorted[middle])
    };
    Spread {
        median,
        min: sorted[0],
        max: sorted[sorted.len() - 1],
    }
}

/// The indices of the pixels where the reference and all images are finite.
fn finite_pixels<'a>(
    images: &'a [Image],
    reference: &'a Image,
) -> impl Iterator<Item = usize> + 'a {
    let finite = |pixel: &[f32; 3]| pixel.iter().all(|value| value.is_finite());
    (0..reference.pixels().len()).filter(move |&index| {
        finite(&reference.pixels()[index])
            && images.iter().all(|image| finite(&image.pixels()[index]))
    })
}

/// Checks that every image has the reference's size.
fn check_sizes(images: &[Image], reference: &Image) {
    for image in images {
        assert_eq!(
            (image.width(), image.height()),
            (reference.width(), reference.height()),
            "the seeds' images and the reference must have one size"
        );
    }
}

/// The mean bias of the seeds' `images` against `reference` (see the
/// module's documentation). Panics if the sizes differ.
pub fn mean_bias(images: &[Image], reference: &Image) -> f64 {
    check_sizes(images, reference);
    if images.is_empty() {
        return f64::NAN;
    }
    let seeds = images.len() as f64;
    let mut average_sum = 0.0f64;
    let mut reference_sum = 0.0f64;
    for index in finite_pixels(images, reference) {
        for channel in 0..3 {
            let seeds_sum: f64 = images
                .iter()
                .map(|image| f64::from(image.pixels()[index][channel]))
                .sum();
            average_sum += seeds_sum / seeds;
            reference_sum += f64::from(reference.pixels()[index][channel]);
        }
    }
    if reference_sum > 0.0 {
        (average_sum - reference_sum) / reference_sum
    } else {
        0.0
    }
}

/// The flicker of the seeds' `images` against `reference` (see the
/// module's documentation); NaN for fewer than two images. Panics if the
/// sizes differ.
pub fn flicker(images: &[Image], reference: &Image) -> f64 {
    check_sizes(images, reference);
    if images.len() < 2 {
        return f64::NAN;
    }
    let seeds = images.len() as f64;
    let mut sum = 0.0f64;
    let mut values = 0usize;
    for index in finite_pixels(images, reference) {
        for channel in 0..3 {
            let value = |image: &Image| f64::from(image.pixels()[index][channel]);
            let mean = images.iter().map(value).sum::<f64>() / seeds;
            let squares: f64 = images
                .iter()
                .map(|image| (value(image) - mean).powi(2))
                .sum();
            let standard_deviation = (squares / (seeds - 1.0)).sqrt();
            let reference_value = f64::from(reference.pixels()[index][channel]);
            sum += standard_deviation
                / (reference_value * reference_value + RELATIVE_MSE_EPSILON).sqrt();
            values += 1;
        }
    }
    if values == 0 {
        f64::NAN
    } else {
        sum / values as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(pixels: &[[f32; 3]]) -> Image {
        Image::from_pixels(pixels.len(), 1, pixels.to_vec()).unwrap()
    }

    fn grey(values: &[f32]) -> Image {
        image(&values.iter().map(|&v| [v; 3]).collect::<Vec<_>>())
    }

    #[test]
    fn spread_has_the_median_of_odd_and_even_counts() {
        let odd = spread(&[3.0, 1.0, 2.0]);
        assert_eq!((odd.median, odd.min, odd.max), (2.0, 1.0, 3.0));
        let even = spread(&[4.0, 1.0, 2.0, 10.0]);
        assert_eq!((even.median, even.min, even.max), (3.0, 1.0, 10.0));
        assert!(spread(&[]).median.is_nan());
    }

    #[test]
    fn mean_bias_is_the_relative_difference_of_the_seeds_average() {
        let reference = grey(&[1.0, 3.0]);
        // Averages 1.5 and 3.5: mean 2.5 against 2.0.
        let images = [grey(&[1.0, 4.0]), grey(&[2.0, 3.0])];
        assert!((mean_bias(&images, &reference) - 0.25).abs() < 1e-15);
        // Unbiased on the whole although every pixel is off.
        let images = [grey(&[2.0, 2.0])];
        assert_eq!(mean_bias(&images, &reference), 0.0);
        // A black reference: 0 by convention.
        assert_eq!(mean_bias(&[grey(&[1.0])], &grey(&[0.0])), 0.0);
    }

    #[test]
    fn mean_bias_averages_the_channels() {
        let reference = image(&[[1.0, 2.0, 3.0]]);
        let images = [image(&[[1.0, 2.0, 6.0]])];
        assert!((mean_bias(&images, &reference) - 0.5).abs() < 1e-15);
    }

    #[test]
    fn flicker_is_the_relative_standard_deviation_across_seeds() {
        let reference = grey(&[1.0, 0.0]);
        // Pixel 0: values 1 and 3, standard deviation √2 (K − 1 = 1), over
        // √(1 + ε). Pixel 1: no change across seeds.
        let images = [grey(&[1.0, 0.5]), grey(&[3.0, 0.5])];
        let expected = (2.0f64.sqrt() / (1.0 + RELATIVE_MSE_EPSILON).sqrt() + 0.0) / 2.0;
        assert!((flicker(&images, &reference) - expected).abs() < 1e-15);
        // Three seeds: values 0, 0, 3 have variance 3 (K − 1 = 2).
        let reference = grey(&[0.0]);
        let images = [grey(&[0.0]), grey(&[0.0]), grey(&[3.0])];
        let expected = 3.0f64.sqrt() / RELATIVE_MSE_EPSILON.sqrt();
        assert!((flicker(&images, &reference) - expected).abs() < 1e-12);
    }

    #[test]
    fn flicker_needs_two_seeds() {
        assert!(flicker(&[grey(&[1.0])], &grey(&[1.0])).is_nan());
    }

    #[test]
    fn non_finite_pixels_are_left_out() {
        let reference = grey(&[1.0, 1.0]);
        let images = [grey(&[1.0, f32::NAN]), grey(&[3.0, 1.0])];
        let expected = 2.0f64.sqrt() / (1.0 + RELATIVE_MSE_EPSILON).sqrt();
        assert!((flicker(&images, &reference) - expected).abs() < 1e-15);
        assert!((mean_bias(&images, &reference) - 1.0).abs() < 1e-15);
    }
}
