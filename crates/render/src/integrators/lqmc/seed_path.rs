//! The seed paths: path tracing with next-event estimation driven by the
//! pixel sampler (Halton in the paper), built by the path-space walk
//! ([`crate::integrators::path_space::walk`]) with the decisions of
//! [`crate::integrators::path`], and through homogeneous media those of
//! [`crate::integrators::volpath`] (free flights from `FREE_FLIGHT` of each
//! block at the hero wavelength, medium vertices scattering with the phase
//! function, next-event estimation through media and index-matched
//! boundaries, Russian roulette on the MIS-rescaled throughput). The
//! observer `SeedRecorder` records each vertex and each splat event
//! (every emitter reached, every next-event connection) for exploration,
//! and computes each event's value as the path tracer does, `path`'s in
//! surface scenes and `volpath`'s through media (the value a seed adds when
//! its event is not explored, so that it is not walked a second time); the
//! values of explored events are computed again by
//! [`super::path_walk::walk`] and [`super::volume_walk`], which record what
//! the members reuse.
//!
//! Emission of index-matched boundaries that are themselves emitters (the
//! path tracers add it as the ray passes) is recorded as an emission event
//! of its own, whose path ends at the boundary point.
//!
//! LQMC's value walks treat every surface as a vertex, so the seed's walk
//! has no null crossings: a thin sheet's straight transmission is a
//! specular vertex, as in Mitsuba's `path` (`volpath` makes it a null
//! crossing that does not count towards the depth).

use super::classification::lobe_roughness;
use super::medium_segment::medium_roughness;
use super::path_record::{CameraVertex, LightConnection, SplatEvent, SurfaceVertex, Terminal};
use crate::geometry::{Ray, SurfaceHit};
use crate::integrators::TraceCounters;
use crate::integrators::driver::camera_numbers;
use crate::integrators::estimator::PathSettings;
use crate::integrators::estimator::mis::{
    emission_light_density, emission_weight, environment_emission, environment_emission_densities,
    volumetric_emission,
};
use crate::integrators::estimator::next_event::{
    AreaRadianceCache, NextEventTerms, VertexScatter, next_event_through_media,
    sample_vertex_light_with_cache,
};
use crate::integrators::estimator::shadow::light_visible_from_hit;
use crate::integrators::path_space::{
    ScattererRef, Scattering, VertexAt, WalkObserver, WalkSettings, WalkStart, WalkState,
    oriented_hit, walk,
};
use crate::material::SurfaceBsdf;
use crate::sampler::{DynSource, SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::{Vec2, Vec3};
use std::ops::ControlFlow;

/// A traced seed path and its splat events.
#[derive(Debug, Clone, Default)]
pub struct SeedPath {
    /// The camera vertex (`None` before tracing).
    pub camera: Option<CameraVertex>,
    /// The surface vertices in order from the camera.
    pub vertices: Vec<SurfaceVertex>,
    /// The splat events, in the order the path tracer adds them.
    pub events: Vec<SplatEvent>,
    /// Per event, its contribution and the wavelengths it was computed at,
    /// as the path tracer's estimate (`None` for index-matched emitters,
    /// whose values only the value walks compute).
    pub event_values: Vec<Option<(SampledSpectrum, SampledWavelengths)>>,
    /// The wavelengths the camera ray started with (before the walk
    /// terminated any secondary ones), which the value walks start with
    /// (`None` before tracing).
    pub wavelengths: Option<SampledWavelengths>,
    /// Emitting index-matched boundaries passed: (vertices before, hit, light).
    passed_emitters: Vec<(usize, SurfaceHit, u32)>,
}

/// Traces the camera ray through `raster` with the numbers of `sampler`
/// (lens, time, wavelength, vertex blocks), filling `path`.
pub fn trace_seed_path(
    scene: &Scene,
    settings: &PathSettings,
    raster: Vec2,
    sampler: &mut dyn SampleSource,
    counters: &mut TraceCounters,
    path: &mut SeedPath,
) {
    path.vertices.clear();
    path.events.clear();
    path.event_values.clear();
    path.passed_emitters.clear();
    let (camera, ray, mut wavelengths) = seed_camera(scene, raster, sampler);
    path.camera = Some(camera);
    path.wavelengths = Some(wavelengths);
    walk(
        scene,
        WalkStart::camera(ray, scene.camera_medium),
        &seed_walk_settings(scene, settings),
        &mut wavelengths,
        &mut DynSource(sampler),
        counters,
        &mut SeedRecorder {
            scene,
            settings,
            path,
            area_radiance: AreaRadianceCache::new(),
        },
    );
    record_passed_emitters(scene, path);
}

/// The camera vertex of a seed through `raster` with the numbers of
/// `sampler`, its ray and its wavelengths.
#[inline(always)]
pub fn seed_camera<S: SampleSource + ?Sized>(
    scene: &Scene,
    raster: Vec2,
    sampler: &mut S,
) -> (CameraVertex, Ray, SampledWavelengths) {
    let (u_lens, u_time) = camera_numbers(scene, sampler);
    let u_wavelength = sampler.get(layout::WAVELENGTH);
    let camera_ray = scene.camera.generate_ray(raster, u_lens, u_time);
    let camera = CameraVertex {
        raster,
        u_lens,
        u_time,
        u_wavelength,
        origin: camera_ray.origin,
    };
    (
        camera,
        Ray::with_time(camera_ray.origin, camera_ray.direction, camera_ray.time),
        SampledWavelengths::sample_visible(u_wavelength),
    )
}

/// The walk of a seed path: the path tracer's (the volumetric one's in
/// scenes with media), every surface a vertex (no null crossings).
pub fn seed_walk_settings(scene: &Scene, settings: &PathSettings) -> WalkSettings {
    WalkSettings::camera(
        WalkSettings::camera_vertices(settings.max_depth),
        settings.russian_roulette_depth,
        scene.has_media(),
        false,
    )
}

/// The seed's observer of the walk: every surface reached is a vertex,
/// every emitter reached and every next-event connection that arrives is a
/// splat event.
struct SeedRecorder<'a> {
    scene: &'a Scene,
    settings: &'a PathSettings,
    path: &'a mut SeedPath,
    /// The path's area-light radiance, as the path tracer caches it.
    area_radiance: AreaRadianceCache,
}

