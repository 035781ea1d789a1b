//! Rebuilding a member's prefix `x_0 .. x_b` from its numbers and
//! reconnecting it to the seed's static suffix `x_{b+1} .. x_k` (Alg. 1,
//! lines 9 and 10), with the failure rules of the implementation notes: a
//! prefix vertex that changes its sampled mode, a prefix ray that leaves the
//! scene, a blocked reconnection, or one that lands away from the seed's
//! `x_{b+1}` make the member fail.
//!
//! Media: in scenes with participating media the prefix is traced through
//! them as [`crate::integrators::volpath`] does (free flights from each
//! block's `FREE_FLIGHT` number, medium vertices scattering with the phase
//! function; [`super::medium_segment`]), and the reconnection and every
//! other segment are traced, with their transmittance, by the walk
//! ([`super::volume_walk`]).

use super::classification::lobe_roughness;
use super::medium_segment::{lands_at, medium_roughness};
use super::path_record::{CameraVertex, SplatEvent, SurfaceVertex, Terminal};
use super::statistics::FailureReason;
pub use crate::film::ImagePlane;
use crate::geometry::{Ray, SurfaceHit, spawn_ray, spawn_ray_through};
use crate::integrators::TraceCounters;
use crate::integrators::path_space::{
    ScattererRef, Scattering, VertexAt, WalkObserver, WalkSettings, WalkStart, WalkState,
    oriented_hit, walk,
};
use crate::material::SurfaceBsdf;
use crate::sampler::{DynSource, SampleSource};
use crate::scene::Scene;
use crate::spectrum::SampledWavelengths;
use glam::{Vec2, Vec3};
use std::ops::ControlFlow;

/// Answers explored dimensions from a member's numbers and every other
/// dimension from the seed's.
pub struct MemberSource<'a> {
    /// The seed's numbers.
    pub seed: &'a mut dyn SampleSource,
    /// `(dimension, number)` of the explored dimensions.
    pub overrides: &'a [(usize, f32)],
}

impl SampleSource for MemberSource<'_> {
    fn get(&mut self, dimension: usize) -> f32 {
        match self.overrides.iter().find(|(d, _)| *d == dimension) {
            Some((_, value)) => *value,
            None => self.seed.get(dimension),
        }
    }
}

/// The camera numbers of a member.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MemberCamera {
    /// Raster position (for b ≥ 1).
    pub raster: Vec2,
    /// Lens numbers.
    pub u_lens: [f32; 2],
    /// Time number.
    pub u_time: f32,
    /// Wavelength number.
    pub u_wavelength: f32,
}

/// A rebuilt surface vertex: the seed's sampled lobe, the roughness of
/// that lobe of the member's own BSDF.
fn rebuilt_surface_vertex(
    raw_hit: SurfaceHit,
    hit: SurfaceHit,
    bsdf: &SurfaceBsdf,
    seed_vertex: &SurfaceVertex,
) -> SurfaceVertex {
    let lobes = if seed_vertex.sampled.is_empty() {
        bsdf.flags()
    } else {
        seed_vertex.sampled
    };
    SurfaceVertex {
        sampled: seed_vertex.sampled,
        ..SurfaceVertex::surface(raw_hit, hit, lobe_roughness(bsdf, lobes))
    }
}

/// At the full-path breakup b = k of an emission path, the rebuilt last
/// vertex `x_k` (layout vertex `m`): `None` for any other vertex; the
/// member's emitter if the ray landed on the seed's light, otherwise the
/// failure `Misplaced` (the member would be an event of another light).
fn rebuilt_emitter(
    scene: &Scene,
    event: &SplatEvent,
    breakup: usize,
    m: usize,
    raw_hit: SurfaceHit,
    hit: SurfaceHit,
    seed_vertex: &SurfaceVertex,
) -> Option<Result<SurfaceVertex, FailureReason>> {
    let Terminal::Emission { light_index } = event.terminal else {
        return None;
    };
    if breakup != event.vertex_count || m + 1 != event.vertex_count {
        return None;
    }
    Some(
        if scene.shapes[hit.shape_index as usize].light == Some(light_index) {
            Ok(SurfaceVertex {
                raw_hit,
                hit,
                ..*seed_vertex
            })
        } else {
            Err(FailureReason::Misplaced)
        },
    )
}

