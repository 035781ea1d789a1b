//! The estimator pieces the integrators share: the formulas of a camera
//! path's estimate that more than one integrator evaluates, kept in one
//! place so that no integrator borrows them from another and no integrator
//! has its own copy.
//!
//! - [`settings`]: [`PathSettings`], the options every path integrator
//!   takes (depth, Russian roulette, MIS heuristic, film splatting).
//! - [`next_event`]: next-event estimation — choosing a light and a point
//!   on it with a vertex's numbers, and the estimate of one light sample at
//!   a surface (the path tracer's) or at any vertex through media (the
//!   volumetric path tracer's).
//! - [`mis`]: the multiple-importance weights of emission found by
//!   scattering against next-event estimation, with Veach's heuristics
//!   and, through media, the spectral balance heuristic over the hero
//!   wavelengths.
//! - [`roulette`]: Russian roulette, the rule of every walk.
//! - [`shadow`]: shadow rays and their transmittance through media and
//!   null surfaces.
//! - [`emitted_ray`]: the start of a light subpath (light tracing, BDPT)
//!   and its first throughput.
//!
//! The path tracer, the volumetric path tracer, the light tracer, BDPT and
//! LQMC (its seed paths and its value walks over fixed vertices) all call
//! these; the random walk that builds the subpaths is
//! [`super::path_space`].

pub mod emitted_ray;
pub mod mis;
pub mod next_event;
pub mod roulette;
pub mod settings;
pub mod shadow;

pub use settings::PathSettings;
