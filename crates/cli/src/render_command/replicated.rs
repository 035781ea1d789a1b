//! A render of independent replications (`--replications R`,
//! `--replication I/R`, `--target-error E`): the options checked against
//! each other, the replications rendered by `render::replication`, their
//! mean written with the variance of the mean and the error estimate. The
//! metadata and the error line are [`crate::replications`]'s, which `lqmc
//! merge` shares.

use super::output::{write_failure, write_png_beside};
use super::report::render_failure;
use super::{Job, RenderArgs, render_metadata};
use crate::error::{CliError, usage};
use crate::replications::{
    ReplicationOptions, ReplicationRequest, describe_estimate, fingerprint_hash, format_indices,
    insert_estimate, keys, replication_request, settings_fingerprint,
};
use render::image::{ImageFormat, VARIANCE_LAYER, write_exr, write_image};
use render::integrators::{FilmObserver, IntegratorKind};
use render::replication::{
    ErrorMeasure, ErrorTarget, ReplicationAccumulator, ReplicationPlan, ReplicationProgress,
    ReplicationRender, render_replications, replication_seed,
};
use render::sampler::{Randomization, SamplerKind};
use render::scene::Scene;
use std::sync::atomic::{AtomicBool, Ordering};

/// The pattern size and samples per pixel that `--pattern-size`,
/// `--replications` and `--spp` ask for together: spp = r × m, any two of
/// them fixing the third (checked for consistency when all three are given).
pub fn pattern_plan(args: &RenderArgs) -> Result<(Option<u64>, Option<u64>), CliError> {
    if args.pattern_size == Some(0) {
        return Err(usage("--pattern-size must be at least 1"));
    }
    if args.replications == Some(0) {
        return Err(usage("--replications must be at least 1"));
    }
    match (args.pattern_size, args.replications, args.spp) {
        (pattern, None, spp) => Ok((pattern, spp)),
        (Some(pattern), Some(replications), spp) => {
            let product = pattern
                .checked_mul(replications)
                .ok_or_else(|| usage("--pattern-size × --replications is too large"))?;
            if spp.is_some_and(|spp| spp != product) {
                return Err(usage(format!(
                    "--spp {} disagrees with --pattern-size {pattern} × --replications \
                     {replications} = {product}",
                    spp.unwrap_or_default()
                )));
            }
            Ok((Some(pattern), Some(product)))
        }
        // Without a pattern size, replications are whole renders.
        (None, Some(_), spp) => Ok((None, spp)),
    }
}

/// The independent replications the options ask for (`None`: one render),
/// checked against the other options.
pub fn requested(
    args: &RenderArgs,
    scene: &Scene,
    integrator: IntegratorKind,
    randomization: Randomization,
) -> Result<Option<ReplicationRequest>, CliError> {
    if args.pattern_size.is_some() {
        if args.replication.is_some() || args.target_error.is_some() {
            return Err(usage(
                "--pattern-size replicates inside one render (Kollig & Keller's passes); --replication and --target-error split the render into whole renders: use one or the other",
            ));
        }
        return Ok(None);
    }
    let request = replication_request(
        &ReplicationOptions {
            replications: args.replications,
            replication: args.replication,
            target_error: args.target_error,
            samples_per_pixel: args.spp,
            timed: args.time.is_some(),
        },
        scene.samples_per_pixel.unwrap_or(16),
    )?;
    if request.is_none() {
        for (given, option) in [
            (args.target_region.is_some(), "--target-region"),
            (args.max_replications.is_some(), "--max-replications"),
            (args.error_measure.is_some(), "--error-measure"),
        ] {
            if given {
                return Err(usage(format!(
                    "{option} is for renders of replications (--replications, --target-error)"
                )));
            }
        }
    }
    if args.max_replications == Some(0) {
        return Err(usage("--max-replications must be at least 1"));
    }
    if request.is_some()
        && randomization == Randomization::None
        && args.sampler != SamplerKind::Independent
        && !integrator.runs_markov_chains()
    {
        return Err(usage(
            "replications need --randomize seeded: with --randomize none every replication has the same QMC points",
        ));
    }
    if let (Some(region), Some(_)) = (args.target_region, &request) {
        let [width, height] = scene.camera.resolution();
        let [x, y, region_width, region_height] = region;
        if x + region_width > width as usize || y + region_height > height as usize {
            return Err(usage(format!(
                "--target-region {x},{y},{region_width},{region_height} reaches outside the {width}x{height} image"
            )));
        }
    }
    Ok(request)
}

