//! [`DiffuseBsdf`]: Lambertian reflection, f = R/π, sampled with the
//! cosine-weighted hemisphere so that f cos θ / pdf = R exactly.
//!
//! The reflectance is sampled at the path's wavelengths when the BSDF is built
//! (once per hit, as in pbrt-v4), so evaluating and sampling are a few
//! multiplications.

use std::f32::consts::FRAC_1_PI;

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::error::{MaterialError, require_finite_non_negative};
use super::flags::BsdfFlags;
use super::shading_frame::same_hemisphere;
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::SampledSpectrum;

/// A Lambertian reflector.
///
/// **Two-sided** (the default, like Mitsuba's `twosided` diffuse and pbrt-v4's
/// `DiffuseBxDF`): both faces reflect; `wi` is sampled on the side of `wo`.
/// **One-sided**: only the face the normal points out of reflects; seen from
/// behind (`wo.z < 0`) the surface is black, which is right for closed
/// objects and makes wrong normals visible.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DiffuseBsdf {
    reflectance: SampledSpectrum,
    two_sided: bool,
}

impl DiffuseBsdf {
    /// A two-sided Lambertian BSDF with the given reflectance (albedo) at the
    /// path's wavelengths. Fails if a component is negative, NaN or infinite.
    /// Values above 1 are accepted (they create energy; clamp beforehand if
    /// that is not wanted).
    pub fn new(reflectance: SampledSpectrum) -> Result<Self, MaterialError> {
        Ok(Self::new_unchecked(
            require_finite_non_negative("diffuse reflectance", reflectance)?,
            true,
        ))
    }

    /// A one-sided Lambertian BSDF: black when seen from below the normal.
    pub fn one_sided(reflectance: SampledSpectrum) -> Result<Self, MaterialError> {
        Ok(Self::new(reflectance)?.with_two_sided(false))
    }

    /// The same BSDF with both faces reflecting (`true`) or only the front.
    pub fn with_two_sided(self, two_sided: bool) -> Self {
        Self { two_sided, ..self }
    }

    /// Builds without validation, for callers that validated already.
    pub(crate) fn new_unchecked(reflectance: SampledSpectrum, two_sided: bool) -> Self {
        Self {
            reflectance,
            two_sided,
        }
    }

    /// The reflectance (albedo) at the path's wavelengths.
    pub fn reflectance(&self) -> SampledSpectrum {
        self.reflectance
    }

    /// Whether both faces reflect.
    pub fn is_two_sided(&self) -> bool {
        self.two_sided
    }

    /// Whether the BSDF scatters from `wo` to `wi` at all.
    #[inline]
    fn connects(&self, wo: Vec3, wi: Vec3) -> bool {
        if self.two_sided {
            same_hemisphere(wo, wi)
        } else {
            wo.z > 0.0 && wi.z > 0.0
        }
    }

    /// f(wo, wi) = R/π on the reflecting side(s), 0 elsewhere.
    #[inline]
    pub fn evaluate(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        if self.connects(wo, wi) {
            self.reflectance * FRAC_1_PI
        } else {
            SampledSpectrum::zero()
        }
    }

    /// Samples `wi` with density |cos θi|/π on the side of `wo`.
    #[inline]
    pub fn sample(&self, wo: Vec3, u: [f32; 2]) -> Option<BsdfSample> {
        if wo.z == 0.0 || (!self.two_sided && wo.z < 0.0) {
            return None;
        }
        let mut wi = sample_cosine_hemisphere(u);
        if wo.z < 0.0 {
            wi.z = -wi.z;
        }
        Some(BsdfSample {
            wi,
            value: self.reflectance * FRAC_1_PI,
            pdf: cosine_hemisphere_pdf(wi.z.abs()),
            flags: BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// The density [`Self::sample`] gives `wi`: |cos θi|/π where the BSDF is
    /// non-zero, else 0.
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        if self.connects(wo, wi) {
            cosine_hemisphere_pdf(wi.z.abs())
        } else {
            0.0
        }
    }

    /// Diffuse reflection, or nothing if the reflectance is black.
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        if self.reflectance.is_black() {
            BsdfFlags::NONE
        } else {
            BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE
        }
    }
}
