//! The environment-map light against Mitsuba 3: a diffuse sphere
//! (reflectance 0.2, 0.5, 0.3) under `museum.exr` (rotated 60° about +y,
//! scale 1.5), 32 × 32, max depth 3. Half the pixels see the map directly
//! (the lookup: orientation, bilinear interpolation, spectral upsampling),
//! the others the sphere lit by it (importance sampling with MIS).
//!
//! The reference in `tests/data/envmap_mitsuba_*` was rendered by
//! `scripts/envmap_reference.py` with Mitsuba 3.9.1 `scalar_spectral`: 32
//! independent images of 64 samples per pixel; the mean and the variance of
//! that mean per pixel (see `envmap_mitsuba_reference.txt`). Checks, as
//! `cornell_reference.rs`: (a) image means agree within 4 standard
//! deviations of the difference plus 1 % (the known difference of our RGB
//! illuminant spectra from Mitsuba's, measured on the Cornell box); (b) at
//! least 99 % of pixels have |z| < 4 in every channel.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use glam::{Affine3A, Vec3};
use render::camera::{FovAxis, PerspectiveSettings, look_at};
use render::image::{Image, read_pfm};
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::description::{
    EnvironmentProjection, FilterDescription, LightDescription, MaterialDescription,
    SceneDescription, ShapeDescription, ShapeGeometry,
};

const RESOLUTION: usize = 32;
const SAMPLES_PER_PIXEL: u64 = 1024;

fn data(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(name)
}

fn reference(name: &str) -> Image {
    let path = data(name);
    let image = read_pfm(&path).unwrap_or_else(|error| panic!("{}: {error}", path.display()));
    assert_eq!([image.width(), image.height()], [RESOLUTION, RESOLUTION]);
    image
}

fn description() -> SceneDescription {
    let world = look_at(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, Vec3::Y).unwrap();
    SceneDescription {
        name: "envmap-reference".into(),
        camera: PerspectiveSettings {
            world_from_camera: world,
            world_from_camera_end: world,
            resolution: [RESOLUTION as u32; 2],
            fov_degrees: 40.0,
            fov_axis: FovAxis::X,
            ..Default::default()
        },
        filter: FilterDescription::Box { radius: 0.5 },
        shapes: vec![ShapeDescription::new(
            ShapeGeometry::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
            MaterialDescription::diffuse_rgb([0.2, 0.5, 0.3]),
        )],
        lights: vec![LightDescription::EnvironmentMap {
            filename: PathBuf::from(env!("CARGO_MANIFEST_DIR"))
                .join("../../../shared/scenes/mitsuba-data/common/textures/museum.exr"),
            projection: EnvironmentProjection::MitsubaEquirectangular,
            to_world: Affine3A::from_rotation_y(60f32.to_radians()),
            scale: 1.5,
        }],
        max_depth: Some(3),
        samples_per_pixel: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

#[test]
fn environment_map_matches_mitsuba_scalar_spectral() {
    let scene = Scene::build(&description()).unwrap();
    let settings = RenderSettings {
        sampler: SamplerKind::Independent,
        samples_per_pixel: SAMPLES_PER_PIXEL,
        max_depth: 3,
        seed: 1,
        ..RenderSettings::default()
    };
    let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    assert_eq!(output.statistics.nonfinite_samples, 0);
    let reference_mean = reference("envmap_mitsuba_mean.pfm");
    let reference_variance = reference("envmap_mitsuba_variance.pfm");
    let pixel_count = (RESOLUTION * RESOLUTION) as f64;
    let mut ours = Vec::new();
    for y in 0..RESOLUTION {
        for x in 0..RESOLUTION {
            let pixel = output.film.pixel(x, y).unwrap();
            ours.push((pixel.weighted_mean(), pixel.variance_of_mean()));
        }
    }
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
            .zip(reference_variance.pixels())
            .map(|((_, v), r)| v[channel] + r[channel] as f64)
            .sum::<f64>()
            / (pixel_count * pixel_count))
            .sqrt();
        eprintln!(
            "channel {channel}: ours {our_mean:.6}, Mitsuba {their_mean:.6}, {:.2} sigma, ratio {:.5}",
            (our_mean - their_mean) / sigma,
            our_mean / their_mean
        );
        assert!(
            (our_mean - their_mean).abs() < 4.0 * sigma + 0.01 * their_mean,
            "channel {channel}: {our_mean} vs Mitsuba's {their_mean}"
        );
    }
    let mut within = 0usize;
    let mut worst = 0.0f64;
    for ((mean, variance), (theirs, their_variance)) in ours.iter().zip(
        reference_mean
            .pixels()
            .iter()
            .zip(reference_variance.pixels()),
    ) {
        let mut pass = true;
        for channel in 0..3 {
            let difference = mean[channel] - theirs[channel] as f64;
            let precision = 1e-6 * theirs[channel].abs() as f64;
            let variance =
                (variance[channel] + their_variance[channel] as f64).max(precision * precision);
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
    assert!(within as f64 >= 0.99 * pixel_count);
}