/// Refuses the outputs a render of replications cannot write: images of
/// one render, and a part in another format than EXR.
pub fn check_outputs(
    args: &RenderArgs,
    replications: Option<&ReplicationRequest>,
    format: ImageFormat,
) -> Result<(), CliError> {
    let Some(request) = replications else {
        return Ok(());
    };
    if args.integrators.lqmc.density.is_some() || args.integrators.bdpt.strategy_images.is_some() {
        return Err(usage(
            "--density and --strategy-images are images of one render: not with replications",
        ));
    }
    if request.is_part() && format != ImageFormat::OpenExr {
        return Err(usage(format!(
            "a replication part is written as EXR (its metadata ties it to its set for lqmc merge), not {}",
            args.output.display()
        )));
    }
    Ok(())
}

/// Renders the independent replications `request` asks for and writes
/// their mean, the variance of the mean and the error estimate.
pub fn render(job: &Job, request: &ReplicationRequest) -> Result<(), CliError> {
    let measure = job.args.error_measure.unwrap_or_default();
    let rendered = render_with_progress(job, request, measure)?;
    let written = write(job, request, &rendered)?;
    report(job, request, measure, &rendered, &written);
    Ok(())
}

/// Renders the replications, showing their progress (and the first one,
/// then the mean of the finished, in the live view).
fn render_with_progress(
    job: &Job,
    request: &ReplicationRequest,
    measure: ErrorMeasure,
) -> Result<ReplicationRender, CliError> {
    let settings = &job.settings;
    let plan = ReplicationPlan {
        first: request.first,
        count: request.count,
        region: job.args.target_region,
        target: request.target_error.map(|relative_error| ErrorTarget {
            relative_error,
            measure,
            max_replications: job.args.max_replications.unwrap_or(1000),
        }),
        time_budget: settings.time_budget,
    };
    let bar = job.console.progress_bar();
    let started = std::time::Instant::now();
    let timed = settings.time_budget.is_some()
        && (request.samples_per_replication.is_none() || plan.target.is_some());
    let progress = |state: ReplicationProgress| {
        let fraction = match settings.time_budget {
            Some(budget) if timed => started.elapsed().as_secs_f64() / budget.as_secs_f64(),
            _ => {
                (state.finished as f64
                    + state.samples_done as f64 / state.samples_total.max(1) as f64)
                    / state.planned.max(1) as f64
            }
        };
        bar.set_position((fraction.min(1.0) * 100.0) as u64);
        let error = match state.estimate {
            Some(estimate) => format!(
                ", error ({}) {:.3} %",
                measure.name(),
                100.0 * estimate.relative(measure)
            ),
            None => String::new(),
        };
        let target = match request.target_error {
            Some(target) => format!(" (target {:.3} %)", 100.0 * target),
            None => String::new(),
        };
        bar.set_message(format!(
            "replication {} of {}{error}{target}",
            state.finished + 1,
            state.planned
        ));
    };
    let live_view = job.live_view.as_ref();
    let first_finished = AtomicBool::new(false);
    let observe = |film: &render::film::Film, splat_scale: f64| {
        if let (Some(view), false) = (live_view, first_finished.load(Ordering::Relaxed)) {
            view.show_film(film, splat_scale);
        }
    };
    let observer: Option<FilmObserver<'_>> = live_view.map(|_| &observe as _);
    let mut show_mean = |accumulator: &ReplicationAccumulator| {
        first_finished.store(true, Ordering::Relaxed);
        if let Some(view) = live_view {
            view.show(
                &accumulator.mean_image(),
                Some(&accumulator.variance_image()),
            );
        }
    };
    let rendered = render_replications(
        &job.scene,
        settings,
        &plan,
        &job.stop,
        &progress,
        observer,
        &mut show_mean,
    )
    .map_err(render_failure)?;
    bar.finish_and_clear();
    Ok(rendered)
}

