//! [`ThinDielectricBsdf`]: a thin dielectric sheet (a window pane, a soap
//! film without interference), Mitsuba 3's `thindielectric` and pbrt-v4's
//! `ThinDielectricBxDF`.
//!
//! Light reflects at the front or passes straight through (the two
//! refractions cancel); the infinitely many internal reflections sum to the
//! geometric series R' = R + T² R / (1 − R²), T' = 1 − R', with R the Fresnel
//! reflectance of one interface (pbrt-v4 §9.5.1). Both lobes are deltas;
//! sampling picks reflection with probability R', so the weight is exactly 1.
//! Transmission does not change the direction, so there is no η² factor.

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::flags::BsdfFlags;
use super::fresnel::{fresnel_dielectric, reflect_about_normal};
use crate::spectrum::SampledSpectrum;

/// A thin sheet of relative index η (sheet over surroundings).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThinDielectricBsdf {
    eta: f32,
}

impl ThinDielectricBsdf {
    /// A sheet of relative index `eta` (> 0, finite; callers validate).
    pub fn new(eta: f32) -> Self {
        Self { eta }
    }

    /// The relative index of refraction.
    pub fn eta(&self) -> f32 {
        self.eta
    }

    /// The sheet's total reflectance R' at incidence cosine |`cos_theta`|.
    pub fn reflectance(&self, cos_theta: f32) -> f32 {
        let single = fresnel_dielectric(cos_theta.abs(), self.eta);
        if single < 1.0 {
            let transmittance = 1.0 - single;
            single + transmittance * transmittance * single / (1.0 - single * single)
        } else {
            1.0
        }
    }

    /// Always 0: both lobes are deltas.
    pub fn evaluate(&self, _wo: Vec3, _wi: Vec3) -> SampledSpectrum {
        SampledSpectrum::zero()
    }

    /// Always 0: both lobes are deltas.
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    /// Reflection (`u_component` < R') or straight transmission.
    pub fn sample(&self, wo: Vec3, u_component: f32) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let reflectance = self.reflectance(wo.z);
        let cos = wo.z.abs();
        if u_component < reflectance {
            return Some(BsdfSample {
                wi: reflect_about_normal(wo),
                value: SampledSpectrum::splat(reflectance / cos),
                pdf: reflectance,
                flags: BsdfFlags::REFLECTION | BsdfFlags::SPECULAR,
                eta: 1.0,
                pdf_is_proportional: false,
            });
        }
        let transmittance = 1.0 - reflectance;
        Some(BsdfSample {
            wi: -wo,
            value: SampledSpectrum::splat(transmittance / cos),
            pdf: transmittance,
            flags: BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// Specular reflection and transmission.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR
    }
}
