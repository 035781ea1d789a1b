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
use super::path_space::{
    ScattererRef, VertexAt, WalkObserver, WalkSettings, WalkStart, WalkState, walk,
};
pub(crate) use super::path_space::{orient_hit, russian_roulette};
use super::progression_variance::ProgressionVariance;
use super::{Integrator, IntegratorRender, MisHeuristic, RenderError, RunControl, TraceCounters};
use crate::film::Film;
use crate::geometry::{OffsetPoint, Ray, SurfaceHit, occlusion_segment_to_point};
use crate::material::SurfaceBsdf;
use crate::sampler::{PixelSampler, SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum, to_linear_srgb};
use glam::Vec3;
use std::ops::ControlFlow;

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
    /// Camera-path integrators (path, volpath): place each sample uniformly
    /// in its pixel and splat it over the pixels of the film's filter
    /// (Mitsuba's film) instead of importance-sampling the filter and adding
    /// it to its own pixel (pbrt-v4's; the default). Splatting lets a
    /// sample reach every pixel its filter covers, as LQMC's splats do, so
    /// it is the like-for-like baseline for LQMC. The variance layer then
    /// comes from the progressions ([`super::progression_variance`]).
    pub splat_film: bool,
    /// Paths of fewer segments than this contribute nothing (default 1:
    /// every path). PSSMLT's separate direct lighting (`--mlt-direct-spp`)
    /// leaves paths of 1 and 2 segments to a path tracer of depth 2 and
    /// runs its chains from 3 on (path and volpath observe it).
    pub min_depth: u32,
}

impl Default for PathSettings {
    fn default() -> Self {
        Self {
            max_depth: 6,
            heuristic: MisHeuristic::Power,
            russian_roulette_depth: 3,
            splat_film: false,
            min_depth: 1,
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
        render_pixel_samples(&estimator, scene, run).map(IntegratorRender::from_camera_paths)
    }
}

/// One camera path per pixel sample, its radiance added to its pixel.
struct PathEstimator<'a> {
    scene: &'a Scene,
    settings: &'a PathSettings,
}

impl PixelSampleEstimator for PathEstimator<'_> {
    type Unit = ();
    type Total = Option<ProgressionVariance>;

    fn pass_size(&self, samples_per_pixel: u64, timed: bool) -> u64 {
        camera_path_pass_size(self.settings, samples_per_pixel, timed)
    }

    fn new_total(&self, resolution: [usize; 2]) -> Result<Self::Total, RenderError> {
        Ok(self
            .settings
            .splat_film
            .then(|| ProgressionVariance::new(resolution)))
    }

    fn new_unit(&self) {}

    fn merge_unit(&self, _total: &mut Self::Total, _unit: (), _kept: bool) {}

    fn end_pass(&self, total: &mut Self::Total, film: &Film, complete: bool) {
        if let Some(progressions) = total {
            progressions.end_progression(film, complete);
        }
    }

    /// Always inlined into the driver's tile loop, so that the AVX2 copy of
    /// that loop compiles the path in it (see [`radiance`]).
    #[inline(always)]
    fn estimate<S: PixelSampler + ?Sized>(
        &self,
        _unit: &mut (),
        sample: PixelSampleIndex,
        sampler: &mut S,
        output: &mut UnitOutput,
    ) {
        let splat_film = self.settings.splat_film;
        let start = CameraPathStart::for_film(self.scene, sample.pixel, sampler, splat_film);
        let mut wavelengths = start.wavelengths;
        let radiance = radiance(
            self.scene,
            self.settings,
            start.ray,
            &mut wavelengths,
            sampler,
            &mut output.counters,
        );
        output.add_camera_path(
            &start,
            sample.pixel,
            to_linear_srgb(&radiance, &wavelengths),
            splat_film,
        );
    }
}

