//! Textures: values that vary over a surface, looked up by the hit's
//! parameterisation. [`SpectrumTexture`] gives spectra (reflectances,
//! illuminants), [`FloatTexture`] scalars (roughness, heights, opacity) and
//! [`RgbTexture`] raw RGB triples that are not colours (normal maps).
//!
//! Each kind is a constant, an image ([`bitmap`]: nearest or bilinear
//! filtering, repeat/mirror/clamp wrapping, a `to_uv` affine map — see
//! [`TexelLookup`] for the exact conventions, those of Mitsuba 3) or a
//! [`Checkerboard`] of two textures of the kind. The scene builder makes
//! them from the scene description; this module knows nothing of it.
//!
//! Textures never draw random numbers; they are evaluated at a
//! [`TextureContext`] made from a [`SurfaceHit`].

pub mod bitmap;
mod checkerboard;
mod error;
mod texel_lookup;

pub use bitmap::{
    BitmapSource, ColourEncoding, FloatBitmap, RgbBitmap, SigmoidTexel, SpectrumBitmap, TexelData,
};
pub use checkerboard::Checkerboard;
pub use error::TextureError;
pub use texel_lookup::{TexelFootprint, TexelLookup, TextureFilter, TextureWrap};

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
    #[inline]
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
    /// An image, upsampled per texel.
    Bitmap(SpectrumBitmap),
    /// Two textures in alternating squares.
    Checkerboard(Box<Checkerboard<SpectrumTexture>>),
}

impl SpectrumTexture {
    /// The texture's spectrum at `context` for the path's `wavelengths`.
    /// A constant, the common case, is handled inline (an RGB reflectance,
    /// the most common constant, without [`Spectrum::sample`]'s call and
    /// dispatch); images and checkerboards in the out-of-line
    /// [`Self::evaluate_general`].
    #[inline]
    pub fn evaluate(
        &self,
        context: &TextureContext,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        match self {
            SpectrumTexture::Constant(Spectrum::RgbAlbedo(albedo)) => albedo.sample(wavelengths),
            SpectrumTexture::Constant(spectrum) => spectrum.sample(wavelengths),
            _ => self.evaluate_general(context, wavelengths),
        }
    }

    /// [`Self::evaluate`] for textures that are not constant.
    #[inline(never)]
    fn evaluate_general(
        &self,
        context: &TextureContext,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        match self {
            SpectrumTexture::Constant(spectrum) => spectrum.sample(wavelengths),
            SpectrumTexture::Bitmap(bitmap) => bitmap.evaluate(context.uv, wavelengths),
            SpectrumTexture::Checkerboard(checkerboard) => checkerboard
                .select(context.uv)
                .evaluate(context, wavelengths),
        }
    }

    /// The spectrum if the texture is constant.
    pub fn as_constant(&self) -> Option<&Spectrum> {
        match self {
            SpectrumTexture::Constant(spectrum) => Some(spectrum),
            _ => None,
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
    /// An image (grey values, or the luminance of RGB texels).
    Bitmap(FloatBitmap),
    /// Two textures in alternating squares.
    Checkerboard(Box<Checkerboard<FloatTexture>>),
}

impl FloatTexture {
    /// The texture's value at `context`.
    pub fn evaluate(&self, context: &TextureContext) -> f32 {
        match self {
            FloatTexture::Constant(value) => *value,
            FloatTexture::Bitmap(bitmap) => bitmap.evaluate(context.uv),
            FloatTexture::Checkerboard(checkerboard) => {
                checkerboard.select(context.uv).evaluate(context)
            }
        }
    }

    /// The derivatives of the value with respect to u and v at `context`
    /// (what bump mapping needs): zero for constants and checkerboards
    /// (piecewise constant), the exact derivative of the bilinear
    /// interpolant for images (zero with nearest filtering), as Mitsuba 3.
    pub fn gradient(&self, context: &TextureContext) -> Vec2 {
        match self {
            FloatTexture::Constant(_) => Vec2::ZERO,
            FloatTexture::Bitmap(bitmap) => bitmap.gradient(context.uv),
            FloatTexture::Checkerboard(checkerboard) => {
                checkerboard.select(context.uv).gradient(context)
            }
        }
    }
}

impl From<f32> for FloatTexture {
    fn from(value: f32) -> Self {
        FloatTexture::Constant(value)
    }
}

/// A texture of raw RGB triples (no spectral upsampling), for data such as
/// normal maps.
#[derive(Debug, Clone, PartialEq)]
pub enum RgbTexture {
    /// The same triple everywhere.
    Constant(Vec3),
    /// An image, linear values.
    Bitmap(RgbBitmap),
    /// Two textures in alternating squares.
    Checkerboard(Box<Checkerboard<RgbTexture>>),
}

impl RgbTexture {
    /// The triple at `context`.
    pub fn evaluate(&self, context: &TextureContext) -> Vec3 {
        match self {
            RgbTexture::Constant(value) => *value,
            RgbTexture::Bitmap(bitmap) => bitmap.evaluate(context.uv),
            RgbTexture::Checkerboard(checkerboard) => {
                checkerboard.select(context.uv).evaluate(context)
            }
        }
    }
}
