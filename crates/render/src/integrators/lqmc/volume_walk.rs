//! Evaluation of a recorded path in a scene with participating media: the
//! volumetric path tracer's contribution ([`crate::integrators::volpath`]:
//! throughput `beta` over the hero wavelength's densities, spectral MIS
//! through the rescaled path probabilities `r_u`, `r_l`, balance heuristic
//! against next-event estimation, transmittance of shadow rays) of a given
//! vertex sequence, and the density of its suffix (see [`super::path_walk`]).
//! The next-event terms, the balance weights of emission and next events
//! and Russian roulette are the volumetric path tracer's own, called from
//! [`crate::integrators::estimator`].
//!
//! Every segment is traced again between its two vertices (through
//! index-matched boundaries) for its transmittance at the path's own
//! wavelengths; this also checks the reconnection `x_b → x_{b+1}` of a
//! member. The suffix density of a step in a medium is the direction's
//! density times the hero wavelength's free-flight density: σt₀ T₀ at a
//! medium vertex (volume measure), T₀ at a surface (area measure, with the
//! cosine), each over the distance squared.
//!
//! Discrete decisions keep the seed's numbers as in the surface walk:
//! specular components and Russian roulette; the free flight of a prefix
//! segment that reaches a surface is checked by the rebuild. In the suffix,
//! positions are kept and the free-flight decision is part of the density.

use super::medium_segment::{SegmentTarget, trace_segment};
use super::path_record::{CameraVertex, SurfaceVertex, Terminal};
use super::path_walk::{
    FixedScattering, WalkInput, WalkedPath, finish, fixed_next_event, next_event_density,
    not_positive, scatter_at_surface, survive_roulette,
};
use super::segment_cache::SegmentReuse;
use super::statistics::FailureReason;
use crate::geometry::{Ray, offset_ray_origin, spawn_ray, spawn_ray_through};
use crate::integrators::TraceCounters;
use crate::integrators::estimator::PathSettings;
use crate::integrators::estimator::mis::{
    balance_weighted_emission, emission_light_density, environment_emission_densities,
};
use crate::integrators::estimator::next_event::VertexScatter;
use crate::integrators::estimator::roulette::roulette_throughput;
use crate::integrators::estimator::shadow::{shadow_ray, shadow_transmittance_with};
use crate::integrators::path_space::{PreviousScattering, medium_leaving};
use crate::sampler::SampleSource;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// The ray of the segment that leaves `from` (the camera when `None`)
/// along `direction`.
fn segment_ray(
    camera: &CameraVertex,
    scene: &Scene,
    from: Option<&SurfaceVertex>,
    direction: Vec3,
) -> Ray {
    match from {
        None => Ray::with_time(camera.origin, direction, scene.camera.time(camera.u_time)),
        Some(vertex) if vertex.is_medium() => {
            Ray::with_time(vertex.raw_hit.point, direction, vertex.raw_hit.time)
        }
        Some(vertex) => spawn_ray(&vertex.raw_hit, direction),
    }
}

/// The path state between vertices (volpath's walk state, with the
/// rescaled light-sampling probability kept along).
struct State {
    beta: SampledSpectrum,
    r_u: SampledSpectrum,
    r_l: SampledSpectrum,
    /// The last scattering (the camera at first).
    previous: PreviousScattering,
    medium: Option<u32>,
}

impl State {
    /// Balance-weighted emission found after the last vertex, as volpath
    /// weighs it ([`balance_weighted_emission`]).
    fn emission(&self, emitted: SampledSpectrum, light_pdf: f32) -> SampledSpectrum {
        if emitted.is_black() {
            return SampledSpectrum::zero();
        }
        let r_l = (!self.previous.delta).then_some(self.r_l);
        balance_weighted_emission(self.beta, emitted, self.r_u, r_l, light_pdf)
            .unwrap_or(SampledSpectrum::zero())
    }

    /// Multiplies in the free flight of a traced segment that ends at
    /// `end` (`None`: escapes); returns the hero wavelength's free-flight
    /// density (σt₀ T₀ or T₀).
    fn apply_segment(
        &mut self,
        scene: &Scene,
        transmittance: SampledSpectrum,
        end: Option<&SurfaceVertex>,
        wavelengths: &SampledWavelengths,
    ) -> Result<f64, FailureReason> {
        let hero = transmittance[0];
        match end.and_then(|vertex| vertex.medium) {
            Some(medium) => {
                let coefficients = scene.media[medium as usize].coefficients(wavelengths);
                let sigma_t = coefficients.sigma_t();
                let hero_pdf = hero * sigma_t[0];
                if not_positive(hero_pdf) {
                    return Err(FailureReason::Evaluation);
                }
                self.beta *= transmittance * coefficients.sigma_s / hero_pdf;
                let ratio = transmittance * sigma_t / hero_pdf;
                self.r_u *= ratio;
                self.r_l *= ratio;
                Ok(hero_pdf as f64)
            }
            None => {
                if not_positive(hero) {
                    return Err(FailureReason::Evaluation);
                }
                let ratio = transmittance / hero;
                self.beta *= ratio;
                self.r_u *= ratio;
                self.r_l *= ratio;
                Ok(hero as f64)
            }
        }
    }
}

