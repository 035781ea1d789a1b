//! `lqmc study equal-time`: which integrator gets closest to a reference in
//! the same wall-clock time? Every integrator renders the scene K times
//! (seeds 0..K) for each time budget with the same threads, interleaved so
//! that changes of machine load hit all alike; each image is compared with
//! a reference, and the study writes a markdown and a JSON table, an
//! error-versus-time plot and a strip of crops.
//!
//! The measures are those of `lqmc compare` (RMSE, relative MSE, mean
//! absolute deviation) per seed, summarised by median and range, and the
//! seeds' mean bias and flicker (see [`super::measures`]). They are
//! computed from the EXR files the study writes, read back, so that what a
//! table says can be recomputed from the images beside it.

use super::crops::{CropRectangle, write_crop_strip};
use super::entry_options::entry_integrator_args;
use super::error_plot::{ErrorCurve, ErrorPoint, write_error_plot};
use super::formatting::{
    command_line, format_percentage, format_significant, load_average, shown_path, spread_json,
    spread_text, utc_timestamp,
};
use super::measures::{Spread, flicker, mean_bias, spread};
use super::study_renders::{
    RenderContext, WrittenRender, definitions_text, print_report, read_reference, read_study_image,
    stop_on_interrupt, write_tables,
};
use super::{IntegratorEntry, StudySceneArgs, check_distinct, parse_integrator_list};
use crate::error::{CliError, usage};
use crate::integrator_options::ownership::check_study_options;
use crate::json::Json;
use crate::render_command::{
    build_scene, default_path_tracer, load_scene_description, parse_time_budget,
};
use clap::{ArgMatches, Args};
use render::image::compare::{ImageComparison, RELATIVE_MSE_EPSILON, compare_images};
use render::image::{Image, read_exr, read_image};
use render::integrators::IntegratorKind;
use render::sampler::SamplerKind;
use std::path::{Path, PathBuf};
use std::time::SystemTime;

/// The seed of a rendered reference: outside the study's seeds 0..K, so the
/// reference's error is independent of every render's.
pub const REFERENCE_SEED: u64 = 1_000_003;

/// The reference's file name in the output directory.
const REFERENCE_FILE: &str = "reference.exr";

/// Arguments of `lqmc study equal-time`.
#[derive(Args, Debug)]
pub struct EqualTimeArgs {
    #[command(flatten)]
    pub scene: StudySceneArgs,
    /// Comma-separated NAME[:SAMPLER][:splat][[OPTIONS]] entries, e.g.
    /// `path,lqmc,path:sobol,path:splat,lqmc[--class-selection fixed]`
    /// (sampler default halton; `path` is volpath in scenes with media;
    /// `:splat` renders path or volpath with `--splat-film`; options in
    /// brackets, separated by spaces, apply to that entry only, after the
    /// study's integrator options).
    #[arg(long, value_name = "LIST", default_value = "path,lqmc")]
    pub integrators: String,
    /// Seconds per render: the main time budget.
    #[arg(long, value_name = "SECONDS")]
    pub time: f64,
    /// Budgets in seconds for the error-versus-time plot, comma-separated
    /// (default: time/4, time/2, time); --time is always among them.
    #[arg(long, value_name = "LIST")]
    pub budgets: Option<String>,
    /// Renders per integrator and budget, with seeds 0..K.
    #[arg(long, value_name = "K", default_value_t = 3)]
    pub seeds: u64,
    /// The reference image (.exr or .pfm), at the study's resolution.
    #[arg(long, value_name = "REF.exr", conflicts_with = "reference_spp")]
    pub reference: Option<PathBuf>,
    /// Render the reference: the scene's path tracer (volpath with media),
    /// Halton, N samples per pixel, all cores, written to DIR/reference.exr
    /// and reused while it matches.
    #[arg(long, value_name = "N")]
    pub reference_spp: Option<u64>,
    /// The reference's own noise: per pixel and channel the variance of the
    /// reference's mean (the `variance` layer lqmc writes, or
    /// `reference_variance.exr` beside another renderer's reference). Its
    /// mean is subtracted from each render's squared error, so that RMSE and
    /// relative MSE measure the render's error, not the reference's.
    #[arg(long, value_name = "VAR.exr")]
    pub reference_variance: Option<PathBuf>,
    /// The crop of crops.png, X,Y,W,H in pixels (default: a centred square
    /// of side min(width, height)/2).
    #[arg(long, value_name = "X,Y,W,H")]
    pub crop: Option<String>,
    /// The output directory.
    #[arg(short, long, value_name = "DIR", default_value = "study-equal-time")]
    pub output: PathBuf,
    /// No progress lines on stderr.
    #[arg(long)]
    pub quiet: bool,
}

