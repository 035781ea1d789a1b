//! The drivers every integrator is run by: they own the thread pool's
//! work, the passes, the time budget and interruptions, and the order in
//! which work is merged into the film, so that no integrator has a render
//! loop of its own and every image is deterministic for any thread count.
//!
//! - [`render_pixel_samples`], the tile driver, for integrators that
//!   estimate one pixel sample at a time ([`PixelSampleEstimator`]): path
//!   tracing, volumetric path tracing, LQMC. A pixel sample may add a camera
//!   sample to its own pixel and splats anywhere on the film.
//! - [`render_splat_paths`], the splat driver, for integrators whose every
//!   contribution is a splat ([`SplatEstimator`]): light tracing now,
//!   Markov chains later. Paths are numbered per pass; the sampler is
//!   positioned at a pixel sample named by the path's number, so every
//!   sampler (per-pixel QMC sequences included) serves it.
//!
//! # Passes and the splat normalisation
//!
//! Work is done in passes of a few samples per pixel (one with a time
//! budget), each pass split into the film's tiles. A time budget or an
//! interruption (the `stop` flag) is checked before each tile. When a pass
//! is cut short:
//! - the camera samples of its finished tiles are kept: each pixel
//!   averages its own samples, so a pixel with one sample more is not
//!   biased (except for LQMC, whose seeds' camera samples belong with
//!   their members' splats:
//!   [`PixelSampleEstimator::keeps_camera_samples_of_partial_passes`]);
//! - its splats are dropped: a splat image is normalised by one count for
//!   the whole film (`1 / samples per pixel`), and a partial pass would
//!   bias every pixel its tiles reached by `√(f(1−f))/(n+f)`.
//!
//! The splat scale is then [`DriverOutput::splat_scale`]: one over the
//! samples per pixel of the whole passes.

use crate::film::{Film, FilmError, FilmTile, PixelBounds, SampleOutcome, SplatBuffer};
#[cfg(target_arch = "x86_64")]
use crate::geometry::Avx2;
use crate::geometry::Ray;
use crate::sampler::{
    IndependentSampler, PixelSampler, Randomization, SamplerError, SamplerKind, layout,
};
use crate::scene::Scene;
use crate::spectrum::SampledWavelengths;
use glam::Vec2;
use rayon::prelude::*;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use super::TraceCounters;

/// Shown the film after each whole pass of a render, with the splat scale
/// of the passes so far: a live view.
pub type FilmObserver<'a> = &'a (dyn Fn(&Film, f64) + Sync);

/// How long a render runs and how it is observed: what every integrator
/// is given by the renderer.
pub struct RunControl<'a> {
    /// The sampler.
    pub sampler: SamplerKind,
    /// Points per replication, if each pixel's samples are independent
    /// replications: the driver then renders one replication per pass and
    /// estimates the variance from them.
    pub pattern_size: Option<u64>,
    /// The seed of every random choice.
    pub seed: u64,
    /// Whether the seed randomizes the sampler's QMC points.
    pub randomization: Randomization,
    /// Samples per pixel to render (with a time budget: at most this many).
    pub samples_per_pixel: u64,
    /// Stop after this much time, before the next tile.
    pub time_budget: Option<Duration>,
    /// Tile side in pixels.
    pub tile_size: usize,
    /// Set from a Ctrl-C handler: stop before the next tile.
    pub stop: &'a AtomicBool,
    /// Receives the number of pixel samples done and the total.
    pub progress: &'a (dyn Fn(u64, u64) + Sync),
    /// Shown the film after each whole pass, with the splat scale of the
    /// passes so far (a live view: `lqmc render --tev`).
    pub observer: Option<FilmObserver<'a>>,
    /// When the render started (the time budget counts from here).
    pub start: Instant,
}

impl RunControl<'_> {
    /// True once the render must stop: interrupted or out of time.
    pub fn out_of_time(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
            || self
                .time_budget
                .is_some_and(|budget| self.start.elapsed() >= budget)
    }
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
    /// The integrator cannot render this scene; the message says why.
    #[error("{0}")]
    Unsupported(String),
    /// The sampler cannot be built with these settings.
    #[error(transparent)]
    Sampler(#[from] SamplerError),
}