/// Samples per pass of a camera-path integrator: one progression per pass
/// when splatting (the variance layer needs each progression's image),
/// else the driver's default.
pub(crate) fn camera_path_pass_size(
    settings: &PathSettings,
    samples_per_pixel: u64,
    timed: bool,
) -> u64 {
    if settings.splat_film || timed {
        1
    } else {
        samples_per_pixel.clamp(1, 4)
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

/// Estimates the radiance along the camera ray `ray` for `wavelengths`:
/// the path-space walk with `PathRadiance` as its observer.
///
/// Generic over the sampler so that a concrete sampler's numbers (a hash
/// for the independent one) inline into the walk; `dyn SampleSource`
/// works as well. Always inlined, so that it is compiled into the AVX2
/// tile loop of the driver (`render_unit_avx2`).
#[inline(always)]
pub fn radiance<S: SampleSource + ?Sized>(
    scene: &Scene,
    settings: &PathSettings,
    ray: Ray,
    wavelengths: &mut SampledWavelengths,
    sampler: &mut S,
    counters: &mut TraceCounters,
) -> SampledSpectrum {
    let mut observer = PathRadiance {
        scene,
        settings,
        radiance: SampledSpectrum::zero(),
        area_radiance: AreaRadianceCache::new(),
    };
    walk(
        scene,
        WalkStart::camera(ray, None),
        &WalkSettings::camera(
            WalkSettings::camera_vertices(settings.max_depth),
            settings.russian_roulette_depth,
            false,
            false,
        ),
        wavelengths,
        sampler,
        counters,
        &mut observer,
    );
    observer.radiance
}

/// The path tracer's observer of the walk: emission found by BSDF sampling
/// and next-event estimation at every non-specular vertex, MIS-weighted
/// against each other with the settings' heuristic.
struct PathRadiance<'a> {
    scene: &'a Scene,
    settings: &'a PathSettings,
    radiance: SampledSpectrum,
    area_radiance: AreaRadianceCache,
}

impl WalkObserver for PathRadiance<'_> {
    const FINDS_EMISSION: bool = true;

    #[inline]
    fn emitter(
        &mut self,
        walk: &WalkState,
        light_index: u32,
        hit: &SurfaceHit,
        wo: Vec3,
        wavelengths: &SampledWavelengths,
    ) {
        // A path of vertex_index scatterings and this segment.
        if walk.vertex_index + 1 < self.settings.min_depth {
            return;
        }
        let scene = self.scene;
        let area_radiance = &mut self.area_radiance;
        let emitted = scene.lights[light_index as usize].emitted_radiance_with_area_radiance(
            hit.geometric_normal,
            hit.uv,
            wo,
            wavelengths,
            |spectrum| area_radiance.radiance(light_index as usize, spectrum, wavelengths),
        );
        if !emitted.is_black() {
            let weight = emission_weight(
                scene,
                self.settings,
                light_index,
                walk.previous.delta,
                walk.previous.point,
                walk.previous.pdf,
                hit.point,
                hit.geometric_normal,
            );
            self.radiance += walk.beta * emitted * weight;
        }
    }

    #[inline]
    fn escaped(&mut self, walk: &WalkState, direction: Vec3, wavelengths: &SampledWavelengths) {
        if walk.vertex_index + 1 < self.settings.min_depth {
            return;
        }
        for &index in &self.scene.environment_lights {
            let light = &self.scene.lights[index as usize];
            let emitted = light.environment_radiance(direction, wavelengths);
            let weight = emission_weight(
                self.scene,
                self.settings,
                index,
                walk.previous.delta,
                walk.previous.point,
                walk.previous.pdf,
                walk.previous.point + direction,
                Vec3::ZERO,
            );
            self.radiance += walk.beta * emitted * weight;
        }
    }

    #[inline]
    fn vertex<S: SampleSource + ?Sized>(
        &mut self,
        walk: &WalkState,
        vertex: &VertexAt<'_>,
        wavelengths: &SampledWavelengths,
        sampler: &mut S,
        counters: &mut TraceCounters,
    ) -> ControlFlow<()> {
        // The path tracer's walk has surface vertices only.
        let ScattererRef::Surface { hit, bsdf, offset } = vertex.scatterer else {
            return ControlFlow::Continue(());
        };
        // Next-event estimation makes a path of this vertex's scatterings
        // before it, its segment and the one to the light.
        if bsdf.flags().is_non_specular() && walk.vertex_index + 2 >= self.settings.min_depth {
            self.radiance += walk.beta
                * sample_light(
                    self.scene,
                    self.settings,
                    hit,
                    offset,
                    bsdf,
                    vertex.wo,
                    walk.block,
                    wavelengths,
                    sampler,
                    counters,
                    &mut self.area_radiance,
                );
        }
        ControlFlow::Continue(())
    }
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
