//! The settings every path integrator shares.

use crate::integrators::MisHeuristic;

/// Settings of the path integrators: depth, Russian roulette and MIS
/// heuristic for every integrator, film splatting and a minimum depth for
/// the camera-path ones (path, volpath).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathSettings {
    /// Maximum number of path segments (Mitsuba's `max_depth`; default 6...
    /// the caller decides; `u32::MAX` for no limit).
    pub max_depth: u32,
    /// The MIS heuristic (default power).
    pub heuristic: MisHeuristic,
    /// The vertex index from which Russian roulette may end paths (default 3).
    pub russian_roulette_depth: u32,
    /// Camera-path integrators (path, volpath): place each sample uniformly
    /// in its pixel and splat it over the pixels of the film's filter
    /// (Mitsuba's film) instead of importance-sampling the filter and adding
    /// it to its own pixel (pbrt-v4's; the default). Splatting lets a
    /// sample reach every pixel its filter covers, as LQMC's splats do, so
    /// it is the like-for-like baseline for LQMC. The variance layer then
    /// comes from the progressions ([`crate::integrators::progression_variance`]).
    pub splat_film: bool,
    /// Paths of fewer segments than this contribute nothing (default 1:
    /// every path). PSSMLT's separate direct lighting (`--mlt-direct-spp`)
    /// leaves paths of 1 and 2 segments to a path tracer of depth 2 and
    /// runs its chains from 3 on (path and volpath observe it).
    pub min_depth: u32,
}

impl Default for PathSettings {
    fn default() -> Self {
        Self {
            max_depth: 6,
            heuristic: MisHeuristic::Power,
            russian_roulette_depth: 3,
            splat_film: false,
            min_depth: 1,
        }
    }
}
