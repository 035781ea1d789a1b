//! Light tracing (particle tracing): one path from the lights per pixel
//! sample, built by the path-space walk in importance transport, every
//! vertex connected to the camera and splatted (pbrt-v4's
//! `LightPathIntegrator`; Mitsuba 3's `ptracer`).
//!
//! For a light path `y₀ … y_k` (`y₀` on the light) with throughput `β_i`
//! up to `y_i`, vertex `i` adds at the raster position where it appears
//! `β_i · f(y_i) · C · We / p_lens`, with `f` the BSDF towards the lens
//! point, `C` the cosine with the adjoint shading-normal correction
//! ([`super::path_space::Vertex::connection_factor`]) and `We / p_lens`
//! the camera's importance over the density of the sampled lens point
//! ([`crate::camera::PerspectiveCamera::sample_incident_importance`]); the
//! splat scale is one over the light paths per pixel, so the image equals
//! the path tracer's in expectation (see [`crate::camera::importance`]).
//!
//! - The light's own vertex is connected too: emitters seen directly.
//!   Points and spots cannot be seen (their vertex is a delta in
//!   position, as in the path tracer), and directional lights and
//!   environments have no vertex in the scene.
//! - Environments seen directly cannot be reached from the lights at all:
//!   each light path's pixel sample also traces one camera ray (the
//!   pixel's film position, uniform in the pixel) and splats the
//!   environment radiance it escapes to; one such ray per pixel per pass
//!   makes the same splat scale exact.
//! - Depth counts segments as the path tracer's (Mitsuba's `max_depth`):
//!   vertex `i` of the light path makes a path of `i + 1` segments.
//! - Russian roulette decides on the throughput relative to the path's
//!   start (the walk carries β / max β₁; the connections scale it back).
//! - Paths whose last scattering before the camera is a delta lobe
//!   (`… S E`: a mirror, glass or a mask seen by the camera) cannot be
//!   connected and are missing, as in Mitsuba's `ptracer`.
//! - Participating media (volumetric light tracing): the walk samples
//!   free flights and medium vertices as `volpath`'s camera paths do, medium
//!   vertices connect to the camera with their phase function, and every
//!   connection and the environment camera ray carry their transmittance
//!   through media and null surfaces. A particle starts in the medium on
//!   the emitting side of its area light's medium interface, or else in
//!   the medium around its point, found from the camera as `volpath`'s
//!   camera paths find it; environment and directional lights in a
//!   scene-filling medium are refused. Free flights are sampled at the
//!   hero wavelength, and each connection divides by the mean over the
//!   wavelengths of the walk's spectral density ratio (the one-sample MIS
//!   over the choice of hero of `volpath`).
//!
//! Numbers: the camera dimensions of [`crate::sampler::layout`] (time,
//! wavelength, the lens point of the light vertex's connection, the film
//! position of the environment ray), the light's choice, point and
//! direction, then a block per light vertex
//! ([`super::path_space::SubpathLayout::LIGHT`]) whose connection slot holds
//! the lens point of that vertex's connection.

use super::driver::{PixelSampleIndex, SplatEstimator, render_splat_paths};
use super::estimator::PathSettings;
use super::estimator::emitted_ray::{EmittedRay, sample_emitted_ray};
use super::estimator::shadow::shadow_transmittance;
use super::path_space::{
    MAX_INTERFACE_CROSSINGS, SubpathLayout, Vertex, WalkSettings, WalkStart, random_walk,
};
use super::{Integrator, IntegratorRender, RenderError, RunControl, TraceCounters};
use crate::film::SplatBuffer;
use crate::geometry::{Ray, occlusion_segment_to_point, offset_ray_origin, spawn_segment_to_point};
use crate::light::Light;
use crate::material::TransportMode;
use crate::medium::medium_after;
use crate::sampler::{PixelSampler, SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, to_linear_srgb};
use glam::{Vec2, Vec3};

