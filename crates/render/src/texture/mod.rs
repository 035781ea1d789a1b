//! Textures: values that vary over a surface, looked up by the hit's
//! parameterisation. [`SpectrumTexture`] gives spectra (reflectances,
//! illuminants), [`FloatTexture`] scalars (roughness, heights, opacity).
//!
//! Textures never draw random numbers; they are evaluated at a
//! [`TextureContext`] made from a [`SurfaceHit`].

use crate::geometry::SurfaceHit;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::{Vec2, Vec3};

/// Where a texture is looked up.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TextureContext {
    /// The surface's texture coordinates.
    pub uv: Vec2,
    /// The world-space point.
    pub point: Vec3,
}

impl TextureContext {
    /// The lookup position of a surface hit.
    pub fn from_hit(hit: &SurfaceHit) -> Self {
        Self {
            uv: hit.uv,
            point: hit.point,
        }
    }
}

/// A spectrum-valued texture.
#[derive(Debug, Clone, PartialEq)]
pub enum SpectrumTexture {
    /// The same spectrum everywhere.
    Constant(Spectrum),
}

impl SpectrumTexture {
    /// The texture's spectrum at `context` for the path's `wavelengths`.
    pub fn evaluate(
        &self,
        _context: &TextureContext,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        match self {
            SpectrumTexture::Constant(spectrum) => spectrum.sample(wavelengths),
        }
    }

    /// The spectrum if the texture is constant.
    pub fn as_constant(&self) -> Option<&Spectrum> {
        match self {
            SpectrumTexture::Constant(spectrum) => Some(spectrum),
        }
    }
}

impl From<Spectrum> for SpectrumTexture {
    fn from(spectrum: Spectrum) -> Self {
        SpectrumTexture::Constant(spectrum)
    }
}

/// A scalar texture.
#[derive(Debug, Clone, PartialEq)]
pub enum FloatTexture {
    /// The same value everywhere.
    Constant(f32),
}

impl FloatTexture {
    /// The texture's value at `context`.
    pub fn evaluate(&self, _context: &TextureContext) -> f32 {
        match self {
            FloatTexture::Constant(value) => *value,
        }
    }
}

impl From<f32> for FloatTexture {
    fn from(value: f32) -> Self {
        FloatTexture::Constant(value)
    }
}
