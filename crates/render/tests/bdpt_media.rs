//! Volumetric bidirectional path tracing converges to the volumetric path
//! tracer's image (`path_comparison::assert_matches_path` compares scenes
//! with media with `volpath`): media behind rough glass under a sky, media
//! seen through index-matched boundaries, a camera and a light in fog; with
//! the independent sampler and with randomized QMC (padded replications
//! and Owen-scrambled Sobol). The medium furnaces give one: a white
//! medium, and spheres of a strongly chromatic medium, where without the
//! spectral MIS of `bdpt::mis` the throughput's ratio of the wavelengths'
//! free-flight densities has infinite variance.

use render::image::Image;
use render::integrators::IntegratorKind;
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::description::SceneDescription;
use std::sync::atomic::AtomicBool;

mod media_scenes;
mod path_comparison;
use media_scenes::{add_chromatic_spheres, medium_furnace};
use path_comparison::{Tested, assert_matches_path, builtin, small};

const BDPT: Tested = Tested {
    integrator: IntegratorKind::Bdpt,
    sampler: SamplerKind::Independent,
};

/// `translucent-spheres`: rough glass spheres filled with scattering media
/// on a plane under a sky, with depth of field.
#[test]
fn bdpt_matches_volpath_in_translucent_spheres() {
    let scene = builtin("translucent-spheres");
    assert_matches_path("translucent-spheres", &scene, BDPT, 2048, 64, None, true);
}

/// The same with randomized QMC: padded replications (Kollig & Keller) and
/// Owen-scrambled Sobol.
#[test]
fn bdpt_with_randomized_qmc_matches_volpath_in_translucent_spheres() {
    let scene = builtin("translucent-spheres");
    for sampler in [SamplerKind::Padded, SamplerKind::Sobol] {
        assert_matches_path(
            &format!("translucent-spheres ({sampler:?})"),
            &scene,
            Tested {
                integrator: IntegratorKind::Bdpt,
                sampler,
            },
            2048,
            64,
            None,
            true,
        );
    }
}

/// `translucent-spheres` with its glass replaced by index-matched
/// boundaries and without its sky: every connection passes media and
/// boundaries, medium vertices connect with their phase functions. The
/// reference takes 16384 samples per pixel: the dark pixels above the
/// spheres get their light from rare lens samples (the Gaussian filter's
/// reach and the depth of field), and at 4096 `volpath`'s film variance
/// misses those tails (three pixels there were 5–10× below the value that
/// `volpath`, BDPT and light tracing all give at 65536 samples).
#[test]
fn bdpt_matches_volpath_in_media_behind_interfaces() {
    let scene = Scene::build(&media_scenes::media_behind_interfaces(small)).unwrap();
    assert_matches_path(
        "translucent-spheres with interfaces",
        &scene,
        BDPT,
        16384,
        64,
        None,
        true,
    );
}

/// The camera and the light in fog that fills a room:
/// `volumetric-caustic`'s room and ceiling light. The image means of 8
/// renders of 256 samples (16 × 12, depth 2, 3 and 8) agree with
/// `volpath`'s, light tracing's and those without light tracing's
/// strategies or with the power heuristic within one standard error; at 64
/// samples per render the per-pixel test sees the tails of connections
/// from fog next to the light and the lens (4.3 % of channels above 3).
#[test]
fn bdpt_matches_volpath_in_a_foggy_room() {
    let scene = Scene::build(&media_scenes::foggy_room(small)).unwrap();
    assert_matches_path("foggy room", &scene, BDPT, 4096, 256, None, true);
}

/// Renders `description` with BDPT and returns the image mean over pixels
/// and channels, per seed.
fn image_means(description: &SceneDescription, sampler: SamplerKind, spp: u64) -> Vec<f64> {
    let scene = Scene::build(description).unwrap();
    (0..8)
        .map(|seed| {
            let settings = RenderSettings {
                integrator: IntegratorKind::Bdpt.into(),
                sampler,
                samples_per_pixel: spp,
                max_depth: 1000,
                seed,
                ..RenderSettings::default()
            };
            let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
            assert_eq!(output.statistics.nonfinite_samples, 0);
            mean(&output.image())
        })
        .collect()
}

fn mean(image: &Image) -> f64 {
    let values: Vec<f64> = image
        .pixels()
        .iter()
        .flatten()
        .map(|&value| value as f64)
        .collect();
    values.iter().sum::<f64>() / values.len() as f64
}

/// The image means' mean and its standard error, and the t statistic
/// against one (the white illuminant's sRGB is 1 within 2e-4).
fn assert_one(means: &[f64], context: &str) {
    let r = means.len() as f64;
    let mean = means.iter().sum::<f64>() / r;
    let variance = means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (r - 1.0);
    let error = (variance / r).sqrt();
    let t = (mean - 1.0) / error.max(1e-6);
    eprintln!("{context}: mean {mean:.5} ± {error:.5} (t = {t:.2})");
    assert!(
        (mean - 1.0).abs() < 4.5 * error + 5e-4,
        "{context}: mean {mean} ± {error}"
    );
}

#[test]
fn bdpt_in_a_medium_furnace_gives_one() {
    let description = medium_furnace(8);
    for sampler in [SamplerKind::Independent, SamplerKind::Padded] {
        assert_one(
            &image_means(&description, sampler, 8),
            &format!("medium furnace ({sampler:?})"),
        );
    }
}

/// Inside the medium furnace, an index-matched sphere and a glass sphere
/// filled with a white medium whose extinction varies 60-fold over the
/// spectrum: in a uniform radiance field both are invisible.
#[test]
fn chromatic_media_in_the_furnace_are_invisible_to_bdpt() {
    let mut description = medium_furnace(8);
    add_chromatic_spheres(&mut description);
    assert_one(
        &image_means(&description, SamplerKind::Independent, 16),
        "chromatic spheres in the medium furnace",
    );
}
