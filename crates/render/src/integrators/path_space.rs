//! The path-space core: every subpath of every integrator — camera paths
//! of path tracing, volumetric path tracing and LQMC, light paths of light
//! tracing, and the subpaths of the bidirectional and Metropolis methods to
//! come — is built by one random walk ([`walk`]) into one vertex type
//! ([`Vertex`]) (pbrt-v4's `RandomWalk` and `Vertex`, Veach 1997 §10.2).
//!
//! # The walk
//!
//! A walk starts from a ray leaving the camera or a light ([`WalkStart`])
//! and alternates segments and scattering vertices:
//!
//! - **Segments** pass index-matched boundaries (`is_interface` shapes),
//!   which are no vertices and use no dimension, and, when the walk traces
//!   media ([`WalkSettings::media`]), sample a free flight through the
//!   homogeneous media they cross: one optical depth τ = −ln(1 − u) at the
//!   hero wavelength per segment, drawn from the `FREE_FLIGHT` dimension of
//!   the block of the vertex the segment ends at, used up piece by piece
//!   (exact: optical depth is additive). A chromatic medium's free flights
//!   are sampled at the hero wavelength; the walk keeps, per wavelength,
//!   the density of the sampled distances over the hero's
//!   ([`WalkState::spectral_density_ratio`], pbrt-v4's `r_u`) for the
//!   spectral MIS of [`super::volpath`].
//! - **Vertices** are surface points with a BSDF and, in media, medium
//!   points with a phase function. At each the walk's observer is called
//!   ([`WalkObserver::vertex`]: next-event estimation, a connection to the
//!   camera, recording), then the walk samples the next direction from the
//!   vertex's block of [`SubpathLayout`], multiplies the throughput β, and
//!   decides Russian roulette by
//!   [`russian_roulette`](super::estimator::roulette::russian_roulette), the rule of every
//!   integrator.
//! - With [`WalkSettings::null_crossings`], a thin sheet's straight
//!   transmission and a mask's pass-through are **null crossings**
//!   (Mitsuba 3's `volpath`): chosen by BSDF sampling with their
//!   probability, they are no vertex and do not count towards the depth,
//!   but take a dimension block each, and shadow rays pass them with their
//!   weight. Without, they are ordinary specular vertices and shadow rays
//!   stop at them (Mitsuba's `path`); passing them there too would count the
//!   light behind them twice.
//! - Emitters that segments reach and the environment they escape to are
//!   reported to observers that ask for them ([`WalkObserver::FINDS_EMISSION`]:
//!   camera paths), with the walk's state for their MIS weights: the
//!   previous vertex's reference point, the density of its sampled
//!   direction and whether it was a delta.
//!
//! Observers are type parameters, so each integrator's walk is compiled
//! with its observer inlined: the path tracer's walk costs what its own
//! loop did.
//!
//! # Densities and transport modes
//!
//! Observers that record vertices for bidirectional MIS
//! ([`WalkObserver::RECORDS_DENSITIES`]; [`random_walk`]) get each vertex's
//! area-measure density of being sampled from the previous vertex
//! (`pdf_forward`) and, once the next vertex is sampled, from the next one
//! (`pdf_reverse`), and whether it scattered by a delta lobe.
//!
//! Light subpaths carry importance transport: the BSDF's adjoint (no
//! 1/η² on refraction) and the adjoint shading-normal correction
//! `|wo·ns| |wi·ng| / (|wo·ng| |wi·ns|)` (Veach 1997, Eq. 5.19) on every
//! scattering and every connection, without which light tracing and BDPT
//! disagree with path tracing under bump and normal maps (pbrt-v4 issues
//! #13 and #385). Radiance transport's Russian roulette undoes the η² of
//! refractions (pbrt-v4's `etaScale`), and with media divides by the mean
//! spectral density ratio (pbrt-v4's `rrBeta`).

use super::TraceCounters;
use super::estimator::roulette::{roulette_throughput, russian_roulette};
use crate::geometry::{OffsetPoint, Ray, SurfaceHit, spawn_ray};
use crate::material::{BsdfFlags, BsdfModel, BsdfSample, SurfaceBsdf, TransportMode};
use crate::medium::{PhaseFunction, medium_after, transmittance};
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;
use std::ops::ControlFlow;

/// A segment (and a shadow ray) stops after this many index-matched
/// boundaries: a guard against rays stuck in coincident surfaces.
pub const MAX_INTERFACE_CROSSINGS: u32 = 256;

/// Where a subpath's numbers are: vertex `k` owns the block of
/// [`layout::VERTEX_BLOCK`] dimensions starting at `first + k · stride`,
/// with the offsets of [`layout`] (scattering direction, component,
/// Russian roulette, ...). The camera subpath's is [`SubpathLayout::CAMERA`];
/// interleaving two subpaths (Kollig & Keller: the first vertex of each in
/// the lowest dimensions, then the second of each, ...) is a stride of two
/// blocks with the second subpath one block later.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SubpathLayout {
    /// The first dimension of vertex 0's block.
    pub first: usize,
    /// Dimensions from one vertex's block to the next one's.
    pub stride: usize,
}

impl SubpathLayout {
    /// The camera subpath of path tracing (the table in [`crate::sampler`]).
    pub const CAMERA: Self = Self {
        first: layout::CAMERA_DIMENSIONS,
        stride: layout::VERTEX_BLOCK,
    };

    /// The light subpath of light tracing: after the camera dimensions and
    /// the light's emission dimensions ([`layout::LIGHT_CHOICE`] and after).
    pub const LIGHT: Self = Self {
        first: layout::LIGHT_SUBPATH_VERTICES,
        stride: layout::VERTEX_BLOCK,
    };

