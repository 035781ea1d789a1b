//! Affine transforms stored with their inverse (pbrt-v4's `Transform`).

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::{GeometryError, Ray};

/// An affine transform together with its inverse, so points, vectors, normals
/// (which transform by the inverse transpose) and rays can be mapped both ways
/// without re-inverting. Composition follows matrix order: `(a * b)` applies `b`
/// first.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    matrix: Mat4,
    inverse: Mat4,
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl std::ops::Mul for Transform {
    type Output = Transform;
    fn mul(self, rhs: Transform) -> Transform {
        Transform {
            matrix: self.matrix * rhs.matrix,
            inverse: rhs.inverse * self.inverse,
        }
    }
}

impl Transform {
    /// The identity.
    pub const IDENTITY: Self = Self {
        matrix: Mat4::IDENTITY,
        inverse: Mat4::IDENTITY,
    };

    /// A transform from an affine matrix (glam column-major; the last row must be
    /// `0 0 0 1`). Fails if the matrix is not affine, not finite or singular.
    pub fn from_matrix(matrix: Mat4) -> Result<Self, GeometryError> {
        if !matrix.is_finite() {
            return Err(GeometryError::NonFinite("transform matrix"));
        }
        if matrix.row(3) != Vec4::new(0.0, 0.0, 0.0, 1.0) {
            return Err(GeometryError::NotAffine);
        }
        let determinant = Mat3::from_mat4(matrix).determinant();
        if determinant == 0.0 || !determinant.is_finite() {
            return Err(GeometryError::SingularTransform(format!(
                "determinant {determinant}"
            )));
        }
        let inverse = matrix.inverse();
        if !inverse.is_finite() {
            return Err(GeometryError::SingularTransform(
                "inverse not finite".into(),
            ));
        }
        Ok(Self { matrix, inverse })
    }

    /// Translation by `offset`.
    pub fn translate(offset: Vec3) -> Self {
        Self {
            matrix: Mat4::from_translation(offset),
            inverse: Mat4::from_translation(-offset),
        }
    }

    /// Axis-aligned scale; fails if a factor is zero or not finite.
    pub fn scale(factors: Vec3) -> Result<Self, GeometryError> {
        if !factors.is_finite() {
            return Err(GeometryError::NonFinite("scale factors"));
        }
        if factors.cmpeq(Vec3::ZERO).any() {
            return Err(GeometryError::SingularTransform(format!(
                "zero scale factor {factors}"
            )));
        }
        Ok(Self {
            matrix: Mat4::from_scale(factors),
            inverse: Mat4::from_scale(factors.recip()),
        })
    }

    /// Rotation by `angle_degrees` counter-clockwise about `axis` (right-handed,
    /// as pbrt's `Rotate`); fails for a zero or non-finite axis.
    pub fn rotate(angle_degrees: f32, axis: Vec3) -> Result<Self, GeometryError> {
        let axis = axis
            .try_normalize()
            .ok_or(GeometryError::NonFinite("rotation axis"))?;
        if !angle_degrees.is_finite() {
            return Err(GeometryError::NonFinite("rotation angle"));
        }
        let matrix = Mat4::from_axis_angle(axis, angle_degrees.to_radians());
        Ok(Self {
            matrix,
            inverse: matrix.transpose(),
        })
    }

    /// The camera-to-world transform of a camera at `eye` looking at `target`
    /// with `up` roughly up: camera space has the camera at the origin looking
    /// down `+z`, with `+y` up and `+x = up × forward` (the frame of pbrt-v4's
    /// `LookAt`, whose result is the inverse of this, and of Mitsuba's
    /// `look_at`). Fails if `eye == target` or `up` is parallel to the view.
    pub fn look_at(eye: Vec3, target: Vec3, up: Vec3) -> Result<Self, GeometryError> {
        if !(eye.is_finite() && target.is_finite() && up.is_finite()) {
            return Err(GeometryError::NonFinite("look_at arguments"));
        }
        let forward = (target - eye)
            .try_normalize()
            .ok_or_else(|| GeometryError::SingularTransform("look_at: eye equals target".into()))?;
        let side = up
            .try_normalize()
            .and_then(|u| u.cross(forward).try_normalize())
            .ok_or_else(|| {
                GeometryError::SingularTransform("look_at: up parallel to view direction".into())
            })?;
        let true_up = forward.cross(side);
        let matrix = Mat4::from_cols(
            side.extend(0.0),
            true_up.extend(0.0),
            forward.extend(0.0),
            eye.extend(1.0),
        );
        // The linear part is orthonormal: its inverse is its transpose.
        let rotation_inverse = Mat3::from_cols(side, true_up, forward).transpose();
        let inverse = Mat4::from_mat3(rotation_inverse) * Mat4::from_translation(-eye);
        Ok(Self { matrix, inverse })
    }

    /// The forward matrix.
    pub fn matrix(&self) -> Mat4 {
        self.matrix
    }

