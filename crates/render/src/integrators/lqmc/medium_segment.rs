//! Path segments through homogeneous media for LQMC: sampling where a
//! segment ends (free flight, for seeds and rebuilt prefixes) and tracing a
//! segment between two given vertices (for the walk, which needs its
//! transmittance and checks that nothing but index-matched boundaries lies
//! in between).
//!
//! Both follow [`crate::integrators::volpath`] exactly: the free-flight
//! distance is drawn once per segment from `FREE_FLIGHT` of the block of the
//! vertex the segment ends at, as an optical depth τ = −ln(1 − u) at the
//! hero wavelength, used up piece by piece between index-matched (`null`)
//! boundaries; crossing a boundary is no vertex and uses no number.

use super::path_record::SurfaceVertex;
use super::statistics::FailureReason;
use crate::geometry::{Ray, SurfaceHit, spawn_ray};
use crate::integrators::path::oriented_hit;
use crate::medium::{medium_after, transmittance};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// Segments stop after this many index-matched boundaries (volpath's guard).
const MAX_INTERFACE_CROSSINGS: u32 = 256;

/// Relative distance short of a medium vertex within which a surface hit
/// counts as reaching it (floating-point slack of the re-traced ray).
const MEDIUM_TARGET_SLACK: f32 = 1e-4;

/// Where a sampled free flight ended.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FlightEnd {
    /// A scattering event at `point` in `medium`.
    Medium {
        /// The point.
        point: Vec3,
        /// The medium.
        medium: u32,
    },
    /// A surface that is not an index-matched boundary.
    Surface {
        /// The hit.
        raw_hit: SurfaceHit,
    },
    /// The ray left the scene.
    Escaped,
    /// No valid end (zero density, too many boundaries).
    Dead,
}

/// A sampled free flight: its end and the factors volpath multiplies into
/// the throughput `beta` and into the rescaled path probabilities `r_u`,
/// `r_l` (spectral MIS over the hero wavelengths).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Flight {
    /// The end.
    pub end: FlightEnd,
    /// T·σs / (T₀σt₀) at a medium vertex, T / T₀ otherwise.
    pub beta_factor: SampledSpectrum,
    /// T·σt / (T₀σt₀) at a medium vertex, T / T₀ otherwise.
    pub probability_factor: SampledSpectrum,
}

/// Samples the end of the segment along `ray` starting in `*medium` with
/// free-flight number `u_free_flight` (asked for only when a medium is
/// met); `ray` and `medium` are left at the last piece. Every emitting
/// index-matched boundary crossed is reported to `passed_emitter` (its hit
/// and light), whose emission volpath adds as the ray passes.
pub fn sample_flight(
    scene: &Scene,
    ray: &mut Ray,
    medium: &mut Option<u32>,
    mut u_free_flight: impl FnMut() -> f32,
    passed_emitter: &mut dyn FnMut(&SurfaceHit, u32),
    wavelengths: &SampledWavelengths,
    closest_hit_rays: &mut u64,
) -> Flight {
    let mut beta_factor = SampledSpectrum::splat(1.0);
    let mut probability_factor = SampledSpectrum::splat(1.0);
    let mut optical_depth: Option<f32> = None;
    let dead = Flight {
        end: FlightEnd::Dead,
        beta_factor: SampledSpectrum::zero(),
        probability_factor: SampledSpectrum::zero(),
    };
    for _ in 0..MAX_INTERFACE_CROSSINGS {
        *closest_hit_rays += 1;
        let hit = scene.geometry.intersect(ray, f32::INFINITY);
        let distance = hit.map_or(f32::INFINITY, |hit| hit.t);
        if let Some(medium_index) = *medium {
            let coefficients = scene.media[medium_index as usize].coefficients(wavelengths);
            let sigma_t = coefficients.sigma_t();
            let hero_sigma_t = sigma_t[0];
            let tau = *optical_depth.get_or_insert_with(|| -(1.0 - u_free_flight()).ln());
            if hero_sigma_t > 0.0 && tau < hero_sigma_t * distance {
                let t = tau / hero_sigma_t;
                let piece = transmittance(sigma_t, t);
                let hero_pdf = piece[0] * hero_sigma_t;
                if hero_pdf <= 0.0 {
                    return dead;
                }
                return Flight {
                    end: FlightEnd::Medium {
                        point: ray.at(t),
                        medium: medium_index,
                    },
                    beta_factor: beta_factor * piece * coefficients.sigma_s / hero_pdf,
                    probability_factor: probability_factor * piece * sigma_t / hero_pdf,
                };
            }
            optical_depth = Some(tau - hero_sigma_t * distance);
            let piece = transmittance(sigma_t, distance);
            if piece[0] <= 0.0 {
                return dead;
            }
            beta_factor *= piece / piece[0];
            probability_factor *= piece / piece[0];
        }
        let Some(raw_hit) = hit else {
            return Flight {
                end: FlightEnd::Escaped,
                beta_factor,
                probability_factor,
            };
        };
        let info = &scene.shapes[raw_hit.shape_index as usize];
        if !info.is_interface {
            return Flight {
                end: FlightEnd::Surface { raw_hit },
                beta_factor,
                probability_factor,
            };
        }
        if let Some(light_index) = info.light {
            passed_emitter(&raw_hit, light_index);
        }
        let oriented = oriented_hit(scene, &raw_hit);
        *medium = medium_after(
            info.medium_interface.as_ref(),
            oriented.geometric_normal,
            ray.direction,
            *medium,
        );
        *ray = spawn_ray(&raw_hit, ray.direction);
    }
    dead
}

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
