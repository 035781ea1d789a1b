//! Seeds traced by the path tracer first: no price where nothing is
//! explored.
//!
//! Recording a seed for exploration (its vertices, events and their values,
//! [`super::seed_path`]) costs about a fifth more than the path tracer's
//! sample, and by default (only caustic paths explored) almost no seed has
//! an event to explore. So where explorations are rare, a seed is first
//! traced by the path tracer's walk and observer ([`PathTracing`]), with a
//! watch on what decides whether an event is explored: the circle of
//! confusion of the first hit, the roughness of each scattering vertex and
//! the events the path can make. Only if one of those events could be
//! explored is the seed traced again, from the same numbers and so along
//! the same path, and recorded; otherwise it is the path tracer's sample,
//! its value and its cost.
//!
//! The watch decides by the same rule as the exploration
//! ([`super::classification::class_of`]) over the same inputs, mirrored
//! from [`super::seed_path`]'s recorder callback by callback, and it errs
//! only towards tracing again: every vertex that could connect to a light
//! counts as a next-event event, and a path that passes an index-matched
//! emitter is always recorded. A seed it lets through is one that no
//! exploration would have taken, so the estimator is the one without the
//! watch (test `screening_changes_no_exploration`).
//!
//! Where it applies ([`screens_seeds`]): scenes without media (the seed's
//! walk through media is not the volumetric path tracer's, which passes
//! null surfaces), with only classes explored that are rare: caustic
//! paths, and depth-of-field paths through a pinhole (none).

use super::classification::{
    PathClass, circle_of_confusion_at, class_of, lobe_roughness, long_enough_to_explore,
    scattered_roughness,
};
use super::path_record::EventKind;
use super::settings::LqmcSettings;
use crate::geometry::{Ray, SurfaceHit};
use crate::integrators::TraceCounters;
use crate::integrators::camera_path::CameraPathRadiance;
use crate::integrators::estimator::PathSettings;
use crate::integrators::path::PathTracing;
use crate::integrators::path_space::{
    ScattererRef, Scattering, VertexAt, WalkObserver, WalkStart, WalkState, walk,
};
use crate::material::BsdfFlags;
use crate::sampler::SampleSource;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;
use std::ops::ControlFlow;

/// Whether a render's seeds are screened: no media, and only classes
/// explored that few paths are in.
pub fn screens_seeds(scene: &Scene, settings: &LqmcSettings) -> bool {
    let rare = |class: PathClass| match class {
        PathClass::Caustic => true,
        PathClass::DepthOfField => scene.camera.lens_radius() <= 0.0,
        PathClass::Normal | PathClass::NextEvent => false,
    };
    settings.screen_seeds
        && !scene.has_media()
        && PathClass::ALL
            .into_iter()
            .all(|class| !settings.class_parameters(class).explore || rare(class))
}

/// One vertex as the screen sees it: what [`super::classification::vertex_roughness`]
/// reads of a recorded vertex.
#[derive(Debug, Clone, Copy)]
struct WatchedVertex {
    roughness: f32,
    sampled: BsdfFlags,
}

/// An event the path can make: the number of its vertices and how it ends.
#[derive(Debug, Clone, Copy)]
struct PossibleEvent {
    vertex_count: usize,
    kind: EventKind,
}

/// Buffers of the screen, reused from one seed to the next.
#[derive(Debug, Default)]
pub struct ScreenScratch {
    vertices: Vec<WatchedVertex>,
    events: Vec<PossibleEvent>,
}

/// A seed traced by the path tracer, if none of its events could be
/// explored: its radiance and wavelengths (as the path tracer's estimate
/// left them). `None` when it must be recorded.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub fn path_traced_seed<S: SampleSource + ?Sized>(
    scene: &Scene,
    settings: &LqmcSettings,
    path_settings: &PathSettings,
    camera_origin: Vec3,
    ray: Ray,
    mut wavelengths: SampledWavelengths,
    sampler: &mut S,
    counters: &mut TraceCounters,
    scratch: &mut ScreenScratch,
) -> Option<(SampledSpectrum, SampledWavelengths)> {
    scratch.vertices.clear();
    scratch.events.clear();
    let mut screen = SeedScreen {
        radiance: PathTracing::observer(scene, path_settings),
        scene,
        camera_origin,
        circle_of_confusion: 0.0,
        vertices: &mut scratch.vertices,
        events: &mut scratch.events,
        passed_emitter: false,
    };
    walk(
        scene,
        WalkStart::camera(ray, scene.camera_medium),
        &super::seed_path::seed_walk_settings(scene, path_settings),
        &mut wavelengths,
        sampler,
        counters,
        &mut screen,
    );
    if screen.passed_emitter || screen.could_explore(settings) {
        return None;
    }
    Some((PathTracing::radiance(screen.radiance), wavelengths))
}

