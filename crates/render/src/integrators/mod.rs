//! Integrators: estimators of the radiance arriving at the camera. Each
//! takes its numbers from a [`crate::sampler::SampleSource`] following the
//! dimension layout of [`crate::sampler::layout`].
//!
//! # The integrator interface
//!
//! An integrator is a module with a type that implements [`Integrator`]:
//! it renders a scene into a film under a [`RunControl`] (samples per pixel,
//! time budget, Ctrl-C, progress) and returns an [`IntegratorRender`]. It
//! does so through one of the shared [`driver`]s — the tile driver for
//! estimators of one pixel sample, the splat driver for integrators that
//! write anywhere on the film — which own the passes, the threads and the
//! deterministic merge order. Its own settings travel in its variant of
//! [`IntegratorSettings`]; its own statistics and images come back in
//! [`IntegratorRender::details`] and [`IntegratorRender::auxiliary_images`].
//! The renderer knows none of them: adding an integrator is a new module,
//! a variant of [`IntegratorKind`] (with its name) and of
//! [`IntegratorSettings`], and its line in [`IntegratorSettings::create`].

pub mod bdpt;
pub mod camera_path;
pub mod driver;
pub mod erpt;
pub mod estimator;
pub mod light;
pub mod lqmc;
pub mod markov_chain;
pub mod mmlt;
pub mod particle_radiance;
pub mod path;
pub mod path_space;
pub mod progression_variance;
pub mod pssmlt;
pub mod vcm;
pub mod volpath;

pub use driver::{DriverStatistics, FilmObserver, RenderError, RunControl};

use crate::film::Film;
use crate::image::Image;
use crate::scene::Scene;

/// The integrators a user can choose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum IntegratorKind {
    /// Unidirectional path tracing with next-event estimation and MIS
    /// (surfaces only: participating media are ignored).
    Path,
    /// Volumetric path tracing: [`Path`](Self::Path) with homogeneous
    /// participating media, index-matched boundaries and spectral MIS
    /// (pbrt-v4's `VolPathIntegrator`; see [`volpath`]).
    VolPath,
    /// Local quasi-Monte Carlo exploration of Halton-seeded path tracing.
    Lqmc,
    /// Light tracing (particle tracing): paths from the lights, every
    /// vertex connected to the camera and splatted (see [`light`]).
    Light,
    /// Bidirectional path tracing: every connection of a camera and a
    /// light subpath, weighted by multiple importance sampling (see
    /// [`bdpt`]).
    Bdpt,
    /// Primary-sample-space Metropolis light transport (Kelemen et al.
    /// 2002) over path tracing or BDPT (see [`pssmlt`]).
    Pssmlt,
    /// Energy redistribution path tracing (Cline et al. 2005): path-traced
    /// seeds whose energy short Metropolis chains redistribute (see
    /// [`erpt`]).
    Erpt,
    /// Multiplexed Metropolis light transport (Hachisuka et al. 2014):
    /// chains per path depth over one BDPT strategy each (see [`mmlt`]).
    Mmlt,
    /// Vertex connection and merging (Georgiev et al. 2012): BDPT plus
    /// progressive photon mapping's merges, one MIS (see [`vcm`]).
    Vcm,
}

impl IntegratorKind {
    /// Every integrator with its command-line name.
    pub const ALL: [(IntegratorKind, &'static str); 9] = [
        (IntegratorKind::Path, "path"),
        (IntegratorKind::VolPath, "volpath"),
        (IntegratorKind::Lqmc, "lqmc"),
        (IntegratorKind::Light, "light"),
        (IntegratorKind::Bdpt, "bdpt"),
        (IntegratorKind::Pssmlt, "pssmlt"),
        (IntegratorKind::Erpt, "erpt"),
        (IntegratorKind::Mmlt, "mmlt"),
        (IntegratorKind::Vcm, "vcm"),
    ];

    /// The integrator called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(k, _)| *k)
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(k, _)| *k == self).unwrap().1
    }

    /// Whether it runs Markov chains ([`markov_chain`]) only: its samples
    /// per pixel are mutations per pixel, and it draws its numbers from its
    /// chains, not from the sampler.
    pub fn runs_markov_chains(self) -> bool {
        matches!(self, IntegratorKind::Pssmlt | IntegratorKind::Mmlt)
    }

    /// Whether it uses Metropolis chains at all (PSSMLT, ERPT): it reports
    /// its chains' statistics.
    pub fn is_metropolis(self) -> bool {
        matches!(
            self,
            IntegratorKind::Pssmlt | IntegratorKind::Erpt | IntegratorKind::Mmlt
        )
    }
}