/// Evaluates the path (see the module documentation); `numbers` answers
/// the seed's numbers by dimension.
pub fn walk_volumetric(
    scene: &Scene,
    settings: &PathSettings,
    input: &WalkInput<'_>,
    numbers: &mut dyn SampleSource,
    segments: &mut SegmentReuse<'_>,
) -> Result<WalkedPath, FailureReason> {
    let camera = input.camera;
    let vertices = input.vertices;
    let mut wavelengths = SampledWavelengths::sample_visible(camera.u_wavelength);
    let mut state = State {
        beta: SampledSpectrum::splat(1.0),
        r_u: SampledSpectrum::splat(1.0),
        r_l: SampledSpectrum::splat(1.0),
        previous: PreviousScattering {
            point: camera.origin,
            pdf: 0.0,
            delta: true,
        },
        medium: scene.camera_medium,
    };
    let mut eta_scale = 1.0f32;
    let mut suffix_density = 1.0f64;
    let in_suffix = |step: usize| input.breakup.is_some_and(|b| step >= b);
    let mut counters = TraceCounters::default();
    if vertices.is_empty() && !matches!(input.terminal, Terminal::Environment { .. }) {
        return Err(FailureReason::Evaluation);
    }
    let scattering_count = match input.terminal {
        Terminal::Emission { .. } => vertices.len() - 1,
        _ => vertices.len(),
    };
    // The direction density at the previous vertex for the suffix density
    // (`None` after a specular scattering, whose delta is left out).
    let mut direction_density: Option<f64> = None;
    if in_suffix(0) && !vertices.is_empty() {
        let first = &vertices[0];
        let projection = scene
            .camera
            .project(first.hit.point, camera.u_lens, camera.u_time)
            .ok_or(FailureReason::OutsideImage)?;
        let axis = projection.axis_cosine as f64;
        direction_density = Some(1.0 / (axis * axis * axis));
    }
    for m in 0..vertices.len() {
        let vertex = &vertices[m];
        let from = if m == 0 { None } else { Some(&vertices[m - 1]) };
        let from_point = from.map_or(camera.origin, |from| from.raw_hit.point);
        let to_vertex = vertex.raw_hit.point - from_point;
        let distance = to_vertex.length();
        let direction = to_vertex / distance;
        // Aimed at the vertex from the offset origin (see `spawn_ray_through`).
        let ray = match from {
            Some(from) if !from.is_medium() => {
                spawn_ray_through(&from.raw_hit, vertex.raw_hit.point)
                    .ok_or(FailureReason::Misplaced)?
                    .0
            }
            _ => segment_ray(camera, scene, from, direction),
        };
        let segment = segments.segment(scene, m, state.medium, &wavelengths, |recorder| {
            trace_segment(
                scene,
                ray,
                state.medium,
                SegmentTarget::Vertex(vertex),
                input.tolerance,
                &wavelengths,
                recorder,
            )
        })?;
        state.medium = segment.end_medium;
        let flight_density =
            state.apply_segment(scene, segment.transmittance, Some(vertex), &wavelengths)?;
        if in_suffix(m) {
            // After a specular scattering only the distance along the
            // (delta) direction has a density.
            suffix_density *= flight_density;
            if let Some(density) = direction_density {
                suffix_density *= density * vertex.measure_cosine(direction) as f64
                    / (distance as f64 * distance as f64);
            }
        }
        let wo = -direction;

        if m >= scattering_count {
            // The emitter reached by the last scattering.
            let Terminal::Emission { light_index } = *input.terminal else {
                return Err(FailureReason::Evaluation);
            };
            let emitted = scene.lights[light_index as usize].emitted_radiance(
                vertex.raw_hit.geometric_normal,
                vertex.raw_hit.uv,
                wo,
                &wavelengths,
            );
            let light_pdf = emission_light_density(
                scene,
                light_index,
                &state.previous,
                vertex.raw_hit.point,
                vertex.raw_hit.geometric_normal,
            );
            return finish(
                state.emission(emitted, light_pdf),
                wavelengths,
                suffix_density,
            );
        }
        let last = m + 1 == scattering_count;

        // The scattering at this vertex: value (with cosine), density, and
        // for surfaces the BSDF.
        let surface = if vertex.is_medium() {
            None
        } else {
            let material = scene.shapes[vertex.hit.shape_index as usize]
                .material
                .as_ref()
                .ok_or(FailureReason::Evaluation)?;
            let mut bsdf = material.surface_bsdf_at(&vertex.hit, &wavelengths);
            bsdf.face_camera(wo);
            Some(bsdf)
        };
        let phase = vertex
            .medium
            .map(|medium| scene.media[medium as usize].phase);
        let reference = match surface {
            Some(_) => offset_ray_origin(vertex.hit.point, vertex.hit.geometric_normal, wo),
            None => vertex.raw_hit.point,
        };
        let scatter = match (&surface, phase) {
            (Some(bsdf), _) => VertexScatter::Surface(bsdf),
            (None, Some(phase)) => VertexScatter::Medium(phase),
            (None, None) => return Err(FailureReason::Evaluation),
        };
        let hit = if vertex.is_medium() {
            None
        } else {
            Some(&vertex.hit)
        };

        if last && let Terminal::NextEvent(connection) = input.terminal {
            let (sample, terms) = fixed_next_event(
                scene,
                input,
                connection,
                m,
                reference,
                scatter,
                wo,
                numbers,
                &wavelengths,
            )?;
            let (ray, t_max) =
                shadow_ray(reference, hit, &sample).ok_or(FailureReason::Evaluation)?;
            let shadow_medium = medium_leaving(scene, hit, state.medium, sample.wi);
            // LQMC's paths make thin sheets and masks vertices (no null
            // crossings): shadow rays stop at them.
            let transmittance = shadow_transmittance_with(
                scene,
                ray,
                t_max,
                shadow_medium,
                false,
                &wavelengths,
                &mut counters,
            );
            if transmittance.is_black() {
                return Err(FailureReason::Occluded);
            }
            let denominator = terms.balance_denominator(state.r_u);
            if not_positive(denominator) {
                return Err(FailureReason::Evaluation);
            }
            if in_suffix(m + 1) && !connection.is_delta {
                suffix_density *= next_event_density(connection, sample.pdf, vertex.raw_hit.point);
            }
            return finish(
                state.beta * terms.scattered * transmittance * sample.radiance / denominator,
                wavelengths,
                suffix_density,
            );
        }

        // The continuation to the next vertex (or the environment).
        let wi = if m + 1 < vertices.len() {
            (vertices[m + 1].raw_hit.point - vertex.raw_hit.point).normalize()
        } else if let Terminal::Environment { direction } = input.terminal {
            *direction
        } else {
            return Err(FailureReason::Evaluation);
        };
        match &surface {
            Some(bsdf) => {
                let FixedScattering {
                    factor,
                    pdf,
                    eta_factor,
                    specular,
                } = scatter_at_surface(vertex, bsdf, wo, wi, m, numbers, &mut wavelengths)?;
                eta_scale *= eta_factor;
                state.beta *= factor;
                state.r_l = state.r_u / pdf;
                state.previous = PreviousScattering {
                    point: reference,
                    pdf,
                    delta: specular,
                };
                direction_density = (!specular).then_some(pdf as f64);
                state.medium = medium_leaving(scene, hit, state.medium, wi);
            }
            None => {
                let phase = phase.expect("a medium vertex has a medium");
                let pdf = phase.pdf(wo, wi);
                if not_positive(pdf) {
                    return Err(FailureReason::Evaluation);
                }
                state.beta *= phase.evaluate(wo, wi) / pdf;
                state.r_l = state.r_u / pdf;
                state.previous = PreviousScattering {
                    point: reference,
                    pdf,
                    delta: false,
                };
                direction_density = Some(pdf as f64);
            }
        }
        let r_u_mean = state.r_u.average();
        if not_positive(r_u_mean) {
            return Err(FailureReason::Evaluation);
        }
        state.beta /= survive_roulette(
            roulette_throughput(state.beta, eta_scale, Some(r_u_mean)),
            m,
            settings,
            numbers,
        )?;
        if state.beta.is_black() {
            return Err(FailureReason::Evaluation);
        }
    }

    // Only escaping paths get here: the segment to the environment.
    let Terminal::Environment { direction } = *input.terminal else {
        return Err(FailureReason::Evaluation);
    };
    let from = vertices.last();
    let ray = segment_ray(camera, scene, from, direction);
    let segment = segments.segment(
        scene,
        vertices.len(),
        state.medium,
        &wavelengths,
        |recorder| {
            trace_segment(
                scene,
                ray,
                state.medium,
                SegmentTarget::Escape,
                input.tolerance,
                &wavelengths,
                recorder,
            )
        },
    )?;
    let flight_density = state.apply_segment(scene, segment.transmittance, None, &wavelengths)?;
    if in_suffix(vertices.len()) {
        suffix_density *= flight_density * direction_density.unwrap_or(1.0);
    }
    let mut total = SampledSpectrum::zero();
    environment_emission_densities(
        scene,
        &state.previous,
        direction,
        &wavelengths,
        |emitted, light_pdf| total += state.emission(emitted, light_pdf),
    );
    finish(total, wavelengths, suffix_density)
}