/// Rebuilds `x_1 .. x_b` (`rebuilt` vertices) by the path-space walk from
/// the camera ray `ray` with the member's numbers (through media as
/// `volpath` traces them: free flights from `FREE_FLIGHT`, directions from
/// `SCATTER_DIRECTION`; the seed's component numbers), without Russian
/// roulette (the seed's decisions are the value walk's). A vertex whose
/// kind differs from the seed's (medium or surface, the medium, the sampled
/// lobe) fails the member with `ModeChange`; a prefix that leaves the scene
/// or reaches a surface without material fails with `Escaped`, one the walk
/// ends otherwise (a sample without value) with `Evaluation`.
#[allow(clippy::too_many_arguments)]
fn rebuild_prefix(
    scene: &Scene,
    seed_vertices: &[SurfaceVertex],
    event: &SplatEvent,
    breakup: usize,
    ray: Ray,
    wavelengths: &mut SampledWavelengths,
    source: &mut dyn SampleSource,
    counters: &mut TraceCounters,
    vertices: &mut Vec<SurfaceVertex>,
) -> Result<(), FailureReason> {
    let rebuilt = breakup.min(seed_vertices.len());
    let mut rebuilder = PrefixRebuilder {
        scene,
        seed_vertices,
        event,
        breakup,
        vertices,
        raw_hit: None,
        outcome: None,
    };
    walk(
        scene,
        WalkStart::camera(ray, scene.camera_medium),
        // No Russian roulette: the seed's decisions are the value walk's.
        &WalkSettings::camera(rebuilt, u32::MAX, scene.has_media(), false),
        wavelengths,
        &mut DynSource(source),
        counters,
        &mut rebuilder,
    );
    match rebuilder.outcome {
        Some(outcome) => outcome,
        None if rebuilder.vertices.len() == rebuilt => Ok(()),
        None => Err(FailureReason::Evaluation),
    }
}

/// The prefix rebuild's observer of the walk: records the member's
/// vertices and checks each against the seed's.
struct PrefixRebuilder<'a> {
    scene: &'a Scene,
    seed_vertices: &'a [SurfaceVertex],
    event: &'a SplatEvent,
    breakup: usize,
    vertices: &'a mut Vec<SurfaceVertex>,
    /// The surface reached, as stored, until its vertex is recorded.
    raw_hit: Option<SurfaceHit>,
    /// How the rebuild ended, if it did before its last vertex.
    outcome: Option<Result<(), FailureReason>>,
}

impl PrefixRebuilder<'_> {
    fn end(&mut self, outcome: Result<(), FailureReason>) -> ControlFlow<()> {
        self.outcome = Some(outcome);
        ControlFlow::Break(())
    }
}