/// An integrator with its own settings (the shared path settings — depth,
/// Russian roulette, MIS heuristic — are [`path::PathSettings`]).
#[derive(Debug, Clone, PartialEq)]
pub enum IntegratorSettings {
    /// [`IntegratorKind::Path`].
    Path,
    /// [`IntegratorKind::VolPath`].
    VolPath,
    /// [`IntegratorKind::Lqmc`] with its options.
    Lqmc(lqmc::LqmcSettings),
    /// [`IntegratorKind::Light`].
    Light,
    /// [`IntegratorKind::Bdpt`] with its options.
    Bdpt(bdpt::BdptSettings),
    /// [`IntegratorKind::Pssmlt`] with its options.
    Pssmlt(pssmlt::PssmltSettings),
    /// [`IntegratorKind::Erpt`] with its options.
    Erpt(erpt::ErptSettings),
    /// [`IntegratorKind::Mmlt`] with its options.
    Mmlt(mmlt::MmltSettings),
    /// [`IntegratorKind::Vcm`] with its options.
    Vcm(vcm::VcmSettings),
}

impl From<IntegratorKind> for IntegratorSettings {
    /// The integrator with its default settings.
    fn from(kind: IntegratorKind) -> Self {
        match kind {
            IntegratorKind::Path => Self::Path,
            IntegratorKind::VolPath => Self::VolPath,
            IntegratorKind::Lqmc => Self::Lqmc(lqmc::LqmcSettings::default()),
            IntegratorKind::Light => Self::Light,
            IntegratorKind::Bdpt => Self::Bdpt(bdpt::BdptSettings::default()),
            IntegratorKind::Pssmlt => Self::Pssmlt(pssmlt::PssmltSettings::default()),
            IntegratorKind::Erpt => Self::Erpt(erpt::ErptSettings::default()),
            IntegratorKind::Mmlt => Self::Mmlt(mmlt::MmltSettings::default()),
            IntegratorKind::Vcm => Self::Vcm(vcm::VcmSettings::default()),
        }
    }
}

impl IntegratorSettings {
    /// Which integrator these are the settings of.
    pub fn kind(&self) -> IntegratorKind {
        match self {
            Self::Path => IntegratorKind::Path,
            Self::VolPath => IntegratorKind::VolPath,
            Self::Lqmc(_) => IntegratorKind::Lqmc,
            Self::Light => IntegratorKind::Light,
            Self::Bdpt(_) => IntegratorKind::Bdpt,
            Self::Pssmlt(_) => IntegratorKind::Pssmlt,
            Self::Erpt(_) => IntegratorKind::Erpt,
            Self::Mmlt(_) => IntegratorKind::Mmlt,
            Self::Vcm(_) => IntegratorKind::Vcm,
        }
    }

    /// The command-line name of the integrator.
    pub fn name(&self) -> &'static str {
        self.kind().name()
    }

    /// The integrator, with the shared path settings `path_settings`.
    pub fn create(&self, path_settings: path::PathSettings) -> Box<dyn Integrator> {
        match self {
            Self::Path => Box::new(path::PathIntegrator::new(path_settings)),
            Self::VolPath => Box::new(volpath::VolPathIntegrator::new(path_settings)),
            Self::Lqmc(settings) => Box::new(lqmc::LqmcIntegrator::new(*settings, path_settings)),
            Self::Light => Box::new(light::LightIntegrator::new(path_settings)),
            Self::Bdpt(settings) => Box::new(bdpt::BdptIntegrator::new(*settings, path_settings)),
            Self::Pssmlt(settings) => Box::new(pssmlt::PssmltIntegrator::new(
                settings.clone(),
                path_settings,
            )),
            Self::Erpt(settings) => {
                Box::new(erpt::ErptIntegrator::new(settings.clone(), path_settings))
            }
            Self::Mmlt(settings) => {
                Box::new(mmlt::MmltIntegrator::new(settings.clone(), path_settings))
            }
            Self::Vcm(settings) => Box::new(vcm::VcmIntegrator::new(*settings, path_settings)),
        }
    }
}

/// A light-transport algorithm: renders a scene under a run control.
pub trait Integrator: Send + Sync {
    /// Renders `scene` (inside the renderer's thread pool) under `run`.
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError>;
}

/// What an integrator rendered.
pub struct IntegratorRender {
    /// The film: camera samples, and splats of whole passes to be scaled by
    /// the renderer's splat scale.
    pub film: Film,
    /// The driver's measurements.
    pub statistics: DriverStatistics,
    /// The estimated variance of each pixel's value, where the film's own
    /// per-pixel sample variance does not describe it (splatting
    /// integrators); `None` uses [`Film::variance_image`].
    pub variance: Option<Image>,
    /// Further images of the render (splat films, scaled like the film's
    /// splats), each written as one EXR file of named layers.
    pub auxiliary_images: Vec<AuxiliaryImage>,
    /// The integrator's own statistics, if it keeps any.
    pub details: Option<Box<dyn IntegratorDetails>>,
}

