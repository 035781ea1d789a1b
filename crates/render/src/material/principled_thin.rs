//! [`PrincipledThinBsdf`]: Mitsuba 3's `principledthin`, the thin-surface
//! variant of the Disney BSDF (Burley 2015, §5.4), with the lobe formulas of
//! Mitsuba 3.9.1's plugin (formulas only).
//!
//! The sheet has no inside: both sides scatter alike (directions are
//! mirrored so that `wo` is above). With h = normalize(wo + wi_r), wi_r the
//! light direction mirrored to `wo`'s side, F = F(wo·h, η),
//! dt = diff_trans/2 and st = spec_trans, f (without cosine) is the sum of
//!
//! - specular reflection st F_t D G / (4 cos θo |cos θi|), GGX as in
//!   [`super::PrincipledBsdf`], F_t = lerp(F, Schlick(c_tint R0(η)),
//!   spec_tint);
//! - specular transmission st base (1 − F) D' G' / (4 cos θo |cos θi|), the
//!   reflection lobe turned to the other side with the roughness scaled by
//!   (0.65 η − 0.35) (Burley 2015, fig. 15);
//! - diffuse reflection (1 − st)(1 − dt) base/π · lerp(f_diff + f_retro,
//!   f_ss, flatness) and sheen (1 − st)(1 − dt) sheen c_sheen (1 − cos θd)⁵;
//! - diffuse transmission (1 − st) dt base/π.
//!
//! Sampling chooses among the four with weights st w_sr/2, st w_st/2,
//! (1 − st)(1 − dt) w_dr and (1 − st) dt w_dt (the sampling rates w).

use std::f32::consts::FRAC_1_PI;

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::flags::BsdfFlags;
use super::fresnel::fresnel_dielectric;
use super::microfacet::MicrofacetDistribution;
use super::principled::{
    diffuse_shape, microfacet_compatible, schlick_fresnel, schlick_r0, schlick_weight, sheen_color,
    spectral_luminance, specular_distribution, tint_color,
};
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// The parameters of a thin principled BSDF at one hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipledThinParameters {
    /// Colour of diffuse and transmitted light.
    pub base_color: SampledSpectrum,
    /// Roughness r (α = r²).
    pub roughness: f32,
    /// Degree of anisotropy.
    pub anisotropic: f32,
    /// Blend from diffuse to specular scattering.
    pub spec_trans: f32,
    /// Relative index of refraction of the sheet.
    pub eta: f32,
    /// Tint of the specular reflection towards the base colour.
    pub spec_tint: f32,
    /// Weight of the sheen.
    pub sheen: f32,
    /// Tint of the sheen.
    pub sheen_tint: f32,
    /// Blend from diffuse to fake subsurface.
    pub flatness: f32,
    /// Diffuse transmission in [0, 2] (Mitsuba's range; halved here).
    pub diff_trans: f32,
    /// Relative sampling weights of the four lobes.
    pub specular_reflectance_sampling_rate: f32,
    pub specular_transmittance_sampling_rate: f32,
    pub diffuse_reflectance_sampling_rate: f32,
    pub diffuse_transmittance_sampling_rate: f32,
}

impl PrincipledThinParameters {
    /// Mitsuba's defaults: roughness 0.5, η = 1.5, other weights 0, rates 1.
    pub fn new(base_color: SampledSpectrum) -> Self {
        Self {
            base_color,
            roughness: 0.5,
            anisotropic: 0.0,
            spec_trans: 0.0,
            eta: 1.5,
            spec_tint: 0.0,
            sheen: 0.0,
            sheen_tint: 0.0,
            flatness: 0.0,
            diff_trans: 0.0,
            specular_reflectance_sampling_rate: 1.0,
            specular_transmittance_sampling_rate: 1.0,
            diffuse_reflectance_sampling_rate: 1.0,
            diffuse_transmittance_sampling_rate: 1.0,
        }
    }
}

/// The normalised lobe weights of the sampling mixture.
struct LobeProbabilities {
    specular_reflection: f32,
    specular_transmission: f32,
    diffuse_reflection: f32,
    diffuse_transmission: f32,
}

/// Mitsuba's thin principled BSDF at one hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipledThinBsdf {
    parameters: PrincipledThinParameters,
    reflection_distribution: MicrofacetDistribution,
    transmission_distribution: MicrofacetDistribution,
    luminance: f32,
}

