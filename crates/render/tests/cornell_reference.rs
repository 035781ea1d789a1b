//! Our path tracer against Mitsuba 3 on the same Cornell box.
//!
//! `builtin:cornell-box` reproduces Mitsuba's `scenes/cbox/cbox-rgb.xml`
//! (geometry, RGB diffuse reflectances, RGB area emitter, camera, box
//! filter, maximum depth 6). The reference in `tests/data/` was rendered by
//! `scripts/perf/mitsuba_cbox_reference.py` with Mitsuba 3.9.1
//! `scalar_spectral`: 32 independent 256 × 256 images of 64 samples per
//! pixel, each box-downsampled to 64 × 64 (`cbox_mitsuba_mean.pfm`), with
//! the per-pixel variance of that mean estimated from the spread of the 32
//! images (`cbox_mitsuba_variance.pfm`); see `cbox_mitsuba_reference.txt`.
//!
//! We render at 64 × 64 directly: with a one-pixel box filter a pixel's
//! value is the integral of radiance over its area, so a 64 × 64 pixel equals
//! the mean of the 4 × 4 pixels of the 256 × 256 image it covers. The
//! independent sampler makes the film's per-pixel variance estimate (`s²/n`)
//! valid for a z-test, and pixels independent of each other.
//!
//! Checks, with the difference of two independent estimates having the sum
//! of their variances:
//! * (a) the image mean per channel agrees within 4 standard deviations of
//!   the difference (variance `Σ (σ²_ours + σ²_ref) / N²` over the `N`
//!   pixels);
//! * (b) per pixel and channel `z = (ours − ref) / √(σ²_ours + σ²_ref)`; at
//!   least 99 % of pixels have `|z| < 4` in all three channels. (Under the
//!   null hypothesis a channel exceeds 4 with probability 6.3e-5, so the
//!   1 % allowance only absorbs the heavy tails of a 1024-sample mean; a
//!   systematic error in a region, such as a wrong wall colour or a missing
//!   bounce, fails it.)
//!
//! Measured (seed 1): image means differ by −0.10 % (R), −0.31 % (G) and
//! −0.96 % (B), i.e. −0.7, −2.2 and −3.1 standard deviations; 4090 of 4096
//! pixels within |z| < 4. The blue deficit is consistent with our RGB
//! illuminant spectrum for the emitter being 0.3–0.5 % below Mitsuba's
//! between 360 and 460 nm (D65 table and sigmoid fit differences), not with
//! a transport error.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use render::image::{Image, read_pfm};
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::builtin::builtin_scene;

/// Side of the compared images in pixels (the reference's).
const RESOLUTION: usize = 64;
/// Our samples per pixel: about 4 M paths, a few seconds on 2 cores.
const SAMPLES_PER_PIXEL: u64 = 1024;
/// Standard deviations allowed for the image means.
const MEAN_TOLERANCE_SIGMAS: f64 = 4.0;
/// Per-pixel |z| bound and the fraction of pixels that must satisfy it.
const PIXEL_Z_BOUND: f64 = 4.0;
const PIXEL_FRACTION_REQUIRED: f64 = 0.99;

fn reference(name: &str) -> Image {
    let path = PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name);
    let image = read_pfm(&path).unwrap_or_else(|error| panic!("{}: {error}", path.display()));
    assert_eq!(
        [image.width(), image.height()],
        [RESOLUTION, RESOLUTION],
        "{name} has an unexpected size"
    );
    image
}