impl IntegratorRender {
    /// The render of a driver whose total the integrator keeps nothing of.
    /// A camera-path integrator's render: with film splatting, the
    /// variance layer from its progressions.
    pub fn from_camera_paths(
        output: driver::DriverOutput<Option<progression_variance::ProgressionVariance>>,
    ) -> Self {
        let variance = output
            .total
            .as_ref()
            .map(|progressions| progressions.variance_image());
        Self {
            variance,
            ..Self::from_driver(output)
        }
    }

    pub fn from_driver<T>(output: driver::DriverOutput<T>) -> Self {
        Self {
            film: output.film,
            statistics: output.statistics,
            variance: None,
            auxiliary_images: Vec::new(),
            details: None,
        }
    }
}

/// A further image of a render: named layers of splat films.
pub struct AuxiliaryImage {
    /// What the image is (the integrator's name for it, e.g. `density`).
    pub name: &'static str,
    /// The layers: the first is the image's RGB, the others named layers.
    pub layers: Vec<(&'static str, Film)>,
}

/// An integrator's own statistics.
pub trait IntegratorDetails: Send + std::any::Any {
    /// A report for the command line (`--stats`), for a render of
    /// `render_seconds` on `threads` threads.
    fn report(&self, render_seconds: f64, threads: usize) -> String;

    /// As `Any`, for callers that know the integrator (tests).
    fn as_any(&self) -> &dyn std::any::Any;
}

/// How multiple importance sampling weighs next-event estimation against
/// BSDF sampling.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MisHeuristic {
    /// Veach's power heuristic with exponent 2 (the default).
    #[default]
    Power,
    /// Veach's balance heuristic.
    Balance,
}

impl MisHeuristic {
    /// The weight of a technique with density `own` against one with `other`.
    #[inline]
    pub fn weight(self, own: f32, other: f32) -> f32 {
        match self {
            MisHeuristic::Power => {
                let (a, b) = (own * own, other * other);
                if a.is_infinite() {
                    1.0
                } else if a + b == 0.0 {
                    0.0
                } else {
                    a / (a + b)
                }
            }
            MisHeuristic::Balance => {
                if own + other == 0.0 {
                    0.0
                } else {
                    own / (own + other)
                }
            }
        }
    }

    /// `weight(own, other) / own`: what a sample drawn with density `own`
    /// is multiplied by. For the power heuristic that is `own / (own² +
    /// other²)`, one division where the weight and the estimator's division
    /// by the density made a chain of two (next-event estimation's hot
    /// path). Where that sum is zero or not finite, the two divisions are
    /// done as written, so the edge cases of [`MisHeuristic::weight`] stay.
    #[inline]
    pub fn weight_over_density(self, own: f32, other: f32) -> f32 {
        let sum = match self {
            MisHeuristic::Power => own * own + other * other,
            MisHeuristic::Balance => own + other,
        };
        if sum > 0.0 && sum < f32::INFINITY {
            match self {
                MisHeuristic::Power => own / sum,
                MisHeuristic::Balance => 1.0 / sum,
            }
        } else {
            self.weight(own, other) / own
        }
    }
}

/// Counters an integrator keeps while tracing.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct TraceCounters {
    /// Closest-hit rays.
    pub closest_hit_rays: u64,
    /// Shadow (any-hit) rays.
    pub shadow_rays: u64,
}

impl TraceCounters {
    /// All rays traced.
    pub fn rays(&self) -> u64 {
        self.closest_hit_rays + self.shadow_rays
    }

    /// Adds another set of counters.
    pub fn add(&mut self, other: &TraceCounters) {
        self.closest_hit_rays += other.closest_hit_rays;
        self.shadow_rays += other.shadow_rays;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heuristics_sum_to_one() {
        for heuristic in [MisHeuristic::Power, MisHeuristic::Balance] {
            let (a, b) = (0.3, 2.1);
            let total = heuristic.weight(a, b) + heuristic.weight(b, a);
            assert!((total - 1.0).abs() < 1e-6);
            assert_eq!(heuristic.weight(0.0, 0.0), 0.0);
        }
        assert_eq!(MisHeuristic::Power.weight(f32::INFINITY, 1.0), 1.0);
    }

    /// The one-division form equals the weight divided by the density, to
    /// rounding, and keeps the edge cases of the weight.
    #[test]
    fn weight_over_density_is_the_weight_divided_by_the_density() {
        for heuristic in [MisHeuristic::Power, MisHeuristic::Balance] {
            for (own, other) in [
                (0.3, 2.1),
                (5.0, 0.0),
                (1e-3, 3.0),
                (2e19, 1.0),
                (7.0, 1e30),
            ] {
                let expected = heuristic.weight(own, other) / own;
                let actual = heuristic.weight_over_density(own, other);
                assert!(
                    (actual - expected).abs() <= 1e-6 * expected.abs(),
                    "{heuristic:?} {own} {other}: {actual} vs {expected}"
                );
            }
        }
    }
}
