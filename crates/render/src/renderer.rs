//! The renderer: builds the thread pool and the integrator a render's
//! settings name, runs it under a [`RunControl`], and normalises what it
//! returns (the splat scale from the whole passes). It knows no
//! integrator's internals: see [`crate::integrators`] for the interface
//! and [`crate::integrators::driver`] for the passes, tiles and the
//! deterministic merge order.

use crate::film::Film;
use crate::image::Image;
use crate::integrators::estimator::PathSettings;
use crate::integrators::{IntegratorDetails, IntegratorSettings, MisHeuristic, RunControl};
use crate::sampler::{Randomization, SamplerKind};
use crate::scene::Scene;
use std::sync::atomic::AtomicBool;
use std::time::{Duration, Instant};

pub use crate::integrators::RenderError;

/// What to render and how.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    /// The integrator with its own settings (default path).
    pub integrator: IntegratorSettings,
    /// The sampler (default Halton).
    pub sampler: SamplerKind,
    /// With a pattern size `m`, each pixel's samples are independent
    /// replications of `m` points (Kollig & Keller, Eq. 5), rendered one
    /// per pass, and the variance layer is estimated from them (Eq. 6).
    /// Only for samplers with replications
    /// ([`SamplerKind::has_replications`]); default none.
    pub pattern_size: Option<u64>,
    /// Samples per pixel to render (with a time budget: at most this many).
    pub samples_per_pixel: u64,
    /// Stop after this much time, at the end of a tile.
    pub time_budget: Option<Duration>,
    /// The seed of every random choice.
    pub seed: u64,
    /// Whether the seed randomizes the sampler's QMC points (default: it
    /// does; [`Randomization::None`] keeps the deterministic sequences).
    pub randomization: Randomization,
    /// Maximum path depth, Mitsuba's convention (segments).
    pub max_depth: u32,
    /// The MIS heuristic.
    pub heuristic: MisHeuristic,
    /// The vertex index from which Russian roulette may end paths, counted
    /// as Mitsuba's `rr_depth` (default 3; Mitsuba's own default is 5).
    pub russian_roulette_depth: u32,
    /// Camera-path integrators: splat each sample over its filter's pixels
    /// instead of importance-sampling the filter (see
    /// [`PathSettings::splat_film`]; default false).
    pub splat_film: bool,
    /// Worker threads (0: all cores).
    pub threads: usize,
    /// Tile side in pixels (default 16).
    pub tile_size: usize,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            integrator: IntegratorSettings::Path,
            sampler: SamplerKind::Halton,
            pattern_size: None,
            samples_per_pixel: 16,
            time_budget: None,
            seed: 0,
            randomization: Randomization::Seeded,
            max_depth: 6,
            heuristic: MisHeuristic::Power,
            russian_roulette_depth: PathSettings::default().russian_roulette_depth,
            splat_film: false,
            threads: 0,
            tile_size: 16,
        }
    }
}

impl RenderSettings {
    /// The settings every path-building integrator shares.
    pub fn path_settings(&self) -> PathSettings {
        PathSettings {
            max_depth: self.max_depth,
            heuristic: self.heuristic,
            russian_roulette_depth: self.russian_roulette_depth,
            splat_film: self.splat_film,
            min_depth: 1,
        }
    }
}

/// What a render measured.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RenderStatistics {
    /// Pixel samples (camera or light paths) traced.
    pub samples: u64,
    /// Rays traced (closest hit and shadow).
    pub rays: u64,
    /// Samples whose value was NaN or infinite, dropped from the image.
    pub nonfinite_samples: u64,
    /// Wall-clock time of the render.
    pub elapsed: Duration,
    /// Samples per pixel completed by every pixel (whole passes).
    pub completed_samples_per_pixel: u64,
    /// True if the render stopped early (time budget or interruption).
    pub stopped_early: bool,
    /// The peak resident memory during the render, where the system tells
    /// ([`crate::memory`]).
    pub memory: Option<crate::memory::MemoryReport>,
}

/// The rendered film and what else the integrator returned.
pub struct RenderOutput {
    /// The accumulated film.
    pub film: Film,
    /// Measurements of the render.
    pub statistics: RenderStatistics,
    /// The factor of the film's splats: one over the samples per pixel of
    /// the whole passes (partial passes' splats are not in the film).
    pub splat_scale: f64,
    /// The integrator's estimate of each pixel's variance where the film's
    /// per-pixel sample variance does not describe it (splatting
    /// integrators).
    pub variance: Option<Image>,
    /// Further images of the render (e.g. LQMC's `density`): named layers,
    /// scaled by [`Self::splat_scale`].
    pub auxiliary_images: Vec<(&'static str, Vec<(&'static str, Image)>)>,
    /// The integrator's own statistics, if any.
    pub details: Option<Box<dyn IntegratorDetails>>,
    /// Per batch of the driver's variance estimate (Kollig & Keller's
    /// replications, a splatting integrator's passes, Metropolis chain
    /// groups), its image's mean luminance; empty without batches.
    pub batch_image_means: Vec<f64>,
}

