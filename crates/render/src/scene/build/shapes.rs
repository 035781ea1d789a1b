//! Render-time shapes from the scene description's [`ShapeGeometry`]:
//! meshes (given, or the unit rectangle and cube placed by a transform),
//! spheres and disks, each checked by its constructor.

use glam::{Affine3A, Mat4};

use crate::geometry::{Disk, GeometryError, Shape, Sphere, Transform, TriangleMesh};
use crate::scene::SceneError;
use crate::scene::description::ShapeGeometry;

/// The shape of `geometry`; `index` (the shape's place in the description)
/// names it in errors.
pub(in crate::scene) fn shape(geometry: &ShapeGeometry, index: usize) -> Result<Shape, SceneError> {
    let geometry_error = |source: GeometryError| SceneError::Geometry { index, source };
    Ok(match geometry {
        ShapeGeometry::Mesh {
            positions,
            normals,
            uvs,
            triangles,
        } => Shape::Mesh(
            TriangleMesh::new(
                positions.clone(),
                normals.clone(),
                uvs.clone(),
                triangles.clone(),
                &transform(Affine3A::IDENTITY, index)?,
            )
            .map_err(geometry_error)?,
        ),
        ShapeGeometry::Sphere { center, radius } => {
            Shape::Sphere(Sphere::new(*center, *radius).map_err(geometry_error)?)
        }
        ShapeGeometry::Rectangle { to_world } => Shape::Mesh(
            TriangleMesh::rectangle(&transform(*to_world, index)?).map_err(geometry_error)?,
        ),
        ShapeGeometry::Cube { to_world } => {
            Shape::Mesh(TriangleMesh::cube(&transform(*to_world, index)?).map_err(geometry_error)?)
        }
        ShapeGeometry::Disk { to_world } => {
            Shape::Disk(Disk::new(transform(*to_world, index)?).map_err(geometry_error)?)
        }
    })
}

/// The transform of shape `index`, or its geometry error if `matrix` is
/// not invertible.
fn transform(matrix: Affine3A, index: usize) -> Result<Transform, SceneError> {
    Transform::from_matrix(Mat4::from(matrix))
        .map_err(|source| SceneError::Geometry { index, source })
}
