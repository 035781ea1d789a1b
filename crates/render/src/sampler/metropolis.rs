//! A Markov chain's state in primary sample space (Kelemen et al. 2002,
//! "A simple and robust mutation strategy for the Metropolis light
//! transport algorithm"): one number per dimension of the layout, mutated
//! by small steps around the current values or replaced by a large step
//! (independent uniform numbers), and restored when the proposal is
//! rejected.
//!
//! Mutation is lazy, as in pbrt-v4's `MLTSampler` and Mitsuba's
//! `PSSMLTSampler`: a dimension is brought up to date only when the path
//! reads it. Each number remembers the iteration it was last updated at;
//! when read, it first takes the value it would have had after the last
//! accepted large step (a fresh uniform number, if it was last set before
//! it), then the small steps of every iteration since (`n` steps of the
//! kernel, composed: symmetric, so the chain keeps detailed balance). A
//! proposal therefore costs only the dimensions its path uses, and paths of
//! different lengths share one state.
//!
//! The chain's own random numbers (mutations, the large-step choice, the
//! acceptance test) come from a PCG stream keyed by the seed and the
//! chain: a chain is the same whatever thread runs it.

use super::SampleSource;
use qmc::random::SeekablePcg;

/// The small-step kernel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SmallStep {
    /// Kelemen et al.'s exponential kernel: a step of size
    /// `s2 · (s1/s2)^u` (u uniform) in a random direction, sizes between
    /// `s1` and `s2` (theirs: 1/1024 and 1/64).
    Exponential {
        /// The smallest step.
        s1: f32,
        /// The largest step.
        s2: f32,
    },
    /// pbrt-v4's normal kernel of standard deviation `sigma` (0.01); `n`
    /// steps are one of standard deviation `sigma √n`.
    Gaussian {
        /// The standard deviation.
        sigma: f32,
    },
}

impl SmallStep {
    /// Kelemen et al. 2002's kernel, s1 = 1/1024, s2 = 1/64.
    pub const KELEMEN: SmallStep = SmallStep::Exponential {
        s1: 1.0 / 1024.0,
        s2: 1.0 / 64.0,
    };
    /// pbrt-v4's `MLTIntegrator` default, σ = 0.01.
    pub const PBRT: SmallStep = SmallStep::Gaussian { sigma: 0.01 };

    /// The most exponential steps composed for one read: past this many
    /// the value is uniform to within float precision anyway, and any
    /// number of symmetric steps is symmetric.
    const MOST_COMPOSED_STEPS: u64 = 64;

    /// `value` after `steps` small steps scaled by `scale`, wrapped to
    /// `[0, 1)`.
    fn apply(self, value: f32, steps: u64, scale: f32, random: &mut SeekablePcg) -> f32 {
        let moved = match self {
            SmallStep::Exponential { s1, s2 } => {
                let mut moved = value as f64;
                let ratio = (s1 as f64 / s2 as f64).ln();
                for _ in 0..steps.min(Self::MOST_COMPOSED_STEPS) {
                    let size = scale as f64 * s2 as f64 * (ratio * random.next_f64()).exp();
                    if random.next_u32() & 1 == 0 {
                        moved += size;
                    } else {
                        moved -= size;
                    }
                }
                moved
            }
            SmallStep::Gaussian { sigma } => {
                let deviation = scale as f64 * sigma as f64 * (steps as f64).sqrt();
                value as f64 + deviation * standard_normal(random)
            }
        };
        wrap(moved)
    }
}

