//! Light tracing (`--integrator light`) converges to the path tracer's
//! image: on the built-in scenes without media, in the furnace, and under a
//! bump map (the adjoint shading-normal correction).
//!
//! Each check renders the scene small with the path tracer at many samples
//! (its film's variance of the pixel mean is the reference's variance) and
//! with the light tracer `SEEDS` times with independent seeds. Two
//! statistics, both with variances estimated from the renders:
//!
//! 1. the image mean: each light-traced render's mean over pixels and
//!    channels is one independent sample, so `(mean − reference mean) /
//!    √(s²/R + v_ref)` is close to Student's t with R − 1 = 15 degrees of
//!    freedom; it must stay within ±4.5 (two-sided p ≈ 4e-4 for t₁₅). This
//!    catches a bias of the whole image, however small per pixel;
//! 2. the per-pixel z-test: `(Ī_p − ref_p) / √(s_p²/R + v_p)` per channel,
//!    with `s_p²` the sample variance over the seeds. With R = 16 this is
//!    close to t₁₅, for which P(|t| > 3) = 0.9 %; skewed pixel
//!    distributions (rare bright light paths) give somewhat more, so the
//!    fraction above 3 must stay under 2.5 % (the bound of the LQMC
//!    variance test, `lqmc_variance.rs`), and every pixel's mean must be
//!    finite.
//!
//! Light tracing cannot render what the camera sees through a purely
//! specular surface first (a path ending `… S E` has no vertex to connect
//! to the lens), so `glass-sphere-box` is compared on the pixels whose
//! camera rays (five per pixel, across its filter) first hit a surface with
//! a non-specular lobe ([`specular_first_hits`]). There the path tracer is
//! the noisy one: its caustic is made of rare bright paths (the light
//! tracer's is smooth), so its film variance is a poor estimate of its
//! error and the per-pixel test is reported, not asserted; the image mean,
//! whose variance comes from the light tracer's replications and the sum
//! of the reference's pixel variances, is asserted.

use glam::Vec3;
use render::camera::{FovAxis, PerspectiveSettings, look_at};
use render::image::Image;
use render::integrators::IntegratorKind;
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use render::scene::description::{
    ColourEncoding, FilterDescription, LightDescription, MaterialDescription, SceneDescription,
    ShapeDescription, ShapeGeometry, SpectrumDescription, TextureDescription, TextureFilter,
    TextureWrap,
};
use std::sync::atomic::AtomicBool;

const WIDTH: u32 = 16;
const SEEDS: u64 = 16;

fn small(mut description: SceneDescription) -> SceneDescription {
    let [width, height] = description.camera.resolution;
    let scaled_height = ((WIDTH as f64 * height as f64 / width as f64).round() as u32).max(1);
    description.camera.resolution = [WIDTH, scaled_height];
    description
}

fn render_once(
    scene: &Scene,
    integrator: IntegratorKind,
    spp: u64,
    seed: u64,
    max_depth: u32,
) -> (Image, Image) {
    let settings = RenderSettings {
        integrator: integrator.into(),
        sampler: SamplerKind::Independent,
        samples_per_pixel: spp,
        seed,
        max_depth,
        ..RenderSettings::default()
    };
    let output = render(scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    (output.image(), output.variance_image())
}

fn values(image: &Image) -> impl Iterator<Item = f64> + '_ {
    image.pixels().iter().flatten().map(|value| *value as f64)
}

/// Pixel-channel indices whose camera ray's first hit is a purely
/// specular surface (light tracing cannot reach them).
fn specular_first_hits(scene: &Scene) -> Vec<bool> {
    let [width, height] = scene.camera.resolution();
    let mut mask = Vec::new();
    for y in 0..height {
        for x in 0..width {
            // The pixel's filter reaches about a pixel around its centre.
            let mut specular = false;
            for (dx, dy) in [
                (-1.0, -1.0),
                (1.0, -1.0),
                (-1.0, 1.0),
                (1.0, 1.0),
                (0.0, 0.0),
            ] {
                let raster = glam::Vec2::new(x as f32 + 0.5 + dx, y as f32 + 0.5 + dy);
                let ray = scene.camera.generate_ray(raster, [0.5; 2], 0.5);
                let ray = render::geometry::Ray::with_time(ray.origin, ray.direction, ray.time);
                if let Some(hit) = scene.geometry.intersect(&ray, f32::INFINITY) {
                    let info = &scene.shapes[hit.shape_index as usize];
                    if let Some(material) = &info.material {
                        let wavelengths = render::spectrum::SampledWavelengths::sample_visible(0.5);
                        let bsdf = material.surface_bsdf_at(&hit, &wavelengths);
                        specular |= !bsdf.flags().is_non_specular();
                    }
                }
            }
            mask.extend([specular; 3]);
        }
    }
    mask
}

