//! Spawning secondary rays from surfaces without self-intersection, after
//! Wächter & Binder, "A Fast and Robust Method for Avoiding Self-Intersection",
//! Ray Tracing Gems (2019), chapter 6.
//!
//! A computed hit point is off the true surface by a few units in the last place
//! (ULPs) of its coordinates. The method moves the origin along the geometric
//! normal (flipped to the side the new ray leaves by) by a fixed number of ULPs
//! per coordinate, done with integer arithmetic on the float bit patterns, so the
//! offset scales with the magnitude of each coordinate. Near the world origin the
//! ULPs get arbitrarily small, so coordinates with magnitude below `1/32` get a
//! small absolute offset instead. The constants are the ones given in the chapter
//! (`origin = 1/32`, `float_scale = 1/65536`, `int_scale = 256`).

use glam::Vec3;

use super::{Ray, SurfaceHit};

/// Below this coordinate magnitude the offset is absolute (Wächter & Binder's `origin`).
const ABSOLUTE_OFFSET_THRESHOLD: f32 = 1.0 / 32.0;
/// Absolute offset scale near the origin (Wächter & Binder's `float_scale`).
const ABSOLUTE_OFFSET_SCALE: f32 = 1.0 / 65536.0;
/// ULPs of offset for a coordinate whose normal component is 1 (`int_scale`).
const ULP_OFFSET_SCALE: f32 = 256.0;

/// Shadow rays stop this fraction of the distance short of their target (pbrt-v4's
/// `ShadowEpsilon`), so the target surface itself is not reported as an occluder.
pub const SHADOW_EPSILON: f32 = 1e-4;

/// `point` moved off its surface (unit geometric normal `normal`) to the side
/// `direction` points to, far enough that a ray leaving from it in `direction`
/// does not hit the surface it started on.
#[inline]
pub fn offset_ray_origin(point: Vec3, normal: Vec3, direction: Vec3) -> Vec3 {
    let normal = if normal.dot(direction) < 0.0 {
        -normal
    } else {
        normal
    };
    offset_along(point, normal)
}

/// `point` moved along `normal` (already flipped to the side to leave by),
/// all three coordinates at once in SSE2 registers: both offsets are computed
/// and one selected per coordinate, without branches (which coordinates are
/// near the origin varies from hit to hit).
#[cfg(target_arch = "x86_64")]
#[inline]
fn offset_along(point: Vec3, normal: Vec3) -> Vec3 {
    use std::arch::x86_64::{
        __m128, _mm_add_epi32, _mm_add_ps, _mm_and_ps, _mm_andnot_ps, _mm_castps_si128,
        _mm_castsi128_ps, _mm_cmplt_ps, _mm_cvttps_epi32, _mm_mul_ps, _mm_or_ps, _mm_set1_ps,
        _mm_srai_epi32, _mm_sub_epi32, _mm_xor_si128,
    };
    let p: __m128 = glam::Vec3A::from(point).into();
    let n: __m128 = glam::Vec3A::from(normal).into();
    // SAFETY: the intrinsics need SSE and SSE2, which every x86_64 processor
    // has (they are part of the target's baseline); they touch no memory.
    let offset = unsafe {
        let absolute = _mm_add_ps(p, _mm_mul_ps(_mm_set1_ps(ABSOLUTE_OFFSET_SCALE), n));
        // Truncation towards zero as `as i32` (|n| <= 1, so no overflow).
        let ulps = _mm_cvttps_epi32(_mm_mul_ps(_mm_set1_ps(ULP_OFFSET_SCALE), n));
        // Adding to the bit pattern grows the magnitude; for negative coordinates
        // growing the magnitude moves towards -inf, so the ULPs are negated where
        // the sign bit is set (`sign` is -1 there, else 0; the only such
        // coordinate not below zero, -0, takes the absolute offset).
        let bits = _mm_castps_si128(p);
        let sign = _mm_srai_epi32::<31>(bits);
        let ulps = _mm_sub_epi32(_mm_xor_si128(ulps, sign), sign);
        let relative = _mm_castsi128_ps(_mm_add_epi32(bits, ulps));
        let magnitude = _mm_andnot_ps(_mm_set1_ps(-0.0), p);
        let near_origin = _mm_cmplt_ps(magnitude, _mm_set1_ps(ABSOLUTE_OFFSET_THRESHOLD));
        _mm_or_ps(
            _mm_and_ps(near_origin, absolute),
            _mm_andnot_ps(near_origin, relative),
        )
    };
    Vec3::from(glam::Vec3A::from(offset))
}

/// `point` moved along `normal` (already flipped to the side to leave by),
/// one coordinate at a time.
#[cfg(not(target_arch = "x86_64"))]
#[inline]
fn offset_along(point: Vec3, normal: Vec3) -> Vec3 {
    Vec3::new(
        offset_coordinate(point.x, normal.x),
        offset_coordinate(point.y, normal.y),
        offset_coordinate(point.z, normal.z),
    )
}