    /// The camera subpath of bidirectional path tracing: its blocks
    /// interleaved with the light subpath's (Kollig & Keller: vertex k of
    /// both subpaths before vertex k + 1 of either), after the camera and
    /// emission dimensions and the light vertex's lens pair
    /// ([`layout::BIDIRECTIONAL_VERTICES`]).
    pub const BIDIRECTIONAL_CAMERA: Self = Self {
        first: layout::BIDIRECTIONAL_VERTICES,
        stride: 2 * layout::VERTEX_BLOCK,
    };

    /// The light subpath of bidirectional path tracing: one block after
    /// each camera block.
    pub const BIDIRECTIONAL_LIGHT: Self = Self {
        first: layout::BIDIRECTIONAL_VERTICES + layout::VERTEX_BLOCK,
        stride: 2 * layout::VERTEX_BLOCK,
    };

    /// The dimension of `offset` in the block of vertex `vertex`.
    #[inline]
    pub const fn dimension(&self, vertex: usize, offset: usize) -> usize {
        self.first + vertex * self.stride + offset
    }
}

/// What scatters at a vertex, borrowed from the walk while it is there.
#[derive(Debug, Clone, Copy)]
pub enum ScattererRef<'a> {
    /// A surface point: the hit (normals oriented as the material sees
    /// them), its BSDF in the walk's transport mode, and the point offset
    /// off the surface for rays leaving it.
    Surface {
        /// The oriented hit.
        hit: &'a SurfaceHit,
        /// The BSDF.
        bsdf: &'a SurfaceBsdf,
        /// The hit point offset towards `wo` (and, on request, the other side).
        offset: &'a OffsetPoint,
    },
    /// A point in a homogeneous medium and its phase function.
    Medium {
        /// The phase function.
        phase: PhaseFunction,
    },
}

/// What scatters at a recorded vertex ([`ScattererRef`], owned). Medium
/// vertices waste the surface's space: recorded subpaths live in vectors
/// reused from path to path, where boxing the surface would allocate.
#[derive(Debug, Clone, Copy)]
#[allow(clippy::large_enum_variant)]
pub enum Scatterer {
    /// A surface point: the oriented hit, its BSDF and offset point.
    Surface {
        /// The oriented hit.
        hit: SurfaceHit,
        /// The BSDF.
        bsdf: SurfaceBsdf,
        /// The hit point offset towards `wo`.
        offset: OffsetPoint,
    },
    /// A point in a homogeneous medium and its phase function.
    Medium {
        /// The phase function.
        phase: PhaseFunction,
    },
}

impl Scatterer {
    /// Borrowed.
    #[inline]
    pub fn as_ref(&self) -> ScattererRef<'_> {
        match self {
            Scatterer::Surface { hit, bsdf, offset } => ScattererRef::Surface { hit, bsdf, offset },
            Scatterer::Medium { phase } => ScattererRef::Medium { phase: *phase },
        }
    }
}

impl ScattererRef<'_> {
    /// Owned.
    #[inline]
    pub fn to_owned(self) -> Scatterer {
        match self {
            ScattererRef::Surface { hit, bsdf, offset } => Scatterer::Surface {
                hit: *hit,
                bsdf: *bsdf,
                offset: *offset,
            },
            ScattererRef::Medium { phase } => Scatterer::Medium { phase },
        }
    }

    /// True if the scattering has a lobe that a connection can evaluate
    /// (every phase function has).
    #[inline]
    pub fn is_connectible(self) -> bool {
        match self {
            ScattererRef::Surface { bsdf, .. } => bsdf.flags().is_non_specular(),
            ScattererRef::Medium { .. } => true,
        }
    }

    /// The origin of a ray leaving `point` (the vertex's) in `direction`:
    /// off the surface to that side, or the medium point itself.
    #[inline]
    pub fn origin_towards(self, point: Vec3, direction: Vec3) -> Vec3 {
        match self {
            ScattererRef::Surface { offset, .. } => offset.towards(direction),
            ScattererRef::Medium { .. } => point,
        }
    }

    /// The scattering value for a connection from `wo` leaving towards
    /// unit `wi`: the BSDF times the cosine, with the adjoint
    /// shading-normal correction in importance transport (`f(wo, wi)
    /// |wi·ns|` for radiance, `f(wo, wi) |wo·ns| |wi·ng| / |wo·ng|` for
    /// importance), or the phase function.
    pub fn connection_factor(
        self,
        wo: Vec3,
        wi: Vec3,
        wavelengths: &SampledWavelengths,
        mode: TransportMode,
    ) -> SampledSpectrum {
        match self {
            ScattererRef::Surface { hit, bsdf, .. } => {
                let value = bsdf.evaluate(wo, wi, wavelengths);
                value
                    * scattering_cosine_factor(
                        wo,
                        wi,
                        hit.geometric_normal,
                        bsdf.shading_normal_for(wo, wi, mode),
                        mode,
                    )
            }
            ScattererRef::Medium { phase } => SampledSpectrum::splat(phase.evaluate(wo, wi)),
        }
    }
}