/// The light tracer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightIntegrator {
    settings: PathSettings,
}

impl LightIntegrator {
    /// Light tracing with `settings` (depth and Russian roulette; the MIS
    /// heuristic is unused: light tracing has one strategy).
    pub fn new(settings: PathSettings) -> Self {
        Self { settings }
    }
}

impl Integrator for LightIntegrator {
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError> {
        let light_media = LightMedia::new(scene, "the light tracer")?;
        let estimator = LightTracer {
            scene,
            settings: &self.settings,
            light_media,
            media: scene.has_media(),
        };
        render_splat_paths(&estimator, scene, run).map(IntegratorRender::from_driver)
    }
}

/// One light path per pixel sample.
struct LightTracer<'a> {
    scene: &'a Scene,
    settings: &'a PathSettings,
    /// The media the particles start in.
    light_media: LightMedia,
    /// The scene has participating media (volumetric walks).
    media: bool,
}

impl SplatEstimator for LightTracer<'_> {
    /// The light path's vertices, reused from path to path.
    type Unit = Vec<Vertex>;
    type Total = ();

    fn new_total(&self, _resolution: [usize; 2]) -> Result<(), RenderError> {
        Ok(())
    }

    fn new_unit(&self) -> Vec<Vertex> {
        Vec::new()
    }

    fn merge_unit(&self, _total: &mut (), _unit: Vec<Vertex>, _kept: bool) {}

    fn trace<S: PixelSampler + ?Sized>(
        &self,
        vertices: &mut Vec<Vertex>,
        path: PixelSampleIndex,
        sampler: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    ) {
        let scene = self.scene;
        let camera = &scene.camera;
        // Splats up to the filter's radius outside the image reach its
        // border pixels.
        let margin = Vec2::from(scene.filter.radius());
        let mut wavelengths = SampledWavelengths::sample_visible(sampler.get(layout::WAVELENGTH));
        let time = if camera.uses_time_sample() {
            camera.time(sampler.get(layout::TIME))
        } else {
            camera.time(0.5)
        };
        if !scene.environment_lights.is_empty() {
            splat_seen_environment(scene, path.pixel, &wavelengths, sampler, splats, counters);
        }
        if self.settings.max_depth == 0 {
            return;
        }
        let Some(emitted) = sample_emitted_ray(scene, sampler, &wavelengths) else {
            return;
        };
        let EmittedRay {
            light_index,
            choice_probability,
            emission,
            on_surface,
        } = emitted;
        let light = &scene.lights[light_index];
        // The medium around the particle's origin.
        let around = self
            .light_media
            .around(scene, light_index, emission.origin, emission.normal);
        // The emitter's own vertex seen by the camera (area lights only).
        if on_surface {
            let u_lens = lens_numbers(scene, sampler, layout::LENS);
            if let Some(camera_sample) =
                camera.sample_incident_importance_with_margin(emission.origin, time, u_lens, margin)
            {
                let cosine = camera_sample.wi.dot(emission.normal);
                // One-sided emitters radiate to the front only; their
                // radiance does not depend on the direction there.
                if cosine > 0.0 {
                    let value = emission.radiance
                        * (cosine * camera_sample.value
                            / (choice_probability * emission.pdf_position * camera_sample.pdf));
                    let origin =
                        offset_ray_origin(emission.origin, emission.normal, camera_sample.wi);
                    splat_if_visible(
                        scene,
                        origin,
                        emission_medium(scene, light, around, emission.normal, camera_sample.wi),
                        time,
                        camera_sample.lens_point,
                        camera_sample.raster,
                        value,
                        &wavelengths,
                        splats,
                        counters,
                    );
                }
            }
        }
        let max_vertices = (self.settings.max_depth - 1) as usize;
        if max_vertices == 0 {
            return;
        }
        // The walk carries β₁ relative to its largest component, and the
        // connections scale it back.
        let Some((beta, beta_scale)) = emitted.scaled_throughput() else {
            return;
        };
        let start = WalkStart {
            ray: Ray::with_time(emitted.ray_origin(), emission.direction, time),
            beta,
            pdf_direction: if emission.is_delta_direction {
                0.0
            } else {
                emission.pdf_direction
            },
            medium: emission_medium(scene, light, around, emission.normal, emission.direction),
        };
        let walk = WalkSettings {
            mode: TransportMode::Importance,
            max_vertices,
            russian_roulette_depth: self.settings.russian_roulette_depth,
            layout: SubpathLayout::LIGHT,
            media: scene.has_media(),
            null_crossings: scene.has_media(),
        };
        vertices.clear();
        random_walk(
            scene,
            start,
            &walk,
            &mut wavelengths,
            sampler,
            counters,
            vertices,
        );
        for (index, vertex) in vertices.iter().enumerate() {
            if !vertex.is_connectible() {
                continue;
            }
            let u_lens = lens_numbers(
                scene,
                sampler,
                SubpathLayout::LIGHT.dimension(index, layout::CAMERA_CONNECTION),
            );
            let Some(camera_sample) = camera.sample_incident_importance_with_margin(
                vertex.point,
                vertex.time,
                u_lens,
                margin,
            ) else {
                continue;
            };
            let factor =
                vertex.connection_factor(camera_sample.wi, &wavelengths, TransportMode::Importance);
            if factor.is_black() {
                continue;
            }
            // In media, the one-sample MIS over the choice of hero
            // wavelength (as `volpath`'s): the throughput's `f / p_hero`
            // becomes `f / mean_j p_j`. Without it, `T_j σ_j / (T_0 σ_0)` has
            // infinite variance wherever the hero's extinction exceeds twice
            // another wavelength's.
            let spectral_mis = if self.media {
                let mean_ratio = vertex.spectral_density_ratio.average();
                if mean_ratio <= 0.0 {
                    continue;
                }
                1.0 / mean_ratio
            } else {
                1.0
            };
            let value = vertex.beta
                * factor
                * (beta_scale * spectral_mis * camera_sample.value / camera_sample.pdf);
            splat_if_visible(
                scene,
                vertex.origin_towards(camera_sample.wi),
                vertex.medium_towards(scene, camera_sample.wi),
                vertex.time,
                camera_sample.lens_point,
                camera_sample.raster,
                value,
                &wavelengths,
                splats,
                counters,
            );
        }
    }
}