/// One coordinate `p` moved by the normal's component `n` (Wächter and
/// Binder's rule, with branches): absolutely near the origin, by ULPs
/// elsewhere. The SSE2 [`offset_along`] computes the same bit for bit.
#[cfg(any(test, not(target_arch = "x86_64")))]
#[inline]
fn offset_coordinate(p: f32, n: f32) -> f32 {
    if p.abs() < ABSOLUTE_OFFSET_THRESHOLD {
        p + ABSOLUTE_OFFSET_SCALE * n
    } else {
        let ulps = (ULP_OFFSET_SCALE * n) as i32;
        // Adding to the bit pattern grows the magnitude; for negative
        // coordinates growing the magnitude moves towards -inf.
        let ulps = if p < 0.0 { -ulps } else { ulps };
        f32::from_bits((p.to_bits() as i32).wrapping_add(ulps) as u32)
    }
}

/// A ray leaving `hit` in `direction`, its origin offset by [`offset_ray_origin`].
pub fn spawn_ray(hit: &SurfaceHit, direction: Vec3) -> Ray {
    Ray::with_time(
        offset_ray_origin(hit.point, hit.geometric_normal, direction),
        direction,
        hit.time,
    )
}

/// A ray leaving `hit` that passes through `target` (a point on another
/// surface, which the ray is to hit): its origin is offset off the surface
/// towards `target`, and its direction is aimed from that origin, not from
/// `hit.point`. (A ray along `target − hit.point` from the offset origin
/// passes the target at the offset's distance, up to 256 ulps of the
/// coordinates: 0.016 in a scene of size 500, beyond a reconnection's
/// tolerance on short segments.) Returns the ray and its length to
/// `target`, or `None` where the two coincide.
pub fn spawn_ray_through(hit: &SurfaceHit, target: Vec3) -> Option<(Ray, f32)> {
    let origin = offset_ray_origin(hit.point, hit.geometric_normal, target - hit.point);
    let to_target = target - origin;
    let distance = to_target.length();
    (distance > 0.0 && distance.is_finite()).then(|| {
        (
            Ray::with_time(origin, to_target / distance, hit.time),
            distance,
        )
    })
}

/// A shadow ray from `hit` towards `target`: returns the ray (unit direction,
/// origin offset off the surface) and the `t_max` to trace it to, which stops
/// [`SHADOW_EPSILON`] (relative) short of `target`. If the target lies on a
/// surface, offset it first (see [`spawn_ray_to_point`] with both ends offset).
/// Returns `None` if the target coincides with the origin.
pub fn spawn_ray_to(hit: &SurfaceHit, target: Vec3) -> Option<(Ray, f32)> {
    let origin = offset_ray_origin(hit.point, hit.geometric_normal, target - hit.point);
    segment(origin, target, hit.time)
}

/// A shadow ray between two surface points, both offset off their surfaces
/// towards each other (pbrt-v4's `SpawnRayTo` between two interactions): the
/// target `point` with unit normal `normal` is typically a sampled point on an
/// area light. Returns the ray and its `t_max`, or `None` for coincident points.
pub fn spawn_ray_to_point(hit: &SurfaceHit, point: Vec3, normal: Vec3) -> Option<(Ray, f32)> {
    let origin = offset_ray_origin(hit.point, hit.geometric_normal, point - hit.point);
    spawn_segment_to_point(origin, hit.time, point, normal)
}

/// [`spawn_ray_to_point`] from an `origin` already offset off its surface
/// (e.g. by [`OffsetPoint::towards`]).
#[inline]
pub fn spawn_segment_to_point(
    origin: Vec3,
    time: f32,
    point: Vec3,
    normal: Vec3,
) -> Option<(Ray, f32)> {
    segment(origin, offset_light_point(origin, point, normal), time)
}

/// [`spawn_segment_to_point`] without the square root and division of a
/// unit direction, for occlusion queries: the direction is the segment
/// itself (the offset target minus `origin`) and the ray is traced to `t =
/// 1 − SHADOW_EPSILON`, the same fraction of the segment. Every
/// intersection test (watertight triangles, spheres, disks, BVH boxes)
/// solves for `t` in units of the direction's length, so an occlusion query
/// finds the same surfaces; only callers that read `t` as a distance need
/// [`spawn_segment_to_point`]. Measured on the Cornell box: about 15
/// instructions and a sqrt-then-divide chain less per shadow ray. `None`
/// for coincident or non-finite ends, as [`spawn_segment_to_point`].
#[inline]
pub fn occlusion_segment_to_point(
    origin: Vec3,
    time: f32,
    point: Vec3,
    normal: Vec3,
) -> Option<(Ray, f32)> {
    let segment = offset_light_point(origin, point, normal) - origin;
    // The same rejections as the length test of `segment`.
    let length_squared = segment.length_squared();
    if !(length_squared > 0.0 && length_squared < f32::INFINITY) {
        return None;
    }
    Some((Ray::with_time(origin, segment, time), 1.0 - SHADOW_EPSILON))
}

