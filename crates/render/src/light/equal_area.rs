//! The equal-area octahedral map between the unit square and the sphere of
//! directions (Clarberg, "Fast Equal-Area Mapping of the (Hemi)Sphere using
//! SIMD", JGT 13(3), 2008), the parameterisation of pbrt-v4's environment
//! maps: a square image whose pixels all subtend the same solid angle
//! 4π / N². The square's centre is +z, its four corners −z; the diagonals
//! of the square's quarters are the equator.

use std::f32::consts::FRAC_PI_4;

use glam::{Vec2, Vec3};

/// The direction of point `p` ∈ [0, 1]² (uniform points map to uniform directions).
pub fn equal_area_square_to_sphere(p: Vec2) -> Vec3 {
    // Work in [−1, 1]² and fold into the first quadrant.
    let u = 2.0 * p.x - 1.0;
    let v = 2.0 * p.y - 1.0;
    let (up, vp) = (u.abs(), v.abs());
    // Signed distance from the diagonal |u| + |v| = 1: positive inside
    // (northern hemisphere), negative outside.
    let signed_distance = 1.0 - (up + vp);
    let distance = signed_distance.abs();
    let r = 1.0 - distance;
    // The azimuth within the quadrant goes linearly along the diamond's edge.
    let phi = if r == 0.0 { 1.0 } else { (vp - up) / r + 1.0 } * FRAC_PI_4;
    let z = (1.0 - r * r).copysign(signed_distance);
    let cos_phi = phi.cos().copysign(u);
    let sin_phi = phi.sin().copysign(v);
    let radial = r * (2.0 - r * r).max(0.0).sqrt();
    Vec3::new(cos_phi * radial, sin_phi * radial, z)
}

/// The point of [0, 1]² of unit direction `d` (the inverse of
/// [`equal_area_square_to_sphere`]).
pub fn equal_area_sphere_to_square(d: Vec3) -> Vec2 {
    let (x, y, z) = (d.x.abs(), d.y.abs(), d.z.abs());
    // r = √(1 − |z|): the distance from the centre (or corner) of the diamond.
    let r = (1.0 - z).max(0.0).sqrt();
    // The azimuth in the first quadrant as a fraction of π/2.
    let (large, small) = (x.max(y), x.min(y));
    let ratio = if large == 0.0 { 0.0 } else { small / large };
    let mut phi = ratio.atan() / (2.0 * FRAC_PI_4);
    if x < y {
        phi = 1.0 - phi;
    }
    let mut v = phi * r;
    let mut u = r - v;
    if d.z < 0.0 {
        // The southern hemisphere is the outside of the diamond, mirrored.
        std::mem::swap(&mut u, &mut v);
        u = 1.0 - u;
        v = 1.0 - v;
    }
    let u = u.copysign(d.x);
    let v = v.copysign(d.y);
    Vec2::new(0.5 * (u + 1.0), 0.5 * (v + 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::sample_uniform_sphere;
    use crate::statistics::chi_square_test;
    use qmc::random::SeekablePcg;

    #[test]
    fn round_trip_and_poles() {
        assert!((equal_area_square_to_sphere(Vec2::splat(0.5)) - Vec3::Z).length() < 1e-6);
        assert!((equal_area_square_to_sphere(Vec2::ZERO) + Vec3::Z).length() < 1e-6);
        assert!((equal_area_square_to_sphere(Vec2::new(1.0, 0.5)) - Vec3::X).length() < 1e-6);
        assert!((equal_area_square_to_sphere(Vec2::new(0.5, 1.0)) - Vec3::Y).length() < 1e-6);
        let mut random = SeekablePcg::new(3, 1);
        for _ in 0..10_000 {
            let p = Vec2::new(random.next_f32(), random.next_f32());
            let d = equal_area_square_to_sphere(p);
            assert!((d.length() - 1.0).abs() < 1e-5);
            let back = equal_area_sphere_to_square(d);
            assert!((back - p).length() < 2e-4, "{p} -> {d} -> {back}");
        }
    }

    /// Uniform points of the square give uniform directions: the counts in
    /// 8 × 16 (cos θ, φ) bins of equal solid angle are equal.
    #[test]
    fn preserves_area() {
        let (bins_z, bins_phi) = (8usize, 16usize);
        let mut observed = vec![0u64; bins_z * bins_phi];
        let samples = 128_000;
        let mut random = SeekablePcg::new(5, 2);
        for _ in 0..samples {
            let d = equal_area_square_to_sphere(Vec2::new(random.next_f32(), random.next_f32()));
            let z_bin = (((d.z + 1.0) / 2.0 * bins_z as f32) as usize).min(bins_z - 1);
            let phi = d.y.atan2(d.x).rem_euclid(std::f32::consts::TAU);
            let phi_bin =
                ((phi / std::f32::consts::TAU * bins_phi as f32) as usize).min(bins_phi - 1);
            observed[z_bin * bins_phi + phi_bin] += 1;
        }
        let expected = vec![samples as f64 / (bins_z * bins_phi) as f64; bins_z * bins_phi];
        let result = chi_square_test(&observed, &expected);
        assert!(result.p_value > 1e-3, "{result:?}");
        // And the inverse maps uniform directions to uniform points.
        let mut observed = vec![0u64; 64];
        for _ in 0..samples {
            let d = sample_uniform_sphere(Vec2::new(random.next_f32(), random.next_f32()));
            let p = equal_area_sphere_to_square(d);
            let (x, y) = (((p.x * 8.0) as usize).min(7), ((p.y * 8.0) as usize).min(7));
            observed[y * 8 + x] += 1;
        }
        let result = chi_square_test(&observed, &[samples as f64 / 64.0; 64]);
        assert!(result.p_value > 1e-3, "{result:?}");
    }
}
