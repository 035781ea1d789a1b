//! The Markov-chain driver: Metropolis sampling of primary sample space
//! (Kelemen et al. 2002), shared by every Metropolis integrator. An
//! integrator gives it a [`PathContribution`] — what one point of primary
//! sample space contributes to the film, as splats — and the driver runs
//! the chains over it:
//!
//! 0. **Groups**: the chains are split into eight independent groups
//!    (fewer with fewer than eight chains), each with its own bootstrap
//!    and its share of the chains and of the mutations per pass; each
//!    group renders the image on its own and the film holds their mean, so
//!    the spread of the groups' images gives the variance layer, the
//!    normalisation's error included ([`ChainBatches`]).
//! 1. **Bootstrap**: per group, its share of the `bootstrap_samples`
//!    independent points (each the first iteration of a
//!    [`MetropolisSampler`] keyed by the seed, the group and the sample's
//!    index, i.e. uniform numbers); the normalisation `b = mean I(u)`, `I`
//!    the target ([`importance`]: the luminance of the contribution summed
//!    over its splats).
//! 2. **Chain starts**: each chain picks a sample of its group's bootstrap
//!    with probability proportional to its `I`, replays it, and continues
//!    on a random stream of its own (two chains that pick one sample do not
//!    run one chain twice).
//! 3. **Passes**: a pass is one mutation per pixel, shared out over the
//!    chains in a fixed way; every mutation splats the proposal with weight
//!    `a · b / I(proposal)` and the current state with `(1 − a) · b /
//!    I(current)` (expected-value splatting, `a = min(1, I(proposal) /
//!    I(current))`), then accepts with probability `a`. Chains run in
//!    parallel; their splats merge in chain order, so the image is the same
//!    for any number of threads. The film's splat scale is one over the
//!    mutations per pixel of the whole passes, as for path samples: a
//!    mutation stands for one uniform path sample.
//!
//! A time budget or Ctrl-C is checked before every pass and by every chain
//! during it; a pass cut short is dropped whole (its splats would favour
//! the chains that ran). Splats with a NaN or infinite value are dropped
//! and counted with the film's non-finite samples; a proposal whose
//! contribution is not finite or not positive is rejected. When the
//! bootstrap finds no light (`b = 0`), the image is black, without chains
//! (no 0/0: pbrt-v4 issues #476, #477).

use super::driver::{DriverStatistics, RenderError, RunControl};
use super::{IntegratorDetails, IntegratorRender, TraceCounters};
use crate::film::{Film, Splat, SplatBuffer};
use crate::sampler::{MetropolisSampler, MutationSettings, SampleSource};
use crate::scene::Scene;
use qmc::random::SeekablePcg;
use rayon::prelude::*;

/// What one point of primary sample space contributes to the film: the
/// function the chains sample.
pub trait PathContribution: Sync {
    /// A thread's scratch memory.
    type Scratch: Send;

    /// Fresh scratch memory.
    fn new_scratch(&self) -> Self::Scratch;

    /// Evaluates the path sample of `source`'s numbers into `splats`
    /// (empty on entry): every contribution at its raster position, scaled
    /// so that the mean over uniform numbers of the splats, times pixels,
    /// is the image (as a pixel sample's over one pixel).
    fn evaluate<S: SampleSource + ?Sized>(
        &self,
        scratch: &mut Self::Scratch,
        source: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    );
}

/// The chains' target `I`: the luminance (Rec. 709 Y, as pbrt-v4 and
/// Mitsuba) of the contribution, summed over its splats, plus 10⁻³ of its
/// absolute RGB sum. The small second term makes `I > 0` wherever the
/// contribution is not zero (a spectral estimate's luminance can be zero
/// or negative where its RGB is not), which the estimator `b f / I` needs
/// to be unbiased.
pub fn importance(splats: &[Splat]) -> f64 {
    splats
        .iter()
        .map(|splat| {
            let rgb = splat.rgb.map(f64::from);
            let luminance = crate::spectrum::linear_srgb_luminance_f64(rgb);
            luminance.max(0.0) + 1e-3 * rgb.iter().map(|value| value.abs()).sum::<f64>()
        })
        .sum()
}