impl PrincipledThinBsdf {
    /// The BSDF of `parameters` for the path's `wavelengths`.
    pub fn new(parameters: PrincipledThinParameters, wavelengths: &SampledWavelengths) -> Self {
        let p = &parameters;
        let scaled_roughness = (0.65 * p.eta - 0.35) * p.roughness;
        let needs_luminance = p.spec_tint != 0.0 || p.sheen_tint != 0.0;
        Self {
            reflection_distribution: specular_distribution(p.roughness, p.anisotropic),
            transmission_distribution: specular_distribution(scaled_roughness, p.anisotropic),
            luminance: if needs_luminance {
                spectral_luminance(p.base_color, wavelengths)
            } else {
                1.0
            },
            parameters,
        }
    }

    /// The parameters.
    pub fn parameters(&self) -> &PrincipledThinParameters {
        &self.parameters
    }

    fn diffuse_transmission(&self) -> f32 {
        0.5 * self.parameters.diff_trans
    }

    /// `wo` and `wi` mirrored so that `wo` is above, and the half vector of
    /// `wo` and `wi` mirrored to its side.
    fn oriented(wo: Vec3, wi: Vec3) -> Option<(Vec3, Vec3, Vec3)> {
        if wo.z == 0.0 {
            return None;
        }
        let sign = wo.z.signum();
        let (wo, wi) = (wo * sign, wi * sign);
        let half = (wo + Vec3::new(wi.x, wi.y, wi.z.abs())).normalize();
        half.is_finite().then_some((wo, wi, half))
    }

    /// f(wo, wi) without the cosine factor.
    pub fn evaluate(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        let Some((wo, wi, half)) = Self::oriented(wo, wi) else {
            return SampledSpectrum::zero();
        };
        let p = &self.parameters;
        let (cos_o, cos_i) = (wo.z, wi.z.abs());
        let reflection = wi.z > 0.0;
        if wi.z == 0.0 {
            return SampledSpectrum::zero();
        }
        let diffuse_transmission = self.diffuse_transmission();
        let mut value = SampledSpectrum::zero();
        if p.spec_trans > 0.0 && microfacet_compatible(half, wo, wi, reflection) {
            let fresnel = fresnel_dielectric(wo.dot(half), p.eta);
            if reflection {
                let distribution = &self.reflection_distribution;
                let d = distribution.d(half);
                let g = distribution.g(wo, wi, half);
                let mut tinted = SampledSpectrum::splat(fresnel * (1.0 - p.spec_tint));
                if p.spec_tint != 0.0 {
                    let r0 = tint_color(p.base_color, self.luminance) * schlick_r0(p.eta);
                    tinted += schlick_fresnel(r0, wo.dot(half), p.eta) * p.spec_tint;
                }
                value += tinted * (p.spec_trans * d * g / (4.0 * cos_o * cos_i));
            } else {
                let distribution = &self.transmission_distribution;
                let d = distribution.d(half);
                let g = distribution.g(wo, wi, half);
                value +=
                    p.base_color * (p.spec_trans * (1.0 - fresnel) * d * g / (4.0 * cos_o * cos_i));
            }
        }
        if reflection && p.spec_trans < 1.0 && diffuse_transmission < 1.0 {
            let weight = (1.0 - p.spec_trans) * (1.0 - diffuse_transmission);
            let cos_d = half.dot(wi);
            let shape = diffuse_shape(cos_o, cos_i, cos_d, p.roughness, p.flatness);
            value += p.base_color * (weight * FRAC_1_PI * shape);
            if p.sheen > 0.0 {
                let color = if p.sheen_tint != 0.0 {
                    sheen_color(tint_color(p.base_color, self.luminance), p.sheen_tint)
                } else {
                    SampledSpectrum::splat(1.0)
                };
                value += color * (p.sheen * weight * schlick_weight(cos_d.abs()));
            }
        }
        if !reflection && p.spec_trans < 1.0 && diffuse_transmission > 0.0 {
            value += p.base_color * ((1.0 - p.spec_trans) * diffuse_transmission * FRAC_1_PI);
        }
        value
    }