/// A standard normal number (Box–Muller, one of the pair).
fn standard_normal(random: &mut SeekablePcg) -> f64 {
    let u1 = 1.0 - random.next_f64();
    let u2 = random.next_f64();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// `value` wrapped into `[0, 1)` (the primary sample space is a torus).
fn wrap(value: f64) -> f32 {
    let wrapped = value - value.floor();
    let wrapped = wrapped as f32;
    if wrapped >= 1.0 {
        qmc::radical_inverse::ONE_MINUS_EPSILON_F32
    } else {
        wrapped
    }
}

/// One dimension's number with what restores it.
#[derive(Debug, Clone, Copy, Default)]
struct PrimaryNumber {
    value: f32,
    /// The iteration it was last brought up to date at.
    updated: u64,
    backup_value: f32,
    backup_updated: u64,
}

/// The mutation settings of a chain.
#[derive(Debug, Clone, PartialEq)]
pub struct MutationSettings {
    /// The probability of a large step (Kelemen et al.: 0.3).
    pub large_step_probability: f32,
    /// The small-step kernel.
    pub small_step: SmallStep,
    /// Per dimension, a factor on the small steps' size (ERPT's steps per
    /// dimension); dimensions past the end use 1.
    pub step_scales: Vec<f32>,
}

impl Default for MutationSettings {
    fn default() -> Self {
        Self {
            large_step_probability: 0.3,
            small_step: SmallStep::KELEMEN,
            step_scales: Vec::new(),
        }
    }
}

/// A chain's state in primary sample space: a [`SampleSource`] whose
/// numbers are the current proposal (see the module docs).
#[derive(Debug, Clone)]
pub struct MetropolisSampler {
    numbers: Vec<PrimaryNumber>,
    random: SeekablePcg,
    /// The current iteration (the proposal's); 1 is the chain's start.
    iteration: u64,
    /// The iteration of the last accepted large step.
    last_large_step: u64,
    large_step: bool,
    settings: MutationSettings,
}

impl MetropolisSampler {
    /// A chain keyed by `seed` and `stream`, at its first iteration: a
    /// large step, so its first numbers are independent uniform ones (the
    /// same numbers for the same key, so a bootstrap sample can be
    /// replayed as a chain's start).
    pub fn new(seed: u64, stream: u64, settings: MutationSettings) -> Self {
        Self {
            numbers: Vec::new(),
            random: SeekablePcg::new(seed, stream),
            iteration: 1,
            last_large_step: 0,
            large_step: true,
            settings,
        }
    }

    /// A chain whose state is the given numbers (dimension, value), as if
    /// accepted at its first iteration: ERPT's chains start from a seed
    /// drawn by another sampler. Dimensions not given are fresh uniform
    /// numbers when first read.
    pub fn from_numbers(
        numbers: &[(usize, f32)],
        seed: u64,
        stream: u64,
        settings: MutationSettings,
    ) -> Self {
        let mut sampler = Self::new(seed, stream, settings);
        for &(dimension, value) in numbers {
            if dimension >= sampler.numbers.len() {
                sampler
                    .numbers
                    .resize(dimension + 1, PrimaryNumber::default());
            }
            sampler.numbers[dimension] = PrimaryNumber {
                value,
                updated: 1,
                backup_value: value,
                backup_updated: 1,
            };
        }
        sampler.large_step = false;
        sampler.last_large_step = 1;
        sampler
    }

    /// Continues the chain on the random stream `stream` of `seed`: a
    /// chain that starts from a replayed bootstrap sample goes on on a
    /// stream of its own.
    pub fn continue_on_stream(&mut self, seed: u64, stream: u64) {
        self.random = SeekablePcg::new(seed, stream);
    }

    /// Starts the next proposal: a large step with the settings'
    /// probability, else small steps.
    pub fn start_iteration(&mut self) {
        self.iteration += 1;
        self.large_step = self.random.next_f32() < self.settings.large_step_probability;
    }

    /// Whether the current proposal is a large step.
    pub fn is_large_step(&self) -> bool {
        self.large_step
    }

    /// Keeps the proposal as the chain's state.
    pub fn accept(&mut self) {
        if self.large_step {
            self.last_large_step = self.iteration;
        }
    }

    /// Drops the proposal: every number it changed goes back.
    pub fn reject(&mut self) {
        for number in &mut self.numbers {
            if number.updated == self.iteration {
                number.value = number.backup_value;
                number.updated = number.backup_updated;
            }
        }
        self.iteration -= 1;
    }

    /// A uniform number of the chain's own stream (the acceptance test).
    pub fn uniform(&mut self) -> f32 {
        self.random.next_f32()
    }

    /// Brings `dimension` up to date for the current iteration.
    fn update(&mut self, dimension: usize) {
        if dimension >= self.numbers.len() {
            self.numbers.resize(dimension + 1, PrimaryNumber::default());
        }
        let number = self.numbers[dimension];
        if number.updated == self.iteration {
            return;
        }
        let mut current = number;
        // Never read, or last set before the accepted large step: the
        // value it took there.
        if current.updated < self.last_large_step || current.updated == 0 {
            current.value = self.random.next_f32();
            current.updated = self.last_large_step;
        }
        current.backup_value = current.value;
        current.backup_updated = current.updated;
        if self.large_step {
            current.value = self.random.next_f32();
        } else {
            let steps = self.iteration - current.updated;
            let scale = self
                .settings
                .step_scales
                .get(dimension)
                .copied()
                .unwrap_or(1.0);
            current.value =
                self.settings
                    .small_step
                    .apply(current.value, steps, scale, &mut self.random);
        }
        current.updated = self.iteration;
        self.numbers[dimension] = current;
    }
}

impl SampleSource for MetropolisSampler {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        self.update(dimension);
        self.numbers[dimension].value
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sampler(small_step: SmallStep) -> MetropolisSampler {
        MetropolisSampler::new(
            7,
            3,
            MutationSettings {
                large_step_probability: 0.3,
                small_step,
                step_scales: Vec::new(),
            },
        )
    }

    /// Reading a dimension twice in an iteration gives one number;
    /// rejecting restores every number the proposal read.
    #[test]
    fn reject_restores_the_state() {
        let mut chain = sampler(SmallStep::KELEMEN);
        let start: Vec<f32> = (0..10).map(|d| chain.get(d)).collect();
        assert_eq!(chain.get(4), start[4]);
        chain.accept();
        for _ in 0..50 {
            chain.start_iteration();
            let proposal: Vec<f32> = (0..10).map(|d| chain.get(d)).collect();
            assert_ne!(proposal, start);
            chain.reject();
        }
        chain.start_iteration();
        chain.reject();
        // The state is unchanged: a proposal of no change reads it back
        // only through mutations, so compare the stored values.
        let stored: Vec<f32> = chain.numbers.iter().map(|n| n.value).collect();
        assert_eq!(stored, start);
    }

    /// The same key gives the same chain: the first iteration's numbers
    /// (a bootstrap sample) and every proposal after.
    #[test]
    fn a_chain_is_its_key() {
        let run = || {
            let mut chain = sampler(SmallStep::PBRT);
            let mut values = Vec::new();
            for iteration in 0..200 {
                if iteration > 0 {
                    chain.start_iteration();
                }
                for d in 0..(iteration % 7 + 2) {
                    values.push(chain.get(d));
                }
                if chain.uniform() < 0.5 {
                    chain.accept();
                } else {
                    chain.reject();
                }
            }
            values
        };
        assert_eq!(run(), run());
    }

    /// With every proposal accepted, each dimension's marginal stays
    /// uniform (the kernels are symmetric on the torus, lazily composed):
    /// the value of a dimension read at every third iteration only, after
    /// 301 iterations, over 4000 independent chains, chi-square test of 32
    /// bins at the 99.9 % level (χ²₃₁: 61.1).
    #[test]
    fn accepted_chains_keep_uniform_marginals() {
        for small_step in [SmallStep::KELEMEN, SmallStep::PBRT] {
            let bins = 32;
            let mut counts = vec![0u64; bins];
            for stream in 0..4000 {
                let mut chain = MetropolisSampler::new(
                    11,
                    stream,
                    MutationSettings {
                        large_step_probability: 0.05,
                        small_step,
                        step_scales: Vec::new(),
                    },
                );
                let mut value = 0.0;
                for iteration in 0..301 {
                    if iteration > 0 {
                        chain.start_iteration();
                    }
                    chain.get(0);
                    if iteration % 3 == 0 {
                        value = chain.get(5);
                    }
                    chain.accept();
                }
                counts[(value * bins as f32) as usize] += 1;
            }
            let expected = 4000.0 / bins as f64;
            let chi_square: f64 = counts
                .iter()
                .map(|&count| (count as f64 - expected).powi(2) / expected)
                .sum();
            assert!(chi_square < 61.1, "{small_step:?}: chi-square {chi_square}");
        }
    }

    /// A chain started from given numbers reads them back, and reads
    /// uniform numbers elsewhere.
    #[test]
    fn a_chain_starts_from_given_numbers() {
        let mut chain = MetropolisSampler::from_numbers(
            &[(0, 0.25), (3, 0.75)],
            1,
            2,
            MutationSettings::default(),
        );
        assert_eq!(chain.get(0), 0.25);
        assert_eq!(chain.get(3), 0.75);
        let other = chain.get(7);
        assert!((0.0..1.0).contains(&other));
        assert_eq!(chain.get(7), other);
        chain.start_iteration();
        chain.reject();
        assert_eq!(chain.get(0), 0.25);
    }

    /// Small steps stay small: with no large steps, a dimension read every
    /// iteration moves by at most the kernel's largest step per iteration.
    #[test]
    fn exponential_steps_are_between_s1_and_s2() {
        let mut chain = MetropolisSampler::new(
            1,
            1,
            MutationSettings {
                large_step_probability: 0.0,
                small_step: SmallStep::KELEMEN,
                step_scales: vec![1.0, 0.5],
            },
        );
        let mut previous = [chain.get(0), chain.get(1)];
        chain.accept();
        for _ in 0..1000 {
            chain.start_iteration();
            let current = [chain.get(0), chain.get(1)];
            for (d, scale) in [(0, 1.0f32), (1, 0.5)] {
                let moved = (current[d] - previous[d]).abs();
                let moved = moved.min(1.0 - moved);
                assert!(
                    moved <= scale / 64.0 + 1e-6 && moved >= scale / 1024.0 - 1e-6,
                    "dimension {d} moved {moved}"
                );
            }
            chain.accept();
            previous = current;
        }
    }
}
