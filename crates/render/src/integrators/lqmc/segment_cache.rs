//! Reuse of the seed's traced segments by the members of an exploration in
//! scenes with media. The volumetric walk traces every segment again for
//! its transmittance, which depends on the wavelengths (explored) but whose
//! geometry — the boundaries crossed and the distance inside each medium —
//! depends only on the segment's two end vertices. A member's suffix
//! segments from x_{b+1} on join the seed's own vertices, so the seed's
//! walk records their pieces once and each member only multiplies
//! `exp(−σt d)` over them at its own wavelengths: the same factors in the
//! same order as tracing them again, without the rays.
//!
//! In surface scenes the seed's walk records its evaluated steps instead
//! ([`SurfaceStep`], [`SurfaceTerminal`]): a step at x_{m+1} depends on
//! x_m, x_{m+1}, x_{m+2} and the wavelengths only, so a member with breakup
//! vertex b whose wavelengths are the seed's (the wavelength not explored)
//! takes the seed's factors of the steps from m = b + 1 on and of the end
//! (emission or next-event connection), recomputing only Russian roulette,
//! whose probability follows the member's own throughput. Where the seed's
//! walk chose its end with the last step at m ≥ b + 1 the end is the
//! seed's too. The step at m = b (at x_{b+1}, whose incoming direction the
//! breakup changed) is reused as well where x_{b+1} is plainly Lambertian
//! and the member arrives on the seed's side of its normals
//! ([`IncomingIndependence`]): its value, density and end do not depend on
//! the incoming direction otherwise, bit for bit. That makes a b = 0 member
//! of a depth-of-field path on a diffuse surface a projection, one
//! visibility ray and a splat.

use super::medium_segment::TracedSegment;
use super::statistics::FailureReason;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;
use std::ops::Range;

/// One recorded segment.
#[derive(Debug, Clone, PartialEq)]
struct RecordedSegment {
    /// The medium the segment starts in.
    start_medium: Option<u32>,
    /// The medium at its end.
    end_medium: Option<u32>,
    /// Its pieces inside media, in [`SegmentCache::pieces`].
    pieces: Range<usize>,
}

/// One evaluated scattering step of a surface walk, at vertex x_{m+1}
/// (layout vertex m): what it multiplies into the path's state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceStep {
    /// The wavelengths the step was evaluated at (a member reuses the step
    /// only at the same ones).
    pub wavelengths: SampledWavelengths,
    /// `f |cos| / p` (or the specular sample's weight).
    pub factor: SampledSpectrum,
    /// The factor on Russian roulette's η² scale.
    pub eta_factor: f32,
    /// The step's factor of the suffix density (1 for a specular step).
    pub density_factor: f64,
    /// Whether the step scattered by a delta lobe.
    pub specular: bool,
}

/// What makes a recorded step at a vertex independent of the direction the
/// path arrives from: a plain Lambertian BSDF
/// ([`crate::material::SurfaceBsdf::is_plain_diffuse`]), and the side of its
/// shading and geometric normals the seed arrived from (the side selects
/// the lobe and the offset of the next-event ray's origin).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IncomingIndependence {
    /// The shading frame's normal.
    pub shading_normal: Vec3,
    /// Whether the seed's `wo` was above the shading normal.
    pub above_shading: bool,
    /// Whether the seed's `wo` was above the geometric normal.
    pub above_geometric: bool,
}

impl IncomingIndependence {
    /// Whether a path arriving from `wo` at a vertex of geometric normal
    /// `geometric_normal` gets the recorded step's values exactly.
    pub fn admits(&self, wo: Vec3, geometric_normal: Vec3) -> bool {
        let shading = wo.dot(self.shading_normal);
        let geometric = wo.dot(geometric_normal);
        shading != 0.0
            && geometric != 0.0
            && (shading > 0.0) == self.above_shading
            && (geometric > 0.0) == self.above_geometric
    }
}

/// The end of a recorded surface walk: what multiplies the throughput
/// after the last step (emission or environment radiance with its MIS
/// weight; for a next-event connection, the whole last step), and the
/// suffix density's factor of a next-event connection.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceTerminal {
    /// The wavelengths the end was evaluated at.
    pub wavelengths: SampledWavelengths,
    /// The factor on the throughput.
    pub value: SampledSpectrum,
    /// The next-event connection's suffix density factor (1 otherwise).
    pub density_factor: f64,
}

