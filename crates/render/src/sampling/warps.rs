//! Warps from the unit square to disks, hemispheres and spheres: Shirley and
//! Chiu's concentric disk mapping, cosine-weighted hemisphere sampling
//! (Malley's method: project the disk up onto the hemisphere), and uniform
//! sphere sampling. BSDFs, shapes and lights all sample with these.
//!
//! Every warp takes its two numbers as anything that converts into a
//! [`Vec2`] (a `[f32; 2]` from a sampler or a `Vec2`): the conversion only
//! moves the two values, so results do not depend on the caller's type.

use std::f32::consts::{FRAC_1_PI, FRAC_PI_4, PI};

use glam::{Vec2, Vec3};

/// Maps `u` ∈ [0, 1)² to the unit disk with constant density 1/π, keeping
/// strata compact and adjacent: concentric squares go to concentric circles
/// (Shirley and Chiu 1997, "A Low Distortion Map Between Disk and Square").
/// Low distortion matters for QMC points, whose uniformity it preserves.
#[inline]
pub fn sample_uniform_disk_concentric(u: impl Into<Vec2>) -> Vec2 {
    let u = u.into();
    let x = 2.0 * u.x - 1.0;
    let y = 2.0 * u.y - 1.0;
    if x == 0.0 && y == 0.0 {
        return Vec2::ZERO;
    }
    // θ = π/4 · (y/x) in the left and right quadrants, π/2 − π/4 · (x/y) in
    // the top and bottom ones; cos and sin of π/2 − φ are sin φ and cos φ, so
    // both need only the sine and cosine of an angle in [−π/4, π/4].
    if x.abs() > y.abs() {
        let (sin, cos) = sin_cos_quarter_pi(FRAC_PI_4 * (y / x));
        Vec2::new(x * cos, x * sin)
    } else {
        let (sin, cos) = sin_cos_quarter_pi(FRAC_PI_4 * (x / y));
        Vec2::new(y * sin, y * cos)
    }
}

/// (sin φ, cos φ) for φ ∈ [−π/4, π/4] by the single-precision minimax
/// polynomials of the Cephes Math Library (Stephen L. Moshier, `sinf.c` and
/// `cosf.c`, coefficients `sincof` and `coscof`): degree 7 for the sine and 8
/// for the cosine, with errors of a few 10⁻⁸ over that range (a rounding
/// step of f32), so this matches `f32::sin_cos` to an ulp or two while costing
/// a few multiplications instead of a library call with range reduction.
#[inline]
fn sin_cos_quarter_pi(phi: f32) -> (f32, f32) {
    let phi2 = phi * phi;
    let sin = ((-1.951_529_6e-4 * phi2 + 8.332_161e-3) * phi2 - 1.666_665_5e-1) * phi2 * phi + phi;
    let cos = ((2.443_315_7e-5 * phi2 - 1.388_731_6e-3) * phi2 + 4.166_664_6e-2) * phi2 * phi2
        - 0.5 * phi2
        + 1.0;
    (sin, cos)
}

/// The concentric map of [`sample_uniform_disk_concentric`] evaluated as
/// written, with the library's `cos` and `sin` of the angle θ = π/4 · (y/x)
/// or π/2 − π/4 · (x/y). It differs from the polynomial form by an ulp or
/// two; the thin lens, disk shapes and the emission disks of lights at
/// infinity sample with it, as they always have, so their images stay bit
/// for bit what they were.
pub fn sample_uniform_disk_concentric_trigonometric(u: impl Into<Vec2>) -> Vec2 {
    let offset = 2.0 * u.into() - Vec2::ONE;
    if offset == Vec2::ZERO {
        return Vec2::ZERO;
    }
    let (radius, theta) = if offset.x.abs() > offset.y.abs() {
        (offset.x, FRAC_PI_4 * (offset.y / offset.x))
    } else {
        (
            offset.y,
            2.0 * FRAC_PI_4 - FRAC_PI_4 * (offset.x / offset.y),
        )
    };
    radius * Vec2::new(theta.cos(), theta.sin())
}

/// A direction in the upper hemisphere (z ≥ 0) with density cos θ / π per unit
/// solid angle ([`cosine_hemisphere_pdf`]): a uniform disk point lifted onto
/// the hemisphere.
#[inline]
pub fn sample_cosine_hemisphere(u: impl Into<Vec2>) -> Vec3 {
    let disk = sample_uniform_disk_concentric(u);
    let z = (1.0 - disk.length_squared()).max(0.0).sqrt();
    Vec3::new(disk.x, disk.y, z)
}

/// The density of [`sample_cosine_hemisphere`]: cos θ / π (per steradian).
#[inline]
pub fn cosine_hemisphere_pdf(cos_theta: f32) -> f32 {
    cos_theta * FRAC_1_PI
}