    /// The inverse matrix.
    pub fn inverse_matrix(&self) -> Mat4 {
        self.inverse
    }

    /// The inverse transform.
    pub fn inverse(&self) -> Self {
        Self {
            matrix: self.inverse,
            inverse: self.matrix,
        }
    }

    /// Maps a point (affected by translation).
    pub fn point(&self, p: Vec3) -> Vec3 {
        self.matrix.transform_point3(p)
    }

    /// Maps a direction vector (ignores translation).
    pub fn vector(&self, v: Vec3) -> Vec3 {
        self.matrix.transform_vector3(v)
    }

    /// Maps a surface normal by the inverse transpose, so it stays perpendicular
    /// to transformed tangents. The result is not renormalised.
    pub fn normal(&self, n: Vec3) -> Vec3 {
        Mat3::from_mat4(self.inverse).transpose() * n
    }

    /// Maps a ray; its parameter `t` is preserved (the direction is not renormalised).
    pub fn ray(&self, ray: &Ray) -> Ray {
        Ray {
            origin: self.point(ray.origin),
            direction: self.vector(ray.direction),
            time: ray.time,
        }
    }

    /// Whether the linear part flips orientation (negative determinant), which
    /// reverses triangle winding.
    pub fn swaps_handedness(&self) -> bool {
        Mat3::from_mat4(self.matrix).determinant() < 0.0
    }

    /// If this is a translation followed by a uniform positive scale (no rotation,
    /// shear or mirroring, to a relative tolerance of 1e-5), returns
    /// `(translation, scale)`.
    pub fn as_translation_uniform_scale(&self) -> Option<(Vec3, f32)> {
        let linear = Mat3::from_mat4(self.matrix);
        let scale = linear.x_axis.x;
        if scale.is_nan() || scale <= 0.0 {
            return None;
        }
        let difference = linear - Mat3::from_diagonal(Vec3::splat(scale));
        let tolerance = 1e-5 * scale;
        let within = [difference.x_axis, difference.y_axis, difference.z_axis]
            .iter()
            .all(|column| column.abs().max_element() <= tolerance);
        within.then(|| (self.matrix.w_axis.truncate(), scale))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    #[test]
    fn inverse_roundtrip_and_normals() {
        let t = Transform::translate(Vec3::new(1.0, 2.0, 3.0))
            * Transform::rotate(30.0, Vec3::new(1.0, 1.0, 0.0)).unwrap()
            * Transform::scale(Vec3::new(2.0, 0.5, 3.0)).unwrap();
        let p = Vec3::new(0.3, -0.7, 1.1);
        let back = t.inverse().point(t.point(p));
        assert_abs_diff_eq!(back.x, p.x, epsilon = 1e-5);
        assert_abs_diff_eq!(back.y, p.y, epsilon = 1e-5);
        assert_abs_diff_eq!(back.z, p.z, epsilon = 1e-5);
        // A normal stays perpendicular to transformed tangents.
        let n = Vec3::new(0.0, 0.0, 1.0);
        let tangent = Vec3::new(1.0, 1.0, 0.0);
        assert_abs_diff_eq!(t.normal(n).dot(t.vector(tangent)), 0.0, epsilon = 1e-5);
    }

    #[test]
    fn look_at_maps_forward_to_target() {
        let t = Transform::look_at(Vec3::new(1.0, 2.0, 3.0), Vec3::new(1.0, 2.0, -7.0), Vec3::Y)
            .unwrap();
        let forward = t.vector(Vec3::Z);
        assert_abs_diff_eq!(forward.z, -1.0, epsilon = 1e-6);
        assert_abs_diff_eq!(t.point(Vec3::ZERO).x, 1.0, epsilon = 1e-6);
        assert_abs_diff_eq!(t.vector(Vec3::Y).y, 1.0, epsilon = 1e-6);
        let identity = t.matrix() * t.inverse_matrix();
        assert!(identity.abs_diff_eq(Mat4::IDENTITY, 1e-5));
        assert!(Transform::look_at(Vec3::ZERO, Vec3::Y, Vec3::Y).is_err());
    }

    #[test]
    fn rejects_bad_matrices() {
        assert!(Transform::scale(Vec3::new(1.0, 0.0, 1.0)).is_err());
        let mut projective = Mat4::IDENTITY;
        projective.x_axis.w = 1.0;
        assert_eq!(
            Transform::from_matrix(projective),
            Err(GeometryError::NotAffine)
        );
        let t = Transform::translate(Vec3::ONE) * Transform::scale(Vec3::splat(2.0)).unwrap();
        assert_eq!(t.as_translation_uniform_scale(), Some((Vec3::ONE, 2.0)));
        assert!(
            Transform::rotate(10.0, Vec3::Z)
                .unwrap()
                .as_translation_uniform_scale()
                .is_none()
        );
    }
}
