//! Our volumetric path tracer against Mitsuba 3's `volpath` on the same
//! scene: a smooth glass sphere filled with a coloured forward-scattering
//! medium and an index-matched (`null`) sphere filled with a medium of
//! chromatic extinction, on a diffuse ground under an area light and a
//! constant environment.
//!
//! The reference `tests/data/volume_spheres_mitsuba.exr` was rendered by
//! `scripts/reference/mitsuba_volume_spheres.py` (Mitsuba 3.9.1,
//! `scalar_spectral`, `volpath`, max_depth 16; see
//! `volume_spheres_mitsuba.txt`): RGB is the mean of K independent images,
//! `variance.R/G/B` the variance of that mean from their spread. The script
//! builds the scene as a Python dict; [`scene`] below is the same scene as a
//! [`SceneDescription`].
//!
//! Checks, with the difference of two independent estimates having the sum
//! of their variances (as `cornell_reference.rs`): (a) the image mean per
//! channel within 4 standard deviations of the difference; (b) per pixel
//! and channel z = (ours − ref) / √(σ²_ours + σ²_ref), at least 98 % of the
//! pixels with |z| < 4 in every channel.

use glam::{Affine3A, Vec3};
use render::camera::{FovAxis, PerspectiveSettings, look_at};
use render::image::read_exr;
use render::integrators::IntegratorKind;
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::description::{
    FilterDescription, LightDescription, MaterialDescription, MediumCoefficients,
    MediumDescription, PhaseDescription, SceneDescription, ShapeDescription, ShapeGeometry,
    SpectrumDescription, TextureDescription,
};
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

const RESOLUTION: usize = 32;
const SAMPLES_PER_PIXEL: u64 = 512;
const MAX_DEPTH: u32 = 16;
const MEAN_TOLERANCE_SIGMAS: f64 = 4.0;
const PIXEL_Z_BOUND: f64 = 4.0;
const PIXEL_FRACTION_REQUIRED: f64 = 0.98;

/// The scene of `scripts/reference/mitsuba_volume_spheres.py`.
fn scene() -> SceneDescription {
    let world = look_at(Vec3::new(0.0, 1.0, -4.0), Vec3::new(0.0, 0.6, 0.0), Vec3::Y).unwrap();
    let medium_a = MediumDescription {
        coefficients: MediumCoefficients::AlbedoExtinction {
            albedo: SpectrumDescription::Rgb([0.9, 0.55, 0.25]),
            sigma_t: SpectrumDescription::Constant(4.0),
        },
        scale: 1.0,
        phase: PhaseDescription::HenyeyGreenstein { g: 0.5 },
    };
    let medium_b = MediumDescription {
        coefficients: MediumCoefficients::AlbedoExtinction {
            albedo: SpectrumDescription::Constant(0.85),
            sigma_t: SpectrumDescription::Sampled {
                wavelengths: vec![360.0, 500.0, 600.0, 830.0],
                values: vec![0.5, 1.5, 3.0, 5.0],
            },
        },
        scale: 1.0,
        phase: PhaseDescription::Isotropic,
    };
    let ground = ShapeDescription::new(
        ShapeGeometry::Rectangle {
            to_world: Affine3A::from_rotation_x(-std::f32::consts::FRAC_PI_2)
                * Affine3A::from_scale(Vec3::splat(4.0)),
        },
        // Mitsuba's plain diffuse is one-sided.
        MaterialDescription::Diffuse {
            reflectance: TextureDescription::Constant(SpectrumDescription::Rgb([0.5; 3])),
            two_sided: false,
        },
    );
    let light = ShapeDescription::new(
        ShapeGeometry::Rectangle {
            to_world: Affine3A::from_translation(Vec3::new(0.0, 3.0, 0.0))
                * Affine3A::from_rotation_x(std::f32::consts::FRAC_PI_2),
        },
        MaterialDescription::Black,
    )
    .emitting([4.0, 4.0, 4.0]);
    let mut glass = ShapeDescription::new(
        ShapeGeometry::Sphere {
            center: Vec3::new(-0.75, 0.6, 0.0),
            radius: 0.55,
        },
        MaterialDescription::smooth_dielectric(1.5),
    );
    glass.interior_medium = Some(0);
    let mut null = ShapeDescription::new(
        ShapeGeometry::Sphere {
            center: Vec3::new(0.75, 0.6, 0.0),
            radius: 0.55,
        },
        MaterialDescription::Interface,
    );
    null.interior_medium = Some(1);
    SceneDescription {
        name: "volume-spheres".into(),
        camera: PerspectiveSettings {
            world_from_camera: world,
            world_from_camera_end: world,
            resolution: [RESOLUTION as u32; 2],
            fov_degrees: 40.0,
            fov_axis: FovAxis::X,
            ..Default::default()
        },
        filter: FilterDescription::Box { radius: 0.5 },
        shapes: vec![ground, light, glass, null],
        lights: vec![LightDescription::ConstantEnvironment {
            radiance: SpectrumDescription::Rgb([0.3, 0.3, 0.3]),
        }],
        media: vec![medium_a, medium_b],
        camera_medium: None,
        max_depth: Some(MAX_DEPTH),
        samples_per_pixel: None,
        russian_roulette_depth: None,
        integrator: Some("volpath".into()),
    }
}

