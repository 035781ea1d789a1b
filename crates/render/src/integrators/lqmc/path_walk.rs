//! Evaluation of a recorded path: the path tracer's contribution
//! `w_t f(X) / p_t(X)` of a given vertex sequence, and the density with
//! which the seed's technique generates the path's suffix from its prefix
//! (`p_t(X) / J`, Eq. 8 of the paper, up to factors every member of an
//! exploration shares).
//!
//! The formulas are the path tracer's, called from
//! [`crate::integrators::estimator`] (next-event estimation's terms and
//! weights, the emission weights, Russian roulette after the third
//! vertex), evaluated on fixed positions instead of sampled ones. Every discrete decision — BSDF
//! component (reflect or refract at a smooth dielectric) and Russian
//! roulette — is decided with the seed's numbers, as LQMC requires (Sec.
//! 3.1: "we do not change the random numbers of the seed path responsible
//! for Russian roulette or BSDF layer selection"); a member whose decisions
//! come out differently fails. Because those numbers are shared by the set,
//! the discrete probabilities belong in `p_t` of the contribution and not in
//! the suffix density (see `estimator`).

use super::path_record::{CameraVertex, LightConnection, SurfaceVertex, Terminal};
use super::segment_cache::{
    IncomingIndependence, SegmentCache, SegmentReuse, SurfaceStep, SurfaceTerminal,
};
use super::statistics::FailureReason;
use crate::camera::CameraProjection;
use crate::geometry::offset_ray_origin;
use crate::integrators::estimator::PathSettings;
use crate::integrators::estimator::mis::{emission_weight, environment_emission};
use crate::integrators::estimator::next_event::{NextEventTerms, VertexScatter};
use crate::integrators::estimator::roulette::{roulette_throughput, russian_roulette};
use crate::integrators::estimator::shadow::light_visible_from_hit;
use crate::integrators::path_space::PreviousScattering;
use crate::light::LightSample;
use crate::material::{BsdfModel, SurfaceBsdf};
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// Directions of a specular scattering recomputed for a member must agree
/// with the recorded ones to this cosine.
pub(super) const SPECULAR_DIRECTION_COSINE: f32 = 1.0 - 1e-4;

/// The η² factor of Russian roulette's throughput at a non-specular vertex
/// (η_t/η_i of a transmission through a rough dielectric, 1 otherwise, as
/// the seed's sampling applied it), or `ModeChange` when the path's
/// directions no longer make the recorded kind of scattering (reflection
/// or transmission about the shading normal): Russian roulette's decisions
/// must see the same factor for the seed and for every member.
pub(super) fn non_specular_eta(
    vertex: &SurfaceVertex,
    bsdf: &SurfaceBsdf,
    wo: Vec3,
    wi: Vec3,
) -> Result<f32, FailureReason> {
    if vertex.sampled.is_empty() {
        return Ok(1.0);
    }
    let normal = bsdf.frame.normal();
    let transmits = wo.dot(normal) * wi.dot(normal) < 0.0;
    if transmits != vertex.sampled.is_transmissive() {
        return Err(FailureReason::ModeChange);
    }
    let front_eta = match bsdf.bsdf.model() {
        BsdfModel::RoughDielectric(dielectric) if transmits => dielectric.eta(),
        _ => return Ok(1.0),
    };
    let eta = if wo.dot(normal) > 0.0 {
        front_eta
    } else {
        1.0 / front_eta
    };
    Ok(eta * eta)
}

/// The value of a path and the density of its suffix.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkedPath {
    /// `w_t f(X) / p_t(X)`, per hero wavelength.
    pub contribution: SampledSpectrum,
    /// The wavelengths (secondary ones possibly terminated by dispersion).
    pub wavelengths: SampledWavelengths,
    /// The continuous density of generating vertices `x_{b+1} .. x_k` from
    /// `x_0 .. x_b` (1 when no breakup vertex was given).
    pub suffix_density: f64,
    /// Whether the steps after `x_{b+1}` and the end were the seed's
    /// recorded ones (see [`super::segment_cache`]).
    pub reused_seed_steps: bool,
}