/// Renders `scene` both ways and asserts the two statistics of the module
/// docs, skipping the pixel channels `skip` marks.
fn assert_light_matches_path(
    name: &str,
    scene: &Scene,
    path_spp: u64,
    light_spp: u64,
    skip: Option<&[bool]>,
    assert_per_pixel: bool,
) {
    let max_depth = scene.max_depth.unwrap_or(6).min(8);
    // Scenes with media are compared with the volumetric path tracer.
    let reference_integrator = if scene.has_media() {
        IntegratorKind::VolPath
    } else {
        IntegratorKind::Path
    };
    let (reference, reference_variance) =
        render_once(scene, reference_integrator, path_spp, 1000, max_depth);
    let count = reference.pixels().len() * 3;
    let keep = |index: usize| skip.is_none_or(|skip| !skip[index]);
    let r = SEEDS as f64;
    let mut sum = vec![0.0f64; count];
    let mut sum_squares = vec![0.0f64; count];
    let mut image_means = Vec::new();
    for seed in 0..SEEDS {
        let (image, _) = render_once(scene, IntegratorKind::Light, light_spp, seed, max_depth);
        let mut image_sum = 0.0;
        let mut kept = 0usize;
        for (index, value) in values(&image).enumerate() {
            assert!(
                value.is_finite(),
                "{name}: pixel channel {index} is {value}"
            );
            sum[index] += value;
            sum_squares[index] += value * value;
            if keep(index) {
                image_sum += value;
                kept += 1;
            }
        }
        image_means.push(image_sum / kept as f64);
    }
    // 1. The image mean.
    let (mut reference_sum, mut reference_variance_sum, mut kept) = (0.0, 0.0, 0usize);
    for (index, (value, variance)) in values(&reference)
        .zip(values(&reference_variance))
        .enumerate()
    {
        if keep(index) {
            reference_sum += value;
            reference_variance_sum += variance;
            kept += 1;
        }
    }
    let reference_mean = reference_sum / kept as f64;
    // Neighbouring pixels of one path-traced render are independent, so the
    // variance of its mean is the sum of the pixel variances over kept².
    let reference_mean_variance = reference_variance_sum / (kept * kept) as f64;
    let light_mean = image_means.iter().sum::<f64>() / r;
    let light_mean_variance = image_means
        .iter()
        .map(|mean| (mean - light_mean).powi(2))
        .sum::<f64>()
        / (r - 1.0)
        / r;
    let t = (light_mean - reference_mean) / (light_mean_variance + reference_mean_variance).sqrt();
    // 2. Per pixel.
    let mut above_three = 0;
    let mut tests = 0;
    for (index, (reference, reference_variance)) in values(&reference)
        .zip(values(&reference_variance))
        .enumerate()
    {
        if !keep(index) {
            continue;
        }
        let mean = sum[index] / r;
        let variance = (sum_squares[index] / r - mean * mean).max(0.0) * r / (r - 1.0);
        let total = variance / r + reference_variance;
        if total <= 0.0 {
            continue;
        }
        tests += 1;
        if (mean - reference).abs() > 3.0 * total.sqrt() {
            above_three += 1;
        }
    }
    let fraction = above_three as f64 / tests.max(1) as f64;
    eprintln!(
        "{name}: image mean light {light_mean:.5} path {reference_mean:.5} ({:+.3} %, t = {t:.2}); |z| > 3 in {:.2} % of {tests} pixel channels",
        100.0 * (light_mean / reference_mean - 1.0),
        100.0 * fraction
    );
    assert!(
        tests > kept / 2,
        "{name}: only {tests} of {kept} channels tested"
    );
    assert!(t.abs() < 4.5, "{name}: image mean t = {t}");
    if assert_per_pixel {
        assert!(fraction < 0.025, "{name}: |z| > 3 in {fraction}");
    }
}

fn builtin(name: &str) -> Scene {
    Scene::build(&small(builtin_scene(name).unwrap())).unwrap()
}

