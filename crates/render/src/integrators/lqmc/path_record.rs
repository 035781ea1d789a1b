//! The record of a camera path that LQMC explores: its camera vertex, its
//! surface vertices and how it ends (an emitter reached by BSDF sampling,
//! the environment, or a next-event-estimation connection). A record holds
//! positions only; every value and density is recomputed from it by
//! [`super::path_walk`], so that the seed and each lattice member go
//! through the same code.

use crate::geometry::SurfaceHit;
use crate::integrators::estimator::next_event::VertexLightSample;
use crate::material::BsdfFlags;
use glam::{Vec2, Vec3};

/// The camera vertex `x_0`: the numbers that place it and the lens point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraVertex {
    /// Continuous raster position of the camera ray.
    pub raster: Vec2,
    /// Lens numbers (dimensions 2, 3).
    pub u_lens: [f32; 2],
    /// Time number (dimension 4).
    pub u_time: f32,
    /// Hero-wavelength number (dimension 5).
    pub u_wavelength: f32,
    /// The lens point in world space (the camera ray's origin).
    pub origin: Vec3,
}

/// One scattering vertex `x_{m+1}` (vertex `m` of the dimension layout): a
/// surface hit, or a scattering event inside a homogeneous medium (then
/// `medium` names the medium, and `raw_hit` and `hit` hold only the point
/// and the time: zero normals, shape index [`MEDIUM_SHAPE`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceVertex {
    /// The hit as the geometry returned it (for ray spawning and emission).
    pub raw_hit: SurfaceHit,
    /// The hit with normals flipped for shapes with `flip_normals` (for
    /// materials).
    pub hit: SurfaceHit,
    /// Flags of the scattering sampled here (empty where none was, and at
    /// medium vertices).
    pub sampled: BsdfFlags,
    /// The vertex's effective roughness for the breakup CDF (see
    /// [`super::classification::vertex_roughness`]).
    pub roughness: f32,
    /// The medium of a medium vertex (`None` on surfaces).
    pub medium: Option<u32>,
}

/// The shape index that medium vertices carry in their hit records.
pub const MEDIUM_SHAPE: u32 = u32::MAX;

impl SurfaceVertex {
    /// A surface vertex with nothing sampled yet.
    pub fn surface(raw_hit: SurfaceHit, hit: SurfaceHit, roughness: f32) -> Self {
        Self {
            raw_hit,
            hit,
            sampled: BsdfFlags::NONE,
            roughness,
            medium: None,
        }
    }

    /// A scattering event at `point` inside medium `medium`, whose phase
    /// function gives it `roughness` (√(1 − g²)).
    pub fn in_medium(point: Vec3, time: f32, medium: u32, roughness: f32) -> Self {
        let hit = SurfaceHit {
            t: 0.0,
            point,
            geometric_normal: Vec3::ZERO,
            shading_normal: Vec3::ZERO,
            uv: Vec2::ZERO,
            dpdu: Vec3::ZERO,
            dpdv: Vec3::ZERO,
            shape_index: MEDIUM_SHAPE,
            primitive_index: 0,
            time,
        };
        Self {
            raw_hit: hit,
            hit,
            sampled: BsdfFlags::NONE,
            roughness,
            medium: Some(medium),
        }
    }

    /// Whether this is a scattering event in a medium.
    pub fn is_medium(&self) -> bool {
        self.medium.is_some()
    }

    /// The factor that turns a solid-angle density at the previous vertex
    /// into a density at this vertex, per unit distance squared: |cos| of
    /// the geometric normal with `direction` on surfaces, 1 in media
    /// (volume measure).
    pub fn measure_cosine(&self, direction: Vec3) -> f32 {
        if self.is_medium() {
            1.0
        } else {
            self.raw_hit.geometric_normal.dot(direction).abs()
        }
    }
}

/// A next-event-estimation connection from the last surface vertex.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightConnection {
    /// The light.
    pub light_index: usize,
    /// Probability of choosing it.
    pub selection_probability: f32,
    /// The point sampled on it (for infinite lights: far along the direction).
    pub point: Vec3,
    /// Its normal as stored in the geometry (before any flip).
    pub stored_normal: Vec3,
    /// Its normal facing the emitting side.
    pub front_normal: Vec3,
    /// Its surface coordinates (textured area lights).
    pub uv: glam::Vec2,
    /// The direction from the seed's vertex (infinite lights keep it).
    pub direction: Vec3,
    /// A delta light (a point light): reconnection samples it again.
    pub is_delta: bool,
    /// An infinite light: reconnection keeps the direction.
    pub is_infinite: bool,
    /// The numbers that sampled it (for delta lights).
    pub u_primitive: f32,
    /// The light-position numbers.
    pub u_position: [f32; 2],
}

