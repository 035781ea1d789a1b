//! The path tracers with `splat_film` (each sample placed uniformly in its
//! pixel's share of the image plane and splatted over the filter's pixels)
//! converge to the image of filter importance sampling, border pixels
//! included, and their variance layer (from the progressions) describes
//! their error.

use render::image::Image;
use render::integrators::IntegratorKind;
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use std::sync::atomic::AtomicBool;

/// A built-in scene at `width` pixels across (aspect ratio kept).
fn small_scene(name: &str, width: u32) -> Scene {
    let mut description = builtin_scene(name).unwrap();
    let [w, h] = description.camera.resolution;
    description.camera.resolution = [width, ((width * h) as f64 / w as f64).round() as u32];
    Scene::build(&description).unwrap()
}

/// The image and its variance layer.
fn render_image(
    scene: &Scene,
    integrator: IntegratorKind,
    splat_film: bool,
    spp: u64,
    seed: u64,
) -> (Image, Image) {
    let settings = RenderSettings {
        integrator: integrator.into(),
        sampler: SamplerKind::Independent,
        samples_per_pixel: spp,
        seed,
        max_depth: scene.max_depth.unwrap_or(6),
        splat_film,
        ..RenderSettings::default()
    };
    let output = render(scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    (output.image(), output.variance_image())
}

/// Per-pixel z-test of `image` against `reference` with both variance
/// layers: at most 1 % of the pixel channels beyond |z| = 4, and the image
/// means within 4 standard errors (from the summed variances: splatting
/// correlates neighbours, so this bound is loose by the filter's width,
/// which is fine for a bias test at the per-cent level).
fn assert_agrees(name: &str, image: (Image, Image), reference: (Image, Image)) {
    let (image, image_variance) = image;
    let (reference, reference_variance) = reference;
    let mut failures = 0;
    let count = image.pixels().len();
    for channel in 0..3 {
        let mut difference_sum = 0.0f64;
        let mut variance_sum = 0.0f64;
        for pixel in 0..count {
            let difference =
                image.pixels()[pixel][channel] as f64 - reference.pixels()[pixel][channel] as f64;
            let variance = image_variance.pixels()[pixel][channel] as f64
                + reference_variance.pixels()[pixel][channel] as f64;
            difference_sum += difference;
            variance_sum += variance;
            if difference.abs() > 4.0 * variance.sqrt() + 1e-5 {
                failures += 1;
            }
        }
        // Neighbouring splatted pixels are positively correlated: allow the
        // image mean the standard error of a 3 × 3 block average.
        let bound = 4.0 * (9.0 * variance_sum).sqrt() / count as f64 + 1e-6;
        assert!(
            (difference_sum / count as f64).abs() < bound,
            "{name}: channel {channel}: mean differs by {} (bound {bound})",
            difference_sum / count as f64
        );
    }
    assert!(
        failures as f64 <= 0.01 * 3.0 * count as f64,
        "{name}: {failures} of {} pixel channels fail |z| > 4",
        3 * count
    );
}

#[test]
fn splatting_path_tracer_converges_to_filter_importance_sampling() {
    // dof-spheres has pbrt-v4's Gaussian filter (radius 1.5): border pixels
    // need the samples beyond the image that the grown image plane places.
    let scene = small_scene("dof-spheres", 40);
    let reference = render_image(&scene, IntegratorKind::Path, false, 512, 1000);
    let splatted = render_image(&scene, IntegratorKind::Path, true, 128, 7);
    assert_agrees("dof-spheres", splatted, reference);
}

#[test]
fn splatting_volumetric_path_tracer_converges_to_filter_importance_sampling() {
    let scene = small_scene("translucent-spheres", 32);
    let reference = render_image(&scene, IntegratorKind::VolPath, false, 256, 1000);
    let splatted = render_image(&scene, IntegratorKind::VolPath, true, 64, 7);
    assert_agrees("translucent-spheres", splatted, reference);
}

#[test]
#[allow(clippy::needless_range_loop)] // pixel and channel index four arrays
fn the_variance_layer_of_a_splatting_render_predicts_its_spread() {
    // As `lqmc_variance.rs` checks LQMC's layer: per seed r, a_r = Σ_p v̂
    // (the layer summed over pixels and channels) and e_r = R/(R−1) Σ_p
    // (I_{r,p} − Ī_p)² are both unbiased for Σ_p Var(I_p); their
    // differences are nearly independent across seeds, so their mean over
    // its standard error is a t statistic robust to the correlation of
    // neighbouring splatted pixels and to heavy tails.
    const SEEDS: u64 = 10;
    let scene = small_scene("dof-spheres", 32);
    let renders: Vec<(Image, Image)> = (0..SEEDS)
        .map(|seed| render_image(&scene, IntegratorKind::Path, true, 16, seed))
        .collect();
    let count = renders[0].0.pixels().len();
    let r = SEEDS as f64;
    let mut mean = vec![[0.0f64; 3]; count];
    for (image, _) in &renders {
        for (sum, value) in mean.iter_mut().zip(image.pixels()) {
            for channel in 0..3 {
                sum[channel] += value[channel] as f64 / r;
            }
        }
    }
    let differences: Vec<f64> = renders
        .iter()
        .map(|(image, variance)| {
            let mut estimated = 0.0;
            let mut empirical = 0.0;
            for pixel in 0..count {
                for channel in 0..3 {
                    estimated += variance.pixels()[pixel][channel] as f64;
                    let deviation = image.pixels()[pixel][channel] as f64 - mean[pixel][channel];
                    empirical += r / (r - 1.0) * deviation * deviation;
                }
            }
            estimated - empirical
        })
        .collect();
    let average = differences.iter().sum::<f64>() / r;
    let spread = (differences
        .iter()
        .map(|d| (d - average).powi(2))
        .sum::<f64>()
        / (r - 1.0))
        .sqrt();
    let t = average / (spread / r.sqrt()).max(1e-30);
    assert!(t.abs() < 4.0, "t = {t}");
}