/// A scattering vertex as the walk shows it to its observer.
#[derive(Debug, Clone, Copy)]
pub struct VertexAt<'a> {
    /// The point.
    pub point: Vec3,
    /// Unit direction towards the previous vertex.
    pub wo: Vec3,
    /// The time of the subpath.
    pub time: f32,
    /// The medium the subpath arrived through.
    pub medium: Option<u32>,
    /// The BSDF or the phase function.
    pub scatterer: ScattererRef<'a>,
    /// Density per unit area (per unit volume in a medium, without the
    /// free flight's factor) of sampling this vertex from the previous one;
    /// 0 unless the observer records densities.
    pub pdf_forward: f32,
    /// Per wavelength, the probability of passing the segment that arrived
    /// here were that wavelength the hero: the transmittance of the media
    /// on it times the null crossings' probabilities (1 without media). The
    /// same either way along the segment, so the reverse densities use it
    /// too.
    pub arrival_transmittance: SampledSpectrum,
    /// Per wavelength, the extinction coefficient σt at a medium vertex
    /// (the free flight's density of stopping here over its
    /// transmittance); 1 at surfaces.
    pub extinction: SampledSpectrum,
}

/// One recorded scattering vertex of a subpath ([`random_walk`]).
#[derive(Debug, Clone, Copy)]
pub struct Vertex {
    /// The point.
    pub point: Vec3,
    /// The geometric normal, oriented as the material sees it (zero in a medium).
    pub geometric_normal: Vec3,
    /// The shading normal, the BSDF frame's (zero in a medium).
    pub shading_normal: Vec3,
    /// Unit direction towards the previous vertex.
    pub wo: Vec3,
    /// The time of the subpath.
    pub time: f32,
    /// The subpath's throughput up to this vertex, excluding its scattering.
    pub beta: SampledSpectrum,
    /// The medium the subpath arrived through.
    pub medium: Option<u32>,
    /// The BSDF or the phase function.
    pub scatterer: Scatterer,
    /// Density per unit area of sampling this vertex from the previous one
    /// (per unit volume in a medium, without the free flight's factor:
    /// [`Self::arrival_transmittance`] times [`Self::extinction`] per
    /// wavelength).
    pub pdf_forward: f32,
    /// Density per unit area of sampling this vertex from the next one
    /// (0 until the next vertex is sampled; 0 for a delta scattering).
    pub pdf_reverse: f32,
    /// [`VertexAt::arrival_transmittance`].
    pub arrival_transmittance: SampledSpectrum,
    /// [`VertexAt::extinction`].
    pub extinction: SampledSpectrum,
    /// The walk's [`WalkState::spectral_density_ratio`] on arrival: per
    /// wavelength, the density of the subpath's free flights up to here
    /// over the hero wavelength's.
    pub spectral_density_ratio: SampledSpectrum,
    /// The next vertex was sampled by a delta lobe.
    pub delta: bool,
    /// The shape hit (`u32::MAX` in a medium).
    pub shape_index: u32,
}

impl Vertex {
    /// The vertex the walk showed, with the walk's throughput and spectral
    /// density ratio up to it.
    pub fn record(vertex: &VertexAt<'_>, walk: &WalkState) -> Self {
        let (geometric_normal, shading_normal, shape_index) = match vertex.scatterer {
            ScattererRef::Surface { hit, bsdf, .. } => {
                (hit.geometric_normal, bsdf.frame.normal(), hit.shape_index)
            }
            ScattererRef::Medium { .. } => (Vec3::ZERO, Vec3::ZERO, u32::MAX),
        };
        Self {
            point: vertex.point,
            geometric_normal,
            shading_normal,
            wo: vertex.wo,
            time: vertex.time,
            beta: walk.beta,
            medium: vertex.medium,
            scatterer: vertex.scatterer.to_owned(),
            pdf_forward: vertex.pdf_forward,
            pdf_reverse: 0.0,
            arrival_transmittance: vertex.arrival_transmittance,
            extinction: vertex.extinction,
            spectral_density_ratio: walk.spectral_density_ratio,
            delta: false,
            shape_index,
        }
    }

    /// True if the scattering has a lobe that a connection can evaluate.
    #[inline]
    pub fn is_connectible(&self) -> bool {
        self.scatterer.as_ref().is_connectible()
    }

    /// The origin of a ray leaving the vertex in `direction`.
    #[inline]
    pub fn origin_towards(&self, direction: Vec3) -> Vec3 {
        self.scatterer
            .as_ref()
            .origin_towards(self.point, direction)
    }

    /// The medium a ray leaving the vertex in `direction` starts in
    /// ([`medium_leaving`]).
    #[inline]
    pub fn medium_towards(&self, scene: &Scene, direction: Vec3) -> Option<u32> {
        let hit = match &self.scatterer {
            Scatterer::Surface { hit, .. } => Some(hit),
            Scatterer::Medium { .. } => None,
        };
        medium_leaving(scene, hit, self.medium, direction)
    }

    /// [`ScattererRef::connection_factor`] from the vertex's `wo`.
    pub fn connection_factor(
        &self,
        wi: Vec3,
        wavelengths: &SampledWavelengths,
        mode: TransportMode,
    ) -> SampledSpectrum {
        self.scatterer
            .as_ref()
            .connection_factor(self.wo, wi, wavelengths, mode)
    }
}

/// The cosine factor of a scattering from `wo` to `wi` at a surface of
/// geometric normal `geometric_normal` and shading normal `shading_normal`:
/// `|wi·ns|` for radiance, `|wo·ns| |wi·ng| / |wo·ng|` for importance (the
/// cosine times Veach's adjoint correction); 0 where `wo` grazes the
/// geometric surface.
#[inline]
fn scattering_cosine_factor(
    wo: Vec3,
    wi: Vec3,
    geometric_normal: Vec3,
    shading_normal: Vec3,
    mode: TransportMode,
) -> f32 {
    match mode {
        TransportMode::Radiance => wi.dot(shading_normal).abs(),
        TransportMode::Importance => {
            let wo_geometric = wo.dot(geometric_normal).abs();
            if wo_geometric == 0.0 {
                0.0
            } else {
                wo.dot(shading_normal).abs() * wi.dot(geometric_normal).abs() / wo_geometric
            }
        }
    }
}

