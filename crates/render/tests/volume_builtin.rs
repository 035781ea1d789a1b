//! The built-in scenes with media build, render with `volpath` without
//! non-finite samples, and show what they are meant to show at a few
//! samples per pixel.

use render::integrators::IntegratorKind;
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use std::sync::atomic::AtomicBool;

#[test]
fn media_scenes_render_with_volpath() {
    for name in ["translucent-spheres", "volumetric-caustic"] {
        let mut description = builtin_scene(name).unwrap();
        description.camera.resolution = [32, 24];
        let scene = Scene::build(&description).unwrap();
        assert!(scene.has_media(), "{name}");
        let settings = RenderSettings {
            integrator: IntegratorKind::VolPath.into(),
            sampler: SamplerKind::Sobol,
            samples_per_pixel: 4,
            max_depth: description.max_depth.unwrap(),
            ..RenderSettings::default()
        };
        let output = render(&scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
        assert_eq!(output.statistics.nonfinite_samples, 0, "{name}");
        let mean = output.film.image(1.0).mean();
        assert!(
            mean.iter().all(|&c| c > 0.0 && c.is_finite()),
            "{name}: {mean:?}"
        );
    }
}
