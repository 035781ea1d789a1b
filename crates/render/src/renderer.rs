//! The render loop: image tiles in parallel with rayon, one pixel sample at a
//! time, in passes so that a time budget or an interruption still leaves a
//! consistent image. Tiles are merged into the film in a fixed order, so a
//! seed gives the same image whatever the number of threads.

use crate::film::{Film, FilmError, PixelBounds, SplatBuffer};
use crate::geometry::Ray;
use crate::integrators::lqmc::{self, LqmcSettings, LqmcStatistics};
use crate::integrators::path::{self, PathSettings};
use crate::integrators::volpath;
use crate::integrators::{IntegratorKind, MisHeuristic, TraceCounters};
use crate::sampler::{IndependentSampler, PixelSampler, SampleSource, SamplerKind, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledWavelengths, to_linear_srgb};
use glam::Vec2;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// What to render and how.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderSettings {
    /// The integrator (default path).
    pub integrator: IntegratorKind,
    /// The sampler (default Halton).
    pub sampler: SamplerKind,
    /// Samples per pixel to render (with a time budget: at most this many).
    pub samples_per_pixel: u64,
    /// Stop after this much time, at the end of a tile.
    pub time_budget: Option<Duration>,
    /// The seed of every random choice.
    pub seed: u64,
    /// Maximum path depth, Mitsuba's convention (segments).
    pub max_depth: u32,
    /// The MIS heuristic.
    pub heuristic: MisHeuristic,
    /// The vertex index from which Russian roulette may end paths, counted
    /// as Mitsuba's `rr_depth` (default 3; Mitsuba's own default is 5).
    pub russian_roulette_depth: u32,
    /// Worker threads (0: all cores).
    pub threads: usize,
    /// Tile side in pixels (default 16).
    pub tile_size: usize,
    /// Settings of the LQMC integrator (used with [`IntegratorKind::Lqmc`]).
    pub lqmc: LqmcSettings,
    /// Gather LQMC's sample density per class ([`RenderOutput::lqmc_density`]).
    pub lqmc_density: bool,
}

impl Default for RenderSettings {
    fn default() -> Self {
        Self {
            integrator: IntegratorKind::Path,
            sampler: SamplerKind::Halton,
            samples_per_pixel: 16,
            time_budget: None,
            seed: 0,
            max_depth: 6,
            heuristic: MisHeuristic::Power,
            russian_roulette_depth: PathSettings::default().russian_roulette_depth,
            threads: 0,
            tile_size: 16,
            lqmc: LqmcSettings::default(),
            lqmc_density: false,
        }
    }
}

/// What a render measured.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RenderStatistics {
    /// Pixel samples (camera paths) traced.
    pub samples: u64,
    /// Rays traced (closest hit and shadow).
    pub rays: u64,
    /// Samples whose value was NaN or infinite, dropped from the image.
    pub nonfinite_samples: u64,
    /// Wall-clock time of the render.
    pub elapsed: Duration,
    /// Samples per pixel completed by every pixel.
    pub completed_samples_per_pixel: u64,
    /// True if the render stopped early (time budget or interruption).
    pub stopped_early: bool,
    /// LQMC's counters (zero for other integrators).
    pub lqmc: LqmcStatistics,
}

/// Why a render failed.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    /// The film could not be set up.
    #[error(transparent)]
    Film(#[from] FilmError),
    /// The thread pool could not be created.
    #[error("cannot start {threads} render threads: {message}")]
    Threads { threads: usize, message: String },
}

/// The rendered film and statistics.
pub struct RenderOutput {
    /// The accumulated film.
    pub film: Film,
    /// Measurements of the render.
    pub statistics: RenderStatistics,
    /// LQMC's sample density per class, when asked for: splatted members
    /// per pixel (box filter, before the splat scale) of normal, caustic and
    /// depth-of-field paths as red, green and blue, and of next-event paths.
    pub lqmc_density: Option<[Film; 2]>,
    /// For LQMC renders, the estimated variance of each pixel's value from
    /// the images of the complete progressions (see
    /// [`lqmc::ProgressionVariance`]); `None` for other integrators, whose
    /// film has a per-pixel sample variance.
    pub lqmc_variance: Option<lqmc::ProgressionVariance>,
}