/// The lens numbers at `dimension` (0.5, 0.5 for a pinhole, which has no
/// lens: the number is not drawn).
#[inline]
pub(super) fn lens_numbers<S: SampleSource + ?Sized>(
    scene: &Scene,
    sampler: &mut S,
    dimension: usize,
) -> [f32; 2] {
    if scene.camera.uses_lens_sample() {
        sampler.get_2d(dimension)
    } else {
        [0.5; 2]
    }
}

/// Splats `value` at `raster` if the segment from `origin` (in `medium`)
/// to the lens point is unoccluded, times its transmittance through the
/// media and null surfaces in scenes with media.
#[allow(clippy::too_many_arguments)]
fn splat_if_visible(
    scene: &Scene,
    origin: Vec3,
    medium: Option<u32>,
    time: f32,
    lens_point: Vec3,
    raster: Vec2,
    value: SampledSpectrum,
    wavelengths: &SampledWavelengths,
    splats: &mut SplatBuffer,
    counters: &mut TraceCounters,
) {
    if value.is_black() {
        return;
    }
    // The lens has no surface to offset from: the segment ends at its
    // point. Transmittance needs distances, so a unit direction; an
    // occlusion query does with the unnormalised segment.
    let value = if scene.has_media() {
        let Some((ray, t_max)) = spawn_segment_to_point(origin, time, lens_point, Vec3::ZERO)
        else {
            return;
        };
        value * shadow_transmittance(scene, ray, t_max, medium, wavelengths, counters)
    } else {
        let Some((ray, t_max)) = occlusion_segment_to_point(origin, time, lens_point, Vec3::ZERO)
        else {
            return;
        };
        counters.shadow_rays += 1;
        if scene.geometry.occluded(&ray, t_max) {
            return;
        }
        value
    };
    if !value.is_black() {
        let _ = splats.add(raster.to_array(), to_linear_srgb(&value, wavelengths));
    }
}

