//! Analytic disks: the unit disk in the `z = 0` plane of object space (normal
//! `+z`, as Mitsuba's `disk`), placed by an arbitrary affine transform.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::sampling::coordinate_frame;
use super::{Bounds3, GeometryError, ShapeSample, SurfaceHit, Transform};
use crate::sampling::sample_uniform_disk_concentric_trigonometric;

/// The unit disk `x² + y² ≤ 1, z = 0` of object space mapped to world space by
/// `object_to_world` (any invertible affine transform: a non-uniform scale makes
/// an ellipse). Rays are intersected in object space, where the ray parameter is
/// unchanged because the direction is transformed linearly and not renormalised.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Disk {
    object_to_world: Transform,
    /// Unit world normal (`+z` of object space, via the inverse transpose).
    normal: Vec3,
    area: f32,
}

impl Disk {
    /// A disk placed by `object_to_world`.
    pub fn new(object_to_world: Transform) -> Result<Self, GeometryError> {
        let normal = object_to_world
            .normal(Vec3::Z)
            .try_normalize()
            .ok_or(GeometryError::NonFinite("disk normal"))?;
        // A linear map scales areas in the plane by |M x × M y|.
        let area = PI
            * object_to_world
                .vector(Vec3::X)
                .cross(object_to_world.vector(Vec3::Y))
                .length();
        if !(area > 0.0 && area.is_finite()) {
            return Err(GeometryError::NonPositiveLength {
                what: "disk area",
                value: area,
            });
        }
        Ok(Self {
            object_to_world,
            normal,
            area,
        })
    }

    /// The object-to-world transform.
    pub fn transform(&self) -> &Transform {
        &self.object_to_world
    }

    /// Unit world-space normal.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// Surface area.
    pub fn surface_area(&self) -> f32 {
        self.area
    }

    /// World bounds (of the transformed object-space square around the disk).
    pub fn bounds(&self) -> Bounds3 {
        Bounds3::from_points(
            [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                .map(|(x, y)| self.object_to_world.point(Vec3::new(x, y, 0.0))),
        )
    }

    /// The ray parameter in `(0, t_max)` of the hit, if any.
    #[inline]
    pub fn intersect_t(&self, origin: Vec3, direction: Vec3, t_max: f32) -> Option<f32> {
        let inverse = self.object_to_world.inverse_matrix();
        let local_origin = inverse.transform_point3(origin);
        let local_direction = inverse.transform_vector3(direction);
        if local_direction.z == 0.0 {
            return None;
        }
        let t = -local_origin.z / local_direction.z;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let local_x = local_origin.x + t * local_direction.x;
        let local_y = local_origin.y + t * local_direction.y;
        (local_x * local_x + local_y * local_y <= 1.0).then_some(t)
    }

    /// The hit record at ray parameter `t`. uv follows pbrt-v4: `u = φ/2π`,
    /// `v = 1 - r` (so `v = 1` at the centre).
    pub fn surface_hit(&self, origin: Vec3, direction: Vec3, t: f32, time: f32) -> SurfaceHit {
        let inverse = self.object_to_world.inverse_matrix();
        let local_origin = inverse.transform_point3(origin);
        let local_direction = inverse.transform_vector3(direction);
        // The hit lies exactly in the plane z = 0 of object space.
        let local = Vec3::new(
            local_origin.x + t * local_direction.x,
            local_origin.y + t * local_direction.y,
            0.0,
        );
        let point = self.object_to_world.point(local);
        let mut phi = local.y.atan2(local.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let radius = local.truncate().length();
        let uv = Vec2::new(phi / (2.0 * PI), 1.0 - radius);
        let mut dpdu =
            self.object_to_world
                .vector(Vec3::new(-2.0 * PI * local.y, 2.0 * PI * local.x, 0.0));
        if dpdu.length_squared() <= 1e-12 * self.area {
            dpdu = coordinate_frame(self.normal).0;
        }
        // ∂p/∂v for v = 1 − radius: towards the centre.
        let dpdv = if radius > 1e-6 {
            self.object_to_world
                .vector(Vec3::new(-local.x / radius, -local.y / radius, 0.0))
        } else {
            self.normal.cross(dpdu)
        };
        SurfaceHit {
            t,
            point,
            geometric_normal: self.normal,
            shading_normal: self.normal,
            uv,
            dpdu,
            dpdv,
            shape_index: 0,
            primitive_index: 0,
            time,
        }
    }

    /// A point uniformly distributed over the disk (concentric map of the object
    /// disk; an affine map has constant area scaling, so uniformity is kept).
    pub fn sample_area(&self, u: Vec2) -> ShapeSample {
        let local = sample_uniform_disk_concentric_trigonometric(u);
        ShapeSample {
            point: self.object_to_world.point(local.extend(0.0)),
            normal: self.normal,
            pdf_area: 1.0 / self.area,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn transformed_disk_hits() {
        let transform = Transform::translate(Vec3::new(0.0, 0.0, 3.0))
            * Transform::scale(Vec3::splat(2.0)).unwrap();
        let disk = Disk::new(transform).unwrap();
        assert_relative_eq!(disk.surface_area(), 4.0 * PI);
        assert_relative_eq!(
            disk.intersect_t(Vec3::new(1.9, 0.0, 0.0), Vec3::Z, 10.0)
                .unwrap(),
            3.0
        );
        assert!(
            disk.intersect_t(Vec3::new(2.1, 0.0, 0.0), Vec3::Z, 10.0)
                .is_none()
        );
        let hit = disk.surface_hit(Vec3::new(1.0, 0.0, 0.0), Vec3::Z, 3.0, 0.0);
        assert_relative_eq!(hit.uv.y, 0.5);
        assert_eq!(hit.geometric_normal, Vec3::Z);
    }
}
