//! Seed paths in scenes with participating media: volumetric path tracing
//! with the decisions of [`crate::integrators::volpath`] (free flights from
//! `FREE_FLIGHT` of each block at the hero wavelength, medium vertices
//! scattering with the phase function, next-event estimation through media
//! and index-matched boundaries, Russian roulette on the MIS-rescaled
//! throughput), recording every vertex and splat event. Values are computed
//! afterwards by [`super::volume_walk`].
//!
//! Emission of index-matched boundaries that are themselves emitters
//! (volpath adds it as the ray passes) is recorded as an emission event of
//! its own, whose path ends at the boundary point.

use super::classification::lobe_roughness;
use super::medium_segment::{FlightEnd, medium_roughness, sample_flight};
use super::path_record::{CameraVertex, LightConnection, SplatEvent, SurfaceVertex, Terminal};
use super::seed_path::SeedPath;
use crate::geometry::{Ray, SurfaceHit, offset_ray_origin, spawn_ray};
use crate::integrators::TraceCounters;
use crate::integrators::path::{PathSettings, oriented_hit};
use crate::integrators::volpath::{shadow_ray, shadow_transmittance};
use crate::medium::medium_after;
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};

/// Traces the seed through media (see the module documentation).
pub fn trace_volumetric_seed_path(
    scene: &Scene,
    settings: &PathSettings,
    raster: Vec2,
    sampler: &mut dyn SampleSource,
    counters: &mut TraceCounters,
    path: &mut SeedPath,
) {
    path.vertices.clear();
    path.events.clear();
    let u_lens = sampler.get_2d(layout::LENS);
    let u_time = sampler.get(layout::TIME);
    let u_wavelength = sampler.get(layout::WAVELENGTH);
    let camera_ray = scene.camera.generate_ray(raster, u_lens, u_time);
    path.camera = Some(CameraVertex {
        raster,
        u_lens,
        u_time,
        u_wavelength,
        origin: camera_ray.origin,
    });
    let mut wavelengths = SampledWavelengths::sample_visible(u_wavelength);
    let mut ray = Ray::with_time(camera_ray.origin, camera_ray.direction, camera_ray.time);
    let mut medium = scene.camera_medium;
    let mut beta = SampledSpectrum::splat(1.0);
    let mut r_u = SampledSpectrum::splat(1.0);
    let mut eta_scale = 1.0f32;
    let mut depth = 0u32;
    // Emitting index-matched boundaries passed: (vertices before, hit, light).
    let mut passed_emitters: Vec<(usize, SurfaceHit, u32)> = Vec::new();
    loop {
        let prefix = path.vertices.len();
        let flight = sample_flight(
            scene,
            &mut ray,
            &mut medium,
            || sampler.get(layout::vertex(depth as usize, layout::FREE_FLIGHT)),
            &mut |hit, light_index| passed_emitters.push((prefix, *hit, light_index)),
            &wavelengths,
            &mut counters.closest_hit_rays,
        );
        beta *= flight.beta_factor;
        r_u *= flight.probability_factor;
        let wo = -ray.direction;
        match flight.end {
            FlightEnd::Dead => break,
            FlightEnd::Escaped => {
                if !scene.environment_lights.is_empty() {
                    path.events.push(SplatEvent::of_first_vertices(
                        path.vertices.len(),
                        Terminal::Environment {
                            direction: ray.direction,
                        },
                    ));
                }
                break;
            }
            FlightEnd::Medium {
                point,
                medium: medium_index,
            } => {
                if beta.is_black() || depth + 2 > settings.max_depth {
                    break;
                }
                path.vertices.push(SurfaceVertex::in_medium(
                    point,
                    ray.time,
                    medium_index,
                    medium_roughness(scene, medium_index),
                ));
                if let Some(connection) = sample_light(
                    scene,
                    None,
                    point,
                    medium,
                    depth,
                    &wavelengths,
                    sampler,
                    counters,
                ) {
                    path.events.push(SplatEvent::of_first_vertices(
                        path.vertices.len(),
                        Terminal::NextEvent(connection),
                    ));
                }
                let phase = scene.media[medium_index as usize].phase;
                let sample = phase.sample(
                    wo,
                    sampler.get_2d(layout::vertex(depth as usize, layout::SCATTER_DIRECTION)),
                );
                if sample.pdf <= 0.0 {
                    break;
                }
                beta *= sample.value / sample.pdf;
                ray = Ray::with_time(point, sample.wi, ray.time);
            }
            FlightEnd::Surface { raw_hit } => {
                let hit = oriented_hit(scene, &raw_hit);
                let info = &scene.shapes[hit.shape_index as usize];
                path.vertices
                    .push(SurfaceVertex::surface(raw_hit, hit, 1.0));
                if let Some(light_index) = info.light {
                    path.events.push(SplatEvent::of_first_vertices(
                        path.vertices.len(),
                        Terminal::Emission { light_index },
                    ));
                }
                if depth + 2 > settings.max_depth {
                    break;
                }
                let Some(material) = &info.material else {
                    break;
                };
                let bsdf = material.surface_bsdf_at(&hit, &wavelengths);
                let flags = bsdf.flags();
                path.vertices.last_mut().expect("just pushed").roughness =
                    lobe_roughness(&bsdf, flags);
                let reference = offset_ray_origin(hit.point, hit.geometric_normal, wo);
                if flags.is_non_specular()
                    && let Some(connection) = sample_light(
                        scene,
                        Some(&hit),
                        reference,
                        medium,
                        depth,
                        &wavelengths,
                        sampler,
                        counters,
                    )
                {
                    path.events.push(SplatEvent::of_first_vertices(
                        path.vertices.len(),
                        Terminal::NextEvent(connection),
                    ));
                }
                let u_component =
                    sampler.get(layout::vertex(depth as usize, layout::SCATTER_COMPONENT));
                let u = sampler.get_2d(layout::vertex(depth as usize, layout::SCATTER_DIRECTION));
                let Some(sample) = bsdf.sample(wo, u_component, u, &mut wavelengths) else {
                    break;
                };
                if sample.pdf <= 0.0 || sample.value.is_black() {
                    break;
                }
                let cosine = sample.wi.dot(bsdf.frame.normal()).abs();
                beta *= sample.value * (cosine / sample.pdf);
                let vertex = path.vertices.last_mut().expect("just pushed");
                vertex.sampled = sample.flags;
                vertex.roughness = lobe_roughness(&bsdf, sample.flags);
                if sample.is_transmission() {
                    eta_scale *= sample.eta * sample.eta;
                }
                medium = medium_after(
                    info.medium_interface.as_ref(),
                    hit.geometric_normal,
                    sample.wi,
                    medium,
                );
                ray = spawn_ray(&raw_hit, sample.wi);
            }
        }
        let r_u_mean = r_u.average();
        if r_u_mean <= 0.0 {
            break;
        }
        let roulette_throughput = (beta * (eta_scale / r_u_mean)).max_component();
        match crate::integrators::path::russian_roulette(
            roulette_throughput,
            depth,
            settings.russian_roulette_depth,
            || sampler.get(layout::vertex(depth as usize, layout::RUSSIAN_ROULETTE)),
        ) {
            Some(survival) => beta /= survival,
            None => break,
        }
        if beta.is_black() {
            break;
        }
        depth += 1;
    }
    record_passed_emitters(scene, &passed_emitters, path);
}

