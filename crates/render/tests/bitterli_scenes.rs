//! Bitterli's `veach-mis` and `veach-bidir` (`scenes/external/bitterli/`)
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
//! veach-mis's whole-image mean is dominated in variance by the sub-pixel
//! footprints of its directly seen lights (radiance 3039 and 30): ±4 % at
//! 16 spp. The "dim" pixels (all but the lights, their sharpest reflections
//! and their neighbours; see [`dim_pixels`]) carry half of the light and are
//! known to a few tenths of a per cent, so they are compared more tightly,
//! with Mitsuba, which agrees with us there and differs from Tungsten.
//!
//! `veach-mis/scene-v4.pbrt` is a different scene from the XML and
//! Tungsten's: its plates have no `specular_reflectance` 0.3 factor (pbrt-v4's
//! conductors have none), GGX instead of Beckmann roughness, and pbrt's
//! `maxdepth 3` is one segment more than the XML's `max_depth` 3. It is
//! compared with a Mitsuba 3 render of an XML equivalent of the file
//! (`scripts/reference/veach_mis_pbrt_mitsuba.py`, means in
//! `tests/data/veach_mis_pbrt_mitsuba.txt`), and, with the plates'
//! reflectance scaled by 0.3 after loading, with Tungsten's image.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use render::image::{Image, read_image};
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::description::{
    MaterialDescription, SceneDescription, SpectrumDescription, TextureDescription,
};
use render::scene::loader::{LoadOptions, load_scene_file};

fn bitterli(relative: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/external/bitterli")
        .join(relative)
}

fn luminance(rgb: [f64; 3]) -> f64 {
    0.2126 * rgb[0] + 0.7152 * rgb[1] + 0.0722 * rgb[2]
}

/// Our render: per pixel the mean and the variance of the mean (pixels are
/// independent with the independent sampler).
struct OurRender {
    means: Vec<[f64; 3]>,
    variances: Vec<[f64; 3]>,
}

impl OurRender {
    /// The mean over the pixels where `keep` holds and its variance.
    fn mean_where(&self, keep: &[bool]) -> ([f64; 3], [f64; 3]) {
        let (mut sum, mut variance, mut count) = ([0.0; 3], [0.0; 3], 0.0);
        for ((mean, pixel_variance), _) in self
            .means
            .iter()
            .zip(&self.variances)
            .zip(keep)
            .filter(|(_, keep)| **keep)
        {
            for channel in 0..3 {
                sum[channel] += mean[channel];
                variance[channel] += pixel_variance[channel];
            }
            count += 1.0;
        }
        (
            sum.map(|s| s / count),
            variance.map(|v| v / (count * count)),
        )
    }

    /// The image mean and its variance.
    fn mean(&self) -> ([f64; 3], [f64; 3]) {
        self.mean_where(&vec![true; self.means.len()])
    }
}

/// `samples` per pixel, or `LQMC_BITTERLI_SPP` if set (to measure the
/// figures more precisely than the tests need).
fn samples_or_override(samples: u64) -> u64 {
    std::env::var("LQMC_BITTERLI_SPP")
        .ok()
        .and_then(|value| value.parse().ok())
        .unwrap_or(samples)
}

/// Renders `scene` at `width` × `height` with `samples` per pixel.
fn render_scene(scene: &str, width: u32, height: u32, samples: u64) -> OurRender {
    render_patched(scene, width, height, samples, |_| {})
}

/// [`render_scene`] of the scene as loaded and then changed by `patch`.
fn render_patched(
    scene: &str,
    width: u32,
    height: u32,
    samples: u64,
    patch: impl Fn(&mut SceneDescription),
) -> OurRender {
    let path = bitterli(scene);
    let loaded = load_scene_file(&path, &LoadOptions::default())
        .unwrap_or_else(|error| panic!("{}: {error}", path.display()));
    let mut description = loaded.description;
    patch(&mut description);
    description.camera.resolution = [width, height];
    let scene = Scene::build(&description).expect("the scene builds");
    let settings = RenderSettings {
        sampler: SamplerKind::Independent,
        samples_per_pixel: samples_or_override(samples),
        max_depth: description.max_depth.unwrap_or(u32::MAX),
        threads: 2,
        seed: 7,
        ..RenderSettings::default()
    };
    let output =
        render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).expect("the scene renders");
    let (mut means, mut variances) = (Vec::new(), Vec::new());
    for y in 0..height as usize {
        for x in 0..width as usize {
            let pixel = output.film.pixel(x, y).unwrap();
            means.push(pixel.weighted_mean());
            variances.push(pixel.variance_of_mean());
        }
    }
    OurRender { means, variances }
}

/// `image` box-filtered down to `width` × `height` (whole factors).
fn downsampled(image: &Image, width: usize, height: usize) -> Vec<[f64; 3]> {
    let (fx, fy) = (image.width() / width, image.height() / height);
    assert_eq!((fx * width, fy * height), (image.width(), image.height()));
    let mut out = vec![[0.0; 3]; width * height];
    for y in 0..image.height() {
        for x in 0..image.width() {
            let pixel = image.pixel(x, y).unwrap();
            let target = &mut out[(y / fy) * width + x / fx];
            for channel in 0..3 {
                target[channel] += f64::from(pixel[channel]) / (fx * fy) as f64;
            }
        }
    }
    out
}

