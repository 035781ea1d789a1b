//! [`ConductorBsdf`]: a perfectly smooth metal, a mirror whose reflectance
//! follows the Fresnel equations for a complex index of refraction η + iκ
//! (or is exactly 1 for an ideal mirror).

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::error::{MaterialError, require_finite_non_negative};
use super::flags::BsdfFlags;
use super::fresnel::{fresnel_complex_spectrum, reflect_about_normal};
use crate::spectrum::SampledSpectrum;

/// How a smooth conductor's reflectance depends on the angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ConductorReflectance {
    /// Reflectance 1 at every angle and wavelength: an ideal mirror.
    Perfect,
    /// The Fresnel reflectance of a metal with index `eta` + i`k` (relative
    /// to the surrounding medium) at the path's wavelengths.
    Fresnel {
        /// Real part η of the relative index of refraction.
        eta: SampledSpectrum,
        /// Extinction coefficient κ (imaginary part).
        k: SampledSpectrum,
    },
}

/// A smooth conductor: specular reflection only, from either side by default
/// (the Fresnel term uses |cos θ|, as pbrt-v4 does), or only from the front
/// ([`Self::with_two_sided`]`(false)`, Mitsuba's `conductor` outside a
/// `twosided`). The reflectance may be scaled by a factor (Mitsuba's
/// `specular_reflectance`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ConductorBsdf {
    reflectance: ConductorReflectance,
    specular_factor: SampledSpectrum,
    two_sided: bool,
}

impl ConductorBsdf {
    /// A metal with index `eta` + i`k` at the path's wavelengths. Fails if a
    /// component is negative, NaN or infinite.
    pub fn new(eta: SampledSpectrum, k: SampledSpectrum) -> Result<Self, MaterialError> {
        Ok(Self::new_unchecked(
            require_finite_non_negative("conductor eta", eta)?,
            require_finite_non_negative("conductor k", k)?,
        ))
    }

    /// Builds without validation, for callers that validated already.
    pub(crate) fn new_unchecked(eta: SampledSpectrum, k: SampledSpectrum) -> Self {
        Self {
            reflectance: ConductorReflectance::Fresnel { eta, k },
            specular_factor: SampledSpectrum::splat(1.0),
            two_sided: true,
        }
    }

    /// The same conductor reflecting from both sides (`true`) or only where
    /// `wo` is above the surface (`false`: black from behind).
    pub fn with_two_sided(self, two_sided: bool) -> Self {
        Self { two_sided, ..self }
    }

    /// The same conductor with its reflectance multiplied by `factor`.
    pub fn with_specular_factor(self, factor: SampledSpectrum) -> Self {
        Self {
            specular_factor: factor,
            ..self
        }
    }

    /// Whether both faces reflect.
    pub fn is_two_sided(&self) -> bool {
        self.two_sided
    }

    /// An ideal mirror (reflectance 1).
    pub fn perfect_mirror() -> Self {
        Self {
            reflectance: ConductorReflectance::Perfect,
            specular_factor: SampledSpectrum::splat(1.0),
            two_sided: true,
        }
    }

    /// How the reflectance is computed.
    pub fn reflectance_model(&self) -> ConductorReflectance {
        self.reflectance
    }

    /// The fraction of light reflected at incidence cosine |`cos_theta`|
    /// (times the specular factor).
    pub fn reflectance(&self, cos_theta: f32) -> SampledSpectrum {
        let fresnel = match &self.reflectance {
            ConductorReflectance::Perfect => SampledSpectrum::splat(1.0),
            ConductorReflectance::Fresnel { eta, k } => {
                fresnel_complex_spectrum(cos_theta.abs(), eta, k)
            }
        };
        fresnel * self.specular_factor
    }

    /// Always 0: a delta lobe has no finite value.
    pub fn evaluate(&self, _wo: Vec3, _wi: Vec3) -> SampledSpectrum {
        SampledSpectrum::zero()
    }

    /// The mirror direction, with value F/|cos θ| and pdf 1, so that the
    /// sample's weight is the Fresnel reflectance F.
    pub fn sample(&self, wo: Vec3) -> Option<BsdfSample> {
        if wo.z == 0.0 || (!self.two_sided && wo.z < 0.0) {
            return None;
        }
        let wi = reflect_about_normal(wo);
        let cos = wi.z.abs();
        Some(BsdfSample {
            wi,
            value: self.reflectance(cos) / cos,
            pdf: 1.0,
            flags: BsdfFlags::REFLECTION | BsdfFlags::SPECULAR,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// Always 0: a delta lobe has no density.
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    /// Specular reflection.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::SPECULAR
    }
}
