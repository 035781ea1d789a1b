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
//! The renderer knows none of them: adding an integrator is a new module
//! and its line in the registry (`integrator_registry!`), which makes its
//! [`IntegratorKind`] with name and help line, its variant of
//! [`IntegratorSettings`] and its construction; the command line takes its
//! names from [`IntegratorKind::ALL`].

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

/// The MIS heuristic lives with the other sampling formulas (materials use
/// it too); integrators name it here.
pub use crate::sampling::MisHeuristic;
pub use driver::{DriverStatistics, FilmObserver, RenderError, RunControl};

use crate::film::Film;
use crate::image::Image;
use crate::scene::Scene;

/// The integrator registry: for each integrator its variant of
/// [`IntegratorKind`] (and, with settings of its own, of
/// [`IntegratorSettings`]), its command-line name, its type and a help line.
/// Each line makes the variant with its docs, its entry in
/// [`IntegratorKind::ALL`], its help line and its line of
/// [`IntegratorSettings::create`]: the integrator's type has
/// `new(path_settings)`, or `new(settings, path_settings)` when it has
/// settings of its own.
macro_rules! integrator_registry {
    ($(
        $(#[$doc:meta])*
        $variant:ident $(($settings:ty))? = $name:literal, $integrator:ty, $help:literal;
    )*) => {
        /// The integrators a user can choose (see `integrator_registry!`).
        #[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
        pub enum IntegratorKind {
            $($(#[$doc])* $variant,)*
        }

        impl IntegratorKind {
            /// Every integrator with its command-line name.
            pub const ALL: [(IntegratorKind, &'static str); [$($name),*].len()] =
                [$((IntegratorKind::$variant, $name)),*];

            /// One line on what the integrator does (the command line's help;
            /// no closing full stop, as clap's other help lines).
            pub fn help(self) -> &'static str {
                match self {
                    $(IntegratorKind::$variant => $help,)*
                }
            }
        }

        /// An integrator with its own settings (the shared path settings —
        /// depth, Russian roulette, MIS heuristic — are
        /// [`path::PathSettings`]).
        #[derive(Debug, Clone, PartialEq)]
        pub enum IntegratorSettings {
            $(
                #[doc = concat!(
                    "[`IntegratorKind::", stringify!($variant), "`]"
                    $(, " with its [`", stringify!($settings), "`]")?, "."
                )]
                $variant $(($settings))?,
            )*
        }

        impl From<IntegratorKind> for IntegratorSettings {
            /// The integrator with its default settings.
            fn from(kind: IntegratorKind) -> Self {
                match kind {
                    $(IntegratorKind::$variant => Self::$variant $((<$settings>::default()))?,)*
                }
            }
        }

        impl IntegratorSettings {
            /// Which integrator these are the settings of.
            pub fn kind(&self) -> IntegratorKind {
                match self {
                    $(Self::$variant { .. } => IntegratorKind::$variant,)*
                }
            }

            /// The integrator, with the shared path settings `path_settings`.
            pub fn create(&self, path_settings: path::PathSettings) -> Box<dyn Integrator> {
                match self.clone() {
                    $(
                        integrator_registry!(@pattern $variant, settings $(, $settings)?) =>
                            integrator_registry!(@create $integrator, path_settings, settings $(, $settings)?),
                    )*
                }
            }
        }
    };
    (@pattern $variant:ident, $bound:ident) => { Self::$variant };
    (@pattern $variant:ident, $bound:ident, $settings:ty) => { Self::$variant($bound) };
    (@create $integrator:ty, $path:ident, $bound:ident) => { Box::new(<$integrator>::new($path)) };
    (@create $integrator:ty, $path:ident, $bound:ident, $settings:ty) => {
        Box::new(<$integrator>::new($bound, $path))
    };
}

integrator_registry! {
    /// Unidirectional path tracing with next-event estimation and MIS
    /// (surfaces only: participating media are ignored).
    Path = "path", path::PathIntegrator,
        "Path tracing with next-event estimation and MIS";
    /// Volumetric path tracing: [`Path`](Self::Path) with homogeneous
    /// participating media, index-matched boundaries and spectral MIS
    /// (pbrt-v4's `VolPathIntegrator`; see [`volpath`]).
    VolPath = "volpath", volpath::VolPathIntegrator,
        "Volumetric path tracing (participating media)";
    /// Local quasi-Monte Carlo exploration of Halton-seeded path tracing.
    Lqmc(lqmc::LqmcSettings) = "lqmc", lqmc::LqmcIntegrator,
        "Local quasi-Monte Carlo exploration (Halton-seeded path tracing)";
    /// Light tracing (particle tracing): paths from the lights, every
    /// vertex connected to the camera and splatted (see [`light`]).
    Light = "light", light::LightIntegrator,
        "Light tracing: paths from the lights connected to the camera";
    /// Bidirectional path tracing: every connection of a camera and a
    /// light subpath, weighted by multiple importance sampling (see
    /// [`bdpt`]).
    Bdpt(bdpt::BdptSettings) = "bdpt", bdpt::BdptIntegrator,
        "Bidirectional path tracing (every connection of a camera and a light subpath, balance heuristic by default)";
    /// Primary-sample-space Metropolis light transport (Kelemen et al.
    /// 2002) over path tracing or BDPT (see [`pssmlt`]).
    Pssmlt(pssmlt::PssmltSettings) = "pssmlt", pssmlt::PssmltIntegrator,
        "Primary-sample-space Metropolis light transport (Kelemen et al. 2002) over path tracing or BDPT (--mlt-base)";
    /// Energy redistribution path tracing (Cline et al. 2005): path-traced
    /// seeds whose energy short Metropolis chains redistribute (see
    /// [`erpt`]).
    Erpt(erpt::ErptSettings) = "erpt", erpt::ErptIntegrator,
        "Energy redistribution path tracing (Cline et al. 2005): path-traced seeds, short Metropolis chains from each";
    /// Multiplexed Metropolis light transport (Hachisuka et al. 2014):
    /// chains per path depth over one BDPT strategy each (see [`mmlt`]).
    Mmlt(mmlt::MmltSettings) = "mmlt", mmlt::MmltIntegrator,
        "Multiplexed Metropolis light transport (Hachisuka et al. 2014): chains per path depth, one BDPT strategy per sample";
    /// Vertex connection and merging (Georgiev et al. 2012): BDPT plus
    /// progressive photon mapping's merges, one MIS (see [`vcm`]).
    Vcm(vcm::VcmSettings) = "vcm", vcm::VcmIntegrator,
        "Vertex connection and merging (Georgiev et al. 2012): BDPT and progressive photon mapping under one MIS (--vcm-mode)";
}

impl IntegratorKind {
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

impl IntegratorSettings {
    /// The command-line name of the integrator.
    pub fn name(&self) -> &'static str {
        self.kind().name()
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

    /// Each line of the registry gives one integrator its name, help line
    /// and settings.
    #[test]
    fn the_registry_round_trips_names_and_settings() {
        for (kind, name) in IntegratorKind::ALL {
            assert_eq!(IntegratorKind::from_name(name), Some(kind));
            assert_eq!(kind.name(), name);
            assert_eq!(IntegratorSettings::from(kind).kind(), kind);
            assert_eq!(IntegratorSettings::from(kind).name(), name);
            assert!(!kind.help().is_empty() && !kind.help().ends_with('.'));
        }
        assert_eq!(IntegratorKind::from_name("sppm"), None);
    }
}