impl RenderOutput {
    /// The estimated variance of each pixel's value, the EXR's variance
    /// layer: from the progressions for LQMC, else the film's variance of
    /// the pixel mean.
    pub fn variance_image(&self) -> crate::image::Image {
        match &self.lqmc_variance {
            Some(progressions) => progressions.variance_image(),
            None => self.film.variance_image(),
        }
    }

    /// Writes the film's image to `path` in the format of its extension, as
    /// [`Film::write`] does, but an EXR file's variance layer is
    /// [`Self::variance_image`] (so LQMC renders get theirs).
    pub fn write(
        &self,
        path: impl AsRef<std::path::Path>,
        splat_scale: f64,
        metadata: &crate::image::Metadata,
    ) -> Result<(), crate::image::ImageError> {
        let path = path.as_ref();
        if self.lqmc_variance.is_some()
            && crate::image::ImageFormat::from_path(path)? == crate::image::ImageFormat::OpenExr
        {
            crate::image::write_exr(
                path,
                &self.film.image(splat_scale),
                &[(crate::image::VARIANCE_LAYER, &self.variance_image())],
                metadata,
            )
        } else {
            self.film.write(path, splat_scale, metadata)
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
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(settings.threads)
        .build()
        .map_err(|error| RenderError::Threads {
            threads: settings.threads,
            message: error.to_string(),
        })?;
    pool.install(|| render_in_pool(scene, settings, stop, progress))
}

fn render_in_pool(
    scene: &Scene,
    settings: &RenderSettings,
    stop: &AtomicBool,
    progress: &(dyn Fn(u64, u64) + Sync),
) -> Result<RenderOutput, RenderError> {
    let start = Instant::now();
    let [width, height] = scene.camera.resolution();
    let mut film = Film::new([width as usize, height as usize], scene.filter)?;
    let tiles = film.tile_bounds(settings.tile_size.max(1))?;
    let prototype =
        settings
            .sampler
            .create(settings.seed, (width, height), settings.samples_per_pixel);
    let path_settings = PathSettings {
        max_depth: settings.max_depth,
        heuristic: settings.heuristic,
        russian_roulette_depth: settings.russian_roulette_depth,
    };
    if settings.integrator == IntegratorKind::Path && scene.has_media() {
        log::warn!("the path integrator ignores participating media; use --integrator volpath");
    }
    let pixel_count = width as u64 * height as u64;
    let total = pixel_count * settings.samples_per_pixel;
    // Progressive passes keep a time budget or an interruption from leaving
    // some pixels far behind others.
    // LQMC renders one progression per pass: the variance layer needs the
    // image of each progression (`lqmc::ProgressionVariance`).
    let pass_size = if settings.time_budget.is_some() || settings.integrator == IntegratorKind::Lqmc
    {
        1
    } else {
        settings.samples_per_pixel.clamp(1, 4)
    };
    let out_of_time = || {
        stop.load(Ordering::Relaxed)
            || settings
                .time_budget
                .is_some_and(|budget| start.elapsed() >= budget)
    };
    let mut statistics = RenderStatistics::default();
    let mut density = if settings.lqmc_density && settings.integrator == IntegratorKind::Lqmc {
        let box_filter = crate::film::Filter::Box(crate::film::BoxFilter::new([0.5, 0.5])?);
        Some([
            Film::new([width as usize, height as usize], box_filter)?,
            Film::new([width as usize, height as usize], box_filter)?,
        ])
    } else {
        None
    };
    let mut progression_variance = (settings.integrator == IntegratorKind::Lqmc)
        .then(|| lqmc::ProgressionVariance::new([width as usize, height as usize]));
    let mut first_sample = 0;
    while first_sample < settings.samples_per_pixel && !out_of_time() {
        let end_sample = (first_sample + pass_size).min(settings.samples_per_pixel);
        let results: Vec<Option<TileResult>> = tiles
            .par_iter()
            .map(|bounds| {
                if out_of_time() {
                    return None;
                }
                let mut sampler = prototype.clone_sampler();
                let samples = first_sample..end_sample;
                Some(match settings.integrator {
                    IntegratorKind::Path | IntegratorKind::VolPath => {
                        let tile_settings = TileSettings {
                            scene,
                            film: &film,
                            integrator: settings.integrator,
                            path_settings: &path_settings,
                            bounds: *bounds,
                        };
                        // The independent sampler (what `SamplerKind::create`
                        // makes for it) as its own type: its hash then inlines
                        // into the path loop.
                        let (tile, counters, count) =
                            if settings.sampler == SamplerKind::Independent {
                                render_tile(
                                    &tile_settings,
                                    samples,
                                    &mut IndependentSampler::new(settings.seed),
                                )
                            } else {
                                render_tile(&tile_settings, samples, sampler.as_mut())
                            };
                        TileResult {
                            tile,
                            splats: None,
                            counters,
                            samples: count,
                            lqmc: LqmcStatistics::default(),
                            density: None,
                        }
                    }
                    IntegratorKind::Lqmc => {
                        let context = lqmc::LqmcContext {
                            scene,
                            settings: &settings.lqmc,
                            path_settings,
                            seed: settings.seed,
                        };
                        render_tile_lqmc(
                            &context,
                            &film,
                            *bounds,
                            samples,
                            sampler.as_mut(),
                            settings.lqmc_density,
                        )
                    }
                })
            })
            .collect();
        let mut complete = true;
        // Tiles and their splats merge in the fixed tile order: the image
        // does not depend on the number of threads.
        for result in results {
            match result {
                Some(result) => {
                    film.merge_tile(&result.tile)?;
                    if let Some(splats) = &result.splats {
                        film.merge_splats(splats);
                    }
                    statistics.rays += result.counters.rays();
                    statistics.samples += result.samples;
                    statistics.lqmc.add(&result.lqmc);
                    if let (Some(films), Some(splats)) = (&mut density, &result.density) {
                        films[0].merge_splats(&splats.rgb);
                        films[1].merge_splats(&splats.next_event);
                    }
                }
                None => complete = false,
            }
        }
        if let Some(progressions) = &mut progression_variance {
            progressions.end_progression(&film, complete);
        }
        if complete {
            statistics.completed_samples_per_pixel = end_sample;
        }
        progress(statistics.samples, total);
        first_sample = end_sample;
    }
    statistics.stopped_early = statistics.completed_samples_per_pixel < settings.samples_per_pixel;
    statistics.nonfinite_samples = film.nonfinite_samples();
    statistics.elapsed = start.elapsed();
    Ok(RenderOutput {
        film,
        statistics,
        lqmc_density: density,
        lqmc_variance: progression_variance,
    })
}

/// What rendering one tile for one pass produced.
struct TileResult {
    tile: crate::film::FilmTile,
    splats: Option<SplatBuffer>,
    counters: TraceCounters,
    samples: u64,
    lqmc: LqmcStatistics,
    density: Option<lqmc::ClassDensity>,
}

/// Renders samples `samples` of every pixel of a tile with LQMC: every
/// contribution is a splat (members land in other pixels), gathered in the
/// tile's own buffer.
fn render_tile_lqmc(
    context: &lqmc::LqmcContext<'_>,
    film: &Film,
    bounds: PixelBounds,
    samples: std::ops::Range<u64>,
    sampler: &mut dyn PixelSampler,
    gather_density: bool,
) -> TileResult {
    let tile = film
        .new_tile(bounds)
        .expect("tiles come from the film's own bounds");
    let mut splats = SplatBuffer::new();
    let mut counters = TraceCounters::default();
    let mut statistics = LqmcStatistics::default();
    let mut scratch = lqmc::LqmcScratch::default();
    scratch.density = gather_density.then(lqmc::ClassDensity::default);
    let mut count = 0;
    for y in bounds.min[1]..bounds.max[1] {
        for x in bounds.min[0]..bounds.max[0] {
            for sample_index in samples.clone() {
                sampler.start_pixel_sample((x as u32, y as u32), sample_index);
                lqmc::render_pixel_sample(
                    context,
                    (x as u32, y as u32),
                    sample_index,
                    &mut *sampler,
                    &mut scratch,
                    &mut splats,
                    &mut statistics,
                    &mut counters,
                );
                count += 1;
            }
        }
    }
    TileResult {
        tile,
        splats: Some(splats),
        counters,
        samples: count,
        lqmc: statistics,
        density: scratch.density.take(),
    }
}

/// What [`render_tile`] renders: the scene, the film and integrator, and
/// the tile's pixels.
struct TileSettings<'a> {
    scene: &'a Scene,
    film: &'a Film,
    integrator: IntegratorKind,
    path_settings: &'a PathSettings,
    bounds: PixelBounds,
}

/// A sampler seen as `dyn SampleSource`, for integrators that take one: a
/// reference to a generic, possibly unsized sampler does not coerce to it.
struct DynSource<'a, S: ?Sized>(&'a mut S);

