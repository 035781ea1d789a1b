//! [`MicrofacetDistribution`]: the statistics of a rough surface's microfacet
//! normals, Trowbridge–Reitz (GGX) or Beckmann, anisotropic (α_x along the
//! shading frame's tangent, α_y along its bitangent), with Smith's
//! masking-shadowing and sampling of the normals visible from a direction.
//!
//! Sources (formulas only):
//! - Walter, Marschner, Li and Torrance 2007, "Microfacet Models for
//!   Refraction through Rough Surfaces" (EGSR): the distributions, the
//!   generalised half vector and the BTDF.
//! - Heitz 2014, "Understanding the Masking-Shadowing Function in
//!   Microfacet-Based BRDFs" (JCGT 3(2)): anisotropic D and Smith Λ.
//! - Heitz 2018, "Sampling the GGX Distribution of Visible Normals" (JCGT
//!   7(4)): GGX visible normals by stretching to α = 1 and sampling a
//!   projected hemisphere.
//! - Heitz and d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using
//!   the Distribution of Visible Normals" (EGSR), with W. Jakob's closed form
//!   of the Beckmann visible-slope CDF ("An Improved Visible Normal Sampling
//!   Routine for the Beckmann Distribution", 2014): Beckmann visible normals.
//!
//! # Masking-shadowing
//!
//! G(wo, wi, m) = G1(wo, m) G1(wi, m), the *separable* Smith form, which is
//! what Mitsuba 3 uses (pbrt-v4 uses the height-correlated
//! 1/(1 + Λ(wo) + Λ(wi)); the two differ by a few percent at grazing angles).
//! G1 = 1/(1 + Λ) with the exact Λ of each distribution (Mitsuba approximates
//! the Beckmann Λ by Walter's rational fit, which differs from the exact one by
//! less than 0.4 %; the exact one keeps the visible-normal density normalised).
//!
//! All directions are in the local shading frame (normal +z).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use crate::math::{erf, inverse_erf};
use crate::sampling::sample_uniform_disk_concentric;

/// The shape of the microfacet normal distribution.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum MicrofacetKind {
    /// Trowbridge–Reitz (GGX): long tails.
    Ggx,
    /// Beckmann–Spizzichino: Gaussian slopes.
    Beckmann,
}

/// Below this roughness a distribution is treated as a perfectly smooth
/// surface (its lobe is narrower than f32 can resolve well); pbrt-v4 uses the
/// same threshold.
pub const SMOOTH_ALPHA_THRESHOLD: f32 = 1e-3;

/// Roughness values are clamped to at least this (Mitsuba 3 clamps at 1e-4),
/// so that D stays finite.
const MINIMUM_ALPHA: f32 = 1e-4;

/// An anisotropic microfacet distribution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MicrofacetDistribution {
    kind: MicrofacetKind,
    alpha_x: f32,
    alpha_y: f32,
}

impl MicrofacetDistribution {
    /// A distribution with roughness `alpha_x` along the tangent and `alpha_y`
    /// along the bitangent (the RMS slope for Beckmann). NaN or negative
    /// values become the minimum roughness 10⁻⁴.
    pub fn new(kind: MicrofacetKind, alpha_x: f32, alpha_y: f32) -> Self {
        let clean = |alpha: f32| {
            if alpha.is_nan() {
                MINIMUM_ALPHA
            } else {
                alpha.max(MINIMUM_ALPHA)
            }
        };
        Self {
            kind,
            alpha_x: clean(alpha_x),
            alpha_y: clean(alpha_y),
        }
    }

    /// pbrt-v4's `RoughnessToAlpha`: α = √roughness, for scene files that
    /// give a perceptual roughness (`remaproughness`).
    pub fn roughness_to_alpha(roughness: f32) -> f32 {
        roughness.max(0.0).sqrt()
    }

    /// GGX or Beckmann.
    pub fn kind(&self) -> MicrofacetKind {
        self.kind
    }

    /// Roughness along the tangent.
    pub fn alpha_x(&self) -> f32 {
        self.alpha_x
    }

    /// Roughness along the bitangent.
    pub fn alpha_y(&self) -> f32 {
        self.alpha_y
    }

