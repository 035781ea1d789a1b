//! The volumetric path tracer against analytic answers: furnaces filled
//! with non-absorbing media (every pixel 1, whatever the media, their phase
//! functions, chromatic extinction and boundaries), Beer–Lambert through an
//! absorbing slab behind index-matched boundaries, `volpath` against `path`
//! on scenes without media, and the dimension layout (crossing a `null`
//! boundary uses no dimension).
//!
//! Tolerances come from the film's per-pixel variance estimates, as in
//! `path_analytic.rs`: a pixel passes when |value − expected| < 6 pooled
//! standard errors (at most 1 % may fail: path contributions are skewed),
//! and the image mean must be within 5 standard errors.

use glam::Vec3;

mod media_scenes;
use media_scenes::{add_chromatic_spheres, medium, medium_furnace};
use render::camera::{FovAxis, PerspectiveSettings, look_at};
use render::geometry::Ray;
use render::image::Image;
use render::integrators::camera_path::radiance;
use render::integrators::path::PathSettings;
use render::integrators::volpath::VolumetricPathTracing;
use render::integrators::{IntegratorKind, TraceCounters};
use render::renderer::{RenderSettings, render};
use render::sampler::{SampleSource, SamplerKind, layout};
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use render::scene::description::{
    FilterDescription, LightDescription, MaterialDescription, MediumCoefficients,
    MediumDescription, PhaseDescription, SceneDescription, ShapeDescription, ShapeGeometry,
    SpectrumDescription,
};
use render::spectrum::SampledWavelengths;
use std::sync::atomic::AtomicBool;

