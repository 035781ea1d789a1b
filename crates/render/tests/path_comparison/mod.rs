//! Comparing an integrator's renders with the path tracer's, for the
//! tests of the integrators that splat (`light_tracing.rs`,
//! `bdpt_convergence.rs`).
//!
//! [`assert_matches_path`] renders the scene small with the path tracer at
//! many samples (its film's variance of the pixel mean is the reference's
//! variance) and with the integrator under test `SEEDS` times with
//! independent seeds. Two statistics, both with variances estimated from
//! the renders:
//!
//! 1. the image mean: each render's mean over pixels and channels is one
//!    independent sample, so `(mean − reference mean) / √(s²/R + v_ref)` is
//!    close to Student's t with R − 1 = 15 degrees of freedom; it must stay
//!    within ±4.5 (two-sided p ≈ 4e-4 for t₁₅). This catches a bias of the
//!    whole image, however small per pixel;
//! 2. the per-pixel z-test: `(Ī_p − ref_p) / √(s_p²/R + v_p)` per channel,
//!    with `s_p²` the sample variance over the seeds. With R = 16 this is
//!    close to t₁₅, for which P(|t| > 3) = 0.9 %; skewed pixel
//!    distributions (rare bright light paths) give somewhat more, so the
//!    fraction above 3 must stay under 2.5 % (the bound of the LQMC
//!    variance test, `lqmc_variance.rs`), and every pixel's mean must be
//!    finite. With the environment variable `DEBUG_Z` set, the pixel
//!    channels above 3 are printed.
#![allow(dead_code)]

