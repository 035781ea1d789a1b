//! What `lqmc render` tells the user: progress, rates, the integrator's own
//! statistics and its failures. With `--quiet` nothing is printed but
//! errors (see [`crate::error`]).

use crate::error::{CliError, usage};
use indicatif::{ProgressBar, ProgressStyle};
use render::integrators::{IntegratorDetails, IntegratorKind, RenderError};
use render::renderer::{RenderSettings, RenderStatistics};
use std::fmt::Display;
use std::io::Write as _;

/// Where a render reports: stdout and a progress bar on stderr, or nowhere
/// with `--quiet`.
#[derive(Debug, Clone, Copy)]
pub struct Console {
    quiet: bool,
}

impl Console {
    /// The console of a render, silent if `quiet`.
    pub fn new(quiet: bool) -> Self {
        Self { quiet }
    }

    /// Prints a line to stdout, ignoring a closed pipe (e.g. `| head`):
    /// results are already written to files or complete, so there is
    /// nothing to report.
    pub fn say(&self, line: impl Display) {
        if !self.quiet {
            let _ = writeln!(std::io::stdout().lock(), "{line}");
        }
    }

    /// A progress bar of 100 steps with a message (hidden when quiet).
    pub fn progress_bar(&self) -> ProgressBar {
        if self.quiet {
            return ProgressBar::hidden();
        }
        let bar = ProgressBar::new(100);
        bar.set_style(
            ProgressStyle::with_template(
                "{bar:40} {percent:>3}% {elapsed_precise} ETA {eta_precise} {msg}",
            )
            .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        bar
    }

    /// Prints a render's time, samples/s, rays/s, dropped NaN/Inf samples
    /// and peak memory.
    pub fn report_rates(&self, statistics: &RenderStatistics) {
        let seconds = statistics.elapsed.as_secs_f64().max(1e-9);
        self.say(format_args!(
            "time {seconds:.3} s, {:.3} M samples/s, {:.3} M rays/s, {} NaN/Inf samples dropped",
            statistics.samples as f64 / seconds / 1e6,
            statistics.rays as f64 / seconds / 1e6,
            statistics.nonfinite_samples,
        ));
        if let Some(memory) = statistics.memory {
            self.say(memory.describe());
        }
    }

    /// Prints the integrator's own statistics after `prefix`: with
    /// `--stats`, and always for the Metropolis integrators' chains and
    /// VCM's iterations and merges.
    pub fn report_details(
        &self,
        stats: bool,
        settings: &RenderSettings,
        statistics: &RenderStatistics,
        details: Option<&dyn IntegratorDetails>,
        prefix: &str,
    ) {
        let kind = settings.integrator.kind();
        let always = kind.is_metropolis() || kind == IntegratorKind::Vcm;
        if let (true, Some(details)) = (stats || always, details) {
            let threads = if settings.threads == 0 {
                std::thread::available_parallelism().map_or(1, |count| count.get())
            } else {
                settings.threads
            };
            let seconds = statistics.elapsed.as_secs_f64().max(1e-9);
            self.say(format_args!("{prefix}{}", details.report(seconds, threads)));
        }
    }
}

/// " (interrupted)", " (time budget reached)" or nothing, after the line
/// that says what was rendered.
pub fn stop_note(interrupted: bool, stopped_early: bool) -> &'static str {
    if interrupted {
        " (interrupted)"
    } else if stopped_early {
        " (time budget reached)"
    } else {
        ""
    }
}

/// A render's failure as a command-line error: an integrator that cannot
/// render the scene or a sampler that cannot be built is bad input
/// (status 2), anything else a failure.
pub fn render_failure(error: RenderError) -> CliError {
    match error {
        RenderError::Unsupported(message) => usage(message),
        RenderError::Sampler(error) => usage(error.to_string()),
        other => CliError::Failure(other.to_string()),
    }
}
