//! The seed paths: path tracing with next-event estimation driven by the
//! pixel sampler (Halton in the paper), recording each vertex and each
//! splat event (every emitter reached, every next-event connection) for
//! exploration. The decisions follow [`crate::integrators::path`] exactly;
//! the values of the events are computed afterwards by
//! [`super::path_walk::walk`].

use super::classification::lobe_roughness;
use super::path_record::{CameraVertex, LightConnection, SplatEvent, SurfaceVertex, Terminal};
use crate::geometry::{Ray, offset_ray_origin, spawn_ray, spawn_ray_to_point};
use crate::integrators::TraceCounters;
use crate::integrators::path::{PathSettings, oriented_hit};
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec2;

/// A traced seed path and its splat events.
#[derive(Debug, Clone, Default)]
pub struct SeedPath {
    /// The camera vertex (`None` before tracing).
    pub camera: Option<CameraVertex>,
    /// The surface vertices in order from the camera.
    pub vertices: Vec<SurfaceVertex>,
    /// The splat events, in the order the path tracer adds them.
    pub events: Vec<SplatEvent>,
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
    if !scene.media.is_empty() {
        return super::volume_seed::trace_volumetric_seed_path(
            scene, settings, raster, sampler, counters, path,
        );
    }
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
    let mut throughput = SampledSpectrum::splat(1.0);
    let mut eta_scale = 1.0f32;
    let mut depth = 0u32;
    loop {
        counters.closest_hit_rays += 1;
        let Some(raw_hit) = scene.geometry.intersect(&ray, f32::INFINITY) else {
            if !scene.environment_lights.is_empty() {
                path.events.push(SplatEvent::of_first_vertices(
                    path.vertices.len(),
                    Terminal::Environment {
                        direction: ray.direction,
                    },
                ));
            }
            break;
        };
        let hit = oriented_hit(scene, &raw_hit);
        let info = &scene.shapes[hit.shape_index as usize];
        let wo = -ray.direction;
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
        path.vertices.last_mut().expect("just pushed").roughness = lobe_roughness(&bsdf, flags);
        let reference = offset_ray_origin(hit.point, hit.geometric_normal, wo);
        if flags.is_non_specular()
            && let Some(connection) = sample_light(
                scene,
                &hit,
                reference,
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
        let u_component = sampler.get(layout::vertex(depth as usize, layout::SCATTER_COMPONENT));
        let u = sampler.get_2d(layout::vertex(depth as usize, layout::SCATTER_DIRECTION));
        let Some(sample) = bsdf.sample(wo, u_component, u, &mut wavelengths) else {
            break;
        };
        let cosine = sample.wi.dot(bsdf.frame.normal()).abs();
        if sample.pdf <= 0.0 || sample.value.is_black() {
            break;
        }
        throughput *= sample.value * (cosine / sample.pdf);
        let vertex = path.vertices.last_mut().expect("just pushed");
        vertex.sampled = sample.flags;
        vertex.roughness = lobe_roughness(&bsdf, sample.flags);
        if sample.is_transmission() {
            eta_scale *= sample.eta * sample.eta;
        }
        ray = spawn_ray(&raw_hit, sample.wi);
        let roulette_throughput = (throughput * eta_scale).max_component();
        match crate::integrators::path::russian_roulette(
            roulette_throughput,
            depth,
            settings.russian_roulette_depth,
            || sampler.get(layout::vertex(depth as usize, layout::RUSSIAN_ROULETTE)),
        ) {
            Some(survival) => throughput /= survival,
            None => break,
        }
        depth += 1;
    }
}

/// Next-event estimation's light sample at a vertex, if it reaches the
/// light unoccluded with non-zero radiance.
pub(super) fn sample_light(
    scene: &Scene,
    hit: &crate::geometry::SurfaceHit,
    reference: glam::Vec3,
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
    counters.shadow_rays += 1;
    let visible = if sample.is_infinite {
        let ray = spawn_ray(hit, sample.wi);
        !scene.geometry.occluded(&ray, f32::INFINITY)
    } else {
        match spawn_ray_to_point(hit, sample.point, sample.normal) {
            Some((ray, t_max)) => !scene.geometry.occluded(&ray, t_max),
            None => false,
        }
    };
    visible.then(|| LightConnection::from_sample(scene, light_sample))
}