/// The chain settings.
#[derive(Debug, Clone, PartialEq)]
pub struct ChainSettings {
    /// Independent samples for the normalisation and the starts (pbrt-v4
    /// and Mitsuba: 100 000).
    pub bootstrap_samples: u64,
    /// Chains (pbrt-v4: 1000).
    pub chains: u64,
    /// The mutations.
    pub mutation: MutationSettings,
}

impl Default for ChainSettings {
    fn default() -> Self {
        Self {
            bootstrap_samples: 100_000,
            chains: 1000,
            mutation: MutationSettings::default(),
        }
    }
}

/// Proposals and acceptances of one mutation type.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct MutationCount {
    /// Proposals made.
    pub proposed: u64,
    /// Proposals accepted.
    pub accepted: u64,
}

impl MutationCount {
    /// The acceptance rate (0 without proposals).
    pub fn rate(&self) -> f64 {
        if self.proposed == 0 {
            0.0
        } else {
            self.accepted as f64 / self.proposed as f64
        }
    }

    /// Adds another count.
    pub fn add(&mut self, other: &MutationCount) {
        self.proposed += other.proposed;
        self.accepted += other.accepted;
    }
}

/// What the chains did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ChainStatistics {
    /// The normalisation `b`: the mean target over the bootstrap (summed
    /// over the targets), averaged over the groups of chains.
    pub normalization: f64,
    /// Bootstrap samples evaluated (over all targets).
    pub bootstrap_samples: u64,
    /// Bootstrap samples with a positive target.
    pub bootstrap_nonzero: u64,
    /// Chains run.
    pub chains: u64,
    /// Large steps.
    pub large_steps: MutationCount,
    /// Small steps.
    pub small_steps: MutationCount,
    /// Seconds of the bootstrap.
    pub bootstrap_seconds: f64,
    /// Seconds of the chains' passes.
    pub chain_seconds: f64,
}

impl ChainStatistics {
    /// Mutations made (every proposal, kept passes or not).
    pub fn mutations(&self) -> u64 {
        self.large_steps.proposed + self.small_steps.proposed
    }

    /// A report for the command line.
    pub fn report(&self) -> String {
        let mutations = self.mutations();
        format!(
            "Markov chains: {} chains, normalisation b = {:.6} from {} bootstrap samples ({} with light, {:.2} s); {} mutations in {:.2} s ({:.3} M mutations/s); acceptance: large steps {:.3} ({} proposed), small steps {:.3} ({} proposed)",
            self.chains,
            self.normalization,
            self.bootstrap_samples,
            self.bootstrap_nonzero,
            self.bootstrap_seconds,
            mutations,
            self.chain_seconds,
            mutations as f64 / self.chain_seconds.max(1e-9) / 1e6,
            self.large_steps.rate(),
            self.large_steps.proposed,
            self.small_steps.rate(),
            self.small_steps.proposed,
        )
    }
}

/// The chains' film and statistics.
pub struct ChainOutput {
    /// The film: splats only, to be scaled by one over the completed
    /// mutations per pixel.
    pub film: Film,
    /// The driver's measurements (samples: bootstrap samples and
    /// mutations; completed samples per pixel: mutations per pixel).
    pub statistics: DriverStatistics,
    /// The chains' own.
    pub chains: ChainStatistics,
}

/// The bootstrap: independent samples of primary sample space, each the
/// first state of a [`MetropolisSampler`] keyed by the seed and its index,
/// so that a chain can start from any of them by replaying it.
pub struct Bootstrap {
    /// Per sample, the running sum of the targets (zero for samples with a
    /// NaN or infinite splat).
    cumulative: Vec<f64>,
    /// Samples with a positive target.
    pub nonzero: u64,
    /// Rays traced.
    pub counters: TraceCounters,
}