impl RenderOutput {
    /// The image: camera samples' means plus the scaled splats.
    pub fn image(&self) -> Image {
        self.film.image(self.splat_scale)
    }

    /// The estimated variance of each pixel's value, the EXR's variance
    /// layer: the integrator's estimate, else the film's variance of the
    /// pixel mean.
    pub fn variance_image(&self) -> Image {
        match &self.variance {
            Some(variance) => variance.clone(),
            None => self.film.variance_image(),
        }
    }

    /// The integrator's statistics as the type `T` it keeps them in.
    pub fn details<T: 'static>(&self) -> Option<&T> {
        self.details
            .as_ref()
            .and_then(|details| details.as_any().downcast_ref::<T>())
    }

    /// The auxiliary image called `name`, if the integrator made one.
    pub fn auxiliary_image(&self, name: &str) -> Option<&[(&'static str, Image)]> {
        self.auxiliary_images
            .iter()
            .find(|(own, _)| *own == name)
            .map(|(_, layers)| layers.as_slice())
    }

    /// Writes the image to `path` in the format of its extension, as
    /// [`Film::write`] does, with [`Self::variance_image`] as an EXR file's
    /// variance layer.
    pub fn write(
        &self,
        path: impl AsRef<std::path::Path>,
        metadata: &crate::image::Metadata,
    ) -> Result<(), crate::image::ImageError> {
        let path = path.as_ref();
        if self.variance.is_some()
            && crate::image::ImageFormat::from_path(path)? == crate::image::ImageFormat::OpenExr
        {
            crate::image::write_exr(
                path,
                &self.image(),
                &[(crate::image::VARIANCE_LAYER, &self.variance_image())],
                metadata,
            )
        } else {
            self.film.write(path, self.splat_scale, metadata)
        }
    }
}

/// Renders `scene`. `stop` is polled between tiles (set it from a Ctrl-C
/// handler); `progress` receives the number of pixel samples done and the
/// total.
pub fn render(
    scene: &Scene,
    settings: &RenderSettings,
    stop: &AtomicBool,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<RenderOutput, RenderError> {
    render_observed(scene, settings, stop, progress, None)
}

/// [`render`], showing `observer` the film after each whole pass with the
/// splat scale of the passes so far (a live view).
pub fn render_observed(
    scene: &Scene,
    settings: &RenderSettings,
    stop: &AtomicBool,
    progress: &(dyn Fn(u64, u64) + Sync),
    observer: Option<crate::integrators::FilmObserver<'_>>,
) -> Result<RenderOutput, RenderError> {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(settings.threads)
        .build()
        .map_err(|error| RenderError::Threads {
            threads: settings.threads,
            message: error.to_string(),
        })?;
    let memory = crate::memory::PeakMemoryMeasurement::start();
    let integrator = settings.integrator.create(settings.path_settings());
    let run = RunControl {
        sampler: settings.sampler,
        pattern_size: settings.pattern_size,
        seed: settings.seed,
        randomization: settings.randomization,
        samples_per_pixel: settings.samples_per_pixel,
        time_budget: settings.time_budget,
        tile_size: settings.tile_size,
        stop,
        progress,
        observer,
        start: Instant::now(),
    };
    let rendered = pool.install(|| integrator.render(scene, &run))?;
    let driver = rendered.statistics;
    let splat_scale = 1.0 / driver.completed_samples_per_pixel.max(1) as f64;
    let statistics = RenderStatistics {
        samples: driver.samples,
        rays: driver.rays,
        nonfinite_samples: rendered.film.nonfinite_samples(),
        elapsed: run.start.elapsed(),
        completed_samples_per_pixel: driver.completed_samples_per_pixel,
        stopped_early: driver.stopped_early,
        memory: memory.finish(),
    };
    let auxiliary_images = rendered
        .auxiliary_images
        .iter()
        .map(|auxiliary| {
            let layers = auxiliary
                .layers
                .iter()
                .map(|(name, film)| (*name, film.image(splat_scale)))
                .collect();
            (auxiliary.name, layers)
        })
        .collect();
    // The driver's batches (independent replications, a splatting
    // integrator's passes) describe any integrator's error.
    let variance = rendered
        .film
        .batch_variance()
        .cloned()
        .or(rendered.variance);
    let batch_image_means = rendered.film.batch_image_means().to_vec();
    Ok(RenderOutput {
        batch_image_means,
        film: rendered.film,
        statistics,
        splat_scale,
        variance,
        auxiliary_images,
        details: rendered.details,
    })
}
