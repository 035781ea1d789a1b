//! The renders of the studies that render a scene (`equal-time`,
//! `lattice-structure`): each one a request with the study's depths and
//! Russian roulette, rendered in this process and written with `lqmc
//! render`'s metadata, so that every image says how it was made.

use super::StudySceneArgs;
use super::equal_time::write_failure;
use crate::error::CliError;
use crate::error::usage;
use crate::integrator_options::default_heuristic;
use crate::render_command::{RenderRequest, render_metadata, traced_samples_per_pixel};
use render::image::{Image, read_exr, read_image};
use render::integrators::{IntegratorDetails, IntegratorSettings};
use render::renderer::{RenderSettings, render};
use render::sampler::{Randomization, SamplerKind};
use render::scene::Scene;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

/// What every render of a study shares.
pub(super) struct RenderContext<'a> {
    /// The scene and render options of the study.
    pub scene_args: &'a StudySceneArgs,
    /// The built scene.
    pub scene: &'a Scene,
    /// Set by Ctrl-C ([`stop_on_interrupt`]).
    pub stop: &'a AtomicBool,
    /// The `-D` definitions as one metadata value ([`definitions_text`]).
    pub definitions: String,
}

/// One render as written.
pub(super) struct WrittenRender {
    /// The image.
    pub image: Image,
    /// Samples traced per pixel (partial passes included).
    pub traced_samples_per_pixel: f64,
    /// Complete passes (the image's samples per pixel).
    pub whole_passes: u64,
    /// Wall-clock seconds of the render.
    pub seconds: f64,
    /// The render's peak resident memory, where the system tells.
    pub peak_resident_bytes: Option<u64>,
    /// What the integrator reports of itself (LQMC's statistics).
    pub details: Option<Box<dyn IntegratorDetails>>,
}

impl RenderContext<'_> {
    /// A request with the study's depth, Russian roulette and MIS options.
    pub fn request(
        &self,
        integrator: IntegratorSettings,
        sampler: SamplerKind,
        seed: u64,
        threads: usize,
    ) -> RenderRequest {
        RenderRequest {
            heuristic: default_heuristic(integrator.kind()),
            integrator,
            sampler,
            pattern_size: None,
            samples_per_pixel: None,
            time_budget: None,
            seed,
            randomization: Randomization::Seeded,
            max_depth: self.scene_args.max_depth,
            russian_roulette_depth: self.scene_args.rr_depth,
            splat_film: false,
            threads,
        }
    }

    /// Renders with `settings` and writes the image with `lqmc render`'s
    /// metadata plus `extra` to `path`.
    pub fn render_to(
        &self,
        settings: &RenderSettings,
        path: &Path,
        extra: &[(&str, String)],
    ) -> Result<WrittenRender, CliError> {
        let output = render(self.scene, settings, self.stop, &|_, _| {})
            .map_err(|error| CliError::Failure(error.to_string()))?;
        if self.stop.load(Ordering::Relaxed) {
            return Err(CliError::Failure(
                "interrupted: the study's tables were not written".into(),
            ));
        }
        let statistics = output.statistics;
        let mut metadata = render_metadata(&self.scene_args.scene, settings, &statistics);
        for (key, value) in extra {
            metadata.insert((*key).to_string(), value.clone());
        }
        if !self.definitions.is_empty() {
            metadata.insert("sceneParameters".into(), self.definitions.clone());
        }
        output
            .write(path, &metadata)
            .map_err(|error| write_failure(path, error))?;
        let seconds = statistics.elapsed.as_secs_f64();
        // LQMC's --stats, on stderr with the progress lines.
        if let (true, Some(details)) = (self.scene_args.integrators.lqmc.stats, &output.details) {
            eprintln!(
                "{}",
                details.report(seconds.max(1e-9), self.scene_args.effective_threads())
            );
        }
        Ok(WrittenRender {
            image: output.image(),
            traced_samples_per_pixel: traced_samples_per_pixel(self.scene, &statistics),
            whole_passes: statistics.completed_samples_per_pixel,
            seconds,
            peak_resident_bytes: statistics.memory.map(|memory| memory.peak_resident_bytes),
            details: output.details,
        })
    }
}

/// The `-D` definitions as one metadata value (empty when none), so that a
/// reference of a file scene is reused only for the same parameters.
pub(super) fn definitions_text(definitions: &[(String, String)]) -> String {
    definitions
        .iter()
        .map(|(name, value)| format!("{name}={value}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// A flag that Ctrl-C sets, so that a render stops and the study ends
/// without writing tables of a cut render.
pub(super) fn stop_on_interrupt() -> Arc<AtomicBool> {
    let stop = Arc::new(AtomicBool::new(false));
    let flag = stop.clone();
    let _ = ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed));
    stop
}

/// Reads an image the study wrote to `directory` under `name`.
pub(super) fn read_study_image(directory: &Path, name: &str) -> Result<Image, CliError> {
    let path = directory.join(name);
    read_exr(&path)
        .map(|contents| contents.image)
        .map_err(|error| CliError::Failure(format!("cannot read back {}: {error}", path.display())))
}

/// Prints the report `markdown` and the files written (`files`, then the
/// images in `images`) to stdout, ignoring a closed pipe.
pub(super) fn print_report(markdown: &str, files: &[&Path], images: &Path) {
    use std::io::Write as _;
    let names: Vec<String> = files
        .iter()
        .map(|file| file.display().to_string())
        .collect();
    let mut stdout = std::io::stdout().lock();
    let _ = writeln!(stdout, "{}", markdown.trim_end());
    let _ = writeln!(
        stdout,
        "wrote {} and the images in {}",
        names.join(", "),
        images.display()
    );
}

/// Writes a study's report `markdown` and its `json` (with a final line
/// break) to `table.md` and `table.json` in `directory`; returns their
/// paths.
pub(super) fn write_tables(
    directory: &Path,
    markdown: &str,
    json: &crate::json::Json,
) -> Result<(PathBuf, PathBuf), CliError> {
    let table_md = directory.join("table.md");
    std::fs::write(&table_md, markdown).map_err(|error| write_failure(&table_md, error))?;
    let table_json = directory.join("table.json");
    std::fs::write(&table_json, json.render() + "\n")
        .map_err(|error| write_failure(&table_json, error))?;
    Ok((table_md, table_json))
}

/// Reads the reference `path` (`--reference`) of a study that renders
/// `width`×`height` images; a usage error if it is unreadable or of another
/// size.
pub(super) fn read_reference(path: &Path, width: usize, height: usize) -> Result<Image, CliError> {
    let image = read_image(path).map_err(|error| usage(format!("--reference: {error}")))?;
    if (image.width(), image.height()) != (width, height) {
        return Err(usage(format!(
            "--reference {} is {}x{}, but the study renders {width}x{height} (see --resolution)",
            path.display(),
            image.width(),
            image.height()
        )));
    }
    Ok(image)
}
