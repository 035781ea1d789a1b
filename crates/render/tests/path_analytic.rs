//! The path tracer against analytic answers, for every sampler: pbrt-v4's
//! closed-sphere furnace, a white furnace under a constant environment, the
//! depth convention, and determinism across thread counts.
//!
//! Tolerances come from the film's per-pixel variance estimates of the pixel
//! means. In these scenes every pixel sees the same distribution, so the
//! per-pixel test uses the pooled (average) estimate, which is accurate
//! where one pixel's 16-sample estimate is not: a pixel passes when
//! |value − expected| < 6 pooled standard errors, and at most 1 % may fail
//! (path contributions are skewed, so a mean of few samples has a heavier
//! tail than a Gaussian). The image mean must be within 5 standard errors
//! (the sum of the per-pixel variances over the pixel count squared).

use glam::Vec3;
use render::camera::{FovAxis, PerspectiveSettings, look_at};
use render::image::Image;
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use render::scene::description::{
    FilterDescription, LightDescription, MaterialDescription, SceneDescription, ShapeDescription,
    ShapeGeometry, SpectrumDescription,
};
use std::sync::atomic::AtomicBool;

const SAMPLERS: [SamplerKind; 4] = [
    SamplerKind::Halton,
    SamplerKind::Sobol,
    SamplerKind::Independent,
    SamplerKind::Lattice,
];

fn render_images(description: &SceneDescription, settings: &RenderSettings) -> (Image, Image) {
    let scene = Scene::build(description).unwrap();
    let stop = AtomicBool::new(false);
    let output = render(&scene, settings, &stop, &|_, _| {}).unwrap();
    assert_eq!(output.statistics.nonfinite_samples, 0);
    (output.film.image(1.0), output.film.variance_image())
}

/// Checks every pixel and the image mean against `expected` (per channel).
fn assert_matches(image: &Image, variance: &Image, expected: f64, context: &str) {
    let pixels = image.pixels();
    let variances = variance.pixels();
    let count = pixels.len() as f64;
    for channel in 0..3 {
        let pooled_variance = variances.iter().map(|v| v[channel] as f64).sum::<f64>() / count;
        let mean = pixels.iter().map(|v| v[channel] as f64).sum::<f64>() / count;
        let variance_of_mean = pooled_variance / count;
        // A tiny floor keeps zero-variance images (exact results) passing.
        let failures = pixels
            .iter()
            .filter(|v| (v[channel] as f64 - expected).abs() > 6.0 * pooled_variance.sqrt() + 1e-4)
            .count();
        assert!(
            failures as f64 <= 0.01 * count,
            "{context}: {failures} of {count} pixels fail in channel {channel}"
        );
        let bound = 5.0 * variance_of_mean.sqrt() + 1e-4;
        assert!(
            (mean - expected).abs() < bound,
            "{context}: channel {channel} mean {mean} vs {expected} (bound {bound})"
        );
    }
}

fn small_furnace(resolution: u32) -> SceneDescription {
    let mut description = builtin_scene("furnace").unwrap();
    description.camera.resolution = [resolution, resolution];
    description
}

#[test]
fn closed_sphere_furnace_is_one_for_every_sampler() {
    let description = small_furnace(16);
    for sampler in SAMPLERS {
        let settings = RenderSettings {
            sampler,
            samples_per_pixel: 16,
            max_depth: 100,
            seed: 3,
            ..RenderSettings::default()
        };
        let (image, variance) = render_images(&description, &settings);
        assert_matches(&image, &variance, 1.0, &format!("furnace {sampler:?}"));
    }
}

#[test]
fn depth_counts_path_segments_like_mitsuba() {
    // Emission only at depth 1: 0.5; one bounce more at depth 2: 0.5 + 0.25.
    let description = small_furnace(12);
    for (max_depth, expected) in [(1, 0.5), (2, 0.75), (3, 0.875)] {
        let settings = RenderSettings {
            sampler: SamplerKind::Sobol,
            samples_per_pixel: 16,
            max_depth,
            ..RenderSettings::default()
        };
        let (image, variance) = render_images(&description, &settings);
        assert_matches(&image, &variance, expected, &format!("depth {max_depth}"));
    }
}

