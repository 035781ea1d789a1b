//! The variance layer of LQMC renders (`RenderOutput::variance_image`, from
//! the progression images) is an honest estimate of the variance of each
//! pixel's value.
//!
//! The seed sampler is `independent`, so that progressions — and renders
//! with different seeds — are independent (a seeded Halton render's
//! progressions share one randomization, so they are not). Two checks on a small dof-spheres (b = 0 and b = 1 explored):
//!
//! 1. Agreement with the empirical variance over `SEEDS` independent
//!    renders. Per seed `r`, `a_r = Σ_p v̂_{r,p}` (the estimated variances
//!    summed over pixels and channels) and `e_r = R/(R−1) Σ_p (I_{r,p} −
//!    Ī_p)²` (its squared deviation from the mean over seeds) are both
//!    unbiased for `Σ_p Var(I_p)`; their differences `d_r` are nearly
//!    independent across seeds, so `mean(d) / (sd(d)/√R)` is a t statistic
//!    that accounts for the correlation between neighbouring pixels and for
//!    heavy tails; it must be within ±4, and the ratio `Σ a / Σ e` is
//!    printed with its standard error.
//! 2. The per-pixel z-test against a path-traced reference of many samples
//!    (its film variance added), with this variance: with M = 16
//!    progressions `z` is close to Student's t with 15 degrees of freedom,
//!    for which P(|t| > 3) = 0.9 %; skewed pixel distributions give more.
//!    The path tracer's film variance (exact for independent samples) at
//!    the same samples per pixel is the yardstick: since LQMC's seeds land
//!    as its camera samples (issue 34) their pixels are as skewed, and the
//!    fraction was 3.34 % for LQMC against 3.71 % for the path tracer
//!    when this was written. LQMC's fraction must stay under the path
//!    tracer's plus one percentage point, or under 2.5 %. `lqmc compare`'s
//!    Šidák-corrected z-test (α = 0.01 over all pixels) with this layer is
//!    run and reported but not asserted: its normal threshold (|z| ≈ 4.6)
//!    ignores the reference's noise and the t tails of a 16-progression
//!    variance, so most images fail it (all 12 did when this was written).

use render::image::Image;
use render::image::compare::{ReferenceVariance, compare_images};
use render::integrators::IntegratorKind;
use render::integrators::IntegratorSettings;
use render::integrators::lqmc::{LqmcDetails, LqmcSettings};
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use std::sync::atomic::AtomicBool;

const WIDTH: u32 = 32;
const SEEDS: u64 = 12;
const PROGRESSIONS: u64 = 16;

fn scene(name: &str) -> Scene {
    let mut description = builtin_scene(name).unwrap();
    let [width, height] = description.camera.resolution;
    let scaled_height = ((WIDTH as f64 * height as f64 / width as f64).round() as u32).max(1);
    description.camera.resolution = [WIDTH, scaled_height];
    Scene::build(&description).unwrap()
}

/// One render's image and variance layer.
fn render_once(scene: &Scene, integrator: IntegratorKind, spp: u64, seed: u64) -> (Image, Image) {
    let settings = RenderSettings {
        // The paper's classes, so that dof-spheres' paths are explored.
        integrator: match integrator {
            IntegratorKind::Lqmc => IntegratorSettings::Lqmc(LqmcSettings::paper_classes()),
            other => other.into(),
        },
        sampler: SamplerKind::Independent,
        samples_per_pixel: spp,
        seed,
        max_depth: scene.max_depth.unwrap_or(6),
        ..RenderSettings::default()
    };
    let stop = AtomicBool::new(false);
    let output = render(scene, &settings, &stop, &|_, _| {}).unwrap();
    if integrator == IntegratorKind::Lqmc {
        let progressions = &output.details::<LqmcDetails>().unwrap().progressions;
        assert_eq!(progressions.progressions(), spp);
        // Every progression finished: their mean is the image.
        let image = output.film.image(1.0 / spp as f64);
        let means = progressions.mean().iter().flatten();
        for (mean, value) in means.zip(image.pixels().iter().flatten()) {
            assert!((mean - *value as f64).abs() <= 1e-4 * (1.0 + mean.abs()));
        }
    } else {
        assert!(output.details.is_none() && output.variance.is_none());
    }
    (output.film.image(1.0 / spp as f64), output.variance_image())
}

fn values(image: &Image) -> impl Iterator<Item = f64> + '_ {
    image.pixels().iter().flatten().map(|value| *value as f64)
}

