//! Evaluation of a recorded path in a scene with participating media: the
//! volumetric path tracer's contribution ([`crate::integrators::volpath`]:
//! throughput `beta` over the hero wavelength's densities, spectral MIS
//! through the rescaled path probabilities `r_u`, `r_l`, balance heuristic
//! against next-event estimation, transmittance of shadow rays) of a given
//! vertex sequence, and the density of its suffix (see [`super::path_walk`]).
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
    SPECULAR_DIRECTION_COSINE, WalkInput, WalkedPath, full_path_next_event, non_specular_eta,
};
use super::segment_cache::SegmentReuse;
use super::statistics::FailureReason;
use crate::geometry::{Ray, offset_ray_origin, spawn_ray, spawn_ray_through};
use crate::integrators::TraceCounters;
use crate::integrators::estimator::PathSettings;
use crate::integrators::estimator::roulette::russian_roulette;
use crate::integrators::estimator::shadow::{shadow_ray, shadow_transmittance_with};
use crate::integrators::path_space::medium_leaving;
use crate::light::LightSample;
use crate::sampler::{SampleSource, layout};
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

/// The path state between vertices (volpath's `PathState`).
struct State {
    beta: SampledSpectrum,
    r_u: SampledSpectrum,
    r_l: SampledSpectrum,
    specular_bounce: bool,
    previous_point: Vec3,
    medium: Option<u32>,
}

impl State {
    /// Balance-weighted emission found after the last vertex (volpath's
    /// `add_emission`).
    fn emission(&self, emitted: SampledSpectrum, light_pdf: f32) -> SampledSpectrum {
        let denominator = if self.specular_bounce {
            self.r_u.average()
        } else {
            (self.r_u + self.r_l * light_pdf).average()
        };
        if denominator > 0.0 && !emitted.is_black() {
            self.beta * emitted / denominator
        } else {
            SampledSpectrum::zero()
        }
    }