/// The media light paths start in (light tracing, BDPT): per light, the
/// medium around it where that is one medium for all its points
/// ([`medium_around_light`]; found per point for area lights), `None` in
/// every case without media.
pub(super) struct LightMedia {
    around: Vec<Option<Option<u32>>>,
}

impl LightMedia {
    /// The lights' media of `scene`; environment and directional lights in
    /// a medium that fills the scene are refused (their paths would start
    /// outside it), with `integrator` named in the message.
    pub(super) fn new(scene: &Scene, integrator: &str) -> Result<Self, RenderError> {
        if scene.camera_medium.is_some() && scene.lights.iter().any(|light| light.is_infinite()) {
            return Err(RenderError::Unsupported(format!(
                "{integrator} cannot start light paths of environment or directional lights in \
                 a medium that fills the scene; use --integrator volpath"
            )));
        }
        let around = if scene.has_media() {
            (0..scene.lights.len())
                .map(|index| medium_around_light(scene, index))
                .collect()
        } else {
            vec![Some(None); scene.lights.len()]
        };
        Ok(Self { around })
    }

    /// The medium around light `light_index`'s point `point` (normal
    /// `normal`).
    pub(super) fn around(
        &self,
        scene: &Scene,
        light_index: usize,
        point: Vec3,
        normal: Vec3,
    ) -> Option<u32> {
        self.around[light_index].unwrap_or_else(|| medium_at(scene, point, normal))
    }

    /// The medium a path leaving light `light_index`'s point `point`
    /// (emitting normal `normal`) in `direction` starts in.
    pub(super) fn leaving(
        &self,
        scene: &Scene,
        light_index: usize,
        point: Vec3,
        normal: Vec3,
        direction: Vec3,
    ) -> Option<u32> {
        let around = self.around(scene, light_index, point, normal);
        emission_medium(scene, &scene.lights[light_index], around, normal, direction)
    }
}

/// The medium a particle leaving light `light` (emitting normal `normal`)
/// in `direction` enters: for an area light on a shape with a medium
/// interface, the medium on that side; otherwise `around`, the medium the
/// light sits in ([`medium_around_light`]).
fn emission_medium(
    scene: &Scene,
    light: &Light,
    around: Option<u32>,
    normal: Vec3,
    direction: Vec3,
) -> Option<u32> {
    match light {
        Light::Area { shape_index, .. } => medium_after(
            scene.shapes[*shape_index as usize]
                .medium_interface
                .as_ref(),
            normal,
            direction,
            around,
        ),
        _ => around,
    }
}

/// The medium a light sits in, where that is the same for all its points:
/// the medium at its position for points, spots and projectors, the
/// camera's for lights at infinity; `None` for area lights, whose points
/// are looked up one by one ([`medium_at`]).
fn medium_around_light(scene: &Scene, light_index: usize) -> Option<Option<u32>> {
    let light = &scene.lights[light_index];
    if light.is_infinite() {
        return Some(scene.camera_medium);
    }
    if matches!(light, Light::Area { .. }) {
        return None;
    }
    let wavelengths = SampledWavelengths::sample_visible(0.5);
    let emission = light.sample_emission(&scene.geometry, 0.5, [0.5; 2], [0.5; 2], &wavelengths)?;
    Some(medium_at(scene, emission.origin, emission.normal))
}

