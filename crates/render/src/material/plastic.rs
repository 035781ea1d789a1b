//! [`PlasticBsdf`]: a diffuse base under a smooth dielectric coating,
//! Mitsuba 3's `plastic` model (implemented from its documented behaviour).
//!
//! Light either reflects specularly at the coating (Fresnel reflectance
//! F(cos θo)) or enters it, scatters diffusely at the base and leaves
//! through the coating again. The internal reflections between coating and
//! base are summed in closed form with the coating's diffuse Fresnel
//! reflectance seen from inside, F_dr,int = F_dr(1/η)
//! ([`fresnel_diffuse_reflectance`]): the base's effective albedo is
//!
//! - d / (1 − F_dr,int) (linear, the default), or
//! - d / (1 − d F_dr,int) (`nonlinear`: light bounces many times, shifting
//!   the colour towards saturation),
//!
//! and the diffuse lobe is f = d_eff (1 − F(cos θo)) (1 − F(cos θi)) / (π η²).
//! The specular lobe is a delta with weight F. Sampling chooses the specular
//! lobe with probability ∝ F w_s and the diffuse one ∝ (1 − F)(1 − w_s),
//! w_s = 1/(1 + mean(d)) (Mitsuba's specular sampling weight for a specular
//! reflectance of 1).
//!
//! One-sided (black from behind) unless two-sided.

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::flags::BsdfFlags;
use super::fresnel::{fresnel_dielectric, fresnel_diffuse_reflectance, reflect_about_normal};
use super::sides::{flip_z, front_side, front_side_pair};
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::SampledSpectrum;

/// The diffuse base of a plastic as the coating sees it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PlasticBase {
    /// The base's albedo with the internal reflections summed, divided by
    /// π η² (the coating's radiance compression).
    pub lambertian: SampledSpectrum,
    /// Mitsuba's specular sampling weight w_s = 1/(1 + mean albedo).
    pub specular_sampling_weight: f32,
}

impl PlasticBase {
    /// The base for albedo `diffuse` under a coating of relative index
    /// `eta` whose hemispherical internal reflectance is
    /// `internal_reflectance`.
    pub fn new(
        diffuse: SampledSpectrum,
        eta: f32,
        internal_reflectance: f32,
        nonlinear: bool,
    ) -> Self {
        let effective = if nonlinear {
            diffuse / (SampledSpectrum::splat(1.0) - diffuse * internal_reflectance)
        } else {
            diffuse / (1.0 - internal_reflectance)
        };
        Self {
            lambertian: effective * (std::f32::consts::FRAC_1_PI / (eta * eta)),
            specular_sampling_weight: 1.0 / (1.0 + diffuse.average().max(0.0)),
        }
    }

    /// The probability of choosing the specular lobe when the coating
    /// reflects `specular` (0..1) of the light.
    pub fn specular_probability(&self, specular: f32) -> f32 {
        let specular_weight = specular * self.specular_sampling_weight;
        let diffuse_weight = (1.0 - specular) * (1.0 - self.specular_sampling_weight);
        if specular_weight + diffuse_weight <= 0.0 {
            return 0.0;
        }
        specular_weight / (specular_weight + diffuse_weight)
    }
}

/// A smooth plastic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlasticBsdf {
    base: PlasticBase,
    eta: f32,
    two_sided: bool,
}

impl PlasticBsdf {
    /// A plastic with base albedo `diffuse` under a coating of relative index
    /// `eta` (coating over outside, > 0).
    pub fn new(diffuse: SampledSpectrum, eta: f32, nonlinear: bool, two_sided: bool) -> Self {
        let internal = fresnel_diffuse_reflectance(1.0 / eta);
        Self {
            base: PlasticBase::new(diffuse, eta, internal, nonlinear),
            eta,
            two_sided,
        }
    }

    /// The coating's relative index.
    pub fn eta(&self) -> f32 {
        self.eta
    }

    /// The diffuse lobe (the specular one is a delta).
    pub fn evaluate(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        let Some((wo, wi)) = front_side_pair(wo, wi, self.two_sided) else {
            return SampledSpectrum::zero();
        };
        let transmitted =
            (1.0 - fresnel_dielectric(wo.z, self.eta)) * (1.0 - fresnel_dielectric(wi.z, self.eta));
        self.base.lambertian * transmitted
    }

    /// The density of the diffuse lobe's samples.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some((wo, wi)) = front_side_pair(wo, wi, self.two_sided) else {
            return 0.0;
        };
        let specular = self
            .base
            .specular_probability(fresnel_dielectric(wo.z, self.eta));
        (1.0 - specular) * cosine_hemisphere_pdf(wi.z)
    }

    /// The specular reflection (`u_component` below its probability) or a
    /// cosine-distributed diffuse direction.
    pub fn sample(&self, wo: Vec3, u_component: f32, u: [f32; 2]) -> Option<BsdfSample> {
        let (wo_front, flipped) = front_side(wo, self.two_sided)?;
        let fresnel = fresnel_dielectric(wo_front.z, self.eta);
        let specular_probability = self.base.specular_probability(fresnel);
        if u_component < specular_probability {
            let wi = reflect_about_normal(wo);
            return Some(BsdfSample {
                wi,
                value: SampledSpectrum::splat(fresnel / wo_front.z),
                pdf: specular_probability,
                flags: BsdfFlags::REFLECTION | BsdfFlags::SPECULAR,
                eta: 1.0,
                pdf_is_proportional: false,
            });
        }
        let wi_front = sample_cosine_hemisphere(u);
        let wi = if flipped { flip_z(wi_front) } else { wi_front };
        Some(BsdfSample {
            wi,
            value: self.evaluate(wo, wi),
            pdf: self.pdf(wo, wi),
            flags: BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// Specular and diffuse reflection.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::SPECULAR | BsdfFlags::DIFFUSE
    }
}
