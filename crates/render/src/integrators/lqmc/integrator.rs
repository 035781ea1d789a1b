//! LQMC as an [`Integrator`]: every pixel sample is a seed path whose
//! events are explored and splatted ([`super::render_pixel_sample`]), run
//! by the tile driver one progression (one sample per pixel) per pass, so
//! that the variance layer can be estimated from the progressions' images
//! ([`ProgressionVariance`]) and a cut-short progression is dropped whole.

use super::class_selection::{ClassSelectionReport, select_classes};
use super::exploration::{ClassDensity, LqmcContext, LqmcScratch, render_pixel_sample};
use super::seed_film::SeedFilm;
use super::seed_screen::screens_seeds;
use super::{ClassSelection, LqmcSettings, LqmcStatistics, ProgressionVariance};
use crate::film::{BoxFilter, Film, Filter};
use crate::integrators::driver::{
    PixelSampleEstimator, PixelSampleIndex, UnitOutput, render_pixel_samples,
};
use crate::integrators::estimator::PathSettings;
use crate::integrators::path::PathIntegrator;
use crate::integrators::volpath::VolPathIntegrator;
use crate::integrators::{
    AuxiliaryImage, Integrator, IntegratorDetails, IntegratorRender, RenderError, RunControl,
};
use crate::sampler::PixelSampler;
use crate::scene::Scene;

/// The LQMC integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LqmcIntegrator {
    settings: LqmcSettings,
    path_settings: PathSettings,
}

impl LqmcIntegrator {
    /// LQMC with `settings`, its seed paths traced with `path_settings`.
    pub fn new(settings: LqmcSettings, path_settings: PathSettings) -> Self {
        Self {
            settings,
            path_settings,
        }
    }
}

/// What an LQMC render measured besides the image: its counters and the
/// statistics of its progressions (the variance layer).
#[derive(Debug, Clone)]
pub struct LqmcDetails {
    /// The counters of `--stats`.
    pub statistics: LqmcStatistics,
    /// The complete progressions' per-pixel statistics.
    pub progressions: ProgressionVariance,
    /// What the class-selection pilot measured and chose, if it ran.
    pub selection: Option<ClassSelectionReport>,
}