/// Where the reference comes from.
enum ReferenceChoice {
    /// A file the user gave.
    File(PathBuf),
    /// Rendered with this many samples per pixel (or reused).
    Render { samples_per_pixel: u64 },
}

/// The reference image and how it was obtained.
struct Reference {
    image: Image,
    /// The path shown in the tables: relative to DIR when rendered there, a
    /// given file as the user gave it (relative to the current directory
    /// where it lies inside it).
    shown_path: String,
    /// The reference's noise, subtracted from the squared errors.
    noise: Option<ReferenceNoise>,
    /// For a rendered reference: the integrator, spp, and whether an
    /// earlier study's was reused.
    rendered: Option<RenderedReference>,
}

/// A reference's own noise, as the means the measures subtract:
/// E[(a − r)²] = E[(a − μ)²] + Var(r) for a render a independent of the
/// reference r with mean μ, so the render's mean squared error is the
/// measured one less the mean of Var(r) over pixels and channels, and its
/// relative MSE the measured one less the mean of Var(r) / (r² + ε).
#[derive(Clone, Debug)]
struct ReferenceNoise {
    /// The file, as shown in the tables.
    shown_path: String,
    /// The mean over pixels and channels of the variance of the reference.
    mean_variance: f64,
    /// The mean of variance / (reference² + ε), ε the relative MSE's.
    mean_relative_variance: f64,
}

impl ReferenceNoise {
    /// The noise of `reference` from its variance image (pixels where
    /// either is not finite left out, as the comparison leaves them out).
    fn measure(shown_path: String, reference: &Image, variance: &Image) -> Self {
        let (mut sum, mut relative_sum, mut count) = (0.0f64, 0.0f64, 0usize);
        for (value, variance) in reference.pixels().iter().zip(variance.pixels()) {
            if !value.iter().chain(variance).all(|c| c.is_finite()) {
                continue;
            }
            for channel in 0..3 {
                let (value, variance) = (f64::from(value[channel]), f64::from(variance[channel]));
                sum += variance;
                relative_sum += variance / (value * value + RELATIVE_MSE_EPSILON);
                count += 1;
            }
        }
        let count = count.max(1) as f64;
        Self {
            shown_path,
            mean_variance: sum / count,
            mean_relative_variance: relative_sum / count,
        }
    }

    /// RMSE and relative MSE with the reference's noise taken out (never
    /// below zero).
    fn corrected(&self, mut comparison: ImageComparison) -> ImageComparison {
        comparison.rmse = (comparison.rmse * comparison.rmse - self.mean_variance)
            .max(0.0)
            .sqrt();
        comparison.relative_mse = (comparison.relative_mse - self.mean_relative_variance).max(0.0);
        comparison
    }
}

struct RenderedReference {
    integrator: &'static str,
    samples_per_pixel: u64,
    reused: bool,
}

/// One render of the study, as it ran.
struct RenderRecord {
    entry: usize,
    budget: usize,
    seed: u64,
    /// The image, relative to the output directory.
    image: String,
    traced_samples_per_pixel: f64,
    whole_passes: u64,
    seconds: f64,
    /// The render's peak resident memory, where the system tells.
    peak_resident_bytes: Option<u64>,
}

/// One seed's measures, from its image as written.
struct SeedMeasures<'a> {
    record: &'a RenderRecord,
    comparison: ImageComparison,
}

/// The measures of one integrator at one budget over the seeds.
struct Cell<'a> {
    entry: usize,
    budget: usize,
    seeds: Vec<SeedMeasures<'a>>,
    samples_per_pixel: Spread,
    rmse: Spread,
    relative_mse: Spread,
    mean_absolute_deviation: Spread,
    mean_bias: f64,
    flicker: f64,
    /// Median RMSE over that of the first integrator at the same budget.
    rmse_ratio_to_first: f64,
    /// The renders' peak resident memory in MB (10⁶ bytes), where every
    /// render measured it.
    peak_memory_megabytes: Option<Spread>,
}

/// What the report says about how the study ran.
struct StudyConditions {
    scene: String,
    resolution: (usize, usize),
    threads: usize,
    seeds: u64,
    time: f64,
    budgets: Vec<f64>,
    entries: Vec<IntegratorEntry>,
    crop: CropRectangle,
    started: String,
    finished: String,
    load_at_start: String,
    load_at_end: String,
    command: String,
}

