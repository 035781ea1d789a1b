//! Multiple importance sampling of the two ways a camera path finds light:
//! scattering (BSDF or phase-function sampling) that reaches an emitter,
//! and next-event estimation that samples a point on a light (Veach 1997,
//! ch. 9; the weights of pbrt-v4's `PathIntegrator`). The weights of a next
//! event are [`super::next_event::NextEventTerms`]'.
//!
//! Through media the heuristic is the one-sample balance heuristic over the
//! techniques and the hero wavelengths of pbrt-v4's `VolPathIntegrator`
//! (Pharr, Jakob & Humphreys, *Physically Based Rendering*, 4th ed., §14.2):
//! a path keeps its throughput `β` = f / p₀ and its *rescaled path
//! probabilities* `r_u` (pᵢ / p₀ per wavelength i of the unidirectional
//! technique) and `r_l` (of light sampling), and a contribution is
//! divided by the mean over the wavelengths of their sum (see
//! [`crate::integrators::volpath`]).

use super::PathSettings;
use crate::integrators::path_space::{PreviousScattering, WalkState};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// The density (per unit solid angle at `from`, the light's selection
/// probability included) with which next-event estimation from `from`
/// chooses light `light_index` and samples `point` on it (normal `normal`
/// as stored; zero for infinite lights, whose `point` is `from` plus the
/// direction).
#[inline(always)]
pub(crate) fn light_sampling_density(
    scene: &Scene,
    light_index: u32,
    from: Vec3,
    point: Vec3,
    normal: Vec3,
) -> f32 {
    let light = &scene.lights[light_index as usize];
    scene.light_sampler.probability(light_index as usize)
        * light.pdf_incident(&scene.geometry, from, point, normal)
}

/// The density of next-event estimation from the scattering `previous` at
/// a point found by scattering from there ([`light_sampling_density`]), 0
/// after a delta (next-event estimation cannot produce that path): the
/// light technique's density in the weights of emission found by
/// scattering.
#[inline(always)]
pub(crate) fn emission_light_density(
    scene: &Scene,
    light_index: u32,
    previous: &PreviousScattering,
    point: Vec3,
    normal: Vec3,
) -> f32 {
    if previous.delta {
        return 0.0;
    }
    light_sampling_density(scene, light_index, previous.point, point, normal)
}

/// The MIS weight of emission reached by BSDF sampling after the
/// scattering `previous`, whose light technique has density `light_pdf`
/// ([`emission_light_density`]): 1 after a specular bounce, otherwise the
/// settings' heuristic of the BSDF density against `light_pdf`.
#[inline(always)]
fn scattering_weight(
    settings: &PathSettings,
    previous: &PreviousScattering,
    light_pdf: f32,
) -> f32 {
    if previous.delta {
        1.0
    } else {
        settings.heuristic.weight(previous.pdf, light_pdf)
    }
}

/// The MIS weight of emission reached by BSDF sampling after the scattering
/// `previous` at `point` of light `light_index` (normal `normal` as stored;
/// zero for infinite lights): [`scattering_weight`] with the density with
/// which next-event estimation from there would have chosen the light and
/// sampled the point.
pub(crate) fn emission_weight(
    scene: &Scene,
    settings: &PathSettings,
    light_index: u32,
    previous: &PreviousScattering,
    point: Vec3,
    normal: Vec3,
) -> f32 {
    let light_pdf = emission_light_density(scene, light_index, previous, point, normal);
    scattering_weight(settings, previous, light_pdf)
}

/// The environments' emission along `direction`, reached by scattering
/// after `previous`: `add(emitted, light_pdf)` for each environment light,
/// in the scene's order, with its radiance and its
/// [`emission_light_density`] (what the spectral balance heuristic takes).
#[inline]
pub(crate) fn environment_emission_densities(
    scene: &Scene,
    previous: &PreviousScattering,
    direction: Vec3,
    wavelengths: &SampledWavelengths,
    mut add: impl FnMut(SampledSpectrum, f32),
) {
    for &index in &scene.environment_lights {
        let emitted = scene.lights[index as usize].environment_radiance(direction, wavelengths);
        let light_pdf = emission_light_density(
            scene,
            index,
            previous,
            previous.point + direction,
            Vec3::ZERO,
        );
        add(emitted, light_pdf);
    }
}

/// [`environment_emission_densities`] with each light's MIS weight:
/// `add(emitted, weight)` ([`emission_weight`]).
#[inline]
pub(crate) fn environment_emission(
    scene: &Scene,
    settings: &PathSettings,
    previous: &PreviousScattering,
    direction: Vec3,
    wavelengths: &SampledWavelengths,
    mut add: impl FnMut(SampledSpectrum, f32),
) {
    environment_emission_densities(
        scene,
        previous,
        direction,
        wavelengths,
        |emitted, light_pdf| add(emitted, scattering_weight(settings, previous, light_pdf)),
    );
}

/// Emission `emitted` reached by scattering, balance-weighted over the
/// techniques and the hero wavelengths: `β Le / mean(r_u + r_l p_light)`,
/// where `r_l` is the path's rescaled light-sampling probability at its
/// last scattering (`None` after a delta, which light sampling cannot
/// make: the denominator is then `mean(r_u)`) and `light_pdf` the light's
/// density ([`emission_light_density`]). `None` where the denominator is
/// not positive.
#[inline(always)]
pub(crate) fn balance_weighted_emission(
    beta: SampledSpectrum,
    emitted: SampledSpectrum,
    r_u: SampledSpectrum,
    r_l: Option<SampledSpectrum>,
    light_pdf: f32,
) -> Option<SampledSpectrum> {
    let denominator = match r_l {
        None => r_u.average(),
        Some(r_l) => (r_u + r_l * light_pdf).average(),
    };
    (denominator > 0.0).then(|| beta * emitted / denominator)
}

/// Emission `emitted` found by a walk through media after its last
/// scattering, balance-weighted against next-event estimation with light
/// density `light_pdf` ([`balance_weighted_emission`]): the path's rescaled
/// light-sampling probability is its unidirectional one over the density
/// of the last sampled direction. `None` where nothing arrives. What the
/// volumetric path tracer adds, and LQMC's seeds record, for emission.
#[inline(always)]
pub(crate) fn volumetric_emission(
    walk: &WalkState,
    emitted: SampledSpectrum,
    light_pdf: f32,
) -> Option<SampledSpectrum> {
    if emitted.is_black() {
        return None;
    }
    let r_u = walk.spectral_density_ratio;
    let r_l = (!walk.previous.delta).then(|| r_u / walk.previous.pdf);
    balance_weighted_emission(walk.beta, emitted, r_u, r_l, light_pdf)
}
