//! Phase functions: the angular distribution of light scattered in a
//! medium, with importance sampling and the density of a direction.
//!
//! Conventions follow [`crate::material`]: `wo` points from the scattering
//! point back towards the previous vertex (the negated ray direction), `wi`
//! towards the next one. A phase function is normalised over the sphere, so
//! for the functions here its value and its sampling density are equal.

use crate::geometry::coordinate_frame;
use glam::Vec3;
use std::f32::consts::PI;

/// Below this |g| Henyey–Greenstein is sampled as isotropic (the inversion
/// formula divides by g).
const ISOTROPIC_G_THRESHOLD: f32 = 1e-3;

/// A phase function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PhaseFunction {
    /// The same density, 1/(4π), in every direction.
    Isotropic,
    /// Henyey & Greenstein (1941): p(θ) = (1 − g²) / (4π (1 + g² − 2g cos θ)^{3/2}),
    /// θ the angle between the incoming propagation direction (−wo) and wi;
    /// g ∈ (−1, 1) is the mean cosine (g > 0 scatters forward).
    HenyeyGreenstein { g: f32 },
}

/// A direction sampled from a phase function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PhaseSample {
    /// The sampled direction (unit length).
    pub wi: Vec3,
    /// The phase function's value p(wo, wi).
    pub value: f32,
    /// The density of `wi` per unit solid angle (equal to `value` here).
    pub pdf: f32,
}

impl PhaseFunction {
    /// Henyey–Greenstein with `g` clamped into (−1, 1) (|g| ≤ 0.999, since
    /// the density becomes a delta at ±1).
    pub fn henyey_greenstein(g: f32) -> Self {
        PhaseFunction::HenyeyGreenstein {
            g: g.clamp(-0.999, 0.999),
        }
    }

    /// p(wo, wi) per unit solid angle.
    pub fn evaluate(&self, wo: Vec3, wi: Vec3) -> f32 {
        match *self {
            PhaseFunction::Isotropic => 1.0 / (4.0 * PI),
            PhaseFunction::HenyeyGreenstein { g } => henyey_greenstein(-wo.dot(wi), g),
        }
    }

    /// The density with which [`Self::sample`] produces `wi` (equal to
    /// [`Self::evaluate`], since sampling is exact).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.evaluate(wo, wi)
    }

    /// Samples `wi` from p(wo, ·) with two uniform numbers `u` (exact
    /// inversion of the cosine's distribution; the azimuth is uniform).
    pub fn sample(&self, wo: Vec3, u: [f32; 2]) -> PhaseSample {
        let cos_theta = match *self {
            PhaseFunction::Isotropic => 1.0 - 2.0 * u[0],
            PhaseFunction::HenyeyGreenstein { g } => {
                if g.abs() < ISOTROPIC_G_THRESHOLD {
                    1.0 - 2.0 * u[0]
                } else {
                    // Inverse of the cumulative distribution of cos θ
                    // (pbrt-v4, 4th ed., §11.3.1, written for the angle to
                    // the propagation direction).
                    let square = (1.0 - g * g) / (1.0 + g - 2.0 * g * u[0]);
                    (1.0 + g * g - square * square) / (2.0 * g)
                }
            }
        }
        .clamp(-1.0, 1.0);
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        let forward = -wo;
        let (s, t) = coordinate_frame(forward);
        let wi = (s * (sin_theta * phi.cos()) + t * (sin_theta * phi.sin()) + forward * cos_theta)
            .normalize();
        let value = self.evaluate(wo, wi);
        PhaseSample {
            wi,
            value,
            pdf: value,
        }
    }
}

