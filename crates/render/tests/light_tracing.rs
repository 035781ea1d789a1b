//! Light tracing (`--integrator light`) converges to the path tracer's
//! image: on the built-in scenes without media, in the furnace, and under a
//! bump map (the adjoint shading-normal correction).
//!
//! Each check is `path_comparison::assert_matches_path`: the image-mean
//! t-test and the per-pixel z-test against the path tracer, with variances
//! from independent seeds.
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
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use render::scene::description::{
    ColourEncoding, FilterDescription, LightDescription, MaterialDescription, SceneDescription,
    ShapeDescription, ShapeGeometry, SpectrumDescription, TextureDescription, TextureFilter,
    TextureWrap,
};

mod media_scenes;
mod path_comparison;
use path_comparison::{
    LIGHT, SEEDS, assert_matches_path, builtin, render_once, small, specular_first_hits, values,
};

#[test]
fn light_tracing_matches_path_tracing_in_the_cornell_box() {
    assert_matches_path(
        "cornell-box",
        &builtin("cornell-box"),
        LIGHT,
        1024,
        64,
        None,
        true,
    );
}

#[test]
fn light_tracing_matches_path_tracing_with_depth_of_field() {
    assert_matches_path(
        "dof-spheres",
        &builtin("dof-spheres"),
        LIGHT,
        1024,
        64,
        None,
        true,
    );
}

#[test]
fn light_tracing_matches_path_tracing_in_the_office() {
    assert_matches_path("office", &builtin("office"), LIGHT, 1024, 64, None, true);
}

#[test]
fn light_tracing_matches_path_tracing_around_a_glass_sphere() {
    let scene = builtin("glass-sphere-box");
    let mask = specular_first_hits(&scene);
    assert_matches_path(
        "glass-sphere-box",
        &scene,
        LIGHT,
        1024,
        64,
        Some(&mask),
        false,
    );
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
    let scene = Scene::build(&media_scenes::media_behind_interfaces(small)).unwrap();
    assert_matches_path(
        "translucent-spheres with interfaces",
        &scene,
        LIGHT,
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
    let scene = Scene::build(&media_scenes::foggy_room(small)).unwrap();
    assert_matches_path("foggy room", &scene, LIGHT, 1024, 64, None, true);
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
/// suspected of the environment lights (docs/integrators/light.md) would show as |t| ≈ 6.6.
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
            .join("../../scenes/external/mitsuba-data/common/textures/floor_tiles_bumpmap.png"),
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
                options: Default::default(),
            };
            bumped += 1;
        }
    }
    assert!(bumped >= 5, "only {bumped} diffuse shapes bump-mapped");
    let scene = Scene::build(&description).unwrap();
    assert_matches_path(
        "cornell-box with bump maps",
        &scene,
        LIGHT,
        1024,
        64,
        None,
        true,
    );
}