impl Bootstrap {
    /// Evaluates `count` (at least 1) samples of `contribution` in
    /// parallel (the same values for any number of threads).
    pub fn run<C: PathContribution>(
        contribution: &C,
        seed: u64,
        count: u64,
        mutation: &MutationSettings,
    ) -> Self {
        let evaluated: Vec<(f64, TraceCounters)> = (0..count.max(1))
            .into_par_iter()
            .map_init(
                || (contribution.new_scratch(), SplatBuffer::new()),
                |(scratch, splats), index| {
                    let mut sampler = MetropolisSampler::new(seed, index, mutation.clone());
                    let mut counters = TraceCounters::default();
                    splats.clear();
                    contribution.evaluate(scratch, &mut sampler, splats, &mut counters);
                    let value = importance(splats.splats());
                    let finite = value.is_finite() && splats.rejected_samples() == 0;
                    (if finite { value } else { 0.0 }, counters)
                },
            )
            .collect();
        let mut cumulative = Vec::with_capacity(evaluated.len());
        let mut sum = 0.0;
        let mut nonzero = 0;
        let mut counters = TraceCounters::default();
        for (value, sample_counters) in &evaluated {
            sum += value;
            cumulative.push(sum);
            nonzero += u64::from(*value > 0.0);
            counters.add(sample_counters);
        }
        Self {
            cumulative,
            nonzero,
            counters,
        }
    }

    /// The samples evaluated.
    pub fn samples(&self) -> u64 {
        self.cumulative.len() as u64
    }

    /// The normalisation `b`: the mean target.
    pub fn normalization(&self) -> f64 {
        self.cumulative.last().copied().unwrap_or(0.0) / self.cumulative.len().max(1) as f64
    }

    /// The sample a uniform number `u` picks in proportion to the targets.
    pub fn pick(&self, u: f64) -> u64 {
        let target = u * self.cumulative.last().copied().unwrap_or(0.0);
        self.cumulative
            .partition_point(|&value| value <= target)
            .min(self.cumulative.len().saturating_sub(1)) as u64
    }
}

impl ChainOutput {
    /// The render of a Metropolis integrator called `name`: the film, the
    /// driver's measurements and the chains' report as its details.
    pub fn into_render(self, name: &'static str) -> IntegratorRender {
        IntegratorRender {
            film: self.film,
            statistics: self.statistics,
            variance: None,
            auxiliary_images: Vec::new(),
            details: Some(Box::new(ChainDetails {
                name,
                chains: self.chains,
            })),
        }
    }
}

/// A Metropolis integrator's statistics (`--stats`).
pub struct ChainDetails {
    /// The integrator's name.
    pub name: &'static str,
    /// What its chains did.
    pub chains: ChainStatistics,
}