/// Our Cornell box at 64 × 64: per pixel the mean and the variance of the
/// mean, in `f64`.
fn render_ours() -> (Vec<[f64; 3]>, Vec<[f64; 3]>) {
    let mut description = builtin_scene("cornell-box").expect("the built-in Cornell box exists");
    description.camera.resolution = [RESOLUTION as u32, RESOLUTION as u32];
    let scene = Scene::build(&description).expect("the built-in Cornell box builds");
    let settings = RenderSettings {
        sampler: SamplerKind::Independent,
        samples_per_pixel: SAMPLES_PER_PIXEL,
        max_depth: 6,
        threads: 2,
        seed: 1,
        ..RenderSettings::default()
    };
    let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {})
        .expect("the Cornell box renders");
    assert_eq!(output.statistics.nonfinite_samples, 0);
    let mut means = Vec::with_capacity(RESOLUTION * RESOLUTION);
    let mut variances = Vec::with_capacity(RESOLUTION * RESOLUTION);
    for y in 0..RESOLUTION {
        for x in 0..RESOLUTION {
            let pixel = output.film.pixel(x, y).expect("pixel inside the film");
            assert_eq!(pixel.sample_count(), SAMPLES_PER_PIXEL);
            means.push(pixel.weighted_mean());
            variances.push(pixel.variance_of_mean());
        }
    }
    (means, variances)
}

#[test]
fn cornell_box_matches_mitsuba_scalar_spectral() {
    let reference_mean = reference("cbox_mitsuba_mean.pfm");
    let reference_variance = reference("cbox_mitsuba_variance.pfm");
    let (our_mean, our_variance) = render_ours();
    let pixel_count = (RESOLUTION * RESOLUTION) as f64;

    // (a) Image means.
    for channel in 0..3 {
        let ours: f64 = our_mean.iter().map(|p| p[channel]).sum::<f64>() / pixel_count;
        let theirs: f64 = reference_mean
            .pixels()
            .iter()
            .map(|p| p[channel] as f64)
            .sum::<f64>()
            / pixel_count;
        let variance: f64 = our_variance
            .iter()
            .zip(reference_variance.pixels())
            .map(|(o, r)| o[channel] + r[channel] as f64)
            .sum::<f64>()
            / (pixel_count * pixel_count);
        let sigma = variance.sqrt();
        eprintln!(
            "channel {channel}: ours {ours:.6}, Mitsuba {theirs:.6}, difference {:.3e} = {:.2} sigma (sigma {sigma:.2e}), ratio {:.5}",
            ours - theirs,
            (ours - theirs) / sigma,
            ours / theirs
        );
        assert!(
            (ours - theirs).abs() < MEAN_TOLERANCE_SIGMAS * sigma,
            "channel {channel}: image mean {ours} vs Mitsuba's {theirs}: {:.2} standard deviations ({sigma:.3e})",
            (ours - theirs) / sigma
        );
    }

    // (b) Per-pixel z-test.
    let mut within = 0usize;
    let mut worst = (0.0f64, 0usize, 0usize);
    for (index, ((ours, our_var), (theirs, their_var))) in our_mean
        .iter()
        .zip(&our_variance)
        .zip(
            reference_mean
                .pixels()
                .iter()
                .zip(reference_variance.pixels()),
        )
        .enumerate()
    {
        let mut pixel_within = true;
        for channel in 0..3 {
            let difference = ours[channel] - theirs[channel] as f64;
            // Floor the variance at f32 storage precision of the reference.
            let precision = 1e-6 * theirs[channel].abs() as f64;
            let variance =
                (our_var[channel] + their_var[channel] as f64).max(precision * precision);
            // Pixels that see only the black outside of the box are exactly
            // zero in both images, with zero variance: they agree.
            let z = if difference == 0.0 {
                0.0
            } else {
                difference / variance.sqrt()
            };
            if z.abs() >= PIXEL_Z_BOUND || !z.is_finite() {
                pixel_within = false;
            }
            if z.abs() > worst.0.abs() {
                worst = (z, index, channel);
            }
        }
        within += usize::from(pixel_within);
    }
    let fraction = within as f64 / pixel_count;
    eprintln!(
        "pixels with |z| < {PIXEL_Z_BOUND} in every channel: {within} of {} ({:.2} %); worst z {:.2} at pixel ({}, {}) channel {}",
        pixel_count,
        100.0 * fraction,
        worst.0,
        worst.1 % RESOLUTION,
        worst.1 / RESOLUTION,
        worst.2
    );
    assert!(
        fraction >= PIXEL_FRACTION_REQUIRED,
        "only {:.2} % of pixels agree with Mitsuba within |z| < {PIXEL_Z_BOUND}",
        100.0 * fraction
    );
}
