//! Spot, directional and environment-map lights rendered by the path tracer
//! against closed forms and quadratures:
//!
//! - a diffuse plane under a directional light: `ρ/π · E cos θ`;
//! - a plane lit by a spot light at points inside the full beam, in the
//!   falloff and outside the cone, for Mitsuba's and pbrt's profiles:
//!   `ρ/π · I f(θ) cos³θ / h²`;
//! - a convex sphere inside a constant-white environment *map* (both
//!   projections) reflects its albedo, as under the constant environment;
//! - a tilted plane under a lat-long map that is bright above the horizon
//!   and ramps to black below it: `ρ/π ∫ L(ω) max(0, n·ω) dω` by quadrature,
//!   which exercises importance sampling, the densities used by MIS and the
//!   bilinear lookup;
//! - the density `pdf_incident` reports equals the one `sample_incident`
//!   drew with.
//!
//! Delta lights with grey albedos give noise-free images (only the
//! wavelengths are sampled, and a grey surface under white light has the
//! same value at every wavelength), so their tolerance is the white
//! illuminant's sRGB error (2e-4) plus the variation across a pixel. The
//! environment-map renders use the film's variance: the image mean must lie
//! within 5 standard errors.

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use glam::{Affine3A, Quat, Vec3};
use render::camera::{FovAxis, PerspectiveSettings, look_at};
use render::image::{Image, write_pfm};
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::description::{
    EnvironmentProjection, FilterDescription, LightDescription, MaterialDescription,
    SceneDescription, ShapeDescription, ShapeGeometry, SpectrumDescription, SpotFalloff,
};
use render::spectrum::SampledWavelengths;

const ALBEDO: f32 = 0.5;

fn camera(eye: Vec3, target: Vec3, up: Vec3, fov_degrees: f32, size: u32) -> PerspectiveSettings {
    let world = look_at(eye, target, up).unwrap();
    PerspectiveSettings {
        world_from_camera: world,
        world_from_camera_end: world,
        resolution: [size, size],
        fov_degrees,
        fov_axis: FovAxis::X,
        ..Default::default()
    }
}