/// The target `point` (unit normal `normal`) of a segment from `origin`,
/// offset off its surface towards `origin`.
#[inline(always)]
fn offset_light_point(origin: Vec3, point: Vec3, normal: Vec3) -> Vec3 {
    offset_ray_origin(point, normal, origin - point)
}

/// A surface point and its ray origin offset to the side of one direction
/// (`wo`, say), kept so that rays leaving to that side reuse it:
/// [`offset_ray_origin`] depends on the direction only through the side it
/// points to, so [`OffsetPoint::towards`] equals `offset_ray_origin(point,
/// normal, direction)` bit for bit and computes it only for the other side.
#[derive(Debug, Clone, Copy)]
pub struct OffsetPoint {
    point: Vec3,
    normal: Vec3,
    /// Whether the kept offset is below the normal (`normal · wo < 0`).
    below: bool,
    offset: Vec3,
}

impl OffsetPoint {
    /// `point` on a surface with unit geometric normal `normal`, offset
    /// towards `direction`.
    #[inline]
    pub fn new(point: Vec3, normal: Vec3, direction: Vec3) -> Self {
        Self {
            point,
            normal,
            below: normal.dot(direction) < 0.0,
            offset: offset_ray_origin(point, normal, direction),
        }
    }

    /// The origin offset towards the direction given to [`OffsetPoint::new`].
    #[inline]
    pub fn origin(&self) -> Vec3 {
        self.offset
    }

    /// `offset_ray_origin(point, normal, direction)`.
    #[inline]
    pub fn towards(&self, direction: Vec3) -> Vec3 {
        if (self.normal.dot(direction) < 0.0) == self.below {
            self.offset
        } else {
            offset_ray_origin(self.point, self.normal, direction)
        }
    }
}

fn segment(origin: Vec3, target: Vec3, time: f32) -> Option<(Ray, f32)> {
    let offset = target - origin;
    let distance = offset.length();
    if distance <= 0.0 || !distance.is_finite() {
        return None;
    }
    // One division for the three components.
    Some((
        Ray::with_time(origin, offset * distance.recip(), time),
        distance * (1.0 - SHADOW_EPSILON),
    ))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_moves_to_the_side_of_the_direction() {
        for p in [
            Vec3::new(1e4, -1e4, 0.001),
            Vec3::new(0.5, -3.0, 7.0),
            Vec3::ZERO,
        ] {
            let n = Vec3::new(0.6, 0.0, 0.8);
            let above = offset_ray_origin(p, n, n);
            let below = offset_ray_origin(p, n, -n);
            assert!((above - p).dot(n) > 0.0, "{p}");
            assert!((below - p).dot(n) < 0.0, "{p}");
        }
    }

    #[test]
    fn offset_matches_the_branching_definition() {
        // Wächter & Binder's per-coordinate rule, written with branches.
        let reference = offset_coordinate;
        let coordinates = [
            0.0, -0.0, 0.01, -0.01, 0.03125, -0.03125, 0.5, -2.0, 555.0, -1e6, 3e-20,
        ];
        let normal = Vec3::new(0.48, -0.6, 0.64);
        for &x in &coordinates {
            for &y in &coordinates {
                let point = Vec3::new(x, y, -x);
                for direction in [normal, -normal] {
                    let side = if normal.dot(direction) < 0.0 {
                        -normal
                    } else {
                        normal
                    };
                    let expected = Vec3::new(
                        reference(point.x, side.x),
                        reference(point.y, side.y),
                        reference(point.z, side.z),
                    );
                    let offset = offset_ray_origin(point, normal, direction);
                    assert_eq!(
                        offset.to_array().map(f32::to_bits),
                        expected.to_array().map(f32::to_bits)
                    );
                }
            }
        }
    }

    #[test]
    fn offset_point_equals_offset_ray_origin() {
        let point = Vec3::new(0.3, -12.0, 250.0);
        let normal = Vec3::new(0.0, 0.6, -0.8);
        for wo in [normal, -normal, Vec3::X + normal * 0.1] {
            let offsets = OffsetPoint::new(point, normal, wo);
            assert_eq!(offsets.origin(), offset_ray_origin(point, normal, wo));
            for direction in [
                normal,
                -normal,
                Vec3::new(0.3, 0.2, 0.9),
                Vec3::new(-0.1, -0.7, 0.2),
            ] {
                assert_eq!(
                    offsets.towards(direction),
                    offset_ray_origin(point, normal, direction)
                );
            }
        }
    }
}
