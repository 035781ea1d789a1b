//! Multiplexed Metropolis light transport (Hachisuka, Kaplanyan &
//! Dachsbacher 2014): primary-sample-space chains over BDPT in which each
//! proposal evaluates one strategy only. The chain driver
//! ([`super::markov_chain`]) runs one target per path depth d (segments,
//! 1 … max depth): the number of dimension [`layout::MULTIPLEXED_STRATEGY`]
//! picks one of the depth's strategies (s, t), s + t − 1 = d, uniformly, and
//! the sample's contribution is that strategy's MIS-weighted connection
//! times the number of strategies. Each depth has its own bootstrap
//! normalisation b_d, and gets chains and mutations in proportion to b_d
//! (Tungsten's MMLT: "one chain per path length, its length in proportion
//! to that length's share"), every mutation carrying the same energy.
//! Strategies: every s from 0 to d with t = d + 1 − s, but (1, 1) (left to
//! (0, 2), as in BDPT) and, without camera connections, t = 1.
//!
//! A chain per depth needs a finite depth: with none (`--max-depth` unlimited,
//! a Mitsuba file's `max_depth` −1) MMLT renders depths up to
//! [`UNLIMITED_DEPTH_CAP`] (pbrt-v4's MLT has no unlimited depth either), and
//! says so in the log.

use super::bdpt::{BdptSettings, Bidirectional, BidirectionalScratch};
use super::driver::{RenderError, RunControl};
use super::estimator::PathSettings;
use super::markov_chain::{ChainSettings, PathContribution, render_markov_chains};
use super::{Integrator, IntegratorRender, TraceCounters};
use crate::film::SplatBuffer;
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;

/// The depths rendered when the depth is unlimited (`u32::MAX`); a finite
/// depth is rendered as asked, up to 1024.
pub const UNLIMITED_DEPTH_CAP: u32 = 32;

/// MMLT's settings.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MmltSettings {
    /// Bootstrap (per depth), chains and mutations.
    pub chains: ChainSettings,
}

/// MMLT as an [`Integrator`].
#[derive(Debug, Clone, PartialEq)]
pub struct MmltIntegrator {
    settings: MmltSettings,
    path: PathSettings,
}

impl MmltIntegrator {
    /// MMLT with `settings` over BDPT with `path`.
    pub fn new(settings: MmltSettings, path: PathSettings) -> Self {
        Self { settings, path }
    }
}

impl Integrator for MmltIntegrator {
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError> {
        let deepest = if self.path.max_depth == u32::MAX {
            log::warn!(
                "mmlt needs a finite depth: rendering paths of at most {UNLIMITED_DEPTH_CAP} segments"
            );
            UNLIMITED_DEPTH_CAP
        } else {
            self.path.max_depth.min(1024)
        };
        let depths: Vec<DepthTarget<'_>> = (1..=deepest as usize)
            .map(|depth| {
                Ok(DepthTarget {
                    bidirectional: Bidirectional::new(
                        scene,
                        &self.path,
                        BdptSettings::default(),
                        "mmlt",
                    )?,
                    strategies: strategies(depth, true),
                })
            })
            .collect::<Result<_, RenderError>>()?;
        let output = render_markov_chains(&depths, scene, run, &self.settings.chains)?;
        Ok(output.into_render("mmlt"))
    }
}

/// The strategies (s, t) of paths of `depth` segments.
pub fn strategies(depth: usize, camera_connections: bool) -> Vec<(usize, usize)> {
    (0..=depth)
        .map(|s| (s, depth + 1 - s))
        .filter(|&(s, t)| !(s == 1 && t == 1) && (camera_connections || t > 1))
        .collect()
}

/// The paths of one depth, one strategy per sample.
struct DepthTarget<'a> {
    bidirectional: Bidirectional<'a>,
    strategies: Vec<(usize, usize)>,
}

impl PathContribution for DepthTarget<'_> {
    type Scratch = BidirectionalScratch;

    fn new_scratch(&self) -> BidirectionalScratch {
        BidirectionalScratch::default()
    }

    fn evaluate<S: SampleSource + ?Sized>(
        &self,
        scratch: &mut Self::Scratch,
        source: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    ) {
        let count = self.strategies.len();
        if count == 0 {
            return;
        }
        let choice =
            ((source.get(layout::MULTIPLEXED_STRATEGY) * count as f32) as usize).min(count - 1);
        // The chosen strategy's value times the number of strategies it was
        // chosen from.
        let first = splats.len();
        self.bidirectional.trace_image_plane_sample(
            scratch,
            Some(self.strategies[choice]),
            source,
            splats,
            counters,
        );
        splats.scale_from(first, count as f32);
    }
}