#[test]
fn light_tracing_matches_path_tracing_in_the_cornell_box() {
    assert_light_matches_path("cornell-box", &builtin("cornell-box"), 1024, 64, None, true);
}

#[test]
fn light_tracing_matches_path_tracing_with_depth_of_field() {
    assert_light_matches_path("dof-spheres", &builtin("dof-spheres"), 1024, 64, None, true);
}

#[test]
fn light_tracing_matches_path_tracing_in_the_office() {
    assert_light_matches_path("office", &builtin("office"), 1024, 64, None, true);
}

#[test]
fn light_tracing_matches_path_tracing_around_a_glass_sphere() {
    let scene = builtin("glass-sphere-box");
    let mask = specular_first_hits(&scene);
    assert_light_matches_path("glass-sphere-box", &scene, 1024, 64, Some(&mask), false);
}

/// pbrt-v4's analytic furnace: every pixel is 1.
#[test]
fn light_tracing_in_the_furnace_gives_one() {
    let scene = builtin("furnace");
    let max_depth = 64;
    let renders: Vec<Image> = (0..SEEDS)
        .map(|seed| render_once(&scene, IntegratorKind::Light, 16, seed, max_depth).0)
        .collect();
    let means: Vec<f64> = renders
        .iter()
        .map(|image| values(image).sum::<f64>() / (image.pixels().len() * 3) as f64)
        .collect();
    let r = SEEDS as f64;
    let mean = means.iter().sum::<f64>() / r;
    let standard_error =
        (means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (r - 1.0) / r).sqrt();
    // The depth limit (64 segments) leaves 0.5^63 of the energy out.
    let t = (mean - 1.0) / standard_error;
    eprintln!("furnace: mean {mean:.5} ± {standard_error:.5} (t = {t:.2})");
    assert!(t.abs() < 4.5, "furnace mean {mean} ± {standard_error}");
}

/// Volumetric light tracing: `translucent-spheres` with its spheres' glass
/// replaced by index-matched boundaries (media seen directly, particles
/// entering and leaving without refraction) and without its environment,
/// so that every connection to the lens passes media and interfaces: medium
/// vertices connect with their phase function, connections carry their
/// transmittance.
#[test]
fn volumetric_light_tracing_matches_volpath_in_media_behind_interfaces() {
    let mut description = small(builtin_scene("translucent-spheres").unwrap());
    for shape in &mut description.shapes {
        if shape.interior_medium.is_some() {
            shape.material = MaterialDescription::Interface;
        }
    }
    description.lights.clear();
    let scene = Scene::build(&description).unwrap();
    assert_light_matches_path(
        "translucent-spheres with interfaces",
        &scene,
        1024,
        64,
        None,
        true,
    );
}

/// Volumetric light tracing with the camera and the light in a medium that
/// fills the room: `volumetric-caustic` with only its room and ceiling
/// light (its beam comes from a small emitter in a tube and its caustic
/// through a glass sphere, which the path tracer finds too rarely to be a
/// reference). Particles start in the fog, the medium around the light is
/// found from the camera.
#[test]
fn volumetric_light_tracing_matches_volpath_in_a_foggy_room() {
    let mut description = small(builtin_scene("volumetric-caustic").unwrap());
    // The room, the tube, its emitter, the sphere, the ceiling light.
    assert_eq!(description.shapes.len(), 5);
    description.shapes = vec![description.shapes[0].clone(), description.shapes[4].clone()];
    let scene = Scene::build(&description).unwrap();
    assert_light_matches_path("foggy room", &scene, 1024, 64, None, true);
}