    /// Whether the surface is so smooth that it should be treated as a
    /// specular (delta) interface.
    pub fn is_effectively_smooth(&self) -> bool {
        self.alpha_x.max(self.alpha_y) < SMOOTH_ALPHA_THRESHOLD
    }

    /// The effective roughness in [0, 1] that LQMC uses: max(α_x, α_y)
    /// clamped to 1.
    pub fn roughness(&self) -> f32 {
        self.alpha_x.max(self.alpha_y).min(1.0)
    }

    /// The distribution of microfacet normals D(m) (per unit solid angle of
    /// m, normalised so that ∫ D(m) cos θm dωm = 1); 0 below the surface.
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (x, y) = (m.x / self.alpha_x, m.y / self.alpha_y);
        let z2 = m.z * m.z;
        match self.kind {
            MicrofacetKind::Ggx => {
                // 1 / (π αx αy (x²/αx² + y²/αy² + z²)²) for unit m.
                let denominator = x * x + y * y + z2;
                1.0 / (PI * self.alpha_x * self.alpha_y * denominator * denominator)
            }
            MicrofacetKind::Beckmann => {
                let exponent = -(x * x + y * y) / z2;
                exponent.exp() / (PI * self.alpha_x * self.alpha_y * z2 * z2)
            }
        }
    }

    /// Smith's Λ(w): the masked projected area of microfacets relative to
    /// the projected area of the macrosurface.
    pub fn lambda(&self, w: Vec3) -> f32 {
        let z2 = w.z * w.z;
        // α² tan² θ with the projected roughness along w's azimuth.
        let alpha2_tan2 = (w.x * w.x * self.alpha_x * self.alpha_x
            + w.y * w.y * self.alpha_y * self.alpha_y)
            / z2;
        if !alpha2_tan2.is_finite() {
            // Grazing: everything is masked.
            return f32::INFINITY;
        }
        if alpha2_tan2 == 0.0 {
            return 0.0;
        }
        match self.kind {
            MicrofacetKind::Ggx => 0.5 * ((1.0 + alpha2_tan2).sqrt() - 1.0),
            MicrofacetKind::Beckmann => {
                // a = 1/(α tan θ); Λ = (erf(a) − 1)/2 + e^(−a²)/(2a√π).
                let a = 1.0 / f64::from(alpha2_tan2).sqrt();
                let value =
                    0.5 * (erf(a) - 1.0) + (-a * a).exp() / (2.0 * a * std::f64::consts::PI.sqrt());
                value.max(0.0) as f32
            }
        }
    }

    /// Smith's G1(w, m) = 1/(1 + Λ(w)), 0 when `w` sees the back of the
    /// microfacet `m` (w·m and cos θ of w of different signs).
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        1.0 / (1.0 + self.lambda(w))
    }

    /// Masking-shadowing G(wo, wi, m) = G1(wo, m) G1(wi, m) (separable).
    pub fn g(&self, wo: Vec3, wi: Vec3, m: Vec3) -> f32 {
        self.g1(wo, m) * self.g1(wi, m)
    }

    /// The density of the normals visible from `w` (w.z > 0):
    /// D_w(m) = G1(w, m) max(0, w·m) D(m) / cos θ_w, per unit solid angle of
    /// m; it integrates to 1 over the hemisphere.
    pub fn visible_normal_pdf(&self, w: Vec3, m: Vec3) -> f32 {
        if w.z <= 0.0 {
            return 0.0;
        }
        let cos = w.dot(m);
        if cos <= 0.0 {
            return 0.0;
        }
        self.g1(w, m) * cos * self.d(m) / w.z
    }

    /// A microfacet normal drawn with density [`Self::visible_normal_pdf`]
    /// from `u` ∈ [0, 1)²; `w` must be in the upper hemisphere.
    pub fn sample_visible_normal(&self, w: Vec3, u: [f32; 2]) -> Vec3 {
        // Stretch to the configuration of roughness 1.
        let stretched = Vec3::new(w.x * self.alpha_x, w.y * self.alpha_y, w.z).normalize();
        let m = match self.kind {
            MicrofacetKind::Ggx => sample_ggx_visible_unit(stretched, u),
            MicrofacetKind::Beckmann => sample_beckmann_visible_unit(stretched, u),
        };
        // Unstretch the normal (normals transform with the inverse transpose).
        Vec3::new(m.x * self.alpha_x, m.y * self.alpha_y, m.z.max(1e-6)).normalize()
    }
}

