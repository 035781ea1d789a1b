//! [`PrincipledMaterial`]: the textured parameters of Mitsuba's
//! `principled` and `principledthin` BSDFs, evaluated at each hit into a
//! [`PrincipledBsdf`] or [`PrincipledThinBsdf`].

use super::bsdf::Bsdf;
use super::principled::{PrincipledBsdf, PrincipledParameters};
use super::principled_thin::{PrincipledThinBsdf, PrincipledThinParameters};
use crate::spectrum::SampledWavelengths;
use crate::texture::{FloatTexture, SpectrumTexture, TextureContext};

/// The lobe sampling weights (Mitsuba's `*_sampling_rate` parameters; all
/// default to 1).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipledSamplingRates {
    /// `main_specular_sampling_rate` (principled) or
    /// `specular_reflectance_sampling_rate` (thin).
    pub specular_reflection: f32,
    /// `specular_transmittance_sampling_rate` (thin only).
    pub specular_transmission: f32,
    /// `clearcoat_sampling_rate` (principled only).
    pub clearcoat: f32,
    /// `diffuse_reflectance_sampling_rate`.
    pub diffuse_reflection: f32,
    /// `diffuse_transmittance_sampling_rate` (thin only).
    pub diffuse_transmission: f32,
}

impl Default for PrincipledSamplingRates {
    fn default() -> Self {
        Self {
            specular_reflection: 1.0,
            specular_transmission: 1.0,
            clearcoat: 1.0,
            diffuse_reflection: 1.0,
            diffuse_transmission: 1.0,
        }
    }
}

/// A principled material: every weight a texture, as Mitsuba allows.
#[derive(Debug, Clone, PartialEq)]
pub struct PrincipledMaterial {
    /// `principledthin` (a sheet without inside) rather than `principled`.
    pub thin: bool,
    pub base_color: SpectrumTexture,
    pub roughness: FloatTexture,
    pub anisotropic: FloatTexture,
    /// Unused by the thin variant.
    pub metallic: FloatTexture,
    pub spec_trans: FloatTexture,
    /// Relative index of refraction (a constant for `principled`, where it
    /// may come from `specular`; a texture for the thin variant).
    pub eta: FloatTexture,
    pub spec_tint: FloatTexture,
    pub sheen: FloatTexture,
    pub sheen_tint: FloatTexture,
    /// Unused by the thin variant.
    pub clearcoat: FloatTexture,
    /// Unused by the thin variant.
    pub clearcoat_gloss: FloatTexture,
    pub flatness: FloatTexture,
    /// Thin variant only (range [0, 2]).
    pub diff_trans: FloatTexture,
    pub sampling_rates: PrincipledSamplingRates,
}

impl PrincipledMaterial {
    /// The BSDF with the textures evaluated at `context`. The base colour's
    /// negative values are clamped to 0 (its square root tints the
    /// transmission); the weights are taken as they are, as Mitsuba does.
    pub fn bsdf(&self, context: &TextureContext, wavelengths: &SampledWavelengths) -> Bsdf {
        let base_color = self.base_color.evaluate(context, wavelengths).clamp_zero();
        let value = |texture: &FloatTexture| texture.evaluate(context);
        let rates = &self.sampling_rates;
        if self.thin {
            let parameters = PrincipledThinParameters {
                base_color,
                roughness: value(&self.roughness),
                anisotropic: value(&self.anisotropic),
                spec_trans: value(&self.spec_trans),
                eta: value(&self.eta),
                spec_tint: value(&self.spec_tint),
                sheen: value(&self.sheen),
                sheen_tint: value(&self.sheen_tint),
                flatness: value(&self.flatness),
                diff_trans: value(&self.diff_trans),
                specular_reflectance_sampling_rate: rates.specular_reflection,
                specular_transmittance_sampling_rate: rates.specular_transmission,
                diffuse_reflectance_sampling_rate: rates.diffuse_reflection,
                diffuse_transmittance_sampling_rate: rates.diffuse_transmission,
            };
            PrincipledThinBsdf::new(parameters, wavelengths).into()
        } else {
            let parameters = PrincipledParameters {
                base_color,
                roughness: value(&self.roughness),
                anisotropic: value(&self.anisotropic),
                metallic: value(&self.metallic),
                spec_trans: value(&self.spec_trans),
                eta: value(&self.eta),
                spec_tint: value(&self.spec_tint),
                sheen: value(&self.sheen),
                sheen_tint: value(&self.sheen_tint),
                clearcoat: value(&self.clearcoat),
                clearcoat_gloss: value(&self.clearcoat_gloss),
                flatness: value(&self.flatness),
                main_specular_sampling_rate: rates.specular_reflection,
                clearcoat_sampling_rate: rates.clearcoat,
                diffuse_reflectance_sampling_rate: rates.diffuse_reflection,
            };
            PrincipledBsdf::new(parameters, wavelengths).into()
        }
    }
}