/// A direction uniformly distributed on the unit sphere (density 1/(4π)):
/// z = 1 − 2u₀ is uniform by Archimedes' hat-box theorem, φ = 2πu₁.
#[inline]
pub fn sample_uniform_sphere(u: impl Into<Vec2>) -> Vec3 {
    let u = u.into();
    let z = 1.0 - 2.0 * u.x;
    let radius = (1.0 - z * z).max(0.0).sqrt();
    let phi = 2.0 * PI * u.y;
    Vec3::new(radius * phi.cos(), radius * phi.sin(), z)
}

/// The density of [`sample_uniform_sphere`]: 1/(4π).
pub const UNIFORM_SPHERE_PDF: f32 = 0.25 * FRAC_1_PI;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn concentric_mapping_stays_in_the_disk_and_maps_edges_to_the_circle() {
        let steps = 64;
        for i in 0..=steps {
            for j in 0..=steps {
                let u = [i as f32 / steps as f32, j as f32 / steps as f32];
                let point = sample_uniform_disk_concentric(u);
                assert!(point.length() <= 1.0 + 1e-6);
                assert!(sample_uniform_disk_concentric_trigonometric(u).length() <= 1.0 + 1e-6);
                let on_square_edge = i == 0 || j == 0 || i == steps || j == steps;
                if on_square_edge {
                    assert!((point.length() - 1.0).abs() < 1e-5, "{u:?} -> {point}");
                }
            }
        }
        assert_eq!(sample_uniform_disk_concentric([0.5, 0.5]), Vec2::ZERO);
        assert_eq!(
            sample_uniform_disk_concentric_trigonometric([0.5, 0.5]),
            Vec2::ZERO
        );
        // The square's centre ring of half-width 1/4 maps to the circle of radius 1/2.
        assert!((sample_uniform_disk_concentric([0.75, 0.6]).length() - 0.5).abs() < 1e-6);
    }

    #[test]
    fn quarter_pi_sin_cos_matches_the_library() {
        let steps = 10_000;
        for i in 0..=steps {
            let phi = FRAC_PI_4 * (2.0 * i as f32 / steps as f32 - 1.0);
            let (sin, cos) = sin_cos_quarter_pi(phi);
            assert!((sin - phi.sin()).abs() <= 2.0 * f32::EPSILON, "sin {phi}");
            assert!((cos - phi.cos()).abs() <= 2.0 * f32::EPSILON, "cos {phi}");
        }
        assert_eq!(sin_cos_quarter_pi(0.0), (0.0, 1.0));
    }

    /// Both forms of the concentric map agree to rounding and fill the disk
    /// uniformly.
    #[test]
    fn concentric_mapping_is_uniform_and_both_forms_agree() {
        // Over 8 rings × 16 sectors of equal area a stratified grid of inputs
        // fills every cell almost exactly (the map preserves area).
        let (rings, sectors, side) = (8usize, 16usize, 512usize);
        let mut counts = vec![0f64; rings * sectors];
        for i in 0..side {
            for j in 0..side {
                let u = [
                    (i as f32 + 0.5) / side as f32,
                    (j as f32 + 0.5) / side as f32,
                ];
                let p = sample_uniform_disk_concentric_trigonometric(u);
                let polynomial = sample_uniform_disk_concentric(u);
                assert!(
                    (polynomial - p).length() < 1e-6,
                    "{u:?}: {polynomial} vs {p}"
                );
                let ring = ((p.length_squared() * rings as f32) as usize).min(rings - 1);
                let angle = p.y.atan2(p.x).rem_euclid(std::f32::consts::TAU);
                let sector =
                    ((angle / std::f32::consts::TAU * sectors as f32) as usize).min(sectors - 1);
                counts[ring * sectors + sector] += 1.0;
            }
        }
        let expected = (side * side) as f64 / (rings * sectors) as f64;
        // A stratified area-preserving map deviates from the expected count only
        // along the cell boundaries: O(side) points per cell at most.
        for &count in &counts {
            assert!(
                (count - expected).abs() < 0.05 * expected,
                "{count} vs {expected}"
            );
        }
    }

    #[test]
    fn hemisphere_and_sphere_samples_are_unit_vectors() {
        for i in 0..50 {
            for j in 0..50 {
                let u = [(i as f32 + 0.5) / 50.0, (j as f32 + 0.5) / 50.0];
                let hemisphere = sample_cosine_hemisphere(u);
                assert!((hemisphere.length() - 1.0).abs() < 1e-5 && hemisphere.z >= 0.0);
                assert!((sample_uniform_sphere(u).length() - 1.0).abs() < 1e-5);
            }
        }
        assert_eq!(sample_cosine_hemisphere([0.5, 0.5]), Vec3::Z);
        assert_eq!(cosine_hemisphere_pdf(1.0), FRAC_1_PI);
    }
}
