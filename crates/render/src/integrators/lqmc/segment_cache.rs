//! Reuse of the seed's traced segments by the members of an exploration in
//! scenes with media. The volumetric walk traces every segment again for
//! its transmittance, which depends on the wavelengths (explored) but whose
//! geometry — the boundaries crossed and the distance inside each medium —
//! depends only on the segment's two end vertices. A member's suffix
//! segments from x_{b+1} on join the seed's own vertices, so the seed's
//! walk records their pieces once and each member only multiplies
//! `exp(−σt d)` over them at its own wavelengths: the same factors in the
//! same order as tracing them again, without the rays.

use super::medium_segment::TracedSegment;
use super::statistics::FailureReason;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
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

/// The traced segments of one event's seed path, by segment index (segment
/// `m` ends at layout vertex `m`; index `vertices.len()` is the escape to
/// the environment).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SegmentCache {
    segments: Vec<Option<RecordedSegment>>,
    /// `(medium, distance)` of every recorded piece.
    pieces: Vec<(u32, f32)>,
    /// The pieces of the segment being traced.
    pending: Vec<(u32, f32)>,
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