/// Writes the replications' mean with its variance (the spread of several,
/// a single one's own estimate) and the metadata that ties a part to its
/// set; returns what it wrote.
fn write(
    job: &Job,
    request: &ReplicationRequest,
    rendered: &ReplicationRender,
) -> Result<Vec<String>, CliError> {
    let args = job.args;
    let accumulator = &rendered.accumulator;
    let [width, height] = job.scene.camera.resolution();
    let indices = accumulator.indices();
    let mut metadata = render_metadata(job.scene_name, &job.settings, &rendered.statistics);
    metadata.insert(
        keys::SET.into(),
        request
            .set_size
            .map_or_else(|| "open".to_string(), |size| size.to_string()),
    );
    metadata.insert(keys::INDICES.into(), format_indices(&indices));
    metadata.insert(
        keys::SAMPLES_PER_REPLICATION.into(),
        request
            .samples_per_replication
            .map_or_else(|| "time".to_string(), |spp| spp.to_string()),
    );
    if let [index] = indices.as_slice() {
        metadata.insert(
            keys::REPLICATION_SEED.into(),
            replication_seed(job.settings.seed, *index).to_string(),
        );
    }
    let fingerprint =
        settings_fingerprint(job.scene_name, &args.define, [width, height], &job.settings);
    metadata.insert(keys::SETTINGS_HASH.into(), fingerprint_hash(&fingerprint));
    metadata.insert(keys::SETTINGS.into(), fingerprint);
    let region = args
        .target_region
        .unwrap_or([0, 0, width as usize, height as usize]);
    insert_estimate(&mut metadata, &accumulator.estimate(), region);
    let image = accumulator.mean_image();
    let variance = if accumulator.count() >= 2 {
        accumulator.variance_image()
    } else {
        rendered.last.variance_image()
    };
    match job.format {
        ImageFormat::OpenExr => write_exr(
            &args.output,
            &image,
            &[(VARIANCE_LAYER, &variance)],
            &metadata,
        ),
        _ => write_image(&args.output, &image, &metadata),
    }
    .map_err(write_failure)?;
    let mut written = vec![args.output.display().to_string()];
    written.extend(write_png_beside(
        &args.output,
        job.format,
        &image,
        args.exposure,
        &metadata,
    )?);
    Ok(written)
}

/// Prints what was rendered, the error estimate and whether the target was
/// reached.
fn report(
    job: &Job,
    request: &ReplicationRequest,
    measure: ErrorMeasure,
    rendered: &ReplicationRender,
    written: &[String],
) {
    let console = job.console;
    let settings = &job.settings;
    let statistics = &rendered.statistics;
    let estimate = rendered.accumulator.estimate();
    let indices = rendered.accumulator.indices();
    let [width, height] = job.scene.camera.resolution();
    let stopped = if job.interrupted() {
        " (interrupted)"
    } else {
        ""
    };
    let per_replication = request
        .samples_per_replication
        .map_or_else(|| "time-limited".to_string(), |spp| spp.to_string());
    let set = match request.set_size {
        Some(size) if request.is_part() => format!(" of a set of {size}"),
        _ => String::new(),
    };
    console.say(format_args!(
        "rendered {} {width}x{height} with {} / {}: {} replication{} ({}){set} of {per_replication} samples per pixel, {} in all{stopped}",
        job.scene_name,
        settings.integrator.name(),
        settings.sampler.name(),
        indices.len(),
        if indices.len() == 1 { "" } else { "s" },
        format_indices(&indices),
        statistics.completed_samples_per_pixel,
    ));
    if rendered.dropped > 0 {
        console.say(format_args!(
            "{} replication cut short and left out (its samples are not in the image)",
            rendered.dropped
        ));
    }
    console.report_rates(statistics);
    console.say(describe_estimate(&estimate, job.args.target_region));
    match (request.target_error, rendered.target_reached) {
        (Some(target), Some(true)) => console.say(format_args!(
            "target {:.3} % ({}) reached after {} replications",
            100.0 * target,
            measure.name(),
            indices.len()
        )),
        (Some(target), _) => console.say(format_args!(
            "target {:.3} % ({}) not reached: {:.3} % after {} replications ({})",
            100.0 * target,
            measure.name(),
            100.0 * estimate.relative(measure),
            indices.len(),
            if job.interrupted() {
                "interrupted"
            } else if settings
                .time_budget
                .is_some_and(|budget| statistics.elapsed >= budget)
            {
                "time budget reached"
            } else {
                "--max-replications reached"
            }
        )),
        _ => {}
    }
    console.report_details(
        job.args.integrators.lqmc.stats,
        settings,
        statistics,
        rendered.last.details.as_deref(),
        "last replication: ",
    );
    console.say(format_args!("wrote {}", written.join(" and ")));
}