impl SeedRecorder<'_> {
    /// Records an event and its value.
    fn push_event(
        &mut self,
        event: SplatEvent,
        value: Option<(SampledSpectrum, SampledWavelengths)>,
    ) {
        self.path.events.push(event);
        self.path.event_values.push(value);
    }
}

impl WalkObserver for SeedRecorder<'_> {
    const FINDS_EMISSION: bool = true;

    fn surface(
        &mut self,
        _walk: &WalkState,
        raw_hit: &SurfaceHit,
        _wavelengths: &SampledWavelengths,
    ) -> ControlFlow<()> {
        self.path.vertices.push(SurfaceVertex::surface(
            *raw_hit,
            oriented_hit(self.scene, raw_hit),
            1.0,
        ));
        ControlFlow::Continue(())
    }

    fn emitter(
        &mut self,
        walk: &WalkState,
        light_index: u32,
        hit: &SurfaceHit,
        wo: Vec3,
        wavelengths: &SampledWavelengths,
    ) {
        let scene = self.scene;
        if scene.shapes[hit.shape_index as usize].is_interface {
            let prefix = self.path.vertices.len();
            self.path.passed_emitters.push((prefix, *hit, light_index));
            return;
        }
        // The path tracer's value (`path::PathRadiance::emitter`,
        // `volpath::VolPathRadiance::emitter` in scenes with media).
        let area_radiance = &mut self.area_radiance;
        let emitted = scene.lights[light_index as usize].emitted_radiance_with_area_radiance(
            hit.geometric_normal,
            hit.uv,
            wo,
            wavelengths,
            |spectrum| area_radiance.radiance(light_index as usize, spectrum, wavelengths),
        );
        let contribution = if scene.has_media() {
            let light_pdf = emission_light_density(
                scene,
                light_index,
                &walk.previous,
                hit.point,
                hit.geometric_normal,
            );
            volumetric_emission(walk, emitted, light_pdf).unwrap_or(SampledSpectrum::zero())
        } else {
            let weight = emission_weight(
                scene,
                self.settings,
                light_index,
                &walk.previous,
                hit.point,
                hit.geometric_normal,
            );
            walk.beta * emitted * weight
        };
        let value = Some((contribution, *wavelengths));
        self.push_event(
            SplatEvent::of_first_vertices(
                self.path.vertices.len(),
                Terminal::Emission { light_index },
            ),
            value,
        );
    }

    fn escaped(&mut self, walk: &WalkState, direction: Vec3, wavelengths: &SampledWavelengths) {
        let scene = self.scene;
        if scene.environment_lights.is_empty() {
            return;
        }
        // The path tracer's value (`path::PathRadiance::escaped`,
        // `volpath::VolPathRadiance::escaped` in scenes with media).
        let mut total = SampledSpectrum::zero();
        if scene.has_media() {
            environment_emission_densities(
                scene,
                &walk.previous,
                direction,
                wavelengths,
                |emitted, light_pdf| {
                    if let Some(value) = volumetric_emission(walk, emitted, light_pdf) {
                        total += value;
                    }
                },
            );
        } else {
            environment_emission(
                scene,
                self.settings,
                &walk.previous,
                direction,
                wavelengths,
                |emitted, weight| total += walk.beta * emitted * weight,
            );
        }
        let value = Some((total, *wavelengths));
        self.push_event(
            SplatEvent::of_first_vertices(
                self.path.vertices.len(),
                Terminal::Environment { direction },
            ),
            value,
        );
    }

    fn vertex<S: SampleSource + ?Sized>(
        &mut self,
        walk: &WalkState,
        vertex: &VertexAt<'_>,
        wavelengths: &SampledWavelengths,
        sampler: &mut S,
        counters: &mut TraceCounters,
    ) -> ControlFlow<()> {
        let scene = self.scene;
        let mut value = None;
        let connection = match vertex.scatterer {
            ScattererRef::Medium { phase } => {
                let medium = vertex.medium.expect("medium vertices lie in a medium");
                self.path.vertices.push(SurfaceVertex::in_medium(
                    vertex.point,
                    vertex.time,
                    medium,
                    medium_roughness(scene, medium),
                ));
                volumetric_next_event(
                    scene,
                    walk,
                    vertex.point,
                    None,
                    vertex.medium,
                    VertexScatter::Medium(phase),
                    vertex.wo,
                    wavelengths,
                    &mut DynSource(sampler),
                    counters,
                )
                .map(|(connection, contribution)| {
                    value = Some((contribution, *wavelengths));
                    connection
                })
            }
            ScattererRef::Surface { hit, bsdf, offset } => {
                let flags = bsdf.flags();
                self.path.vertices.last_mut().expect("reached").roughness =
                    lobe_roughness(bsdf, flags);
                if !flags.is_non_specular() {
                    return ControlFlow::Continue(());
                }
                if scene.has_media() {
                    volumetric_next_event(
                        scene,
                        walk,
                        offset.origin(),
                        Some(hit),
                        vertex.medium,
                        VertexScatter::Surface(bsdf),
                        vertex.wo,
                        wavelengths,
                        &mut DynSource(sampler),
                        counters,
                    )
                } else {
                    sample_surface_light(
                        scene,
                        self.settings,
                        hit,
                        offset.origin(),
                        bsdf,
                        vertex.wo,
                        walk,
                        wavelengths,
                        &mut DynSource(sampler),
                        counters,
                        &mut self.area_radiance,
                    )
                }
                .map(|(connection, contribution)| {
                    value = Some((contribution, *wavelengths));
                    connection
                })
            }
        };
        if let Some(connection) = connection {
            self.push_event(
                SplatEvent::of_first_vertices(
                    self.path.vertices.len(),
                    Terminal::NextEvent(connection),
                ),
                value,
            );
        }
        ControlFlow::Continue(())
    }

    fn scattered(&mut self, vertex: &VertexAt<'_>, scattering: &Scattering) -> ControlFlow<()> {
        if let ScattererRef::Surface { bsdf, .. } = vertex.scatterer {
            let recorded = self.path.vertices.last_mut().expect("reached");
            recorded.sampled = scattering.flags;
            recorded.roughness = lobe_roughness(bsdf, scattering.flags);
        }
        ControlFlow::Continue(())
    }
}