/// How a walk runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkSettings {
    /// Radiance for camera subpaths, importance for light subpaths.
    pub mode: TransportMode,
    /// The most scattering vertices (for a camera path of at most
    /// `max_depth` segments, `max_depth − 1`: the segment after the last
    /// vertex may still find an emitter).
    pub max_vertices: usize,
    /// The vertex index from which Russian roulette may end the walk
    /// (Mitsuba's `rr_depth`, as [`super::estimator::PathSettings`]).
    pub russian_roulette_depth: u32,
    /// Where the walk's numbers are.
    pub layout: SubpathLayout,
    /// Trace participating media (volumetric integrators); without, media
    /// are ignored (the path tracer).
    pub media: bool,
    /// Treat thin sheets' and masks' straight transmission as null
    /// crossings, no vertices (Mitsuba's `volpath`); without, they are
    /// specular vertices (Mitsuba's `path`).
    pub null_crossings: bool,
}

impl WalkSettings {
    /// The most vertices of a path of at most `max_depth` segments whose
    /// last segment may end on an emitter.
    pub fn camera_vertices(max_depth: u32) -> usize {
        max_depth.saturating_sub(1) as usize
    }

    /// A camera subpath (radiance, [`SubpathLayout::CAMERA`]).
    pub fn camera(
        max_vertices: usize,
        russian_roulette_depth: u32,
        media: bool,
        null_crossings: bool,
    ) -> Self {
        Self {
            mode: TransportMode::Radiance,
            max_vertices,
            russian_roulette_depth,
            layout: SubpathLayout::CAMERA,
            media,
            null_crossings,
        }
    }
}

/// The start of a walk: a ray leaving the camera or a light.
#[derive(Debug, Clone, Copy)]
#[must_use]
pub struct WalkStart {
    /// The ray (its origin already offset from its surface).
    pub ray: Ray,
    /// The throughput carried along it.
    pub beta: SampledSpectrum,
    /// The density per unit solid angle of its direction (0 for a delta
    /// direction, and for camera rays, whose emitters seen directly get no
    /// MIS weight).
    pub pdf_direction: f32,
    /// The medium the ray starts in (ignored unless the walk traces media).
    pub medium: Option<u32>,
}

impl WalkStart {
    /// A camera ray starting in `medium`: throughput 1, no direction
    /// density (emitters it reaches get no MIS weight).
    pub fn camera(ray: Ray, medium: Option<u32>) -> Self {
        Self {
            ray,
            beta: SampledSpectrum::splat(1.0),
            pdf_direction: 0.0,
            medium,
        }
    }
}

/// The scattering the walk did last, as emission found after it is
/// weighed: where it was, the density of its sampled direction and whether
/// that was a delta.
#[derive(Debug, Clone, Copy)]
pub struct PreviousScattering {
    /// The reference point of light sampling there: a surface point offset
    /// towards `wo`, a medium point, or the walk's origin.
    pub point: Vec3,
    /// The solid-angle density of the sampled direction (a stochastic
    /// BSDF's own density estimate, as next-event estimation evaluates it).
    pub pdf: f32,
    /// The direction was a delta (or the walk's start ray): emission found
    /// after it cannot be sampled by next-event estimation.
    pub delta: bool,
}

/// The walk's state between vertices, as observers see it.
#[derive(Debug, Clone, Copy)]
pub struct WalkState {
    /// The throughput: the path's value over the hero wavelength's densities.
    pub beta: SampledSpectrum,
    /// Per wavelength, the density of the sampled free-flight distances
    /// over the hero wavelength's (pbrt-v4's rescaled path probability
    /// `r_u`); 1 without media.
    pub spectral_density_ratio: SampledSpectrum,
    /// The last scattering.
    pub previous: PreviousScattering,
    /// The medium the walk is in.
    pub medium: Option<u32>,
    /// Per wavelength, the probability of passing the current segment so
    /// far were that wavelength the hero (transmittance times null
    /// crossings; 1 without media): the free flight's factor of the
    /// densities of what the segment reaches.
    pub segment_transmittance: SampledSpectrum,
    /// The index of the next vertex (Mitsuba's depth: scatterings so far).
    pub vertex_index: u32,
    /// The dimension block of the next vertex (null crossings take one each).
    pub block: u32,
}

/// How a vertex scattered.
#[derive(Debug, Clone, Copy)]
pub struct Scattering {
    /// The sampled direction.
    pub wi: Vec3,
    /// Its solid-angle density (0 for a delta).
    pub pdf_forward: f32,
    /// The solid-angle density of sampling `wo` from `wi` (0 for a delta,
    /// and unless the observer records densities).
    pub pdf_reverse: f32,
    /// The direction was sampled by a delta lobe.
    pub delta: bool,
    /// The sampled lobe's flags (none in a medium).
    pub flags: BsdfFlags,
}

/// What an integrator does along a walk. Every method but [`vertex`](Self::vertex)
/// does nothing by default.
pub trait WalkObserver {
    /// Report emitters reached and the environment escaped to, and continue
    /// from the last vertex to find them (camera subpaths).
    const FINDS_EMISSION: bool;
    /// Compute vertices' area densities (bidirectional MIS).
    const RECORDS_DENSITIES: bool = false;

    /// The segment after the last scattering reached light `light_index`'s
    /// surface at `hit` (as stored: the normal not oriented), seen from `wo`.
    #[inline]
    fn emitter(
        &mut self,
        _walk: &WalkState,
        _light_index: u32,
        _hit: &SurfaceHit,
        _wo: Vec3,
        _wavelengths: &SampledWavelengths,
    ) {
    }