use render::image::Image;
use render::integrators::{IntegratorKind, IntegratorSettings};
use render::renderer::{RenderOutput, RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use render::scene::description::SceneDescription;
use std::sync::atomic::AtomicBool;

pub const WIDTH: u32 = 16;
pub const SEEDS: u64 = 16;

pub fn small(mut description: SceneDescription) -> SceneDescription {
    let [width, height] = description.camera.resolution;
    let scaled_height = ((WIDTH as f64 * height as f64 / width as f64).round() as u32).max(1);
    description.camera.resolution = [WIDTH, scaled_height];
    description
}

/// Renders `scene` with the independent sampler.
pub fn render_once(
    scene: &Scene,
    integrator: IntegratorKind,
    spp: u64,
    seed: u64,
    max_depth: u32,
) -> (Image, Image) {
    render_with(
        scene,
        integrator,
        SamplerKind::Independent,
        spp,
        seed,
        max_depth,
    )
}

/// Renders `scene` with `sampler` (randomized by the seed).
pub fn render_with(
    scene: &Scene,
    integrator: impl Into<IntegratorSettings>,
    sampler: SamplerKind,
    spp: u64,
    seed: u64,
    max_depth: u32,
) -> (Image, Image) {
    let output = render_output(scene, integrator, sampler, spp, seed, max_depth, 0);
    (output.image(), output.variance_image())
}

/// The whole render of [`render_with`] on `threads` threads (0: all).
pub fn render_output(
    scene: &Scene,
    integrator: impl Into<IntegratorSettings>,
    sampler: SamplerKind,
    spp: u64,
    seed: u64,
    max_depth: u32,
    threads: usize,
) -> RenderOutput {
    let settings = RenderSettings {
        integrator: integrator.into(),
        sampler,
        samples_per_pixel: spp,
        seed,
        max_depth,
        threads,
        ..RenderSettings::default()
    };
    render(scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap()
}

pub fn values(image: &Image) -> impl Iterator<Item = f64> + '_ {
    image.pixels().iter().flatten().map(|value| *value as f64)
}

/// Pixel-channel indices whose camera ray's first hit is a purely
/// specular surface (light tracing cannot reach them).
pub fn specular_first_hits(scene: &Scene) -> Vec<bool> {
    let [width, height] = scene.camera.resolution();
    let mut mask = Vec::new();
    for y in 0..height {
        for x in 0..width {
            // The pixel's filter reaches about a pixel around its centre.
            let mut specular = false;
            for (dx, dy) in [
                (-1.0, -1.0),
                (1.0, -1.0),
                (-1.0, 1.0),
                (1.0, 1.0),
                (0.0, 0.0),
            ] {
                let raster = glam::Vec2::new(x as f32 + 0.5 + dx, y as f32 + 0.5 + dy);
                let ray = scene.camera.generate_ray(raster, [0.5; 2], 0.5);
                let ray = render::geometry::Ray::with_time(ray.origin, ray.direction, ray.time);
                if let Some(hit) = scene.geometry.intersect(&ray, f32::INFINITY) {
                    let info = &scene.shapes[hit.shape_index as usize];
                    if let Some(material) = &info.material {
                        let wavelengths = render::spectrum::SampledWavelengths::sample_visible(0.5);
                        let bsdf = material.surface_bsdf_at(&hit, &wavelengths);
                        specular |= !bsdf.flags().is_non_specular();
                    }
                }
            }
            mask.extend([specular; 3]);
        }
    }
    mask
}

/// What to compare with the path tracer.
#[derive(Debug, Clone, Copy)]
pub struct Tested {
    /// The integrator.
    pub integrator: IntegratorKind,
    /// Its sampler.
    pub sampler: SamplerKind,
}

/// Light tracing with the independent sampler.
pub const LIGHT: Tested = Tested {
    integrator: IntegratorKind::Light,
    sampler: SamplerKind::Independent,
};

/// Renders `scene` with the path tracer and `tested` and asserts the two
/// statistics of the module docs, skipping the pixel channels `skip` marks.
pub fn assert_matches_path(
    name: &str,
    scene: &Scene,
    tested: Tested,
    path_spp: u64,
    light_spp: u64,
    skip: Option<&[bool]>,
    assert_per_pixel: bool,
) {
    assert_settings_match_path(
        name,
        scene,
        tested.integrator.into(),
        tested.sampler,
        path_spp,
        light_spp,
        skip,
        assert_per_pixel,
    );
}

/// [`assert_matches_path`] for an integrator with its own settings.
#[allow(clippy::too_many_arguments)]
pub fn assert_settings_match_path(
    name: &str,
    scene: &Scene,
    integrator: IntegratorSettings,
    sampler: SamplerKind,
    path_spp: u64,
    light_spp: u64,
    skip: Option<&[bool]>,
    assert_per_pixel: bool,
) {
    let max_depth = scene.max_depth.unwrap_or(6).min(8);
    // Scenes with media are compared with the volumetric path tracer.
    let reference_integrator = if scene.has_media() {
        IntegratorKind::VolPath
    } else {
        IntegratorKind::Path
    };
    let (reference, reference_variance) =
        render_once(scene, reference_integrator, path_spp, 1000, max_depth);
    let count = reference.pixels().len() * 3;
    let keep = |index: usize| skip.is_none_or(|skip| !skip[index]);
    let r = SEEDS as f64;
    let mut sum = vec![0.0f64; count];
    let mut sum_squares = vec![0.0f64; count];
    let mut image_means = Vec::new();
    for seed in 0..SEEDS {
        let (image, _) = render_with(
            scene,
            integrator.clone(),
            sampler,
            light_spp,
            seed,
            max_depth,
        );
        let mut image_sum = 0.0;
        let mut kept = 0usize;
        for (index, value) in values(&image).enumerate() {
            assert!(
                value.is_finite(),
                "{name}: pixel channel {index} is {value}"
            );
            sum[index] += value;
            sum_squares[index] += value * value;
            if keep(index) {
                image_sum += value;
                kept += 1;
            }
        }
        image_means.push(image_sum / kept as f64);
    }
    // 1. The image mean.
    let (mut reference_sum, mut reference_variance_sum, mut kept) = (0.0, 0.0, 0usize);
    for (index, (value, variance)) in values(&reference)
        .zip(values(&reference_variance))
        .enumerate()
    {
        if keep(index) {
            reference_sum += value;
            reference_variance_sum += variance;
            kept += 1;
        }
    }
    let reference_mean = reference_sum / kept as f64;
    // Neighbouring pixels of one path-traced render are independent, so the
    // variance of its mean is the sum of the pixel variances over kept².
    let reference_mean_variance = reference_variance_sum / (kept * kept) as f64;
    let light_mean = image_means.iter().sum::<f64>() / r;
    let light_mean_variance = image_means
        .iter()
        .map(|mean| (mean - light_mean).powi(2))
        .sum::<f64>()
        / (r - 1.0)
        / r;
    let t = (light_mean - reference_mean) / (light_mean_variance + reference_mean_variance).sqrt();
    // 2. Per pixel.
    let mut above_three = 0;
    let mut tests = 0;
    for (index, (reference, reference_variance)) in values(&reference)
        .zip(values(&reference_variance))
        .enumerate()
    {
        if !keep(index) {
            continue;
        }
        let mean = sum[index] / r;
        let variance = (sum_squares[index] / r - mean * mean).max(0.0) * r / (r - 1.0);
        let total = variance / r + reference_variance;
        if total <= 0.0 {
            continue;
        }
        tests += 1;
        if (mean - reference).abs() > 3.0 * total.sqrt() {
            above_three += 1;
            if std::env::var("DEBUG_Z").is_ok() {
                eprintln!(
                    "pixel {} channel {}: {mean:.5} vs {reference:.5}, z = {:.2}",
                    index / 3,
                    index % 3,
                    (mean - reference) / total.sqrt()
                );
            }
        }
    }
    let fraction = above_three as f64 / tests.max(1) as f64;
    eprintln!(
        "{name}: image mean light {light_mean:.5} path {reference_mean:.5} ({:+.3} %, t = {t:.2}); |z| > 3 in {:.2} % of {tests} pixel channels",
        100.0 * (light_mean / reference_mean - 1.0),
        100.0 * fraction
    );
    assert!(
        tests > kept / 2,
        "{name}: only {tests} of {kept} channels tested"
    );
    assert!(t.abs() < 4.5, "{name}: image mean t = {t}");
    if assert_per_pixel {
        assert!(fraction < 0.025, "{name}: |z| > 3 in {fraction}");
    }
}

/// The mean of independent `values` and its standard error.
pub fn mean_and_error(values: &[f64]) -> (f64, f64) {
    let r = values.len() as f64;
    let mean = values.iter().sum::<f64>() / r;
    let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (r - 1.0);
    (mean, (variance / r).sqrt())
}

/// A built-in scene at the tests' width.
pub fn builtin(name: &str) -> Scene {
    Scene::build(&small(builtin_scene(name).unwrap())).unwrap()
}
