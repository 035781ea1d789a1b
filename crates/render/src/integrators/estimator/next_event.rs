//! Next-event estimation (Veach 1997 §9.2; pbrt-v4's `SampleLd`): at a
//! path vertex, choose a light with the light sampler, sample a point on it
//! as seen from the vertex, and estimate the light arriving from it — the
//! scattering value times the light's radiance, the shadow ray's
//! visibility or transmittance, and the MIS weight against the vertex's
//! own sampling over the light's density.

use super::PathSettings;
use super::shadow::{shadow_ray, shadow_transmittance};
use crate::geometry::{OffsetPoint, Ray, SurfaceHit, occlusion_segment_to_point};
use crate::integrators::TraceCounters;
use crate::integrators::path_space::medium_leaving;
use crate::light::LightSample;
use crate::material::SurfaceBsdf;
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec3;

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

/// A light chosen for next-event estimation at a path vertex and the point
/// sampled on it, with the numbers that made both (LQMC keeps them).
#[derive(Debug, Clone, Copy)]
pub(crate) struct VertexLightSample {
    pub light_index: usize,
    pub selection_probability: f32,
    pub u_primitive: f32,
    pub u_position: [f32; 2],
    pub sample: LightSample,
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
pub(crate) fn sample_vertex_light_with_cache<S: SampleSource + ?Sized>(
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

/// The path tracer's next-event estimation at `hit`: one light sample,
/// MIS-weighted against BSDF sampling with the settings' heuristic (not
/// weighted for delta lights), its shadow ray stopped by any surface.
/// `offsets` is the hit point offset to the side of `wo` (the reference
/// point of light sampling). The result still has to be multiplied by the
/// path throughput.
#[allow(clippy::too_many_arguments)]
pub(crate) fn next_event_at_surface<S: SampleSource + ?Sized>(
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

/// The volumetric path tracer's next-event estimation from `reference` (a
/// medium point, or a surface point offset off `hit`): one light sample,
/// its transmittance through the media and index-matched boundaries to the
/// light, balance-weighted over wavelengths and against `scatter`'s
/// sampling ([`super::mis`]'s spectral MIS). `scatter(wi)` gives the
/// scattering value (BSDF times cosine, or the phase function) and its
/// sampling density; `r_u` is the path's rescaled probability at the vertex.
/// The result still has to be multiplied by the path throughput.
#[allow(clippy::too_many_arguments)]
pub(crate) fn next_event_through_media(
    scene: &Scene,
    reference: Vec3,
    hit: Option<&SurfaceHit>,
    medium: Option<u32>,
    scatter: &dyn Fn(Vec3) -> (SampledSpectrum, f32),
    r_u: SampledSpectrum,
    depth: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut dyn SampleSource,
    counters: &mut TraceCounters,
) -> SampledSpectrum {
    let Some(VertexLightSample {
        selection_probability,
        sample,
        ..
    }) = sample_vertex_light(scene, reference, depth, wavelengths, sampler)
    else {
        return SampledSpectrum::zero();
    };
    let (value, scatter_pdf) = scatter(sample.wi);
    if value.is_black() {
        return SampledSpectrum::zero();
    }
    let (ray, t_max) = match shadow_ray(reference, hit, &sample) {
        Some(segment) => segment,
        None => return SampledSpectrum::zero(),
    };
    // The medium the shadow ray starts in: at a surface, the side `wi` leaves to.
    let start_medium = medium_leaving(scene, hit, medium, sample.wi);
    let transmittance =
        shadow_transmittance(scene, ray, t_max, start_medium, wavelengths, counters);
    if transmittance.is_black() {
        return SampledSpectrum::zero();
    }
    let light_pdf = selection_probability * sample.pdf;
    let r_l = r_u * light_pdf;
    let denominator = if sample.is_delta {
        r_l.average()
    } else {
        (r_l + r_u * scatter_pdf).average()
    };
    if denominator <= 0.0 {
        return SampledSpectrum::zero();
    }
    value * transmittance * sample.radiance / denominator
}
