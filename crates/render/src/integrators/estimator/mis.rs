//! Multiple importance sampling of the two ways a camera path finds light:
//! scattering (BSDF or phase-function sampling) that reaches an emitter,
//! and next-event estimation that samples a point on a light (Veach 1997,
//! ch. 9; the weights of pbrt-v4's `PathIntegrator`).

use super::PathSettings;
use crate::scene::Scene;
use glam::Vec3;

/// The MIS weight of emission reached by BSDF sampling: 1 after a specular
/// bounce (next-event estimation cannot produce that path), otherwise the
/// heuristic of the BSDF density against the density with which next-event
/// estimation from `previous_point` would have chosen light `light_index` and
/// sampled `point` (normal `normal` as stored; zero for infinite lights).
#[allow(clippy::too_many_arguments)]
pub(crate) fn emission_weight(
    scene: &Scene,
    settings: &PathSettings,
    light_index: u32,
    specular_bounce: bool,
    previous_point: Vec3,
    previous_bsdf_pdf: f32,
    point: Vec3,
    normal: Vec3,
) -> f32 {
    if specular_bounce {
        return 1.0;
    }
    let light = &scene.lights[light_index as usize];
    let light_pdf = scene.light_sampler.probability(light_index as usize)
        * light.pdf_incident(&scene.geometry, previous_point, point, normal);
    settings.heuristic.weight(previous_bsdf_pdf, light_pdf)
}