fn scene(
    camera: PerspectiveSettings,
    shapes: Vec<ShapeDescription>,
    lights: Vec<LightDescription>,
) -> SceneDescription {
    SceneDescription {
        name: "light-test".into(),
        camera,
        filter: FilterDescription::Box { radius: 0.5 },
        shapes,
        lights,
        max_depth: Some(4),
        samples_per_pixel: Some(4),
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

/// A large grey diffuse square through the origin with normal `normal`.
fn plane(normal: Vec3, center: Vec3) -> ShapeDescription {
    let rotation = Quat::from_rotation_arc(Vec3::Z, normal.normalize());
    ShapeDescription::new(
        ShapeGeometry::Rectangle {
            to_world: Affine3A::from_scale_rotation_translation(
                Vec3::new(50.0, 50.0, 1.0),
                rotation,
                center,
            ),
        },
        MaterialDescription::diffuse_rgb([ALBEDO; 3]),
    )
}

/// Per channel: the image mean and the standard error of that mean.
fn render_mean(
    description: &SceneDescription,
    sampler: SamplerKind,
    spp: u64,
) -> ([f64; 3], [f64; 3]) {
    let scene = Scene::build(description).unwrap();
    let settings = RenderSettings {
        sampler,
        samples_per_pixel: spp,
        max_depth: 4,
        seed: 5,
        ..RenderSettings::default()
    };
    let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    assert_eq!(output.statistics.nonfinite_samples, 0);
    let image = output.film.image(1.0);
    let variance = output.film.variance_image();
    let count = image.pixels().len() as f64;
    let mut mean = [0.0; 3];
    let mut error = [0.0; 3];
    for channel in 0..3 {
        mean[channel] = image
            .pixels()
            .iter()
            .map(|p| p[channel] as f64)
            .sum::<f64>()
            / count;
        error[channel] = (variance
            .pixels()
            .iter()
            .map(|p| p[channel] as f64)
            .sum::<f64>()
            / (count * count))
            .sqrt();
    }
    (mean, error)
}

fn assert_close(mean: [f64; 3], error: [f64; 3], expected: f64, relative: f64, context: &str) {
    for channel in 0..3 {
        let bound = 5.0 * error[channel] + relative * expected + 1e-5;
        assert!(
            (mean[channel] - expected).abs() < bound,
            "{context}: channel {channel}: {} vs {expected} (bound {bound})",
            mean[channel]
        );
    }
}

#[test]
fn directional_light_on_a_diffuse_plane() {
    for degrees in [0.0f32, 30.0, 75.0] {
        let theta = degrees.to_radians();
        let description = scene(
            camera(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, Vec3::Y, 20.0, 8),
            vec![plane(Vec3::Z, Vec3::ZERO)],
            vec![LightDescription::Directional {
                // Travelling down towards the plane, tilted by θ.
                direction: -Vec3::new(theta.sin(), 0.0, theta.cos()),
                irradiance: SpectrumDescription::Rgb([2.0, 2.0, 2.0]),
            }],
        );
        let (mean, error) = render_mean(&description, SamplerKind::Sobol, 4);
        let expected = (ALBEDO / std::f32::consts::PI * 2.0 * theta.cos()) as f64;
        assert_close(
            mean,
            error,
            expected,
            5e-4,
            &format!("directional {degrees}°"),
        );
    }
    // Light arriving from behind a one-sided-lit point: nothing (the plane
    // is two-sided, so look at it from below while the light is above).
    let description = scene(
        camera(Vec3::new(0.0, 0.0, -5.0), Vec3::ZERO, Vec3::Y, 20.0, 4),
        vec![plane(Vec3::Z, Vec3::ZERO)],
        vec![LightDescription::Directional {
            direction: -Vec3::Z,
            irradiance: SpectrumDescription::Rgb([1.0, 1.0, 1.0]),
        }],
    );
    let (mean, _) = render_mean(&description, SamplerKind::Sobol, 2);
    assert_eq!(mean, [0.0; 3]);
}

/// Mitsuba's `spot_light` test scene's parameters: cutoff 20°, beam 15°,
/// intensity 5; the plane z = 1 is seen from the light's position along
/// directions at angle θ from the axis, through a 0.1° field of view.
fn spot_scene(theta_degrees: f32, falloff: SpotFalloff) -> SceneDescription {
    let theta = theta_degrees.to_radians();
    scene(
        camera(
            Vec3::ZERO,
            Vec3::new(theta.tan(), 0.0, 1.0),
            Vec3::Y,
            0.1,
            4,
        ),
        vec![plane(Vec3::Z, Vec3::Z)],
        vec![LightDescription::Spot {
            to_world: Affine3A::IDENTITY,
            intensity: SpectrumDescription::Rgb([5.0, 5.0, 5.0]),
            cutoff_degrees: 20.0,
            falloff_start_degrees: 15.0,
            falloff,
            texture: None,
        }],
    )
}

#[test]
fn spot_light_irradiance_inside_and_outside_the_cone() {
    let (cos_end, cos_start) = (20f64.to_radians().cos(), 15f64.to_radians().cos());
    let smoothstep = |cos: f64| {
        let t = ((cos - cos_end) / (cos_start - cos_end)).clamp(0.0, 1.0);
        t * t * (3.0 - 2.0 * t)
    };
    for (degrees, falloff, profile) in [
        (5.0f64, SpotFalloff::MitsubaLinearAngle, 1.0),
        (17.5, SpotFalloff::MitsubaLinearAngle, 0.5),
        (19.0, SpotFalloff::MitsubaLinearAngle, 0.2),
        (25.0, SpotFalloff::MitsubaLinearAngle, 0.0),
        (5.0, SpotFalloff::PbrtSmoothstep, 1.0),
        (
            17.5,
            SpotFalloff::PbrtSmoothstep,
            smoothstep(17.5f64.to_radians().cos()),
        ),
        (25.0, SpotFalloff::PbrtSmoothstep, 0.0),
    ] {
        let description = spot_scene(degrees as f32, falloff);
        let (mean, error) = render_mean(&description, SamplerKind::Sobol, 4);
        // The plane point at angle θ is 1/cos θ away and sees the light at
        // incidence θ: E = I f(θ) cos θ / d² = I f(θ) cos³θ.
        let cos = degrees.to_radians().cos();
        let expected = ALBEDO as f64 / std::f64::consts::PI * 5.0 * profile * cos.powi(3);
        // ±0.05° across the image changes f by up to 1 % linearly (which
        // averages out) and cos³θ by 3 tan θ · 0.05° ≈ 1e-3.
        assert_close(
            mean,
            error,
            expected,
            2e-3,
            &format!("spot {degrees}° {falloff:?}"),
        );
    }
}

/// A temporary PFM file holding `image`, removed when dropped.
struct TemporaryImage(PathBuf);

impl TemporaryImage {
    fn new(name: &str, image: &Image) -> Self {
        let path =
            std::env::temp_dir().join(format!("lqmc-light-test-{}-{name}.pfm", std::process::id()));
        write_pfm(&path, image).unwrap();
        Self(path)
    }
}

impl Drop for TemporaryImage {
    fn drop(&mut self) {
        let _ = std::fs::remove_file(&self.0);
    }
}

fn sphere_in(light: LightDescription) -> SceneDescription {
    let sphere = ShapeDescription::new(
        ShapeGeometry::Sphere {
            center: Vec3::ZERO,
            radius: 1.0,
        },
        MaterialDescription::diffuse_rgb([0.8; 3]),
    );
    scene(
        camera(Vec3::new(0.0, 0.0, -3.0), Vec3::ZERO, Vec3::Y, 10.0, 8),
        vec![sphere],
        vec![light],
    )
}

#[test]
fn constant_environment_map_equals_the_constant_environment() {
    let lat_long = TemporaryImage::new(
        "white-latlong",
        &Image::from_pixels(8, 5, vec![[1.0; 3]; 40]).unwrap(),
    );
    let equal_area = TemporaryImage::new(
        "white-equal-area",
        &Image::from_pixels(4, 4, vec![[0.5; 3]; 16]).unwrap(),
    );
    let rotation = Affine3A::from_rotation_x(0.7);
    let cases = [
        (
            "constant",
            LightDescription::ConstantEnvironment {
                radiance: SpectrumDescription::Rgb([1.0; 3]),
            },
        ),
        (
            "lat-long",
            LightDescription::EnvironmentMap {
                filename: lat_long.0.clone(),
                projection: EnvironmentProjection::MitsubaEquirectangular,
                to_world: rotation,
                scale: 1.0,
            },
        ),
        (
            "equal-area",
            LightDescription::EnvironmentMap {
                filename: equal_area.0.clone(),
                projection: EnvironmentProjection::PbrtEqualArea,
                to_world: rotation,
                scale: 2.0,
            },
        ),
    ];
    for (name, light) in cases {
        let (mean, error) = render_mean(&sphere_in(light), SamplerKind::Independent, 32);
        assert_close(mean, error, 0.8, 3e-4, name);
    }
}

/// The profile of [`half_sky_image`]: 1 down to the horizon, falling to 0
/// at one row below it (θ = 5π/8) as (1 − t)² with t linear in θ, 0 below.
/// The square is Mitsuba 3's spectral lookup: it interpolates the sigmoid
/// spectra and the scales 2 max(rgb) separately and multiplies them, and a
/// black texel has both zero (Mitsuba 3.9.1 `scalar_spectral` gives 0.25 of
/// white halfway between a white and a black row; `scalar_rgb` gives 0.5).
fn half_sky_profile(theta: f64) -> f64 {
    let horizon = std::f64::consts::FRAC_PI_2;
    let step = std::f64::consts::PI / 8.0;
    if theta <= horizon {
        1.0
    } else {
        (1.0 - (theta - horizon) / step).max(0.0).powi(2)
    }
}

/// 16 × 9 lat-long rows at θ = jπ/8: rows 0..=4 (down to the horizon) 1,
/// the rest 0, so the lookup gives [`half_sky_profile`].
fn half_sky_image() -> Image {
    let mut pixels = Vec::new();
    for row in 0..9 {
        for _ in 0..16 {
            pixels.push(if row <= 4 { [1.0; 3] } else { [0.0; 3] });
        }
    }
    Image::from_pixels(16, 9, pixels).unwrap()
}

#[test]
fn tilted_plane_under_a_half_sky_matches_quadrature() {
    let sky = TemporaryImage::new("half-sky", &half_sky_image());
    for degrees in [0.0f64, 60.0, 120.0] {
        let alpha = degrees.to_radians();
        let normal = Vec3::new(alpha.sin() as f32, alpha.cos() as f32, 0.0);
        // ρ/π ∫ L(θ) max(0, n·ω) dω with ω = (sin θ sin φ, cos θ, −sin θ cos φ).
        let steps = 800usize;
        let theta_max = 5.0 * std::f64::consts::PI / 8.0;
        let mut integral = 0.0f64;
        for i in 0..steps {
            let theta = (i as f64 + 0.5) / steps as f64 * theta_max;
            let radiance = half_sky_profile(theta);
            for j in 0..steps {
                let phi = (j as f64 + 0.5) / steps as f64 * std::f64::consts::TAU;
                let omega = [
                    theta.sin() * phi.sin(),
                    theta.cos(),
                    -theta.sin() * phi.cos(),
                ];
                let cosine = normal.x as f64 * omega[0]
                    + normal.y as f64 * omega[1]
                    + normal.z as f64 * omega[2];
                integral += radiance * cosine.max(0.0) * theta.sin();
            }
        }
        integral *= theta_max / steps as f64 * std::f64::consts::TAU / steps as f64;
        let expected = ALBEDO as f64 / std::f64::consts::PI * integral;
        let description = scene(
            camera(normal * 3.0, Vec3::ZERO, Vec3::Z, 20.0, 8),
            vec![plane(normal, Vec3::ZERO)],
            vec![LightDescription::EnvironmentMap {
                filename: sky.0.clone(),
                projection: EnvironmentProjection::MitsubaEquirectangular,
                to_world: Affine3A::IDENTITY,
                scale: 1.0,
            }],
        );
        for sampler in [SamplerKind::Independent, SamplerKind::Halton] {
            let (mean, error) = render_mean(&description, sampler, 64);
            assert_close(
                mean,
                error,
                expected,
                3e-4,
                &format!("half sky, normal at {degrees}°, {sampler:?}"),
            );
        }
    }
}

#[test]
fn sampled_density_equals_the_reported_density() {
    let sky = TemporaryImage::new("pdf-sky", &half_sky_image());
    let description = scene(
        camera(Vec3::new(0.0, 0.0, 3.0), Vec3::ZERO, Vec3::Y, 20.0, 4),
        vec![plane(Vec3::Z, Vec3::ZERO)],
        vec![LightDescription::EnvironmentMap {
            filename: sky.0.clone(),
            projection: EnvironmentProjection::MitsubaEquirectangular,
            to_world: Affine3A::from_rotation_z(0.3),
            scale: 1.0,
        }],
    );
    let scene = Scene::build(&description).unwrap();
    let light_index = scene.environment_lights[0] as usize;
    let light = &scene.lights[light_index];
    assert!(light.is_infinite() && !light.is_delta());
    let wavelengths = SampledWavelengths::sample_visible(0.4);
    let reference = Vec3::new(0.1, 0.2, 0.01);
    for i in 0..1000 {
        let u = [(i as f32 + 0.5) / 1000.0, ((i * 37) % 1000) as f32 / 1000.0];
        let Some(sample) = light.sample_incident(&scene.geometry, reference, 0.5, u, &wavelengths)
        else {
            continue;
        };
        let pdf = light.pdf_incident(&scene.geometry, reference, sample.point, Vec3::ZERO);
        assert!(
            (pdf - sample.pdf).abs() <= 2e-3 * sample.pdf,
            "{pdf} vs {}",
            sample.pdf
        );
        let radiance = light.environment_radiance(sample.wi, &wavelengths);
        assert_eq!(radiance, sample.radiance);
        // Directions below the ramp are never sampled.
        assert!(!radiance.is_black() || sample.pdf == 0.0);
    }
    // Lookups in a direction that cannot be sampled have density 0.
    let down = Affine3A::from_rotation_z(0.3).transform_vector3(-Vec3::Y);
    assert_eq!(
        light.pdf_incident(&scene.geometry, reference, reference + down, Vec3::ZERO),
        0.0
    );
}

#[test]
fn bad_light_parameters_are_errors() {
    let mut description = spot_scene(5.0, SpotFalloff::PbrtSmoothstep);
    if let LightDescription::Spot {
        falloff_start_degrees,
        ..
    } = &mut description.lights[0]
    {
        *falloff_start_degrees = 25.0;
    }
    let error = Scene::build(&description).unwrap_err().to_string();
    assert!(error.contains("spot light"), "{error}");
    // A wide spot without a texture is fine.
    let mut wide = spot_scene(5.0, SpotFalloff::PbrtSmoothstep);
    if let LightDescription::Spot { cutoff_degrees, .. } = &mut wide.lights[0] {
        *cutoff_degrees = 120.0;
    }
    assert!(Scene::build(&wide).is_ok());
    let mut missing = sphere_in(LightDescription::EnvironmentMap {
        filename: PathBuf::from("/nonexistent/sky.exr"),
        projection: EnvironmentProjection::MitsubaEquirectangular,
        to_world: Affine3A::IDENTITY,
        scale: 1.0,
    });
    let error = Scene::build(&missing).unwrap_err().to_string();
    assert!(error.contains("/nonexistent/sky.exr"), "{error}");
    missing.lights = vec![LightDescription::Directional {
        direction: Vec3::ZERO,
        irradiance: SpectrumDescription::Rgb([1.0; 3]),
    }];
    assert!(Scene::build(&missing).is_err());
}
