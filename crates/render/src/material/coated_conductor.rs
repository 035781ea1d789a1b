//! [`CoatedConductorBsdf`]: pbrt-v4's `coatedconductor`, a conductor base
//! under a dielectric coating with an optional scattering medium between
//! them (pbrt-v4, 4th ed., §14.3; the `CoatedConductorBxDF` is the
//! `LayeredBxDF` with a dielectric top and a conductor bottom). Implemented
//! from the book's description: the random walks, their determinism and
//! the MIS density estimate are those of [`super::layered`], with a smooth
//! ([`ConductorBsdf`]) or rough ([`RoughConductorBsdf`], GGX) conductor as
//! the bottom interface.
//!
//! The conductor lies under the coating, so its complex index is relative
//! to the coating's: pbrt-v4 divides the conductor's η and κ by the
//! interface's η (`CoatedConductorMaterial::GetBxDF`); callers pass the
//! already divided values ([`super::Material::CoatedConductor`] does).
//!
//! With a smooth coating over a smooth conductor and a clear layer every
//! path through the layer is a chain of deltas: [`CoatedConductorBsdf::evaluate`]
//! and [`CoatedConductorBsdf::pdf`] see none of it (evaluate is 0, the
//! density only the uniform floor of the estimate), and the samples are
//! delta samples (specular flags, not proportional densities).

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::conductor::{ConductorBsdf, ConductorReflectance};
use super::flags::{BsdfFlags, TransportMode};
use super::layered::{LayerBase, LayeredBsdf};
use super::microfacet::MicrofacetDistribution;
use super::rough_conductor::RoughConductorBsdf;
use crate::spectrum::SampledSpectrum;

/// The conductor at the bottom of the layer, seen from inside it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) enum ConductorBase {
    Smooth(ConductorBsdf),
    Rough(RoughConductorBsdf),
}

impl ConductorBase {
    /// A conductor of Fresnel `reflectance` (relative to the coating),
    /// rough with `distribution` unless it is `None` or effectively smooth.
    fn new(
        reflectance: ConductorReflectance,
        distribution: Option<MicrofacetDistribution>,
    ) -> Self {
        match distribution.filter(|d| !d.is_effectively_smooth()) {
            Some(distribution) => ConductorBase::Rough(RoughConductorBsdf::new(
                distribution,
                reflectance,
                SampledSpectrum::splat(1.0),
                true,
            )),
            None => ConductorBase::Smooth(match reflectance {
                ConductorReflectance::Perfect => ConductorBsdf::perfect_mirror(),
                ConductorReflectance::Fresnel { eta, k } => ConductorBsdf::new_unchecked(eta, k),
            }),
        }
    }
}

impl LayerBase for ConductorBase {
    fn evaluate(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        match self {
            ConductorBase::Smooth(smooth) => smooth.evaluate(wo, wi),
            ConductorBase::Rough(rough) => rough.evaluate(wo, wi),
        }
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            ConductorBase::Smooth(smooth) => smooth.pdf(wo, wi),
            ConductorBase::Rough(rough) => rough.pdf(wo, wi),
        }
    }

    fn sample(&self, wo: Vec3, _u_component: f32, u: [f32; 2]) -> Option<BsdfSample> {
        match self {
            ConductorBase::Smooth(smooth) => smooth.sample(wo),
            ConductorBase::Rough(rough) => rough.sample(wo, u),
        }
    }

    fn is_specular(&self) -> bool {
        matches!(self, ConductorBase::Smooth(_))
    }

    fn flags(&self) -> BsdfFlags {
        match self {
            ConductorBase::Smooth(smooth) => smooth.flags(),
            ConductorBase::Rough(rough) => rough.flags(),
        }
    }

    fn roughness(&self) -> f32 {
        match self {
            ConductorBase::Smooth(_) => 0.0,
            ConductorBase::Rough(rough) => rough.distribution().roughness(),
        }
    }
}

/// pbrt-v4's `coatedconductor` at a hit, for a path's wavelengths.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoatedConductorBsdf {
    layered: LayeredBsdf<ConductorBase>,
}