/// The emission events of the index-matched emitting boundaries the seed
/// passed: each is the path of the vertices before it and the boundary
/// point (copied after the seed's vertices, since the seed goes on through
/// the boundary), ending there as an emitter reached by the last scattering.
fn record_passed_emitters(
    scene: &Scene,
    passed_emitters: &[(usize, SurfaceHit, u32)],
    path: &mut SeedPath,
) {
    for (prefix, raw_hit, light_index) in passed_emitters {
        let first_vertex = path.vertices.len();
        path.vertices.extend_from_within(..*prefix);
        path.vertices.push(SurfaceVertex::surface(
            *raw_hit,
            oriented_hit(scene, raw_hit),
            1.0,
        ));
        path.events.push(SplatEvent {
            first_vertex,
            vertex_count: prefix + 1,
            terminal: Terminal::Emission {
                light_index: *light_index,
            },
        });
    }
}

/// Next-event estimation's light sample at a vertex (a surface `hit` or a
/// medium point), if some light arrives through the media and boundaries.
#[allow(clippy::too_many_arguments)]
fn sample_light(
    scene: &Scene,
    hit: Option<&SurfaceHit>,
    reference: Vec3,
    medium: Option<u32>,
    depth: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut dyn SampleSource,
    counters: &mut TraceCounters,
) -> Option<LightConnection> {
    let light_sample = crate::integrators::path::sample_vertex_light(
        scene,
        reference,
        depth,
        wavelengths,
        sampler,
    )?;
    let sample = &light_sample.sample;
    let (ray, t_max) = shadow_ray(reference, hit, sample)?;
    let start_medium = start_medium(scene, hit, medium, sample.wi);
    let transmittance =
        shadow_transmittance(scene, ray, t_max, start_medium, wavelengths, counters);
    if transmittance.is_black() {
        return None;
    }
    Some(LightConnection::from_sample(scene, light_sample))
}

/// The medium a ray leaving a vertex along `direction` starts in: at a
/// surface, the side `direction` leaves to; in a medium, that medium.
pub fn start_medium(
    scene: &Scene,
    hit: Option<&SurfaceHit>,
    medium: Option<u32>,
    direction: Vec3,
) -> Option<u32> {
    match hit {
        Some(hit) => medium_after(
            scene.shapes[hit.shape_index as usize]
                .medium_interface
                .as_ref(),
            hit.geometric_normal,
            direction,
            medium,
        ),
        None => medium,
    }
}