impl LightConnection {
    /// The connection to next-event estimation's light sample (once it is
    /// known to arrive): the light's stored normal undoes an area light's
    /// flip, so reconnection can sample the same light again.
    pub(crate) fn from_sample(
        scene: &crate::scene::Scene,
        light_sample: VertexLightSample,
    ) -> Self {
        let VertexLightSample {
            light_index,
            selection_probability,
            u_primitive,
            u_position,
            sample,
        } = light_sample;
        let stored_normal = match &scene.lights[light_index] {
            crate::light::Light::Area {
                flip_normals: true, ..
            } => -sample.normal,
            crate::light::Light::TexturedArea(light) if light.flip_normals => -sample.normal,
            _ => sample.normal,
        };
        LightConnection {
            light_index,
            selection_probability,
            point: sample.point,
            stored_normal,
            front_normal: sample.normal,
            uv: sample.uv,
            direction: sample.wi,
            is_delta: sample.is_delta,
            is_infinite: sample.is_infinite,
            u_primitive,
            u_position,
        }
    }
}

/// How a path of a splat event ends.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Terminal {
    /// Its last surface vertex lies on the emitter `light_index`, reached by
    /// BSDF sampling.
    Emission {
        /// The area light.
        light_index: u32,
    },
    /// Its last scattering escaped along `direction` to the environment.
    Environment {
        /// The escaping direction.
        direction: Vec3,
    },
    /// Next-event estimation from its last surface vertex.
    NextEvent(LightConnection),
}

/// One splat event of a seed path: the path made of the first
/// `vertex_count` surface vertices and `terminal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SplatEvent {
    /// Index in the seed's vertex list of this event's first vertex (0,
    /// except for the emission of an index-matched boundary passed on the
    /// way, whose path is stored as a copy after the seed's vertices).
    pub first_vertex: usize,
    /// Surface vertices of this event's path.
    pub vertex_count: usize,
    /// How it ends.
    pub terminal: Terminal,
}

impl SplatEvent {
    /// The event whose path is the seed's first `vertex_count` vertices
    /// (every event but an index-matched boundary's emission).
    pub fn of_first_vertices(vertex_count: usize, terminal: Terminal) -> Self {
        Self {
            first_vertex: 0,
            vertex_count,
            terminal,
        }
    }

    /// The event's vertices in the seed's vertex list.
    pub fn vertex_range(&self) -> std::ops::Range<usize> {
        self.first_vertex..self.first_vertex + self.vertex_count
    }

    /// How the event's path ends.
    pub fn kind(&self) -> EventKind {
        match self.terminal {
            Terminal::Emission { .. } => EventKind::Emission,
            Terminal::Environment { .. } => EventKind::Environment,
            Terminal::NextEvent(_) => EventKind::NextEvent,
        }
    }

    /// Index `k` of the path's last vertex in the paper's numbering
    /// (`x_0` the camera, `x_k` on the light).
    pub fn last_vertex(&self) -> usize {
        self.kind().last_vertex(self.vertex_count)
    }

    /// Number of surface vertices that scatter (the emitter of an emission
    /// event does not).
    pub fn scattering_count(&self) -> usize {
        self.kind().scattering_count(self.vertex_count)
    }

    /// Whether this path was made by next-event estimation.
    pub fn is_next_event(&self) -> bool {
        self.kind() == EventKind::NextEvent
    }
}

/// How a splat event's path ends, without the ending's data: what its
/// length in the paper's numbering depends on.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EventKind {
    /// An emitter reached by the last scattering (the last vertex is on it).
    Emission,
    /// The environment reached by the last scattering.
    Environment,
    /// A next-event connection from the last vertex.
    NextEvent,
}

impl EventKind {
    /// Index `k` of the last vertex of a path of `vertex_count` surface
    /// vertices ending so.
    pub fn last_vertex(self, vertex_count: usize) -> usize {
        match self {
            Self::Emission => vertex_count,
            Self::Environment | Self::NextEvent => vertex_count + 1,
        }
    }

    /// How many of `vertex_count` surface vertices scatter.
    pub fn scattering_count(self, vertex_count: usize) -> usize {
        match self {
            Self::Emission => vertex_count - 1,
            Self::Environment | Self::NextEvent => vertex_count,
        }
    }
}
