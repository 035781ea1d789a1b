//! `lqmc compare`: error measures of an image against a reference, and
//! Mitsuba's per-pixel z-test when the reference's variance is given.

/// Prints a line to stdout, ignoring a closed pipe.
macro_rules! say {
    ($($argument:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout().lock(), $($argument)*);
    }};
}

use crate::error::{CliError, usage};
use crate::json::Json;
use clap::Args;
use render::image::compare::{DEFAULT_ALPHA, ReferenceVariance, compare_images};
use render::image::{Image, Metadata, VARIANCE_LAYER, read_exr, read_image};
use std::path::{Path, PathBuf};

/// Arguments of `lqmc compare`.
#[derive(Args, Debug)]
pub struct CompareArgs {
    /// The image to test (.exr, .pfm or .png).
    pub image: PathBuf,
    /// The reference image.
    pub reference: PathBuf,
    /// The variance of one sample of the reference per pixel (Mitsuba's
    /// `*_var.exr`): enables the per-pixel z-test.
    #[arg(long)]
    pub variance: Option<PathBuf>,
    /// Run the z-test with IMAGE's own `variance` layer instead: the
    /// estimated variance of each pixel's value, which `lqmc render` and
    /// `lqmc merge` write into EXR files for every integrator (the test
    /// then reports 1 spp, as the layer is already divided by the sample
    /// count).
    #[arg(long, conflicts_with_all = ["variance", "spp"])]
    pub image_variance: bool,
    /// Samples per pixel of IMAGE for the z-test (default: the `spp`
    /// metadata that `lqmc render` writes into EXR files).
    #[arg(long)]
    pub spp: Option<u64>,
    /// Family-wise significance level of the z-test (Šidák-corrected per
    /// pixel and channel).
    #[arg(long, default_value_t = DEFAULT_ALPHA)]
    pub alpha: f64,
    /// Print one JSON object instead of text.
    #[arg(long)]
    pub json: bool,
}

/// The image and, for EXR files, their metadata.
fn read_with_metadata(path: &Path) -> Result<(Image, Metadata), CliError> {
    let is_exr = path
        .extension()
        .is_some_and(|extension| extension.eq_ignore_ascii_case("exr"));
    if is_exr {
        let contents = read_exr(path).map_err(|error| usage(error.to_string()))?;
        Ok((contents.image, contents.metadata))
    } else {
        let image = read_image(path).map_err(|error| usage(error.to_string()))?;
        Ok((image, Metadata::new()))
    }
}

/// The `variance` layer of the EXR file `path`.
fn image_variance_layer(path: &Path) -> Result<Image, CliError> {
    let contents = read_exr(path).map_err(|error| usage(error.to_string()))?;
    contents.layers.get(VARIANCE_LAYER).cloned().ok_or_else(|| {
        usage(format!(
            "{} has no `{VARIANCE_LAYER}` layer for --image-variance",
            path.display()
        ))
    })
}

/// Runs `lqmc compare`.
pub fn run(args: &CompareArgs) -> Result<(), CliError> {
    if !(args.alpha > 0.0 && args.alpha < 1.0) {
        return Err(usage("--alpha must be in (0, 1)"));
    }
    let (image, metadata) = read_with_metadata(&args.image)?;
    let (reference, _) = read_with_metadata(&args.reference)?;
    let variance = match &args.variance {
        Some(path) => Some(read_with_metadata(path)?.0),
        None if args.image_variance => Some(image_variance_layer(&args.image)?),
        None => None,
    };
    let samples_per_pixel = match (args.spp, metadata.get("spp")) {
        _ if args.image_variance => Some(1),
        (Some(0), _) => return Err(usage("--spp must be at least 1")),
        (Some(spp), _) => Some(spp),
        (None, Some(text)) => text.trim().parse::<u64>().ok(),
        (None, None) => None,
    };
    let reference_variance = match &variance {
        Some(variance) => Some(ReferenceVariance {
            variance,
            samples_per_pixel: samples_per_pixel.ok_or_else(|| {
                usage(format!(
                    "the z-test needs the samples per pixel of {}: pass --spp N",
                    args.image.display()
                ))
            })?,
            alpha: args.alpha,
        }),
        None => None,
    };
    let comparison = compare_images(&image, &reference, reference_variance)
        .map_err(|error| usage(error.to_string()))?;
    if args.json {
        let mut pairs = vec![
            ("rmse", Json::Number(comparison.rmse)),
            ("relative_mse", Json::Number(comparison.relative_mse)),
            (
                "mean_absolute_deviation",
                Json::Number(comparison.mean_absolute_deviation),
            ),
            ("image_mean", Json::numbers(&comparison.image_mean)),
            ("reference_mean", Json::numbers(&comparison.reference_mean)),
            (
                "relative_mean_difference",
                Json::Number(comparison.relative_mean_difference),
            ),
            (
                "non_finite_pixels",
                Json::Integer(comparison.non_finite_pixels as u64),
            ),
        ];
        if let Some(z_test) = &comparison.z_test {
            pairs.push((
                "z_test",
                Json::object(vec![
                    ("spp", Json::Integer(z_test.samples_per_pixel)),
                    ("alpha", Json::Number(z_test.alpha)),
                    ("passed_pixels", Json::Integer(z_test.passed_pixels as u64)),
                    ("pixels", Json::Integer(z_test.pixels as u64)),
                    ("pass_fraction", Json::Number(z_test.pass_fraction())),
                    ("max_z", Json::Number(z_test.max_z)),
                ]),
            ));
        }
        say!("{}", Json::object(pairs).render());
        return Ok(());
    }
    let [r, g, b] = comparison.image_mean;
    let [rr, rg, rb] = comparison.reference_mean;
    say!("rmse: {:.6e}", comparison.rmse);
    say!("relative mse: {:.6e}", comparison.relative_mse);
    say!(
        "mean absolute deviation: {:.6e}",
        comparison.mean_absolute_deviation
    );
    say!("image mean (rgb): {r:.6} {g:.6} {b:.6}");
    say!("reference mean (rgb): {rr:.6} {rg:.6} {rb:.6}");
    say!(
        "difference of means: {:+.3} %",
        100.0 * comparison.relative_mean_difference
    );
    if comparison.non_finite_pixels > 0 {
        say!("non-finite pixels: {}", comparison.non_finite_pixels);
    }
    if let Some(z_test) = &comparison.z_test {
        say!(
            "z-test ({} spp, alpha {}): {} of {} pixels pass ({:.2} %), max |z| {:.2}",
            z_test.samples_per_pixel,
            z_test.alpha,
            z_test.passed_pixels,
            z_test.pixels,
            100.0 * z_test.pass_fraction(),
            z_test.max_z
        );
    }
    Ok(())
}