fn render_images(description: &SceneDescription, settings: &RenderSettings) -> (Image, Image) {
    let scene = Scene::build(description).unwrap();
    let output = render(&scene, settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    assert_eq!(output.statistics.nonfinite_samples, 0);
    (output.film.image(1.0), output.film.variance_image())
}

/// Every pixel and the image mean against `expected(x, y)` per channel.
fn assert_matches(
    image: &Image,
    variance: &Image,
    expected: &dyn Fn(usize, usize) -> f64,
    context: &str,
) {
    let width = image.width();
    let count = image.pixels().len() as f64;
    for channel in 0..3 {
        let pooled_variance = variance
            .pixels()
            .iter()
            .map(|v| v[channel] as f64)
            .sum::<f64>()
            / count;
        let mut failures = 0;
        let (mut mean, mut expected_mean) = (0.0, 0.0);
        for (index, pixel) in image.pixels().iter().enumerate() {
            let target = expected(index % width, index / width);
            mean += pixel[channel] as f64 / count;
            expected_mean += target / count;
            // A small floor for the 2e-4 of the white illuminant's sRGB.
            if (pixel[channel] as f64 - target).abs() > 6.0 * pooled_variance.sqrt() + 5e-4 {
                failures += 1;
            }
        }
        assert!(
            failures as f64 <= 0.01 * count,
            "{context}: {failures} of {count} pixels fail in channel {channel}"
        );
        let bound = 5.0 * (pooled_variance / count).sqrt() + 5e-4;
        assert!(
            (mean - expected_mean).abs() < bound,
            "{context}: channel {channel} mean {mean} vs {expected_mean} (bound {bound})"
        );
    }
}

fn volpath_settings(sampler: SamplerKind, samples_per_pixel: u64) -> RenderSettings {
    RenderSettings {
        integrator: IntegratorKind::VolPath.into(),
        sampler,
        samples_per_pixel,
        max_depth: 1000,
        seed: 5,
        ..RenderSettings::default()
    }
}

#[test]
fn camera_inside_an_infinite_albedo_one_medium_sees_the_furnace_value() {
    let description = medium_furnace(16);
    for sampler in [
        SamplerKind::Independent,
        SamplerKind::Halton,
        SamplerKind::Sobol,
    ] {
        let (image, variance) = render_images(&description, &volpath_settings(sampler, 16));
        assert_matches(
            &image,
            &variance,
            &|_, _| 1.0,
            &format!("medium furnace {sampler:?}"),
        );
    }
}

/// Inside the medium furnace: an index-matched sphere and a glass sphere
/// (index 1.5), both filled with a white medium whose extinction differs
/// strongly between wavelengths. In a uniform radiance field a lossless
/// dielectric boundary and a non-absorbing medium are invisible, so every
/// pixel is still 1: this checks medium tracking through both kinds of
/// boundary and the spectral MIS over the hero wavelengths.
#[test]
fn spheres_of_chromatic_media_inside_the_furnace_are_invisible() {
    let mut description = medium_furnace(16);
    add_chromatic_spheres(&mut description);
    let (image, variance) = render_images(
        &description,
        &volpath_settings(SamplerKind::Independent, 32),
    );
    assert_matches(
        &image,
        &variance,
        &|_, _| 1.0,
        "chromatic spheres in the furnace",
    );
}

/// A camera looking through a purely absorbing slab (σt = 0.7, thickness 1,
/// bounded by an index-matched cube) at a white emitter of radiance 1: the
/// pixels are exp(−σt d / cos θ) with θ the angle of the pixel's ray to the
/// slab normal (a 4° field of view keeps cos θ near 1; the exact value is
/// used).
#[test]
fn absorbing_slab_follows_beer_lambert() {
    let sigma_t = 0.7f32;
    let resolution = 8u32;
    let fov_degrees = 4.0f32;
    let world = look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y).unwrap();
    let mut slab = ShapeDescription::new(
        ShapeGeometry::Cube {
            to_world: glam::Affine3A::from_scale(Vec3::new(5.0, 5.0, 0.5)),
        },
        MaterialDescription::Interface,
    );
    slab.interior_medium = Some(0);
    let emitter = ShapeDescription::new(
        ShapeGeometry::Rectangle {
            to_world: glam::Affine3A::from_translation(Vec3::new(0.0, 0.0, 2.0))
                * glam::Affine3A::from_rotation_y(std::f32::consts::PI)
                * glam::Affine3A::from_scale(Vec3::splat(10.0)),
        },
        MaterialDescription::Black,
    )
    .emitting([1.0, 1.0, 1.0]);
    let description = SceneDescription {
        name: "absorbing-slab".into(),
        camera: PerspectiveSettings {
            world_from_camera: world,
            world_from_camera_end: world,
            resolution: [resolution, resolution],
            fov_degrees,
            fov_axis: FovAxis::X,
            ..Default::default()
        },
        filter: FilterDescription::Box { radius: 0.5 },
        shapes: vec![slab, emitter],
        lights: Vec::new(),
        media: vec![medium(
            SpectrumDescription::Constant(0.0),
            SpectrumDescription::Constant(sigma_t),
            PhaseDescription::Isotropic,
        )],
        camera_medium: None,
        max_depth: Some(8),
        samples_per_pixel: Some(64),
        russian_roulette_depth: None,
        integrator: None,
    };
    let (image, variance) = render_images(
        &description,
        &volpath_settings(SamplerKind::Independent, 256),
    );
    let tan_half = (fov_degrees.to_radians() / 2.0).tan() as f64;
    let expected = |x: usize, y: usize| {
        let px = ((x as f64 + 0.5) / resolution as f64 * 2.0 - 1.0) * tan_half;
        let py = ((y as f64 + 0.5) / resolution as f64 * 2.0 - 1.0) * tan_half;
        let cos = 1.0 / (1.0 + px * px + py * py).sqrt();
        (-(sigma_t as f64) / cos).exp()
    };
    assert_matches(&image, &variance, &expected, "absorbing slab");
}

