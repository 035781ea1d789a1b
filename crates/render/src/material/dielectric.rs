//! [`DielectricBsdf`]: a perfectly smooth interface between two dielectrics
//! (glass, water): specular reflection with the Fresnel reflectance R and
//! specular refraction by Snell's law with T = 1 − R.
//!
//! Sampling picks reflection with probability R and transmission with
//! probability T (both are known exactly), so a sample's weight
//! f |cos θ| / pdf is 1 for reflection and 1 (importance) or 1/η² (radiance)
//! for transmission: no variance beyond the choice itself.

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::error::MaterialError;
use super::flags::{BsdfFlags, TransportMode};
use super::fresnel::{fresnel_dielectric, reflect_about_normal, refract};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// A smooth dielectric interface with relative index of refraction
/// η = η_inside / η_outside, the normal pointing outside.
///
/// With dispersion the index depends on the wavelength, so refraction sends
/// each wavelength in its own direction and a path can only follow one:
/// [`Self::sample`] then keeps only the hero wavelength
/// ([`SampledWavelengths::terminate_secondary`]) and uses the hero's η.
/// η = 1 is an index-matched interface (e.g. a medium boundary): light passes
/// straight through, as specular transmission.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DielectricBsdf {
    eta: f32,
    dispersive: bool,
}

impl DielectricBsdf {
    /// An interface with relative index `eta` (at the hero wavelength) and no
    /// dispersion. Fails unless `eta` is finite and > 0.
    pub fn new(eta: f32) -> Result<Self, MaterialError> {
        if eta.is_finite() && eta > 0.0 {
            Ok(Self::new_unchecked(eta, false))
        } else {
            Err(MaterialError::NonPositiveIndexOfRefraction { value: eta })
        }
    }

    /// The same interface, marked dispersive (`true`) or not: a dispersive
    /// interface terminates the secondary wavelengths when sampled.
    pub fn with_dispersion(self, dispersive: bool) -> Self {
        Self { dispersive, ..self }
    }

    /// Builds without validation, for callers that validated already.
    pub(crate) fn new_unchecked(eta: f32, dispersive: bool) -> Self {
        Self { eta, dispersive }
    }

    /// The relative index of refraction (inside over outside) at the hero
    /// wavelength.
    pub fn eta(&self) -> f32 {
        self.eta
    }

    /// Whether the index depends on the wavelength.
    pub fn is_dispersive(&self) -> bool {
        self.dispersive
    }

    /// Always 0: both lobes are deltas.
    pub fn evaluate(&self, _wo: Vec3, _wi: Vec3) -> SampledSpectrum {
        SampledSpectrum::zero()
    }

    /// Chooses reflection (probability R(wo)) or refraction (probability T)
    /// with `u_component` and returns the specular direction. The value is
    /// R/|cos θi| or T/|cos θi|, the latter divided by η² (η the relative index
    /// along the path, [`BsdfSample::eta`]) in [`TransportMode::Radiance`].
    /// Returns `None` only for grazing `wo` (cos θ = 0).
    pub fn sample(
        &self,
        wo: Vec3,
        u_component: f32,
        wavelengths: &mut SampledWavelengths,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        if self.dispersive {
            wavelengths.terminate_secondary();
        }
        if wo.z == 0.0 {
            return None;
        }
        let reflectance = fresnel_dielectric(wo.z, self.eta);
        let transmittance = 1.0 - reflectance;
        if u_component < reflectance / (reflectance + transmittance) {
            let wi = reflect_about_normal(wo);
            return Some(BsdfSample {
                wi,
                value: SampledSpectrum::splat(reflectance / wi.z.abs()),
                pdf: reflectance / (reflectance + transmittance),
                flags: BsdfFlags::REFLECTION | BsdfFlags::SPECULAR,
                eta: 1.0,
                pdf_is_proportional: false,
            });
        }
        // R < 1 here, so there is no total internal reflection (up to
        // rounding, which the `?` covers).
        let refraction = refract(wo, self.eta)?;
        let wi = refraction.direction;
        let mut value = transmittance / wi.z.abs();
        if mode == TransportMode::Radiance {
            value /= refraction.relative_eta * refraction.relative_eta;
        }
        Some(BsdfSample {
            wi,
            value: SampledSpectrum::splat(value),
            pdf: transmittance / (reflectance + transmittance),
            flags: BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR,
            eta: refraction.relative_eta,
            pdf_is_proportional: false,
        })
    }

    /// Always 0: both lobes are deltas.
    pub fn pdf(&self, _wo: Vec3, _wi: Vec3) -> f32 {
        0.0
    }

    /// Specular reflection and transmission; transmission only when η = 1
    /// (nothing is reflected at an index-matched interface).
    pub fn flags(&self) -> BsdfFlags {
        if self.eta == 1.0 {
            BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR
        } else {
            BsdfFlags::REFLECTION | BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR
        }
    }
}