/// The study's budgets: `--budgets` (default time/4, time/2, time) with
/// `time` added, ascending, without repeats.
fn study_budgets(time: f64, list: Option<&str>) -> Result<Vec<f64>, CliError> {
    let mut budgets = match list {
        None => vec![time / 4.0, time / 2.0],
        Some(list) => list
            .split(',')
            .map(str::trim)
            .filter(|item| !item.is_empty())
            .map(|item| {
                let seconds: f64 = item.parse().map_err(|_| {
                    usage(format!("--budgets: `{item}` is not a number of seconds"))
                })?;
                parse_time_budget("--budgets", seconds).map(|_| seconds)
            })
            .collect::<Result<Vec<_>, CliError>>()?,
    };
    budgets.push(time);
    budgets.sort_by(f64::total_cmp);
    budgets.dedup();
    Ok(budgets)
}

/// The file name of a render's image (relative to the output directory).
fn image_name(entry: &IntegratorEntry, budget: f64, seed: u64) -> String {
    format!("images/{}-b{budget}-seed{seed}.exr", entry.file_stem())
}

/// Creates `directory` and its `images` folder and checks that files can
/// be written there, before anything is rendered.
pub(super) fn prepare_output_directory(directory: &Path) -> Result<(), CliError> {
    let images = directory.join("images");
    std::fs::create_dir_all(&images).map_err(|error| {
        CliError::Failure(format!("cannot create {}: {error}", images.display()))
    })?;
    let probe = directory.join(".lqmc-write-test");
    std::fs::write(&probe, b"").map_err(|error| {
        CliError::Failure(format!(
            "cannot write into {}: {error}",
            directory.display()
        ))
    })?;
    let _ = std::fs::remove_file(&probe);
    Ok(())
}

/// A failure to write `path`.
pub(super) fn write_failure(path: &Path, error: impl std::fmt::Display) -> CliError {
    CliError::Failure(format!("cannot write {}: {error}", path.display()))
}

/// Renders the reference into DIR/reference.exr, or reuses the one there
/// if it was rendered with the same scene, parameters, resolution,
/// integrator, depths and samples per pixel.
fn rendered_reference(
    context: &RenderContext<'_>,
    args: &EqualTimeArgs,
    samples_per_pixel: u64,
) -> Result<Reference, CliError> {
    let path = args.output.join(REFERENCE_FILE);
    let integrator = default_path_tracer(context.scene);
    let mut request = context.request(integrator.into(), SamplerKind::Halton, REFERENCE_SEED, 0);
    request.samples_per_pixel = Some(samples_per_pixel);
    let settings = request.settings(context.scene);
    let [width, height] = context.scene.camera.resolution();
    let expected: Vec<(&str, String)> = vec![
        ("scene", args.scene.scene.clone()),
        ("integrator", integrator.name().to_string()),
        ("sampler", SamplerKind::Halton.name().to_string()),
        ("spp", samples_per_pixel.to_string()),
        ("maxDepth", settings.max_depth.to_string()),
        ("rrDepth", settings.russian_roulette_depth.to_string()),
        ("sceneParameters", context.definitions.clone()),
    ];
    if path.exists() {
        match read_exr(&path) {
            Ok(contents) => {
                let mut differences: Vec<String> = expected
                    .iter()
                    .filter_map(|(key, value)| {
                        let found = contents.metadata.get(*key).cloned().unwrap_or_default();
                        (found != *value).then(|| format!("{key} `{found}`, not `{value}`"))
                    })
                    .collect();
                let size = (contents.image.width(), contents.image.height());
                if size != (width as usize, height as usize) {
                    differences.push(format!("size {}x{}, not {width}x{height}", size.0, size.1));
                }
                if differences.is_empty() {
                    if !args.quiet {
                        eprintln!(
                            "reusing the reference {} ({}, Halton, {samples_per_pixel} spp)",
                            path.display(),
                            integrator.name()
                        );
                    }
                    return Ok(Reference {
                        image: contents.image,
                        shown_path: REFERENCE_FILE.into(),
                        noise: None,
                        rendered: Some(RenderedReference {
                            integrator: integrator.name(),
                            samples_per_pixel,
                            reused: true,
                        }),
                    });
                }
                if !args.quiet {
                    eprintln!(
                        "{} does not match ({}): rendering it again",
                        path.display(),
                        differences.join("; ")
                    );
                }
            }
            Err(error) => {
                if !args.quiet {
                    eprintln!(
                        "{} is unreadable ({error}): rendering it again",
                        path.display()
                    );
                }
            }
        }
    }
    if !args.quiet {
        eprintln!(
            "rendering the reference: {}, Halton, {samples_per_pixel} spp, seed {REFERENCE_SEED}, all cores ...",
            integrator.name()
        );
    }
    let written = context.render_to(&settings, &path, &[])?;
    Ok(Reference {
        image: written.image,
        shown_path: REFERENCE_FILE.into(),
        noise: None,
        rendered: Some(RenderedReference {
            integrator: integrator.name(),
            samples_per_pixel,
            reused: false,
        }),
    })
}