/// What a driver measured.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct DriverStatistics {
    /// Pixel samples (paths) traced, those of dropped partial passes included.
    pub samples: u64,
    /// Rays traced (closest hit and shadow).
    pub rays: u64,
    /// Samples per pixel completed by every pixel: the whole passes.
    pub completed_samples_per_pixel: u64,
    /// True if the render stopped before all samples per pixel.
    pub stopped_early: bool,
}

/// A driver's result: the film, its measurements and what the
/// integrator's work units added up to.
pub struct DriverOutput<T> {
    /// The film with every merged tile and the splats of whole passes.
    pub film: Film,
    /// Measurements.
    pub statistics: DriverStatistics,
    /// The integrator's own sum over its work units.
    pub total: T,
}

impl<T> DriverOutput<T> {
    /// The scale of the film's splats: one over the samples per pixel of
    /// the whole passes (see the module docs); 1 before any pass completed
    /// (the film then has no splats).
    pub fn splat_scale(&self) -> f64 {
        1.0 / self.statistics.completed_samples_per_pixel.max(1) as f64
    }
}

/// What one work unit (a tile of one pass) writes: camera samples into its
/// tile, splats anywhere, and its ray counts.
pub struct UnitOutput {
    /// Camera samples of the tile's pixels.
    pub tile: FilmTile,
    /// Contributions to any pixel (kept only if the pass completes).
    pub splats: SplatBuffer,
    /// Rays traced.
    pub counters: TraceCounters,
}

impl UnitOutput {
    /// Adds a camera sample of value `rgb` to `pixel` with the filter
    /// weight `weight` (non-finite values are counted and dropped).
    #[inline]
    pub fn add_camera_sample(&mut self, pixel: [usize; 2], rgb: [f32; 3], weight: f32) {
        let _ = self.tile.add_sample(pixel, rgb, weight);
    }

    /// Adds a camera path's value `rgb`, started at `start` for `pixel`:
    /// to the pixel with its filter-importance weight, or, with
    /// `splat_film`, splatted at its film position over the filter's pixels
    /// (Mitsuba's film; see [`CameraPathStart::for_film`]).
    #[inline]
    pub fn add_camera_path(
        &mut self,
        start: &CameraPathStart,
        pixel: (u32, u32),
        rgb: [f32; 3],
        splat_film: bool,
    ) {
        if splat_film {
            let weight = start.position.weight;
            let _ = self.splats.add(
                start.position.raster_position,
                rgb.map(|value| value * weight),
            );
        } else {
            self.add_camera_sample(
                [pixel.0 as usize, pixel.1 as usize],
                rgb,
                start.position.weight,
            );
        }
    }

    /// Adds a splat (non-finite values are counted and dropped).
    #[inline]
    pub fn add_splat(&mut self, raster_position: [f32; 2], rgb: [f32; 3]) -> SampleOutcome {
        self.splats.add(raster_position, rgb)
    }
}

/// One pixel sample to estimate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PixelSampleIndex {
    /// The pixel.
    pub pixel: (u32, u32),
    /// The sample's index within its pixel.
    pub sample_index: u64,
}

/// An integrator that estimates one pixel sample at a time, run by
/// [`render_pixel_samples`].
pub trait PixelSampleEstimator: Sync {
    /// A work unit's own state: scratch buffers and statistics.
    type Unit: Send;
    /// The sum of every merged work unit (statistics, extra images).
    type Total: Send;

    /// Samples per pixel in one pass, for a render of `samples_per_pixel`
    /// samples (with a time budget when `timed`). The default: up to four
    /// (one with a time budget, so that the budget is met closely).
    fn pass_size(&self, samples_per_pixel: u64, timed: bool) -> u64 {
        if timed {
            1
        } else {
            samples_per_pixel.clamp(1, 4)
        }
    }

