//! [`RoughConductorBsdf`]: a rough metal, the Torrance–Sparrow microfacet
//! BRDF f = F(wo·h) D(h) G(wo, wi, h) / (4 cos θo cos θi) with the conductor
//! Fresnel term, sampled through the normals visible from `wo` (Mitsuba 3's
//! `roughconductor`; Walter et al. 2007, Heitz 2018).

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::conductor::ConductorReflectance;
use super::flags::BsdfFlags;
use super::fresnel::fresnel_complex_spectrum;
use super::microfacet::MicrofacetDistribution;
use super::sides::{flip_z, front_side, front_side_pair};
use crate::spectrum::SampledSpectrum;

/// A rough conductor.
///
/// **One-sided** (Mitsuba's default): black when `wo` is below the surface.
/// **Two-sided**: the back reflects like the front.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughConductorBsdf {
    distribution: MicrofacetDistribution,
    reflectance: ConductorReflectance,
    specular_factor: SampledSpectrum,
    two_sided: bool,
}

impl RoughConductorBsdf {
    /// A rough conductor with the given microfacets and Fresnel model, its
    /// reflectance multiplied by `specular_factor` (Mitsuba's
    /// `specular_reflectance`, 1 for physical metals).
    pub fn new(
        distribution: MicrofacetDistribution,
        reflectance: ConductorReflectance,
        specular_factor: SampledSpectrum,
        two_sided: bool,
    ) -> Self {
        Self {
            distribution,
            reflectance,
            specular_factor,
            two_sided,
        }
    }

    /// The microfacet distribution.
    pub fn distribution(&self) -> &MicrofacetDistribution {
        &self.distribution
    }

    /// Whether the back reflects too.
    pub fn is_two_sided(&self) -> bool {
        self.two_sided
    }

    /// Fresnel reflectance times the specular factor at |cos θ| of the
    /// microfacet.
    fn fresnel(&self, cos_theta: f32) -> SampledSpectrum {
        let fresnel = match &self.reflectance {
            ConductorReflectance::Perfect => SampledSpectrum::splat(1.0),
            ConductorReflectance::Fresnel { eta, k } => {
                fresnel_complex_spectrum(cos_theta.abs(), eta, k)
            }
        };
        fresnel * self.specular_factor
    }

    /// f(wo, wi) without the cosine factor.
    pub fn evaluate(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        let Some((wo, wi)) = front_side_pair(wo, wi, self.two_sided) else {
            return SampledSpectrum::zero();
        };
        let half = wo + wi;
        if half.length_squared() == 0.0 {
            return SampledSpectrum::zero();
        }
        let half = half.normalize();
        let d = self.distribution.d(half);
        let g = self.distribution.g(wo, wi, half);
        if d == 0.0 || g == 0.0 {
            return SampledSpectrum::zero();
        }
        self.fresnel(wo.dot(half)) * (d * g / (4.0 * wo.z * wi.z))
    }

    /// The density of [`Self::sample`]: D_wo(h) / (4 wo·h).
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some((wo, wi)) = front_side_pair(wo, wi, self.two_sided) else {
            return 0.0;
        };
        let half = wo + wi;
        if half.length_squared() == 0.0 {
            return 0.0;
        }
        let half = half.normalize();
        let cos = wo.dot(half);
        if cos <= 0.0 {
            return 0.0;
        }
        self.distribution.visible_normal_pdf(wo, half) / (4.0 * cos)
    }

    /// Reflects `wo` about a visible microfacet normal drawn from `u`.
    pub fn sample(&self, wo: Vec3, u: [f32; 2]) -> Option<BsdfSample> {
        let (wo_front, flipped) = front_side(wo, self.two_sided)?;
        let m = self.distribution.sample_visible_normal(wo_front, u);
        let cos = wo_front.dot(m);
        let wi_front = 2.0 * cos * m - wo_front;
        if wi_front.z <= 0.0 || cos <= 0.0 {
            return None;
        }
        let wi = if flipped { flip_z(wi_front) } else { wi_front };
        Some(BsdfSample {
            wi,
            value: self.evaluate(wo, wi),
            pdf: self.pdf(wo, wi),
            flags: BsdfFlags::REFLECTION | BsdfFlags::GLOSSY,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// Glossy reflection.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::GLOSSY
    }
}