    /// The segment after the last scattering left the scene in `direction`.
    #[inline]
    fn escaped(&mut self, _walk: &WalkState, _direction: Vec3, _wavelengths: &SampledWavelengths) {}

    /// The segment reached a surface that is no index-matched boundary
    /// (`hit` as stored), before its emission and its vertex; `Break` ends
    /// the walk.
    #[inline]
    fn surface(
        &mut self,
        _walk: &WalkState,
        _hit: &SurfaceHit,
        _wavelengths: &SampledWavelengths,
    ) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }

    /// At a scattering vertex, before the walk samples its next direction;
    /// `Break` ends the walk there.
    fn vertex<S: SampleSource + ?Sized>(
        &mut self,
        walk: &WalkState,
        vertex: &VertexAt<'_>,
        wavelengths: &SampledWavelengths,
        sampler: &mut S,
        counters: &mut TraceCounters,
    ) -> ControlFlow<()>;

    /// The vertex scattered (the walk's β already includes it); `Break`
    /// ends the walk.
    #[inline]
    fn scattered(&mut self, _vertex: &VertexAt<'_>, _scattering: &Scattering) -> ControlFlow<()> {
        ControlFlow::Continue(())
    }
}

/// What a segment ended at.
enum SegmentEnd {
    /// A scattering event in a medium at `point`, where the extinction
    /// coefficients are `extinction`.
    Medium {
        point: Vec3,
        extinction: SampledSpectrum,
    },
    /// A surface that is not an index-matched boundary: the hit (as
    /// stored) is in the segment's hit slot.
    Surface,
    /// The ray left the scene.
    Escaped,
    /// The throughput became zero, or the segment crossed too many boundaries.
    Dead,
}

