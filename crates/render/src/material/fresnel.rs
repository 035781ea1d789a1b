//! Specular reflection and refraction: the mirror direction, Snell's law, and
//! the Fresnel reflectance of unpolarised light at a dielectric interface and
//! at a conductor (complex index of refraction η + iκ).
//!
//! Formulas: Born and Wolf, *Principles of Optics*, §1.5 and §14.2; pbrt-v4
//! §9.3 and §9.4. All directions are in the local shading frame (normal +z) and
//! point away from the surface.

use glam::Vec3;

use crate::spectrum::SampledSpectrum;

/// The mirror reflection of `wo` about the normal (0, 0, 1).
#[inline]
pub fn reflect_about_normal(wo: Vec3) -> Vec3 {
    Vec3::new(-wo.x, -wo.y, wo.z)
}

/// The result of refracting a direction through an interface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Refraction {
    /// The transmitted direction (pointing away from the surface, on the other
    /// side).
    pub direction: Vec3,
    /// The relative index of refraction η_t / η_i seen along the path: `eta`
    /// if `wi` was on the normal's side, 1/`eta` if it was below.
    pub relative_eta: f32,
}

/// Refracts `wi` through the interface with normal (0, 0, 1) by Snell's law.
///
/// `eta` is the relative index η_below / η_above (inside over outside for a
/// surface whose normal points out). Returns `None` on total internal
/// reflection. `wi` must have unit length.
#[inline]
pub fn refract(wi: Vec3, eta: f32) -> Option<Refraction> {
    let mut cos_i = wi.z;
    let mut relative_eta = eta;
    let mut normal_sign = 1.0;
    if cos_i < 0.0 {
        // Coming from below: swap the media and flip the normal.
        relative_eta = 1.0 / relative_eta;
        cos_i = -cos_i;
        normal_sign = -1.0;
    }
    let cos2_t = transmitted_cos_squared(cos_i, relative_eta);
    if cos2_t <= 0.0 {
        return None;
    }
    let cos_t = cos2_t.sqrt();
    // wt = −wi/η + (cos_i/η − cos_t) n (pbrt-v4 eq. 9.4).
    let normal = Vec3::new(0.0, 0.0, normal_sign);
    let direction = -wi / relative_eta + (cos_i / relative_eta - cos_t) * normal;
    Some(Refraction {
        direction,
        relative_eta,
    })
}

/// cos² θt of the refracted direction for incidence cosine `cos_i` ≥ 0 and
/// relative index `eta`; ≤ 0 means total internal reflection.
///
/// Snell's law gives cos² θt = 1 − (1 − cos² θi)/η²; written as
/// (cos² θi + η² − 1)/η² it does not cancel catastrophically at grazing
/// incidence (for η = 1 it is exactly cos² θi).
#[inline]
fn transmitted_cos_squared(cos_i: f32, eta: f32) -> f32 {
    let eta2 = eta * eta;
    (cos_i * cos_i + (eta2 - 1.0)) / eta2
}