impl CoatedConductorBsdf {
    /// A conductor of Fresnel `conductor` reflectance (η and κ relative to
    /// the coating), rough with `conductor_distribution` or smooth for
    /// `None`, under a coating of relative index `interface_eta` (> 0),
    /// rough with `interface_distribution` or smooth, over a layer of
    /// optical thickness `thickness` (clamped to at least the smallest
    /// positive f32) whose medium has albedo `albedo` and Henyey–Greenstein
    /// asymmetry `g`. Walks take at most `max_depth` (≥ 1) events;
    /// `samples` (≥ 1) walks are averaged per call.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        interface_eta: f32,
        interface_distribution: Option<MicrofacetDistribution>,
        conductor: ConductorReflectance,
        conductor_distribution: Option<MicrofacetDistribution>,
        thickness: f32,
        albedo: SampledSpectrum,
        g: f32,
        max_depth: u32,
        samples: u32,
    ) -> Self {
        Self {
            layered: LayeredBsdf::new(
                interface_eta,
                interface_distribution,
                ConductorBase::new(conductor, conductor_distribution),
                thickness,
                albedo,
                g,
                max_depth,
                samples,
            ),
        }
    }

    /// The coating's microfacet distribution (`None` if smooth).
    pub fn interface_distribution(&self) -> Option<&MicrofacetDistribution> {
        self.layered.distribution()
    }

    /// An unbiased estimate of f(wo, wi) (without the cosine factor).
    pub fn evaluate(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        self.layered.evaluate(wo, wi, mode)
    }

    /// pbrt-v4's estimate of the sampling density, for MIS weights: not
    /// normalised, but the same for the same directions.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.layered.pdf(wo, wi)
    }

    /// Samples the coating; a transmission continues as a random walk until
    /// it leaves through the top (see [`super::CoatedDiffuseBsdf::sample`]).
    pub fn sample(
        &self,
        wo: Vec3,
        u_component: f32,
        u: [f32; 2],
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        self.layered.sample(wo, u_component, u, mode)
    }

    /// Reflection: specular for a smooth coating, glossy for a rough
    /// coating or conductor, diffuse if the medium scatters.
    pub fn flags(&self) -> BsdfFlags {
        self.layered.flags()
    }

    /// The effective roughness for LQMC: the smaller α of coating and
    /// conductor (0 if either is smooth).
    pub fn roughness(&self) -> f32 {
        self.layered.roughness()
    }
}

#[cfg(test)]
mod tests {
    use super::super::layered::test_support::*;
    use super::*;
    use crate::material::fresnel::{fresnel_complex, fresnel_dielectric, refract};
    use crate::material::{MicrofacetKind, abs_cos_theta};

    fn ggx(alpha: f32) -> MicrofacetDistribution {
        MicrofacetDistribution::new(MicrofacetKind::Ggx, alpha, alpha)
    }