/// Runs `lqmc study equal-time`; `matches` are its arguments as clap
/// parsed them.
pub fn run(args: &EqualTimeArgs, matches: &ArgMatches) -> Result<(), CliError> {
    args.scene.validate()?;
    if args.seeds == 0 {
        return Err(usage("--seeds must be at least 1"));
    }
    parse_time_budget("--time", args.time)?;
    let budgets = study_budgets(args.time, args.budgets.as_deref())?;
    let mut entries = parse_integrator_list(&args.integrators)?;
    let reference_choice = match (&args.reference, args.reference_spp) {
        (Some(path), _) => ReferenceChoice::File(path.clone()),
        (None, Some(0)) => return Err(usage("--reference-spp must be at least 1")),
        (None, Some(samples_per_pixel)) => ReferenceChoice::Render { samples_per_pixel },
        (None, None) => {
            return Err(usage(
                "a reference is needed: pass --reference REF.exr (an image of the scene at the study's resolution) or --reference-spp N (rendered with the scene's path tracer)",
            ));
        }
    };
    let description = load_scene_description(
        &args.scene.scene,
        &args.scene.define,
        args.scene.resolution,
        args.quiet,
    )?;
    let [width, height] = description.camera.resolution;
    let (width, height) = (width as usize, height as usize);
    let crop = match &args.crop {
        Some(text) => CropRectangle::parse(text, width, height)?,
        None => CropRectangle::centred_square(width, height),
    };
    let given_reference = match &reference_choice {
        ReferenceChoice::File(path) => {
            let image = read_reference(path, width, height)?;
            Some(image)
        }
        ReferenceChoice::Render { .. } => None,
    };
    let noise = match (&args.reference_variance, &given_reference) {
        (Some(path), Some(image)) => {
            let variance = read_image(path)
                .map_err(|error| usage(format!("--reference-variance: {error}")))?;
            if (variance.width(), variance.height()) != (width, height) {
                return Err(usage(format!(
                    "--reference-variance {} is {}x{}, but the reference is {width}x{height}",
                    path.display(),
                    variance.width(),
                    variance.height()
                )));
            }
            Some(ReferenceNoise::measure(shown_path(path), image, &variance))
        }
        (Some(_), None) => {
            return Err(usage(
                "--reference-variance is the variance of a reference given with --reference REF.exr",
            ));
        }
        (None, _) => None,
    };
    let scene = build_scene(&args.scene.scene, &description)?;
    for entry in &mut entries {
        entry.resolve_path_tracer(scene.has_media());
    }
    check_distinct(&entries)?;
    let kinds: Vec<IntegratorKind> = entries.iter().map(|entry| entry.integrator).collect();
    check_study_options(matches, &kinds)?;
    let settings_of_entries = entries
        .iter()
        .map(|entry| {
            if entry.options.is_empty() {
                args.scene.integrators.settings(entry.integrator)
            } else {
                let options = entry_integrator_args(matches, entry)?;
                super::validate_integrator_args(&options)?;
                options.settings(entry.integrator)
            }
        })
        .collect::<Result<Vec<_>, CliError>>()?;
    prepare_output_directory(&args.output)?;

    let stop = stop_on_interrupt();
    let context = RenderContext {
        scene_args: &args.scene,
        scene: &scene,
        stop: &stop,
        definitions: definitions_text(&args.scene.define),
    };
    let started = utc_timestamp(SystemTime::now());
    let load_at_start = load_average();
    let reference = match (reference_choice, given_reference) {
        (ReferenceChoice::File(path), Some(image)) => Reference {
            image,
            shown_path: shown_path(&path),
            noise,
            rendered: None,
        },
        (ReferenceChoice::Render { samples_per_pixel }, _) => {
            rendered_reference(&context, args, samples_per_pixel)?
        }
        (ReferenceChoice::File(_), None) => unreachable!("a given reference was read above"),
    };

    // Seeds outermost, integrators innermost: a change of load during the
    // study hits every integrator at every budget alike.
    let total = args.seeds as usize * budgets.len() * entries.len();
    let mut records = Vec::with_capacity(total);
    for seed in 0..args.seeds {
        for (budget_index, &budget) in budgets.iter().enumerate() {
            for (entry_index, entry) in entries.iter().enumerate() {
                let mut request = context.request(
                    settings_of_entries[entry_index].clone(),
                    entry.sampler,
                    seed,
                    args.scene.threads,
                );
                request.time_budget = Some(parse_time_budget("--budgets", budget)?);
                request.splat_film = entry.splat_film;
                let settings = request.settings(&scene);
                let name = image_name(entry, budget, seed);
                let WrittenRender {
                    image,
                    traced_samples_per_pixel: traced,
                    whole_passes,
                    seconds,
                    peak_resident_bytes,
                    ..
                } = context.render_to(
                    &settings,
                    &args.output.join(&name),
                    &[("timeBudgetSeconds", format!("{budget}"))],
                )?;
                if !args.quiet {
                    let rmse = compare_images(&image, &reference.image, None)
                        .map(|comparison| format_significant(comparison.rmse, 4))
                        .unwrap_or_else(|_| "—".into());
                    eprintln!(
                        "[{}/{total}] seed {seed}, {budget} s: {} {traced:.1} spp in {seconds:.3} s, RMSE {rmse}",
                        records.len() + 1,
                        entry.label(),
                    );
                }
                records.push(RenderRecord {
                    entry: entry_index,
                    budget: budget_index,
                    seed,
                    image: name,
                    traced_samples_per_pixel: traced,
                    whole_passes,
                    seconds,
                    peak_resident_bytes,
                });
            }
        }
    }
    let finished = utc_timestamp(SystemTime::now());
    let load_at_end = load_average();

    let cells = measure_cells(&records, &entries, &budgets, &reference, &args.output)?;
    let conditions = StudyConditions {
        scene: args.scene.scene.clone(),
        resolution: (width, height),
        threads: args.scene.effective_threads(),
        seeds: args.seeds,
        time: args.time,
        budgets,
        entries,
        crop,
        started,
        finished,
        load_at_start,
        load_at_end,
        command: command_line(),
    };
    let markdown = markdown_table(&conditions, &reference, &cells);
    let (table_md, table_json) = write_tables(
        &args.output,
        &markdown,
        &json_table(&conditions, &reference, &cells),
    )?;
    let svg = args.output.join("error-vs-time.svg");
    let png = args.output.join("error-vs-time.png");
    write_error_plot(
        &svg,
        &png,
        &format!(
            "{} {width}x{height}, {} threads, {} seeds",
            conditions.scene, conditions.threads, conditions.seeds
        ),
        "seconds per render",
        "RMSE (median over seeds; bars: min to max)",
        &error_curves(&conditions, &cells),
    )?;
    let crops = args.output.join("crops.png");
    write_crops(&crops, &conditions, &reference, &records, &args.output)?;

    print_report(
        &markdown,
        &[&table_md, &table_json, &svg, &png, &crops],
        &args.output.join("images"),
    );
    Ok(())
}