/// The medium at `point` (on a surface of normal `normal`, or zero), found
/// as the camera paths of `volpath` find it: from the camera (in its
/// medium) along a segment to the point, the medium changed at every
/// surface with a medium interface crossed on the way.
pub(super) fn medium_at(scene: &Scene, point: Vec3, normal: Vec3) -> Option<u32> {
    let camera_ray = scene.camera.generate_ray(
        Vec2::from(scene.camera.resolution().map(|size| size as f32 * 0.5)),
        [0.5; 2],
        0.5,
    );
    let Some((mut ray, mut t_max)) =
        spawn_segment_to_point(camera_ray.origin, camera_ray.time, point, normal)
    else {
        return scene.camera_medium;
    };
    let mut medium = scene.camera_medium;
    for _ in 0..MAX_INTERFACE_CROSSINGS {
        let Some(hit) = scene.geometry.intersect(&ray, t_max) else {
            break;
        };
        let info = &scene.shapes[hit.shape_index as usize];
        let oriented_normal = if info.flip_normals {
            -hit.geometric_normal
        } else {
            hit.geometric_normal
        };
        medium = medium_after(
            info.medium_interface.as_ref(),
            oriented_normal,
            ray.direction,
            medium,
        );
        let next = crate::geometry::spawn_ray(&hit, ray.direction);
        t_max -= (next.origin - ray.origin).dot(ray.direction);
        if t_max <= 0.0 {
            break;
        }
        ray = next;
    }
    medium
}

/// The environment seen directly: one camera ray per pixel sample, at a
/// position uniform in the pixel's share of the image grown by the
/// filter's radius on every side (border pixels' filters reach that far
/// out, as the path tracer's camera samples do), splatted there if it
/// leaves the scene, scaled by the grown image's area over the image's.
fn splat_seen_environment<S: SampleSource + ?Sized>(
    scene: &Scene,
    pixel: (u32, u32),
    wavelengths: &SampledWavelengths,
    sampler: &mut S,
    splats: &mut SplatBuffer,
    counters: &mut TraceCounters,
) {
    let [u, v] = sampler.get_2d(layout::FILM);
    let [width, height] = scene.camera.resolution().map(|size| size as f32);
    let [margin_x, margin_y] = scene.filter.radius();
    let (grown_width, grown_height) = (width + 2.0 * margin_x, height + 2.0 * margin_y);
    let raster = Vec2::new(
        -margin_x + (pixel.0 as f32 + u) * grown_width / width,
        -margin_y + (pixel.1 as f32 + v) * grown_height / height,
    );
    let area_ratio = grown_width * grown_height / (width * height);
    let u_lens = lens_numbers(scene, sampler, layout::LENS);
    let u_time = if scene.camera.uses_time_sample() {
        sampler.get(layout::TIME)
    } else {
        0.5
    };
    let camera_ray = scene.camera.generate_ray(raster, u_lens, u_time);
    let mut ray = Ray::with_time(camera_ray.origin, camera_ray.direction, camera_ray.time);
    // Through media (and null surfaces), the environment is attenuated on
    // its way to the lens.
    let transmittance = if scene.has_media() {
        let transmittance = shadow_transmittance(
            scene,
            ray,
            f32::INFINITY,
            scene.camera_medium,
            wavelengths,
            counters,
        );
        if transmittance.is_black() {
            return;
        }
        transmittance
    } else {
        loop {
            counters.closest_hit_rays += 1;
            match scene.geometry.intersect(&ray, f32::INFINITY) {
                // Index-matched boundaries are crossed, as the path tracer does.
                Some(hit) if scene.shapes[hit.shape_index as usize].is_interface => {
                    ray = crate::geometry::spawn_ray(&hit, ray.direction);
                }
                Some(_) => return,
                None => break,
            }
        }
        SampledSpectrum::splat(1.0)
    };
    let mut radiance = SampledSpectrum::zero();
    for &index in &scene.environment_lights {
        radiance += scene.lights[index as usize].environment_radiance(ray.direction, wavelengths);
    }
    let _ = splats.add(
        raster.to_array(),
        to_linear_srgb(&(radiance * transmittance * area_ratio), wavelengths),
    );
}