#[test]
fn media_spheres_match_mitsuba_volpath_scalar_spectral() {
    let path =
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/volume_spheres_mitsuba.exr");
    let reference = read_exr(&path).unwrap_or_else(|error| panic!("{}: {error}", path.display()));
    let reference_variance = reference
        .layers
        .get("variance")
        .expect("the reference has a variance layer");
    assert_eq!(
        [reference.image.width(), reference.image.height()],
        [RESOLUTION, RESOLUTION]
    );

    let scene = Scene::build(&scene()).unwrap();
    let settings = RenderSettings {
        integrator: IntegratorKind::VolPath.into(),
        sampler: SamplerKind::Independent,
        samples_per_pixel: SAMPLES_PER_PIXEL,
        max_depth: MAX_DEPTH,
        threads: 2,
        seed: 1,
        ..RenderSettings::default()
    };
    let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    assert_eq!(output.statistics.nonfinite_samples, 0);

    let pixel_count = (RESOLUTION * RESOLUTION) as f64;
    let mut mean_difference = [0.0f64; 3];
    let mut mean_variance = [0.0f64; 3];
    let (mut ours_mean, mut theirs_mean) = ([0.0f64; 3], [0.0f64; 3]);
    let mut within = 0usize;
    let mut worst = (0.0f64, 0usize, 0usize);
    for y in 0..RESOLUTION {
        for x in 0..RESOLUTION {
            let pixel = output.film.pixel(x, y).unwrap();
            let ours = pixel.weighted_mean();
            let our_variance = pixel.variance_of_mean();
            let theirs = reference.image.pixel(x, y).unwrap();
            let their_variance = reference_variance.pixel(x, y).unwrap();
            let mut pixel_within = true;
            for c in 0..3 {
                let difference = ours[c] - theirs[c] as f64;
                let variance = our_variance[c] + their_variance[c] as f64;
                mean_difference[c] += difference / pixel_count;
                mean_variance[c] += variance / (pixel_count * pixel_count);
                ours_mean[c] += ours[c] / pixel_count;
                theirs_mean[c] += theirs[c] as f64 / pixel_count;
                let precision = 1e-6 * (theirs[c] as f64).abs();
                let z = if difference == 0.0 {
                    0.0
                } else {
                    difference / variance.max(precision * precision).sqrt()
                };
                if z.abs() >= PIXEL_Z_BOUND || !z.is_finite() {
                    pixel_within = false;
                }
                if z.abs() > worst.0.abs() {
                    worst = (z, y * RESOLUTION + x, c);
                }
            }
            within += usize::from(pixel_within);
        }
    }
    for c in 0..3 {
        let sigma = mean_variance[c].sqrt();
        eprintln!(
            "channel {c}: ours {:.5}, Mitsuba {:.5}, difference {:.2} sigma, ratio {:.4}",
            ours_mean[c],
            theirs_mean[c],
            mean_difference[c] / sigma,
            ours_mean[c] / theirs_mean[c]
        );
    }
    eprintln!(
        "pixels with |z| < {PIXEL_Z_BOUND}: {within} of {pixel_count}; worst z {:.2} at ({}, {}) channel {}",
        worst.0,
        worst.1 % RESOLUTION,
        worst.1 / RESOLUTION,
        worst.2
    );
    for c in 0..3 {
        let sigma = mean_variance[c].sqrt();
        assert!(
            mean_difference[c].abs() < MEAN_TOLERANCE_SIGMAS * sigma,
            "channel {c}: image means differ by {:.2} standard deviations",
            mean_difference[c] / sigma
        );
    }
    assert!(
        within as f64 >= PIXEL_FRACTION_REQUIRED * pixel_count,
        "only {within} of {pixel_count} pixels agree with Mitsuba within |z| < {PIXEL_Z_BOUND}"
    );
}