/// The Fresnel reflectance of unpolarised light at a smooth dielectric
/// interface: the mean of the squared s- and p-polarised amplitude
/// coefficients.
///
/// `cos_theta_i` is the cosine of the incident direction with the normal;
/// negative means the light arrives from below, in which case the media are
/// swapped. `eta` is η_below / η_above. Returns 1 under total internal
/// reflection.
pub fn fresnel_dielectric(cos_theta_i: f32, eta: f32) -> f32 {
    if eta == 1.0 {
        // Index matched: exactly 0, where the general formula would leave
        // rounding residue (cos θt recomputed from sin² θt).
        return 0.0;
    }
    let mut cos_i = cos_theta_i.clamp(-1.0, 1.0);
    let mut eta = eta;
    if cos_i < 0.0 {
        eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let cos2_t = transmitted_cos_squared(cos_i, eta);
    if cos2_t <= 0.0 {
        return 1.0;
    }
    let cos_t = cos2_t.sqrt();
    let parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (parallel * parallel + perpendicular * perpendicular)
}

/// The Fresnel reflectance of unpolarised light arriving from a dielectric
/// (index 1 relative to the conductor's η) onto a conductor with complex
/// relative index `eta` + i`k` (κ ≥ 0 is the extinction coefficient).
///
/// The same formula as [`fresnel_dielectric`] with complex arithmetic; for κ = 0
/// it reduces to it. `cos_theta_i` is clamped to [0, 1]: conductors are opaque,
/// so light only arrives from the normal's side (callers pass |cos θ|).
pub fn fresnel_complex(cos_theta_i: f32, eta: f32, k: f32) -> f32 {
    if eta == 0.0 && k == 0.0 {
        // The limit η → 0: the critical angle goes to 0 and all light reflects.
        return 1.0;
    }
    let cos_i = cos_theta_i.clamp(0.0, 1.0);
    let eta = Complex::new(eta, k);
    let sin2_i = 1.0 - cos_i * cos_i;
    let sin2_t = Complex::real(sin2_i) / (eta * eta);
    let cos_t = (Complex::real(1.0) - sin2_t).sqrt();
    let cos_i = Complex::real(cos_i);
    let parallel = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let perpendicular = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (parallel.norm_squared() + perpendicular.norm_squared())
}

/// [`fresnel_complex`] at every wavelength of a sampled spectrum.
pub fn fresnel_complex_spectrum(
    cos_theta_i: f32,
    eta: &SampledSpectrum,
    k: &SampledSpectrum,
) -> SampledSpectrum {
    eta.zip(k, |eta, k| fresnel_complex(cos_theta_i, eta, k))
}

/// The hemispherical average of the Fresnel reflectance of a dielectric
/// interface with relative index `eta` under cosine-weighted (diffuse)
/// illumination, F_dr = 2 ∫₀¹ F(μ, η) μ dμ, by the polynomial fits that
/// Mitsuba 3 uses: Egan and Hilgeman 1973 for η < 1 (light leaving a denser
/// medium, which is where most of it reflects back), d'Eon and Irving 2011
/// ("A Quantized-Diffusion Model for Rendering Translucent Materials") for
/// η ≥ 1.
pub fn fresnel_diffuse_reflectance(eta: f32) -> f32 {
    if eta < 1.0 {
        -1.4399 * eta * eta + 0.7099 * eta + 0.6681 + 0.0636 / eta
    } else {
        let inverse = 1.0 / eta;
        let polynomial = [0.919317, -3.4793, 6.75335, -7.80989, 4.98554, -1.36881];
        polynomial
            .iter()
            .rev()
            .fold(0.0, |sum, coefficient| sum * inverse + coefficient)
    }
}

/// The few complex operations the conductor Fresnel equations need.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Complex {
    re: f32,
    im: f32,
}

impl Complex {
    const fn new(re: f32, im: f32) -> Self {
        Self { re, im }
    }

    const fn real(re: f32) -> Self {
        Self { re, im: 0.0 }
    }

    fn norm_squared(self) -> f32 {
        self.re * self.re + self.im * self.im
    }

    /// The principal square root (non-negative real part), computed without
    /// cancellation (Numerical Recipes, 3rd ed., §5.5).
    fn sqrt(self) -> Self {
        let modulus = self.norm_squared().sqrt();
        if modulus == 0.0 {
            return Self::real(0.0);
        }
        let t1 = (0.5 * (modulus + self.re.abs())).sqrt();
        let t2 = 0.5 * self.im / t1;
        if self.re >= 0.0 {
            Self::new(t1, t2)
        } else {
            Self::new(t2.abs(), t1.copysign(self.im))
        }
    }
}

impl std::ops::Add for Complex {
    type Output = Complex;
    fn add(self, other: Complex) -> Complex {
        Complex::new(self.re + other.re, self.im + other.im)
    }
}

impl std::ops::Sub for Complex {
    type Output = Complex;
    fn sub(self, other: Complex) -> Complex {
        Complex::new(self.re - other.re, self.im - other.im)
    }
}

impl std::ops::Mul for Complex {
    type Output = Complex;
    fn mul(self, other: Complex) -> Complex {
        Complex::new(
            self.re * other.re - self.im * other.im,
            self.re * other.im + self.im * other.re,
        )
    }
}

