//! Comparing a rendered image with a reference: the error measures rendering
//! papers report (RMSE, relative MSE, mean absolute deviation, the
//! difference of image means) and, given the reference's per-pixel variance,
//! the per-pixel z-test with which Mitsuba 3 tests its own renders.
//!
//! # The z-test
//!
//! Mitsuba's reference sets store, per pixel and channel, the mean of many
//! samples and the variance σ² of *one* sample. A render with `n` samples per
//! pixel then has standard error σ/√n (assuming its estimator has the same
//! per-sample variance), so z = |image − reference| · √(n / σ²) is a
//! standard normal deviate where the render is unbiased. As Mitsuba does,
//! variances are floored at 10⁻⁴ (so black pixels do not fail on rounding)
//! and the significance level is Šidák-corrected for the number of tests:
//! a channel fails when its two-sided p-value is below
//! 1 − (1 − α)^(1/tests) with α = 0.01 by default. A pixel passes when all
//! three channels pass. Non-finite values fail.
//!
//! The test runs in CIE XYZ, not in RGB, as Mitsuba's does
//! (`src/render/tests/test_renders.py` converts image, reference and variance
//! image with `Bitmap.convert(XYZ)`): Mitsuba's moment integrator computes
//! the variance of the XYZ sample and writes it through the XYZ → sRGB
//! matrix, so the RGB "variance" of a spectral reference is a linear mix of
//! XYZ variances with negative weights (often negative itself) and is only a
//! variance again after the inverse matrix. Tested in RGB, a spectral render
//! fails wherever the floored RGB variance understates the true one.
//! (Mitsuba applies Šidák over the pixel count and counts passing channels;
//! here the correction is over all 3 × pixels tests and pixels are counted.)

use super::{Image, ImageError};
use crate::statistics::regularized_gamma_q;

/// The variance floor of the z-test (Mitsuba's).
pub const VARIANCE_FLOOR: f64 = 1e-4;

/// Linear sRGB (Rec. 709 primaries, D65) → CIE XYZ with the 6-decimal
/// coefficients Mitsuba 3 uses (`srgb_to_xyz` in its `color.h`): the inverse,
/// to about 10⁻⁶, of the XYZ → sRGB matrix with which Mitsuba wrote its
/// reference and variance images. The project's 4-decimal
/// [`crate::spectrum::LINEAR_SRGB_TO_XYZ`] would leave errors of ~10⁻⁴ of the
/// large, cancelling RGB variance components.
pub const MITSUBA_LINEAR_SRGB_TO_XYZ: [[f64; 3]; 3] = [
    [0.412453, 0.357580, 0.180423],
    [0.212671, 0.715160, 0.072169],
    [0.019334, 0.119193, 0.950227],
];

/// A pixel's linear sRGB values in CIE XYZ ([`MITSUBA_LINEAR_SRGB_TO_XYZ`]).
fn srgb_pixel_to_xyz(rgb: [f32; 3]) -> [f64; 3] {
    MITSUBA_LINEAR_SRGB_TO_XYZ.map(|row| {
        row[0] * f64::from(rgb[0]) + row[1] * f64::from(rgb[1]) + row[2] * f64::from(rgb[2])
    })
}

/// The default family-wise significance level α of the z-test (Mitsuba's).
pub const DEFAULT_ALPHA: f64 = 0.01;

/// The offset ε of the relative MSE, (a − b)² / (b² + ε).
pub const RELATIVE_MSE_EPSILON: f64 = 1e-2;

/// The outcome of the per-pixel z-test.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ZTest {
    /// Samples per pixel of the tested image.
    pub samples_per_pixel: u64,
    /// The family-wise significance level α.
    pub alpha: f64,
    /// The Šidák-corrected per-channel significance level.
    pub per_test_level: f64,
    /// Pixels where every channel passed.
    pub passed_pixels: usize,
    /// All pixels.
    pub pixels: usize,
    /// The largest |z| seen.
    pub max_z: f64,
}

impl ZTest {
    /// The fraction of pixels that passed.
    pub fn pass_fraction(&self) -> f64 {
        self.passed_pixels as f64 / self.pixels.max(1) as f64
    }
}

/// Error measures of an image against a reference (averaged over pixels and
/// the three channels).
#[derive(Debug, Clone, PartialEq)]
pub struct ImageComparison {
    /// Root mean squared error.
    pub rmse: f64,
    /// Mean of (a − b)² / (b² + [`RELATIVE_MSE_EPSILON`]).
    pub relative_mse: f64,
    /// Mean absolute deviation |a − b|.
    pub mean_absolute_deviation: f64,
    /// Per-channel mean of the image.
    pub image_mean: [f64; 3],
    /// Per-channel mean of the reference.
    pub reference_mean: [f64; 3],
    /// (mean of image − mean of reference) / mean of reference over all
    /// channels (0 when the reference is black).
    pub relative_mean_difference: f64,
    /// Pixels of the image with a NaN or infinite channel (left out of the
    /// error measures; they fail the z-test).
    pub non_finite_pixels: usize,
    /// The z-test, when a variance image was given.
    pub z_test: Option<ZTest>,
}

