//! The environment-map light against Mitsuba 3: a diffuse sphere
//! (reflectance 0.2, 0.5, 0.3) under `museum.exr` (rotated 60° about +y,
//! scale 1.5), 32 × 32, max depth 3. Half the pixels see the map directly
//! (the lookup: orientation, bilinear interpolation, spectral upsampling),
//! the others the sphere lit by it (importance sampling with MIS).
//!
//! The reference in `tests/data/envmap_mitsuba_*` was rendered by
//! `scripts/envmap_reference.py` with Mitsuba 3.9.1 `scalar_spectral`: 32
//! independent images of 64 samples per pixel; the mean and the variance of
//! that mean per pixel (see `envmap_mitsuba_reference.txt`). Checks (see
//! `light_common`): image means within 4 σ + 1 %, at least 99 % of pixels
//! within |z| < 4. Measured (seed 1, 1024 spp): means −0.03 %, −0.12 %,
//! −0.32 % (−0.7, −1.4, −2.4 σ); 1017 of 1024 pixels within |z| < 4.

mod light_common;

use std::path::PathBuf;

use glam::{Affine3A, Vec3};
use render::camera::{FovAxis, PerspectiveSettings, look_at};
use render::image::{Image, read_pfm};
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
                .join("../../scenes/external/mitsuba-data/common/textures/museum.exr"),
            projection: EnvironmentProjection::MitsubaEquirectangular,
            to_world: Affine3A::from_rotation_y(60f32.to_radians()),
            scale: 1.5,
        }],
        max_depth: Some(3),
        samples_per_pixel: None,
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

#[test]
fn environment_map_matches_mitsuba_scalar_spectral() {
    let ours = light_common::render_estimate(&description(), SAMPLES_PER_PIXEL, 3);
    let variance = reference("envmap_mitsuba_variance.pfm");
    light_common::assert_matches_reference(
        &ours,
        &reference("envmap_mitsuba_mean.pfm"),
        |index, channel| variance.pixels()[index][channel] as f64,
        0.99,
    );
}
