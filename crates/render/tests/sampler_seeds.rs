//! Renders with different seeds are independent randomizations for every
//! sampler (issue 15, item 5).
//!
//! For each sampler, 16 renders of a small Cornell box with seeds 1 to 16;
//! per pixel and channel the mean and the sample variance across the 16
//! renders, against the same figures of the independent sampler:
//!
//! 1. wherever the independent renders vary, the sampler's renders vary
//!    too (a sampler the seed does not randomize has variance 0);
//! 2. the pixel means agree with the independent sampler's: Welch's
//!    `t = (m_s − m_i) / √(v_s/16 + v_i/16)` below the two-sided Student-t
//!    critical value with 15 degrees of freedom (the fewest Welch's
//!    approximation can give: heavier tails, so conservative) at a family
//!    level of 0.1 % split over all pixels and channels (Bonferroni, valid
//!    however the pixels of one render are correlated);
//! 3. the image means agree: per seed `r` the difference `D_r` of the two
//!    samplers' image means; the 16 `D_r` are independent (different
//!    seeds, different samplers) with mean 0 if both are unbiased, so
//!    `mean(D) / (sd(D)/4)` is a t statistic with 15 degrees of freedom
//!    (image means of 768 values are close to normal), tested at 0.1 %.
//!
//! The ratio of the mean per-pixel variances (sampler / independent) is
//! printed: QMC samplers are expected below 1.

use render::image::Image;
use render::renderer::{RenderSettings, render};
use render::sampler::{Randomization, SamplerKind};
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use render::statistics::student_t_two_sided_critical;
use std::sync::atomic::AtomicBool;

const SEEDS: u64 = 16;
const SIDE: u32 = 16;
const SAMPLES_PER_PIXEL: u64 = 4;
/// The probability of a false alarm of each test over all its comparisons.
const FAMILY_LEVEL: f64 = 1e-3;

fn cornell_box() -> Scene {
    let mut description = builtin_scene("cornell-box").unwrap();
    description.camera.resolution = [SIDE, SIDE];
    Scene::build(&description).unwrap()
}

fn render_with(
    scene: &Scene,
    sampler: SamplerKind,
    randomization: Randomization,
    seed: u64,
) -> Image {
    let settings = RenderSettings {
        sampler,
        randomization,
        samples_per_pixel: SAMPLES_PER_PIXEL,
        seed,
        max_depth: 6,
        threads: 2,
        ..RenderSettings::default()
    };
    let stop = AtomicBool::new(false);
    render(scene, &settings, &stop, &|_, _| {}).unwrap().image()
}

/// Per pixel and channel (flattened), the mean and sample variance over
/// seeds 1 to 16, and each seed's image mean.
struct SeedStatistics {
    means: Vec<f64>,
    variances: Vec<f64>,
    image_means: Vec<f64>,
}

fn seed_statistics(scene: &Scene, sampler: SamplerKind) -> SeedStatistics {
    let renders: Vec<Vec<f64>> = (1..=SEEDS)
        .map(|seed| {
            render_with(scene, sampler, Randomization::Seeded, seed)
                .pixels()
                .iter()
                .flat_map(|rgb| rgb.map(f64::from))
                .collect()
        })
        .collect();
    let values = renders[0].len();
    let n = SEEDS as f64;
    let means: Vec<f64> = (0..values)
        .map(|v| renders.iter().map(|render| render[v]).sum::<f64>() / n)
        .collect();
    let variances = (0..values)
        .map(|v| {
            renders
                .iter()
                .map(|render| (render[v] - means[v]).powi(2))
                .sum::<f64>()
                / (n - 1.0)
        })
        .collect();
    let image_means = renders
        .iter()
        .map(|render| render.iter().sum::<f64>() / values as f64)
        .collect();
    SeedStatistics {
        means,
        variances,
        image_means,
    }
}

#[test]
fn every_sampler_is_an_independent_randomization_per_seed() {
    let scene = cornell_box();
    let independent = seed_statistics(&scene, SamplerKind::Independent);
    let values = independent.means.len();
    let degrees_of_freedom = (SEEDS - 1) as f64;
    let pixel_critical =
        student_t_two_sided_critical(FAMILY_LEVEL / values as f64, degrees_of_freedom);
    let image_critical = student_t_two_sided_critical(FAMILY_LEVEL, degrees_of_freedom);
    for sampler in [
        SamplerKind::Halton,
        SamplerKind::Sobol,
        SamplerKind::Lattice,
        SamplerKind::GlobalSobol,
        SamplerKind::GlobalNiederreiter,
        SamplerKind::Hammersley,
        SamplerKind::Padded,
        SamplerKind::LatinSupercube,
    ] {
        let statistics = seed_statistics(&scene, sampler);
        let name = sampler.name();
        let mut largest_t = 0.0f64;
        for v in 0..values {
            let (mean, variance) = (statistics.means[v], statistics.variances[v]);
            let (reference_mean, reference_variance) =
                (independent.means[v], independent.variances[v]);
            if reference_variance > 0.0 {
                assert!(
                    variance > 0.0,
                    "{name}: value {v} is the same for every seed (independent variance {reference_variance})"
                );
            }
            let standard_error = ((variance + reference_variance) / SEEDS as f64).sqrt();
            if standard_error == 0.0 {
                assert_eq!(mean, reference_mean, "{name}: value {v}");
                continue;
            }
            let t = (mean - reference_mean) / standard_error;
            largest_t = largest_t.max(t.abs());
        }
        assert!(
            largest_t < pixel_critical,
            "{name}: largest pixel |t| {largest_t} ≥ {pixel_critical}"
        );
        let differences: Vec<f64> = statistics
            .image_means
            .iter()
            .zip(&independent.image_means)
            .map(|(a, b)| a - b)
            .collect();
        let mean_difference = differences.iter().sum::<f64>() / SEEDS as f64;
        let spread = (differences
            .iter()
            .map(|d| (d - mean_difference).powi(2))
            .sum::<f64>()
            / (SEEDS - 1) as f64)
            .sqrt();
        let image_t = mean_difference / (spread / (SEEDS as f64).sqrt());
        assert!(
            image_t.abs() < image_critical,
            "{name}: image mean t {image_t} (critical {image_critical})"
        );
        let variance_ratio =
            statistics.variances.iter().sum::<f64>() / independent.variances.iter().sum::<f64>();
        println!(
            "{name}: mean per-pixel variance ratio to independent {variance_ratio:.3}, \
             largest pixel |t| {largest_t:.2} (critical {pixel_critical:.2}), \
             image mean t {image_t:.2} (critical {image_critical:.2})"
        );
    }
}

/// Without randomization the Halton renders do not change with the seed
/// (paths of 6 segments use far fewer than its 256 dimensions): the check
/// above would catch a sampler the seed does not reach.
#[test]
fn unrandomized_halton_renders_do_not_depend_on_the_seed() {
    let scene = cornell_box();
    let first = render_with(&scene, SamplerKind::Halton, Randomization::None, 1);
    let second = render_with(&scene, SamplerKind::Halton, Randomization::None, 2);
    assert_eq!(first, second);
}
