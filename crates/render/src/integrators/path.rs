//! Unidirectional path tracing with next-event estimation and multiple
//! importance sampling (pbrt-v4's `PathIntegrator`, Veach 1997), spectral
//! with four hero wavelengths.
//!
//! Depth follows Mitsuba's convention: `max_depth` is the largest number of
//! segments a path may have, so 1 shows only directly visible emitters and
//! 2 adds direct illumination. Russian roulette uses its own dimension of
//! each vertex block and starts after the third vertex.

use super::driver::{
    CameraPathStart, PixelSampleEstimator, PixelSampleIndex, UnitOutput, render_pixel_samples,
};
use super::path_vertex::PathVertex;
use super::{Integrator, IntegratorRender, MisHeuristic, RenderError, RunControl, TraceCounters};
use crate::geometry::{OffsetPoint, Ray, SurfaceHit, occlusion_segment_to_point, spawn_ray};
use crate::material::SurfaceBsdf;
use crate::sampler::{PixelSampler, SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum, to_linear_srgb};
use glam::Vec3;

/// Settings of the path tracer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathSettings {
    /// Maximum number of path segments (Mitsuba's `max_depth`; default 6...
    /// the caller decides; `u32::MAX` for no limit).
    pub max_depth: u32,
    /// The MIS heuristic (default power).
    pub heuristic: MisHeuristic,
    /// The vertex index from which Russian roulette may end paths (default 3).
    pub russian_roulette_depth: u32,
}

impl Default for PathSettings {
    fn default() -> Self {
        Self {
            max_depth: 6,
            heuristic: MisHeuristic::Power,
            russian_roulette_depth: 3,
        }
    }
}

/// The path tracer as an [`Integrator`], run by the tile driver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathIntegrator {
    settings: PathSettings,
}

impl PathIntegrator {
    /// The path tracer with `settings`.
    pub fn new(settings: PathSettings) -> Self {
        Self { settings }
    }
}

impl Integrator for PathIntegrator {
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError> {
        if scene.has_media() {
            log::warn!("the path integrator ignores participating media; use --integrator volpath");
        }
        let estimator = PathEstimator {
            scene,
            settings: &self.settings,
        };
        render_pixel_samples(&estimator, scene, run).map(IntegratorRender::from_driver)
    }
}

/// One camera path per pixel sample, its radiance added to its pixel.
struct PathEstimator<'a> {
    scene: &'a Scene,
    settings: &'a PathSettings,
}

impl PixelSampleEstimator for PathEstimator<'_> {
    type Unit = ();
    type Total = ();

    fn new_total(&self, _resolution: [usize; 2]) -> Result<(), RenderError> {
        Ok(())
    }

    fn new_unit(&self) {}

    fn merge_unit(&self, _total: &mut (), _unit: (), _kept: bool) {}

    #[inline]
    fn estimate<S: PixelSampler + ?Sized>(
        &self,
        _unit: &mut (),
        sample: PixelSampleIndex,
        sampler: &mut S,
        output: &mut UnitOutput,
    ) {
        let start = CameraPathStart::new(self.scene, sample.pixel, sampler);
        let mut wavelengths = start.wavelengths;
        let radiance = radiance(
            self.scene,
            self.settings,
            start.ray,
            &mut wavelengths,
            sampler,
            &mut output.counters,
            None,
        );
        output.add_camera_sample(
            [sample.pixel.0 as usize, sample.pixel.1 as usize],
            to_linear_srgb(&radiance, &wavelengths),
            start.position.weight,
        );
    }
}

/// An area light's radiance at one path's wavelengths, kept for the rest of
/// the path: every next-event sample and every emitter hit of the path needs
/// it, and evaluating an RGB illuminant spectrum at four wavelengths cost
/// more than the rest of a light sample. One entry (scenes usually have one
/// area light or a few); a miss evaluates and replaces it. The wavelengths
/// never change along a path (terminating the secondary ones changes their
/// densities, not the wavelengths), so entries stay valid.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AreaRadianceCache {
    light_index: usize,
    radiance: SampledSpectrum,
}