/// The variance of one sample per pixel and channel, and the sample count of
/// the image under test.
#[derive(Debug, Clone, Copy)]
pub struct ReferenceVariance<'a> {
    /// Variance of one sample (Mitsuba's `*_var.exr`).
    pub variance: &'a Image,
    /// Samples per pixel of the image under test.
    pub samples_per_pixel: u64,
    /// Family-wise significance level (default [`DEFAULT_ALPHA`]).
    pub alpha: f64,
}

/// Compares `image` with `reference`; with `variance`, runs the z-test too.
/// Fails when the sizes differ.
pub fn compare_images(
    image: &Image,
    reference: &Image,
    variance: Option<ReferenceVariance<'_>>,
) -> Result<ImageComparison, ImageError> {
    let size_error = |what: &str, other: &Image| ImageError::SizeMismatch {
        what: what.to_string(),
        expected: (image.width(), image.height()),
        found: (other.width(), other.height()),
    };
    if (image.width(), image.height()) != (reference.width(), reference.height()) {
        return Err(size_error("reference", reference));
    }
    if let Some(variance) = &variance
        && (image.width(), image.height())
            != (variance.variance.width(), variance.variance.height())
    {
        return Err(size_error("variance image", variance.variance));
    }
    let mut squared = 0.0f64;
    let mut relative = 0.0f64;
    let mut absolute = 0.0f64;
    let mut image_sum = [0.0f64; 3];
    let mut reference_sum = [0.0f64; 3];
    let mut finite_pixels = 0usize;
    let mut non_finite_pixels = 0usize;
    for (a, b) in image.pixels().iter().zip(reference.pixels()) {
        if !a.iter().all(|c| c.is_finite()) {
            non_finite_pixels += 1;
            continue;
        }
        finite_pixels += 1;
        for channel in 0..3 {
            let (a, b) = (f64::from(a[channel]), f64::from(b[channel]));
            let difference = a - b;
            squared += difference * difference;
            relative += difference * difference / (b * b + RELATIVE_MSE_EPSILON);
            absolute += difference.abs();
            image_sum[channel] += a;
            reference_sum[channel] += b;
        }
    }
    let values = (3 * finite_pixels).max(1) as f64;
    let pixels = finite_pixels.max(1) as f64;
    let image_mean = image_sum.map(|sum| sum / pixels);
    let reference_mean = reference_sum.map(|sum| sum / pixels);
    let reference_total: f64 = reference_mean.iter().sum();
    let relative_mean_difference = if reference_total > 0.0 {
        (image_mean.iter().sum::<f64>() - reference_total) / reference_total
    } else {
        0.0
    };
    let z_test = variance.map(|variance| z_test(image, reference, variance));
    Ok(ImageComparison {
        rmse: (squared / values).sqrt(),
        relative_mse: relative / values,
        mean_absolute_deviation: absolute / values,
        image_mean,
        reference_mean,
        relative_mean_difference,
        non_finite_pixels,
        z_test,
    })
}

/// The two-sided tail probability P(|Z| ≥ z) of a standard normal Z:
/// Q(1/2, z²/2) with the regularized upper incomplete gamma function.
pub fn normal_two_sided_p_value(z: f64) -> f64 {
    if z.is_nan() {
        return 0.0;
    }
    regularized_gamma_q(0.5, 0.5 * z * z)
}