    /// Whether the camera samples of a partial pass's finished tiles are
    /// kept (the default: each pixel averages its own samples, so one more
    /// does not bias it). LQMC keeps none: its image is the mean of whole
    /// progressions, whose spread its variance layer reports, and a seed's
    /// camera sample without its members' splats would be half a sample.
    fn keeps_camera_samples_of_partial_passes(&self) -> bool {
        true
    }

    /// The total before any work unit, for a film of `resolution` pixels.
    fn new_total(&self, resolution: [usize; 2]) -> Result<Self::Total, RenderError>;

    /// A fresh work unit.
    fn new_unit(&self) -> Self::Unit;

    /// Estimates one pixel sample; `sampler` is positioned at it.
    fn estimate<S: PixelSampler + ?Sized>(
        &self,
        unit: &mut Self::Unit,
        sample: PixelSampleIndex,
        sampler: &mut S,
        output: &mut UnitOutput,
    );

    /// Adds a finished work unit to the total, in the fixed tile order;
    /// `kept` is false for a unit of a partial pass (its splats are dropped).
    fn merge_unit(&self, total: &mut Self::Total, unit: Self::Unit, kept: bool);

    /// Called after each pass has been merged into `film`; `complete` is
    /// false for a partial pass.
    fn end_pass(&self, _total: &mut Self::Total, _film: &Film, _complete: bool) {}

    /// Called before each pass's tiles: an integrator that needs the whole
    /// pass's light subpaths before any camera subpath (VCM) traces them
    /// here, through `pass`. Returns the rays it traced.
    fn begin_pass(&self, _pass: &PassWork<'_>) -> TraceCounters {
        TraceCounters::default()
    }

    /// Whether the driver estimates the variance layer from the passes'
    /// images (each pass a batch; see [`super::progression_variance`]):
    /// for integrators whose contributions are splats, where the film's
    /// per-pixel sample variance says nothing. Default: no.
    fn variance_from_passes(&self) -> bool {
        false
    }
}

/// What [`PixelSampleEstimator::begin_pass`] can do: work over the pass's
/// pixel samples with the render's sampler, in parallel and in a fixed
/// order.
pub struct PassWork<'a> {
    tiles: &'a [PixelBounds],
    samples: std::ops::Range<u64>,
    prototype: &'a dyn PixelSampler,
    resolution: [usize; 2],
}

impl PassWork<'_> {
    /// The pass's samples per pixel (their indices).
    pub fn samples(&self) -> std::ops::Range<u64> {
        self.samples.clone()
    }

    /// The film's resolution.
    pub fn resolution(&self) -> [usize; 2] {
        self.resolution
    }

    /// The film's tiles, in the order [`Self::for_each_pixel_sample`]
    /// returns their states.
    pub fn tiles(&self) -> &[PixelBounds] {
        self.tiles
    }

    /// A sampler positioned at sample `sample_index` of `pixel`: numbers
    /// shared by the whole pass.
    pub fn sampler_at(&self, pixel: (u32, u32), sample_index: u64) -> Box<dyn PixelSampler> {
        let mut sampler = self.prototype.clone_sampler();
        sampler.start_pixel_sample(pixel, sample_index);
        sampler
    }

    /// Runs `work` once per pixel sample of the pass, the sampler
    /// positioned at it, with a state per tile (from `start`, given the
    /// tile's index): the film's
    /// tiles in parallel, pixels in rows within a tile, a pixel's samples
    /// in order. Returns the tiles' states in tile order and the rays
    /// counted.
    pub fn for_each_pixel_sample<State: Send>(
        &self,
        start: &(dyn Fn(usize) -> State + Sync),
        work: &(
             dyn Fn(&mut State, PixelSampleIndex, &mut dyn PixelSampler, &mut TraceCounters) + Sync
         ),
    ) -> (Vec<State>, TraceCounters) {
        let per_tile: Vec<(State, TraceCounters)> = self
            .tiles
            .par_iter()
            .enumerate()
            .map(|(tile_index, bounds)| {
                let mut sampler = self.prototype.clone_sampler();
                let mut counters = TraceCounters::default();
                let mut state = start(tile_index);
                for y in bounds.min[1]..bounds.max[1] {
                    for x in bounds.min[0]..bounds.max[0] {
                        for sample_index in self.samples.clone() {
                            let pixel = (x as u32, y as u32);
                            sampler.start_pixel_sample(pixel, sample_index);
                            let index = PixelSampleIndex {
                                pixel,
                                sample_index,
                            };
                            work(&mut state, index, sampler.as_mut(), &mut counters);
                        }
                    }
                }
                (state, counters)
            })
            .collect();
        let mut counters = TraceCounters::default();
        let mut states = Vec::with_capacity(per_tile.len());
        for (state, tile_counters) in per_tile {
            states.push(state);
            counters.add(&tile_counters);
        }
        (states, counters)
    }
}