/// The traced segments of one event's seed path, by segment index (segment
/// `m` ends at layout vertex `m`; index `vertices.len()` is the escape to
/// the environment), and in surface scenes its evaluated steps.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SegmentCache {
    segments: Vec<Option<RecordedSegment>>,
    /// `(medium, distance)` of every recorded piece.
    pieces: Vec<(u32, f32)>,
    /// The pieces of the segment being traced.
    pending: Vec<(u32, f32)>,
    /// The seed's surface steps, by layout vertex (surface scenes).
    pub surface_steps: Vec<SurfaceStep>,
    /// The seed's end (surface scenes).
    pub surface_terminal: Option<SurfaceTerminal>,
    /// Per layout vertex of the seed's surface walk (every scattering
    /// vertex, the next-event one included): whether its step is
    /// independent of the incoming direction, and on which sides.
    pub incoming_independence: Vec<Option<IncomingIndependence>>,
}

/// What a walk does with the segment cache.
#[derive(Debug)]
pub enum SegmentReuse<'a> {
    /// Trace every segment.
    None,
    /// Trace every segment and record them (the seed's walk).
    Record(&'a mut SegmentCache),
    /// Reuse the recorded segments from index `first` on (a member with
    /// breakup vertex `b` reuses those from `b + 1`: both of their end
    /// vertices are the seed's).
    Reuse {
        /// The seed's segments.
        cache: &'a SegmentCache,
        /// The first reusable segment index.
        first: usize,
    },
}

impl SegmentCache {
    /// Forgets every segment.
    pub fn clear(&mut self) {
        self.segments.clear();
        self.pieces.clear();
        self.surface_steps.clear();
        self.surface_terminal = None;
        self.incoming_independence.clear();
        self.pending.clear();
    }

    /// Starts tracing a segment to record.
    pub(super) fn begin(&mut self) {
        self.pending.clear();
    }

    /// Notes a piece of the segment being traced.
    pub(super) fn piece(&mut self, medium: u32, distance: f32) {
        self.pending.push((medium, distance));
    }

    /// Stores the traced segment `index` (which started in `start_medium`).
    pub(super) fn finish(
        &mut self,
        index: usize,
        start_medium: Option<u32>,
        end_medium: Option<u32>,
    ) {
        if self.segments.len() <= index {
            self.segments.resize(index + 1, None);
        }
        let start = self.pieces.len();
        self.pieces.extend_from_slice(&self.pending);
        self.segments[index] = Some(RecordedSegment {
            start_medium,
            end_medium,
            pieces: start..self.pieces.len(),
        });
    }

    /// Segment `index` at `wavelengths`, if it was recorded starting in
    /// `start_medium`.
    pub(super) fn replay(
        &self,
        scene: &Scene,
        index: usize,
        start_medium: Option<u32>,
        wavelengths: &SampledWavelengths,
    ) -> Option<Result<TracedSegment, FailureReason>> {
        let segment = self.segments.get(index)?.as_ref()?;
        if segment.start_medium != start_medium {
            return None;
        }
        let mut transmittance = SampledSpectrum::splat(1.0);
        for &(medium, distance) in &self.pieces[segment.pieces.clone()] {
            transmittance *= scene.media[medium as usize].transmittance(distance, wavelengths);
        }
        Some(Ok(TracedSegment {
            transmittance,
            end_medium: segment.end_medium,
        }))
    }
}

impl SegmentReuse<'_> {
    /// Segment `index` (starting in `medium`): replayed from the cache
    /// where allowed, otherwise traced by `trace` (which reports its
    /// pieces to the recorder it is given) and recorded when recording.
    pub(super) fn segment(
        &mut self,
        scene: &Scene,
        index: usize,
        medium: Option<u32>,
        wavelengths: &SampledWavelengths,
        trace: impl FnOnce(Option<&mut SegmentCache>) -> Result<TracedSegment, FailureReason>,
    ) -> Result<TracedSegment, FailureReason> {
        match self {
            SegmentReuse::None => trace(None),
            SegmentReuse::Record(cache) => {
                cache.begin();
                let traced = trace(Some(cache))?;
                cache.finish(index, medium, traced.end_medium);
                Ok(traced)
            }
            SegmentReuse::Reuse { cache, first } => {
                if index >= *first
                    && let Some(replayed) = cache.replay(scene, index, medium, wavelengths)
                {
                    return replayed;
                }
                trace(None)
            }
        }
    }
}
