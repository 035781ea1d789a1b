//! Bitterli's `veach-mis` and `veach-bidir` (`../shared/scenes/bitterli/`)
//! against the image means of Tungsten's references (`TungstenRender.exr`,
//! RGB renders at full resolution).
//!
//! The image mean is the mean radiance over the image plane, so it does not
//! depend on the resolution: we render small (a 1/8 of Tungsten's size in
//! each axis) with few samples and compare the mean with Tungsten's mean at
//! full resolution. The tolerance is the 2 % plus four standard
//! errors of our mean, estimated from the per-pixel variances of the pixel
//! means (pixels are independent with the independent sampler).
//!
//! Luminance (Rec. 709 weights) is compared: per channel, a spectral
//! renderer differs from an RGB one by a few per cent in saturated light
//! (see `pbrt_scenes.rs` for the Cornell box); these scenes are grey, so
//! the channels are printed as well.
//!
//! `veach-mis/scene-v4.pbrt` is a different scene from the XML and
//! Tungsten's (its plates have no `specular_reflectance` 0.3 factor, which
//! pbrt-v4's conductors do not have, and GGX instead of Beckmann
//! roughness); it is rendered and its mean printed, but not compared.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use render::image::read_image;
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::loader::{LoadOptions, load_scene_file};

fn bitterli(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../../shared/scenes/bitterli")
        .join(relative)
}

fn luminance(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// Our image mean and the variance of each channel's mean, rendering
/// `scene` at `width` × `height` with `samples` per pixel.
fn render_mean(scene: &str, width: u32, height: u32, samples: u64) -> ([f64; 3], [f64; 3]) {
    let path = bitterli(scene);
    let loaded = load_scene_file(&path, &LoadOptions::default())
        .unwrap_or_else(|error| panic!("{}: {error}", path.display()));
    let mut description = loaded.description;
    description.camera.resolution = [width, height];
    let scene = Scene::build(&description).expect("the scene builds");
    let settings = RenderSettings {
        sampler: SamplerKind::Independent,
        samples_per_pixel: samples,
        max_depth: description.max_depth.unwrap_or(u32::MAX),
        threads: 2,
        seed: 7,
        ..RenderSettings::default()
    };
    let output =
        render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).expect("the scene renders");
    let (mut sum, mut variance) = ([0.0; 3], [0.0; 3]);
    for y in 0..height as usize {
        for x in 0..width as usize {
            let pixel = output.film.pixel(x, y).unwrap();
            for channel in 0..3 {
                sum[channel] += pixel.weighted_mean()[channel];
                variance[channel] += pixel.variance_of_mean()[channel];
            }
        }
    }
    let count = f64::from(width * height);
    (
        sum.map(|s| s / count),
        variance.map(|v| v / (count * count)),
    )
}

fn tungsten_mean(scene: &str) -> [f64; 3] {
    let path = bitterli(scene).join("TungstenRender.exr");
    read_image(&path)
        .unwrap_or_else(|error| panic!("{}: {error}", path.display()))
        .mean()
}

/// Checks our luminance mean against Tungsten's: within 2 % plus four
/// standard errors.
fn compare(name: &str, ours: [f64; 3], variance: [f64; 3], tungsten: [f64; 3]) {
    for channel in 0..3 {
        eprintln!(
            "{name} channel {channel}: ours {:.4} ± {:.4}, Tungsten {:.4}, ratio {:.4}",
            ours[channel],
            variance[channel].sqrt(),
            tungsten[channel],
            ours[channel] / tungsten[channel]
        );
    }
    // Luminance is linear in the channels; its variance is bounded by
    // assuming fully correlated channels.
    let sigma = luminance(variance.map(f64::sqrt));
    let ratio = luminance(ours) / luminance(tungsten);
    let relative_sigma = sigma / luminance(tungsten);
    eprintln!("{name} luminance: ratio {ratio:.4} ± {relative_sigma:.4}");
    assert!(
        (ratio - 1.0).abs() < 0.02 + 4.0 * relative_sigma,
        "{name}: luminance ratio to Tungsten {ratio:.4} (σ {relative_sigma:.4})"
    );
}

#[test]
fn veach_mis_matches_tungsten_mean() {
    let (ours, variance) = render_mean("veach-mis/scene.xml", 160, 90, 16);
    compare("veach-mis", ours, variance, tungsten_mean("veach-mis"));
}

#[test]
fn veach_mis_pbrt_renders() {
    let (ours, variance) = render_mean("veach-mis/scene-v4.pbrt", 160, 90, 8);
    let tungsten = tungsten_mean("veach-mis");
    eprintln!(
        "veach-mis (pbrt-v4 file, brighter plates, not compared): {ours:.4?} ± {:.4?}; \
         luminance {:.3} × Tungsten's",
        variance.map(f64::sqrt),
        luminance(ours) / luminance(tungsten)
    );
    assert!(ours.iter().all(|&c| c.is_finite() && c > 0.0));
}

#[test]
fn veach_bidir_matches_tungsten_mean() {
    let (ours, variance) = render_mean("veach-bidir/scene.xml", 128, 128, 32);
    compare("veach-bidir", ours, variance, tungsten_mean("veach-bidir"));
}
