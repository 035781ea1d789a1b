//! Scenes with participating media shared by the integration tests of
//! `volpath` (`volume_analytic.rs`), light tracing (`light_tracing.rs`) and
//! BDPT (`bdpt_media.rs`).
#![allow(dead_code)]

use glam::Vec3;
use render::scene::builtin::builtin_scene;
use render::scene::description::{
    MaterialDescription, MediumCoefficients, MediumDescription, PhaseDescription, SceneDescription,
    ShapeDescription, ShapeGeometry, SpectrumDescription,
};

/// A homogeneous medium of `albedo` and extinction `sigma_t`.
pub fn medium(
    albedo: SpectrumDescription,
    sigma_t: SpectrumDescription,
    phase: PhaseDescription,
) -> MediumDescription {
    MediumDescription {
        coefficients: MediumCoefficients::AlbedoExtinction { albedo, sigma_t },
        scale: 1.0,
        phase,
    }
}

/// The closed furnace sphere (diffuse albedo 0.5, emitting 0.5) with the
/// camera at its centre inside medium 0, a white non-absorbing medium:
/// every pixel is 1.
pub fn medium_furnace(resolution: u32) -> SceneDescription {
    let mut description = builtin_scene("furnace").unwrap();
    description.camera.resolution = [resolution, resolution];
    description.media = vec![medium(
        SpectrumDescription::Constant(1.0),
        SpectrumDescription::Constant(1.5),
        PhaseDescription::HenyeyGreenstein { g: 0.6 },
    )];
    description.camera_medium = Some(0);
    description.max_depth = Some(1000);
    description
}

/// Adds to [`medium_furnace`] an index-matched sphere and a glass sphere
/// (index 1.5), both filled with a white medium whose extinction varies
/// 60-fold over the spectrum: in the furnace's uniform radiance field both
/// are invisible.
pub fn add_chromatic_spheres(description: &mut SceneDescription) {
    description.media.push(medium(
        SpectrumDescription::Constant(1.0),
        SpectrumDescription::Sampled {
            wavelengths: vec![360.0, 500.0, 600.0, 830.0],
            values: vec![0.5, 4.0, 12.0, 30.0],
        },
        PhaseDescription::Isotropic,
    ));
    let medium_index = description.media.len() - 1;
    for (center, material) in [
        (Vec3::new(-0.35, 0.0, 0.55), MaterialDescription::Interface),
        (
            Vec3::new(0.35, 0.0, 0.55),
            MaterialDescription::smooth_dielectric(1.5),
        ),
    ] {
        let mut sphere = ShapeDescription::new(
            ShapeGeometry::Sphere {
                center,
                radius: 0.3,
            },
            material,
        );
        sphere.interior_medium = Some(medium_index);
        sphere.exterior_medium = Some(0);
        description.shapes.push(sphere);
    }
}

/// `translucent-spheres` (`small`: the tests' size) with its spheres' glass
/// replaced by index-matched boundaries and without its environment: media
/// seen directly, particles entering and leaving without refraction, every
/// connection to the lens passing media and boundaries.
pub fn media_behind_interfaces(
    small: impl Fn(SceneDescription) -> SceneDescription,
) -> SceneDescription {
    let mut description = small(builtin_scene("translucent-spheres").unwrap());
    for shape in &mut description.shapes {
        if shape.interior_medium.is_some() {
            shape.material = MaterialDescription::Interface;
        }
    }
    description.lights.clear();
    description
}

/// `volumetric-caustic` (`small`) with only its room and ceiling light:
/// the camera and the light in fog that fills the room.
pub fn foggy_room(small: impl Fn(SceneDescription) -> SceneDescription) -> SceneDescription {
    let mut description = small(builtin_scene("volumetric-caustic").unwrap());
    // The room, the tube, its emitter, the sphere, the ceiling light.
    assert_eq!(description.shapes.len(), 5);
    description.shapes = vec![description.shapes[0].clone(), description.shapes[4].clone()];
    description
}