/// The path tracer's observer with the watch.
struct SeedScreen<'a, 'b> {
    radiance: <PathTracing as CameraPathRadiance>::Observer<'a>,
    scene: &'a Scene,
    camera_origin: Vec3,
    circle_of_confusion: f32,
    vertices: &'b mut Vec<WatchedVertex>,
    events: &'b mut Vec<PossibleEvent>,
    passed_emitter: bool,
}

impl SeedScreen<'_, '_> {
    /// Whether an event the path can make would be explored, by the rule
    /// of `exploration::handle_event`: at least three vertices, a class
    /// that `settings` explores.
    fn could_explore(&self, settings: &LqmcSettings) -> bool {
        self.events.iter().any(|event| {
            if !long_enough_to_explore(event.kind.last_vertex(event.vertex_count)) {
                return false;
            }
            let scattering = event.kind.scattering_count(event.vertex_count);
            let class = class_of(
                settings,
                || self.circle_of_confusion,
                self.vertices[..scattering]
                    .iter()
                    .map(|vertex| scattered_roughness(vertex.sampled, vertex.roughness)),
                event.kind == EventKind::NextEvent,
            );
            settings.class_parameters(class).explore
        })
    }
}

impl WalkObserver for SeedScreen<'_, '_> {
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
        self.radiance
            .emitter(walk, light_index, hit, wo, wavelengths);
        if self.scene.shapes[hit.shape_index as usize].is_interface {
            self.passed_emitter = true;
            return;
        }
        self.events.push(PossibleEvent {
            vertex_count: self.vertices.len(),
            kind: EventKind::Emission,
        });
    }

    #[inline]
    fn escaped(&mut self, walk: &WalkState, direction: Vec3, wavelengths: &SampledWavelengths) {
        self.radiance.escaped(walk, direction, wavelengths);
        if !self.scene.environment_lights.is_empty() {
            self.events.push(PossibleEvent {
                vertex_count: self.vertices.len(),
                kind: EventKind::Environment,
            });
        }
    }

    #[inline]
    fn surface(
        &mut self,
        walk: &WalkState,
        hit: &SurfaceHit,
        wavelengths: &SampledWavelengths,
    ) -> ControlFlow<()> {
        if self.vertices.is_empty() {
            self.circle_of_confusion =
                circle_of_confusion_at(self.scene, self.camera_origin, hit.point);
        }
        self.vertices.push(WatchedVertex {
            roughness: 1.0,
            sampled: BsdfFlags::NONE,
        });
        self.radiance.surface(walk, hit, wavelengths)
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
        if let ScattererRef::Surface { bsdf, .. } = vertex.scatterer {
            let flags = bsdf.flags();
            if let Some(last) = self.vertices.last_mut() {
                last.roughness = lobe_roughness(bsdf, flags);
            }
            if flags.is_non_specular() {
                self.events.push(PossibleEvent {
                    vertex_count: self.vertices.len(),
                    kind: EventKind::NextEvent,
                });
            }
        }
        self.radiance
            .vertex(walk, vertex, wavelengths, sampler, counters)
    }

    #[inline]
    fn scattered(&mut self, vertex: &VertexAt<'_>, scattering: &Scattering) -> ControlFlow<()> {
        if let ScattererRef::Surface { bsdf, .. } = vertex.scatterer
            && let Some(last) = self.vertices.last_mut()
        {
            last.sampled = scattering.flags;
            last.roughness = lobe_roughness(bsdf, scattering.flags);
        }
        self.radiance.scattered(vertex, scattering)
    }
}
