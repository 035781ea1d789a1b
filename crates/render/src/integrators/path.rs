//! Unidirectional path tracing with next-event estimation and multiple
//! importance sampling (pbrt-v4's `PathIntegrator`, Veach 1997), spectral
//! with four hero wavelengths.
//!
//! Depth follows Mitsuba's convention: `max_depth` is the largest number of
//! segments a path may have, so 1 shows only directly visible emitters and
//! 2 adds direct illumination. Russian roulette uses its own dimension of
//! each vertex block and starts after the third vertex.

use super::TraceCounters;
use super::camera_path::{CameraPathIntegrator, CameraPathRadiance};
pub use super::estimator::PathSettings;
use super::estimator::mis::{emission_weight, environment_emission};
use super::estimator::next_event::{AreaRadianceCache, next_event_at_surface};
use super::path_space::{ScattererRef, VertexAt, WalkObserver, WalkState};
use crate::geometry::SurfaceHit;
use crate::sampler::SampleSource;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;
use std::ops::ControlFlow;

/// The path tracer as an [`Integrator`]: the camera-path shell over
/// [`PathTracing`].
pub type PathIntegrator = CameraPathIntegrator<PathTracing>;

/// The path tracer's radiance estimate for the camera-path shell
/// ([`super::camera_path::radiance`]): a walk over surfaces (media are
/// ignored) observed by [`PathRadiance`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathTracing;

impl CameraPathRadiance for PathTracing {
    const MEDIA: bool = false;
    type Observer<'a> = PathRadiance<'a>;

    fn check_scene(scene: &Scene) {
        if scene.has_media() {
            log::warn!("the path integrator ignores participating media; use --integrator volpath");
        }
    }

    #[inline(always)]
    fn observer<'a>(scene: &'a Scene, settings: &'a PathSettings) -> PathRadiance<'a> {
        PathRadiance {
            scene,
            settings,
            radiance: SampledSpectrum::zero(),
            area_radiance: AreaRadianceCache::new(),
        }
    }

    #[inline(always)]
    fn radiance(observer: PathRadiance<'_>) -> SampledSpectrum {
        observer.radiance
    }
}

/// The path tracer's observer of the walk: emission found by BSDF sampling
/// and next-event estimation at every non-specular vertex, MIS-weighted
/// against each other with the settings' heuristic.
pub struct PathRadiance<'a> {
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
                &walk.previous,
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
        let radiance = &mut self.radiance;
        environment_emission(
            self.scene,
            self.settings,
            &walk.previous,
            direction,
            wavelengths,
            |emitted, weight| *radiance += walk.beta * emitted * weight,
        );
    }

    // Always inlined, so that the walk compiled into the driver's AVX2 tile
    // loop has its observer in it: with LQMC's seed screen as a second user
    // LLVM stopped inlining it.
    #[inline(always)]
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
                * next_event_at_surface(
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