impl IntegratorDetails for LqmcDetails {
    fn report(&self, render_seconds: f64, threads: usize) -> String {
        let mut report = self.statistics.report(render_seconds, threads);
        if let Some(selection) = &self.selection {
            for line in selection.lines() {
                report.push('\n');
                report.push_str(&line);
            }
        }
        report
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

impl Integrator for LqmcIntegrator {
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError> {
        // The classes whose exploration pays, measured by a pilot.
        let (settings, selection) = if self.settings.class_selection == ClassSelection::Measured
            && !self.settings.explores_nothing()
        {
            let (settings, report) =
                select_classes(scene, &self.settings, self.path_settings, run)?;
            for line in report.lines() {
                log::info!("{line}");
            }
            (settings, Some(report))
        } else {
            (self.settings, None)
        };
        // Nothing to explore: every seed would be a path-traced sample, so
        // the path tracer renders them, at its cost (the seeds' recording
        // is saved) and with its image, bit for bit.
        if settings.explores_nothing() && !settings.gather_density {
            log::info!(
                "lqmc explores no class: its seeds are rendered by the path tracer ({})",
                if scene.has_media() { "volpath" } else { "path" }
            );
            let mut render = if scene.has_media() {
                VolPathIntegrator::new(self.path_settings).render(scene, run)
            } else {
                PathIntegrator::new(self.path_settings).render(scene, run)
            }?;
            if let Some(selection) = selection {
                render.details = Some(Box::new(PathTracedDetails {
                    selection,
                    path_tracer: render.details.take(),
                }));
            }
            return Ok(render);
        }
        let estimator = LqmcEstimator {
            context: LqmcContext {
                scene,
                settings: &settings,
                path_settings: self.path_settings,
                seed: run.seed,
                film: SeedFilm::new(scene, self.path_settings.splat_film),
                screen_seeds: screens_seeds(scene, &settings),
            },
        };
        let output = render_pixel_samples(&estimator, scene, run)?;
        let LqmcTotal {
            statistics,
            density,
            progressions,
        } = output.total;
        let auxiliary_images = density
            .map(|[classes, next_event]| AuxiliaryImage {
                name: "density",
                layers: vec![("rgb", classes), ("nee", next_event)],
            })
            .into_iter()
            .collect();
        Ok(IntegratorRender {
            film: output.film,
            statistics: output.statistics,
            variance: Some(progressions.variance_image()),
            auxiliary_images,
            details: Some(Box::new(LqmcDetails {
                statistics,
                progressions,
                selection,
            })),
        })
    }
}

/// The details of an LQMC render whose pilot chose no class, so that the
/// path tracer rendered it: the pilot's report and the path tracer's own.
pub struct PathTracedDetails {
    /// What the class-selection pilot measured and chose.
    pub selection: ClassSelectionReport,
    /// The path tracer's details, if it has any.
    pub path_tracer: Option<Box<dyn IntegratorDetails>>,
}

impl IntegratorDetails for PathTracedDetails {
    fn report(&self, render_seconds: f64, threads: usize) -> String {
        let mut lines = self.selection.lines();
        lines.push("LQMC explores no class: its seeds were rendered by the path tracer".into());
        if let Some(details) = &self.path_tracer {
            lines.push(details.report(render_seconds, threads));
        }
        lines.join("\n")
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// The seed paths of one pixel sample each, explored.
struct LqmcEstimator<'a> {
    context: LqmcContext<'a>,
}

/// The sum of an LQMC render's work units.
struct LqmcTotal {
    statistics: LqmcStatistics,
    /// Members per pixel and class, when gathered (classes, next events).
    density: Option<[Film; 2]>,
    progressions: ProgressionVariance,
}

impl PixelSampleEstimator for LqmcEstimator<'_> {
    type Unit = (LqmcScratch, LqmcStatistics);
    type Total = LqmcTotal;

    /// One progression per pass: the variance layer needs each one's image.
    fn pass_size(&self, _samples_per_pixel: u64, _timed: bool) -> u64 {
        1
    }

    /// A cut-short progression is dropped whole: the seeds' camera samples
    /// with their members' splats.
    fn keeps_camera_samples_of_partial_passes(&self) -> bool {
        false
    }

    fn new_total(&self, resolution: [usize; 2]) -> Result<LqmcTotal, RenderError> {
        let density = if self.context.settings.gather_density {
            let box_filter = Filter::Box(BoxFilter::new([0.5, 0.5])?);
            Some([
                Film::new(resolution, box_filter)?,
                Film::new(resolution, box_filter)?,
            ])
        } else {
            None
        };
        Ok(LqmcTotal {
            statistics: LqmcStatistics::default(),
            density,
            progressions: ProgressionVariance::new(resolution),
        })
    }

    fn new_unit(&self) -> Self::Unit {
        let mut scratch = LqmcScratch::default();
        scratch.density = self
            .context
            .settings
            .gather_density
            .then(ClassDensity::default);
        (scratch, LqmcStatistics::default())
    }

    /// Always inlined into the driver's tile loop, as the path tracer's:
    /// screened seeds are traced by the same code ([`render_pixel_sample`]).
    #[inline(always)]
    fn estimate<S: PixelSampler + ?Sized>(
        &self,
        (scratch, statistics): &mut Self::Unit,
        sample: PixelSampleIndex,
        sampler: &mut S,
        output: &mut UnitOutput,
    ) {
        render_pixel_sample(
            &self.context,
            sample.pixel,
            sample.sample_index,
            sampler,
            scratch,
            output,
            statistics,
        );
    }

    fn merge_unit(&self, total: &mut LqmcTotal, (mut scratch, statistics): Self::Unit, kept: bool) {
        if !kept {
            return;
        }
        total.statistics.add(&statistics);
        if let (Some(films), Some(splats)) = (&mut total.density, scratch.density.take()) {
            films[0].merge_splats(&splats.rgb);
            films[1].merge_splats(&splats.next_event);
        }
    }

    fn end_pass(&self, total: &mut LqmcTotal, film: &Film, complete: bool) {
        total.progressions.end_progression(film, complete);
    }
}
