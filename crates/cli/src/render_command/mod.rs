//! `lqmc render` and `lqmc scenes`: render a scene to EXR and PNG.
//!
//! [`arguments`] defines the options (the integrators' own groups are
//! [`crate::integrator_options`]); [`run`] checks them, loads the scene and
//! prepares a [`Job`], which [`single`] renders once or [`replicated`] as
//! independent replications; [`output`] writes the files and [`report`]
//! prints what happened.

pub mod arguments;
pub mod output;
pub mod replicated;
pub mod report;
pub mod request;
pub mod scene;
pub mod single;

pub use arguments::{RenderArgs, parse_definition};
pub use request::{RenderRequest, parse_time_budget, render_metadata, traced_samples_per_pixel};
pub use scene::{build_scene, default_path_tracer, load_scene_description};

use crate::error::{CliError, usage};
use crate::integrator_options::ownership::{
    Choice, check_conditional_options, check_render_options,
};
use crate::live_view::LiveView;
use crate::replications::ReplicationRequest;
use clap::ArgMatches;
use render::image::ImageFormat;
use render::integrators::IntegratorKind;
use render::renderer::RenderSettings;
use render::scene::Scene;
use render::scene::builtin::BUILTIN_SCENES;
use report::Console;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// The scene rendered when none is named.
const DEFAULT_SCENE_NAME: &str = "builtin:cornell-box";

/// A render ready to run: every option checked, the scene built, nothing
/// rendered yet.
pub struct Job<'a> {
    /// The options.
    pub args: &'a RenderArgs,
    /// The scene as the user named it.
    pub scene_name: &'a str,
    /// The scene.
    pub scene: Scene,
    /// The renderer's settings.
    pub settings: RenderSettings,
    /// The format of `--output`.
    pub format: ImageFormat,
    /// Where the render reports.
    pub console: Console,
    /// Set by Ctrl-C: the render stops and writes what it has.
    pub stop: Arc<AtomicBool>,
    /// The viewer shown the image while it renders (`--tev`).
    pub live_view: Option<LiveView>,
}

/// Runs `lqmc render`; `matches` are its arguments as clap parsed them
/// (which options the user gave).
pub fn run(args: &RenderArgs, matches: &ArgMatches) -> Result<(), CliError> {
    let (job, replications) = prepare(args, matches)?;
    match replications {
        Some(request) => replicated::render(&job, &request),
        None => single::render(&job),
    }
}

/// Runs `lqmc scenes`.
pub fn list_scenes() -> Result<(), CliError> {
    let console = Console::new(false);
    for (name, description) in BUILTIN_SCENES {
        console.say(format_args!("builtin:{name:<18} {description}"));
    }
    Ok(())
}

/// Checks the options, loads the scene and prepares the render, with the
/// replications it is split into, if any.
fn prepare<'a>(
    args: &'a RenderArgs,
    matches: &ArgMatches,
) -> Result<(Job<'a>, Option<ReplicationRequest>), CliError> {
    let format = check_options_without_scene(args)?;
    if let Some(kind) = args.integrator {
        check_render_options(matches, kind, Choice::Named)?;
    }
    let scene_name = args.scene.as_deref().unwrap_or(DEFAULT_SCENE_NAME);
    let description =
        load_scene_description(scene_name, &args.define, args.resolution, args.quiet)?;
    let scene = build_scene(scene_name, &description)?;
    let kind = match args.integrator {
        Some(kind) => kind,
        None => {
            let kind = scene::default_integrator(&description, &scene);
            check_render_options(matches, kind, Choice::SceneDefault)?;
            kind
        }
    };
    check_conditional_options(matches, kind, scene.has_media())?;
    let (request, replications) = render_request(args, &scene, kind)?;
    replicated::check_outputs(args, replications.as_ref(), format)?;
    if let Some(directory) = &args.integrators.bdpt.strategy_images {
        output::create_strategy_directory(directory)?;
    }
    output::check_writable(&args.output)?;
    let live_view = open_live_view(args, &scene)?;
    let job = Job {
        args,
        scene_name,
        settings: request.settings(&scene),
        scene,
        format,
        console: Console::new(args.quiet),
        stop: stop_on_interrupt(),
        live_view,
    };
    Ok((job, replications))
}

/// Checks the options that need no scene; returns the output's format.
fn check_options_without_scene(args: &RenderArgs) -> Result<ImageFormat, CliError> {
    if args.spp == Some(0) {
        return Err(usage("--spp must be at least 1"));
    }
    if let Some(seconds) = args.time {
        parse_time_budget("--time", seconds)?;
    }
    if args.path.max_depth == Some(0) {
        return Err(usage("--max-depth must be at least 1"));
    }
    output::output_format(&args.output)
}

/// What the options ask `kind` to render of `scene`, and the independent
/// replications the render is split into, if any.
fn render_request(
    args: &RenderArgs,
    scene: &Scene,
    kind: IntegratorKind,
) -> Result<(RenderRequest, Option<ReplicationRequest>), CliError> {
    let integrator = args.integrators.settings(kind)?;
    let (pattern_size, samples_per_pixel) = replicated::pattern_plan(args)?;
    args.sampler
        .check_pattern_size(pattern_size)
        .map_err(|error| usage(error.to_string()))?;
    let randomization = args.randomize;
    let replications = replicated::requested(args, scene, kind, randomization)?;
    let request = RenderRequest {
        integrator,
        sampler: args.sampler,
        pattern_size,
        samples_per_pixel: match &replications {
            Some(request) => request.samples_per_replication,
            None => samples_per_pixel,
        },
        time_budget: args
            .time
            .map(|seconds| parse_time_budget("--time", seconds))
            .transpose()?,
        seed: args.seed,
        randomization,
        max_depth: args.path.max_depth,
        russian_roulette_depth: args.path.rr_depth,
        heuristic: args.path.heuristic(kind),
        splat_film: args.path_tracer.splat_film,
        threads: args.threads,
    };
    Ok((request, replications))
}

/// Connects to tev if `--tev` asks for it.
fn open_live_view(args: &RenderArgs, scene: &Scene) -> Result<Option<LiveView>, CliError> {
    let Some(address) = &args.tev else {
        return Ok(None);
    };
    let [width, height] = scene.camera.resolution();
    let name = args.output.file_name().map_or_else(
        || "lqmc".to_string(),
        |name| name.to_string_lossy().into_owned(),
    );
    LiveView::open(address, &name, width, height)
        .map(Some)
        .map_err(|error| usage(format!("--tev: {error}")))
}

/// A flag that Ctrl-C sets. A second Ctrl-C while the image is written
/// falls through to the default.
fn stop_on_interrupt() -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    stop
}

impl Job<'_> {
    /// Whether Ctrl-C stopped the render.
    pub fn interrupted(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// The integrator the render uses.
    pub fn integrator(&self) -> IntegratorKind {
        self.settings.integrator.kind()
    }
}
