//! Path segments through homogeneous media for LQMC's value walk: tracing a
//! segment between two given vertices (the walk needs its transmittance and
//! checks that nothing but index-matched boundaries lies in between). Where
//! a segment ends is sampled by the path-space walk
//! ([`crate::integrators::path_space`]) for seeds and rebuilt prefixes: the
//! free-flight distance is drawn once per segment from `FREE_FLIGHT` of the
//! block of the vertex the segment ends at, as an optical depth
//! τ = −ln(1 − u) at the hero wavelength, used up piece by piece between
//! index-matched (`null`) boundaries; crossing a boundary is no vertex and
//! uses no number.

use super::path_record::SurfaceVertex;
use super::statistics::FailureReason;
use crate::geometry::{Ray, SurfaceHit, spawn_ray};
use crate::integrators::path_space::MAX_INTERFACE_CROSSINGS;
use crate::integrators::path_space::oriented_hit;
use crate::medium::medium_after;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// Relative distance short of a medium vertex within which a surface hit
/// counts as reaching it (floating-point slack of the re-traced ray).
const MEDIUM_TARGET_SLACK: f32 = 1e-4;

/// What a traced segment between given vertices passes through.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TracedSegment {
    /// The transmittance per wavelength, exp(−Σ σt d) over its pieces.
    pub transmittance: SampledSpectrum,
    /// The medium at its end (before any boundary of the end vertex).
    pub end_medium: Option<u32>,
}

/// Where a traced segment ends.
#[derive(Debug, Clone, Copy)]
pub enum SegmentTarget<'a> {
    /// At a recorded vertex.
    Vertex(&'a SurfaceVertex),
    /// Out of the scene.
    Escape,
}

/// Whether a hit is the recorded surface vertex `target` (relative
/// `tolerance` of the segment length `distance`).
pub fn lands_on(hit: &SurfaceHit, target: &SurfaceVertex, distance: f32, tolerance: f32) -> bool {
    lands_at(hit.shape_index, hit.point, target, distance, tolerance)
}

/// Whether a hit of shape `shape_index` at `point` is the recorded surface
/// vertex `target` (see [`lands_on`]).
pub fn lands_at(
    shape_index: u32,
    point: glam::Vec3,
    target: &SurfaceVertex,
    distance: f32,
    tolerance: f32,
) -> bool {
    !target.is_medium()
        && shape_index == target.raw_hit.shape_index
        && (point - target.raw_hit.point).length() <= tolerance * distance.max(1e-6)
}

/// Traces the segment from `ray` (starting in `medium`) to `target` through
/// index-matched boundaries: fails with `Occluded` if another surface lies
/// in between, `Misplaced` if a surface target is not where the ray lands
/// or a medium target lies in another medium. Its pieces inside media are
/// reported to `recorder` when given (see [`super::segment_cache`]).
pub fn trace_segment(
    scene: &Scene,
    mut ray: Ray,
    mut medium: Option<u32>,
    target: SegmentTarget<'_>,
    tolerance: f32,
    wavelengths: &SampledWavelengths,
    mut recorder: Option<&mut super::segment_cache::SegmentCache>,
) -> Result<TracedSegment, FailureReason> {
    let mut result = SampledSpectrum::splat(1.0);
    let target_point = match target {
        SegmentTarget::Vertex(vertex) => Some(vertex.raw_hit.point),
        SegmentTarget::Escape => None,
    };
    let total = target_point.map_or(f32::INFINITY, |point| (point - ray.origin).length());
    let mut add_piece = |medium: Option<u32>, distance: f32| -> Result<(), FailureReason> {
        if let Some(index) = medium {
            if !distance.is_finite() {
                return Err(FailureReason::Evaluation);
            }
            if let Some(recorder) = recorder.as_deref_mut() {
                recorder.piece(index, distance);
            }
            result *= scene.media[index as usize].transmittance(distance, wavelengths);
        }
        Ok(())
    };
    for _ in 0..MAX_INTERFACE_CROSSINGS {
        let hit = scene.geometry.intersect(&ray, f32::INFINITY);
        let remaining = target_point.map_or(f32::INFINITY, |point| (point - ray.origin).length());
        match (target, hit) {
            (SegmentTarget::Vertex(vertex), _) if vertex.is_medium() => {
                if let Some(hit) = hit
                    && hit.t < remaining - MEDIUM_TARGET_SLACK * total
                {
                    if !scene.shapes[hit.shape_index as usize].is_interface {
                        return Err(FailureReason::Occluded);
                    }
                    add_piece(medium, hit.t)?;
                } else {
                    add_piece(medium, remaining)?;
                    if medium != vertex.medium {
                        return Err(FailureReason::Misplaced);
                    }
                    return Ok(TracedSegment {
                        transmittance: result,
                        end_medium: medium,
                    });
                }
            }
            (SegmentTarget::Vertex(vertex), Some(hit)) => {
                if lands_on(&hit, vertex, total, tolerance) {
                    add_piece(medium, hit.t)?;
                    return Ok(TracedSegment {
                        transmittance: result,
                        end_medium: medium,
                    });
                }
                if hit.t >= remaining * (1.0 - tolerance) {
                    return Err(FailureReason::Misplaced);
                }
                if !scene.shapes[hit.shape_index as usize].is_interface {
                    return Err(FailureReason::Occluded);
                }
                add_piece(medium, hit.t)?;
            }
            (SegmentTarget::Vertex(_), None) => return Err(FailureReason::Misplaced),
            (SegmentTarget::Escape, None) => {
                add_piece(medium, f32::INFINITY)?;
                return Ok(TracedSegment {
                    transmittance: result,
                    end_medium: medium,
                });
            }
            (SegmentTarget::Escape, Some(hit)) => {
                if !scene.shapes[hit.shape_index as usize].is_interface {
                    return Err(FailureReason::Occluded);
                }
                add_piece(medium, hit.t)?;
            }
        }
        // Cross the index-matched boundary.
        let raw_hit = hit.expect("a boundary was hit");
        let info = &scene.shapes[raw_hit.shape_index as usize];
        let oriented = oriented_hit(scene, &raw_hit);
        medium = medium_after(
            info.medium_interface.as_ref(),
            oriented.geometric_normal,
            ray.direction,
            medium,
        );
        ray = spawn_ray(&raw_hit, ray.direction);
    }
    Err(FailureReason::Evaluation)
}

/// The effective roughness of a medium vertex for the breakup CDF:
/// √(1 − g²) of its phase function (1 for isotropic scattering), as the
/// authors' renderer uses.
pub fn medium_roughness(scene: &Scene, medium: u32) -> f32 {
    match scene.media[medium as usize].phase {
        crate::medium::PhaseFunction::Isotropic => 1.0,
        crate::medium::PhaseFunction::HenyeyGreenstein { g } => (1.0 - g * g).max(0.0).sqrt(),
    }
}
