//! Bidirectional path tracing (Veach & Guibas 1994; Veach 1997 ch. 10; the
//! estimator of Kollig & Keller's Eq. 4): per pixel sample one camera
//! subpath `z₀ z₁ …` and one light subpath `y₀ y₁ …`, both built by the
//! path-space walk ([`super::path_space`]), and every connection of a
//! prefix of one with a prefix of the other, weighted by multiple
//! importance sampling over all the ways the same path could have been made
//! ([`mis`]; balance heuristic by default, as Kollig & Keller use).
//!
//! Strategy (s, t) uses s light and t camera vertices, a path of s + t − 1
//! segments (at most the depth, Mitsuba's convention as the path tracer's):
//!
//! - s = 0: the camera subpath reaches an emitter (t = 2: emitters seen
//!   directly, which no other strategy makes here: weight 1);
//! - s = 1: next-event estimation from `z_{t−1}` (the path tracer's light
//!   choice and point sampling);
//! - t = 1: light tracing, `y_{s−1}` connected to a lens point and splatted
//!   where it appears (as [`super::light`] does);
//! - s, t ≥ 2: `y_{s−1}` joined to `z_{t−1}` by a shadow ray.
//!
//! (s, t) = (1, 1), the light's own point seen by the camera, is left to
//! (0, 2), as pbrt-v4 does.
//!
//! # Film
//!
//! Camera subpaths start uniformly in the pixel's share of the image grown
//! by the filter's reach ([`crate::film::ImagePlane`]), and every
//! contribution is splatted with the filter: the camera side's at the
//! subpath's raster position (times the plane's area over the image's),
//! light tracing's where its vertex appears. Light tracing's connections
//! reach the same grown plane, and the camera rays' density is taken over
//! it ([`crate::camera::PerspectiveCamera::pdf_importance_with_margin`]),
//! so that the MIS weights compare the two strategies' true densities.
//!
//! # Numbers
//!
//! The camera and emission dimensions, then the subpaths' vertex blocks
//! interleaved, camera block k before light block k (Kollig & Keller's
//! order; the table in [`crate::sampler`]).
//!
//! # Lights at infinity
//!
//! Environments are vertices at infinity, measured by direction (pbrt-v4's
//! convention): a camera subpath that escapes reaches every environment at
//! once, so its origin density is the sum over them of the choice
//! probability times the direction density
//! ([`Bidirectional::environment_density`]); a light subpath leaving an
//! environment starts on a disk facing the scene, and its first vertex's
//! density is the disk's over the cosine there, without a distance.
//!
//! Directional lights are handled as pbrt-v4 does: a light subpath starts
//! at a uniform point of the disk covering the scene, facing the light,
//! and leaves in the light's one direction, so its first vertex's density
//! is the disk's times the cosine there (as from the sky); next-event
//! estimation from `z_{t−1}` gives that vertex the same reverse density.
//! The light is a delta in direction: no camera subpath reaches it, and
//! the split that would is left out of the weights, as for points and spots.
//!
//! # Participating media
//!
//! In scenes with media both subpaths are volumetric walks (the camera's
//! from the camera's medium, the light's from the medium around the point
//! it leaves), with null crossings as `volpath` and the light tracer make
//! them, and every connection, next-event estimation and light-tracing
//! splat is weighted by the transmittance of its segment through media and
//! null surfaces ([`super::estimator::shadow::shadow_transmittance`]). The densities
//! include the free flights at the hero wavelength: a medium vertex's the
//! extinction times the transmittance, a surface vertex's the transmittance
//! of the segment that reached it; a connection's reverse densities take
//! its segment's transmittance (Veach 1997 §10.2's densities over media,
//! as in Pauly et al. 2000). The throughputs divide by the hero wavelength's
//! densities only (no spectral MIS, unlike `volpath`): unbiased where every
//! wavelength's extinction is positive wherever another's is, noisier than
//! `volpath` in strongly chromatic media. Environment and directional
//! lights in a medium that fills the scene are refused, as by the light
//! tracer.
//!
//! # Users
//!
//! The BDPT integrator renders one sample per pixel sample
//! ([`Bidirectional::trace_pixel_sample`]). Others run the same samples
//! and keep their own parts: VCM ([`super::vcm`]) gives each sample its
//! iteration's light subpath, wavelengths and merges through
//! [`LightSubpathPass`]; PSSMLT's path contribution (in [`super::pssmlt`])
//! and MMLT's choice of one strategy (in [`super::mmlt`]) drive
//! [`Bidirectional::trace_image_plane_sample`].

pub mod mis;

use super::driver::{PixelSampleIndex, SplatEstimator, render_splat_paths};
use super::estimator::PathSettings;
use super::estimator::emitted_ray::{EmittedRay, sample_emitted_ray};
use super::estimator::next_event::{AreaRadianceCache, VertexLightSample, choose_and_sample_light};
use super::estimator::shadow::{ShadowTarget, shadow_transmittance, unoccluded};
use super::light::{LightMedia, lens_numbers};
use super::path_space::{
    Scatterer, Scattering, SubpathLayout, Vertex, VertexAt, WalkObserver, WalkSettings, WalkStart,
    WalkState, random_walk, record_scattering, solid_angle_to_area, walk,
};
use super::{AuxiliaryImage, Integrator, IntegratorRender, RenderError, RunControl, TraceCounters};
use crate::film::{Film, ImagePlane, SplatBuffer};
use crate::geometry::{Ray, SurfaceHit, spawn_segment_to_point};
use crate::light::Light;
use crate::material::TransportMode;
use crate::sampler::{PixelSampler, SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, to_linear_srgb};
use glam::{Vec2, Vec3};
use mis::{Strategies, VertexDensities, strategy_weight};
use std::ops::ControlFlow;

/// The options of bidirectional path tracing beyond the shared path
/// settings (depth, Russian roulette, heuristic).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct BdptSettings {
    /// Use the strategies that connect light subpath vertices to the camera
    /// (t = 1, light tracing; default on). Kollig & Keller leave them out
    /// for OFFICE (`--bdpt-skip-eye-connections`): without them, paths
    /// seen through a specular surface first (`… S E`) get only the camera
    /// subpath's strategies.
    pub camera_connections: bool,
    /// Keep one weighted image per strategy (s, t) (pbrt-v4's
    /// `visualizestrategies`; `--strategy-images DIR`), returned as the
    /// layers of the auxiliary image `strategies` named `s{s}_t{t}`; they
    /// sum to the image. Strategies with more than
    /// [`STRATEGY_IMAGE_LIMIT`] vertices on either side are not kept.
    pub strategy_images: bool,
}

impl Default for BdptSettings {
    fn default() -> Self {
        Self {
            camera_connections: true,
            strategy_images: false,
        }
    }
}

/// Strategy images keep (s, t) with s, t up to this.
pub const STRATEGY_IMAGE_LIMIT: usize = 16;

