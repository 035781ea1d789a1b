//! The path-space core: subpaths built by one random walk into one vertex
//! type with area-measure forward and reverse densities (pbrt-v4's
//! `RandomWalk` and `Vertex`, Veach 1997 §10.2), for the integrators that
//! connect or reweigh vertices: light tracing now, BDPT, Metropolis and
//! VCM next.
//!
//! A walk starts from a ray leaving the camera or a light with its
//! throughput and the solid-angle density of its direction, and records
//! every scattering vertex: its position and normals, the throughput β of
//! the subpath up to it, its BSDF (in the walk's transport mode), the
//! density of having sampled it from the previous vertex (`pdf_forward`)
//! and, once the next vertex is sampled, from the next one
//! (`pdf_reverse`), both per unit area, and whether it scattered by a delta
//! lobe. Index-matched boundaries (`is_interface` shapes) are crossed and are
//! no vertices; Russian roulette ends walks by [`super::path::russian_roulette`],
//! the rule of every integrator.
//!
//! Light subpaths carry importance transport: the BSDF's adjoint (no
//! 1/η² on refraction) and the adjoint shading-normal correction
//! `|wo·ns| |wi·ng| / (|wo·ng| |wi·ns|)` (Veach 1997, Eq. 5.19) on every
//! scattering and every connection, without which light tracing and BDPT
//! disagree with path tracing under bump and normal maps (pbrt-v4 issues
//! #13 and #385).
//!
//! Each vertex takes its numbers from its block of the subpath's
//! [`SubpathLayout`].

use super::TraceCounters;
use super::path::{orient_hit, russian_roulette};
use crate::geometry::{Ray, spawn_ray};
use crate::material::{SurfaceBsdf, TransportMode};
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

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

    /// The dimension of `offset` in the block of vertex `vertex`.
    #[inline]
    pub const fn dimension(&self, vertex: usize, offset: usize) -> usize {
        self.first + vertex * self.stride + offset
    }
}

/// One scattering vertex of a subpath.
#[derive(Debug, Clone, Copy)]
pub struct Vertex {
    /// The surface point.
    pub point: Vec3,
    /// The geometric normal, oriented as the material sees it.
    pub geometric_normal: Vec3,
    /// The shading normal (the BSDF frame's normal).
    pub shading_normal: Vec3,
    /// Unit direction towards the previous vertex.
    pub wo: Vec3,
    /// The time of the subpath.
    pub time: f32,
    /// The subpath's throughput up to this vertex, excluding its BSDF.
    pub beta: SampledSpectrum,
    /// The BSDF, in the walk's transport mode.
    pub bsdf: SurfaceBsdf,
    /// Density per unit area of sampling this vertex from the previous one.
    pub pdf_forward: f32,
    /// Density per unit area of sampling this vertex from the next one
    /// (0 until the next vertex is sampled; 0 for a delta scattering).
    pub pdf_reverse: f32,
    /// The next vertex was sampled by a delta lobe.
    pub delta: bool,
    /// The shape hit.
    pub shape_index: u32,
}

impl Vertex {
    /// True if the BSDF has a lobe that a connection can evaluate.
    #[inline]
    pub fn is_connectible(&self) -> bool {
        self.bsdf.flags().is_non_specular()
    }

    /// The BSDF times the cosine for a connection leaving towards unit
    /// `wi`, with the adjoint shading-normal correction in importance
    /// transport: `f(wo, wi) |wi·ns|` for radiance,
    /// `f(wo, wi) |wo·ns| |wi·ng| / |wo·ng|` for importance.
    pub fn connection_factor(
        &self,
        wi: Vec3,
        wavelengths: &SampledWavelengths,
        mode: TransportMode,
    ) -> SampledSpectrum {
        let value = self.bsdf.evaluate(self.wo, wi, wavelengths);
        value * scattering_cosine_factor(self, wi, mode)
    }
}

/// The cosine factor of a scattering from `vertex.wo` to `wi`: `|wi·ns|`
/// for radiance, `|wo·ns| |wi·ng| / |wo·ng|` for importance (the cosine
/// times Veach's adjoint correction); 0 where `wo` grazes the geometric
/// surface.
#[inline]
fn scattering_cosine_factor(vertex: &Vertex, wi: Vec3, mode: TransportMode) -> f32 {
    match mode {
        TransportMode::Radiance => wi.dot(vertex.shading_normal).abs(),
        TransportMode::Importance => {
            let wo_geometric = vertex.wo.dot(vertex.geometric_normal).abs();
            if wo_geometric == 0.0 {
                0.0
            } else {
                vertex.wo.dot(vertex.shading_normal).abs() * wi.dot(vertex.geometric_normal).abs()
                    / wo_geometric
            }
        }
    }
}

/// How a walk runs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct WalkSettings {
    /// Radiance for camera subpaths, importance for light subpaths.
    pub mode: TransportMode,
    /// The most vertices to record.
    pub max_vertices: usize,
    /// The vertex index from which Russian roulette may end the walk
    /// (Mitsuba's `rr_depth`, as [`super::path::PathSettings`]).
    pub russian_roulette_depth: u32,
    /// Where the walk's numbers are.
    pub layout: SubpathLayout,
}