/// The measures of every integrator at every budget, from the images as
/// written (budget-major, integrators in the order given).
fn measure_cells<'a>(
    records: &'a [RenderRecord],
    entries: &[IntegratorEntry],
    budgets: &[f64],
    reference: &Reference,
    directory: &Path,
) -> Result<Vec<Cell<'a>>, CliError> {
    let mut cells: Vec<Cell<'a>> = Vec::new();
    for budget in 0..budgets.len() {
        for entry in 0..entries.len() {
            let cell_records: Vec<&RenderRecord> = records
                .iter()
                .filter(|record| record.entry == entry && record.budget == budget)
                .collect();
            let images = cell_records
                .iter()
                .map(|record| read_study_image(directory, &record.image))
                .collect::<Result<Vec<_>, CliError>>()?;
            let seeds = cell_records
                .iter()
                .zip(&images)
                .map(|(record, image)| {
                    let comparison = compare_images(image, &reference.image, None)
                        .map_err(|error| CliError::Failure(error.to_string()))?;
                    let comparison = match &reference.noise {
                        Some(noise) => noise.corrected(comparison),
                        None => comparison,
                    };
                    Ok(SeedMeasures { record, comparison })
                })
                .collect::<Result<Vec<_>, CliError>>()?;
            let values = |measure: fn(&SeedMeasures<'_>) -> f64| {
                spread(&seeds.iter().map(measure).collect::<Vec<_>>())
            };
            let rmse = values(|seed| seed.comparison.rmse);
            let first_rmse = if entry == 0 {
                rmse.median
            } else {
                cells[cells.len() - entry].rmse.median
            };
            cells.push(Cell {
                entry,
                budget,
                samples_per_pixel: values(|seed| seed.record.traced_samples_per_pixel),
                rmse,
                relative_mse: values(|seed| seed.comparison.relative_mse),
                mean_absolute_deviation: values(|seed| seed.comparison.mean_absolute_deviation),
                mean_bias: mean_bias(&images, &reference.image),
                flicker: flicker(&images, &reference.image),
                rmse_ratio_to_first: rmse.median / first_rmse,
                peak_memory_megabytes: cell_records
                    .iter()
                    .map(|record| record.peak_resident_bytes.map(|bytes| bytes as f64 / 1e6))
                    .collect::<Option<Vec<f64>>>()
                    .map(|megabytes| spread(&megabytes)),
                seeds,
            });
        }
    }
    Ok(cells)
}