/// Renders `scene` with `estimator` under `run` (see the module docs).
pub fn render_pixel_samples<E: PixelSampleEstimator>(
    estimator: &E,
    scene: &Scene,
    run: &RunControl<'_>,
) -> Result<DriverOutput<E::Total>, RenderError> {
    let [width, height] = scene.camera.resolution();
    let resolution = [width as usize, height as usize];
    let mut film = Film::new(resolution, scene.filter)?;
    let tiles = film.tile_bounds(run.tile_size.max(1))?;
    let prototype = run.sampler.create(
        run.seed,
        run.randomization,
        (width, height),
        run.samples_per_pixel,
        run.pattern_size,
    )?;
    let mut total = estimator.new_total(resolution)?;
    // With replications, a pass is one replication of every pixel.
    let pass_size = run
        .pattern_size
        .unwrap_or_else(|| estimator.pass_size(run.samples_per_pixel, run.time_budget.is_some()));
    // Batches of the variance layer: Kollig & Keller's replications, else
    // the passes of a splatting integrator.
    let mut batches = (run.pattern_size.is_some() || estimator.variance_from_passes())
        .then(|| super::progression_variance::ProgressionVariance::new(resolution));
    let pixel_count = width as u64 * height as u64;
    let all_samples = pixel_count * run.samples_per_pixel;
    let mut statistics = DriverStatistics::default();
    let mut first_sample = 0;
    while first_sample < run.samples_per_pixel && !run.out_of_time() {
        let end_sample = (first_sample + pass_size).min(run.samples_per_pixel);
        let samples = first_sample..end_sample;
        let prepared = estimator.begin_pass(&PassWork {
            tiles: &tiles,
            samples: samples.clone(),
            prototype: prototype.as_ref(),
            resolution,
        });
        statistics.rays += prepared.rays();
        let results: Vec<Option<(UnitOutput, E::Unit, u64)>> = tiles
            .par_iter()
            .map(|bounds| {
                if run.out_of_time() {
                    return None;
                }
                let mut output = UnitOutput {
                    tile: film
                        .new_tile(*bounds)
                        .expect("tiles come from the film's own bounds"),
                    splats: SplatBuffer::new(),
                    counters: TraceCounters::default(),
                };
                let mut unit = estimator.new_unit();
                // The independent sampler as its own type: its hash then
                // inlines into the integrator's path loop.
                let count = if run.sampler == SamplerKind::Independent {
                    render_unit_fastest(
                        estimator,
                        &mut unit,
                        *bounds,
                        samples.clone(),
                        &mut IndependentSampler::new(run.seed),
                        &mut output,
                    )
                } else {
                    let mut sampler = prototype.clone_sampler();
                    render_unit(
                        estimator,
                        &mut unit,
                        *bounds,
                        samples.clone(),
                        sampler.as_mut(),
                        &mut output,
                    )
                };
                Some((output, unit, count))
            })
            .collect();
        let complete = results.iter().all(Option::is_some);
        // Tiles and their splats merge in the fixed tile order: the image
        // does not depend on the number of threads (the splats in parallel
        // over bands of rows, each pixel in that order).
        let mut splat_buffers = Vec::new();
        let keep_tiles = complete || estimator.keeps_camera_samples_of_partial_passes();
        for (output, unit, count) in results.into_iter().flatten() {
            if keep_tiles {
                film.merge_tile(&output.tile)?;
            }
            if complete {
                splat_buffers.push(output.splats);
            }
            estimator.merge_unit(&mut total, unit, complete);
            statistics.rays += output.counters.rays();
            statistics.samples += count;
        }
        if splat_buffers
            .iter()
            .any(|buffer| !buffer.is_empty() || buffer.rejected_samples() > 0)
        {
            film.merge_splat_buffers(&splat_buffers.iter().collect::<Vec<_>>());
        }
        estimator.end_pass(&mut total, &film, complete);
        if let Some(batches) = &mut batches {
            // A batch cut short by the samples per pixel (not a multiple of
            // the pass size) is not like the others: it is left out.
            let whole = end_sample - first_sample == pass_size;
            batches.end_progression_of(&film, complete && whole, pass_size);
        }
        if complete {
            statistics.completed_samples_per_pixel = end_sample;
            if let Some(observe) = run.observer {
                observe(&film, 1.0 / end_sample as f64);
            }
        }
        (run.progress)(statistics.samples, all_samples);
        first_sample = end_sample;
    }
    statistics.stopped_early = statistics.completed_samples_per_pixel < run.samples_per_pixel;
    if let Some(batches) = batches {
        film.set_batch_variance(batches.variance_image(), batches.image_means().to_vec());
    }
    Ok(DriverOutput {
        film,
        statistics,
        total,
    })
}