/// Pixels brighter than this (luminance of Tungsten's image at our size)…
const BRIGHT: f64 = 20.0;
/// …and those within this many pixels of them are left out of the "dim"
/// comparisons.
const DILATION: i64 = 2;

/// The "dim" pixels of veach-mis at `width` × `height`: all but the directly
/// seen lights, their sharpest reflections and their neighbours (the tent
/// filter spreads them), as `scripts/reference/veach_mis_pbrt_mitsuba.py`
/// chooses them. The lights' sub-pixel footprints (radiance 3039 and 30)
/// dominate the variance of the whole image's mean (±4 % at 16 spp,
/// 160 × 90); the rest, half of the image's light, is known to a few tenths
/// of a per cent.
fn dim_pixels(width: usize, height: usize) -> Vec<bool> {
    let tungsten = read_image(bitterli("veach-mis/TungstenRender.exr")).unwrap();
    let small = downsampled(&tungsten, width, height);
    let bright: Vec<bool> = small.iter().map(|p| luminance(*p) > BRIGHT).collect();
    (0..width * height)
        .map(|index| {
            let (x, y) = ((index % width) as i64, (index / width) as i64);
            !(-DILATION..=DILATION).any(|dy| {
                (-DILATION..=DILATION).any(|dx| {
                    let (nx, ny) = (x + dx, y + dy);
                    (0..width as i64).contains(&nx)
                        && (0..height as i64).contains(&ny)
                        && bright[(ny * width as i64 + nx) as usize]
                })
            })
        })
        .collect()
}

/// The mean of `pixels` where `keep` holds.
fn masked_mean(pixels: &[[f64; 3]], keep: &[bool]) -> [f64; 3] {
    let (mut sum, mut count) = ([0.0; 3], 0.0);
    for (pixel, _) in pixels.iter().zip(keep).filter(|(_, keep)| **keep) {
        for channel in 0..3 {
            sum[channel] += pixel[channel];
        }
        count += 1.0;
    }
    sum.map(|s| s / count)
}

fn tungsten_mean(scene: &str) -> [f64; 3] {
    image_mean(&bitterli(scene).join("TungstenRender.exr"))
}

/// Checks our luminance mean against Tungsten's: within 2 % plus four
/// standard errors.
fn compare(name: &str, ours: [f64; 3], variance: [f64; 3], tungsten: [f64; 3]) {
    compare_with(name, "Tungsten", ours, variance, tungsten, [0.0; 3], 0.02);
}

/// Checks our luminance mean against a reference's (with the variances of
/// both means): within `tolerance` plus four standard errors.
fn compare_with(
    name: &str,
    reference_name: &str,
    ours: [f64; 3],
    variance: [f64; 3],
    reference: [f64; 3],
    reference_variance: [f64; 3],
    tolerance: f64,
) {
    for channel in 0..3 {
        eprintln!(
            "{name} channel {channel}: ours {:.4} ± {:.4}, {reference_name} {:.4} ± {:.4}, ratio {:.4}",
            ours[channel],
            variance[channel].sqrt(),
            reference[channel],
            reference_variance[channel].sqrt(),
            ours[channel] / reference[channel]
        );
    }
    // Luminance is linear in the channels; its variance is bounded by
    // assuming fully correlated channels.
    let sigma =
        luminance(variance.map(f64::sqrt)).hypot(luminance(reference_variance.map(f64::sqrt)));
    let ratio = luminance(ours) / luminance(reference);
    let relative_sigma = sigma / luminance(reference);
    eprintln!("{name} luminance: ratio to {reference_name} {ratio:.4} ± {relative_sigma:.4}");
    assert!(
        (ratio - 1.0).abs() < tolerance + 4.0 * relative_sigma,
        "{name}: luminance ratio to {reference_name} {ratio:.4} (σ {relative_sigma:.4})"
    );
}

/// The image mean of an EXR per channel.
fn image_mean(path: &Path) -> [f64; 3] {
    read_image(path)
        .unwrap_or_else(|error| panic!("{}: {error}", path.display()))
        .mean()
}

/// The values of the row `KEY v0 v1 …` of the Mitsuba reference file of the
/// pbrt-v4 scene.
fn veach_mis_pbrt_row(key: &str) -> Vec<f64> {
    let text = include_str!("data/veach_mis_pbrt_mitsuba.txt");
    let line = text
        .lines()
        .find_map(|line| line.strip_prefix(key)?.strip_prefix(' '))
        .unwrap_or_else(|| panic!("no '{key}' line"));
    line.split_whitespace()
        .map(|v| v.parse().unwrap())
        .collect()
}