/// Walks from `start` through the scene, calling `observer` at every
/// vertex and, if it asks, at every emitter and escape. Every subpath of
/// every integrator is built here.
#[inline(always)]
pub fn walk<S: SampleSource + ?Sized, O: WalkObserver>(
    scene: &Scene,
    start: WalkStart,
    settings: &WalkSettings,
    wavelengths: &mut SampledWavelengths,
    sampler: &mut S,
    counters: &mut TraceCounters,
    observer: &mut O,
) {
    let mut ray = start.ray;
    let mut state = WalkState {
        beta: start.beta,
        spectral_density_ratio: SampledSpectrum::splat(1.0),
        previous: PreviousScattering {
            point: start.ray.origin,
            pdf: start.pdf_direction,
            delta: start.pdf_direction == 0.0,
        },
        medium: if settings.media { start.medium } else { None },
        segment_transmittance: SampledSpectrum::splat(1.0),
        vertex_index: 0,
        block: 0,
    };
    // Product of relative IORs of refractions, undone for Russian roulette.
    let mut eta_scale = 1.0f32;
    // The previous vertex's position and direction density, for area densities.
    let mut previous_vertex_point = start.ray.origin;
    let mut pdf_direction = start.pdf_direction;
    // The hit a segment ends at, written in place (a copy of the hit per
    // segment cost the path tracer about 1 % of its instructions).
    let mut segment_hit: Option<SurfaceHit> = None;
    loop {
        let end = trace_segment(
            scene,
            settings,
            &mut state,
            &mut ray,
            &mut segment_hit,
            wavelengths,
            sampler,
            counters,
            observer,
        );
        let wo = -ray.direction;
        let at_last_vertex = state.vertex_index as usize + 1 >= settings.max_vertices;
        match end {
            SegmentEnd::Dead => break,
            SegmentEnd::Escaped => {
                observer.escaped(&state, ray.direction, wavelengths);
                break;
            }
            SegmentEnd::Medium { point, extinction } => {
                if state.vertex_index as usize >= settings.max_vertices {
                    break;
                }
                let Some(medium) = state.medium else { break };
                let phase = scene.media[medium as usize].phase;
                let mut vertex = VertexAt {
                    point,
                    wo,
                    time: ray.time,
                    medium: state.medium,
                    scatterer: ScattererRef::Medium { phase },
                    pdf_forward: 0.0,
                    arrival_transmittance: state.segment_transmittance,
                    extinction,
                };
                if O::RECORDS_DENSITIES {
                    // A direction density times the inverse square distance:
                    // the volume density without the free flight's factor.
                    let distance_squared = (point - previous_vertex_point).length_squared();
                    if distance_squared > 0.0 {
                        vertex.pdf_forward = pdf_direction / distance_squared;
                    }
                }
                if observer
                    .vertex(&state, &vertex, wavelengths, sampler, counters)
                    .is_break()
                    || (at_last_vertex && !O::FINDS_EMISSION)
                {
                    break;
                }
                let sample = phase.sample(
                    wo,
                    sampler.get_2d(
                        settings
                            .layout
                            .dimension(state.block as usize, layout::SCATTER_DIRECTION),
                    ),
                );
                if sample.pdf <= 0.0 {
                    break;
                }
                state.beta *= sample.value / sample.pdf;
                let scattering = Scattering {
                    wi: sample.wi,
                    pdf_forward: sample.pdf,
                    pdf_reverse: if O::RECORDS_DENSITIES {
                        phase.pdf(sample.wi, wo)
                    } else {
                        0.0
                    },
                    delta: false,
                    flags: BsdfFlags::NONE,
                };
                if observer.scattered(&vertex, &scattering).is_break() {
                    break;
                }
                state.previous = PreviousScattering {
                    point,
                    pdf: sample.pdf,
                    delta: false,
                };
                state.segment_transmittance = SampledSpectrum::splat(1.0);
                previous_vertex_point = point;
                pdf_direction = sample.pdf;
                ray = Ray::with_time(point, sample.wi, ray.time);
            }
            SegmentEnd::Surface => {
                let Some(hit) = segment_hit.as_mut() else {
                    break;
                };
                let info = &scene.shapes[hit.shape_index as usize];
                if observer.surface(&state, hit, wavelengths).is_break() {
                    break;
                }
                if O::FINDS_EMISSION
                    && let Some(light_index) = info.light
                {
                    observer.emitter(&state, light_index, hit, wo, wavelengths);
                }
                // Without null crossings, a path at its last vertex is over
                // before its BSDF is built.
                if !settings.null_crossings && state.vertex_index as usize >= settings.max_vertices
                {
                    break;
                }
                let Some(material) = &info.material else {
                    break;
                };
                orient_hit(info.flip_normals, hit);
                let hit: &SurfaceHit = hit;
                let mut bsdf = material.surface_bsdf_at(hit, wavelengths);
                if settings.mode == TransportMode::Importance {
                    bsdf.bsdf = bsdf.bsdf.with_transport_mode(settings.mode);
                } else {
                    // The frame Mitsuba's flip of perturbed normals picks
                    // for the camera-side direction (itself for others).
                    bsdf.face_camera(wo);
                }
                let u_component = sampler.get(
                    settings
                        .layout
                        .dimension(state.block as usize, layout::SCATTER_COMPONENT),
                );
                let null_probability = if settings.null_crossings {
                    null_transmission(&bsdf, wo)
                } else {
                    0.0
                };
                if null_probability > 0.0 {
                    // A surface with a null lobe (a thin sheet's straight
                    // transmission, a mask's pass-through): choose it with
                    // its probability first; it is no vertex and no depth.
                    let u = sampler.get_2d(
                        settings
                            .layout
                            .dimension(state.block as usize, layout::SCATTER_DIRECTION),
                    );
                    let mut probe = *wavelengths;
                    if let Some(sample) = bsdf.sample(wo, u_component, u, &mut probe)
                        && is_null_sample(&bsdf, u_component, &sample)
                    {
                        state.medium = medium_after(
                            info.medium_interface.as_ref(),
                            hit.geometric_normal,
                            -wo,
                            state.medium,
                        );
                        ray = spawn_ray(hit, -wo);
                        state.segment_transmittance *= null_probability;
                        state.block += 1;
                        continue;
                    }
                }
                if state.vertex_index as usize >= settings.max_vertices {
                    break;
                }
                let offset = OffsetPoint::new(hit.point, hit.geometric_normal, wo);
                let mut vertex = VertexAt {
                    point: hit.point,
                    wo,
                    time: hit.time,
                    medium: state.medium,
                    scatterer: ScattererRef::Surface {
                        hit,
                        bsdf: &bsdf,
                        offset: &offset,
                    },
                    pdf_forward: 0.0,
                    arrival_transmittance: state.segment_transmittance,
                    extinction: SampledSpectrum::splat(1.0),
                };
                if O::RECORDS_DENSITIES {
                    vertex.pdf_forward = solid_angle_to_area(
                        pdf_direction,
                        previous_vertex_point,
                        hit.point,
                        hit.geometric_normal,
                    );
                }
                if observer
                    .vertex(&state, &vertex, wavelengths, sampler, counters)
                    .is_break()
                    || (at_last_vertex && !O::FINDS_EMISSION)
                {
                    break;
                }
                let u = sampler.get_2d(
                    settings
                        .layout
                        .dimension(state.block as usize, layout::SCATTER_DIRECTION),
                );
                let Some(sample) = bsdf.sample(wo, u_component, u, wavelengths) else {
                    break;
                };
                if sample.pdf <= 0.0 || sample.value.is_black() {
                    break;
                }
                let factor = scattering_cosine_factor(
                    wo,
                    sample.wi,
                    hit.geometric_normal,
                    bsdf.shading_normal_for(wo, sample.wi, settings.mode),
                    settings.mode,
                );
                state.beta *= sample.value * (factor / sample.pdf);
                // A stochastic BSDF's sample carries a path density; MIS
                // needs the BSDF's own density (the one next-event
                // estimation evaluates).
                let pdf = if sample.pdf_is_proportional {
                    bsdf.pdf(wo, sample.wi)
                } else {
                    sample.pdf
                };
                let delta = sample.is_specular();
                let scattering = if O::RECORDS_DENSITIES {
                    Scattering {
                        wi: sample.wi,
                        pdf_forward: if delta { 0.0 } else { pdf },
                        pdf_reverse: if delta {
                            0.0
                        } else {
                            bsdf.pdf_in_mode(sample.wi, wo, settings.mode.other())
                        },
                        delta,
                        flags: sample.flags,
                    }
                } else {
                    Scattering {
                        wi: sample.wi,
                        pdf_forward: pdf,
                        pdf_reverse: 0.0,
                        delta,
                        flags: sample.flags,
                    }
                };
                pdf_direction = scattering.pdf_forward;
                if observer.scattered(&vertex, &scattering).is_break() {
                    break;
                }
                state.previous = PreviousScattering {
                    point: offset.origin(),
                    pdf,
                    delta,
                };
                state.segment_transmittance = SampledSpectrum::splat(1.0);
                previous_vertex_point = hit.point;
                if settings.mode == TransportMode::Radiance && sample.is_transmission() {
                    eta_scale *= sample.eta * sample.eta;
                }
                if settings.media {
                    state.medium = medium_after(
                        info.medium_interface.as_ref(),
                        hit.geometric_normal,
                        sample.wi,
                        state.medium,
                    );
                }
                ray = Ray::with_time(offset.towards(sample.wi), sample.wi, hit.time);
            }
        }

        // Russian roulette on the throughput without the refraction
        // scaling and, with media, over the mean spectral density ratio
        // (pbrt-v4's rrBeta).
        let throughput = if settings.media {
            let mean_ratio = state.spectral_density_ratio.average();
            if mean_ratio <= 0.0 {
                break;
            }
            roulette_throughput(state.beta, eta_scale, Some(mean_ratio))
        } else {
            roulette_throughput(state.beta, eta_scale, None)
        };
        let block = state.block as usize;
        match russian_roulette(
            throughput,
            state.vertex_index,
            settings.russian_roulette_depth,
            || sampler.get(settings.layout.dimension(block, layout::RUSSIAN_ROULETTE)),
        ) {
            Some(survival) => state.beta /= survival,
            None => break,
        }
        if settings.media && state.beta.is_black() {
            break;
        }
        state.vertex_index += 1;
        state.block += 1;
    }
}

