//! The record of a ray hitting a surface.

use glam::{Vec2, Vec3};

/// Everything shading needs about a ray–surface hit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceHit {
    /// Ray parameter of the hit (distance when the ray direction is unit length).
    pub t: f32,
    /// World-space hit point. For triangles it is interpolated from the vertices
    /// (not `origin + t·direction`) and for spheres reprojected onto the surface,
    /// which keeps its error small enough for [`super::offset_ray_origin`].
    pub point: Vec3,
    /// Unit geometric normal facing as authored: the side from which the
    /// triangle's vertices appear counter-clockwise, outward for spheres, the
    /// transformed `+z` of a disk. Not flipped towards the ray.
    pub geometric_normal: Vec3,
    /// Unit shading normal: interpolated vertex normals for meshes that have
    /// them (flipped if necessary into the hemisphere of the geometric normal),
    /// otherwise the geometric normal.
    pub shading_normal: Vec3,
    /// Surface parameterisation: the mesh's uvs (default `(0,0), (1,0), (1,1)` per
    /// triangle as pbrt), or pbrt's `(φ/2π, …)` parameterisations of spheres and disks.
    pub uv: Vec2,
    /// `∂p/∂u`, a non-zero tangent of the surface (not normalised, not
    /// necessarily perpendicular to the shading normal); where the
    /// parameterisation is degenerate (poles, disk centre, degenerate uvs) an
    /// arbitrary tangent perpendicular to the geometric normal.
    pub dpdu: Vec3,
    /// `∂p/∂v` (not normalised; bump mapping needs both derivatives); where
    /// the parameterisation is degenerate, the geometric normal × `dpdu`.
    pub dpdv: Vec3,
    /// Index of the shape in the list the [`super::Geometry`] was built from.
    pub shape_index: u32,
    /// Triangle index within a mesh; 0 for spheres and disks.
    pub primitive_index: u32,
    /// Time of the ray that produced the hit (carried to spawned rays).
    pub time: f32,
}