impl std::ops::Div for Complex {
    type Output = Complex;
    fn div(self, other: Complex) -> Complex {
        let scale = 1.0 / other.norm_squared();
        Complex::new(
            scale * (self.re * other.re + self.im * other.im),
            scale * (self.im * other.re - self.re * other.im),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_reflectance_of_glass_is_four_percent() {
        // ((η − 1)/(η + 1))² = (0.5/2.5)² = 0.04.
        assert!((fresnel_dielectric(1.0, 1.5) - 0.04).abs() < 1e-7);
        assert!((fresnel_dielectric(-1.0, 1.5) - 0.04).abs() < 1e-7);
        assert_eq!(fresnel_dielectric(0.7, 1.0), 0.0);
        assert!((fresnel_dielectric(0.0, 1.5) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn brewster_angle_has_no_p_polarised_reflection() {
        // At tan θ_B = η the p component vanishes, so F = r_s²/2 with
        // r_s = (cos θi − η cos θt)/(cos θi + η cos θt) and θt = 90° − θB.
        let eta = 1.5_f32;
        let theta_b = eta.atan();
        let (cos_i, cos_t) = (theta_b.cos(), theta_b.sin());
        let r_s = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
        assert!((fresnel_dielectric(cos_i, eta) - 0.5 * r_s * r_s).abs() < 1e-6);
    }

    #[test]
    fn total_internal_reflection_beyond_the_critical_angle() {
        let eta = 1.5_f32;
        let critical_sin = 1.0 / eta;
        let cos_beyond = -(1.0 - (critical_sin + 0.01).powi(2)).sqrt();
        assert_eq!(fresnel_dielectric(cos_beyond, eta), 1.0);
        let cos_before = -(1.0 - (critical_sin - 0.01).powi(2)).sqrt();
        assert!(fresnel_dielectric(cos_before, eta) < 1.0);
        let sin = critical_sin + 0.01;
        let below = Vec3::new(sin, 0.0, -(1.0 - sin * sin).sqrt());
        assert!(refract(below, eta).is_none());
    }

    #[test]
    fn refraction_obeys_snell() {
        let eta = 1.33_f32;
        let sin_i = 0.6_f32;
        let wi = Vec3::new(sin_i, 0.0, 0.8);
        let refraction = refract(wi, eta).unwrap();
        let wt = refraction.direction;
        assert!((wt.length() - 1.0).abs() < 1e-6);
        assert!(wt.z < 0.0);
        assert!(
            (wt.x + sin_i / eta).abs() < 1e-6,
            "tangential component flips"
        );
        assert_eq!(refraction.relative_eta, eta);
        // And back: refracting the transmitted direction returns wi (reversibility).
        let back = refract(wt, eta).unwrap();
        assert!((back.direction - wi).length() < 1e-6);
        assert!((back.relative_eta - 1.0 / eta).abs() < 1e-7);
        // Index matching passes straight through.
        assert!((refract(wi, 1.0).unwrap().direction + wi).length() < 1e-6);
    }

    #[test]
    fn conductor_with_no_extinction_is_a_dielectric() {
        for eta in [1.2_f32, 1.5, 2.4] {
            for step in 0..=20 {
                let cos = step as f32 / 20.0;
                let dielectric = fresnel_dielectric(cos, eta);
                let conductor = fresnel_complex(cos, eta, 0.0);
                assert!((dielectric - conductor).abs() < 1e-5, "{eta} {cos}");
            }
        }
    }

    #[test]
    fn conductor_normal_incidence_closed_form() {
        // F(0) = ((η − 1)² + κ²) / ((η + 1)² + κ²).
        for (eta, k) in [(0.2_f32, 3.0_f32), (1.1, 2.6), (0.27, 2.78), (2.0, 0.5)] {
            let expected = ((eta - 1.0).powi(2) + k * k) / ((eta + 1.0).powi(2) + k * k);
            assert!((fresnel_complex(1.0, eta, k) - expected).abs() < 1e-6);
        }
        assert_eq!(fresnel_complex(0.5, 0.0, 0.0), 1.0);
        assert!(
            (fresnel_complex(0.0, 0.2, 3.0) - 1.0).abs() < 1e-6,
            "grazing"
        );
    }

    #[test]
    fn diffuse_fresnel_fits_match_the_integral() {
        // 2 ∫ F(μ) μ dμ by the midpoint rule; the fits are good to ~1 %
        // for these indices.
        for eta in [1.0 / 1.5, 1.0 / 1.33, 1.33, 1.5] {
            let steps = 100_000;
            let integral: f64 = (0..steps)
                .map(|i| {
                    let mu = (i as f64 + 0.5) / steps as f64;
                    2.0 * f64::from(fresnel_dielectric(mu as f32, eta)) * mu / steps as f64
                })
                .sum();
            let fit = f64::from(fresnel_diffuse_reflectance(eta));
            assert!(
                (fit - integral).abs() < 0.01 * integral.max(0.05),
                "{eta}: {fit} vs {integral}"
            );
        }
        // Mitsuba 3.9.1's values (mi.fresnel_diffuse_reflectance).
        assert!((fresnel_diffuse_reflectance(1.5) - 0.091_774_28).abs() < 1e-6);
        assert!((fresnel_diffuse_reflectance(1.0 / 1.5) - 0.596_811_06).abs() < 1e-6);
    }

    #[test]
    fn complex_square_root_is_principal() {
        for (re, im) in [
            (4.0_f32, 0.0_f32),
            (-4.0, 0.0),
            (-4.0, -0.0),
            (3.0, 4.0),
            (-3.0, -4.0),
        ] {
            let root = Complex::new(re, im).sqrt();
            assert!(root.re >= 0.0);
            let square = root * root;
            assert!((square.re - re).abs() < 1e-5 && (square.im - im).abs() < 1e-5);
        }
    }
}