/// The Henyey–Greenstein density for the cosine of the angle between the
/// propagation directions before and after scattering.
fn henyey_greenstein(cos_theta: f32, g: f32) -> f32 {
    let denominator = 1.0 + g * g - 2.0 * g * cos_theta;
    (1.0 - g * g) / (4.0 * PI * denominator * denominator.max(1e-12).sqrt())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::statistics::chi_square_test;

    /// SplitMix64 for test inputs.
    fn uniforms(count: usize, seed: u64) -> Vec<[f32; 2]> {
        let mut state = seed;
        let mut next = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
        };
        (0..count).map(|_| [next(), next()]).collect()
    }

    const PHASES: [PhaseFunction; 5] = [
        PhaseFunction::Isotropic,
        PhaseFunction::HenyeyGreenstein { g: 0.0 },
        PhaseFunction::HenyeyGreenstein { g: 0.3 },
        PhaseFunction::HenyeyGreenstein { g: -0.7 },
        PhaseFunction::HenyeyGreenstein { g: 0.9 },
    ];

    /// Chi-square test of the sampled directions against the density,
    /// integrated numerically over a (cos θ, φ) grid around wo.
    #[test]
    fn sampling_matches_the_density_chi_square() {
        let wo = Vec3::new(0.3, -0.5, 0.8).normalize();
        let (s, t) = coordinate_frame(-wo);
        let (cos_bins, phi_bins) = (20usize, 10usize);
        for phase in PHASES {
            let count = 200_000;
            let mut observed = vec![0u64; cos_bins * phi_bins];
            for u in uniforms(count, 7) {
                let sample = phase.sample(wo, u);
                assert!((sample.wi.length() - 1.0).abs() < 1e-4);
                assert!((sample.value - sample.pdf).abs() <= 1e-6 * sample.pdf);
                let cos_theta = sample.wi.dot(-wo).clamp(-1.0, 1.0);
                let phi = sample
                    .wi
                    .dot(t)
                    .atan2(sample.wi.dot(s))
                    .rem_euclid(2.0 * PI);
                let i = (((cos_theta + 1.0) / 2.0 * cos_bins as f32) as usize).min(cos_bins - 1);
                let j = ((phi / (2.0 * PI) * phi_bins as f32) as usize).min(phi_bins - 1);
                observed[i * phi_bins + j] += 1;
            }
            // Expected counts: Simpson's rule over each bin (cos θ, φ), fine
            // in cos θ for the narrow peak of g = 0.9.
            let mut expected = vec![0.0f64; cos_bins * phi_bins];
            let (cos_steps, phi_steps) = (256usize, 4usize);
            let weight = |k: usize, steps: usize| -> f64 {
                if k == 0 || k == steps {
                    1.0
                } else if k % 2 == 1 {
                    4.0
                } else {
                    2.0
                }
            };
            for i in 0..cos_bins {
                for j in 0..phi_bins {
                    let mut integral = 0.0f64;
                    for a in 0..=cos_steps {
                        for b in 0..=phi_steps {
                            let c = -1.0
                                + 2.0 * (i as f64 + a as f64 / cos_steps as f64) / cos_bins as f64;
                            let p = 2.0
                                * std::f64::consts::PI
                                * (j as f64 + b as f64 / phi_steps as f64)
                                / phi_bins as f64;
                            let sine = (1.0 - c * c).max(0.0).sqrt();
                            let wi = s * (sine * p.cos()) as f32
                                + t * (sine * p.sin()) as f32
                                + (-wo) * c as f32;
                            integral += weight(a, cos_steps)
                                * weight(b, phi_steps)
                                * phase.evaluate(wo, wi) as f64;
                        }
                    }
                    let area =
                        (2.0 / cos_bins as f64) * (2.0 * std::f64::consts::PI / phi_bins as f64);
                    expected[i * phi_bins + j] =
                        integral * area / (9.0 * (cos_steps * phi_steps) as f64) * count as f64;
                }
            }
            let total: f64 = expected.iter().sum();
            assert!(
                (total / count as f64 - 1.0).abs() < 1e-3,
                "{phase:?}: ∫p = {}",
                total / count as f64
            );
            let result = chi_square_test(&observed, &expected);
            assert!(result.p_value > 1e-4, "{phase:?}: {result:?}");
        }
    }

    /// The density integrates to 1 and its mean cosine is g.
    #[test]
    fn density_is_normalised_with_mean_cosine_g() {
        let wo = Vec3::Z;
        for phase in PHASES {
            let steps = 20_000;
            let (mut total, mut mean_cosine) = (0.0f64, 0.0f64);
            for k in 0..steps {
                let c = -1.0 + 2.0 * (k as f64 + 0.5) / steps as f64;
                let wi = Vec3::new((1.0 - c * c).sqrt() as f32, 0.0, -c as f32);
                let p =
                    phase.evaluate(wo, wi) as f64 * 2.0 * std::f64::consts::PI * 2.0 / steps as f64;
                total += p;
                mean_cosine += p * c;
            }
            let g = match phase {
                PhaseFunction::Isotropic => 0.0,
                PhaseFunction::HenyeyGreenstein { g } => g as f64,
            };
            assert!((total - 1.0).abs() < 2e-3, "{phase:?}: {total}");
            assert!((mean_cosine - g).abs() < 2e-3, "{phase:?}: {mean_cosine}");
        }
    }

    #[test]
    fn forward_scattering_peaks_along_the_propagation_direction() {
        let phase = PhaseFunction::henyey_greenstein(0.8);
        let wo = Vec3::Z;
        assert!(phase.evaluate(wo, -Vec3::Z) > phase.evaluate(wo, Vec3::Z));
        assert_eq!(
            PhaseFunction::henyey_greenstein(2.0),
            PhaseFunction::HenyeyGreenstein { g: 0.999 }
        );
    }
}