/// A diffuse sphere of albedo 0.8 filling the view, lit by a constant
/// environment of radiance 1: a convex surface reflects ρ·L = 0.8 exactly.
fn white_furnace() -> SceneDescription {
    let world = look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y).unwrap();
    SceneDescription {
        name: "white-furnace".into(),
        camera: PerspectiveSettings {
            world_from_camera: world,
            world_from_camera_end: world,
            resolution: [12, 12],
            fov_degrees: 10.0,
            fov_axis: FovAxis::X,
            ..Default::default()
        },
        filter: FilterDescription::Box { radius: 0.5 },
        shapes: vec![ShapeDescription::new(
            ShapeGeometry::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
            MaterialDescription::diffuse_rgb([0.8, 0.8, 0.8]),
        )],
        lights: vec![LightDescription::ConstantEnvironment {
            radiance: SpectrumDescription::Rgb([1.0, 1.0, 1.0]),
        }],
        max_depth: Some(6),
        samples_per_pixel: Some(16),
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

#[test]
fn convex_sphere_under_constant_environment_reflects_its_albedo() {
    for sampler in SAMPLERS {
        let settings = RenderSettings {
            sampler,
            samples_per_pixel: 32,
            ..RenderSettings::default()
        };
        let (image, variance) = render_images(&white_furnace(), &settings);
        // The D65-normalised white illuminant maps to sRGB (1, 1, 1) within
        // 2e-4 (the spectral module's measurement), hence the small slack.
        assert_matches(
            &image,
            &variance,
            0.8,
            &format!("white furnace {sampler:?}"),
        );
    }
}

#[test]
fn images_do_not_depend_on_the_thread_count() {
    let mut description = builtin_scene("cornell-box").unwrap();
    description.camera.resolution = [24, 20];
    for sampler in SAMPLERS {
        let settings = |threads| RenderSettings {
            sampler,
            samples_per_pixel: 3,
            threads,
            tile_size: 8,
            seed: 11,
            ..RenderSettings::default()
        };
        let (one, one_variance) = render_images(&description, &settings(1));
        let (two, two_variance) = render_images(&description, &settings(2));
        assert_eq!(one.pixels(), two.pixels(), "{sampler:?}");
        assert_eq!(one_variance.pixels(), two_variance.pixels(), "{sampler:?}");
        // A different seed changes the random samplers' images.
        if sampler == SamplerKind::Independent {
            let other = RenderSettings {
                seed: 12,
                ..settings(2)
            };
            let (reseeded, _) = render_images(&description, &other);
            assert_ne!(one.pixels(), reseeded.pixels());
        }
    }
}

#[test]
fn samplers_agree_on_the_cornell_box_mean() {
    // Three estimators of the same image: their means agree within their
    // combined standard errors.
    let mut description = builtin_scene("cornell-box").unwrap();
    description.camera.resolution = [24, 24];
    let mut results = Vec::new();
    for sampler in SAMPLERS {
        let settings = RenderSettings {
            sampler,
            samples_per_pixel: 16,
            ..RenderSettings::default()
        };
        let (image, variance) = render_images(&description, &settings);
        let count = image.pixels().len() as f64;
        let mean = image.mean();
        let mut variance_of_mean = [0.0f64; 3];
        for pixel in variance.pixels() {
            for c in 0..3 {
                variance_of_mean[c] += pixel[c] as f64 / (count * count);
            }
        }
        results.push((sampler, mean, variance_of_mean));
    }
    for pair in results.windows(2) {
        let ((a, mean_a, var_a), (b, mean_b, var_b)) = (&pair[0], &pair[1]);
        for c in 0..3 {
            let bound = 5.0 * (var_a[c] + var_b[c]).sqrt();
            assert!(
                (mean_a[c] - mean_b[c]).abs() < bound,
                "{a:?} vs {b:?} channel {c}: {} vs {} (bound {bound})",
                mean_a[c],
                mean_b[c]
            );
        }
    }
}