/// [`render_unit`] as AVX2 code on CPUs that have it (see
/// [`render_unit_avx2`]), otherwise as baseline code.
fn render_unit_fastest<E: PixelSampleEstimator, S: PixelSampler + ?Sized>(
    estimator: &E,
    unit: &mut E::Unit,
    bounds: PixelBounds,
    samples: std::ops::Range<u64>,
    sampler: &mut S,
    output: &mut UnitOutput,
) -> u64 {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx2) = Avx2::detect() {
        // SAFETY: the proof says the CPU supports AVX2.
        return unsafe {
            render_unit_avx2(avx2, estimator, unit, bounds, samples, sampler, output)
        };
    }
    render_unit(estimator, unit, bounds, samples, sampler, output)
}

/// [`render_unit`] compiled for AVX2, with the integrator's path loop
/// inlined into it: three-operand VEX instructions need fewer register
/// copies than two-operand SSE (the path tracer's render phase on the
/// Cornell box: 463.9 M → 452.7 M instructions). The same IEEE operations
/// in the same order (no fused multiply–add: the `fma` feature stays off),
/// so the same image bit for bit. Only what inlines into it is compiled
/// for AVX2: the path tracer's `estimate` and `radiance` are
/// `#[inline(always)]` for that (LLVM did not inline them across the
/// change of target features); it is used with the independent sampler,
/// the one the comparison with Mitsuba runs.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn render_unit_avx2<E: PixelSampleEstimator, S: PixelSampler + ?Sized>(
    _: Avx2,
    estimator: &E,
    unit: &mut E::Unit,
    bounds: PixelBounds,
    samples: std::ops::Range<u64>,
    sampler: &mut S,
    output: &mut UnitOutput,
) -> u64 {
    render_unit(estimator, unit, bounds, samples, sampler, output)
}

/// Renders samples `samples` of every pixel of one tile: pixel by pixel,
/// the samples of a pixel in order. Generic over the sampler so that a
/// concrete one inlines into the integrator.
#[inline(always)]
fn render_unit<E: PixelSampleEstimator, S: PixelSampler + ?Sized>(
    estimator: &E,
    unit: &mut E::Unit,
    bounds: PixelBounds,
    samples: std::ops::Range<u64>,
    sampler: &mut S,
    output: &mut UnitOutput,
) -> u64 {
    let mut count = 0;
    for y in bounds.min[1]..bounds.max[1] {
        for x in bounds.min[0]..bounds.max[0] {
            for sample_index in samples.clone() {
                let pixel = (x as u32, y as u32);
                sampler.start_pixel_sample(pixel, sample_index);
                estimator.estimate(
                    unit,
                    PixelSampleIndex {
                        pixel,
                        sample_index,
                    },
                    sampler,
                    output,
                );
                count += 1;
            }
        }
    }
    count
}