/// What [`walk`] evaluates.
#[derive(Debug, Clone, Copy)]
pub struct WalkInput<'a> {
    /// The camera vertex.
    pub camera: &'a CameraVertex,
    /// The surface vertices (for an emission path the last is the emitter).
    pub vertices: &'a [SurfaceVertex],
    /// How the path ends.
    pub terminal: &'a Terminal,
    /// Vertices before this index were rebuilt for a member: a
    /// next-event connection from one of them needs a shadow ray.
    pub rebuilt_vertices: usize,
    /// The breakup vertex `b` (paper numbering) whose suffix density is
    /// wanted.
    pub breakup: Option<usize>,
    /// Relative distance within which a re-traced segment must land on its
    /// vertex (scenes with media, whose every segment is traced again).
    pub tolerance: f32,
    /// The wavelengths `SampledWavelengths::sample_visible(camera.u_wavelength)`
    /// when the caller has them already (surface scenes; saves sampling
    /// them again).
    pub wavelengths: Option<SampledWavelengths>,
    /// The camera's projection of the first vertex through the lens point
    /// `camera.origin` (`camera.project(first vertex, u_lens, u_time)`)
    /// when the caller has it already (a member with breakup vertex 0).
    pub first_projection: Option<CameraProjection>,
}

/// Whether `input` is a next-event path at its full-path breakup b = k
/// (every vertex rebuilt, the light point sampled again).
pub(super) fn full_path_next_event(input: &WalkInput<'_>) -> bool {
    matches!(input.terminal, Terminal::NextEvent(connection) if !connection.is_delta)
        && input.breakup.is_some_and(|b| b > input.vertices.len())
}

/// The next event of the path `input` at its last scattering vertex `m`
/// (reference point `reference`, where `scatter` scatters from `wo`): the
/// light sample of its connection and the terms of its estimate
/// ([`NextEventTerms`], the path tracers' own). The full-path breakup
/// b = k samples the light point again with the member's light-position
/// numbers. `Evaluation` where no light arrives or none is scattered
/// towards it.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(super) fn fixed_next_event(
    scene: &Scene,
    input: &WalkInput<'_>,
    connection: &LightConnection,
    m: usize,
    reference: Vec3,
    scatter: VertexScatter<'_>,
    wo: Vec3,
    numbers: &mut dyn SampleSource,
    wavelengths: &SampledWavelengths,
) -> Result<(LightSample, NextEventTerms), FailureReason> {
    let resampled = full_path_next_event(input)
        .then(|| numbers.get_2d(layout::vertex(m, layout::LIGHT_POSITION)));
    let sample = connection_light_sample(scene, connection, reference, resampled, wavelengths)?;
    if sample.radiance.is_black() || !(sample.pdf > 0.0 && sample.pdf.is_finite()) {
        return Err(FailureReason::Evaluation);
    }
    let terms = NextEventTerms::new(
        scatter,
        wo,
        sample.wi,
        wavelengths,
        connection.selection_probability,
        sample.pdf,
        sample.is_delta,
    );
    if terms.scattered.is_black() {
        return Err(FailureReason::Evaluation);
    }
    Ok((sample, terms))
}