fn z_test(image: &Image, reference: &Image, variance: ReferenceVariance<'_>) -> ZTest {
    let tests = (3 * image.pixels().len()).max(1) as f64;
    let per_test_level = 1.0 - (1.0 - variance.alpha).powf(1.0 / tests);
    let n = variance.samples_per_pixel as f64;
    let mut passed_pixels = 0;
    let mut max_z = 0.0f64;
    for ((a, b), v) in image
        .pixels()
        .iter()
        .zip(reference.pixels())
        .zip(variance.variance.pixels())
    {
        let mut pixel_passes = true;
        let (a, b, v) = (
            srgb_pixel_to_xyz(*a),
            srgb_pixel_to_xyz(*b),
            srgb_pixel_to_xyz(*v),
        );
        for channel in 0..3 {
            let difference = (a[channel] - b[channel]).abs();
            let sigma2 = v[channel].max(VARIANCE_FLOOR);
            let z = difference * (n / sigma2).sqrt();
            if !z.is_finite() {
                pixel_passes = false;
                max_z = f64::INFINITY;
                continue;
            }
            max_z = max_z.max(z);
            if normal_two_sided_p_value(z) < per_test_level {
                pixel_passes = false;
            }
        }
        if pixel_passes {
            passed_pixels += 1;
        }
    }
    ZTest {
        samples_per_pixel: variance.samples_per_pixel,
        alpha: variance.alpha,
        per_test_level,
        passed_pixels,
        pixels: image.pixels().len(),
        max_z,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(values: &[[f32; 3]]) -> Image {
        Image::from_pixels(values.len(), 1, values.to_vec()).unwrap()
    }

    #[test]
    fn identical_images_have_zero_error_and_pass() {
        let a = image(&[[0.5, 0.25, 1.0], [0.0, 0.0, 0.0]]);
        let variance = image(&[[0.1; 3], [0.1; 3]]);
        let comparison = compare_images(
            &a,
            &a,
            Some(ReferenceVariance {
                variance: &variance,
                samples_per_pixel: 16,
                alpha: DEFAULT_ALPHA,
            }),
        )
        .unwrap();
        assert_eq!(comparison.rmse, 0.0);
        assert_eq!(comparison.relative_mse, 0.0);
        assert_eq!(comparison.relative_mean_difference, 0.0);
        assert_eq!(comparison.z_test.unwrap().pass_fraction(), 1.0);
    }

    #[test]
    fn error_measures_match_hand_computation() {
        let a = image(&[[1.0, 1.0, 1.0], [2.0, 2.0, 2.0]]);
        let b = image(&[[1.0, 1.0, 1.0], [1.0, 1.0, 1.0]]);
        let comparison = compare_images(&a, &b, None).unwrap();
        // Differences: three 0s and three 1s.
        assert!((comparison.rmse - (0.5f64).sqrt()).abs() < 1e-12);
        assert!((comparison.mean_absolute_deviation - 0.5).abs() < 1e-12);
        assert!((comparison.relative_mse - 0.5 / 1.01).abs() < 1e-12);
        assert!((comparison.relative_mean_difference - 0.5).abs() < 1e-12);
    }

    #[test]
    fn z_test_flags_a_biased_pixel_and_non_finite_values() {
        let reference = image(&[[1.0; 3], [1.0; 3], [1.0; 3]]);
        let variance = image(&[[1.0; 3], [1.0; 3], [1.0; 3]]);
        // With n = 100 the standard error is 0.1: 0.05 off is fine, 1.0 off is 10σ.
        let tested = image(&[[1.05; 3], [2.0, 1.0, 1.0], [f32::NAN, 1.0, 1.0]]);
        let comparison = compare_images(
            &tested,
            &reference,
            Some(ReferenceVariance {
                variance: &variance,
                samples_per_pixel: 100,
                alpha: DEFAULT_ALPHA,
            }),
        )
        .unwrap();
        let z_test = comparison.z_test.unwrap();
        assert_eq!(z_test.passed_pixels, 1);
        assert_eq!(comparison.non_finite_pixels, 1);
    }

    #[test]
    #[allow(clippy::needless_range_loop)] // a matrix product, indexed as written
    fn z_test_runs_in_xyz_where_spectral_variances_are_variances() {
        // A pixel of Mitsuba's test_constant_ref_spectral_var.exr (background,
        // constant emitter): the RGB "variance" is negative in red, so an RGB
        // test floors it to 1e-4 and fails a render whose red is off by its
        // own noise (0.04 at 64 spp). In XYZ the variances are positive and
        // above the floor (0.011, 0.0012, 0.30), and the pixel passes.
        let variance = image(&[[-0.114_687_2, 0.004_162_3, 0.313_992_5]]);
        let xyz = srgb_pixel_to_xyz(variance.pixels()[0]);
        assert!(xyz.iter().all(|&v| v > 1e-3), "{xyz:?}");
        let reference = image(&[[0.999_091_3, 0.999_659_2, 1.003_521]]);
        // The first background pixel of a 64 spp render of that scene.
        let tested = image(&[[0.991_374, 1.004_194, 0.928_199_7]]);
        let z_test = compare_images(
            &tested,
            &reference,
            Some(ReferenceVariance {
                variance: &variance,
                samples_per_pixel: 64,
                alpha: DEFAULT_ALPHA,
            }),
        )
        .unwrap()
        .z_test
        .unwrap();
        assert_eq!(z_test.passed_pixels, 1, "{z_test:?}");
        // The sRGB → XYZ matrix inverts Mitsuba's XYZ → sRGB (3.240479, ...).
        let xyz_to_srgb = [
            [3.240479, -1.537150, -0.498535],
            [-0.969256, 1.875991, 0.041556],
            [0.055648, -0.204043, 1.057311],
        ];
        for (i, row) in MITSUBA_LINEAR_SRGB_TO_XYZ.iter().enumerate() {
            for j in 0..3 {
                let product: f64 = (0..3).map(|k| row[k] * xyz_to_srgb[k][j]).sum();
                let identity = if i == j { 1.0 } else { 0.0 };
                assert!((product - identity).abs() < 1e-5, "{i} {j} {product}");
            }
        }
    }

    #[test]
    fn p_values_of_the_standard_normal() {
        // P(|Z| ≥ 1.959964) = 0.05, P(|Z| ≥ 3.290527) = 0.001.
        assert!((normal_two_sided_p_value(1.959_963_985) - 0.05).abs() < 1e-8);
        assert!((normal_two_sided_p_value(3.290_526_731) - 0.001).abs() < 1e-9);
        assert_eq!(normal_two_sided_p_value(0.0), 1.0);
    }

    #[test]
    fn sizes_must_agree() {
        let a = image(&[[1.0; 3]]);
        let b = image(&[[1.0; 3], [1.0; 3]]);
        assert!(compare_images(&a, &b, None).is_err());
    }
}