/// Follows `ray` from the last vertex (or the walk's start) through
/// index-matched boundaries and, when the walk traces media, through media
/// to where the segment ends, drawing the optical depth from `FREE_FLIGHT`
/// of the current block the first time a medium is met. Updates β and the
/// spectral density ratio with each piece's transmittance and densities,
/// the medium, and reports emitting boundaries passed.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn trace_segment<S: SampleSource + ?Sized, O: WalkObserver>(
    scene: &Scene,
    settings: &WalkSettings,
    state: &mut WalkState,
    ray: &mut Ray,
    hit_slot: &mut Option<SurfaceHit>,
    wavelengths: &SampledWavelengths,
    sampler: &mut S,
    counters: &mut TraceCounters,
    observer: &mut O,
) -> SegmentEnd {
    let mut optical_depth: Option<f32> = None;
    for _ in 0..MAX_INTERFACE_CROSSINGS {
        counters.closest_hit_rays += 1;
        *hit_slot = scene.geometry.intersect(ray, f32::INFINITY);
        let hit = hit_slot.as_ref();
        if settings.media
            && let Some(medium_index) = state.medium
        {
            let distance = hit.map_or(f32::INFINITY, |hit| hit.t);
            let coefficients = scene.media[medium_index as usize].coefficients(wavelengths);
            let sigma_t = coefficients.sigma_t();
            let hero_sigma_t = sigma_t[0];
            let tau = *optical_depth.get_or_insert_with(|| {
                let u = sampler.get(
                    settings
                        .layout
                        .dimension(state.block as usize, layout::FREE_FLIGHT),
                );
                -(1.0 - u).ln()
            });
            if hero_sigma_t > 0.0 && tau < hero_sigma_t * distance {
                // Scattering inside this piece: p₀(t) = σt₀ T₀(t).
                let t = tau / hero_sigma_t;
                let piece = transmittance(sigma_t, t);
                let hero_pdf = piece[0] * hero_sigma_t;
                if hero_pdf <= 0.0 {
                    return SegmentEnd::Dead;
                }
                state.beta *= piece * coefficients.sigma_s / hero_pdf;
                state.spectral_density_ratio *= piece * sigma_t / hero_pdf;
                state.segment_transmittance *= piece;
                if state.beta.is_black() {
                    return SegmentEnd::Dead;
                }
                return SegmentEnd::Medium {
                    point: ray.at(t),
                    extinction: sigma_t,
                };
            }
            // Passing through the whole piece: probability T₀(distance).
            optical_depth = Some(tau - hero_sigma_t * distance);
            let piece = transmittance(sigma_t, distance);
            if piece[0] <= 0.0 {
                return SegmentEnd::Dead;
            }
            let ratio = piece / piece[0];
            state.beta *= ratio;
            state.spectral_density_ratio *= ratio;
            state.segment_transmittance *= piece;
        }
        let Some(hit) = hit else {
            return SegmentEnd::Escaped;
        };
        let info = &scene.shapes[hit.shape_index as usize];
        if !info.is_interface {
            return SegmentEnd::Surface;
        }
        // An index-matched boundary: emission it may carry, then straight on.
        if O::FINDS_EMISSION
            && let Some(light_index) = info.light
        {
            observer.emitter(state, light_index, hit, -ray.direction, wavelengths);
        }
        if settings.media {
            let oriented_normal = if info.flip_normals {
                -hit.geometric_normal
            } else {
                hit.geometric_normal
            };
            state.medium = medium_after(
                info.medium_interface.as_ref(),
                oriented_normal,
                ray.direction,
                state.medium,
            );
        }
        *ray = spawn_ray(hit, ray.direction);
    }
    SegmentEnd::Dead
}

/// The observer of [`random_walk`]: records every vertex with its area
/// densities.
struct VertexRecorder<'a> {
    vertices: &'a mut Vec<Vertex>,
    /// Where this walk's vertices start in `vertices`.
    first: usize,
}

impl WalkObserver for VertexRecorder<'_> {
    const FINDS_EMISSION: bool = false;
    const RECORDS_DENSITIES: bool = true;

    #[inline]
    fn vertex<S: SampleSource + ?Sized>(
        &mut self,
        walk: &WalkState,
        vertex: &VertexAt<'_>,
        _wavelengths: &SampledWavelengths,
        _sampler: &mut S,
        _counters: &mut TraceCounters,
    ) -> ControlFlow<()> {
        self.vertices.push(Vertex::record(vertex, walk));
        ControlFlow::Continue(())
    }

    #[inline]
    fn scattered(&mut self, vertex: &VertexAt<'_>, scattering: &Scattering) -> ControlFlow<()> {
        record_scattering(&mut self.vertices[self.first..], vertex, scattering);
        ControlFlow::Continue(())
    }
}