    /// A gold-like conductor relative to a coating of index 1.5 (η 0.2,
    /// κ 3.0 in air, divided by 1.5).
    fn gold_under_coating() -> ConductorReflectance {
        ConductorReflectance::Fresnel {
            eta: SampledSpectrum::splat(0.2 / 1.5),
            k: SampledSpectrum::splat(3.0 / 1.5),
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn coated(
        interface_alpha: Option<f32>,
        conductor: ConductorReflectance,
        conductor_alpha: Option<f32>,
        thickness: f32,
        albedo: f32,
        g: f32,
        max_depth: u32,
    ) -> CoatedConductorBsdf {
        CoatedConductorBsdf::new(
            1.5,
            interface_alpha.map(ggx),
            conductor,
            conductor_alpha.map(ggx),
            thickness,
            SampledSpectrum::splat(albedo),
            g,
            max_depth,
            1,
        )
    }

    /// Cases with something to evaluate (at least one rough interface or a
    /// scattering medium).
    fn cases() -> Vec<(&'static str, CoatedConductorBsdf)> {
        let gold = gold_under_coating();
        vec![
            (
                "smooth coating, rough gold",
                coated(None, gold, Some(0.3), 0.01, 0.0, 0.0, 10),
            ),
            (
                "rough coating, smooth gold",
                coated(Some(0.3), gold, None, 0.01, 0.0, 0.0, 10),
            ),
            (
                "rough coating, rough gold",
                coated(Some(0.2), gold, Some(0.4), 0.01, 0.0, 0.0, 10),
            ),
            (
                "rough coating, rough gold, scattering",
                coated(Some(0.25), gold, Some(0.3), 0.4, 0.7, 0.4, 10),
            ),
            // Deep walks: light leaving at grazing angles makes many round
            // trips, which evaluation (next-event estimates plus the summed
            // delta chains) counts beyond `max_depth` and sampling does not.
            (
                "smooth coating, smooth gold, scattering",
                coated(None, gold, None, 0.4, 0.7, -0.3, 100),
            ),
        ]
    }

    #[test]
    fn smooth_over_smooth_and_clear_has_the_closed_form_albedo() {
        // Every path is a delta; with R = F(μo) at the coating, T the
        // layer's transmittance e^(−τ/μt) along the refracted cosine μt and
        // Fc the conductor's reflectance at μt, the internal reflections sum
        // to A = R + (1 − R)² Fc T² / (1 − R Fc T²) (the coating reflects F
        // from inside too, at μt). A perfect mirror with τ → 0 reflects all
        // (A = 1).
        let eta = 1.5f32;
        for (conductor, thickness) in [
            (ConductorReflectance::Perfect, 0.0f32),
            (ConductorReflectance::Perfect, 0.3),
            (gold_under_coating(), 0.0),
            (gold_under_coating(), 0.2),
        ] {
            let bsdf = coated(None, conductor, None, thickness, 0.0, 0.0, 400);
            for cos in [0.95f32, 0.5, 0.15] {
                let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                let reflected = f64::from(fresnel_dielectric(cos, eta));
                let mu_t = refract(wo, eta).unwrap().direction.z.abs();
                let fc = match conductor {
                    ConductorReflectance::Perfect => 1.0,
                    ConductorReflectance::Fresnel { eta, k } => {
                        f64::from(fresnel_complex(mu_t, eta[0], k[0]))
                    }
                };
                let t2 = f64::from((-2.0 * thickness.max(f32::MIN_POSITIVE) / mu_t).exp());
                let exact =
                    reflected + (1.0 - reflected).powi(2) * fc * t2 / (1.0 - reflected * fc * t2);
                let (albedo, error) = sampled_integral(&bsdf.layered, wo, 20_000, 7, |_| 1.0);
                eprintln!(
                    "{conductor:?}, τ {thickness}, cos θo {cos}: albedo {albedo:.5} ± {error:.5}, closed form {exact:.5}"
                );
                assert!(
                    (albedo - exact).abs() < 4.0 * error + 1e-4,
                    "{albedo} ± {error} vs {exact}"
                );
                assert!(albedo <= 1.0 + 1e-4);
                let wi = Vec3::new(-0.3, 0.2, 0.9).normalize();
                assert!(bsdf.evaluate(wo, wi, TransportMode::Radiance).is_black());
                let sample = bsdf
                    .sample(wo, 0.9, [0.3, 0.6], TransportMode::Radiance)
                    .unwrap();
                assert!(sample.is_specular() && !sample.pdf_is_proportional);
            }
            assert!(bsdf.flags().is_specular() && !bsdf.flags().is_non_specular());
        }
    }

    #[test]
    fn rough_coatings_over_a_perfect_mirror_lose_only_the_microfacet_energy() {
        // A perfect mirror under a clear layer of thickness 0: all energy
        // losses are the rough coating's single-scattering ones, small for a
        // small α, and sampling agrees with evaluation.
        let mut previous = [1.0 + 1e-3; 2];
        for alpha in [0.1f32, 0.3, 0.6] {
            let bsdf = coated(
                Some(alpha),
                ConductorReflectance::Perfect,
                None,
                0.0,
                0.0,
                0.0,
                200,
            );
            for (index, cos) in [0.9f32, 0.4].into_iter().enumerate() {
                let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                let (albedo, error) = sampled_integral(&bsdf.layered, wo, 20_000, 8, |_| 1.0);
                let (evaluated, evaluated_error) =
                    evaluated_integral(&bsdf.layered, wo, 40_000, 9, |_| 1.0);
                eprintln!(
                    "mirror under α {alpha}, cos θo {cos}: albedo {albedo:.4} ± {error:.4}, evaluated {evaluated:.4} ± {evaluated_error:.4}"
                );
                let sigma = (error.powi(2) + evaluated_error.powi(2)).sqrt();
                assert!((albedo - evaluated).abs() < 4.0 * sigma + 2e-3);
                assert!(albedo <= previous[index] + 4.0 * error, "{albedo}");
                assert!(albedo > 0.3, "{albedo}");
                previous[index] = albedo;
            }
        }
    }

    #[test]
    fn sample_weights_match_evaluation() {
        let wo = Vec3::new(0.5, 0.1, 0.8).normalize();
        for (name, bsdf) in cases() {
            assert_sampling_matches_evaluation(name, &bsdf.layered, wo, 40_000);
        }
    }

    /// Not for a rough coating over a smooth conductor: there the only
    /// estimate of leaving is f_exit along the mirror's direction, whose
    /// 1/|cos θ| factor (the inside direction, grazing for light trapped by
    /// total internal reflection) gives the evaluation an unbounded
    /// variance, so the per-cell variances the statistic divides by are
    /// unreliable (that case is checked by the mean weight against the mean
    /// evaluation, with the evaluation's large error, and by reciprocity).
    #[test]
    fn sampling_passes_a_weighted_chi_square_test() {
        for cos in [0.9f32, 0.3] {
            let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
            for (name, bsdf) in cases() {
                if name == "rough coating, smooth gold" {
                    continue;
                }
                eprint!("{name}, cos θo {cos}: ");
                let p = weighted_chi_square(&bsdf.layered, wo, 8, 100_000, 400, 63);
                assert!(p > P_VALUE_THRESHOLD, "{name}, cos θo {cos}: p = {p}");
            }
        }
    }

    #[test]
    fn evaluation_is_reciprocal_in_expectation() {
        for (name, bsdf) in cases() {
            assert_reciprocal(name, &bsdf.layered);
        }
    }

    #[test]
    fn energy_never_exceeds_one() {
        for (name, bsdf) in cases() {
            for cos in [0.95f32, 0.5, 0.1] {
                let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
                let (albedo, error) = sampled_integral(&bsdf.layered, wo, 20_000, 10, |_| 1.0);
                eprintln!("{name}, cos θo {cos}: albedo {albedo:.4} ± {error:.4}");
                assert!(albedo <= 1.0 + 4.0 * error, "{name}: {albedo} ± {error}");
            }
        }
    }

    #[test]
    fn queries_are_deterministic_two_sided_and_flagged() {
        for (name, bsdf) in cases() {
            let wo = Vec3::new(0.3, 0.4, 0.866).normalize();
            let wi = Vec3::new(-0.2, 0.5, 0.84).normalize();
            let mode = TransportMode::Radiance;
            assert_eq!(bsdf.evaluate(wo, wi, mode), bsdf.evaluate(wo, wi, mode));
            assert_eq!(bsdf.evaluate(wo, wi, mode), bsdf.evaluate(-wo, -wi, mode));
            assert!(bsdf.evaluate(wo, -wi, mode).is_black());
            let pdf = bsdf.pdf(wo, wi);
            assert!(pdf > 0.0 && pdf == bsdf.pdf(-wo, -wi), "{name}: {pdf}");
            assert!(bsdf.flags().is_non_specular(), "{name}");
            for u_component in [0.01, 0.3, 0.7, 0.95] {
                let sample = bsdf.sample(wo, u_component, [0.2, 0.9], mode);
                assert_eq!(sample, bsdf.sample(wo, u_component, [0.2, 0.9], mode));
                if let Some(sample) = sample {
                    assert!(sample.wi.z > 0.0 && abs_cos_theta(sample.wi) <= 1.0);
                }
            }
        }
        let rough = coated(
            Some(0.3),
            gold_under_coating(),
            Some(0.5),
            0.01,
            0.0,
            0.0,
            10,
        );
        assert!((rough.roughness() - 0.3).abs() < 1e-6);
        assert!(rough.interface_distribution().is_some());
    }
}