/// A row of three values (per channel) of the Mitsuba reference file.
fn veach_mis_pbrt_mitsuba(key: &str) -> [f64; 3] {
    veach_mis_pbrt_row(key)
        .try_into()
        .unwrap_or_else(|_| panic!("'{key}' has three values"))
}

/// Squares of standard errors.
fn squared(errors: [f64; 3]) -> [f64; 3] {
    errors.map(|e| e * e)
}

/// The XML veach-mis against Tungsten (whole image, 2 % plus four standard
/// errors) and against Mitsuba's own `veach-mis/scene.exr` on the dim pixels
/// (1 % plus four standard errors). `scene.exr` is an RGB render like
/// Tungsten's: Mitsuba 3.9.1's `scalar_rgb` gives its mean to 0.1 %, while
/// `scalar_spectral` lifts the plates' RGB η and κ with its bounded
/// reflectance fit and renders 7 % darker. Ours is spectral; its copper
/// plates differ from RGB ones by about 1 % in red.
#[test]
fn veach_mis_matches_tungsten_and_mitsuba() {
    let (width, height) = (160, 90);
    let ours = render_scene("veach-mis/scene.xml", width, height, 16);
    let (mean, variance) = ours.mean();
    compare("veach-mis", mean, variance, tungsten_mean("veach-mis"));
    let dim = dim_pixels(width as usize, height as usize);
    let (dim_mean, dim_variance) = ours.mean_where(&dim);
    let mitsuba = read_image(bitterli("veach-mis/scene.exr")).unwrap();
    let mitsuba_dim = masked_mean(
        &downsampled(&mitsuba, width as usize, height as usize),
        &dim,
    );
    let tungsten = read_image(bitterli("veach-mis/TungstenRender.exr")).unwrap();
    let tungsten_dim = masked_mean(
        &downsampled(&tungsten, width as usize, height as usize),
        &dim,
    );
    eprintln!(
        "veach-mis dim pixels: Mitsuba's luminance {:.4} × Tungsten's",
        luminance(mitsuba_dim) / luminance(tungsten_dim)
    );
    compare_with(
        "veach-mis dim pixels",
        "Mitsuba",
        dim_mean,
        dim_variance,
        mitsuba_dim,
        [0.0; 3],
        0.01,
    );
}

/// The scene the pbrt-v4 file describes, against Mitsuba 3 `scalar_spectral`
/// rendering its XML equivalent: the whole image within 2 % plus four
/// standard errors, the dim pixels within 1 % plus four.
#[test]
fn veach_mis_pbrt_matches_mitsuba_equivalent() {
    let size = veach_mis_pbrt_row("size");
    let (width, height) = (size[0] as u32, size[1] as u32);
    let ours = render_scene("veach-mis/scene-v4.pbrt", width, height, 16);
    let (mean, variance) = ours.mean();
    compare_with(
        "veach-mis pbrt-v4",
        "Mitsuba (XML equivalent)",
        mean,
        variance,
        veach_mis_pbrt_mitsuba("mean"),
        squared(veach_mis_pbrt_mitsuba("mean_standard_error")),
        0.02,
    );
    let bright = veach_mis_pbrt_row("bright");
    assert_eq!((bright[0], bright[1]), (BRIGHT, DILATION as f64));
    let (dim_mean, dim_variance) = ours.mean_where(&dim_pixels(width as usize, height as usize));
    compare_with(
        "veach-mis pbrt-v4 dim pixels",
        "Mitsuba (XML equivalent)",
        dim_mean,
        dim_variance,
        veach_mis_pbrt_mitsuba("dim_mean"),
        squared(veach_mis_pbrt_mitsuba("dim_mean_standard_error")),
        0.01,
    );
}

/// The pbrt-v4 file with the XML's `specular_reflectance` 0.3 on its plates
/// (set on the loaded description: pbrt-v4's conductor has no such
/// parameter) against Tungsten. It still has GGX plates and one segment
/// more than the XML.
#[test]
fn veach_mis_pbrt_with_xml_plates_matches_tungsten() {
    let scale_plates = |description: &mut SceneDescription| {
        let mut plates = 0;
        for shape in &mut description.shapes {
            if let MaterialDescription::Conductor {
                specular_reflectance,
                ..
            } = &mut shape.material
            {
                *specular_reflectance = Some(TextureDescription::Constant(
                    SpectrumDescription::Constant(0.3),
                ));
                plates += 1;
            }
        }
        assert_eq!(plates, 4, "the file has four conductor plates");
    };
    let ours = render_patched("veach-mis/scene-v4.pbrt", 160, 90, 16, scale_plates);
    let (mean, variance) = ours.mean();
    compare(
        "veach-mis pbrt-v4, plates × 0.3",
        mean,
        variance,
        tungsten_mean("veach-mis"),
    );
}

#[test]
fn veach_bidir_matches_tungsten_mean() {
    let (mean, variance) = render_scene("veach-bidir/scene.xml", 128, 128, 32).mean();
    compare("veach-bidir", mean, variance, tungsten_mean("veach-bidir"));
}