    fn lobe_probabilities(&self) -> Option<LobeProbabilities> {
        let p = &self.parameters;
        let diffuse_transmission = self.diffuse_transmission();
        let specular_reflection = 0.5 * p.spec_trans * p.specular_reflectance_sampling_rate;
        let specular_transmission = 0.5 * p.spec_trans * p.specular_transmittance_sampling_rate;
        let diffuse_reflection = p.diffuse_reflectance_sampling_rate
            * (1.0 - p.spec_trans)
            * (1.0 - diffuse_transmission);
        let diffuse_transmission =
            p.diffuse_transmittance_sampling_rate * (1.0 - p.spec_trans) * diffuse_transmission;
        let total =
            specular_reflection + specular_transmission + diffuse_reflection + diffuse_transmission;
        (total > 0.0 && total.is_finite()).then(|| LobeProbabilities {
            specular_reflection: specular_reflection / total,
            specular_transmission: specular_transmission / total,
            diffuse_reflection: diffuse_reflection / total,
            diffuse_transmission: diffuse_transmission / total,
        })
    }

    /// The density with which [`Self::sample`] produces `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some((wo, wi, half)) = Self::oriented(wo, wi) else {
            return 0.0;
        };
        if wi.z == 0.0 {
            return 0.0;
        }
        let Some(probabilities) = self.lobe_probabilities() else {
            return 0.0;
        };
        let reflection = wi.z > 0.0;
        let mut pdf = 0.0;
        if microfacet_compatible(half, wo, wi, reflection) {
            let mirrored = Vec3::new(wi.x, wi.y, wi.z.abs());
            let jacobian = (1.0 / (4.0 * mirrored.dot(half))).abs();
            pdf += if reflection {
                probabilities.specular_reflection
                    * self.reflection_distribution.visible_normal_pdf(wo, half)
            } else {
                probabilities.specular_transmission
                    * self.transmission_distribution.visible_normal_pdf(wo, half)
            } * jacobian;
        }
        pdf + if reflection {
            probabilities.diffuse_reflection
        } else {
            probabilities.diffuse_transmission
        } * cosine_hemisphere_pdf(wi.z.abs())
    }

    /// Chooses the lobe with `u_component` and samples it with `u`.
    pub fn sample(&self, wo: Vec3, u_component: f32, u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let sign = wo.z.signum();
        let wo_up = wo * sign;
        let probabilities = self.lobe_probabilities()?;
        let reflect_about = |m: Vec3| 2.0 * wo_up.dot(m) * m - wo_up;
        let mut threshold = probabilities.specular_reflection;
        let (wi_up, flags) = if u_component < threshold {
            let m = self.reflection_distribution.sample_visible_normal(wo_up, u);
            let wi = reflect_about(m);
            if wi.z <= 0.0 || !microfacet_compatible(m, wo_up, wi, true) {
                return None;
            }
            (wi, BsdfFlags::REFLECTION | BsdfFlags::GLOSSY)
        } else if u_component < threshold + probabilities.specular_transmission {
            let m = self
                .transmission_distribution
                .sample_visible_normal(wo_up, u);
            let reflected = reflect_about(m);
            let wi = Vec3::new(reflected.x, reflected.y, -reflected.z);
            if wi.z >= 0.0 || !microfacet_compatible(m, wo_up, wi, false) {
                return None;
            }
            (wi, BsdfFlags::TRANSMISSION | BsdfFlags::GLOSSY)
        } else {
            threshold += probabilities.specular_transmission;
            if u_component < threshold + probabilities.diffuse_reflection {
                (
                    sample_cosine_hemisphere(u),
                    BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE,
                )
            } else {
                (
                    -sample_cosine_hemisphere(u),
                    BsdfFlags::TRANSMISSION | BsdfFlags::DIFFUSE,
                )
            }
        };
        let wi = wi_up * sign;
        Some(BsdfSample {
            wi,
            value: self.evaluate(wo, wi),
            pdf: self.pdf(wo, wi),
            flags,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// Diffuse and glossy reflection and transmission.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::TRANSMISSION | BsdfFlags::GLOSSY | BsdfFlags::DIFFUSE
    }

    /// The smoothest lobe's roughness for LQMC: the specular lobes' α where
    /// spec_trans weighs in, else 1 (diffuse only).
    pub fn roughness(&self) -> f32 {
        if self.parameters.spec_trans > 0.0 {
            self.reflection_distribution
                .roughness()
                .min(self.transmission_distribution.roughness())
        } else {
            1.0
        }
    }
}
