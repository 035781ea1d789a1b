//! The renderer's geometry layer: rays, bounds, affine transforms, shapes
//! (triangle meshes, spheres, disks, and Mitsuba-style rectangles and cubes built
//! as meshes), their ray intersection routines, robust spawning of secondary rays,
//! uniform and solid-angle sampling of shapes for area lights, and the
//! [`Geometry`] aggregate that owns all shapes and an 8-wide BVH (built with
//! obvhs' PLOC, traversed by this crate with SIMD box and triangle tests) for
//! closest-hit and any-hit queries.
//!
//! Geometry is single precision (`f32`, glam `Vec3`). pbrt-v4 is the model for
//! conventions: intersection routines are written to be watertight (triangles) or
//! numerically careful (spheres), and secondary rays are offset from surfaces with
//! the method of Wächter & Binder (Ray Tracing Gems, 2019, ch. 6).
//!
//! Conventions shared by all modules:
//! * ray directions passed to [`Geometry::intersect`] and [`Geometry::occluded`]
//!   should be normalised (`t` is then a distance in scene units, as the
//!   shadow-ray and offset conventions assume);
//! * geometric normals face "as authored": the counter-clockwise winding side of a
//!   triangle, the outside of a sphere, `+z` of a disk in its object space;
//! * every BVH primitive remembers the `shape_index` (position in the list given to
//!   [`Geometry::new`]) and `primitive_index` (triangle index within a mesh, 0 for
//!   analytic shapes) so the scene can map hits back to materials and emitters.

mod accelerator;
mod bounds;
mod bvh_memory;
mod disk;
mod error;
mod hit;
mod mesh;
pub mod procedural;
mod ray;
mod sampling;
mod shape;
mod simd;
mod spawn;
mod sphere;
mod transform;
mod triangle;
mod triangle_packet;
mod wide_bvh;

/// Re-exported for the callers that sample shapes and directions together.
pub use crate::sampling::sample_uniform_sphere;
pub use accelerator::{
    AcceleratorOptions, AcceleratorStatistics, Geometry, PrimitiveHit, PrimitiveReference,
    TriangleLeafLayout,
};
pub use bounds::Bounds3;
pub use disk::Disk;
pub use error::GeometryError;
pub use hit::SurfaceHit;
pub use mesh::TriangleMesh;
pub use ray::Ray;
pub use sampling::{
    AliasTable, ShapeSample, area_pdf_to_solid_angle, coordinate_frame, sample_uniform_triangle,
};
pub use shape::Shape;
#[cfg(target_arch = "x86_64")]
pub(crate) use simd::Avx2;
pub use spawn::{
    OffsetPoint, SHADOW_EPSILON, occlusion_segment_to_point, offset_ray_origin, spawn_ray,
    spawn_ray_through, spawn_ray_to, spawn_ray_to_point, spawn_segment_to_point,
};
pub use sphere::Sphere;
pub use transform::Transform;
pub use triangle::{TriangleIntersection, intersect_triangle};
