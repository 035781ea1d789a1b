//! The spot light against Mitsuba 3's own test scene
//! `mitsuba-data/tests/scenes/spot_light/test_spot_direct.xml`, rebuilt here
//! as a scene description (what the Mitsuba loader will produce): a white
//! diffuse square 1 ahead of the camera, lit by a constant environment of
//! 0.1 and a spot light of intensity 5 (cutoff 20°, beam width 15°) at the
//! camera's position projecting `de_bruijn_pattern.png`; `direct`
//! integrator (our path tracer at depth 2), 48 × 48.
//!
//! Mitsuba's reference (`refs/test_spot_ref_spectral.exr`, 32,000 samples
//! per pixel) comes with the variance of one sample per pixel
//! (`*_var.exr`), so the reference mean's variance is that over 32,000.
//! Checks (see `light_common`): image means within 4 σ + 1 %, at least 99 %
//! of pixels within |z| < 4.
//!
//! The stripes of the pattern are narrow and of high contrast, and our
//! power-proportional light selection picks the spot for only about 8 % of
//! the light samples (the environment's bounding-disk power dominates;
//! Mitsuba picks each emitter half the time), so a pixel's estimate rests on
//! few spot samples with a heavy-tailed distribution: at 256 samples per
//! pixel 2.4 % of pixels exceed |z| = 4 (with the RMSE against the
//! reference 2.7 times Mitsuba's own at 256 samples, the ratio √(0.5/0.08)
//! predicts), at 1024 only 0.3 %. Measured (seed 1, 1024 spp): image
//! means within +0.2 %, +0.7 %, −0.6 % (0.5, 1.9, −1.5 σ); 2297 of 2304
//! pixels within |z| < 4.

mod light_common;

use std::path::PathBuf;

use glam::{Affine2, Affine3A, Vec3};
use render::camera::{FovAxis, PerspectiveSettings, look_at};
use render::image::read_exr;
use render::scene::description::{
    FilterDescription, LightDescription, MaterialDescription, SceneDescription, ShapeDescription,
    ShapeGeometry, SpectrumDescription, SpotFalloff, TextureDescription, TextureFilter,
    TextureWrap,
};

const RESOLUTION: usize = 48;
const SAMPLES_PER_PIXEL: u64 = 1024;
/// Samples per pixel of Mitsuba's reference.
const REFERENCE_SAMPLES: f64 = 32_000.0;

fn scene_directory() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/external/mitsuba-data/tests/scenes/spot_light")
}

fn description() -> SceneDescription {
    let world = look_at(Vec3::ZERO, Vec3::Z, Vec3::Y).unwrap();
    // <scale 3, 3, 1/> <rotate y 180/> <translate z 1/>
    let square = Affine3A::from_translation(Vec3::Z)
        * Affine3A::from_rotation_y(std::f32::consts::PI)
        * Affine3A::from_scale(Vec3::new(3.0, 3.0, 1.0));
    SceneDescription {
        name: "mitsuba-spot".into(),
        camera: PerspectiveSettings {
            world_from_camera: world,
            world_from_camera_end: world,
            resolution: [RESOLUTION as u32; 2],
            fov_degrees: 50.0,
            fov_axis: FovAxis::X,
            ..Default::default()
        },
        filter: FilterDescription::Box { radius: 0.5 },
        shapes: vec![ShapeDescription::new(
            ShapeGeometry::Rectangle { to_world: square },
            MaterialDescription::Diffuse {
                reflectance: TextureDescription::Constant(SpectrumDescription::Rgb([1.0; 3])),
                two_sided: false,
            },
        )],
        lights: vec![
            LightDescription::ConstantEnvironment {
                radiance: SpectrumDescription::Rgb([0.1; 3]),
            },
            LightDescription::Spot {
                // <lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/>
                to_world: Affine3A::IDENTITY,
                intensity: SpectrumDescription::Rgb([5.0; 3]),
                cutoff_degrees: 20.0,
                falloff_start_degrees: 15.0,
                falloff: SpotFalloff::MitsubaLinearAngle,
                texture: Some(TextureDescription::Bitmap {
                    filename: scene_directory().join("textures/de_bruijn_pattern.png"),
                    encoding: None,
                    filter: TextureFilter::Bilinear,
                    wrap: TextureWrap::Repeat,
                    to_uv: Affine2::IDENTITY,
                    flip_vertically: false,
                    scale: 1.0,
                    invert: false,
                }),
            },
        ],
        max_depth: Some(2),
        samples_per_pixel: None,
        russian_roulette_depth: None,
        media: Vec::new(),
        camera_medium: None,
        integrator: None,
    }
}

#[test]
fn textured_spot_light_matches_mitsuba() {
    let reference = read_exr(scene_directory().join("refs/test_spot_ref_spectral.exr"))
        .unwrap()
        .image;
    let variance = read_exr(scene_directory().join("refs/test_spot_ref_spectral_var.exr"))
        .unwrap()
        .image;
    assert_eq!([reference.width(), reference.height()], [RESOLUTION; 2]);
    let ours = light_common::render_estimate(&description(), SAMPLES_PER_PIXEL, 2);
    light_common::assert_matches_reference(
        &ours,
        &reference,
        |index, channel| variance.pixels()[index][channel] as f64 / REFERENCE_SAMPLES,
        0.99,
    );
}