/// Heitz 2018: for roughness 1 the visible normals are the projection onto
/// the unit hemisphere of a uniform point on the disk seen from `w`, which is
/// a half disk (the part facing `w`) and a half ellipse. The disk sample uses
/// the concentric mapping (strata stay compact for QMC points).
fn sample_ggx_visible_unit(w: Vec3, u: [f32; 2]) -> Vec3 {
    let tangent = if w.z < 0.99999 {
        Vec3::Z.cross(w).normalize()
    } else {
        Vec3::X
    };
    let bitangent = w.cross(tangent);
    let mut disk = sample_uniform_disk_concentric(u);
    // Warp the lower half of the disk onto the ellipse of the hemisphere's
    // projected lower half.
    let height = (1.0 - disk.x * disk.x).max(0.0).sqrt();
    let s = 0.5 * (1.0 + w.z);
    disk.y = (1.0 - s) * height + s * disk.y;
    let z = (1.0 - disk.length_squared()).max(0.0).sqrt();
    disk.x * tangent + disk.y * bitangent + z * w
}

/// Heitz and d'Eon 2014 for Beckmann with roughness 1: rotate `w` into the
/// xz-plane, draw the visible slope (x̃, ỹ), rotate back and turn the slope
/// into a normal m = (−x̃, −ỹ, 1)/‖·‖.
fn sample_beckmann_visible_unit(w: Vec3, u: [f32; 2]) -> Vec3 {
    let sin_theta = (w.x * w.x + w.y * w.y).sqrt();
    let (cos_phi, sin_phi) = if sin_theta > 0.0 {
        (w.x / sin_theta, w.y / sin_theta)
    } else {
        (1.0, 0.0)
    };
    let slope = beckmann_visible_slope(f64::from(w.z.clamp(0.0, 1.0)), u);
    let rotated = Vec2::new(
        cos_phi * slope.x - sin_phi * slope.y,
        sin_phi * slope.x + cos_phi * slope.y,
    );
    Vec3::new(-rotated.x, -rotated.y, 1.0).normalize()
}