/// The emission events of the index-matched emitting boundaries the seed
/// passed: each is the path of the vertices before it and the boundary
/// point (copied after the seed's vertices, since the seed goes on through
/// the boundary), ending there as an emitter reached by the last scattering.
fn record_passed_emitters(scene: &Scene, path: &mut SeedPath) {
    for index in 0..path.passed_emitters.len() {
        let (prefix, raw_hit, light_index) = path.passed_emitters[index];
        let first_vertex = path.vertices.len();
        path.vertices.extend_from_within(..prefix);
        path.vertices.push(SurfaceVertex::surface(
            raw_hit,
            oriented_hit(scene, &raw_hit),
            1.0,
        ));
        path.events.push(SplatEvent {
            first_vertex,
            vertex_count: prefix + 1,
            terminal: Terminal::Emission { light_index },
        });
        path.event_values.push(None);
    }
}

/// Next-event estimation at a vertex of a walk through media (a medium
/// point, or a surface point `reference` offset off `hit`), with the
/// volumetric path tracer's terms and balance weight
/// ([`next_event_through_media`]): the light sample's connection
/// and its contribution `β · scattered · T · Le / mean(r_l + r_u p)`, if
/// some light arrives. The seed's walk has no null crossings: shadow rays
/// stop at thin sheets and masks, which its paths pass by sampling them.
#[allow(clippy::too_many_arguments)]
fn volumetric_next_event(
    scene: &Scene,
    walk: &WalkState,
    reference: Vec3,
    hit: Option<&SurfaceHit>,
    medium: Option<u32>,
    scatter: VertexScatter<'_>,
    wo: Vec3,
    wavelengths: &SampledWavelengths,
    sampler: &mut dyn SampleSource,
    counters: &mut TraceCounters,
) -> Option<(LightConnection, SampledSpectrum)> {
    let (light_sample, contribution) = next_event_through_media(
        scene,
        reference,
        hit,
        medium,
        scatter,
        wo,
        walk.spectral_density_ratio,
        walk.block,
        wavelengths,
        sampler,
        counters,
        false,
    )?;
    Some((
        LightConnection::from_sample(scene, light_sample),
        walk.beta * contribution,
    ))
}

