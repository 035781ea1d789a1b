//! Rendering a scene description and comparing it with a Mitsuba 3
//! reference, for the light tests (`light_*_reference.rs`).
//!
//! The statistic is that of `cornell_reference.rs`: the difference of two
//! independent estimates has the sum of their variances, so (a) each
//! channel's image mean must agree within 4 standard deviations of the
//! difference plus a relative allowance for the known difference of our
//! RGB-illuminant spectra from Mitsuba's (measured on the Cornell box:
//! up to 1 %), and (b) at least `pixel_fraction` of the pixels must have
//! |z| < 4 in every channel.

use std::sync::atomic::AtomicBool;

use render::image::Image;
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::description::SceneDescription;

/// Per pixel (row-major): our mean and the variance of that mean.
pub type Estimate = Vec<([f64; 3], [f64; 3])>;

/// Renders `description` with the independent sampler (whose per-pixel
/// variance estimates are valid) at `samples_per_pixel` and depth `max_depth`.
pub fn render_estimate(
    description: &SceneDescription,
    samples_per_pixel: u64,
    max_depth: u32,
) -> Estimate {
    let scene = Scene::build(description).unwrap();
    let settings = RenderSettings {
        sampler: SamplerKind::Independent,
        samples_per_pixel,
        max_depth,
        seed: 1,
        ..RenderSettings::default()
    };
    let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    assert_eq!(output.statistics.nonfinite_samples, 0);
    let [width, height] = description.camera.resolution;
    let mut estimate = Vec::new();
    for y in 0..height as usize {
        for x in 0..width as usize {
            let pixel = output.film.pixel(x, y).unwrap();
            estimate.push((pixel.weighted_mean(), pixel.variance_of_mean()));
        }
    }
    estimate
}

/// Checks `ours` against the reference mean and the variance of that mean
/// (negative variances, which Mitsuba's files contain, count as 0).
pub fn assert_matches_reference(
    ours: &Estimate,
    reference_mean: &Image,
    reference_variance_of_mean: impl Fn(usize, usize) -> f64,
    pixel_fraction: f64,
) {
    assert_eq!(ours.len(), reference_mean.pixels().len());
    let pixel_count = ours.len() as f64;
    for channel in 0..3 {
        let our_mean = ours.iter().map(|(m, _)| m[channel]).sum::<f64>() / pixel_count;
        let their_mean = reference_mean
            .pixels()
            .iter()
            .map(|p| p[channel] as f64)
            .sum::<f64>()
            / pixel_count;
        let sigma = (ours
            .iter()
            .enumerate()
            .map(|(index, (_, v))| v[channel] + reference_variance_of_mean(index, channel).max(0.0))
            .sum::<f64>()
            / (pixel_count * pixel_count))
            .sqrt();
        eprintln!(
            "channel {channel}: ours {our_mean:.6}, Mitsuba {their_mean:.6}, {:.2} sigma, ratio {:.5}",
            (our_mean - their_mean) / sigma,
            our_mean / their_mean
        );
        assert!(
            (our_mean - their_mean).abs() < 4.0 * sigma + 0.01 * their_mean.abs(),
            "channel {channel}: image mean {our_mean} vs Mitsuba's {their_mean}"
        );
    }
    let mut within = 0usize;
    let mut worst = 0.0f64;
    for (index, ((mean, variance), theirs)) in ours.iter().zip(reference_mean.pixels()).enumerate()
    {
        let mut pass = true;
        for channel in 0..3 {
            let difference = mean[channel] - theirs[channel] as f64;
            // Floor at the f32 precision of the stored reference.
            let precision = 1e-6 * theirs[channel].abs() as f64;
            let variance = (variance[channel]
                + reference_variance_of_mean(index, channel).max(0.0))
            .max(precision * precision);
            let z = if difference == 0.0 {
                0.0
            } else {
                difference / variance.sqrt()
            };
            worst = worst.max(z.abs());
            pass &= z.abs() < 4.0;
        }
        within += usize::from(pass);
    }
    eprintln!("{within} of {pixel_count} pixels within |z| < 4 (worst |z| {worst:.2})");
    assert!(
        within as f64 >= pixel_fraction * pixel_count,
        "only {within} of {pixel_count} pixels agree with Mitsuba within |z| < 4"
    );
}