    /// The light density of found emission (volpath's `light_density`).
    fn light_density(&self, scene: &Scene, light_index: u32, point: Vec3, normal: Vec3) -> f32 {
        if self.specular_bounce {
            return 0.0;
        }
        scene.light_sampler.probability(light_index as usize)
            * scene.lights[light_index as usize].pdf_incident(
                &scene.geometry,
                self.previous_point,
                point,
                normal,
            )
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
        specular_bounce: true,
        previous_point: camera.origin,
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
            let light_pdf = state.light_density(
                scene,
                light_index,
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
        let scatter = |wi: Vec3, wavelengths: &SampledWavelengths| -> (SampledSpectrum, f32) {
            match (&surface, phase) {
                (Some(bsdf), _) => (
                    bsdf.evaluate(wo, wi, wavelengths) * wi.dot(bsdf.frame.normal()).abs(),
                    bsdf.pdf(wo, wi),
                ),
                (None, Some(phase)) => {
                    let value = phase.evaluate(wo, wi);
                    (SampledSpectrum::splat(value), phase.pdf(wo, wi))
                }
                (None, None) => (SampledSpectrum::zero(), 0.0),
            }
        };
        let hit = if vertex.is_medium() {
            None
        } else {
            Some(&vertex.hit)
        };

        if last && let Terminal::NextEvent(connection) = input.terminal {
            let light = &scene.lights[connection.light_index];
            // The full-path breakup b = k samples the light point again
            // with the member's light-position numbers.
            let sample = if full_path_next_event(input) {
                light
                    .sample_incident(
                        &scene.geometry,
                        reference,
                        connection.u_primitive,
                        numbers.get_2d(layout::vertex(m, layout::LIGHT_POSITION)),
                        &wavelengths,
                    )
                    .ok_or(FailureReason::Evaluation)?
            } else if connection.is_delta {
                light
                    .sample_incident(
                        &scene.geometry,
                        reference,
                        connection.u_primitive,
                        connection.u_position,
                        &wavelengths,
                    )
                    .ok_or(FailureReason::Evaluation)?
            } else if connection.is_infinite {
                let wi = connection.direction;
                LightSample {
                    radiance: light.environment_radiance(wi, &wavelengths),
                    wi,
                    point: connection.point,
                    normal: Vec3::ZERO,
                    uv: glam::Vec2::ZERO,
                    pdf: light.pdf_incident(&scene.geometry, reference, reference + wi, Vec3::ZERO),
                    is_delta: false,
                    is_infinite: true,
                }
            } else {
                let wi = (connection.point - reference).normalize();
                LightSample {
                    radiance: light.emitted_radiance(
                        connection.stored_normal,
                        connection.uv,
                        -wi,
                        &wavelengths,
                    ),
                    wi,
                    point: connection.point,
                    normal: connection.front_normal,
                    uv: connection.uv,
                    pdf: light.pdf_incident(
                        &scene.geometry,
                        reference,
                        connection.point,
                        connection.stored_normal,
                    ),
                    is_delta: false,
                    is_infinite: false,
                }
            };
            if sample.radiance.is_black() || !(sample.pdf > 0.0 && sample.pdf.is_finite()) {
                return Err(FailureReason::Evaluation);
            }
            let (value, scatter_pdf) = scatter(sample.wi, &wavelengths);
            if value.is_black() {
                return Err(FailureReason::Evaluation);
            }
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
            let light_pdf = connection.selection_probability * sample.pdf;
            let r_l = state.r_u * light_pdf;
            let denominator = if sample.is_delta {
                r_l.average()
            } else {
                (r_l + state.r_u * scatter_pdf).average()
            };
            if not_positive(denominator) {
                return Err(FailureReason::Evaluation);
            }
            if in_suffix(m + 1) && !connection.is_delta {
                let mut density = sample.pdf as f64;
                if !connection.is_infinite {
                    let to_light = connection.point - vertex.raw_hit.point;
                    let distance_squared = to_light.length_squared() as f64;
                    density *= connection.stored_normal.dot(to_light).abs() as f64
                        / distance_squared.sqrt()
                        / distance_squared;
                }
                suffix_density *= density;
            }
            return finish(
                state.beta * value * transmittance * sample.radiance / denominator,
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
                let specular = vertex.sampled.is_specular();
                let (value, pdf) = if specular {
                    let u_component = numbers.get(layout::vertex(m, layout::SCATTER_COMPONENT));
                    let u = numbers.get_2d(layout::vertex(m, layout::SCATTER_DIRECTION));
                    let sample = bsdf
                        .sample(wo, u_component, u, &mut wavelengths)
                        .ok_or(FailureReason::Evaluation)?;
                    if sample.flags != vertex.sampled
                        || sample.wi.dot(wi) < SPECULAR_DIRECTION_COSINE
                    {
                        return Err(FailureReason::ModeChange);
                    }
                    if sample.is_transmission() {
                        eta_scale *= sample.eta * sample.eta;
                    }
                    (sample.value, sample.pdf)
                } else {
                    eta_scale *= non_specular_eta(vertex, bsdf, wo, wi)?;
                    (bsdf.evaluate(wo, wi, &wavelengths), bsdf.pdf(wo, wi))
                };
                if not_positive(pdf) || value.is_black() {
                    return Err(FailureReason::Evaluation);
                }
                let cosine = wi.dot(bsdf.frame.normal()).abs();
                state.beta *= value * (cosine / pdf);
                state.r_l = state.r_u / pdf;
                state.specular_bounce = specular;
                state.previous_point = reference;
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
                state.specular_bounce = false;
                state.previous_point = reference;
                direction_density = Some(pdf as f64);
            }
        }
        let r_u_mean = state.r_u.average();
        if not_positive(r_u_mean) {
            return Err(FailureReason::Evaluation);
        }
        let roulette_throughput = (state.beta * (eta_scale / r_u_mean)).max_component();
        state.beta /= russian_roulette(
            roulette_throughput,
            m as u32,
            settings.russian_roulette_depth,
            || numbers.get(layout::vertex(m, layout::RUSSIAN_ROULETTE)),
        )
        .ok_or(FailureReason::RussianRoulette)?;
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
    for &index in &scene.environment_lights {
        let emitted = scene.lights[index as usize].environment_radiance(direction, &wavelengths);
        let light_pdf =
            state.light_density(scene, index, state.previous_point + direction, Vec3::ZERO);
        total += state.emission(emitted, light_pdf);
    }
    finish(total, wavelengths, suffix_density)
}

/// Whether `value` is zero, negative or NaN.
fn not_positive(value: f32) -> bool {
    value.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
}

/// The walked path, or `Evaluation` for a black contribution.
fn finish(
    contribution: SampledSpectrum,
    wavelengths: SampledWavelengths,
    suffix_density: f64,
) -> Result<WalkedPath, FailureReason> {
    if contribution.is_black() {
        return Err(FailureReason::Evaluation);
    }
    Ok(WalkedPath {
        contribution,
        wavelengths,
        suffix_density,
        reused_seed_steps: false,
    })
}