impl AreaRadianceCache {
    pub(crate) fn new() -> Self {
        Self {
            light_index: usize::MAX,
            radiance: SampledSpectrum::zero(),
        }
    }

    /// The radiance of light `light_index`, whose spectrum is `spectrum`, at
    /// `wavelengths` (the path's).
    #[inline]
    pub(crate) fn radiance(
        &mut self,
        light_index: usize,
        spectrum: &Spectrum,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        if self.light_index != light_index {
            self.light_index = light_index;
            self.radiance = spectrum.sample(wavelengths);
        }
        self.radiance
    }
}

/// The shading frame and the orientation-corrected hit of a surface.
pub(crate) fn oriented_hit(scene: &Scene, hit: &SurfaceHit) -> SurfaceHit {
    let mut hit = *hit;
    orient_hit(
        scene.shapes[hit.shape_index as usize].flip_normals,
        &mut hit,
    );
    hit
}

/// [`oriented_hit`] in place, for a shape whose `flip_normals` is given:
/// the path tracer needs the hit as stored only until it scatters, and a
/// second copy of the hit cost about 20 instructions per vertex.
#[inline]
pub(crate) fn orient_hit(flip_normals: bool, hit: &mut SurfaceHit) {
    if flip_normals {
        hit.geometric_normal = -hit.geometric_normal;
        hit.shading_normal = -hit.shading_normal;
    }
}