/// A diffuse sphere of albedo 0.8 lit by `light`, seen from inside its
/// silhouette: the camera 0.5 outside the unit sphere, its 60° view (39°
/// to the corners) within the silhouette's 41.8° half-angle, so every
/// pixel sees the sphere.
fn sphere_under(light: LightDescription, resolution: u32) -> SceneDescription {
    let world = look_at(Vec3::new(0.0, 0.0, -1.5), Vec3::ZERO, Vec3::Y).unwrap();
    SceneDescription {
        name: "sphere-under-environment".into(),
        camera: PerspectiveSettings {
            world_from_camera: world,
            world_from_camera_end: world,
            resolution: [resolution, resolution],
            fov_degrees: 60.0,
            fov_axis: FovAxis::X,
            ..Default::default()
        },
        filter: FilterDescription::Box { radius: 0.5 },
        shapes: vec![ShapeDescription::new(
            ShapeGeometry::Sphere {
                center: Vec3::ZERO,
                radius: 1.0,
            },
            MaterialDescription::diffuse_rgb([0.8, 0.8, 0.8]),
        )],
        lights: vec![light],
        max_depth: Some(6),
        samples_per_pixel: None,
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

/// The white furnace for light tracing: a convex diffuse sphere of albedo
/// 0.8 under a constant environment of radiance 1 reflects exactly 0.8
/// everywhere. Every light path starts on the bounding sphere's disk
/// (`sample_emission` of the constant environment), so this checks the
/// disk's density, the direction's and the throughput
/// `L · π R² · 4π` against an exact answer. The tolerance is the image
/// mean's t over `SEEDS` renders (|t| < 4.5, as the other tests); at
/// 2048 paths per pixel its standard error is about 0.7 % (measured
/// 0.0053), so a deficit of 3 % or more fails, and the 4.4 % once
/// suspected of the environment lights (README) would show as |t| ≈ 6.6.
#[test]
fn light_tracing_under_a_constant_environment_reflects_the_albedo() {
    let description = sphere_under(
        LightDescription::ConstantEnvironment {
            radiance: SpectrumDescription::Rgb([1.0, 1.0, 1.0]),
        },
        8,
    );
    let scene = Scene::build(&description).unwrap();
    let means: Vec<f64> = (0..SEEDS)
        .map(|seed| {
            let (image, _) = render_once(&scene, IntegratorKind::Light, 2048, seed, 6);
            values(&image).sum::<f64>() / (image.pixels().len() * 3) as f64
        })
        .collect();
    let r = SEEDS as f64;
    let mean = means.iter().sum::<f64>() / r;
    let standard_error =
        (means.iter().map(|m| (m - mean).powi(2)).sum::<f64>() / (r - 1.0) / r).sqrt();
    // The D65-normalised white maps to sRGB (1, 1, 1) within 2e-4 (see
    // path_analytic.rs), far below the standard error.
    let t = (mean - 0.8) / standard_error;
    eprintln!("white furnace (light): mean {mean:.5} ± {standard_error:.5} (t = {t:.2})");
    assert!(
        t.abs() < 4.5,
        "white furnace mean {mean} ± {standard_error}"
    );
}

/// Light tracing under bump maps: the Cornell box with every diffuse
/// surface bump-mapped by Mitsuba's floor-tile height field (the texture of
/// its `test_bumpmap` scene, tiled 8 × 8 per triangle's uv square, height
/// scale 1), so that shading and geometric normals differ everywhere.
/// Without the adjoint shading-normal correction on light subpaths (Veach
/// 1997, Eq. 5.19; pbrt-v4 issues #13 and #385) light tracing disagrees
/// with the path tracer here: measured with the correction switched off,
/// image mean +8.3 % (t = 9.5) and 44.5 % of channels above |z| = 3; with
/// it, +2.3 % (t = 2.6; the plain box gives the same against this
/// 1024-spp reference) and 0.9 %.
#[test]
fn light_tracing_matches_path_tracing_under_bump_maps() {
    let mut description = small(builtin_scene("cornell-box").unwrap());
    let height = TextureDescription::Bitmap {
        filename: std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("../../../shared/scenes/mitsuba-data/common/textures/floor_tiles_bumpmap.png"),
        encoding: Some(ColourEncoding::Linear),
        filter: TextureFilter::Bilinear,
        wrap: TextureWrap::Repeat,
        to_uv: glam::Affine2::from_scale(glam::Vec2::splat(8.0)),
        flip_vertically: false,
        scale: 1.0,
        invert: false,
    };
    let mut bumped = 0;
    for shape in &mut description.shapes {
        if matches!(shape.material, MaterialDescription::Diffuse { .. }) {
            shape.material = MaterialDescription::BumpMap {
                height: height.clone(),
                scale: 1.0,
                nested: Box::new(shape.material.clone()),
            };
            bumped += 1;
        }
    }
    assert!(bumped >= 5, "only {bumped} diffuse shapes bump-mapped");
    let scene = Scene::build(&description).unwrap();
    assert_light_matches_path("cornell-box with bump maps", &scene, 1024, 64, None, true);
}
