//! LQMC's class selection (`lqmc::class_selection`): a pilot with its own
//! seed keeps the classes whose exploration pays and switches off the
//! others; the render is then LQMC with those classes fixed (unbiased as
//! LQMC is), the same whatever the threads, and where no class is left it
//! is the path tracer's image bit for bit.

use render::image::Image;
use render::integrators::lqmc::integrator::PathTracedDetails;
use render::integrators::lqmc::{ClassSelection, LqmcDetails, LqmcSettings, PathClass};
use render::integrators::{IntegratorKind, IntegratorSettings};
use render::renderer::{RenderOutput, RenderSettings, render};
use render::scene::Scene;
use render::scene::builtin::builtin_scene;
use std::sync::atomic::AtomicBool;

fn scene(name: &str, resolution: [u32; 2]) -> Scene {
    let mut description = builtin_scene(name).unwrap();
    description.camera.resolution = resolution;
    Scene::build(&description).unwrap()
}

fn render_with(
    scene: &Scene,
    integrator: IntegratorSettings,
    spp: u64,
    seed: u64,
    threads: usize,
) -> RenderOutput {
    let settings = RenderSettings {
        integrator,
        samples_per_pixel: spp,
        seed,
        threads,
        max_depth: scene.max_depth.unwrap_or(6),
        ..RenderSettings::default()
    };
    render(scene, &settings, &AtomicBool::new(false), &|_, _| {}).unwrap()
}

fn image(output: &RenderOutput, spp: u64) -> Image {
    output.film.image(1.0 / spp as f64)
}

/// The paper's classes on dof-spheres: exploring normal paths costs three
/// times a seed for no less variance and depth of field fails to pay too,
/// so the pilot switches both off (the caustic class never occurs, too rare
/// to judge, and stays) and the render explores nothing; with
/// `--class-selection fixed` both are explored.
#[test]
fn the_pilot_switches_off_classes_that_do_not_pay() {
    let scene = scene("dof-spheres", [64, 48]);
    let candidates = LqmcSettings {
        class_selection: ClassSelection::Measured,
        ..LqmcSettings::paper_classes()
    };
    let measured = render_with(&scene, IntegratorSettings::Lqmc(candidates), 2, 3, 2);
    let details = measured.details::<LqmcDetails>().expect("an LQMC render");
    let selection = details.selection.as_ref().expect("the pilot ran");
    let chosen = |class: PathClass| {
        selection
            .classes
            .iter()
            .find(|measurement| measurement.class == class)
            .copied()
            .unwrap()
    };
    for class in [PathClass::Normal, PathClass::DepthOfField] {
        let measurement = chosen(class);
        assert!(measurement.measured, "{measurement:?}");
        assert!(!measurement.explored, "{measurement:?}");
        assert!(
            measurement.variance_ratio * measurement.cost_ratio >= 1.0,
            "{measurement:?}"
        );
    }
    let caustic = chosen(PathClass::Caustic);
    assert!(!caustic.measured && caustic.explored, "{caustic:?}");
    assert_eq!(details.statistics.explorations.iter().sum::<u64>(), 0);

    let fixed = LqmcSettings {
        class_selection: ClassSelection::Fixed,
        ..candidates
    };
    let fixed = render_with(&scene, IntegratorSettings::Lqmc(fixed), 2, 3, 2);
    let details = fixed.details::<LqmcDetails>().expect("an LQMC render");
    assert!(details.selection.is_none());
    assert!(details.statistics.explorations[PathClass::Normal.index()] > 0);
    assert!(details.statistics.explorations[PathClass::DepthOfField.index()] > 0);
}

/// Where the pilot keeps no class, the path tracer renders the seeds: its
/// image bit for bit, with the pilot's report in the details.
#[test]
fn no_class_kept_renders_as_the_path_tracer() {
    let scene = scene("dof-spheres", [64, 48]);
    let mut candidates = LqmcSettings::paper_classes();
    candidates.class_selection = ClassSelection::Measured;
    candidates.caustic.explore = false;
    let lqmc = render_with(&scene, IntegratorSettings::Lqmc(candidates), 2, 5, 2);
    let details = lqmc
        .details::<PathTracedDetails>()
        .expect("the path tracer rendered it");
    assert!(
        details
            .selection
            .classes
            .iter()
            .all(|class| !class.explored)
    );
    let path = render_with(&scene, IntegratorKind::Path.into(), 2, 5, 2);
    assert_eq!(image(&lqmc, 2).pixels(), image(&path, 2).pixels());
}

/// The pilot's choice and so the image do not depend on the threads.
#[test]
fn the_selection_is_the_same_whatever_the_threads() {
    let scene = scene("glass-sphere-box", [64, 48]);
    let mut settings = LqmcSettings::default();
    settings.normal.explore = true;
    let one = render_with(&scene, IntegratorSettings::Lqmc(settings), 2, 7, 1);
    let two = render_with(&scene, IntegratorSettings::Lqmc(settings), 2, 7, 2);
    let selection =
        |output: &RenderOutput| output.details::<LqmcDetails>().unwrap().selection.clone();
    assert!(selection(&one).is_some());
    assert_eq!(selection(&one), selection(&two));
    assert_eq!(image(&one, 2).pixels(), image(&two, 2).pixels());
}