/// The index of strategy (s, t) among the strategy images.
fn strategy_index(s: usize, t: usize) -> Option<usize> {
    (s <= STRATEGY_IMAGE_LIMIT && t <= STRATEGY_IMAGE_LIMIT)
        .then_some(s * (STRATEGY_IMAGE_LIMIT + 1) + t)
}

/// The layer name of strategy (s, t): `s{s}_t{t}`.
pub fn strategy_layer_name(s: usize, t: usize) -> &'static str {
    static NAMES: std::sync::OnceLock<Vec<String>> = std::sync::OnceLock::new();
    let names = NAMES.get_or_init(|| {
        (0..=STRATEGY_IMAGE_LIMIT)
            .flat_map(|s| (0..=STRATEGY_IMAGE_LIMIT).map(move |t| format!("s{s}_t{t}")))
            .collect()
    });
    strategy_index(s, t).map_or("", |index| names[index].as_str())
}

/// Bidirectional path tracing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BdptIntegrator {
    bdpt: BdptSettings,
    settings: PathSettings,
}

impl BdptIntegrator {
    /// BDPT with its options `bdpt` and `settings` (depth, Russian
    /// roulette, MIS heuristic).
    pub fn new(bdpt: BdptSettings, settings: PathSettings) -> Self {
        Self { bdpt, settings }
    }
}

impl Integrator for BdptIntegrator {
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError> {
        let estimator = Bidirectional::new(scene, &self.settings, self.bdpt, "bdpt")?;
        let output = render_splat_paths(&estimator, scene, run)?;
        let auxiliary_images = output
            .total
            .into_layers()
            .map(|layers| AuxiliaryImage {
                name: "strategies",
                layers,
            })
            .into_iter()
            .collect();
        Ok(IntegratorRender {
            film: output.film,
            statistics: output.statistics,
            variance: None,
            auxiliary_images,
            details: None,
        })
    }
}

/// The strategy images of a render: a film per (s, t) that received
/// splats.
pub struct StrategyFilms {
    films: Option<Vec<Option<Film>>>,
    resolution: [usize; 2],
    filter: crate::film::Filter,
}

impl StrategyFilms {
    /// The films with their layer names, in (s, t) order.
    fn into_layers(self) -> Option<Vec<(&'static str, Film)>> {
        let films = self.films?;
        let mut layers = Vec::new();
        for (index, film) in films.into_iter().enumerate() {
            if let Some(film) = film {
                let (s, t) = (
                    index / (STRATEGY_IMAGE_LIMIT + 1),
                    index % (STRATEGY_IMAGE_LIMIT + 1),
                );
                layers.push((strategy_layer_name(s, t), film));
            }
        }
        Some(layers)
    }
}

/// Light the camera subpath reached (a strategy with s = 0): an emitter
/// its segment met, or the environments it escaped to.
#[derive(Debug, Clone, Copy)]
struct ReachedLight {
    /// Scattering vertices of the camera subpath before it.
    vertices_before: usize,
    /// What it reached.
    end: ReachedEnd,
    /// The subpath's throughput on arrival.
    beta: SampledSpectrum,
    /// The density of the end sampled from the previous vertex: per unit
    /// area at an emitter (without the free flight), per unit solid angle
    /// towards the environments (0 after a delta).
    pdf_forward: f32,
    /// Per wavelength, the probability of passing the segment to it.
    arrival_transmittance: SampledSpectrum,
    /// The walk's spectral density ratio on arrival.
    spectral_density_ratio: SampledSpectrum,
}

/// Where the camera subpath reached light.
#[derive(Debug, Clone, Copy)]
enum ReachedEnd {
    /// A point of an emitter.
    Emitter {
        light_index: u32,
        point: Vec3,
        /// The geometric normal as stored (the light flips it itself).
        stored_normal: Vec3,
        uv: Vec2,
        /// Unit direction towards the previous vertex.
        wo: Vec3,
    },
    /// The environments, in a unit direction.
    Environment { direction: Vec3 },
}

/// The light subpath's first vertex: the point on the light.
#[derive(Debug, Clone, Copy)]
pub(crate) struct LightOrigin {
    point: Vec3,
    /// The light's front normal (zero for lights without a surface).
    normal: Vec3,
    /// The light is a delta in position (points, spots, projectors) or in
    /// direction (directional lights): no camera path can reach it.
    pub(crate) delta_light: bool,
    /// For an environment: the direction the subpath leaves it in (`point`
    /// is then on the disk it starts from).
    from_infinity: Option<Vec3>,
    /// Its densities.
    pub(crate) densities: VertexDensities,
    /// The light subpath's vertices carry their throughput over this
    /// (the largest component of `β(y₁)`), so that Russian roulette
    /// decides on the scatterings' product as from the camera (see
    /// [`super::light`]); connections multiply it back.
    pub(crate) beta_scale: f32,
}

/// A work unit's scratch: the two subpaths and the densities of a strategy.
#[derive(Default)]
pub struct BidirectionalScratch {
    camera: Vec<Vertex>,
    reached: Vec<ReachedLight>,
    light: Vec<Vertex>,
    camera_densities: Vec<VertexDensities>,
    light_densities: Vec<VertexDensities>,
    /// Per strategy, its splats ([`BdptSettings::strategy_images`]).
    strategy_splats: Option<Vec<SplatBuffer>>,
}

/// A pass whose light subpaths were traced before its camera subpaths and
/// are shared by them (VCM's iteration, [`super::vcm`]): a bidirectional
/// sample of such a pass takes its wavelengths, time and strategies from
/// the pass, connects to the light subpath the pass traced for the
/// sample's pixel instead of tracing one, and adds the merges of its camera
/// subpath's vertices with the pass's light vertices. The pass keeps its
/// subpaths and its merges to itself: BDPT calls it at these points of a
/// sample and knows nothing of how it stores them.
pub(crate) trait LightSubpathPass<'a> {
    /// The pass's wavelengths.
    fn wavelengths(&self) -> SampledWavelengths;
    /// The pass's time sample (0.5 without motion blur).
    fn time_sample(&self) -> f32;
    /// The pass's techniques (with merging's η).
    fn strategies(&self) -> Strategies;
    /// Asks the cache for the light subpath of [`Self::light_subpath`],
    /// which the sample reads after its camera subpath is traced.
    fn prefetch_light_subpath(&self);
    /// The light subpath the pass traced for the sample's pixel: its origin
    /// (`None`: no light emits), its vertices, and whether its walk dropped
    /// the secondary wavelengths.
    fn light_subpath(&self) -> (Option<LightOrigin>, &'a [Vertex], bool);
    /// The weight of light that the camera subpath reached after
    /// `vertices_before` of its vertices `camera` (a strategy with s = 0),
    /// where the pass sets it instead of the MIS weight of the strategies.
    fn reached_light_weight(&self, camera: &[Vertex], vertices_before: usize) -> Option<f32>;
    /// Called once the camera subpath `camera` is traced, before its
    /// connections (paths of at most `max_depth` segments): the pass may
    /// look up the light vertices its vertices merge with.
    fn find_merge_partners(&mut self, camera: &[Vertex], max_depth: usize);
    /// The merges of the camera subpath `camera`, traced at
    /// `camera_wavelengths`, in linear sRGB; `camera_densities` and
    /// `light_densities` are scratch space for the weights.
    fn merges(
        &mut self,
        bidirectional: &Bidirectional<'_>,
        camera: &[Vertex],
        camera_wavelengths: &SampledWavelengths,
        camera_densities: &mut Vec<VertexDensities>,
        light_densities: &mut Vec<VertexDensities>,
    ) -> [f32; 3];
}

