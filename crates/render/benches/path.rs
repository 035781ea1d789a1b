//! Paths per second of the path tracer on `builtin:cornell-box`.
//!
//! Each iteration is one call of [`render::renderer::render`]: the Cornell box
//! at 64 × 64 pixels, 16 samples per pixel, maximum depth 6 (Mitsuba's
//! convention: path segments), next-event estimation with MIS (the power
//! heuristic). Halton and independent samplers, on 1 and 2 threads.
//! divan's item counter reports camera paths (pixel samples) per second:
//! read `Mitem/s` as M paths/s. The time includes the renderer's own thread
//! pool set-up and film merging, as a user of `render` would see it.
//!
//! Run with `cargo bench -p render --bench path`.

use std::sync::LazyLock;
use std::sync::atomic::AtomicBool;

use divan::counter::ItemsCount;
use divan::{Bencher, black_box};
use render::renderer::{RenderSettings, render};
use render::sampler::SamplerKind;
use render::scene::Scene;
use render::scene::builtin::builtin_scene;

/// Image side in pixels.
const RESOLUTION: u32 = 64;
/// Samples per pixel per iteration.
const SAMPLES_PER_PIXEL: u64 = 16;
/// Maximum path depth (segments, as Mitsuba counts).
const MAX_DEPTH: u32 = 6;
/// Camera paths traced per iteration.
const PATHS_PER_ITERATION: u64 = RESOLUTION as u64 * RESOLUTION as u64 * SAMPLES_PER_PIXEL;

fn main() {
    divan::main();
}

static CORNELL_BOX: LazyLock<Scene> = LazyLock::new(|| {
    let mut description = builtin_scene("cornell-box").expect("the built-in Cornell box exists");
    description.camera.resolution = [RESOLUTION, RESOLUTION];
    Scene::build(&description).expect("the built-in Cornell box builds")
});

fn render_cornell_box(bencher: Bencher, sampler: SamplerKind, threads: usize) {
    let scene = &*CORNELL_BOX;
    let settings = RenderSettings {
        sampler,
        samples_per_pixel: SAMPLES_PER_PIXEL,
        max_depth: MAX_DEPTH,
        threads,
        seed: 7,
        ..RenderSettings::default()
    };
    let stop = AtomicBool::new(false);
    bencher
        .counter(ItemsCount::new(PATHS_PER_ITERATION))
        .bench(|| {
            let output = render(black_box(scene), &settings, &stop, &|_, _| {})
                .expect("the Cornell box renders");
            assert_eq!(output.statistics.samples, PATHS_PER_ITERATION);
            black_box(output.film)
        });
}

/// Cornell box with the Halton sampler (the project's default).
#[divan::bench(args = [1, 2], sample_count = 10, sample_size = 1)]
fn cornell_box_halton(bencher: Bencher, threads: usize) {
    render_cornell_box(bencher, SamplerKind::Halton, threads);
}

/// Cornell box with independent uniform random numbers (Mitsuba's default).
#[divan::bench(args = [1, 2], sample_count = 10, sample_size = 1)]
fn cornell_box_independent(bencher: Bencher, threads: usize) {
    render_cornell_box(bencher, SamplerKind::Independent, threads);
}