impl WalkObserver for PrefixRebuilder<'_> {
    const FINDS_EMISSION: bool = false;

    fn surface(
        &mut self,
        _walk: &WalkState,
        raw_hit: &SurfaceHit,
        _wavelengths: &SampledWavelengths,
    ) -> ControlFlow<()> {
        let m = self.vertices.len();
        let Some(seed_vertex) = self.seed_vertices.get(m) else {
            return self.end(Err(FailureReason::Evaluation));
        };
        if seed_vertex.is_medium() {
            return self.end(Err(FailureReason::ModeChange));
        }
        let hit = oriented_hit(self.scene, raw_hit);
        if let Some(emitter) = rebuilt_emitter(
            self.scene,
            self.event,
            self.breakup,
            m,
            *raw_hit,
            hit,
            seed_vertex,
        ) {
            return match emitter {
                Ok(vertex) => {
                    self.vertices.push(vertex);
                    self.end(Ok(()))
                }
                Err(reason) => self.end(Err(reason)),
            };
        }
        if self.scene.shapes[hit.shape_index as usize]
            .material
            .is_none()
        {
            return self.end(Err(FailureReason::Escaped));
        }
        self.raw_hit = Some(*raw_hit);
        ControlFlow::Continue(())
    }

    fn escaped(&mut self, _walk: &WalkState, _direction: Vec3, _wavelengths: &SampledWavelengths) {
        self.outcome = Some(Err(FailureReason::Escaped));
    }

    fn vertex<S: SampleSource + ?Sized>(
        &mut self,
        _walk: &WalkState,
        vertex: &VertexAt<'_>,
        _wavelengths: &SampledWavelengths,
        _sampler: &mut S,
        _counters: &mut TraceCounters,
    ) -> ControlFlow<()> {
        let seed_vertex = &self.seed_vertices[self.vertices.len()];
        match vertex.scatterer {
            ScattererRef::Medium { .. } => {
                let Some(medium) = vertex.medium else {
                    return self.end(Err(FailureReason::Evaluation));
                };
                if seed_vertex.medium != Some(medium) {
                    return self.end(Err(FailureReason::ModeChange));
                }
                self.vertices.push(SurfaceVertex::in_medium(
                    vertex.point,
                    vertex.time,
                    medium,
                    medium_roughness(self.scene, medium),
                ));
            }
            ScattererRef::Surface { hit, bsdf, .. } => {
                let raw_hit = self.raw_hit.take().expect("the surface was reached");
                self.vertices
                    .push(rebuilt_surface_vertex(raw_hit, *hit, bsdf, seed_vertex));
            }
        }
        ControlFlow::Continue(())
    }

    fn scattered(&mut self, vertex: &VertexAt<'_>, scattering: &Scattering) -> ControlFlow<()> {
        if matches!(vertex.scatterer, ScattererRef::Surface { .. })
            && scattering.flags != self.seed_vertices[self.vertices.len() - 1].sampled
        {
            return self.end(Err(FailureReason::ModeChange));
        }
        ControlFlow::Continue(())
    }
}

/// How a segment traced from `ray` towards the recorded surface vertex
/// `target`, `distance` away, ends: `Ok` if it lands on it (within the
/// relative `tolerance`), `Occluded` if something lies before it,
/// `Misplaced` otherwise. Only the closest primitive is asked for (no
/// surface record), up to the farthest distance at which a hit can still
/// land on the target: the triangle inequality bounds it by the distance
/// plus the tolerance plus the ray origin's offset from `from`.
fn trace_to_vertex(
    scene: &Scene,
    ray: &Ray,
    from: glam::Vec3,
    target: &SurfaceVertex,
    distance: f32,
    tolerance: f32,
    counters: &mut TraceCounters,
) -> Result<(), FailureReason> {
    counters.closest_hit_rays += 1;
    let offset = (ray.origin - from).length();
    let reach = (distance * (1.0 + 2.0 * tolerance) + 2.0 * offset) * (1.0 + 1e-5);
    match scene.geometry.intersect_primitive(ray, reach) {
        Some(hit)
            if lands_at(
                hit.reference.shape_index,
                ray.origin + hit.t * ray.direction,
                target,
                distance,
                tolerance,
            ) =>
        {
            Ok(())
        }
        Some(hit) if hit.t < distance * (1.0 - tolerance) => Err(FailureReason::Occluded),
        _ => Err(FailureReason::Misplaced),
    }
}

/// A rebuilt member: its camera vertex and, for breakup vertex 0, the
/// camera's projection of its first vertex (which the walk needs again).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RebuiltMember {
    /// The camera vertex.
    pub camera: CameraVertex,
    /// For b = 0: `camera.project(x_1, u_lens, u_time)`.
    pub first_projection: Option<crate::camera::CameraProjection>,
}