pub(crate) struct Bidirectional<'a> {
    scene: &'a Scene,
    settings: &'a PathSettings,
    strategies: Strategies,
    strategy_images: bool,
    image_plane: ImagePlane,
    /// The grown plane's margin in pixels per side.
    margin: Vec2,
    /// The scene has participating media: volumetric walks, null
    /// crossings and transmittance along connections.
    media: bool,
    /// The media light subpaths start in.
    light_media: LightMedia,
}

/// The camera subpath's observer: records the vertices with their
/// densities, and the light reached (emitters, then the environments).
struct CameraSubpathRecorder<'a> {
    vertices: &'a mut Vec<Vertex>,
    reached: &'a mut Vec<ReachedLight>,
    camera_point: Vec3,
}

impl WalkObserver for CameraSubpathRecorder<'_> {
    const FINDS_EMISSION: bool = true;
    const RECORDS_DENSITIES: bool = true;

    fn emitter(
        &mut self,
        walk: &WalkState,
        light_index: u32,
        hit: &SurfaceHit,
        wo: Vec3,
        _wavelengths: &SampledWavelengths,
    ) {
        let previous_point = self.vertices.last().map_or(self.camera_point, |v| v.point);
        let pdf_forward = if walk.previous.delta {
            0.0
        } else {
            solid_angle_to_area(
                walk.previous.pdf,
                previous_point,
                hit.point,
                hit.geometric_normal,
            )
        };
        self.reached.push(ReachedLight {
            vertices_before: self.vertices.len(),
            end: ReachedEnd::Emitter {
                light_index,
                point: hit.point,
                stored_normal: hit.geometric_normal,
                uv: hit.uv,
                wo,
            },
            beta: walk.beta,
            pdf_forward,
            arrival_transmittance: walk.segment_transmittance,
            spectral_density_ratio: walk.spectral_density_ratio,
        });
    }

    fn escaped(&mut self, walk: &WalkState, direction: Vec3, _wavelengths: &SampledWavelengths) {
        self.reached.push(ReachedLight {
            vertices_before: self.vertices.len(),
            end: ReachedEnd::Environment { direction },
            beta: walk.beta,
            pdf_forward: if walk.previous.delta {
                0.0
            } else {
                walk.previous.pdf
            },
            arrival_transmittance: walk.segment_transmittance,
            spectral_density_ratio: walk.spectral_density_ratio,
        });
    }

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
        record_scattering(self.vertices, vertex, scattering);
        ControlFlow::Continue(())
    }
}

/// The solid-angle density with which `vertex` scatters from `wo` into
/// `wi` (its BSDF's or phase function's) on a subpath in transport `mode`:
/// radiance when a camera subpath samples there, importance when a light
/// subpath does, whichever subpath the vertex was recorded on (the side
/// check of bump and normal maps depends on it, see
/// [`crate::material::SurfaceBsdf::pdf_in_mode`]).
fn scattering_pdf(vertex: &Vertex, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
    match &vertex.scatterer {
        Scatterer::Surface { bsdf, .. } => bsdf.pdf_in_mode(wo, wi, mode),
        Scatterer::Medium { phase } => phase.pdf(wo, wi),
    }
}

/// The area density at `to` (normal `to_normal`, zero in a medium) of
/// `vertex` scattering towards it after arriving from `wo`, on a subpath
/// in transport `mode`.
fn area_density_from(
    vertex: &Vertex,
    wo: Vec3,
    to: Vec3,
    to_normal: Vec3,
    mode: TransportMode,
) -> f32 {
    let wi = (to - vertex.point).normalize_or_zero();
    solid_angle_to_area(
        scattering_pdf(vertex, wo, wi, mode),
        vertex.point,
        to,
        to_normal,
    )
}

/// The density of a camera subpath at `vertex`, arrived at from `wo`,
/// scattering towards the light subpath's origin `origin`: per unit area
/// there, or per unit solid angle for an origin at infinity.
fn density_towards_origin(vertex: &Vertex, wo: Vec3, origin: &LightOrigin) -> f32 {
    match origin.from_infinity {
        Some(direction) => scattering_pdf(vertex, wo, -direction, TransportMode::Radiance),
        None => area_density_from(
            vertex,
            wo,
            origin.point,
            origin.normal,
            TransportMode::Radiance,
        ),
    }
}

/// Sets the reverse density of `z_{t−2}` (`camera[t − 3]`, when t ≥ 3)
/// for a strategy that joins the camera subpath's end `z_{t−1}` to light
/// arriving from the unit direction `wi`: `z_{t−1}` scattering towards it,
/// with the free flight of the segment between them.
pub(crate) fn set_camera_predecessor_reverse(
    camera: &[Vertex],
    t: usize,
    wi: Vec3,
    densities: &mut [VertexDensities],
) {
    if t < 3 {
        return;
    }
    let (end, previous) = (&camera[t - 2], &camera[t - 3]);
    densities[t - 2].set_reverse(
        area_density_from(
            end,
            wi,
            previous.point,
            previous.geometric_normal,
            TransportMode::Importance,
        ),
        end.arrival_transmittance * previous.extinction,
    );
}

/// The reverse density, and its free flight, of a light subpath's vertex
/// `before` (its point, normal and extinction) — or of the subpath's
/// origin when `before` is `None` — as sampled by `scatterer` after arriving
/// from `wo`; `arrival` is the transmittance of the segment between them.
pub(crate) fn light_vertex_reverse(
    scatterer: &Vertex,
    wo: Vec3,
    before: Option<(Vec3, Vec3, SampledSpectrum)>,
    origin: &LightOrigin,
    arrival: SampledSpectrum,
) -> (f32, SampledSpectrum) {
    match before {
        Some((point, normal, extinction)) => (
            area_density_from(scatterer, wo, point, normal, TransportMode::Radiance),
            arrival * extinction,
        ),
        None => (density_towards_origin(scatterer, wo, origin), arrival),
    }
}