impl<S: SampleSource + ?Sized> SampleSource for DynSource<'_, S> {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        self.0.get(dimension)
    }

    #[inline]
    fn get_2d(&mut self, dimension: usize) -> [f32; 2] {
        self.0.get_2d(dimension)
    }
}

/// Renders samples `samples` of every pixel of a tile. Generic over the
/// sampler so that a concrete one inlines into the path loop.
fn render_tile<S: PixelSampler + ?Sized>(
    settings: &TileSettings<'_>,
    samples: std::ops::Range<u64>,
    sampler: &mut S,
) -> (crate::film::FilmTile, TraceCounters, u64) {
    let TileSettings {
        scene,
        film,
        integrator,
        path_settings,
        bounds,
    } = *settings;
    let mut tile = film
        .new_tile(bounds)
        .expect("tiles come from the film's own bounds");
    let mut counters = TraceCounters::default();
    let mut count = 0;
    for y in bounds.min[1]..bounds.max[1] {
        for x in bounds.min[0]..bounds.max[0] {
            for sample_index in samples.clone() {
                sampler.start_pixel_sample((x as u32, y as u32), sample_index);
                let position = film.camera_sample_position([x, y], sampler.get_2d(layout::FILM));
                // Numbers the camera does not use (a pinhole's lens, a
                // closed shutter's time) are not drawn: a hash each saved.
                let u_lens = if scene.camera.uses_lens_sample() {
                    sampler.get_2d(layout::LENS)
                } else {
                    [0.5; 2]
                };
                let u_time = if scene.camera.uses_time_sample() {
                    sampler.get(layout::TIME)
                } else {
                    0.5
                };
                let camera_ray =
                    scene
                        .camera
                        .generate_ray(Vec2::from(position.raster_position), u_lens, u_time);
                let mut wavelengths =
                    SampledWavelengths::sample_visible(sampler.get(layout::WAVELENGTH));
                let ray = Ray::with_time(camera_ray.origin, camera_ray.direction, camera_ray.time);
                let radiance = match integrator {
                    // LQMC tiles are rendered by `render_tile_lqmc`; its seed
                    // paths are path-traced, so the path tracer stands for it.
                    IntegratorKind::Path | IntegratorKind::Lqmc => path::radiance(
                        scene,
                        path_settings,
                        ray,
                        &mut wavelengths,
                        &mut *sampler,
                        &mut counters,
                        None,
                    ),
                    IntegratorKind::VolPath => volpath::radiance(
                        scene,
                        path_settings,
                        ray,
                        &mut wavelengths,
                        &mut DynSource(&mut *sampler),
                        &mut counters,
                    ),
                };
                let rgb = to_linear_srgb(&radiance, &wavelengths);
                // Non-finite values are counted and dropped by the tile.
                let _ = tile.add_sample([x, y], rgb, position.weight);
                count += 1;
            }
        }
    }
    (tile, counters, count)
}
