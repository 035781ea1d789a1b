use super::*;

fn camera(settings: PerspectiveSettings) -> PerspectiveCamera {
    PerspectiveCamera::new(&settings).unwrap()
}

#[test]
fn centre_ray_looks_at_the_target_and_corners_span_the_fov() {
    let world = look_at(Vec3::new(0.0, 1.0, 5.0), Vec3::new(0.0, 1.0, 0.0), Vec3::Y).unwrap();
    let camera = camera(PerspectiveSettings {
        world_from_camera: world,
        world_from_camera_end: world,
        resolution: [200, 100],
        fov_degrees: 90.0,
        ..Default::default()
    });
    let centre = camera.generate_ray(Vec2::new(100.0, 50.0), [0.5, 0.5], 0.5);
    assert!((centre.direction - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
    assert!((centre.origin - Vec3::new(0.0, 1.0, 5.0)).length() < 1e-6);
    // The right edge of the image at 90° horizontal fov is 45° to the right.
    let right = camera.generate_ray(Vec2::new(200.0, 50.0), [0.5, 0.5], 0.5);
    assert!((right.direction - Vec3::new(1.0, 0.0, -1.0).normalize()).length() < 1e-6);
    // The top edge is up, with half the horizontal extent (aspect 2).
    let top = camera.generate_ray(Vec2::new(100.0, 0.0), [0.5, 0.5], 0.5);
    assert!((top.direction - Vec3::new(0.0, 0.5, -1.0).normalize()).length() < 1e-6);
}

#[test]
fn thin_lens_rays_converge_on_the_focus_plane() {
    let camera = camera(PerspectiveSettings {
        resolution: [64, 64],
        lens_radius: 0.2,
        focus_distance: 3.0,
        ..Default::default()
    });
    let raster = Vec2::new(10.0, 40.0);
    let pinhole = camera.generate_ray(raster, [0.5, 0.5], 0.0);
    let focus_point = pinhole.direction * (3.0 / pinhole.direction.z);
    for u in [[0.1, 0.9], [0.7, 0.2], [0.99, 0.5]] {
        let ray = camera.generate_ray(raster, u, 0.0);
        assert!(ray.origin.z.abs() < 1e-6 && ray.origin.truncate().length() <= 0.2 + 1e-6);
        let t = (3.0 - ray.origin.z) / ray.direction.z;
        let at_focus = ray.origin + ray.direction * t;
        assert!(
            (at_focus - focus_point).length() < 1e-4,
            "{at_focus} vs {focus_point}"
        );
    }
}

#[test]
fn camera_moves_during_the_shutter() {
    let start = Affine3A::from_translation(Vec3::ZERO);
    let end = Affine3A::from_translation(Vec3::new(2.0, 0.0, 0.0));
    let camera = camera(PerspectiveSettings {
        world_from_camera: start,
        world_from_camera_end: end,
        shutter: [0.0, 1.0],
        ..Default::default()
    });
    let ray = camera.generate_ray(Vec2::new(256.0, 256.0), [0.5, 0.5], 0.25);
    assert!((ray.time - 0.25).abs() < 1e-6);
    assert!((ray.origin - Vec3::new(0.5, 0.0, 0.0)).length() < 1e-6);
}

#[test]
fn invalid_settings_are_errors() {
    for settings in [
        PerspectiveSettings {
            resolution: [0, 4],
            ..Default::default()
        },
        PerspectiveSettings {
            fov_degrees: 180.0,
            ..Default::default()
        },
        PerspectiveSettings {
            lens_radius: -1.0,
            ..Default::default()
        },
        PerspectiveSettings {
            lens_radius: 0.1,
            focus_distance: 0.0,
            ..Default::default()
        },
        PerspectiveSettings {
            shutter: [1.0, 0.0],
            ..Default::default()
        },
    ] {
        assert!(PerspectiveCamera::new(&settings).is_err());
    }
    assert!(look_at(Vec3::ZERO, Vec3::ZERO, Vec3::Y).is_err());
    assert!(look_at(Vec3::ZERO, Vec3::Y, Vec3::Y).is_err());
}