/// The geometry's stored normal of an area light's point from its front
/// normal (the light flips stored normals itself).
fn stored_normal(light: &Light, front: Vec3) -> Vec3 {
    let flipped = match light {
        Light::Area { flip_normals, .. } => *flip_normals,
        Light::TexturedArea(light) => light.flip_normals,
        _ => false,
    };
    if flipped { -front } else { front }
}

impl Bidirectional<'_> {
    /// The densities of a subpath's vertex at its origin (`origin`) and its
    /// first `count − 1` recorded vertices, into `densities`; with media,
    /// with their free flights per wavelength.
    pub(crate) fn subpath_densities(
        &self,
        origin: VertexDensities,
        vertices: &[Vertex],
        count: usize,
        densities: &mut Vec<VertexDensities>,
    ) {
        densities.clear();
        densities.push(origin);
        let vertices_used = &vertices[..count - 1];
        if !self.media {
            densities.extend(vertices_used.iter().map(|vertex| {
                VertexDensities::geometric(vertex.pdf_forward, vertex.pdf_reverse, vertex.delta)
            }));
            return;
        }
        densities.extend(
            vertices_used
                .iter()
                .enumerate()
                .map(|(index, vertex)| VertexDensities {
                    forward: vertex.pdf_forward,
                    reverse: vertex.pdf_reverse,
                    forward_free_flight: vertex.arrival_transmittance * vertex.extinction,
                    // Sampled back from the next vertex along the segment
                    // that reached it (the last one's is set by the
                    // strategy).
                    reverse_free_flight: match vertices.get(index + 1) {
                        Some(next) => next.arrival_transmittance * vertex.extinction,
                        None => vertex.extinction,
                    },
                    delta: vertex.delta,
                    on_surface: vertex.geometric_normal != Vec3::ZERO,
                }),
        );
    }

    /// The transmittance of a connection's segment from `origin` (offset
    /// off its surface, in `medium`) at `time` to `end`: 1 or 0 by one
    /// shadow ray without media; with them, the media's transmittance and
    /// the null surfaces' weights along it (zero where it is blocked).
    fn transmittance(
        &self,
        origin: Vec3,
        medium: Option<u32>,
        time: f32,
        end: ShadowTarget,
        wavelengths: &SampledWavelengths,
        counters: &mut TraceCounters,
    ) -> SampledSpectrum {
        let scene = self.scene;
        if self.media {
            let segment = match end {
                ShadowTarget::Point(point, normal) => {
                    spawn_segment_to_point(origin, time, point, normal)
                }
                ShadowTarget::Infinity(direction) => {
                    Some((Ray::with_time(origin, direction, time), f32::INFINITY))
                }
            };
            return match segment {
                Some((ray, t_max)) => {
                    shadow_transmittance(scene, ray, t_max, medium, wavelengths, counters)
                }
                None => SampledSpectrum::zero(),
            };
        }
        counters.shadow_rays += 1;
        if unoccluded(scene, origin, time, end) {
            SampledSpectrum::splat(1.0)
        } else {
            SampledSpectrum::zero()
        }
    }

    /// The density of a light subpath starting at infinity in the unit
    /// direction `-direction` (`direction` points from the scene to the
    /// sky), over all environments, each chosen with its probability: what
    /// a camera subpath escaping along `direction` is compared with.
    fn environment_density(&self, direction: Vec3) -> f32 {
        let scene = self.scene;
        scene
            .environment_lights
            .iter()
            .map(|&index| {
                scene.light_sampler.probability(index as usize)
                    * scene.lights[index as usize].pdf_incident(
                        &scene.geometry,
                        Vec3::ZERO,
                        direction,
                        Vec3::ZERO,
                    )
            })
            .sum()
    }
}

impl SplatEstimator for Bidirectional<'_> {
    type Unit = BidirectionalScratch;
    type Total = StrategyFilms;

    fn new_total(&self, resolution: [usize; 2]) -> Result<StrategyFilms, RenderError> {
        let count = (STRATEGY_IMAGE_LIMIT + 1) * (STRATEGY_IMAGE_LIMIT + 1);
        Ok(StrategyFilms {
            films: self
                .strategy_images
                .then(|| (0..count).map(|_| None).collect()),
            resolution,
            filter: self.scene.filter,
        })
    }

    fn new_unit(&self) -> BidirectionalScratch {
        let count = (STRATEGY_IMAGE_LIMIT + 1) * (STRATEGY_IMAGE_LIMIT + 1);
        BidirectionalScratch {
            strategy_splats: self
                .strategy_images
                .then(|| vec![SplatBuffer::default(); count]),
            ..BidirectionalScratch::default()
        }
    }

    fn merge_unit(&self, total: &mut StrategyFilms, unit: BidirectionalScratch, kept: bool) {
        let (Some(films), Some(buffers)) = (&mut total.films, &unit.strategy_splats) else {
            return;
        };
        if !kept {
            return;
        }
        for (film, buffer) in films.iter_mut().zip(buffers) {
            if buffer.is_empty() {
                continue;
            }
            if film.is_none() {
                match Film::new(total.resolution, total.filter) {
                    Ok(new) => *film = Some(new),
                    Err(_) => continue,
                }
            }
            if let Some(film) = film {
                film.merge_splats(buffer);
            }
        }
    }

    fn trace<S: PixelSampler + ?Sized>(
        &self,
        scratch: &mut BidirectionalScratch,
        path: PixelSampleIndex,
        sampler: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    ) {
        self.trace_pixel_sample(scratch, path.pixel, None, sampler, splats, counters);
    }
}

impl<'a> Bidirectional<'a> {
    /// BDPT over `scene` with `settings` (depth, Russian roulette, MIS
    /// heuristic) and its options `bdpt`, for the integrator `integrator`
    /// (named in errors): the estimator of the BDPT integrator, and the
    /// path sampler of the Metropolis integrators and of VCM's connections
    /// with the default options.
    pub(crate) fn new(
        scene: &'a Scene,
        settings: &'a PathSettings,
        bdpt: BdptSettings,
        integrator: &str,
    ) -> Result<Self, RenderError> {
        let light_media = LightMedia::new(scene, integrator)?;
        let image_plane = ImagePlane::new(scene);
        Ok(Self {
            scene,
            settings,
            strategies: Strategies::bidirectional(settings.heuristic, bdpt.camera_connections),
            strategy_images: bdpt.strategy_images,
            image_plane,
            margin: -image_plane.origin,
            media: scene.has_media(),
            light_media,
        })
    }

    /// The scene.
    pub(crate) fn scene(&self) -> &'a Scene {
        self.scene
    }
}

