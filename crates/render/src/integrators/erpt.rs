//! Energy redistribution path tracing (Cline, Talbot & Egbert 2005), in
//! primary sample space: every pixel sample is a path-traced seed (drawn by
//! the render's sampler, so QMC seeds too), and the seed's energy is
//! redistributed by short Metropolis chains started from it.
//!
//! A seed `u` with contribution `F(u)` (its splats, as the path tracer's
//! whole-image-plane sample of [`super::pssmlt::CameraPathContribution`])
//! and target `I(u)` (its luminance, [`super::markov_chain::importance`])
//! starts `⌊ξ + I(u) / (L · e_d)⌋` chains (ξ uniform) of `L` mutations each;
//! every mutation deposits the energy `e_d` with expected-value splats
//! (`a · e_d · F(y)/I(y)` at the proposal, `(1 − a) · e_d · F(x)/I(x)` at
//! the current state). The seed itself is not splatted: its energy is what
//! the chains deposit. Because a seed's chains are `I(u)/(L e_d)` in
//! expectation, chain starts are distributed in proportion to `I`, which
//! the chains keep stationary, so the image is unbiased for any fixed
//! `e_d` (Cline et al.'s argument): `e_d = b / (L · c)` with `b` the mean
//! target of an independent bootstrap and `c` the mean chains per seed.
//!
//! Defaults, with their sources: chain length 100 and one chain per seed
//! on average (Mitsuba 0.6 `erpt`: `chainLength` 100, `numChains` 1), small
//! steps only (Cline et al.'s perturbations; no large steps: the seeds
//! explore), Kelemen's exponential kernel, 100 000 bootstrap samples.
//! Chains draw their numbers from streams keyed by the seed, the pixel
//! sample and the chain: the image is the same for any number of threads.

use super::driver::{
    PixelSampleIndex, RenderError, RunControl, SplatEstimator, render_splat_paths,
};
use super::estimator::PathSettings;
use super::markov_chain::{
    Bootstrap, Chain, ChainOutput, ChainStatistics, ChainWork, PathContribution, importance,
};
use super::pssmlt::CameraPathContribution;
use super::{Integrator, IntegratorRender, TraceCounters};
use crate::film::SplatBuffer;
use crate::sampler::{MetropolisSampler, MutationSettings, PixelSampler, SampleSource, layout};
use crate::scene::Scene;
use qmc::random::SeekablePcg;

/// ERPT's settings.
#[derive(Debug, Clone, PartialEq)]
pub struct ErptSettings {
    /// Mutations per chain, L (Mitsuba: 100).
    pub chain_length: u64,
    /// Chains per seed on average, c (Mitsuba: 1).
    pub chains_per_sample: f64,
    /// Bootstrap samples for the normalisation b.
    pub bootstrap_samples: u64,
    /// The mutations (default: small steps only, Kelemen's kernel).
    pub mutation: MutationSettings,
}

impl Default for ErptSettings {
    fn default() -> Self {
        Self {
            chain_length: 100,
            chains_per_sample: 1.0,
            bootstrap_samples: 100_000,
            mutation: MutationSettings {
                large_step_probability: 0.0,
                ..MutationSettings::default()
            },
        }
    }
}

/// ERPT as an [`Integrator`].
#[derive(Debug, Clone, PartialEq)]
pub struct ErptIntegrator {
    settings: ErptSettings,
    path: PathSettings,
}

impl ErptIntegrator {
    /// ERPT with `settings` over camera paths of `path`.
    pub fn new(settings: ErptSettings, path: PathSettings) -> Self {
        Self { settings, path }
    }
}

impl Integrator for ErptIntegrator {
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError> {
        let contribution = CameraPathContribution::new(scene, self.path);
        let clock = std::time::Instant::now();
        let bootstrap = Bootstrap::run(
            &contribution,
            run.seed ^ BOOTSTRAP_KEY,
            self.settings.bootstrap_samples,
            &self.settings.mutation,
        );
        let bootstrap_seconds = clock.elapsed().as_secs_f64();
        let normalization = bootstrap.normalization();
        let chain_length = self.settings.chain_length.max(1);
        let deposit =
            normalization / (chain_length as f64 * self.settings.chains_per_sample.max(1e-9));
        let [width, height] = scene.camera.resolution();
        let estimator = Erpt {
            contribution,
            settings: &self.settings,
            chain_length,
            deposit,
            resolution: [width as f32, height as f32],
            width: width as u64,
            pixels: width as u64 * height as u64,
            seed: run.seed,
        };
        let clock = std::time::Instant::now();
        let mut output = render_splat_paths(&estimator, scene, run)?;
        let mut chains = output.total;
        chains.normalization = normalization;
        chains.bootstrap_samples = bootstrap.samples();
        chains.bootstrap_nonzero = bootstrap.nonzero;
        chains.bootstrap_seconds = bootstrap_seconds;
        chains.chain_seconds = clock.elapsed().as_secs_f64();
        output.statistics.rays += bootstrap.counters.rays();
        Ok(ChainOutput {
            film: output.film,
            statistics: output.statistics,
            chains,
        }
        .into_render("erpt"))
    }
}

