//! The record of one vertex of a traced path: what an integrator needs to
//! rebuild a prefix of the path from new numbers and reconnect it to a kept
//! suffix (Metropolis light transport, LQMC), or to compute MIS weights of
//! other techniques (bidirectional methods).

use crate::material::BsdfFlags;
use glam::Vec3;

/// One scattering vertex of a camera path.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PathVertex {
    /// Position.
    pub point: Vec3,
    /// Geometric normal (as stored in the geometry).
    pub geometric_normal: Vec3,
    /// Shading normal.
    pub shading_normal: Vec3,
    /// The shape hit.
    pub shape_index: u32,
    /// The triangle hit, for meshes.
    pub primitive_index: u32,
    /// Direction towards the previous vertex.
    pub wo: Vec3,
    /// Direction towards the next vertex (zero at the last vertex).
    pub wi: Vec3,
    /// The BSDF's lobes at this vertex.
    pub flags: BsdfFlags,
    /// The sampled scattering's flags (specular, transmission, ...); empty
    /// at the last vertex.
    pub sampled: BsdfFlags,
    /// Solid-angle density of sampling `wi` from `wo`.
    pub pdf_forward: f32,
    /// Solid-angle density of sampling `wo` from `wi` (the reverse
    /// direction, as bidirectional MIS needs).
    pub pdf_reverse: f32,
    /// The first primary-sample-space dimension of this vertex's block.
    pub first_dimension: usize,
}