impl Bidirectional<'_> {
    /// The largest number of segments of a path.
    pub(crate) fn max_depth(&self) -> usize {
        self.settings.max_depth as usize
    }

    /// Whether the scene has participating media (the weights then take
    /// the spectral density ratios of the subpaths).
    pub(crate) fn has_media(&self) -> bool {
        self.media
    }

    /// The sample of pixel `pixel`: the camera subpath from the pixel's
    /// share of the image plane, every strategy, and with `pass` (VCM's
    /// iteration) the pass's light subpath and merges.
    pub(crate) fn trace_pixel_sample<S: SampleSource + ?Sized>(
        &self,
        scratch: &mut BidirectionalScratch,
        pixel: (u32, u32),
        pass: Option<&mut dyn LightSubpathPass<'_>>,
        sampler: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    ) {
        let raster = self
            .image_plane
            .seed_raster(self.scene, pixel, sampler.get_2d(layout::FILM));
        self.trace_from(scratch, raster, None, pass, sampler, splats, counters);
    }

    /// A sample from a uniform point of the whole image plane (the film
    /// numbers place it): every strategy, or with `only` the one strategy
    /// (s, t), the subpaths then walked only as far as it needs. What the
    /// Metropolis integrators' chains drive.
    pub(crate) fn trace_image_plane_sample<S: SampleSource + ?Sized>(
        &self,
        scratch: &mut BidirectionalScratch,
        only: Option<(usize, usize)>,
        source: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    ) {
        let raster = self
            .image_plane
            .raster(Vec2::from(source.get_2d(layout::FILM)));
        self.trace_from(scratch, raster, only, None, source, splats, counters);
    }

    /// One bidirectional sample whose camera subpath starts at `raster`:
    /// every strategy, or with `only` the one strategy (s, t). With `pass`
    /// (a VCM iteration), the wavelengths, time and strategies are the
    /// pass's, the light subpath is the one it traced, and the camera
    /// subpath's vertices merge with the pass's light vertices.
    #[allow(clippy::too_many_arguments)]
    fn trace_from<S: SampleSource + ?Sized>(
        &self,
        scratch: &mut BidirectionalScratch,
        raster: Vec2,
        only: Option<(usize, usize)>,
        mut pass: Option<&mut dyn LightSubpathPass<'_>>,
        sampler: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    ) {
        let scene = self.scene;
        let camera = &scene.camera;
        let max_depth = self.settings.max_depth as usize;
        if max_depth == 0 {
            return;
        }
        let wanted = |s: usize, t: usize| only.is_none_or(|strategy| strategy == (s, t));
        // With one strategy, the camera subpath needs t − 1 vertices (s = 0
        // finds its emitter on the segment after the last), the light
        // subpath s − 1 after its origin.
        let camera_vertex_limit = match only {
            Some((_, t)) => t.saturating_sub(1),
            None => usize::MAX,
        };
        let light_vertex_limit = match only {
            Some((s, _)) => s.saturating_sub(1),
            None => usize::MAX,
        };
        let needs_light_subpath = only.is_none_or(|(s, t)| s >= 2 || (t == 1 && s >= 1));

        // The camera subpath.
        if let Some(pass) = &pass {
            // Its light subpath, read after the camera subpath is traced.
            pass.prefetch_light_subpath();
        }
        let strategies = pass
            .as_ref()
            .map_or(self.strategies, |pass| pass.strategies());
        let u_lens = lens_numbers(scene, sampler, layout::LENS);
        let u_time = match &pass {
            Some(pass) => pass.time_sample(),
            None if camera.uses_time_sample() => sampler.get(layout::TIME),
            None => 0.5,
        };
        let mut wavelengths = match &pass {
            Some(pass) => pass.wavelengths(),
            None => SampledWavelengths::sample_visible(sampler.get(layout::WAVELENGTH)),
        };
        let camera_ray = camera.generate_ray(raster, u_lens, u_time);
        let time = camera_ray.time;
        let camera_density = camera.pdf_importance_with_margin(
            camera_ray.origin,
            camera_ray.direction,
            time,
            self.margin,
        );
        if camera_density.direction <= 0.0 {
            return;
        }
        let BidirectionalScratch {
            camera: camera_vertices,
            reached,
            light: light_vertices,
            camera_densities,
            light_densities,
            strategy_splats,
        } = scratch;
        camera_vertices.clear();
        reached.clear();
        walk(
            scene,
            WalkStart {
                ray: Ray::with_time(camera_ray.origin, camera_ray.direction, time),
                beta: SampledSpectrum::splat(1.0),
                pdf_direction: camera_density.direction,
                medium: scene.camera_medium,
            },
            &WalkSettings {
                mode: TransportMode::Radiance,
                max_vertices: WalkSettings::camera_vertices(self.settings.max_depth)
                    .min(camera_vertex_limit),
                russian_roulette_depth: self.settings.russian_roulette_depth,
                layout: SubpathLayout::BIDIRECTIONAL_CAMERA,
                media: self.media,
                null_crossings: self.media,
            },
            &mut wavelengths,
            sampler,
            counters,
            &mut CameraSubpathRecorder {
                vertices: camera_vertices,
                reached,
                camera_point: camera_ray.origin,
            },
        );

        // The wavelengths as the camera subpath left them: merges combine
        // them with other light subpaths'.
        let camera_wavelengths = wavelengths;
        if let Some(pass) = pass.as_deref_mut()
            && strategies.merging.is_some()
        {
            pass.find_merge_partners(camera_vertices, max_depth);
        }

        // The light subpath (with VCM, the one the pass traced for this
        // pixel: the same numbers).
        light_vertices.clear();
        let (light_origin, light_vertices): (Option<LightOrigin>, &[Vertex]) = match &pass {
            Some(pass) => {
                let (origin, vertices, secondary_terminated) = pass.light_subpath();
                if secondary_terminated {
                    wavelengths.terminate_secondary();
                }
                (origin, vertices)
            }
            None if needs_light_subpath => (
                self.trace_light_subpath(
                    time,
                    &mut wavelengths,
                    sampler,
                    counters,
                    light_vertices,
                    light_vertex_limit,
                ),
                light_vertices,
            ),
            None => (None, light_vertices),
        };

        // The camera side's strategies (t ≥ 2), summed and splatted at the
        // camera subpath's raster position.
        let mut camera_side = SampledSpectrum::zero();

        // s = 0: emitters the camera subpath reached, and the
        // environments it escaped to.
        for reached in reached.iter() {
            let emitted = match reached.end {
                ReachedEnd::Emitter {
                    light_index,
                    stored_normal,
                    uv,
                    wo,
                    ..
                } => scene.lights[light_index as usize].emitted_radiance(
                    stored_normal,
                    uv,
                    wo,
                    &wavelengths,
                ),
                ReachedEnd::Environment { direction } => {
                    let mut emitted = SampledSpectrum::zero();
                    for &index in &scene.environment_lights {
                        emitted += scene.lights[index as usize]
                            .environment_radiance(direction, &wavelengths);
                    }
                    emitted
                }
            };
            if emitted.is_black() {
                continue;
            }
            let t = reached.vertices_before + 2;
            if !wanted(0, t) {
                continue;
            }
            self.subpath_densities(
                VertexDensities::default(),
                camera_vertices,
                t - 1,
                camera_densities,
            );
            let previous = (t >= 3).then(|| &camera_vertices[t - 3]);
            // The density of the end as a light subpath's origin, and of
            // z_{t−2} as that subpath's first vertex.
            let (origin_density, predecessor_density) = match reached.end {
                ReachedEnd::Emitter {
                    light_index,
                    point,
                    stored_normal,
                    wo,
                    ..
                } => {
                    let light = &scene.lights[light_index as usize];
                    let choice = scene.light_sampler.probability(light_index as usize);
                    let emission_pdf =
                        light.pdf_emission(&scene.geometry, point, wo, stored_normal);
                    (
                        choice * emission_pdf.position,
                        previous.map(|previous| {
                            solid_angle_to_area(
                                emission_pdf.direction,
                                point,
                                previous.point,
                                previous.geometric_normal,
                            )
                        }),
                    )
                }
                // From the sky: the disk's density, times the cosine there.
                ReachedEnd::Environment { direction } => (
                    self.environment_density(direction),
                    previous.map(|previous| self.disk_density(direction, previous)),
                ),
            };
            camera_densities.push(VertexDensities {
                forward: reached.pdf_forward,
                reverse: origin_density,
                forward_free_flight: reached.arrival_transmittance,
                reverse_free_flight: SampledSpectrum::splat(1.0),
                delta: false,
                on_surface: true,
            });
            if let (Some(previous), Some(density)) = (previous, predecessor_density) {
                camera_densities[t - 2]
                    .set_reverse(density, reached.arrival_transmittance * previous.extinction);
            }
            let weight = match pass.as_ref().and_then(|pass| {
                pass.reached_light_weight(camera_vertices, reached.vertices_before)
            }) {
                Some(weight) => weight,
                None => strategy_weight(
                    camera_densities,
                    &[],
                    false,
                    strategies,
                    self.media.then_some(&reached.spectral_density_ratio),
                ),
            };
            let value = reached.beta * emitted * weight;
            self.record(strategy_splats, 0, t, raster, &value, &wavelengths);
            camera_side += value;
        }

        for t in 2..=(camera_vertices.len() + 1).min(max_depth + 1) {
            let end = &camera_vertices[t - 2];
            if !end.is_connectible() || !strategies.connections {
                continue;
            }
            // s = 1: next-event estimation from z_{t−1}.
            if t <= max_depth && wanted(1, t) {
                let value = self.next_event(
                    camera_vertices,
                    t,
                    &wavelengths,
                    strategies,
                    sampler,
                    counters,
                    camera_densities,
                    light_densities,
                );
                self.record(strategy_splats, 1, t, raster, &value, &wavelengths);
                camera_side += value;
            }
            // s ≥ 2: connections to the light subpath's vertices.
            let Some(origin) = &light_origin else {
                continue;
            };
            for s in 2..=(light_vertices.len() + 1).min(max_depth + 1 - t) {
                if !wanted(s, t) {
                    continue;
                }
                let value = self.connect(
                    camera_vertices,
                    t,
                    origin,
                    light_vertices,
                    s,
                    &wavelengths,
                    strategies,
                    counters,
                    camera_densities,
                    light_densities,
                );
                self.record(strategy_splats, s, t, raster, &value, &wavelengths);
                camera_side += value;
            }
        }
        let mut rgb = if camera_side.is_black() {
            [0.0; 3]
        } else {
            to_linear_srgb(&camera_side, &wavelengths)
        };
        // Vertex merging with the pass's light vertices.
        if let Some(pass) = pass
            && strategies.merging.is_some()
        {
            let merged = pass.merges(
                self,
                camera_vertices,
                &camera_wavelengths,
                camera_densities,
                light_densities,
            );
            rgb = std::array::from_fn(|channel| rgb[channel] + merged[channel]);
        }
        if rgb != [0.0; 3] {
            let _ = splats.add(
                raster.to_array(),
                rgb.map(|channel| channel * self.image_plane.area_scale),
            );
        }

        // t = 1: light tracing.
        let Some(origin) = &light_origin else {
            return;
        };
        if !strategies.camera_connections || !strategies.connections {
            return;
        }
        for s in 2..=(light_vertices.len() + 1).min(max_depth) {
            if !wanted(s, 1) {
                continue;
            }
            let Some((raster, rgb)) = self.light_tracing(
                origin,
                light_vertices,
                s,
                &wavelengths,
                strategies,
                sampler,
                counters,
                camera_densities,
                light_densities,
            ) else {
                continue;
            };
            let _ = splats.add(raster.to_array(), rgb);
            if let Some(buffers) = strategy_splats
                && let Some(index) = strategy_index(s, 1)
            {
                let _ = buffers[index].add(raster.to_array(), rgb);
            }
        }
    }
}