/// The visible slopes of the roughness-1 Beckmann surface seen from
/// direction (sin θ, 0, cos θ).
///
/// The slopes are independent: ỹ is normal with variance ½, so
/// ỹ = erf⁻¹(2u₁ − 1); x̃ has density ∝ (cos θ − x̃ sin θ) e^(−x̃²) on
/// x̃ < cot θ, whose CDF is (Jakob 2014)
///
///   C(x) = (1 + erf(x) + tan θ e^(−x²)/√π) / (1 + erf(cot θ) + tan θ e^(−cot²θ)/√π),
///
/// inverted here by Newton's method safeguarded with bisection (f64).
fn beckmann_visible_slope(cos_theta: f64, u: [f32; 2]) -> Vec2 {
    const SQRT_PI_INV: f64 = 0.564_189_583_547_756_3;
    let clamp_unit = |value: f32| f64::from(value).clamp(1e-7, 1.0 - 1e-7);
    let (u0, u1) = (clamp_unit(u[0]), clamp_unit(u[1]));
    let slope_y = inverse_erf(2.0 * u1 - 1.0);
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    if sin_theta < 1e-6 {
        // Normal incidence: both slopes are plain Gaussians.
        return Vec2::new(inverse_erf(2.0 * u0 - 1.0) as f32, slope_y as f32);
    }
    let tan_theta = sin_theta / cos_theta.max(1e-12);
    let cot_theta = cos_theta / sin_theta;
    let unnormalised_cdf = |x: f64| 1.0 + erf(x) + tan_theta * (-x * x).exp() * SQRT_PI_INV;
    let normalisation = unnormalised_cdf(cot_theta);
    let target = u0 * normalisation;
    // C is increasing on (−∞, cot θ]; below −6 it is below 1e-15.
    let (mut low, mut high) = (-6.0_f64, cot_theta);
    let mut x = inverse_erf(2.0 * u0 - 1.0).clamp(low, high);
    for _ in 0..64 {
        let value = unnormalised_cdf(x) - target;
        if value.abs() < 1e-12 * normalisation {
            break;
        }
        if value > 0.0 {
            high = x;
        } else {
            low = x;
        }
        let derivative = 2.0 * SQRT_PI_INV * (-x * x).exp() * (1.0 - x * tan_theta);
        let newton = x - value / derivative;
        x = if derivative > 0.0 && newton > low && newton < high {
            newton
        } else {
            0.5 * (low + high)
        };
        if high - low < 1e-12 {
            break;
        }
    }
    Vec2::new(x as f32, slope_y as f32)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ D(m) cos θm dωm = 1 by a midpoint rule in (cos θ, φ).
    #[test]
    fn distributions_are_normalised() {
        for kind in [MicrofacetKind::Ggx, MicrofacetKind::Beckmann] {
            for (ax, ay) in [(0.1, 0.1), (0.3, 0.05), (0.7, 1.0)] {
                let distribution = MicrofacetDistribution::new(kind, ax, ay);
                let (nz, nphi) = (4000, 256);
                let mut sum = 0.0_f64;
                for i in 0..nz {
                    // Substitute z = t² to resolve the narrow peak near z = 1.
                    let t = (i as f64 + 0.5) / nz as f64;
                    let z = 1.0 - t * t;
                    let dz = 2.0 * t / nz as f64;
                    for j in 0..nphi {
                        let phi = (j as f64 + 0.5) / nphi as f64 * 2.0 * std::f64::consts::PI;
                        let r = (1.0 - z * z).max(0.0).sqrt();
                        let m = Vec3::new((r * phi.cos()) as f32, (r * phi.sin()) as f32, z as f32);
                        sum += f64::from(distribution.d(m)) * z * dz * 2.0 * std::f64::consts::PI
                            / nphi as f64;
                    }
                }
                assert!((sum - 1.0).abs() < 2e-3, "{kind:?} {ax} {ay}: {sum}");
            }
        }
    }

    #[test]
    fn smith_lambda_limits() {
        let distribution = MicrofacetDistribution::new(MicrofacetKind::Beckmann, 0.5, 0.5);
        assert_eq!(distribution.lambda(Vec3::Z), 0.0);
        // Walter et al.'s rational approximation of the Beckmann G1 for
        // a = 1/(α tan θ) < 1.6 agrees with the exact form to < 0.4 %.
        for theta in [0.5_f32, 1.0, 1.3, 1.5] {
            let w = Vec3::new(theta.sin(), 0.0, theta.cos());
            let a = 1.0 / (0.5 * theta.tan());
            let approximation = if a >= 1.6 {
                1.0
            } else {
                (3.535 * a + 2.181 * a * a) / (1.0 + 2.276 * a + 2.577 * a * a)
            };
            let exact = distribution.g1(w, Vec3::Z);
            assert!(
                (exact - approximation).abs() < 4e-3 * exact.max(0.05),
                "{theta}"
            );
        }
        let ggx = MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.5, 0.5);
        let w = Vec3::new(0.6, 0.0, 0.8);
        // Λ = (√(1 + α² tan² θ) − 1)/2 with tan θ = 0.75.
        let expected = 0.5 * ((1.0_f32 + 0.25 * 0.5625).sqrt() - 1.0);
        assert!((ggx.lambda(w) - expected).abs() < 1e-6);
        // w sees the back of a microfacet tilted away from it.
        assert_eq!(ggx.g1(w, Vec3::new(-0.9, 0.0, 0.436).normalize()), 0.0);
    }

    #[test]
    fn visible_normals_face_the_viewer() {
        for kind in [MicrofacetKind::Ggx, MicrofacetKind::Beckmann] {
            let distribution = MicrofacetDistribution::new(kind, 0.4, 0.15);
            for w in [
                Vec3::Z,
                Vec3::new(0.6, 0.0, 0.8),
                Vec3::new(-0.3, 0.94, 0.1),
            ] {
                let w = w.normalize();
                for i in 0..32 {
                    for j in 0..32 {
                        let u = [(i as f32 + 0.5) / 32.0, (j as f32 + 0.5) / 32.0];
                        let m = distribution.sample_visible_normal(w, u);
                        assert!((m.length() - 1.0).abs() < 1e-4);
                        assert!(m.z > 0.0 && w.dot(m) > -1e-4, "{kind:?} {w} {m}");
                    }
                }
            }
        }
    }
}
