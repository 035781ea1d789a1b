//! Watertight ray–triangle intersection after Woop, Benthin & Wald, "Watertight
//! Ray/Triangle Intersection", JCGT 2(1), 2013.
//!
//! The ray is transformed (a permutation, a shear and a scale) so that it starts
//! at the origin and points along `+z`; the triangle's vertices get the same
//! transform and the hit test becomes a 2-D point-in-triangle test at the origin
//! using edge functions. Because the transformed vertex coordinates depend only on
//! the vertex and the ray, an edge shared by two triangles yields exactly negated
//! edge functions in both, so a ray cannot slip between them. When an edge
//! function evaluates to exactly zero in single precision it is recomputed in
//! double precision (as the paper recommends), so rays through edges and vertices
//! are classified consistently.

use glam::Vec3;

/// The result of a ray–triangle test: the ray parameter and the barycentric
/// weights of the three vertices (`b0 + b1 + b2 = 1`, the hit point is
/// `b0 p0 + b1 p1 + b2 p2`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleIntersection {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Barycentric weights of vertices 0, 1, 2.
    pub barycentric: [f32; 3],
}

/// Precomputed per-ray data for the watertight test (the axis permutation and
/// shear), shared by all triangles tested against one ray.
#[derive(Clone, Copy, Debug)]
pub(crate) struct WatertightRay {
    pub(super) origin: Vec3,
    /// Axes: `kx`, `ky` (the 2-D test plane) and `kz` (the dominant direction axis).
    pub(super) axes: [usize; 3],
    pub(super) shear_x: f32,
    pub(super) shear_y: f32,
    pub(super) shear_z: f32,
}

impl WatertightRay {
    /// Prepares a ray (`direction` must be non-zero).
    #[inline]
    pub(crate) fn new(origin: Vec3, direction: Vec3) -> Self {
        let abs = direction.abs();
        // The dominant axis `kz`, with `kx = (kz + 1) % 3` and
        // `ky = (kx + 1) % 3` chosen in the same branches: constants the
        // compiler knows to be below 3 (a lookup table indexed by `kz` was
        // written to the stack for every ray, and its entries then
        // bounds-checked).
        let (mut kx, mut ky, kz) = if abs.x > abs.y {
            if abs.x > abs.z { (1, 2, 0) } else { (0, 1, 2) }
        } else if abs.y > abs.z {
            (2, 0, 1)
        } else {
            (0, 1, 2)
        };
        // Swapping kx and ky when the dominant component is negative keeps the
        // winding (and so the sign of the determinant) consistent.
        // Array indexing: `Vec3`'s `Index` is a bounds-checked `match`.
        let d = direction.to_array();
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        Self {
            origin,
            axes: [kx, ky, kz],
            shear_x: d[kx] / d[kz],
            shear_y: d[ky] / d[kz],
            shear_z: 1.0 / d[kz],
        }
    }

    /// Tests the triangle `(p0, p1, p2)` for a hit with `0 < t < t_max`.
    #[inline]
    pub(crate) fn intersect(
        &self,
        p0: Vec3,
        p1: Vec3,
        p2: Vec3,
        t_max: f32,
    ) -> Option<TriangleIntersection> {
        let [kx, ky, kz] = self.axes;
        let a = p0 - self.origin;
        let b = p1 - self.origin;
        let c = p2 - self.origin;
        // Shear so that the ray becomes the +z axis.
        let ax = a[kx] - self.shear_x * a[kz];
        let ay = a[ky] - self.shear_y * a[kz];
        let bx = b[kx] - self.shear_x * b[kz];
        let by = b[ky] - self.shear_y * b[kz];
        let cx = c[kx] - self.shear_x * c[kz];
        let cy = c[ky] - self.shear_y * c[kz];
        // Scaled barycentric coordinates: edge functions of the edges opposite
        // each vertex, evaluated at the origin.
        let mut u = cx * by - cy * bx;
        let mut v = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        if u == 0.0 || v == 0.0 || w == 0.0 {
            let (ax, ay, bx, by, cx, cy) = (
                ax as f64, ay as f64, bx as f64, by as f64, cx as f64, cy as f64,
            );
            u = (cx * by - cy * bx) as f32;
            v = (ax * cy - ay * cx) as f32;
            w = (bx * ay - by * ax) as f32;
        }
        // Both faces are hit: the origin must be on the same side of all edges.
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let determinant = u + v + w;
        if determinant == 0.0 {
            return None;
        }
        let az = self.shear_z * a[kz];
        let bz = self.shear_z * b[kz];
        let cz = self.shear_z * c[kz];
        let scaled_t = u * az + v * bz + w * cz;
        // Compare t with the range without dividing: flip signs so the
        // determinant is positive, then require 0 < T < t_max * det.
        let (scaled_t, determinant_abs) = if determinant < 0.0 {
            (-scaled_t, -determinant)
        } else {
            (scaled_t, determinant)
        };
        if scaled_t <= 0.0 || scaled_t >= t_max * determinant_abs {
            return None;
        }
        let reciprocal = 1.0 / determinant;
        let t = scaled_t / determinant_abs;
        Some(TriangleIntersection {
            t,
            barycentric: [u * reciprocal, v * reciprocal, w * reciprocal],
        })
    }
}

/// Watertight intersection of a ray with the triangle `(p0, p1, p2)`, reporting
/// hits with `0 < t < t_max` from either side. Degenerate triangles never hit.
pub fn intersect_triangle(
    origin: Vec3,
    direction: Vec3,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
    t_max: f32,
) -> Option<TriangleIntersection> {
    if direction == Vec3::ZERO {
        return None;
    }
    WatertightRay::new(origin, direction).intersect(p0, p1, p2, t_max)
}

#[cfg(test)]
mod tests {
    use super::*;
    use approx::assert_abs_diff_eq;

    #[test]
    fn hits_inside_misses_outside() {
        let (p0, p1, p2) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        let hit = intersect_triangle(
            Vec3::new(0.25, 0.25, 2.0),
            -Vec3::Z,
            p0,
            p1,
            p2,
            f32::INFINITY,
        )
        .unwrap();
        assert_abs_diff_eq!(hit.t, 2.0, epsilon = 1e-6);
        assert_abs_diff_eq!(hit.barycentric[0], 0.5, epsilon = 1e-6);
        assert_abs_diff_eq!(hit.barycentric[1], 0.25, epsilon = 1e-6);
        assert_abs_diff_eq!(hit.barycentric[2], 0.25, epsilon = 1e-6);
        // From behind too.
        assert!(
            intersect_triangle(
                Vec3::new(0.25, 0.25, -2.0),
                Vec3::Z,
                p0,
                p1,
                p2,
                f32::INFINITY
            )
            .is_some()
        );
        // Outside, behind the origin, beyond t_max.
        assert!(
            intersect_triangle(
                Vec3::new(0.75, 0.75, 2.0),
                -Vec3::Z,
                p0,
                p1,
                p2,
                f32::INFINITY
            )
            .is_none()
        );
        assert!(
            intersect_triangle(
                Vec3::new(0.25, 0.25, 2.0),
                Vec3::Z,
                p0,
                p1,
                p2,
                f32::INFINITY
            )
            .is_none()
        );
        assert!(
            intersect_triangle(Vec3::new(0.25, 0.25, 2.0), -Vec3::Z, p0, p1, p2, 1.5).is_none()
        );
    }
}
