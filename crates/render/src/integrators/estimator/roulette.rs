//! Russian roulette: the rule every walk and every evaluation of a fixed
//! path decides by, so that a rebuilt path takes its seed's decision from
//! the same number.

use crate::spectrum::SampledSpectrum;

/// Russian roulette at vertex `depth` (the rule of pbrt-v4's
/// `PathIntegrator`, Pharr, Jakob & Humphreys, *Physically Based
/// Rendering*, 4th ed.): from `start_depth` on, a path whose
/// `roulette_throughput` is below 1 survives with probability
/// max(throughput, 0.05), decided by the number `u` gives (read only
/// then). Returns the probability to divide the
/// throughput by (1 without roulette), or `None` when the path ends.
#[inline]
pub(crate) fn russian_roulette(
    roulette_throughput: f32,
    depth: u32,
    start_depth: u32,
    u: impl FnOnce() -> f32,
) -> Option<f32> {
    if depth + 1 >= start_depth && roulette_throughput < 1.0 {
        let survival = roulette_throughput.max(0.05);
        (u() < survival).then_some(survival)
    } else {
        Some(1.0)
    }
}

/// The throughput Russian roulette decides on (pbrt-v4's `rrBeta`): the
/// largest component of `beta` with the refractions' η² undone
/// (`eta_scale`, the product of η² of the refractions so far) and, through
/// media, over the mean spectral density ratio `mean_density_ratio` of the
/// hero wavelengths (`None` without media).
#[inline(always)]
pub(crate) fn roulette_throughput(
    beta: SampledSpectrum,
    eta_scale: f32,
    mean_density_ratio: Option<f32>,
) -> f32 {
    match mean_density_ratio {
        None => (beta * eta_scale).max_component(),
        Some(mean_ratio) => (beta * (eta_scale / mean_ratio)).max_component(),
    }
}