/// Over the pixel channels of `renders` (image, variance layer) with a
/// positive total variance: how many differ from `reference` by more than
/// three standard deviations (the render's and the reference's variance
/// added), and how many were tested.
fn count_above_three(
    renders: &[(Image, Image)],
    reference: &Image,
    reference_variance: &Image,
) -> (usize, usize) {
    let (mut above_three, mut tests) = (0, 0);
    for (image, variance) in renders {
        for ((value, variance), (reference, reference_variance)) in values(image)
            .zip(values(variance))
            .zip(values(reference).zip(values(reference_variance)))
        {
            let total = variance + reference_variance;
            if total <= 0.0 {
                continue;
            }
            tests += 1;
            if (value - reference).abs() > 3.0 * total.sqrt() {
                above_three += 1;
            }
        }
    }
    (above_three, tests)
}

#[test]
fn lqmc_variance_layer_matches_independent_renders_and_passes_the_z_test() {
    let scene = scene("dof-spheres");
    let (reference, reference_variance) = render_once(&scene, IntegratorKind::Path, 512, 1000);
    let renders: Vec<(Image, Image)> = (0..SEEDS)
        .map(|seed| render_once(&scene, IntegratorKind::Lqmc, PROGRESSIONS, seed))
        .collect();
    let count = reference.pixels().len() * 3;
    let r = SEEDS as f64;

    // 1. Estimated against empirical variance.
    let mut mean = vec![0.0f64; count];
    for (image, _) in &renders {
        for (sum, value) in mean.iter_mut().zip(values(image)) {
            *sum += value / r;
        }
    }
    let differences: Vec<f64> = renders
        .iter()
        .map(|(image, variance)| {
            let estimated: f64 = values(variance).sum();
            let empirical: f64 = values(image)
                .zip(&mean)
                .map(|(value, mean)| (value - mean).powi(2))
                .sum::<f64>()
                * r
                / (r - 1.0);
            estimated - empirical
        })
        .collect();
    let estimated_total: f64 = renders.iter().map(|(_, v)| values(v).sum::<f64>()).sum();
    let empirical_total = estimated_total - differences.iter().sum::<f64>();
    let mean_difference = differences.iter().sum::<f64>() / r;
    let spread = (differences
        .iter()
        .map(|d| (d - mean_difference).powi(2))
        .sum::<f64>()
        / (r - 1.0))
        .sqrt();
    let t = mean_difference / (spread / r.sqrt());
    let ratio = estimated_total / empirical_total;
    eprintln!(
        "estimated / empirical variance: {ratio:.3} ± {:.3} (t = {t:.2})",
        spread / r.sqrt() * r / empirical_total
    );
    assert!(t.abs() < 4.0, "ratio {ratio}, t = {t}");

    // 2. Per-pixel z-test against the path tracer, with the layer.
    let (above_three, tests) = count_above_three(&renders, &reference, &reference_variance);
    let mut failed_images = 0;
    for (image, variance) in &renders {
        let comparison = compare_images(
            image,
            &reference,
            Some(ReferenceVariance {
                variance,
                samples_per_pixel: 1,
                alpha: 0.01,
            }),
        )
        .unwrap();
        let z_test = comparison.z_test.unwrap();
        if z_test.passed_pixels < z_test.pixels {
            failed_images += 1;
        }
    }
    let fraction = above_three as f64 / tests as f64;
    eprintln!(
        "|z| > 3 in {:.2} % of {tests} pixel channels; {failed_images} of {SEEDS} images fail the Šidák z-test",
        100.0 * fraction
    );
    assert!(tests > count * SEEDS as usize / 2, "{tests} tests");
    // The yardstick: the path tracer's renders of as many samples, with
    // their film variance.
    let path_renders: Vec<(Image, Image)> = (0..SEEDS)
        .map(|seed| render_once(&scene, IntegratorKind::Path, PROGRESSIONS, 2000 + seed))
        .collect();
    let (path_above_three, path_tests) =
        count_above_three(&path_renders, &reference, &reference_variance);
    let path_fraction = path_above_three as f64 / path_tests as f64;
    eprintln!(
        "the path tracer's film variance at {PROGRESSIONS} spp: |z| > 3 in {:.2} % of {path_tests} pixel channels",
        100.0 * path_fraction
    );
    assert!(
        fraction < 0.025_f64.max(path_fraction + 0.01),
        "lqmc {fraction}, path {path_fraction}"
    );
}