/// Rebuilds the member's vertices (prefix, then the seed's suffix) into
/// `vertices` and returns its camera vertex; `wavelengths` are those of the
/// member's wavelength number.
#[allow(clippy::too_many_arguments)]
pub fn rebuild_member(
    scene: &Scene,
    tolerance: f32,
    image_plane: &ImagePlane,
    seed_vertices: &[SurfaceVertex],
    event: &SplatEvent,
    breakup: usize,
    camera: &MemberCamera,
    wavelengths: SampledWavelengths,
    source: &mut dyn SampleSource,
    counters: &mut TraceCounters,
    vertices: &mut Vec<SurfaceVertex>,
) -> Result<RebuiltMember, FailureReason> {
    vertices.clear();
    let seed_vertices = &seed_vertices[event.vertex_range()];
    if breakup == 0 {
        let first = seed_vertices.first().ok_or(FailureReason::Evaluation)?;
        let projection = scene
            .camera
            .project(first.raw_hit.point, camera.u_lens, camera.u_time)
            .filter(|projection| image_plane.contains(projection.raster))
            .ok_or(FailureReason::OutsideImage)?;
        let member = RebuiltMember {
            camera: CameraVertex {
                raster: projection.raster,
                u_lens: camera.u_lens,
                u_time: camera.u_time,
                u_wavelength: camera.u_wavelength,
                origin: projection.origin,
            },
            first_projection: Some(projection),
        };
        if !scene.media.is_empty() {
            // The walk traces (and checks) every segment through the media.
            vertices.extend_from_slice(seed_vertices);
            return Ok(member);
        }
        let to_first = first.raw_hit.point - projection.origin;
        let distance = to_first.length();
        let ray = Ray::with_time(
            projection.origin,
            to_first / distance,
            scene.camera.time(camera.u_time),
        );
        trace_to_vertex(
            scene,
            &ray,
            projection.origin,
            first,
            distance,
            tolerance,
            counters,
        )?;
        vertices.extend_from_slice(seed_vertices);
        return Ok(member);
    }

    let camera_ray = scene
        .camera
        .generate_ray(camera.raster, camera.u_lens, camera.u_time);
    let camera_vertex = CameraVertex {
        raster: camera.raster,
        u_lens: camera.u_lens,
        u_time: camera.u_time,
        u_wavelength: camera.u_wavelength,
        origin: camera_ray.origin,
    };
    let member = RebuiltMember {
        camera: camera_vertex,
        first_projection: None,
    };
    let mut wavelengths = wavelengths;
    let ray = Ray::with_time(camera_ray.origin, camera_ray.direction, camera_ray.time);
    rebuild_prefix(
        scene,
        seed_vertices,
        event,
        breakup,
        ray,
        &mut wavelengths,
        source,
        counters,
        vertices,
    )?;
    if !scene.media.is_empty() {
        // The walk traces (and checks) the reconnection through the media.
        vertices.extend_from_slice(&seed_vertices[breakup.min(seed_vertices.len())..]);
        return Ok(member);
    }

    // Reconnect x_b (layout vertex b − 1) to x_{b+1}.
    let breakup_vertex = *vertices.last().expect("breakup ≥ 1 pushed a vertex");
    if breakup < seed_vertices.len() {
        let target = &seed_vertices[breakup];
        let distance = (target.raw_hit.point - breakup_vertex.raw_hit.point).length();
        let (ray, _) = spawn_ray_through(&breakup_vertex.raw_hit, target.raw_hit.point)
            .ok_or(FailureReason::Misplaced)?;
        trace_to_vertex(
            scene,
            &ray,
            breakup_vertex.raw_hit.point,
            target,
            distance,
            tolerance,
            counters,
        )?;
        vertices.extend_from_slice(&seed_vertices[breakup..]);
    } else if let Terminal::Environment { direction } = event.terminal {
        let ray = spawn_ray(&breakup_vertex.raw_hit, direction);
        counters.closest_hit_rays += 1;
        if scene.geometry.intersect(&ray, f32::INFINITY).is_some() {
            return Err(FailureReason::Occluded);
        }
    }
    // A next-event connection from x_b is checked by the walk's shadow ray.
    Ok(member)
}