/// Per-pixel z-test of two independent renders of the same scene.
fn assert_same_estimate(description: &SceneDescription, samples_per_pixel: u64, context: &str) {
    let settings = |integrator: IntegratorKind, seed| RenderSettings {
        integrator: integrator.into(),
        sampler: SamplerKind::Independent,
        samples_per_pixel,
        max_depth: description.max_depth.unwrap_or(6),
        seed,
        ..RenderSettings::default()
    };
    let (path, path_variance) = render_images(description, &settings(IntegratorKind::Path, 1));
    let (volume, volume_variance) =
        render_images(description, &settings(IntegratorKind::VolPath, 2));
    let count = path.pixels().len();
    let mut within = 0;
    let mut mean_difference = [0.0f64; 3];
    let mut mean_variance = [0.0f64; 3];
    for index in 0..count {
        let mut pixel_within = true;
        for c in 0..3 {
            let difference = volume.pixels()[index][c] as f64 - path.pixels()[index][c] as f64;
            let variance =
                volume_variance.pixels()[index][c] as f64 + path_variance.pixels()[index][c] as f64;
            mean_difference[c] += difference / count as f64;
            mean_variance[c] += variance / (count * count) as f64;
            if difference != 0.0 && difference.abs() >= 4.0 * variance.sqrt() {
                pixel_within = false;
            }
        }
        within += usize::from(pixel_within);
    }
    for c in 0..3 {
        let sigma = mean_variance[c].sqrt();
        assert!(
            mean_difference[c].abs() < 4.0 * sigma,
            "{context}: channel {c} image means differ by {} ({} sigma)",
            mean_difference[c],
            mean_difference[c] / sigma
        );
    }
    assert!(
        within as f64 >= 0.98 * count as f64,
        "{context}: only {within} of {count} pixels agree within |z| < 4"
    );
}

#[test]
fn volpath_equals_path_on_scenes_without_media() {
    for (name, resolution, samples_per_pixel) in
        [("cornell-box", 24, 64), ("glass-sphere-box", 24, 64)]
    {
        let mut description = builtin_scene(name).unwrap();
        description.camera.resolution = [resolution, resolution];
        assert_same_estimate(&description, samples_per_pixel, name);
    }
}

/// Records the dimensions a path asks for; every number is 0.5.
struct RecordingSource(Vec<usize>);

impl SampleSource for RecordingSource {
    fn get(&mut self, dimension: usize) -> f32 {
        self.0.push(dimension);
        0.5
    }
}

/// A camera ray crossing two nested index-matched spheres (three media
/// pieces with a thin medium, then vacuum) to a black wall uses one
/// free-flight dimension, that of vertex 0's block, and nothing else.
#[test]
fn crossing_null_boundaries_uses_one_free_flight_dimension() {
    let thin = medium(
        SpectrumDescription::Constant(0.5),
        SpectrumDescription::Constant(1e-3),
        PhaseDescription::Isotropic,
    );
    let mut shapes = Vec::new();
    for (radius, interior) in [(1.0, 0), (0.5, 1)] {
        let mut sphere = ShapeDescription::new(
            ShapeGeometry::Sphere {
                center: Vec3::ZERO,
                radius,
            },
            MaterialDescription::Interface,
        );
        sphere.interior_medium = Some(interior);
        sphere.exterior_medium = if interior == 0 { None } else { Some(0) };
        shapes.push(sphere);
    }
    shapes.push(ShapeDescription::new(
        ShapeGeometry::Rectangle {
            to_world: glam::Affine3A::from_translation(Vec3::new(0.0, 0.0, 3.0))
                * glam::Affine3A::from_scale(Vec3::splat(10.0)),
        },
        MaterialDescription::Black,
    ));
    let world = look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y).unwrap();
    let description = SceneDescription {
        name: "nested-null-spheres".into(),
        camera: PerspectiveSettings {
            world_from_camera: world,
            world_from_camera_end: world,
            resolution: [4, 4],
            ..Default::default()
        },
        filter: FilterDescription::Box { radius: 0.5 },
        shapes,
        lights: vec![LightDescription::ConstantEnvironment {
            radiance: SpectrumDescription::Rgb([1.0, 1.0, 1.0]),
        }],
        media: vec![thin.clone(), thin],
        camera_medium: None,
        max_depth: Some(8),
        samples_per_pixel: None,
        russian_roulette_depth: None,
        integrator: None,
    };
    let scene = Scene::build(&description).unwrap();
    let mut source = RecordingSource(Vec::new());
    let mut wavelengths = SampledWavelengths::sample_visible(0.5);
    let mut counters = TraceCounters::default();
    let radiance = radiance::<VolumetricPathTracing, _>(
        &scene,
        &PathSettings::default(),
        Ray::new(Vec3::new(0.0, 0.0, -3.0), Vec3::Z),
        &mut wavelengths,
        &mut source,
        &mut counters,
    );
    assert!(radiance.is_black());
    assert_eq!(source.0, vec![layout::vertex(0, layout::FREE_FLIGHT)]);
    // Five pieces: camera to the outer sphere, outer shell, inner sphere,
    // outer shell, then to the wall.
    assert_eq!(counters.closest_hit_rays, 5);
}

