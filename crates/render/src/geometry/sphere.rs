//! Analytic spheres: intersection with a numerically careful quadratic, uniform
//! area sampling and solid-angle (cone) sampling from outside.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::sampling::coordinate_frame;
use super::{Bounds3, GeometryError, ShapeSample, SurfaceHit, Transform};
use crate::sampling::sample_uniform_sphere;

/// `sin²(1.5°)`: below this `sin²θmax` the cone sampling switches to the
/// small-angle formulation (threshold from pbrt-v4, `Sphere::Sample`).
const SMALL_CONE_SIN2_THRESHOLD: f32 = 0.00068523;

/// A full sphere given by its world-space centre and radius.
///
/// A sphere may be placed with a transform, but only a translation combined with
/// a uniform positive scale is accepted ([`Sphere::from_transform`]): these keep
/// it a sphere with an axis-aligned parameterisation, so no per-hit transforms
/// are needed. Rotations (which would only rotate the uv parameterisation),
/// non-uniform scales (ellipsoids) and mirroring are rejected.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    center: Vec3,
    radius: f32,
}

impl Sphere {
    /// A sphere of `radius > 0` around `center`.
    pub fn new(center: Vec3, radius: f32) -> Result<Self, GeometryError> {
        if !center.is_finite() {
            return Err(GeometryError::NonFinite("sphere centre"));
        }
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(GeometryError::NonPositiveLength {
                what: "sphere radius",
                value: radius,
            });
        }
        Ok(Self { center, radius })
    }

    /// The object-space sphere of `radius` around the origin placed by
    /// `object_to_world`, which must be a translation and uniform scale.
    pub fn from_transform(radius: f32, object_to_world: &Transform) -> Result<Self, GeometryError> {
        let (translation, scale) = object_to_world
            .as_translation_uniform_scale()
            .ok_or(GeometryError::SphereTransformNotSimilarity)?;
        Self::new(translation, radius * scale)
    }

    /// Centre.
    pub fn center(&self) -> Vec3 {
        self.center
    }

    /// Radius.
    pub fn radius(&self) -> f32 {
        self.radius
    }

    /// Surface area `4πr²`.
    pub fn surface_area(&self) -> f32 {
        4.0 * PI * self.radius * self.radius
    }

    /// World bounds.
    pub fn bounds(&self) -> Bounds3 {
        Bounds3::new(
            self.center - Vec3::splat(self.radius),
            self.center + Vec3::splat(self.radius),
        )
    }

    /// The smallest ray parameter in `(0, t_max)` where the ray meets the sphere.
    ///
    /// Follows Haines, Günther & Akenine-Möller, "Precision Improvements for
    /// Ray/Sphere Intersection" (Ray Tracing Gems, 2019, ch. 7): the
    /// discriminant is computed from the squared distance between the centre and
    /// the ray's line (no cancellation of two large squares), and the two roots
    /// from the stable form `q = -(b + sign(b)·√Δ)`, `t0 = q/a`, `t1 = c/q`
    /// (with `b` the half coefficient), so neither root suffers cancellation.
    #[inline]
    pub fn intersect_t(&self, origin: Vec3, direction: Vec3, t_max: f32) -> Option<f32> {
        let to_origin = origin - self.center;
        let a = direction.length_squared();
        let half_b = to_origin.dot(direction);
        let distance = to_origin.length();
        let c = (distance - self.radius) * (distance + self.radius);
        // Vector from the centre to the closest point of the line.
        let closest = to_origin - (half_b / a) * direction;
        let line_distance = closest.length();
        let quarter_discriminant =
            a * (self.radius - line_distance) * (self.radius + line_distance);
        if quarter_discriminant < 0.0 || a == 0.0 {
            return None;
        }
        let root = quarter_discriminant.sqrt();
        let q = -(half_b + root.copysign(half_b));
        let (mut t0, mut t1) = if q == 0.0 { (0.0, 0.0) } else { (q / a, c / q) };
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        if t0 > 0.0 && t0 < t_max {
            Some(t0)
        } else if t1 > 0.0 && t1 < t_max {
            Some(t1)
        } else {
            None
        }
    }

    /// The hit record at ray parameter `t` (shape and primitive index 0).
    pub fn surface_hit(&self, origin: Vec3, direction: Vec3, t: f32, time: f32) -> SurfaceHit {
        let offset = origin + t * direction - self.center;
        // Reproject onto the surface to remove the error of origin + t·direction.
        let local = offset * (self.radius / offset.length());
        let normal = local / self.radius;
        let point = self.center + local;
        // pbrt-v4's parameterisation: u = φ/2π, v = (π - θ)/π (v = 1 at +z).
        let mut phi = normal.y.atan2(normal.x);
        if phi < 0.0 {
            phi += 2.0 * PI;
        }
        let theta = normal.z.clamp(-1.0, 1.0).acos();
        let uv = Vec2::new(phi / (2.0 * PI), (PI - theta) / PI);
        let mut dpdu = Vec3::new(-2.0 * PI * local.y, 2.0 * PI * local.x, 0.0);
        if dpdu.length_squared() <= 1e-12 * self.radius * self.radius {
            dpdu = coordinate_frame(normal).0;
        }
        // ∂p/∂v = π (−z cos φ, −z sin φ, r sin θ) for v = (π − θ)/π.
        let rho = local.truncate().length();
        let dpdv = if rho > 1e-6 * self.radius {
            PI * Vec3::new(-local.z * local.x / rho, -local.z * local.y / rho, rho)
        } else {
            normal.cross(dpdu)
        };
        SurfaceHit {
            t,
            point,
            geometric_normal: normal,
            shading_normal: normal,
            uv,
            dpdu,
            dpdv,
            shape_index: 0,
            primitive_index: 0,
            time,
        }
    }

    /// A point uniformly distributed over the surface (density `1/(4πr²)`).
    pub fn sample_area(&self, u: Vec2) -> ShapeSample {
        let normal = sample_uniform_sphere(u);
        ShapeSample {
            point: self.center + self.radius * normal,
            normal,
            pdf_area: 1.0 / self.surface_area(),
        }
    }

    /// `(sin²θmax, 1 - cosθmax)` of the cone subtended from `reference` (outside),
    /// with the small-angle form `1 - cosθmax ≈ sin²θmax / 2` for tiny cones.
    fn cone(&self, reference: Vec3) -> (f32, f32) {
        let sin2_theta_max = self.radius * self.radius / reference.distance_squared(self.center);
        let one_minus_cos = if sin2_theta_max < SMALL_CONE_SIN2_THRESHOLD {
            0.5 * sin2_theta_max
        } else {
            1.0 - (1.0 - sin2_theta_max).max(0.0).sqrt()
        };
        (sin2_theta_max, one_minus_cos)
    }

    /// Whether `reference` is inside (or on) the sphere.
    fn contains(&self, reference: Vec3) -> bool {
        reference.distance_squared(self.center) <= self.radius * self.radius
    }

    /// The subtended solid angle `2π(1 - cosθmax)` from a point outside (`4π` inside).
    pub fn solid_angle(&self, reference: Vec3) -> f32 {
        if self.contains(reference) {
            4.0 * PI
        } else {
            2.0 * PI * self.cone(reference).1
        }
    }

    /// A point on the sphere sampled for lighting `reference`.
    ///
    /// From outside, the direction is uniform within the cone of directions the
    /// sphere subtends (pbrt-v4's approach): `cosθ` is uniform in
    /// `[cosθmax, 1]` (for `sin²θmax < sin²1.5°`, `sin²θ` uniform in
    /// `[0, sin²θmax]`, avoiding the cancellation in `1 - cosθ`), and the point on
    /// the sphere is found directly from the angle `α` at the centre,
    /// `cosα = sin²θ/sinθmax + cosθ·√(1 - sin²θ/sin²θmax)` (law of cosines), so
    /// no ray–sphere intersection is needed. Only the visible cap is sampled.
    /// The returned `pdf_area` is the solid-angle density `1/(2π(1-cosθmax))`
    /// converted to area; [`Sphere::pdf_solid_angle_from`] gives it directly.
    ///
    /// From inside, the point is uniform over the area.
    pub fn sample_from(&self, reference: Vec3, u: Vec2) -> ShapeSample {
        if self.contains(reference) {
            return self.sample_area(u);
        }
        let (sin2_theta_max, one_minus_cos_theta_max) = self.cone(reference);
        let sin_theta_max = sin2_theta_max.sqrt();
        let (sin2_theta, cos_theta) = if sin2_theta_max < SMALL_CONE_SIN2_THRESHOLD {
            let sin2 = sin2_theta_max * u.x;
            (sin2, (1.0 - sin2).sqrt())
        } else {
            let cos = 1.0 - one_minus_cos_theta_max * u.x;
            ((1.0 - cos * cos).max(0.0), cos)
        };
        let cos_alpha = sin2_theta / sin_theta_max
            + cos_theta * (1.0 - sin2_theta / sin2_theta_max).max(0.0).sqrt();
        let sin_alpha = (1.0 - cos_alpha * cos_alpha).max(0.0).sqrt();
        let phi = 2.0 * PI * u.y;
        let axis = (self.center - reference).normalize();
        let (s, t) = coordinate_frame(axis);
        // The normal points back towards the reference side of the sphere.
        let normal = -(sin_alpha * phi.cos() * s + sin_alpha * phi.sin() * t + cos_alpha * axis);
        let point = self.center + self.radius * normal;
        let pdf_solid_angle = 1.0 / (2.0 * PI * one_minus_cos_theta_max);
        let to_reference = reference - point;
        let distance_squared = to_reference.length_squared();
        let cosine = normal.dot(to_reference).abs() / distance_squared.sqrt();
        ShapeSample {
            point,
            normal,
            pdf_area: pdf_solid_angle * cosine / distance_squared,
        }
    }

    /// The solid-angle density of [`Sphere::sample_from`] for the direction from
    /// `reference` to `point` (a point on the sphere with unit `normal`):
    /// `1/(2π(1-cosθmax))` from outside, the converted area density from inside.
    pub fn pdf_solid_angle_from(&self, reference: Vec3, point: Vec3, normal: Vec3) -> f32 {
        if self.contains(reference) {
            super::area_pdf_to_solid_angle(1.0 / self.surface_area(), reference, point, normal)
        } else {
            1.0 / (2.0 * PI * self.cone(reference).1)
        }
    }

    /// The area density of [`Sphere::sample_from`] at `point` (unit `normal`).
    pub fn pdf_area_from(&self, reference: Vec3, point: Vec3, normal: Vec3) -> f32 {
        if self.contains(reference) {
            return 1.0 / self.surface_area();
        }
        let to_reference = reference - point;
        let distance_squared = to_reference.length_squared();
        let cosine = normal.dot(to_reference) / distance_squared.sqrt();
        if cosine <= 0.0 {
            return 0.0; // the far side is never sampled
        }
        self.pdf_solid_angle_from(reference, point, normal) * cosine / distance_squared
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_relative_eq;

    #[test]
    fn analytic_hits() {
        let sphere = Sphere::new(Vec3::new(0.0, 0.0, 5.0), 2.0).unwrap();
        assert_relative_eq!(
            sphere
                .intersect_t(Vec3::ZERO, Vec3::Z, f32::INFINITY)
                .unwrap(),
            3.0
        );
        assert_relative_eq!(
            sphere
                .intersect_t(Vec3::new(0.0, 0.0, 5.0), Vec3::Z, f32::INFINITY)
                .unwrap(),
            2.0
        );
        assert!(
            sphere
                .intersect_t(Vec3::ZERO, -Vec3::Z, f32::INFINITY)
                .is_none()
        );
        assert!(
            sphere
                .intersect_t(Vec3::new(2.1, 0.0, 0.0), Vec3::Z, f32::INFINITY)
                .is_none()
        );
        assert!(sphere.intersect_t(Vec3::ZERO, Vec3::Z, 2.9).is_none());
        assert!(Sphere::new(Vec3::ZERO, 0.0).is_err());
        assert!(
            Sphere::from_transform(1.0, &Transform::scale(Vec3::new(1.0, 2.0, 1.0)).unwrap())
                .is_err()
        );
    }
}