/// Records in a subpath's `vertices` how its last vertex (`vertex`)
/// scattered: whether by a delta lobe, and the area density of sampling the
/// vertex before it from it (its `pdf_reverse`, without the free flight's
/// factor).
#[inline]
pub fn record_scattering(vertices: &mut [Vertex], vertex: &VertexAt<'_>, scattering: &Scattering) {
    let count = vertices.len();
    if let Some(last) = vertices.last_mut() {
        last.delta = scattering.delta;
    }
    if count >= 2 {
        let previous = &mut vertices[count - 2];
        previous.pdf_reverse = solid_angle_to_area(
            scattering.pdf_reverse,
            vertex.point,
            previous.point,
            previous.geometric_normal,
        );
    }
}

/// Walks from `start`, appending up to `settings.max_vertices` vertices
/// with their densities to `vertices` (after those it holds, which the
/// walk leaves alone): the subpaths of light tracing and the bidirectional
/// methods.
pub fn random_walk<S: SampleSource + ?Sized>(
    scene: &Scene,
    start: WalkStart,
    settings: &WalkSettings,
    wavelengths: &mut SampledWavelengths,
    sampler: &mut S,
    counters: &mut TraceCounters,
    vertices: &mut Vec<Vertex>,
) {
    let first = vertices.len();
    walk(
        scene,
        start,
        settings,
        wavelengths,
        sampler,
        counters,
        &mut VertexRecorder { vertices, first },
    );
}

/// The density per unit area at `point` (normal `normal`) of a direction
/// density `pdf_solid_angle` from `from`; a zero normal (a medium point)
/// takes no cosine.
#[inline]
pub fn solid_angle_to_area(pdf_solid_angle: f32, from: Vec3, point: Vec3, normal: Vec3) -> f32 {
    let offset = point - from;
    let distance_squared = offset.length_squared();
    if distance_squared == 0.0 {
        return 0.0;
    }
    if normal == Vec3::ZERO {
        return pdf_solid_angle / distance_squared;
    }
    let cosine = (offset.dot(normal) / distance_squared.sqrt()).abs();
    pdf_solid_angle * cosine / distance_squared
}

/// The medium a ray leaving a vertex in `direction` starts in: at a surface
/// `hit` (oriented) with a medium interface, the side `direction` leaves
/// to; otherwise `medium`, the one the path arrived through.
#[inline]
pub fn medium_leaving(
    scene: &Scene,
    hit: Option<&SurfaceHit>,
    medium: Option<u32>,
    direction: Vec3,
) -> Option<u32> {
    match hit {
        Some(hit) => medium_after(
            scene.shapes[hit.shape_index as usize]
                .medium_interface
                .as_ref(),
            hit.geometric_normal,
            direction,
            medium,
        ),
        None => medium,
    }
}

/// [`SurfaceHit`]'s normals turned as a shape's `flip_normals` asks, in
/// place: the walk needs the hit as stored only until it scatters.
#[inline]
pub(crate) fn orient_hit(flip_normals: bool, hit: &mut SurfaceHit) {
    if flip_normals {
        hit.geometric_normal = -hit.geometric_normal;
        hit.shading_normal = -hit.shading_normal;
    }
}

/// A copy of `hit` (as the geometry stored it) with its normals turned as
/// its shape's `flip_normals` asks: the hit its material sees.
pub(crate) fn oriented_hit(scene: &Scene, hit: &SurfaceHit) -> SurfaceHit {
    let mut hit = *hit;
    orient_hit(
        scene.shapes[hit.shape_index as usize].flip_normals,
        &mut hit,
    );
    hit
}

/// The weight with which `bsdf` lets light arriving from `wo` pass straight
/// through as a *null* event, not a scattering one: Mitsuba 3 flags a thin
/// dielectric's transmission (weight 1 − R', see [`crate::material::ThinDielectricBsdf`]) and
/// a mask's pass-through (1 − α) `Null`, so that its `volpath` lets shadow
/// rays through them with this weight and does not count crossing them as
/// a bounce. Their expectation is the same as that of a specular vertex;
/// counting them in the depth would end paths earlier than Mitsuba does.
pub(crate) fn null_transmission(bsdf: &SurfaceBsdf, wo: Vec3) -> f32 {
    let opacity = bsdf.adapter.opacity.clamp(0.0, 1.0);
    let thin = match (bsdf.bsdf.model(), bsdf.bsdf.back_model()) {
        (BsdfModel::ThinDielectric(thin), None | Some(BsdfModel::ThinDielectric(_))) => {
            let cosine = wo.dot(bsdf.frame.normal());
            if cosine == 0.0 {
                0.0
            } else {
                let back = bsdf.bsdf.back_model();
                let sheet = match back {
                    Some(BsdfModel::ThinDielectric(back)) if cosine < 0.0 => back,
                    _ => thin,
                };
                1.0 - sheet.reflectance(cosine)
            }
        }
        _ => 0.0,
    };
    (1.0 - opacity) + opacity * thin
}

/// Whether `sample` (drawn with component sample `u_component`) took the
/// null lobe of [`null_transmission`]: a mask's pass-through, or a thin
/// dielectric's straight transmission.
pub(crate) fn is_null_sample(bsdf: &SurfaceBsdf, u_component: f32, sample: &BsdfSample) -> bool {
    if bsdf.adapter.nested_component_sample(u_component).is_none() {
        return true;
    }
    matches!(bsdf.bsdf.model(), BsdfModel::ThinDielectric(_)) && sample.is_transmission()
}