/// A sentence on the reference.
fn reference_text(reference: &Reference) -> String {
    match &reference.rendered {
        Some(rendered) => format!(
            "{}, Halton, {} spp, seed {REFERENCE_SEED}, all cores ({} {})",
            rendered.integrator,
            rendered.samples_per_pixel,
            if rendered.reused {
                "reused from an earlier study:"
            } else {
                "rendered for this study:"
            },
            reference.shown_path
        ),
        None => match &reference.noise {
            Some(noise) => format!(
                "the image {}, whose own noise (the mean of its variance {}, {} over pixels and channels; \
                 relative {}) is subtracted from each render's squared error and relative MSE (not from MAD)",
                reference.shown_path,
                noise.shown_path,
                format_significant(noise.mean_variance, 4),
                format_significant(noise.mean_relative_variance, 4)
            ),
            None => format!("the image {}", reference.shown_path),
        },
    }
}

/// The budgets as `0.5, 1, 2 s`.
fn budgets_text(budgets: &[f64]) -> String {
    let list: Vec<String> = budgets.iter().map(|budget| format!("{budget}")).collect();
    format!("{} s", list.join(", "))
}

/// The markdown report: conditions, the table, the measures' definitions
/// and the command line.
fn markdown_table(
    conditions: &StudyConditions,
    reference: &Reference,
    cells: &[Cell<'_>],
) -> String {
    let (width, height) = conditions.resolution;
    let labels: Vec<String> = conditions
        .entries
        .iter()
        .map(IntegratorEntry::label)
        .collect();
    let renamed: Vec<String> = conditions
        .entries
        .iter()
        .filter(|entry| entry.requested != entry.label())
        .map(|entry| format!("`{}` ran as {}", entry.requested, entry.label()))
        .collect();
    let renamed = if renamed.is_empty() {
        String::new()
    } else {
        format!(" ({})", renamed.join(", "))
    };
    let crop = conditions.crop;
    let mut text = format!(
        "# Equal-time study: {scene}\n\n\
         Scene {scene} at {width}x{height}, {threads} thread(s) per render; integrators {integrators}{renamed} \
         (sampler Halton unless named after a colon); seeds 0 to {last_seed} ({seeds} renders per integrator \
         and budget, each sampler randomized by its seed); time budgets {budgets} per render (main budget {time} s), \
         renders interleaved (seed, then budget, then integrator innermost). Reference: {reference}. \
         Measured {started} to {finished}; load average (1/5/15 min) {load_start} at the start, {load_end} at \
         the end. Each entry is the median over the seeds with [min, max]; spp is the median of the samples traced \
         per pixel.\n\n",
        scene = conditions.scene,
        threads = conditions.threads,
        integrators = labels.join(", "),
        last_seed = conditions.seeds - 1,
        seeds = conditions.seeds,
        budgets = budgets_text(&conditions.budgets),
        time = conditions.time,
        reference = reference_text(reference),
        started = conditions.started,
        finished = conditions.finished,
        load_start = conditions.load_at_start,
        load_end = conditions.load_at_end,
    );
    text += &format!(
        "| budget (s) | integrator | spp | RMSE | relative MSE | MAD | mean bias | flicker | RMSE / {}'s | peak memory (MB) |\n",
        labels[0]
    );
    text += "|---|---|---|---|---|---|---|---|---|---|\n";
    for cell in cells {
        text += &format!(
            "| {} | {} | {:.1} | {} | {} | {} | {} | {} | {} | {} |\n",
            conditions.budgets[cell.budget],
            labels[cell.entry],
            cell.samples_per_pixel.median,
            spread_text(&cell.rmse),
            spread_text(&cell.relative_mse),
            spread_text(&cell.mean_absolute_deviation),
            format_percentage(cell.mean_bias, 3),
            format_significant(cell.flicker, 4),
            format_significant(cell.rmse_ratio_to_first, 4),
            cell.peak_memory_megabytes
                .as_ref()
                .map_or("—".to_string(), |megabytes| format!(
                    "{:.1}",
                    megabytes.median
                )),
        );
    }
    text += &format!(
        "\nMeasures, against the reference over all pixels and the three channels (pixels with a NaN or \
         infinite value left out): RMSE; relative MSE, the mean of (image − reference)² / (reference² + {RELATIVE_MSE_EPSILON}); \
         MAD, the mean absolute deviation |image − reference|; mean bias, (m − r) / r with m the mean over pixels and \
         channels of the seeds' average image and r the reference's; flicker, the mean over pixels and channels of the \
         standard deviation of a pixel across the seeds (denominator K − 1) over √(reference² + {RELATIVE_MSE_EPSILON}) \
         (— for one seed). RMSE / {first}'s is the ratio of the median RMSEs at the same budget. Peak memory: the \
         median over the seeds of each render's peak resident memory (Linux's VmHWM, reset at the render's start).\n\n\
         Files: images/INTEGRATOR-bBUDGET-seedK.exr, table.json (every number, per seed too), error-vs-time.svg and \
         .png (median RMSE against the budget, bars from min to max), crops.png (the crop {x},{y},{w},{h} of the \
         reference, then of each integrator's seed-0 render at {largest} s, enlarged {scale}×).\n\n\
         Command:\n\n```sh\n{command}\n```\n",
        first = labels[0],
        x = crop.x,
        y = crop.y,
        w = crop.width,
        h = crop.height,
        largest = conditions.budgets[conditions.budgets.len() - 1],
        scale = crop.enlargement(),
        command = conditions.command,
    );
    text
}

/// The JSON report: the conditions and every number, per seed too.
fn json_table(conditions: &StudyConditions, reference: &Reference, cells: &[Cell<'_>]) -> Json {
    let (width, height) = conditions.resolution;
    let reference_json = match &reference.rendered {
        Some(rendered) => Json::object(vec![
            ("image", Json::String(reference.shown_path.clone())),
            (
                "source",
                Json::String(
                    if rendered.reused {
                        "reused"
                    } else {
                        "rendered"
                    }
                    .into(),
                ),
            ),
            ("integrator", Json::String(rendered.integrator.into())),
            ("sampler", Json::String(SamplerKind::Halton.name().into())),
            ("spp", Json::Integer(rendered.samples_per_pixel)),
            ("seed", Json::Integer(REFERENCE_SEED)),
        ]),
        None => {
            let mut fields = vec![
                ("image", Json::String(reference.shown_path.clone())),
                ("source", Json::String("file".into())),
            ];
            if let Some(noise) = &reference.noise {
                fields.push(("variance", Json::String(noise.shown_path.clone())));
                fields.push(("mean_variance", Json::Number(noise.mean_variance)));
                fields.push((
                    "mean_relative_variance",
                    Json::Number(noise.mean_relative_variance),
                ));
            }
            Json::object(fields)
        }
    };
    let integrators = conditions
        .entries
        .iter()
        .map(|entry| {
            Json::object(vec![
                ("label", Json::String(entry.label())),
                ("requested", Json::String(entry.requested.clone())),
                ("integrator", Json::String(entry.integrator.name().into())),
                ("sampler", Json::String(entry.sampler.name().into())),
                ("splat_film", Json::Bool(entry.splat_film)),
            ])
        })
        .collect();
    let rows = cells
        .iter()
        .map(|cell| {
            let entry = &conditions.entries[cell.entry];
            let seeds = cell
                .seeds
                .iter()
                .map(|seed| {
                    let record = seed.record;
                    Json::object(vec![
                        ("seed", Json::Integer(record.seed)),
                        ("image", Json::String(record.image.clone())),
                        ("spp", Json::Number(record.traced_samples_per_pixel)),
                        ("whole_passes", Json::Integer(record.whole_passes)),
                        ("seconds", Json::Number(record.seconds)),
                        ("rmse", Json::Number(seed.comparison.rmse)),
                        ("relative_mse", Json::Number(seed.comparison.relative_mse)),
                        ("mad", Json::Number(seed.comparison.mean_absolute_deviation)),
                        (
                            "relative_mean_difference",
                            Json::Number(seed.comparison.relative_mean_difference),
                        ),
                        (
                            "non_finite_pixels",
                            Json::Integer(seed.comparison.non_finite_pixels as u64),
                        ),
                        (
                            "peak_resident_bytes",
                            Json::Integer(record.peak_resident_bytes.unwrap_or(0)),
                        ),
                    ])
                })
                .collect();
            Json::object(vec![
                ("integrator", Json::String(entry.label())),
                (
                    "budget_seconds",
                    Json::Number(conditions.budgets[cell.budget]),
                ),
                ("seeds", Json::Array(seeds)),
                ("spp", spread_json(&cell.samples_per_pixel)),
                ("rmse", spread_json(&cell.rmse)),
                ("relative_mse", spread_json(&cell.relative_mse)),
                ("mad", spread_json(&cell.mean_absolute_deviation)),
                ("mean_bias", Json::Number(cell.mean_bias)),
                ("flicker", Json::Number(cell.flicker)),
                (
                    "rmse_ratio_to_first",
                    Json::Number(cell.rmse_ratio_to_first),
                ),
                (
                    "peak_memory_mb",
                    cell.peak_memory_megabytes
                        .as_ref()
                        .map_or(Json::Integer(0), spread_json),
                ),
            ])
        })
        .collect();
    let crop = conditions.crop;
    Json::object(vec![
        ("study", Json::String("equal-time".into())),
        ("scene", Json::String(conditions.scene.clone())),
        ("resolution", Json::integers(&[width as u64, height as u64])),
        ("threads", Json::Integer(conditions.threads as u64)),
        ("seeds", Json::Integer(conditions.seeds)),
        ("time_seconds", Json::Number(conditions.time)),
        ("budgets_seconds", Json::numbers(&conditions.budgets)),
        ("integrators", Json::Array(integrators)),
        ("reference", reference_json),
        ("relative_mse_epsilon", Json::Number(RELATIVE_MSE_EPSILON)),
        ("crop", crop.json()),
        ("started", Json::String(conditions.started.clone())),
        ("finished", Json::String(conditions.finished.clone())),
        (
            "load_average_start",
            Json::String(conditions.load_at_start.clone()),
        ),
        (
            "load_average_end",
            Json::String(conditions.load_at_end.clone()),
        ),
        ("rows", Json::Array(rows)),
        ("command", Json::String(conditions.command.clone())),
    ])
}

/// The plot's lines: each integrator's RMSE spread at each budget.
fn error_curves(conditions: &StudyConditions, cells: &[Cell<'_>]) -> Vec<ErrorCurve> {
    conditions
        .entries
        .iter()
        .enumerate()
        .map(|(entry, integrator)| ErrorCurve {
            label: integrator.label(),
            points: cells
                .iter()
                .filter(|cell| cell.entry == entry)
                .map(|cell| ErrorPoint {
                    x: conditions.budgets[cell.budget],
                    median: cell.rmse.median,
                    min: cell.rmse.min,
                    max: cell.rmse.max,
                })
                .collect(),
        })
        .collect()
}

/// Writes the strip of crops: the reference, then each integrator's render
/// of seed 0 at the largest budget, tone-mapped as `lqmc render`'s PNG.
fn write_crops(
    path: &Path,
    conditions: &StudyConditions,
    reference: &Reference,
    records: &[RenderRecord],
    directory: &Path,
) -> Result<(), CliError> {
    let largest = conditions.budgets.len() - 1;
    let renders = (0..conditions.entries.len())
        .map(|entry| {
            let record = records
                .iter()
                .find(|record| {
                    record.entry == entry && record.budget == largest && record.seed == 0
                })
                .expect("every integrator rendered seed 0 at every budget");
            read_study_image(directory, &record.image)
        })
        .collect::<Result<Vec<_>, CliError>>()?;
    let panels: Vec<(String, &Image)> =
        std::iter::once(("reference".to_string(), &reference.image))
            .chain(
                conditions
                    .entries
                    .iter()
                    .map(IntegratorEntry::label)
                    .zip(&renders),
            )
            .collect();
    write_crop_strip(
        path,
        &panels,
        conditions.crop,
        &[("budgetSeconds", format!("{}", conditions.budgets[largest]))],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn budgets_default_to_quarter_half_and_whole_time() {
        assert_eq!(study_budgets(2.0, None).unwrap(), [0.5, 1.0, 2.0]);
        assert_eq!(study_budgets(0.2, Some("0.2, 0.1")).unwrap(), [0.1, 0.2]);
        assert_eq!(study_budgets(1.0, Some("4")).unwrap(), [1.0, 4.0]);
        assert!(study_budgets(1.0, Some("0")).is_err());
        assert!(study_budgets(1.0, Some("-1")).is_err());
        assert!(study_budgets(1.0, Some("x")).is_err());
    }

    #[test]
    fn image_names_carry_integrator_budget_and_seed() {
        let entries = parse_integrator_list("path:sobol").unwrap();
        assert_eq!(
            image_name(&entries[0], 0.25, 3),
            "images/path-sobol-b0.25-seed3.exr"
        );
        assert_eq!(
            image_name(&entries[0], 2.0, 0),
            "images/path-sobol-b2-seed0.exr"
        );
    }
}