/// An integrator whose every contribution is a splat, run by
/// [`render_splat_paths`]: one path per pixel sample, numbered
/// `pass · pixels + y · width + x` (its [`PixelSampleIndex`]); the path is
/// not tied to that pixel, which only names its numbers.
pub trait SplatEstimator: Sync {
    /// A work unit's own state: scratch buffers and statistics.
    type Unit: Send;
    /// The sum of every merged work unit.
    type Total: Send;

    /// The total before any work unit, for a film of `resolution` pixels.
    fn new_total(&self, resolution: [usize; 2]) -> Result<Self::Total, RenderError>;

    /// A fresh work unit.
    fn new_unit(&self) -> Self::Unit;

    /// Traces one path, splatting into `splats`; `sampler` is positioned at
    /// the path's numbers.
    fn trace<S: PixelSampler + ?Sized>(
        &self,
        unit: &mut Self::Unit,
        path: PixelSampleIndex,
        sampler: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    );

    /// Adds a finished work unit to the total, in a fixed order; `kept` is
    /// false for a unit of a partial pass (its splats were dropped).
    fn merge_unit(&self, total: &mut Self::Total, unit: Self::Unit, kept: bool);

    /// [`PixelSampleEstimator::begin_pass`].
    fn begin_pass(&self, _pass: &PassWork<'_>) -> TraceCounters {
        TraceCounters::default()
    }

    /// [`PixelSampleEstimator::pass_size`]. Each pass is a batch of the
    /// variance layer ([`PixelSampleEstimator::variance_from_passes`]), so
    /// the default makes at least 16 of them: `spp / 16` samples per pixel
    /// per pass, between 1 and 4 (one with a time budget). Smaller passes
    /// cost time at the passes' ends (light tracing of the Cornell box at
    /// 16 spp, 2 threads: 4–9 % slower with passes of 1 than of 4).
    fn pass_size(&self, samples_per_pixel: u64, timed: bool) -> u64 {
        if timed {
            1
        } else {
            (samples_per_pixel / 16).clamp(1, 4)
        }
    }
}

/// A [`SplatEstimator`] seen as a [`PixelSampleEstimator`] that writes no
/// camera samples: the tile driver's passes, partial-pass rule and merge
/// order serve both.
struct SplatsOnly<'a, E>(&'a E);

impl<E: SplatEstimator> PixelSampleEstimator for SplatsOnly<'_, E> {
    type Unit = E::Unit;
    type Total = E::Total;

    fn new_total(&self, resolution: [usize; 2]) -> Result<Self::Total, RenderError> {
        self.0.new_total(resolution)
    }

    fn new_unit(&self) -> Self::Unit {
        self.0.new_unit()
    }

    #[inline]
    fn estimate<S: PixelSampler + ?Sized>(
        &self,
        unit: &mut Self::Unit,
        sample: PixelSampleIndex,
        sampler: &mut S,
        output: &mut UnitOutput,
    ) {
        self.0.trace(
            unit,
            sample,
            sampler,
            &mut output.splats,
            &mut output.counters,
        );
    }

    fn merge_unit(&self, total: &mut Self::Total, unit: Self::Unit, kept: bool) {
        self.0.merge_unit(total, unit, kept);
    }

    fn begin_pass(&self, pass: &PassWork<'_>) -> TraceCounters {
        self.0.begin_pass(pass)
    }

    fn pass_size(&self, samples_per_pixel: u64, timed: bool) -> u64 {
        self.0.pass_size(samples_per_pixel, timed)
    }

    /// Every contribution is a splat: the passes give the variance layer.
    fn variance_from_passes(&self) -> bool {
        true
    }
}