/// Single scattering in a slab: a camera looking along the normal through
/// an isotropic slab (σs = 0.6, σa = 0.2, thickness 1, bounded by an
/// index-matched box much wider than thick) under a constant environment of
/// radiance L = 1, with `max_depth` 2 (emission plus one scattering). The
/// answer, for the infinite slab, is L e^(−σt d) plus
/// L σs/(4π) · 2π ∫₀^d e^(−σt s) ∫₀¹ (e^(−σt (d − s)/μ) + e^(−σt s/μ)) dμ ds
/// (the scattered light arrives through the slab's far and near faces),
/// integrated numerically here. This checks next-event estimation through a
/// medium and across a `null` boundary with its transmittance.
#[test]
fn slab_single_scattering_matches_the_closed_form_integral() {
    let (sigma_s, sigma_a, thickness) = (0.6f64, 0.2f64, 1.0f64);
    let sigma_t = sigma_s + sigma_a;
    let steps = 2000;
    let mut single = 0.0;
    for i in 0..steps {
        let s = (i as f64 + 0.5) / steps as f64 * thickness;
        let mut angular = 0.0;
        for j in 0..steps {
            let mu = (j as f64 + 0.5) / steps as f64;
            angular += ((-sigma_t * (thickness - s) / mu).exp() + (-sigma_t * s / mu).exp())
                / steps as f64;
        }
        single += (-sigma_t * s).exp() * angular * thickness / steps as f64;
    }
    let expected = (-sigma_t * thickness).exp() + sigma_s / 2.0 * single;

    let world = look_at(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y).unwrap();
    let mut slab = ShapeDescription::new(
        ShapeGeometry::Cube {
            to_world: glam::Affine3A::from_scale(Vec3::new(60.0, 60.0, 0.5)),
        },
        MaterialDescription::Interface,
    );
    slab.interior_medium = Some(0);
    let description = SceneDescription {
        name: "single-scattering-slab".into(),
        camera: PerspectiveSettings {
            world_from_camera: world,
            world_from_camera_end: world,
            resolution: [8, 8],
            fov_degrees: 1.0,
            fov_axis: FovAxis::X,
            ..Default::default()
        },
        filter: FilterDescription::Box { radius: 0.5 },
        shapes: vec![slab],
        lights: vec![LightDescription::ConstantEnvironment {
            radiance: SpectrumDescription::Rgb([1.0, 1.0, 1.0]),
        }],
        media: vec![MediumDescription {
            coefficients: MediumCoefficients::AbsorptionScattering {
                sigma_a: SpectrumDescription::Constant(sigma_a as f32),
                sigma_s: SpectrumDescription::Constant(sigma_s as f32),
            },
            scale: 1.0,
            phase: PhaseDescription::Isotropic,
        }],
        camera_medium: None,
        max_depth: Some(2),
        samples_per_pixel: None,
        russian_roulette_depth: None,
        integrator: None,
    };
    let settings = RenderSettings {
        max_depth: 2,
        ..volpath_settings(SamplerKind::Independent, 1024)
    };
    let (image, variance) = render_images(&description, &settings);
    eprintln!("expected {expected}, image mean {:?}", image.mean());
    assert_matches(
        &image,
        &variance,
        &|_, _| expected,
        "single-scattering slab",
    );
}