/// The start of a walk: a ray leaving the camera or a light.
#[derive(Debug, Clone, Copy)]
pub struct WalkStart {
    /// The ray (its origin already offset from its surface).
    pub ray: Ray,
    /// The throughput carried along it.
    pub beta: SampledSpectrum,
    /// The density per unit solid angle of its direction (0 for a delta
    /// direction: the first vertex's forward density is then 0).
    pub pdf_direction: f32,
}

/// The density per unit area at `point` (normal `normal`) of a direction
/// density `pdf_solid_angle` from `from`.
#[inline]
pub fn solid_angle_to_area(pdf_solid_angle: f32, from: Vec3, point: Vec3, normal: Vec3) -> f32 {
    let offset = point - from;
    let distance_squared = offset.length_squared();
    if distance_squared == 0.0 {
        return 0.0;
    }
    let cosine = (offset.dot(normal) / distance_squared.sqrt()).abs();
    pdf_solid_angle * cosine / distance_squared
}

/// Walks from `start` through the scene, appending up to
/// `settings.max_vertices` vertices to `vertices` (cleared first). Every
/// subpath of every integrator is built here.
pub fn random_walk<S: SampleSource + ?Sized>(
    scene: &Scene,
    start: WalkStart,
    settings: &WalkSettings,
    wavelengths: &mut SampledWavelengths,
    sampler: &mut S,
    counters: &mut TraceCounters,
    vertices: &mut Vec<Vertex>,
) {
    vertices.clear();
    let mut ray = start.ray;
    let mut beta = start.beta;
    let mut pdf_direction = start.pdf_direction;
    // The previous vertex's position (the walk's origin at first), for the
    // area densities: index-matched crossings are no vertices.
    let mut previous_point = start.ray.origin;
    while vertices.len() < settings.max_vertices {
        counters.closest_hit_rays += 1;
        let Some(mut hit) = scene.geometry.intersect(&ray, f32::INFINITY) else {
            break;
        };
        let info = &scene.shapes[hit.shape_index as usize];
        if info.is_interface {
            ray = spawn_ray(&hit, ray.direction);
            continue;
        }
        let Some(material) = &info.material else {
            break;
        };
        orient_hit(info.flip_normals, &mut hit);
        let mut bsdf = material.surface_bsdf_at(&hit, wavelengths);
        bsdf.bsdf = bsdf.bsdf.with_transport_mode(settings.mode);
        let index = vertices.len();
        let mut vertex = Vertex {
            point: hit.point,
            geometric_normal: hit.geometric_normal,
            shading_normal: bsdf.frame.normal(),
            wo: -ray.direction,
            time: hit.time,
            beta,
            bsdf,
            pdf_forward: solid_angle_to_area(
                pdf_direction,
                previous_point,
                hit.point,
                hit.geometric_normal,
            ),
            pdf_reverse: 0.0,
            delta: false,
            shape_index: hit.shape_index,
        };
        if index + 1 == settings.max_vertices {
            vertices.push(vertex);
            break;
        }
        let u_component = sampler.get(settings.layout.dimension(index, layout::SCATTER_COMPONENT));
        let u = sampler.get_2d(settings.layout.dimension(index, layout::SCATTER_DIRECTION));
        let Some(sample) = bsdf.sample(vertex.wo, u_component, u, wavelengths) else {
            vertices.push(vertex);
            break;
        };
        if sample.pdf <= 0.0 || sample.value.is_black() {
            vertices.push(vertex);
            break;
        }
        let factor = scattering_cosine_factor(&vertex, sample.wi, settings.mode);
        beta *= sample.value * (factor / sample.pdf);
        vertex.delta = sample.is_specular();
        // The densities of the two directions at this vertex: the sampled
        // one forward, the reverse one (towards the previous vertex) for
        // the previous vertex's reverse density. A delta lobe has neither.
        let (pdf_forward_direction, pdf_reverse_direction) = if vertex.delta {
            (0.0, 0.0)
        } else {
            let forward = if sample.pdf_is_proportional {
                bsdf.pdf(vertex.wo, sample.wi)
            } else {
                sample.pdf
            };
            (forward, bsdf.pdf(sample.wi, vertex.wo))
        };
        if let Some(previous) = vertices.last_mut() {
            previous.pdf_reverse = solid_angle_to_area(
                pdf_reverse_direction,
                vertex.point,
                previous.point,
                previous.geometric_normal,
            );
        }
        vertices.push(vertex);
        pdf_direction = pdf_forward_direction;
        previous_point = hit.point;
        ray = spawn_ray(&hit, sample.wi);
        match russian_roulette(
            beta.max_component(),
            index as u32,
            settings.russian_roulette_depth,
            || sampler.get(settings.layout.dimension(index, layout::RUSSIAN_ROULETTE)),
        ) {
            Some(survival) => beta /= survival,
            None => break,
        }
    }
}