impl IntegratorDetails for ChainDetails {
    fn report(&self, _render_seconds: f64, _threads: usize) -> String {
        format!("{}: {}", self.name, self.chains.report())
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// One chain: its sampler, its current state's splats and target.
pub struct Chain {
    sampler: MetropolisSampler,
    current: SplatBuffer,
    current_importance: f64,
    proposal: SplatBuffer,
}

/// What mutations add up to: their splats, rays and acceptances.
#[derive(Default)]
pub struct ChainWork {
    /// The splats, with expected-value weights.
    pub splats: SplatBuffer,
    /// Rays traced.
    pub counters: TraceCounters,
    /// Large steps.
    pub large_steps: MutationCount,
    /// Small steps.
    pub small_steps: MutationCount,
}

impl ChainWork {
    /// Adds another's counts (not its splats).
    pub fn add_counts(&mut self, other: &ChainWork) {
        self.counters.add(&other.counters);
        self.large_steps.add(&other.large_steps);
        self.small_steps.add(&other.small_steps);
    }
}

impl Chain {
    /// A chain in the state `sampler` holds, whose splats are `current`
    /// with target `importance` (positive).
    pub fn new(sampler: MetropolisSampler, current: SplatBuffer, importance: f64) -> Self {
        Self {
            sampler,
            current,
            current_importance: importance,
            proposal: SplatBuffer::new(),
        }
    }

    /// Runs `mutations` mutations, each splatting the proposal with
    /// `a · energy / I(proposal)` and the current state with
    /// `(1 − a) · energy / I(current)` into `work`, then accepting with
    /// probability `a`. `stop` is asked every 64 mutations; returns false
    /// if it stopped the chain.
    pub fn mutate<C: PathContribution>(
        &mut self,
        contribution: &C,
        scratch: &mut C::Scratch,
        mutations: u64,
        energy: f64,
        work: &mut ChainWork,
        stop: &dyn Fn() -> bool,
    ) -> bool {
        for mutation in 0..mutations {
            if mutation % 64 == 0 && stop() {
                return false;
            }
            self.sampler.start_iteration();
            let large_step = self.sampler.is_large_step();
            self.proposal.clear();
            contribution.evaluate(
                scratch,
                &mut self.sampler,
                &mut self.proposal,
                &mut work.counters,
            );
            work.splats.add_rejected(self.proposal.rejected_samples());
            let proposed = importance(self.proposal.splats());
            let acceptance = if proposed.is_finite()
                && proposed > 0.0
                && self.proposal.rejected_samples() == 0
            {
                (proposed / self.current_importance).min(1.0)
            } else {
                0.0
            };
            if acceptance > 0.0 {
                let weight = (acceptance * energy / proposed) as f32;
                for splat in self.proposal.splats() {
                    let _ = work
                        .splats
                        .add(splat.raster_position, splat.rgb.map(|value| value * weight));
                }
            }
            if acceptance < 1.0 {
                let weight = ((1.0 - acceptance) * energy / self.current_importance) as f32;
                for splat in self.current.splats() {
                    let _ = work
                        .splats
                        .add(splat.raster_position, splat.rgb.map(|value| value * weight));
                }
            }
            let count = if large_step {
                &mut work.large_steps
            } else {
                &mut work.small_steps
            };
            count.proposed += 1;
            if self.sampler.uniform() < acceptance as f32 {
                count.accepted += 1;
                self.sampler.accept();
                std::mem::swap(&mut self.current, &mut self.proposal);
                self.current_importance = proposed;
            } else {
                self.sampler.reject();
            }
        }
        true
    }
}

/// The bootstrap's and the chains' stream keys: distinct uses of one seed.
const CHAIN_START_KEY: u64 = 0x6d6c_745f_7374_6172;
const CHAIN_STREAM_KEY: u64 = 0x6d6c_745f_6368_6169;

/// Runs Metropolis chains over `targets` for `scene` under `run`
/// (`run.samples_per_pixel`: mutations per pixel); see the module docs.
/// One target (PSSMLT) is the plain algorithm; with several (MMLT's path
/// depths), each has its own bootstrap normalisation `b_k`, and chains and
/// mutations per pass in proportion to `b_k` (at least one of each where
/// `b_k > 0`), every mutation of target k carrying the energy
/// `b_k · pixels / M_k` (`M_k` its mutations per pass), so the passes add
/// up to the image exactly whatever the rounding.
pub fn render_markov_chains<C: PathContribution>(
    targets: &[C],
    scene: &Scene,
    run: &RunControl<'_>,
    settings: &ChainSettings,
) -> Result<ChainOutput, RenderError> {
    let [width, height] = scene.camera.resolution();
    let film = Film::new([width as usize, height as usize], scene.filter)?;
    render_markov_chains_onto(film, targets, scene, run, settings)
}

/// [`render_markov_chains`] adding its splats to `film` (which may hold
/// camera samples of another estimator: PSSMLT's separate direct light).
pub fn render_markov_chains_onto<C: PathContribution>(
    mut film: Film,
    targets: &[C],
    scene: &Scene,
    run: &RunControl<'_>,
    settings: &ChainSettings,
) -> Result<ChainOutput, RenderError> {
    let [width, height] = scene.camera.resolution();
    let pixels = width as u64 * height as u64;
    let mut statistics = DriverStatistics::default();
    let mut chain_statistics = ChainStatistics::default();

    // 1. The bootstraps: per group of chains, one per target (see
    //    [`ChainBatches`]: the groups are independent renders).
    let clock = std::time::Instant::now();
    let groups = ChainBatches::groups(settings.chains);
    let bootstraps: Vec<Vec<Bootstrap>> = (0..groups)
        .map(|group| {
            let share = |total: u64| group_share(total, group, groups);
            targets
                .iter()
                .enumerate()
                .map(|(index, target)| {
                    Bootstrap::run(
                        target,
                        group_key(run.seed, index, group),
                        share(settings.bootstrap_samples),
                        &settings.mutation,
                    )
                })
                .collect()
        })
        .collect();
    let mut group_totals = vec![0.0; groups];
    for (group, group_bootstraps) in bootstraps.iter().enumerate() {
        for bootstrap in group_bootstraps {
            statistics.rays += bootstrap.counters.rays();
            statistics.samples += bootstrap.samples();
            chain_statistics.bootstrap_samples += bootstrap.samples();
            chain_statistics.bootstrap_nonzero += bootstrap.nonzero;
            let normalization = bootstrap.normalization();
            if normalization > 0.0 && normalization.is_finite() {
                group_totals[group] += normalization;
            }
        }
    }
    chain_statistics.normalization = group_totals.iter().sum::<f64>() / groups as f64;
    chain_statistics.bootstrap_seconds = clock.elapsed().as_secs_f64();
    (run.progress)(0, pixels.saturating_mul(run.samples_per_pixel));
    if !group_totals
        .iter()
        .any(|total| *total > 0.0 && total.is_finite())
    {
        // No light found: the image is black (all passes "done").
        statistics.completed_samples_per_pixel = run.samples_per_pixel;
        return Ok(ChainOutput {
            film,
            statistics,
            chains: chain_statistics,
        });
    }

    // 2. The chains' starts: per group its share of the chains and of the
    //    mutations per pass, per target in proportion to its normalisation.
    //    A group renders the image on its own; the film gets each group's
    //    over the number of groups (a group that found no light renders
    //    black, as it should).
    let mut plans = Vec::new();
    for (group, group_bootstraps) in bootstraps.iter().enumerate() {
        let total = group_totals[group];
        if !(total > 0.0 && total.is_finite()) {
            continue;
        }
        let share = |count: u64| group_share(count, group, groups);
        let (chain_total, group_pixels) = (share(settings.chains.max(1)).max(1), share(pixels));
        for (target, bootstrap) in group_bootstraps.iter().enumerate() {
            let normalization = bootstrap.normalization();
            if !(normalization > 0.0 && normalization.is_finite()) {
                continue;
            }
            let target_share = normalization / total;
            let chains = ((chain_total as f64 * target_share).round() as u64).max(1);
            let mutations = ((group_pixels as f64 * target_share).round() as u64).max(1);
            for chain in 0..chains {
                plans.push(ChainPlan {
                    group,
                    target,
                    index: chain,
                    mutations: mutations * (chain + 1) / chains - mutations * chain / chains,
                    energy: normalization * pixels as f64 / (mutations * groups as u64) as f64,
                });
            }
        }
    }
    chain_statistics.chains = plans.len() as u64;
    // Per thread, a scratch per target.
    let new_scratches = || {
        targets
            .iter()
            .map(|target| target.new_scratch())
            .collect::<Vec<_>>()
    };
    let mut chains: Vec<(ChainPlan, Chain)> = plans
        .into_par_iter()
        .map_init(new_scratches, |scratches, plan| {
            let target = &targets[plan.target];
            let key = group_key(run.seed, plan.target, plan.group);
            let start = bootstraps[plan.group][plan.target]
                .pick(SeekablePcg::new(key ^ CHAIN_START_KEY, plan.index).next_f64());
            let mut sampler = MetropolisSampler::new(key, start, settings.mutation.clone());
            let mut current = SplatBuffer::new();
            let mut counters = TraceCounters::default();
            target.evaluate(
                &mut scratches[plan.target],
                &mut sampler,
                &mut current,
                &mut counters,
            );
            sampler.accept();
            sampler.continue_on_stream(key ^ CHAIN_STREAM_KEY, plan.index);
            let current_importance = importance(current.splats());
            (plan, Chain::new(sampler, current, current_importance))
        })
        .collect();

    // 3. The passes: one mutation per pixel each (over all targets).
    let clock = std::time::Instant::now();
    let mut batches = ChainBatches::new(
        film.resolution(),
        groups,
        chains.iter().map(|(plan, _)| plan.group).collect(),
    );
    let splats_before = (batches.is_some() && run.observer.is_some()).then(|| film.splat_sums());
    let mut pass = 0;
    while pass < run.samples_per_pixel && !run.out_of_time() {
        let outputs: Vec<(ChainWork, bool)> = chains
            .par_iter_mut()
            .map_init(new_scratches, |scratches, (plan, chain)| {
                let mut work = ChainWork::default();
                let finished = chain.mutate(
                    &targets[plan.target],
                    &mut scratches[plan.target],
                    plan.mutations,
                    plan.energy,
                    &mut work,
                    &|| run.out_of_time(),
                );
                (work, finished)
            })
            .collect();
        let complete = outputs.iter().all(|(_, finished)| *finished);
        for (work, _) in &outputs {
            statistics.rays += work.counters.rays();
            statistics.samples += work.large_steps.proposed + work.small_steps.proposed;
            chain_statistics.large_steps.add(&work.large_steps);
            chain_statistics.small_steps.add(&work.small_steps);
        }
        if !complete {
            break;
        }
        // With groups, their sums make the film's splats at the end (each
        // splat filtered once); a live view needs the film every pass.
        if batches.is_none() || run.observer.is_some() {
            film.merge_splat_buffers(
                &outputs
                    .iter()
                    .map(|(work, _)| &work.splats)
                    .collect::<Vec<_>>(),
            );
        }
        if let Some(batches) = &mut batches {
            batches.add_pass(&film, &outputs);
        }
        pass += 1;
        statistics.completed_samples_per_pixel = pass;
        if let Some(observe) = run.observer {
            observe(&film, 1.0 / pass as f64);
        }
        (run.progress)(pass * pixels, pixels.saturating_mul(run.samples_per_pixel));
    }
    chain_statistics.chain_seconds = clock.elapsed().as_secs_f64();
    statistics.stopped_early = statistics.completed_samples_per_pixel < run.samples_per_pixel;
    if let Some(batches) = &batches {
        // A live view's passes were merged into the film: back to its
        // splats before the chains, so that the image is the same bit for
        // bit with or without one.
        let rejected = match &splats_before {
            Some(before) => {
                film.set_splat_sums(before);
                0
            }
            None => batches.rejected_samples,
        };
        film.add_splat_sums(&batches.total(), rejected);
    }
    if let Some(batches) = batches {
        // The chains' variance and that of the film's own camera samples
        // (PSSMLT's separate direct light), independent of each other.
        let mut variance = film.variance_image();
        let splat_scale = 1.0 / pass.max(1) as f64;
        let chains = batches.variance_of_mean(splat_scale);
        for (pixel, chain) in variance.pixels_mut().iter_mut().zip(chains) {
            for channel in 0..3 {
                pixel[channel] += chain[channel] as f32;
            }
        }
        // The camera samples' share of the image mean (PSSMLT's separate
        // direct light) is the same in every group's image; its own error
        // is not in their spread.
        let camera = film.image(0.0);
        let camera_mean = camera
            .pixels()
            .iter()
            .map(|pixel| crate::spectrum::linear_srgb_luminance_f64(pixel.map(f64::from)))
            .sum::<f64>()
            / camera.pixels().len().max(1) as f64;
        let image_means = batches
            .image_means(splat_scale)
            .into_iter()
            .map(|mean| mean + camera_mean)
            .collect();
        film.set_batch_variance(variance, image_means);
    }
    Ok(ChainOutput {
        film,
        statistics,
        chains: chain_statistics,
    })
}

/// Independent groups of chains, the batches of the variance layer: the
/// chains are split into `G` groups (eight, fewer with fewer chains), each
/// with its own bootstraps (1/G of the samples, keyed by the group), its
/// share of the chains and of the mutations per pass: each group renders
/// the image on its own, as an independent replication would, and the film
/// holds their mean. Each group's splats are summed apart, so `s² / G` over
/// the groups' images estimates the variance of the pixel's value — the
/// normalisation's error included, which batches of chains sharing one
/// bootstrap would miss (with a bootstrap of 10 000 samples on a 16-pixel
/// Cornell box, that error was half the variance).
struct ChainBatches {
    /// Each chain's group, in the fixed chain order.
    group_of_chain: Vec<usize>,
    /// Splat sums per group and pixel.
    sums: Vec<Vec<[f64; 3]>>,
    /// Splats dropped as not finite.
    rejected_samples: u64,
}

impl ChainBatches {
    /// Groups (at most).
    const GROUPS: u64 = 8;

    /// The number of groups for `chains` chains: eight, or one per chain
    /// when there are fewer.
    fn groups(chains: u64) -> usize {
        chains.clamp(1, Self::GROUPS) as usize
    }

    /// Sums for a film of `resolution` over `groups` groups (none with one
    /// group: no variance to estimate).
    fn new(resolution: [usize; 2], groups: usize, group_of_chain: Vec<usize>) -> Option<Self> {
        (groups >= 2).then(|| Self {
            group_of_chain,
            sums: vec![vec![[0.0; 3]; resolution[0] * resolution[1]]; groups],
            rejected_samples: 0,
        })
    }

    /// Per pixel, the sum over the groups, in group order: the film's
    /// splats.
    fn total(&self) -> Vec<[f64; 3]> {
        let mut total = self.sums[0].clone();
        for sums in &self.sums[1..] {
            for (pixel, sum) in total.iter_mut().zip(sums) {
                for channel in 0..3 {
                    pixel[channel] += sum[channel];
                }
            }
        }
        total
    }

    /// Adds a whole pass's chain outputs (in chain order), filtered as
    /// `film` filters splats; the groups in parallel, each in chain order.
    fn add_pass(&mut self, film: &Film, outputs: &[(ChainWork, bool)]) {
        self.rejected_samples += outputs
            .iter()
            .map(|(work, _)| work.splats.rejected_samples())
            .sum::<u64>();
        let group_of_chain = &self.group_of_chain;
        self.sums
            .par_iter_mut()
            .enumerate()
            .for_each(|(group, sums)| {
                for ((work, _), _) in outputs
                    .iter()
                    .zip(group_of_chain)
                    .filter(|(_, own)| **own == group)
                {
                    for splat in work.splats.splats() {
                        let rgb = splat.rgb.map(f64::from);
                        film.for_each_splat_pixel(splat.raster_position, |index, weight| {
                            for channel in 0..3 {
                                sums[index][channel] += weight * rgb[channel];
                            }
                        });
                    }
                }
            });
    }

    /// Per group, the mean luminance of its image (`G · sums ·
    /// splat_scale`).
    fn image_means(&self, splat_scale: f64) -> Vec<f64> {
        let scale = self.sums.len() as f64 * splat_scale;
        self.sums
            .iter()
            .map(|sums| {
                sums.iter()
                    .map(|sum| {
                        crate::spectrum::linear_srgb_luminance_f64(sum.map(|value| value * scale))
                    })
                    .sum::<f64>()
                    / sums.len().max(1) as f64
            })
            .collect()
    }

    /// Per pixel, the variance of the mean of the groups' images, each
    /// `G · sums · splat_scale`.
    fn variance_of_mean(&self, splat_scale: f64) -> Vec<[f64; 3]> {
        let count = self.sums.len() as f64;
        let scale = count * splat_scale;
        (0..self.sums[0].len())
            .map(|pixel| {
                let mut variance = [0.0; 3];
                for (channel, value) in variance.iter_mut().enumerate() {
                    let images = self.sums.iter().map(|sums| sums[pixel][channel] * scale);
                    let mean = images.clone().sum::<f64>() / count;
                    let squared: f64 = images.map(|image| (image - mean).powi(2)).sum();
                    *value = squared / (count - 1.0) / count;
                }
                variance
            })
            .collect()
    }
}

/// What one chain does per pass.
struct ChainPlan {
    /// Its group ([`ChainBatches`]).
    group: usize,
    /// Its target.
    target: usize,
    /// Its number among the target's chains.
    index: u64,
    /// Mutations per pass.
    mutations: u64,
    /// The energy of each mutation.
    energy: f64,
}

/// The random key of target `index`: the seed itself for the first (one
/// target: PSSMLT), a hash of it for the others.
fn target_key(seed: u64, index: usize) -> u64 {
    if index == 0 {
        seed
    } else {
        qmc::hash::hash2(seed, index as u64)
    }
}

/// Group `group`'s share of `total` (bootstrap samples, chains, mutations)
/// split over `groups` groups: the shares differ by at most one and sum to
/// `total`.
fn group_share(total: u64, group: usize, groups: usize) -> u64 {
    let (group, groups) = (group as u64, groups as u64);
    total * (group + 1) / groups - total * group / groups
}

/// The random key of target `index` in chain group `group`: the target's
/// key for the first group, a hash of it for the others.
fn group_key(seed: u64, index: usize, group: usize) -> u64 {
    let key = target_key(seed, index);
    if group == 0 {
        key
    } else {
        qmc::hash::hash3(key, group as u64, 0x0067_726f_7570)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::SmallStep;

    /// A contribution without a scene: one splat `[v, 1, 0]`, where `v` is
    /// 10⁴ on the slab u₀ < 10⁻³ (rare and bright: nothing may clamp it),
    /// `1 + u₁` where u₀ > ½ (dimension 1 is read only there: lazy
    /// updates), and 1 elsewhere. ∫v = 10 + 0.499 + 0.75 = 11.249, ∫1 = 1.
    struct Slabs;

    impl PathContribution for Slabs {
        type Scratch = ();

        fn new_scratch(&self) {}

        fn evaluate<S: SampleSource + ?Sized>(
            &self,
            _scratch: &mut (),
            source: &mut S,
            splats: &mut SplatBuffer,
            _counters: &mut TraceCounters,
        ) {
            let u0 = source.get(0);
            let v = if u0 < 1e-3 {
                1e4
            } else if u0 > 0.5 {
                1.0 + source.get(1)
            } else {
                1.0
            };
            let _ = splats.add([0.5, 0.5], [v, 1.0, 0.0]);
        }
    }

    /// Chains started from the bootstrap keep the target I stationary and
    /// splat with expected values: the mean splat per mutation over b is
    /// ∫f / ∫I (b, the bootstrap's estimate of ∫I, is common to all chains
    /// and divided out), the bright slab's contributions unclamped. Per
    /// chain means are independent, so their spread gives the standard
    /// error; the means must be within 4 of it.
    #[test]
    fn chains_integrate_a_function_with_a_rare_bright_part() {
        for (small_step, large_step_probability) in
            [(SmallStep::KELEMEN, 0.3), (SmallStep::PBRT, 0.1)]
        {
            let mutation = MutationSettings {
                large_step_probability,
                small_step,
                step_scales: Vec::new(),
            };
            let bootstrap = Bootstrap::run(&Slabs, 5, 20_000, &mutation);
            let normalization = bootstrap.normalization();
            let chains = 400;
            let mutations = 500;
            let mut means = Vec::new();
            for index in 0..chains {
                let start = bootstrap.pick(SeekablePcg::new(9, index).next_f64());
                let mut sampler = MetropolisSampler::new(5, start, mutation.clone());
                let mut current = SplatBuffer::new();
                Slabs.evaluate(
                    &mut (),
                    &mut sampler,
                    &mut current,
                    &mut TraceCounters::default(),
                );
                sampler.accept();
                sampler.continue_on_stream(11, index);
                let importance = importance(current.splats());
                let mut chain = Chain::new(sampler, current, importance);
                let mut work = ChainWork::default();
                assert!(chain.mutate(
                    &Slabs,
                    &mut (),
                    mutations,
                    normalization,
                    &mut work,
                    &|| false
                ));
                let mut sum = [0.0f64; 2];
                for splat in work.splats.splats() {
                    sum[0] += f64::from(splat.rgb[0]);
                    sum[1] += f64::from(splat.rgb[1]);
                }
                means.push(sum.map(|value| value / mutations as f64));
            }
            // ∫I for I = Y(v, 1, 0) + 10⁻³ (v + 1).
            let integral_v = 11.249;
            let integral_importance = 0.2126 * integral_v + 0.7152 + 1e-3 * (integral_v + 1.0);
            for (channel, integral) in [(0, integral_v), (1, 1.0)] {
                let expected = integral / integral_importance;
                let values: Vec<f64> = means
                    .iter()
                    .map(|mean| mean[channel] / normalization)
                    .collect();
                let mean = values.iter().sum::<f64>() / chains as f64;
                let variance = values
                    .iter()
                    .map(|value| (value - mean).powi(2))
                    .sum::<f64>()
                    / (chains as f64 - 1.0);
                let error = (variance / chains as f64).sqrt();
                assert!(
                    (mean - expected).abs() < 4.0 * error,
                    "{small_step:?}, channel {channel}: {mean} ± {error}, expected {expected}"
                );
            }
        }
    }
}