/// The bootstrap's and the chains' stream keys.
const BOOTSTRAP_KEY: u64 = 0x6572_7074_5f62_6f6f;
const CHAIN_KEY: u64 = 0x6572_7074_5f63_6861;

/// The splat estimator: a seed per pixel sample, its chains.
struct Erpt<'a> {
    contribution: CameraPathContribution<'a>,
    settings: &'a ErptSettings,
    chain_length: u64,
    /// The energy of one mutation, e_d.
    deposit: f64,
    resolution: [f32; 2],
    width: u64,
    pixels: u64,
    seed: u64,
}

/// A work unit's scratch and counts.
#[derive(Default)]
struct ErptUnit {
    /// The contribution's scratch memory.
    scratch: <CameraPathContribution<'static> as PathContribution>::Scratch,
    numbers: Vec<(usize, f32)>,
    seed_splats: SplatBuffer,
    work: ChainWork,
    chains: u64,
}

/// The sampler's numbers for a seed of `pixel`, with the film numbers
/// (dimensions 0, 1) turned from the pixel's into the whole image plane's,
/// recorded so that chains can start from them.
struct RecordedSeed<'a, S: ?Sized> {
    sampler: &'a mut S,
    pixel: [f32; 2],
    resolution: [f32; 2],
    numbers: &'a mut Vec<(usize, f32)>,
}

impl<S: SampleSource + ?Sized> SampleSource for RecordedSeed<'_, S> {
    fn get(&mut self, dimension: usize) -> f32 {
        let mut value = self.sampler.get(dimension);
        if dimension == layout::FILM || dimension == layout::FILM + 1 {
            let axis = dimension - layout::FILM;
            value = ((self.pixel[axis] + value) / self.resolution[axis])
                .min(qmc::radical_inverse::ONE_MINUS_EPSILON_F32);
        }
        self.numbers.push((dimension, value));
        value
    }
}

impl SplatEstimator for Erpt<'_> {
    type Unit = ErptUnit;
    type Total = ChainStatistics;

    fn new_total(&self, _resolution: [usize; 2]) -> Result<ChainStatistics, RenderError> {
        Ok(ChainStatistics::default())
    }

    fn new_unit(&self) -> ErptUnit {
        ErptUnit::default()
    }

    fn merge_unit(&self, total: &mut ChainStatistics, unit: ErptUnit, _kept: bool) {
        total.chains += unit.chains;
        total.large_steps.add(&unit.work.large_steps);
        total.small_steps.add(&unit.work.small_steps);
    }

    fn trace<S: PixelSampler + ?Sized>(
        &self,
        unit: &mut ErptUnit,
        path: PixelSampleIndex,
        sampler: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    ) {
        if !(self.deposit > 0.0 && self.deposit.is_finite()) {
            return;
        }
        let ErptUnit {
            scratch,
            numbers,
            seed_splats,
            work,
            chains,
        } = unit;
        numbers.clear();
        seed_splats.clear();
        self.contribution.evaluate(
            scratch,
            &mut RecordedSeed {
                sampler,
                pixel: [path.pixel.0 as f32, path.pixel.1 as f32],
                resolution: self.resolution,
                numbers,
            },
            seed_splats,
            counters,
        );
        splats.add_rejected(seed_splats.rejected_samples());
        let seed_importance = importance(seed_splats.splats());
        if !(seed_importance > 0.0 && seed_importance.is_finite())
            || seed_splats.rejected_samples() > 0
        {
            return;
        }
        // The seed's number in the render: pass-major, as the driver numbers
        // pixel samples.
        let seed_index = path.sample_index * self.pixels
            + path.pixel.1 as u64 * self.width
            + path.pixel.0 as u64;
        let mut random = SeekablePcg::new(self.seed ^ CHAIN_KEY, seed_index);
        let expected = seed_importance / (self.chain_length as f64 * self.deposit);
        let count = (random.next_f64() + expected).floor() as u64;
        for chain_index in 0..count {
            let stream = qmc::hash::hash2(seed_index, chain_index);
            let chain_sampler = MetropolisSampler::from_numbers(
                numbers,
                self.seed ^ CHAIN_KEY,
                stream,
                self.settings.mutation.clone(),
            );
            let mut chain = Chain::new(chain_sampler, seed_splats.clone(), seed_importance);
            work.splats.clear();
            chain.mutate(
                &self.contribution,
                scratch,
                self.chain_length,
                self.deposit,
                work,
                &|| false,
            );
            for splat in work.splats.splats() {
                let _ = splats.add(splat.raster_position, splat.rgb);
            }
            splats.add_rejected(work.splats.rejected_samples());
        }
        *chains += count;
        counters.add(&work.counters);
        work.counters = TraceCounters::default();
    }
}
