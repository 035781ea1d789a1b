//! One render (no `--replications`): rendered with a progress bar, written
//! with its variance layer and the integrator's own images, and reported
//! with the error its batches and variance layer estimate.

use super::output::{write_density, write_failure, write_png_beside, write_strategy_images};
use super::report::{render_failure, stop_note};
use super::{Job, render_metadata, traced_samples_per_pixel};
use crate::error::CliError;
use crate::replications::{ErrorEvidence, describe_single_render_error};
use render::image::Metadata;
use render::integrators::FilmObserver;
use render::renderer::{RenderOutput, render_observed};
use render::sampler::SamplerKind;

/// Renders `job` once, writes the images and reports.
pub fn render(job: &Job) -> Result<(), CliError> {
    let output = render_with_progress(job)?;
    let metadata = render_metadata(job.scene_name, &job.settings, &output.statistics);
    let written = write(job, &output, &metadata)?;
    report(job, &output, &written);
    Ok(())
}

/// Renders with a progress bar (by time when only a time budget ends the
/// render, else by samples) and the live view.
fn render_with_progress(job: &Job) -> Result<RenderOutput, CliError> {
    let bar = job.console.progress_bar();
    let started = std::time::Instant::now();
    let by_time = job.settings.time_budget.filter(|_| job.args.spp.is_none());
    let progress = |done: u64, total: u64| {
        let fraction = match by_time {
            Some(budget) => started.elapsed().as_secs_f64() / budget.as_secs_f64(),
            None => done as f64 / total.max(1) as f64,
        };
        bar.set_position((fraction.min(1.0) * 100.0) as u64);
        let seconds = started.elapsed().as_secs_f64().max(1e-9);
        bar.set_message(format!("{:.3} M samples/s", done as f64 / seconds / 1e6));
    };
    let observe = |film: &render::film::Film, splat_scale: f64| {
        if let Some(view) = &job.live_view {
            view.show_film(film, splat_scale);
        }
    };
    let observer: Option<FilmObserver<'_>> = job.live_view.as_ref().map(|_| &observe as _);
    let output = render_observed(&job.scene, &job.settings, &job.stop, &progress, observer)
        .map_err(render_failure)?;
    bar.finish_and_clear();
    if let Some(view) = &job.live_view {
        view.show(&output.image(), Some(&output.variance_image()));
    }
    Ok(output)
}

/// Writes the image, LQMC's density, BDPT's strategy images and the PNG;
/// returns what it wrote.
fn write(job: &Job, output: &RenderOutput, metadata: &Metadata) -> Result<Vec<String>, CliError> {
    let args = job.args;
    output
        .write(&args.output, metadata)
        .map_err(write_failure)?;
    let mut written = vec![args.output.display().to_string()];
    if let Some(path) = &args.integrators.lqmc.density {
        written.extend(write_density(path, output, metadata)?);
    }
    if let Some(directory) = &args.integrators.bdpt.strategy_images {
        written.extend(write_strategy_images(directory, output, metadata)?);
    }
    written.extend(write_png_beside(
        &args.output,
        job.format,
        &output.image(),
        args.exposure,
        metadata,
    )?);
    Ok(written)
}

/// Prints what was rendered, the rates, the integrator's statistics, the
/// error estimate (if the render has one) and the files.
fn report(job: &Job, output: &RenderOutput, written: &[String]) {
    let console = job.console;
    let settings = &job.settings;
    let statistics = &output.statistics;
    let [width, height] = job.scene.camera.resolution();
    let stopped = stop_note(job.interrupted(), statistics.stopped_early);
    if job.integrator().runs_markov_chains() {
        // The chains draw their own numbers: no sampler to name.
        console.say(format_args!(
            "rendered {} {width}x{height} with {}: {} mutations per pixel{stopped}",
            job.scene_name,
            settings.integrator.name(),
            statistics.completed_samples_per_pixel,
        ));
    } else {
        console.say(format_args!(
            "rendered {} {width}x{height} with {} / {}: {:.1} samples per pixel{stopped}",
            job.scene_name,
            settings.integrator.name(),
            settings.sampler.name(),
            traced_samples_per_pixel(&job.scene, statistics),
        ));
    }
    console.report_rates(statistics);
    console.report_details(
        job.args.integrators.lqmc.stats,
        settings,
        statistics,
        output.details.as_deref(),
        "",
    );
    if let Some(line) = describe_single_render_error(
        &output.image(),
        &output.variance_image(),
        &error_evidence(job, output),
    ) {
        console.say(line);
    }
    console.say(format_args!("wrote {}", written.join(" and ")));
}

/// What the render's error can be estimated from: its batches (and whether
/// they are independent) and whether its variance layer is an estimate.
fn error_evidence<'a>(job: &Job, output: &'a RenderOutput) -> ErrorEvidence<'a> {
    let settings = &job.settings;
    let (batches, independent) = if settings.pattern_size.is_some() {
        ("independent replications (Kollig & Keller)", true)
    } else if job.integrator().runs_markov_chains() {
        ("independent groups of chains", true)
    } else if settings.sampler == SamplerKind::Independent {
        ("independent passes", true)
    } else {
        ("passes", false)
    };
    let batch_means = output.batch_image_means.as_slice();
    // A variance from batches needs two of them; one from the samples of a
    // pixel (or of progressions) needs two samples per pixel.
    let variance_estimated = if batch_means.is_empty() {
        output.statistics.completed_samples_per_pixel >= 2
    } else {
        batch_means.len() >= 2
    };
    ErrorEvidence {
        batch_means,
        batches,
        independent,
        variance_estimated,
    }
}