/// The light sample of a next-event connection as seen from `reference`
/// (a member's vertex): with `resampled_position` (the full-path breakup
/// b = k) the light point sampled again with those numbers; a delta light
/// sampled again with the seed's numbers; an infinite light in the seed's
/// direction; otherwise the seed's point on the light.
#[inline(always)]
fn connection_light_sample(
    scene: &Scene,
    connection: &LightConnection,
    reference: Vec3,
    resampled_position: Option<[f32; 2]>,
    wavelengths: &SampledWavelengths,
) -> Result<LightSample, FailureReason> {
    let light = &scene.lights[connection.light_index];
    let sample_again = |u_position: [f32; 2]| {
        light
            .sample_incident(
                &scene.geometry,
                reference,
                connection.u_primitive,
                u_position,
                wavelengths,
            )
            .ok_or(FailureReason::Evaluation)
    };
    if let Some(u_position) = resampled_position {
        return sample_again(u_position);
    }
    if connection.is_delta {
        return sample_again(connection.u_position);
    }
    Ok(if connection.is_infinite {
        let wi = connection.direction;
        LightSample {
            radiance: light.environment_radiance(wi, wavelengths),
            wi,
            point: connection.point,
            normal: Vec3::ZERO,
            uv: Vec2::ZERO,
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
                wavelengths,
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
    })
}

/// The density of a (non-delta) next-event connection's light point from
/// the vertex at `from`: the solid-angle density `solid_angle_pdf`, turned
/// into an area density on the light for a light at a finite distance.
#[inline(always)]
pub(super) fn next_event_density(
    connection: &LightConnection,
    solid_angle_pdf: f32,
    from: Vec3,
) -> f64 {
    let mut density = solid_angle_pdf as f64;
    if !connection.is_infinite {
        let to_light = connection.point - from;
        let distance_squared = to_light.length_squared() as f64;
        density *= connection.stored_normal.dot(to_light).abs() as f64
            / distance_squared.sqrt()
            / distance_squared;
    }
    density
}

/// The scattering at a fixed surface vertex `m` from `wo` into `wi`, the
/// continuation to the next vertex.
pub(super) struct FixedScattering {
    /// The throughput's factor `f |cos| / p`.
    pub factor: SampledSpectrum,
    /// The solid-angle density `p` of `wi`.
    pub pdf: f32,
    /// The η² Russian roulette's throughput undoes (1 but for
    /// transmissions).
    pub eta_factor: f32,
    /// The vertex scattered by a specular lobe.
    pub specular: bool,
}

/// Scatters at the surface vertex `vertex` (vertex `m` of the layout, its
/// BSDF `bsdf`) from `wo` into `wi` as the seed did: a specular lobe is
/// sampled again with the seed's numbers (and must give the seed's lobe
/// and, within [`SPECULAR_DIRECTION_COSINE`], `wi`; `wavelengths` then
/// loses its secondary ones where the lobe disperses), other lobes are
/// evaluated.
#[inline(always)]
pub(super) fn scatter_at_surface(
    vertex: &SurfaceVertex,
    bsdf: &SurfaceBsdf,
    wo: Vec3,
    wi: Vec3,
    m: usize,
    numbers: &mut dyn SampleSource,
    wavelengths: &mut SampledWavelengths,
) -> Result<FixedScattering, FailureReason> {
    let specular = vertex.sampled.is_specular();
    let (value, pdf, eta_factor) = if specular {
        let u_component = numbers.get(layout::vertex(m, layout::SCATTER_COMPONENT));
        let u = numbers.get_2d(layout::vertex(m, layout::SCATTER_DIRECTION));
        let sample = bsdf
            .sample(wo, u_component, u, wavelengths)
            .ok_or(FailureReason::Evaluation)?;
        if sample.flags != vertex.sampled || sample.wi.dot(wi) < SPECULAR_DIRECTION_COSINE {
            return Err(FailureReason::ModeChange);
        }
        let eta_factor = if sample.is_transmission() {
            sample.eta * sample.eta
        } else {
            1.0
        };
        (sample.value, sample.pdf, eta_factor)
    } else {
        let eta_factor = non_specular_eta(vertex, bsdf, wo, wi)?;
        (
            bsdf.evaluate(wo, wi, wavelengths),
            bsdf.pdf(wo, wi),
            eta_factor,
        )
    };
    if not_positive(pdf) || value.is_black() {
        return Err(FailureReason::Evaluation);
    }
    let cosine = wi.dot(bsdf.frame.normal()).abs();
    Ok(FixedScattering {
        factor: value * (cosine / pdf),
        pdf,
        eta_factor,
        specular,
    })
}

/// Russian roulette at vertex `m` on `roulette_throughput` with the seed's
/// number: the probability to divide the throughput by, or the failure
/// `RussianRoulette` where the member's path ends.
#[inline(always)]
pub(super) fn survive_roulette(
    roulette_throughput: f32,
    m: usize,
    settings: &PathSettings,
    numbers: &mut dyn SampleSource,
) -> Result<f32, FailureReason> {
    russian_roulette(
        roulette_throughput,
        m as u32,
        settings.russian_roulette_depth,
        || numbers.get(layout::vertex(m, layout::RUSSIAN_ROULETTE)),
    )
    .ok_or(FailureReason::RussianRoulette)
}

/// Whether `value` is zero, negative or NaN.
#[inline(always)]
pub(super) fn not_positive(value: f32) -> bool {
    value.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
}

/// Evaluates the path; `numbers` answers the seed's numbers by dimension;
/// `segments` records or reuses traced segments in scenes with media (see
/// [`super::segment_cache`]; surface scenes trace no segment again).
pub fn walk(
    scene: &Scene,
    settings: &PathSettings,
    input: &WalkInput<'_>,
    numbers: &mut dyn SampleSource,
    segments: &mut SegmentReuse<'_>,
) -> Result<WalkedPath, FailureReason> {
    if !scene.media.is_empty() {
        return super::volume_walk::walk_volumetric(scene, settings, input, numbers, segments);
    }
    let camera = input.camera;
    let vertices = input.vertices;
    let mut wavelengths = input
        .wavelengths
        .unwrap_or_else(|| SampledWavelengths::sample_visible(camera.u_wavelength));
    let mut throughput = SampledSpectrum::splat(1.0);
    let mut eta_scale = 1.0f32;
    // The last scattering, for the emission weights (the camera at first).
    let mut previous = PreviousScattering {
        point: camera.origin,
        pdf: 0.0,
        delta: true,
    };
    let mut suffix_density = 1.0f64;
    // Step `s` generates x_{s+1} from x_s; the suffix density is the
    // product over the steps s ≥ b.
    let in_suffix = |step: usize| input.breakup.is_some_and(|b| step >= b);
    let escapes_at_once = matches!(input.terminal, Terminal::Environment { .. });
    if vertices.is_empty() && !escapes_at_once {
        return Err(FailureReason::Evaluation);
    }
    if in_suffix(0) && !vertices.is_empty() {
        let first = &vertices[0];
        let projection = match input.first_projection {
            Some(projection) => projection,
            None => scene
                .camera
                .project(first.hit.point, camera.u_lens, camera.u_time)
                .ok_or(FailureReason::OutsideImage)?,
        };
        let to_point = first.hit.point - projection.origin;
        let distance_squared = to_point.length_squared() as f64;
        let cosine =
            (first.raw_hit.geometric_normal.dot(to_point).abs() as f64) / distance_squared.sqrt();
        let axis = projection.axis_cosine as f64;
        suffix_density *= cosine / (axis * axis * axis * distance_squared);
    }
    let scattering_count = match input.terminal {
        Terminal::Emission { .. } => vertices.len() - 1,
        _ => vertices.len(),
    };
    let ends_by_next_event = matches!(input.terminal, Terminal::NextEvent(_));
    // Steps that continue to a next vertex or the environment; a
    // next-event path's last step is its end.
    let regular_steps = scattering_count - usize::from(ends_by_next_event);
    for m in 0..scattering_count {
        let vertex = &vertices[m];
        let previous_point = if m == 0 {
            camera.origin
        } else {
            vertices[m - 1].hit.point
        };
        let wo = (previous_point - vertex.hit.point).normalize();
        // The seed's steps from x_{b+2} on, and from x_{b+1} on where that
        // vertex does not care where the member arrives from.
        if let SegmentReuse::Reuse { cache, first } = segments
            && (m >= *first
                || (m + 1 == *first
                    && cache
                        .incoming_independence
                        .get(m)
                        .copied()
                        .flatten()
                        .is_some_and(|independence| {
                            independence.admits(wo, vertex.hit.geometric_normal)
                        })))
            && let Some(end) = cache.surface_terminal
            && end.wavelengths == wavelengths
            && cache.surface_steps.len() == regular_steps
            && cache.surface_steps[m..]
                .iter()
                .all(|step| step.wavelengths == wavelengths)
        {
            return reuse_seed_steps(
                settings,
                cache,
                m,
                ReusedState {
                    throughput,
                    eta_scale,
                    suffix_density,
                },
                &in_suffix,
                scattering_count,
                numbers,
            );
        }
        let Some(material) = &scene.shapes[vertex.hit.shape_index as usize].material else {
            return Err(FailureReason::Evaluation);
        };
        let mut bsdf = material.surface_bsdf_at(&vertex.hit, &wavelengths);
        bsdf.face_camera(wo);
        if let SegmentReuse::Record(cache) = segments {
            let shading_normal = bsdf.frame.normal();
            cache
                .incoming_independence
                .push(bsdf.is_plain_diffuse().then(|| IncomingIndependence {
                    shading_normal,
                    above_shading: wo.dot(shading_normal) > 0.0,
                    above_geometric: wo.dot(vertex.hit.geometric_normal) > 0.0,
                }));
        }
        let reference = offset_ray_origin(vertex.hit.point, vertex.hit.geometric_normal, wo);
        let step = m + 1;
        let last = m + 1 == scattering_count;

        if last && let Terminal::NextEvent(connection) = input.terminal {
            let (sample, terms) = fixed_next_event(
                scene,
                input,
                connection,
                m,
                reference,
                VertexScatter::Surface(&bsdf),
                wo,
                numbers,
                &wavelengths,
            )?;
            if m < input.rebuilt_vertices && !light_visible_from_hit(scene, &vertex.hit, &sample) {
                return Err(FailureReason::Occluded);
            }
            let weight = terms.weight(settings.heuristic);
            let end_density = if connection.is_delta {
                1.0
            } else {
                next_event_density(connection, sample.pdf, vertex.hit.point)
            };
            if in_suffix(step) && !connection.is_delta {
                suffix_density *= end_density;
            }
            // The weight over the light's density in two divisions, as the
            // walk has always evaluated it (see
            // `NextEventTerms::weight_over_density`).
            let end_value = terms.scattered * sample.radiance * (weight / terms.light_pdf());
            if let SegmentReuse::Record(cache) = segments {
                cache.surface_terminal = Some(SurfaceTerminal {
                    wavelengths,
                    value: end_value,
                    density_factor: end_density,
                });
            }
            return Ok(WalkedPath {
                contribution: throughput * end_value,
                wavelengths,
                suffix_density,
                reused_seed_steps: false,
            });
        }

        // The continuation to the next vertex (or the environment).
        let (wi, next) = if m + 1 < vertices.len() {
            let next = &vertices[m + 1];
            ((next.hit.point - vertex.hit.point).normalize(), Some(next))
        } else if let Terminal::Environment { direction } = input.terminal {
            (*direction, None)
        } else {
            return Err(FailureReason::Evaluation);
        };
        let wavelengths_before = wavelengths;
        let FixedScattering {
            factor,
            pdf,
            eta_factor,
            specular,
        } = scatter_at_surface(vertex, &bsdf, wo, wi, m, numbers, &mut wavelengths)?;
        eta_scale *= eta_factor;
        throughput *= factor;
        let density_factor = if specular {
            1.0
        } else {
            let mut density = pdf as f64;
            if let Some(next) = next {
                let to_next = next.hit.point - vertex.hit.point;
                let distance_squared = to_next.length_squared() as f64;
                density *= next.raw_hit.geometric_normal.dot(to_next).abs() as f64
                    / distance_squared.sqrt()
                    / distance_squared;
            }
            density
        };
        if in_suffix(step) && !specular {
            suffix_density *= density_factor;
        }
        if let SegmentReuse::Record(cache) = segments {
            cache.surface_steps.push(SurfaceStep {
                wavelengths: wavelengths_before,
                factor,
                eta_factor,
                density_factor,
                specular,
            });
        }
        previous = PreviousScattering {
            point: reference,
            pdf,
            delta: specular,
        };
        throughput /= survive_roulette(
            roulette_throughput(throughput, eta_scale, None),
            m,
            settings,
            numbers,
        )?;
    }

    let contribution = match input.terminal {
        Terminal::Emission { light_index } => {
            let emitter = vertices.last().expect("checked non-empty");
            let previous_point = if vertices.len() == 1 {
                camera.origin
            } else {
                vertices[vertices.len() - 2].hit.point
            };
            let wo = (previous_point - emitter.raw_hit.point).normalize();
            let light = &scene.lights[*light_index as usize];
            let emitted = light.emitted_radiance(
                emitter.raw_hit.geometric_normal,
                emitter.raw_hit.uv,
                wo,
                &wavelengths,
            );
            let weight = emission_weight(
                scene,
                settings,
                *light_index,
                &previous,
                emitter.raw_hit.point,
                emitter.raw_hit.geometric_normal,
            );
            if let SegmentReuse::Record(cache) = segments {
                cache.surface_terminal = Some(SurfaceTerminal {
                    wavelengths,
                    value: emitted * weight,
                    density_factor: 1.0,
                });
            }
            throughput * emitted * weight
        }
        Terminal::Environment { direction } => {
            let mut end_value = SampledSpectrum::zero();
            let mut total = SampledSpectrum::zero();
            environment_emission(
                scene,
                settings,
                &previous,
                *direction,
                &wavelengths,
                |emitted, weight| {
                    total += throughput * emitted * weight;
                    end_value += emitted * weight;
                },
            );
            if let SegmentReuse::Record(cache) = segments {
                cache.surface_terminal = Some(SurfaceTerminal {
                    wavelengths,
                    value: end_value,
                    density_factor: 1.0,
                });
            }
            total
        }
        Terminal::NextEvent(_) => return Err(FailureReason::Evaluation),
    };
    finish(contribution, wavelengths, suffix_density)
}

/// The walked path, or `Evaluation` for a black contribution.
#[inline]
pub(super) fn finish(
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

/// A member's path state where it starts to reuse the seed's steps.
struct ReusedState {
    throughput: SampledSpectrum,
    eta_scale: f32,
    suffix_density: f64,
}

/// The rest of a member's walk from step `first` on, whose vertices and
/// wavelengths are the seed's (see [`super::segment_cache`]): the seed's
/// recorded factors, Russian roulette decided again on the member's own
/// throughput with the seed's numbers, and the seed's end.
fn reuse_seed_steps(
    settings: &PathSettings,
    cache: &SegmentCache,
    first: usize,
    mut state: ReusedState,
    in_suffix: &impl Fn(usize) -> bool,
    scattering_count: usize,
    numbers: &mut dyn SampleSource,
) -> Result<WalkedPath, FailureReason> {
    let end = cache.surface_terminal.ok_or(FailureReason::Evaluation)?;
    for (m, step) in cache.surface_steps.iter().enumerate().skip(first) {
        state.throughput *= step.factor;
        state.eta_scale *= step.eta_factor;
        if in_suffix(m + 1) && !step.specular {
            state.suffix_density *= step.density_factor;
        }
        state.throughput /= survive_roulette(
            roulette_throughput(state.throughput, state.eta_scale, None),
            m,
            settings,
            numbers,
        )?;
    }
    // A next-event connection is the last step, `scattering_count`.
    if cache.surface_steps.len() < scattering_count && in_suffix(scattering_count) {
        state.suffix_density *= end.density_factor;
    }
    let contribution = state.throughput * end.value;
    if contribution.is_black() {
        return Err(FailureReason::Evaluation);
    }
    Ok(WalkedPath {
        contribution,
        wavelengths: end.wavelengths,
        suffix_density: state.suffix_density,
        reused_seed_steps: true,
    })
}