impl Bidirectional<'_> {
    /// Splats a camera-side strategy's `value` into its strategy image,
    /// where they are kept.
    fn record(
        &self,
        buffers: &mut Option<Vec<SplatBuffer>>,
        s: usize,
        t: usize,
        raster: Vec2,
        value: &SampledSpectrum,
        wavelengths: &SampledWavelengths,
    ) {
        let Some(buffers) = buffers else {
            return;
        };
        if value.is_black() {
            return;
        }
        if let Some(index) = strategy_index(s, t) {
            let rgb = to_linear_srgb(value, wavelengths);
            let _ = buffers[index].add(
                raster.to_array(),
                rgb.map(|channel| channel * self.image_plane.area_scale),
            );
        }
    }
}

impl Bidirectional<'_> {
    /// The area density at `vertex` of a light subpath leaving the sky
    /// seen in `direction` (from the scene): the density of its starting
    /// disk times the cosine at the vertex (the light's own, the same for
    /// every environment: the disk spans the scene).
    fn disk_density(&self, direction: Vec3, vertex: &Vertex) -> f32 {
        let Some(&index) = self.scene.environment_lights.first() else {
            return 0.0;
        };
        self.light_disk_density(&self.scene.lights[index as usize], direction, vertex)
    }

    /// The area density at `vertex` of a light subpath leaving `light` (at
    /// infinity: an environment or a directional light) seen in
    /// `direction` from the scene: its disk's density times the cosine at
    /// the vertex.
    fn light_disk_density(&self, light: &Light, direction: Vec3, vertex: &Vertex) -> f32 {
        let position = light
            .pdf_emission(&self.scene.geometry, vertex.point, -direction, Vec3::ZERO)
            .position;
        if vertex.geometric_normal == Vec3::ZERO {
            position
        } else {
            position * direction.dot(vertex.geometric_normal).abs()
        }
    }

    /// Traces the light subpath, appending its walk's vertices (`y₁` on)
    /// to `vertices`, and returns its origin `y₀`, or `None` if no light
    /// emits. The vertices' throughputs include the emission: `β(y₁) = Le
    /// |cos| / (p_choice p_position p_direction)`.
    pub(crate) fn trace_light_subpath<S: SampleSource + ?Sized>(
        &self,
        time: f32,
        wavelengths: &mut SampledWavelengths,
        sampler: &mut S,
        counters: &mut TraceCounters,
        vertices: &mut Vec<Vertex>,
        vertex_limit: usize,
    ) -> Option<LightOrigin> {
        let scene = self.scene;
        let first = vertices.len();
        let emitted = sample_emitted_ray(scene, sampler, wavelengths)?;
        let EmittedRay {
            light_index,
            choice_probability: choice,
            emission,
            on_surface,
        } = emitted;
        let light = &scene.lights[light_index];
        let at_infinity = light.is_infinite();
        let mut origin = LightOrigin {
            point: emission.origin,
            normal: if on_surface {
                emission.normal
            } else {
                Vec3::ZERO
            },
            delta_light: light.is_delta(),
            from_infinity: at_infinity.then_some(emission.direction),
            // A directional light's origin counts only towards the split
            // where the camera subpath reaches it, which is left out (it is
            // a delta in direction); 0 says so.
            densities: VertexDensities::geometric(
                if emission.is_delta_direction {
                    0.0
                } else if at_infinity {
                    self.environment_density(-emission.direction)
                } else {
                    choice * emission.pdf_position
                },
                0.0,
                false,
            ),
            beta_scale: 1.0,
        };
        let max_vertices = (self.settings.max_depth.saturating_sub(1) as usize).min(vertex_limit);
        if max_vertices == 0 {
            return Some(origin);
        }
        let Some((beta, beta_scale)) = emitted.scaled_throughput() else {
            return Some(origin);
        };
        origin.beta_scale = beta_scale;
        random_walk(
            scene,
            WalkStart {
                ray: Ray::with_time(emitted.ray_origin(), emission.direction, time),
                beta,
                pdf_direction: emission.pdf_direction,
                medium: self.light_media.leaving(
                    scene,
                    light_index,
                    emission.origin,
                    emission.normal,
                    emission.direction,
                ),
            },
            &WalkSettings {
                mode: TransportMode::Importance,
                max_vertices,
                russian_roulette_depth: self.settings.russian_roulette_depth,
                layout: SubpathLayout::BIDIRECTIONAL_LIGHT,
                media: self.media,
                null_crossings: self.media,
            },
            wavelengths,
            sampler,
            counters,
            vertices,
        );
        let vertices = &mut vertices[first..];
        // From the sky, y₁'s density is the disk's over its cosine (no
        // distance: the disk is at infinity).
        if at_infinity && let Some(first) = vertices.first_mut() {
            let cosine = if first.geometric_normal == Vec3::ZERO {
                1.0
            } else {
                emission.direction.dot(first.geometric_normal).abs()
            };
            first.pdf_forward = emission.pdf_position * cosine;
        }
        // y₀'s reverse density: y₁ scattering back to it after arriving
        // from y₂ (used by the strategies with s ≥ 3).
        if vertices.len() >= 2 {
            let (first, second) = (&vertices[0], &vertices[1]);
            origin.densities.set_reverse(
                density_towards_origin(first, -second.wo, &origin),
                first.arrival_transmittance,
            );
        }
        Some(origin)
    }

    /// Strategy (1, t): next-event estimation from `z_{t−1}`, weighted.
    #[allow(clippy::too_many_arguments)]
    fn next_event<S: SampleSource + ?Sized>(
        &self,
        camera: &[Vertex],
        t: usize,
        wavelengths: &SampledWavelengths,
        strategies: Strategies,
        sampler: &mut S,
        counters: &mut TraceCounters,
        camera_densities: &mut Vec<VertexDensities>,
        light_densities: &mut Vec<VertexDensities>,
    ) -> SampledSpectrum {
        let scene = self.scene;
        let end = &camera[t - 2];
        let block = SubpathLayout::BIDIRECTIONAL_CAMERA;
        // The reference point off the surface on the arriving side, as the
        // path tracer's (a sphere sampled from a point on itself would be
        // seen from outside).
        let Some(VertexLightSample {
            light_index,
            selection_probability: choice,
            sample,
            ..
        }) = choose_and_sample_light(
            scene,
            end.origin_towards(end.wo),
            sampler.get(block.dimension(t - 2, layout::LIGHT_SELECTION)),
            || sampler.get_2d(block.dimension(t - 2, layout::LIGHT_POSITION)),
            wavelengths,
            &mut AreaRadianceCache::new(),
        )
        else {
            return SampledSpectrum::zero();
        };
        let light = &scene.lights[light_index];
        if sample.pdf.is_nan() || sample.pdf <= 0.0 || choice <= 0.0 {
            return SampledSpectrum::zero();
        }
        let factor = end.connection_factor(sample.wi, wavelengths, TransportMode::Radiance);
        if factor.is_black() {
            return SampledSpectrum::zero();
        }
        let transmittance = self.transmittance(
            end.origin_towards(sample.wi),
            end.medium_towards(scene, sample.wi),
            end.time,
            ShadowTarget::of_sample(&sample),
            wavelengths,
            counters,
        );
        if transmittance.is_black() {
            return SampledSpectrum::zero();
        }
        let value = end.beta * factor * sample.radiance * transmittance / (choice * sample.pdf);
        // The light subpath's origin and the density with which it would
        // have reached the camera subpath's end.
        let (origin, end_reverse) = if sample.is_infinite {
            // The sampled sky direction, or the directional light (its
            // forward density as the light subpath gives it: 0, see
            // `trace_light_subpath`).
            let mut origin = VertexDensities::geometric(
                if sample.is_delta {
                    0.0
                } else {
                    self.environment_density(sample.wi)
                },
                0.0,
                false,
            );
            origin.set_reverse(
                scattering_pdf(end, end.wo, sample.wi, TransportMode::Radiance),
                transmittance,
            );
            (origin, self.light_disk_density(light, sample.wi, end))
        } else {
            // The sampled light point.
            let light_normal = if sample.is_delta {
                Vec3::ZERO
            } else {
                sample.normal
            };
            let emission_pdf = light.pdf_emission(
                &scene.geometry,
                sample.point,
                -sample.wi,
                stored_normal(light, sample.normal),
            );
            let mut origin = VertexDensities::geometric(
                choice
                    * if sample.is_delta {
                        1.0
                    } else {
                        emission_pdf.position
                    },
                0.0,
                false,
            );
            origin.set_reverse(
                area_density_from(
                    end,
                    end.wo,
                    sample.point,
                    light_normal,
                    TransportMode::Radiance,
                ),
                transmittance,
            );
            let end_reverse = solid_angle_to_area(
                emission_pdf.direction,
                sample.point,
                end.point,
                end.geometric_normal,
            );
            (origin, end_reverse)
        };
        light_densities.clear();
        light_densities.push(origin);
        self.subpath_densities(VertexDensities::default(), camera, t, camera_densities);
        camera_densities[t - 1].set_reverse(end_reverse, transmittance * end.extinction);
        camera_densities[t - 1].delta = false;
        set_camera_predecessor_reverse(camera, t, sample.wi, camera_densities);
        let weight = strategy_weight(
            camera_densities,
            light_densities,
            sample.is_delta,
            strategies,
            self.media.then_some(&end.spectral_density_ratio),
        );
        value * weight
    }

    /// Strategy (s, t), s, t ≥ 2: `y_{s−1}` joined to `z_{t−1}`, weighted.
    #[allow(clippy::too_many_arguments)]
    fn connect(
        &self,
        camera: &[Vertex],
        t: usize,
        origin: &LightOrigin,
        light: &[Vertex],
        s: usize,
        wavelengths: &SampledWavelengths,
        strategies: Strategies,
        counters: &mut TraceCounters,
        camera_densities: &mut Vec<VertexDensities>,
        light_densities: &mut Vec<VertexDensities>,
    ) -> SampledSpectrum {
        let camera_end = &camera[t - 2];
        let light_end = &light[s - 2];
        if !light_end.is_connectible() {
            return SampledSpectrum::zero();
        }
        let offset = light_end.point - camera_end.point;
        let distance_squared = offset.length_squared();
        if distance_squared.is_nan() || distance_squared <= 0.0 {
            return SampledSpectrum::zero();
        }
        let direction = offset / distance_squared.sqrt();
        let camera_factor =
            camera_end.connection_factor(direction, wavelengths, TransportMode::Radiance);
        if camera_factor.is_black() {
            return SampledSpectrum::zero();
        }
        let light_factor =
            light_end.connection_factor(-direction, wavelengths, TransportMode::Importance);
        if light_factor.is_black() {
            return SampledSpectrum::zero();
        }
        let value = camera_end.beta
            * camera_factor
            * light_factor
            * light_end.beta
            * (origin.beta_scale / distance_squared);
        if value.is_black() {
            return SampledSpectrum::zero();
        }
        let transmittance = self.transmittance(
            camera_end.origin_towards(direction),
            camera_end.medium_towards(self.scene, direction),
            camera_end.time,
            ShadowTarget::Point(light_end.point, light_end.geometric_normal),
            wavelengths,
            counters,
        );
        if transmittance.is_black() {
            return SampledSpectrum::zero();
        }
        let value = value * transmittance;
        self.subpath_densities(VertexDensities::default(), camera, t, camera_densities);
        self.subpath_densities(origin.densities, light, s, light_densities);
        camera_densities[t - 1].set_reverse(
            area_density_from(
                light_end,
                light_end.wo,
                camera_end.point,
                camera_end.geometric_normal,
                TransportMode::Importance,
            ),
            transmittance * camera_end.extinction,
        );
        camera_densities[t - 1].delta = false;
        light_densities[s - 1].set_reverse(
            area_density_from(
                camera_end,
                camera_end.wo,
                light_end.point,
                light_end.geometric_normal,
                TransportMode::Radiance,
            ),
            transmittance * light_end.extinction,
        );
        light_densities[s - 1].delta = false;
        set_camera_predecessor_reverse(camera, t, direction, camera_densities);
        let before = (s >= 3).then(|| {
            let before = &light[s - 3];
            (before.point, before.geometric_normal, before.extinction)
        });
        let (density, free_flight) = light_vertex_reverse(
            light_end,
            -direction,
            before,
            origin,
            light_end.arrival_transmittance,
        );
        light_densities[s - 2].set_reverse(density, free_flight);
        let spectral_density_ratio =
            camera_end.spectral_density_ratio * light_end.spectral_density_ratio;
        let weight = strategy_weight(
            camera_densities,
            light_densities,
            origin.delta_light,
            strategies,
            self.media.then_some(&spectral_density_ratio),
        );
        value * weight
    }

    /// Strategy (s, 1): `y_{s−1}` connected to a lens point, weighted; the
    /// raster position where it appears and its value to splat there.
    #[allow(clippy::too_many_arguments)]
    fn light_tracing<S: SampleSource + ?Sized>(
        &self,
        origin: &LightOrigin,
        light: &[Vertex],
        s: usize,
        wavelengths: &SampledWavelengths,
        strategies: Strategies,
        sampler: &mut S,
        counters: &mut TraceCounters,
        camera_densities: &mut Vec<VertexDensities>,
        light_densities: &mut Vec<VertexDensities>,
    ) -> Option<(Vec2, [f32; 3])> {
        let scene = self.scene;
        let light_end = &light[s - 2];
        if !light_end.is_connectible() {
            return None;
        }
        let u_lens = lens_numbers(
            scene,
            sampler,
            SubpathLayout::BIDIRECTIONAL_LIGHT.dimension(s - 2, layout::CAMERA_CONNECTION),
        );
        let camera_sample = scene.camera.sample_incident_importance_with_margin(
            light_end.point,
            light_end.time,
            u_lens,
            self.margin,
        )?;
        let factor =
            light_end.connection_factor(camera_sample.wi, wavelengths, TransportMode::Importance);
        let value =
            light_end.beta * factor * (origin.beta_scale * camera_sample.value / camera_sample.pdf);
        if value.is_black() {
            return None;
        }
        let transmittance = self.transmittance(
            light_end.origin_towards(camera_sample.wi),
            light_end.medium_towards(scene, camera_sample.wi),
            light_end.time,
            ShadowTarget::Point(camera_sample.lens_point, Vec3::ZERO),
            wavelengths,
            counters,
        );
        if transmittance.is_black() {
            return None;
        }
        let value = value * transmittance;
        camera_densities.clear();
        camera_densities.push(VertexDensities::default());
        self.subpath_densities(origin.densities, light, s, light_densities);
        let camera_direction = scene.camera.pdf_importance_with_margin(
            camera_sample.lens_point,
            -camera_sample.wi,
            light_end.time,
            self.margin,
        );
        light_densities[s - 1].set_reverse(
            solid_angle_to_area(
                camera_direction.direction,
                camera_sample.lens_point,
                light_end.point,
                light_end.geometric_normal,
            ),
            transmittance * light_end.extinction,
        );
        light_densities[s - 1].delta = false;
        let before = (s >= 3).then(|| {
            let before = &light[s - 3];
            (before.point, before.geometric_normal, before.extinction)
        });
        let (density, free_flight) = light_vertex_reverse(
            light_end,
            camera_sample.wi,
            before,
            origin,
            light_end.arrival_transmittance,
        );
        light_densities[s - 2].set_reverse(density, free_flight);
        let weight = strategy_weight(
            camera_densities,
            light_densities,
            origin.delta_light,
            strategies,
            self.media.then_some(&light_end.spectral_density_ratio),
        );
        Some((
            camera_sample.raster,
            to_linear_srgb(&(value * weight), wavelengths),
        ))
    }
}
