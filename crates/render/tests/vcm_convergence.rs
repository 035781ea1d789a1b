//! Vertex connection and merging (`--integrator vcm`) converges to the path
//! tracer's image: the image-mean t-test and per-pixel z-test of
//! [`path_comparison`] (variances from 16 independent seeds) on built-in
//! scenes, with the independent sampler and randomized Halton.
//!
//! VCM is consistent, not unbiased: a merge at radius r blurs the light
//! arriving within r, a bias of order r² where the arriving light is not
//! constant. At the default radius (0.003 of the scene's radius) and
//! 16-pixel-wide images a merge's share is tiny and the bias far below the
//! renders' noise, so the tolerances are those of the unbiased
//! integrators (|t| < 4.5 for the image mean, under 2.5 % of pixel
//! channels with |z| > 3). The merges themselves are tested where their
//! bias vanishes for any radius: in the furnace (a sphere of constant
//! radiance, whose area within a ball of radius r around a point of it is
//! exactly π r², Archimedes' hat-box theorem), by every mode including the
//! merges-only `bpm` and `ppm` at a large radius, per pixel as well.

use render::integrators::IntegratorSettings;
use render::integrators::vcm::{VcmMode, VcmSettings, VcmStatistics};
use render::sampler::SamplerKind;

mod path_comparison;
use path_comparison::{
    SEEDS, assert_settings_match_path, builtin, mean_and_error, render_output, values,
};

fn vcm(mode: VcmMode, radius_fraction: f32) -> IntegratorSettings {
    IntegratorSettings::Vcm(VcmSettings {
        mode,
        radius_fraction,
        ..VcmSettings::default()
    })
}

#[test]
fn vcm_matches_path_tracing_in_the_cornell_box() {
    assert_settings_match_path(
        "cornell-box (vcm)",
        &builtin("cornell-box"),
        vcm(VcmMode::Vcm, 0.003),
        SamplerKind::Independent,
        4096,
        64,
        None,
        true,
    );
}

#[test]
fn vcm_with_halton_matches_path_tracing_in_the_cornell_box() {
    assert_settings_match_path(
        "cornell-box (vcm, Halton)",
        &builtin("cornell-box"),
        vcm(VcmMode::Vcm, 0.003),
        SamplerKind::Halton,
        4096,
        64,
        None,
        true,
    );
}

/// The caustic under the glass sphere: light paths that BDPT reaches only
/// by light tracing, which merges also reach.
#[test]
fn vcm_matches_path_tracing_in_the_glass_sphere_box() {
    assert_settings_match_path(
        "glass-sphere-box (vcm)",
        &builtin("glass-sphere-box"),
        vcm(VcmMode::Vcm, 0.003),
        SamplerKind::Independent,
        8192,
        64,
        None,
        true,
    );
}

/// `--vcm-mode bpt` is BDPT with the iteration's shared wavelengths: the
/// same image in expectation.
#[test]
fn bpt_mode_matches_path_tracing() {
    assert_settings_match_path(
        "cornell-box (vcm-mode bpt)",
        &builtin("cornell-box"),
        vcm(VcmMode::Bpt, 0.003),
        SamplerKind::Independent,
        4096,
        64,
        None,
        true,
    );
}

/// In the furnace every pixel is 1 whatever the radius: every mode, the
/// merging ones at a radius of a tenth of the sphere's. The image mean's
/// t-test, and per pixel channel the z-test of its mean over the seeds
/// against 1 (under 2.5 % of channels with |z| > 3, as for the unbiased
/// integrators: here merges carry the whole image of `bpm` and `ppm`, and
/// their bias is exactly zero).
#[test]
fn every_mode_gives_one_in_the_furnace() {
    let scene = builtin("furnace");
    for (mode, radius) in [
        (VcmMode::Vcm, 0.003),
        (VcmMode::Vcm, 0.1),
        (VcmMode::Bpt, 0.003),
        (VcmMode::Bpm, 0.1),
        (VcmMode::Ppm, 0.1),
    ] {
        let images: Vec<Vec<f64>> = (0..SEEDS)
            .map(|seed| {
                values(
                    &render_output(
                        &scene,
                        vcm(mode, radius),
                        SamplerKind::Independent,
                        32,
                        seed,
                        64,
                        0,
                    )
                    .image(),
                )
                .collect()
            })
            .collect();
        let means: Vec<f64> = images
            .iter()
            .map(|image| image.iter().sum::<f64>() / image.len() as f64)
            .collect();
        let (mean, error) = mean_and_error(&means);
        let t = (mean - 1.0) / error;
        let channels = images[0].len();
        let above_three = (0..channels)
            .filter(|&channel| {
                let seeds: Vec<f64> = images.iter().map(|image| image[channel]).collect();
                let (mean, error) = mean_and_error(&seeds);
                (mean - 1.0).abs() > 3.0 * error
            })
            .count();
        let fraction = above_three as f64 / channels as f64;
        eprintln!(
            "furnace ({}, radius {radius}): {mean:.5} ± {error:.5} (t = {t:.2}); |z| > 3 in {:.2} % of {channels} pixel channels",
            mode.name(),
            100.0 * fraction
        );
        assert!(
            t.abs() < 4.5,
            "furnace ({}) mean {mean} ± {error}",
            mode.name()
        );
        assert!(
            fraction < 0.025,
            "furnace ({}): |z| > 3 in {fraction}",
            mode.name()
        );
    }
}

/// The image does not depend on the number of threads, and the render
/// reports its iterations and merges.
#[test]
fn one_image_for_any_thread_count() {
    let scene = builtin("cornell-box");
    let renders: Vec<_> = [1, 2, 3]
        .iter()
        .map(|&threads| {
            render_output(
                &scene,
                vcm(VcmMode::Vcm, 0.05),
                SamplerKind::Independent,
                4,
                7,
                6,
                threads,
            )
        })
        .collect();
    let first = renders[0].image();
    for output in &renders[1..] {
        assert_eq!(output.image().pixels(), first.pixels());
    }
    let statistics = renders[0]
        .details::<VcmStatistics>()
        .expect("VCM reports its statistics");
    assert_eq!(statistics.iterations, 4);
    assert!(statistics.merges > 0, "{statistics:?}");
    assert!(statistics.light_vertices > 0, "{statistics:?}");
    assert!(statistics.radii[1] < statistics.radii[0], "{statistics:?}");
}
