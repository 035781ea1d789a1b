//! A render stopped in the middle of a pass (Ctrl-C or `--time`) keeps no
//! part of that pass's splats: an LQMC render, or a path tracer splatting
//! its film, stopped by a time budget is bit for bit the render of the
//! whole passes it completed, so the cut adds no bias (a partial pass's
//! splats would be divided by the whole passes' count). Where the budget
//! falls depends on the machine; the equality holds wherever it does.

use render::image::Image;
use render::integrators::IntegratorSettings;
use render::integrators::lqmc::LqmcSettings;
use render::renderer::{RenderSettings, render};
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

fn small_scene(name: &str) -> Scene {
    let mut description = builtin_scene(name).unwrap();
    description.camera.resolution = [32, 24];
    Scene::build(&description).unwrap()
}

/// The image of `settings` and the whole passes it kept.
fn render_image(scene: &Scene, settings: &RenderSettings) -> (Image, u64) {
    let output = render(scene, settings, &AtomicBool::new(false), &|_, _| {}).unwrap();
    (
        output.image(),
        output.statistics.completed_samples_per_pixel,
    )
}

fn assert_partial_pass_dropped(scene_name: &str, integrator: IntegratorSettings, splat_film: bool) {
    let scene = small_scene(scene_name);
    let settings = RenderSettings {
        integrator,
        samples_per_pixel: 1 << 20,
        time_budget: Some(Duration::from_millis(150)),
        seed: 5,
        splat_film,
        threads: 2,
        // Small tiles: the budget is likely to fall inside a pass.
        tile_size: 4,
        max_depth: scene.max_depth.unwrap_or(6),
        ..RenderSettings::default()
    };
    let (stopped, completed) = render_image(&scene, &settings);
    assert!(completed >= 1, "{scene_name}: no pass completed");
    let whole = RenderSettings {
        samples_per_pixel: completed,
        time_budget: None,
        ..settings
    };
    let (whole_passes, _) = render_image(&scene, &whole);
    for (a, b) in stopped.pixels().iter().zip(whole_passes.pixels()) {
        assert_eq!(
            a.map(f32::to_bits),
            b.map(f32::to_bits),
            "{scene_name}: the partial pass left a trace ({completed} whole passes)"
        );
    }
}

#[test]
fn lqmc_drops_a_partial_pass() {
    assert_partial_pass_dropped(
        "glass-sphere-box",
        IntegratorSettings::Lqmc(LqmcSettings::paper_classes()),
        false,
    );
}

#[test]
fn a_splatting_path_tracer_drops_a_partial_pass() {
    assert_partial_pass_dropped("dof-spheres", IntegratorSettings::Path, true);
}
