//! Local quasi-Monte Carlo exploration (LQMC; Tessari, Hanika &
//! Dachsbacher): Halton-seeded path tracing with next-event estimation
//! whose every splat event is explored locally in primary sample space by
//! a Cranley–Patterson-rotated rank-1 lattice on a tile around the seed's
//! numbers (Alg. 1), with the prefix up to a breakup vertex rebuilt from the
//! lattice numbers and reconnected to the seed's suffix.
//!
//! Unlike the authors' renderer, the estimator includes the probability
//! `P(b | X_j)` of the breakup vertex and class membership of every member
//! (see [`estimator`]), and every seed contribution reaches the image.
//!
//! Modules: [`settings`] (options and defaults), [`path_record`] and
//! [`seed_path`] (the seed, an observer of the path-space walk, through
//! media too), [`classification`] (classes, breakup CDF),
//! [`explored_dimensions`] (dimensions and tiles), [`lattice_step`] (tile
//! transform, closest point, shift), [`prefix_rebuild`] (members),
//! [`seed_film`] (where seeds lie on the image and how their values land),
//! [`seed_screen`] (seeds path-traced alone where nothing could be explored),
//! [`class_selection`] (a pilot that keeps the classes whose exploration pays),
//! [`path_walk`] (contribution and suffix density of a path),
//! [`medium_segment`] and [`volume_walk`] (the same
//! through homogeneous media, as `volpath` traces them), [`segment_cache`]
//! (members reuse the seed's traced suffix segments),
//! [`estimator`] (Eq. 9 extended), [`statistics`] (`--stats`),
//! [`integrator`] (LQMC behind the integrator interface),
//! [`exploration`] (one pixel sample), [`progression_variance`] (the
//! variance layer of LQMC renders).

pub mod class_selection;
pub mod classification;
pub mod estimator;
pub mod exploration;
pub mod explored_dimensions;
pub mod integrator;
pub mod lattice_step;
pub mod medium_segment;
pub mod path_record;
pub mod path_walk;
pub mod prefix_rebuild;
pub mod seed_film;
pub mod seed_path;
pub mod seed_screen;
pub mod segment_cache;
pub mod settings;
pub mod statistics;
pub mod volume_walk;

pub use super::progression_variance::{self, ProgressionVariance};
pub use class_selection::ClassSelectionReport;
pub use classification::PathClass;
pub use exploration::{ClassDensity, LqmcContext, LqmcScratch, render_pixel_sample};
pub use integrator::{LqmcDetails, LqmcIntegrator};
pub use settings::{
    BreakupChoice, ClassParameters, ClassSelection, ExploredEffects, LatticeScramble, LqmcSettings,
};
pub use statistics::{ClosestPointTiming, FailureReason, LqmcStatistics};