/// Renders `scene` with the splatting `estimator` under `run`: passes of
/// one path per pixel (several per pass without a time budget), split into
/// the film's tiles, merged in a fixed order, partial passes dropped.
pub fn render_splat_paths<E: SplatEstimator>(
    estimator: &E,
    scene: &Scene,
    run: &RunControl<'_>,
) -> Result<DriverOutput<E::Total>, RenderError> {
    render_pixel_samples(&SplatsOnly(estimator), scene, run)
}

/// The start of a camera path: the film position of the pixel sample, the
/// camera ray and the sampled wavelengths, from the camera dimensions of
/// the layout. Every camera-path integrator starts here.
#[derive(Debug, Clone, Copy)]
pub struct CameraPathStart {
    /// Where the sample lies on the film and its filter weight.
    pub position: crate::film::CameraSamplePosition,
    /// The camera ray.
    pub ray: Ray,
    /// The path's wavelengths.
    pub wavelengths: SampledWavelengths,
}

/// The lens and time numbers of a camera sample. Numbers the camera does
/// not use (a pinhole's lens, a closed shutter's time) are not drawn (a
/// hash each saved): the centre of their range stands in.
#[inline(always)]
pub(crate) fn camera_numbers<S: crate::sampler::SampleSource + ?Sized>(
    scene: &Scene,
    sampler: &mut S,
) -> ([f32; 2], f32) {
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
    (u_lens, u_time)
}

impl CameraPathStart {
    /// The camera sample of `pixel` for the sampler's current numbers.
    #[inline(always)]
    pub fn new<S: crate::sampler::SampleSource + ?Sized>(
        scene: &Scene,
        pixel: (u32, u32),
        sampler: &mut S,
    ) -> Self {
        // The film is built with the scene's filter.
        let position = crate::film::CameraSamplePosition::new(
            &scene.filter,
            [pixel.0 as usize, pixel.1 as usize],
            sampler.get_2d(layout::FILM),
        );
        Self::at_position(scene, position, sampler)
    }

    /// The camera sample of `pixel` as [`CameraPathStart::new`] places it,
    /// or, with `splat_film`, uniformly in the pixel's share of the
    /// [`crate::film::ImagePlane`] (weight: the plane's area scale), to be
    /// splatted over the filter's pixels by [`UnitOutput::add_camera_path`].
    #[inline(always)]
    pub fn for_film<S: crate::sampler::SampleSource + ?Sized>(
        scene: &Scene,
        pixel: (u32, u32),
        sampler: &mut S,
        splat_film: bool,
    ) -> Self {
        if !splat_film {
            return Self::new(scene, pixel, sampler);
        }
        // Spread over the image grown by the filter's reach, as LQMC's
        // seeds are: the weight carries the domain's area over the image's.
        let image_plane = crate::film::ImagePlane::new(scene);
        let raster = image_plane.seed_raster(scene, pixel, sampler.get_2d(layout::FILM));
        let position = crate::film::CameraSamplePosition {
            raster_position: raster.to_array(),
            weight: image_plane.area_scale,
        };
        Self::at_position(scene, position, sampler)
    }

    /// The camera ray and wavelengths of a sample at `position`.
    #[inline(always)]
    pub fn at_position<S: crate::sampler::SampleSource + ?Sized>(
        scene: &Scene,
        position: crate::film::CameraSamplePosition,
        sampler: &mut S,
    ) -> Self {
        let (u_lens, u_time) = camera_numbers(scene, sampler);
        let camera_ray =
            scene
                .camera
                .generate_ray(Vec2::from(position.raster_position), u_lens, u_time);
        let wavelengths = SampledWavelengths::sample_visible(sampler.get(layout::WAVELENGTH));
        Self {
            position,
            ray: Ray::with_time(camera_ray.origin, camera_ray.direction, camera_ray.time),
            wavelengths,
        }
    }
}