/// Estimates the radiance along the camera ray `ray` for `wavelengths`.
/// When `vertices` is given, the path's scattering vertices are recorded.
///
/// Generic over the sampler so that a concrete sampler's numbers (a hash
/// for the independent one) inline into the loop; `dyn SampleSource`
/// works as well.
pub fn radiance<S: SampleSource + ?Sized>(
    scene: &Scene,
    settings: &PathSettings,
    mut ray: Ray,
    wavelengths: &mut SampledWavelengths,
    sampler: &mut S,
    counters: &mut TraceCounters,
    mut vertices: Option<&mut Vec<PathVertex>>,
) -> SampledSpectrum {
    let mut radiance = SampledSpectrum::zero();
    let mut throughput = SampledSpectrum::splat(1.0);
    // Product of relative IORs of refractions, undone for Russian roulette.
    let mut eta_scale = 1.0f32;
    let mut specular_bounce = true;
    let mut previous_point = ray.origin;
    let mut previous_bsdf_pdf = 0.0f32;
    let mut depth = 0u32;
    let mut area_radiance = AreaRadianceCache::new();
    loop {
        counters.closest_hit_rays += 1;
        // The hit as stored (emission and light densities take its normal)
        // until it is oriented for scattering below.
        let Some(mut hit) = scene.geometry.intersect(&ray, f32::INFINITY) else {
            for &index in &scene.environment_lights {
                let light = &scene.lights[index as usize];
                let emitted = light.environment_radiance(ray.direction, wavelengths);
                let weight = emission_weight(
                    scene,
                    settings,
                    index,
                    specular_bounce,
                    previous_point,
                    previous_bsdf_pdf,
                    previous_point + ray.direction,
                    Vec3::ZERO,
                );
                radiance += throughput * emitted * weight;
            }
            break;
        };
        let info = &scene.shapes[hit.shape_index as usize];
        let wo = -ray.direction;

        // Emission seen by this segment.
        if let Some(light_index) = info.light {
            let light = &scene.lights[light_index as usize];
            let emitted = light.emitted_radiance_with_area_radiance(
                hit.geometric_normal,
                hit.uv,
                wo,
                wavelengths,
                |spectrum| area_radiance.radiance(light_index as usize, spectrum, wavelengths),
            );
            if !emitted.is_black() {
                let weight = emission_weight(
                    scene,
                    settings,
                    light_index,
                    specular_bounce,
                    previous_point,
                    previous_bsdf_pdf,
                    hit.point,
                    hit.geometric_normal,
                );
                radiance += throughput * emitted * weight;
            }
        }

        // Index-matched boundaries (media are ignored here) are passed
        // straight through, as pbrt-v4's PathIntegrator does.
        if info.is_interface {
            ray = spawn_ray(&hit, ray.direction);
            continue;
        }
        // A path of depth + 2 segments is the longest a scattering here can make.
        if depth + 2 > settings.max_depth {
            break;
        }
        let Some(material) = &info.material else {
            break;
        };
        orient_hit(info.flip_normals, &mut hit);
        let bsdf = material.surface_bsdf_at(&hit, wavelengths);
        let flags = bsdf.flags();
        // Light sampling and its densities are taken from the hit point moved
        // off the surface to the side of `wo`, so that a point on a sphere
        // light's own surface counts as inside or outside as seen from there
        // (pbrt-v4 does the same).
        // Rays leaving to the side of `wo` start from the same offset point.
        let offsets = OffsetPoint::new(hit.point, hit.geometric_normal, wo);
        let reference = offsets.origin();

        // Next-event estimation.
        if flags.is_non_specular() {
            radiance += throughput
                * sample_light(
                    scene,
                    settings,
                    &hit,
                    &offsets,
                    &bsdf,
                    wo,
                    depth,
                    wavelengths,
                    sampler,
                    counters,
                    &mut area_radiance,
                );
        }

        // Continue the path by sampling the BSDF.
        let u_component = sampler.get(layout::vertex(depth as usize, layout::SCATTER_COMPONENT));
        let u = sampler.get_2d(layout::vertex(depth as usize, layout::SCATTER_DIRECTION));
        let Some(sample) = bsdf.sample(wo, u_component, u, wavelengths) else {
            break;
        };
        let cosine = sample.wi.dot(bsdf.frame.normal()).abs();
        if sample.pdf <= 0.0 || sample.value.is_black() {
            break;
        }
        throughput *= sample.value * (cosine / sample.pdf);
        // A stochastic BSDF's sample carries a path density; MIS needs the
        // BSDF's own density estimate (the one next-event estimation uses).
        let bsdf_pdf = if sample.pdf_is_proportional {
            bsdf.pdf(wo, sample.wi)
        } else {
            sample.pdf
        };
        if let Some(vertices) = vertices.as_deref_mut() {
            vertices.push(PathVertex {
                point: hit.point,
                geometric_normal: hit.geometric_normal,
                shading_normal: hit.shading_normal,
                shape_index: hit.shape_index,
                primitive_index: hit.primitive_index,
                wo,
                wi: sample.wi,
                flags,
                sampled: sample.flags,
                pdf_forward: bsdf_pdf,
                pdf_reverse: if sample.is_specular() {
                    sample.pdf
                } else {
                    bsdf.pdf(sample.wi, wo)
                },
                first_dimension: layout::vertex(depth as usize, 0),
            });
        }
        specular_bounce = sample.is_specular();
        previous_bsdf_pdf = bsdf_pdf;
        previous_point = reference;
        if sample.is_transmission() {
            eta_scale *= sample.eta * sample.eta;
        }
        ray = Ray::with_time(offsets.towards(sample.wi), sample.wi, hit.time);

        // Russian roulette on the throughput without the refraction scaling.
        let roulette_throughput = (throughput * eta_scale).max_component();
        match russian_roulette(
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
    radiance
}

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

/// Next-event estimation at `hit`: one light sample, MIS-weighted against
/// BSDF sampling (not weighted for delta lights). `offsets` is the hit point
/// offset to the side of `wo` (the reference point of light sampling).
#[allow(clippy::too_many_arguments)]
fn sample_light<S: SampleSource + ?Sized>(
    scene: &Scene,
    settings: &PathSettings,
    hit: &SurfaceHit,
    offsets: &OffsetPoint,
    bsdf: &SurfaceBsdf,
    wo: Vec3,
    depth: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut S,
    counters: &mut TraceCounters,
    area_radiance: &mut AreaRadianceCache,
) -> SampledSpectrum {
    let Some(VertexLightSample {
        selection_probability,
        sample,
        ..
    }) = sample_vertex_light_with_cache(
        scene,
        offsets.origin(),
        depth,
        wavelengths,
        sampler,
        area_radiance,
    )
    else {
        return SampledSpectrum::zero();
    };
    let (value, bsdf_pdf) = bsdf.evaluate_with_pdf(wo, sample.wi, wavelengths);
    let value = value * sample.wi.dot(bsdf.frame.normal()).abs();
    if value.is_black() {
        return SampledSpectrum::zero();
    }
    counters.shadow_rays += 1;
    let origin = offsets.towards(sample.wi);
    let visible = if sample.is_infinite {
        let ray = Ray::with_time(origin, sample.wi, hit.time);
        !scene.geometry.occluded(&ray, f32::INFINITY)
    } else {
        match occlusion_segment_to_point(origin, hit.time, sample.point, sample.normal) {
            Some((ray, t_max)) => !scene.geometry.occluded(&ray, t_max),
            None => false,
        }
    };
    if !visible {
        return SampledSpectrum::zero();
    }
    let light_pdf = selection_probability * sample.pdf;
    let weight_over_pdf = if sample.is_delta {
        1.0 / light_pdf
    } else {
        settings.heuristic.weight_over_density(light_pdf, bsdf_pdf)
    };
    value * sample.radiance * weight_over_pdf
}

/// Russian roulette at vertex `depth` (pbrt-v4's rule): from
/// `start_depth` on, a path whose `roulette_throughput` is below 1 survives
/// with probability max(throughput, 0.05), decided by the number `u` gives
/// (read only then). Returns the probability to divide the throughput by (1
/// without roulette), or `None` when the path ends. Every integrator and
/// LQMC's walks decide here, so a rebuilt path takes its seed's decision
/// from the same number.
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

/// A light chosen for next-event estimation at a path vertex and the point
/// sampled on it, with the numbers that made both (LQMC keeps them).
#[derive(Debug, Clone, Copy)]
pub(crate) struct VertexLightSample {
    pub light_index: usize,
    pub selection_probability: f32,
    pub u_primitive: f32,
    pub u_position: [f32; 2],
    pub sample: crate::light::LightSample,
}

/// Chooses a light and samples it as seen from `reference`, with the light
/// dimensions of vertex `depth`; `None` when nothing is chosen or the
/// sampled radiance is black. Every integrator's next-event estimation
/// starts here.
pub(crate) fn sample_vertex_light(
    scene: &Scene,
    reference: Vec3,
    depth: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut dyn SampleSource,
) -> Option<VertexLightSample> {
    sample_vertex_light_with_cache(
        scene,
        reference,
        depth,
        wavelengths,
        sampler,
        &mut AreaRadianceCache::new(),
    )
}

/// [`sample_vertex_light`] taking area lights' radiance from a path's
/// `area_radiance` cache.
fn sample_vertex_light_with_cache<S: SampleSource + ?Sized>(
    scene: &Scene,
    reference: Vec3,
    depth: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut S,
    area_radiance: &mut AreaRadianceCache,
) -> Option<VertexLightSample> {
    let u_select = sampler.get(layout::vertex(depth as usize, layout::LIGHT_SELECTION));
    let u_position = sampler.get_2d(layout::vertex(depth as usize, layout::LIGHT_POSITION));
    let (light_index, selection_probability, u_primitive) = scene.light_sampler.sample(u_select)?;
    let sample = scene.lights[light_index].sample_incident_with_area_radiance(
        &scene.geometry,
        reference,
        u_primitive,
        u_position,
        wavelengths,
        |spectrum| area_radiance.radiance(light_index, spectrum, wavelengths),
    )?;
    if sample.radiance.is_black() {
        return None;
    }
    Some(VertexLightSample {
        light_index,
        selection_probability,
        u_primitive,
        u_position,
        sample,
    })
}