/// Next-event estimation at a surface vertex of a scene without media, with
/// the path tracer's terms and weight ([`NextEventTerms`]): the light
/// sample's connection and its contribution `β f |cos| Le w / p`, if the
/// BSDF passes light that way and the light is visible (no shadow ray
/// otherwise, as the path tracer).
#[allow(clippy::too_many_arguments)]
fn sample_surface_light(
    scene: &Scene,
    settings: &PathSettings,
    hit: &SurfaceHit,
    reference: Vec3,
    bsdf: &SurfaceBsdf,
    wo: Vec3,
    walk: &WalkState,
    wavelengths: &SampledWavelengths,
    sampler: &mut dyn SampleSource,
    counters: &mut TraceCounters,
    area_radiance: &mut AreaRadianceCache,
) -> Option<(LightConnection, SampledSpectrum)> {
    let light_sample = sample_vertex_light_with_cache(
        scene,
        reference,
        walk.block,
        wavelengths,
        sampler,
        area_radiance,
    )?;
    let terms =
        NextEventTerms::of_sample(VertexScatter::Surface(bsdf), wo, &light_sample, wavelengths);
    if terms.scattered.is_black() {
        return None;
    }
    counters.shadow_rays += 1;
    if !light_visible_from_hit(scene, hit, &light_sample.sample) {
        return None;
    }
    // Multiplied in the path tracer's order (`next_event_at_surface`), so
    // that the sums agree bit for bit.
    let contribution = walk.beta
        * (terms.scattered
            * light_sample.sample.radiance
            * terms.weight_over_density(settings.heuristic));
    Some((
        LightConnection::from_sample(scene, light_sample),
        contribution,
    ))
}
