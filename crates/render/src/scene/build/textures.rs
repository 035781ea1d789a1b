//! Render-time textures from the scene description's
//! [`TextureDescription`]s. Bitmap filenames arrive already resolved by the
//! loaders; a file that cannot be read is a [`SceneError::Parameter`] that
//! names the parameter and the path.

use glam::Vec3;

use super::parameter_error;
use crate::scene::SceneError;
use crate::scene::description::{SpectrumDescription, TextureDescription};
use crate::scene::spectra::{SpectrumUsage, build_spectrum};
use crate::spectrum::linear_srgb_luminance;
use crate::texture::{
    BitmapSource, Checkerboard, FloatBitmap, FloatTexture, RgbBitmap, RgbTexture, SpectrumBitmap,
    SpectrumTexture, TexelLookup,
};

/// The source and lookup of a bitmap description, or `None` for other kinds.
fn bitmap_parts(description: &TextureDescription) -> Option<(BitmapSource, TexelLookup)> {
    match description {
        TextureDescription::Bitmap {
            filename,
            encoding,
            filter,
            wrap,
            to_uv,
            flip_vertically,
            scale,
            invert,
        } => Some((
            BitmapSource {
                filename: filename.clone(),
                encoding: *encoding,
                flip_vertically: *flip_vertically,
                scale: *scale,
                invert: *invert,
            },
            TexelLookup {
                width: 1,
                height: 1,
                filter: *filter,
                wrap: *wrap,
                to_uv: *to_uv,
            },
        )),
        _ => None,
    }
}

/// The spectrum texture `description` stands for, its RGB values lifted to
/// spectra as `usage` says; `what` names the parameter in errors.
pub fn build_spectrum_texture(
    description: &TextureDescription,
    usage: SpectrumUsage,
    what: &str,
) -> Result<SpectrumTexture, SceneError> {
    Ok(match description {
        TextureDescription::Constant(spectrum) => {
            SpectrumTexture::Constant(build_spectrum(spectrum, usage, what)?)
        }
        TextureDescription::Bitmap { .. } => {
            let (source, lookup) = bitmap_parts(description)
                .ok_or_else(|| parameter_error(what, "not an image texture"))?;
            SpectrumTexture::Bitmap(SpectrumBitmap::load(&source, usage, lookup, what)?)
        }
        TextureDescription::Checkerboard { even, odd, to_uv } => {
            SpectrumTexture::Checkerboard(Box::new(Checkerboard {
                even: build_spectrum_texture(even, usage, what)?,
                odd: build_spectrum_texture(odd, usage, what)?,
                to_uv: *to_uv,
            }))
        }
    })
}

/// The scalar texture `description` stands for: constants are taken as they
/// are (an RGB triple by its luminance, as Mitsuba 3's `eval_1`), images by
/// their grey value or luminance.
pub fn build_float_texture(
    description: &TextureDescription,
    what: &str,
) -> Result<FloatTexture, SceneError> {
    Ok(match description {
        TextureDescription::Constant(SpectrumDescription::Constant(value)) => {
            FloatTexture::Constant(*value)
        }
        TextureDescription::Constant(SpectrumDescription::Rgb(rgb)) => {
            FloatTexture::Constant(linear_srgb_luminance(*rgb))
        }
        TextureDescription::Constant(other) => {
            return Err(parameter_error(
                what,
                format!("expected a number or an RGB value, got {other:?}"),
            ));
        }
        TextureDescription::Bitmap { .. } => {
            let (source, lookup) = bitmap_parts(description)
                .ok_or_else(|| parameter_error(what, "not an image texture"))?;
            FloatTexture::Bitmap(FloatBitmap::load(&source, lookup, what)?)
        }
        TextureDescription::Checkerboard { even, odd, to_uv } => {
            FloatTexture::Checkerboard(Box::new(Checkerboard {
                even: build_float_texture(even, what)?,
                odd: build_float_texture(odd, what)?,
                to_uv: *to_uv,
            }))
        }
    })
}

/// The raw-RGB texture `description` stands for (normal maps): constants
/// as given (a number replicated), images as linear values.
pub fn build_rgb_texture(
    description: &TextureDescription,
    what: &str,
) -> Result<RgbTexture, SceneError> {
    Ok(match description {
        TextureDescription::Constant(SpectrumDescription::Constant(value)) => {
            RgbTexture::Constant(Vec3::splat(*value))
        }
        TextureDescription::Constant(SpectrumDescription::Rgb(rgb)) => {
            RgbTexture::Constant(Vec3::from(*rgb))
        }
        TextureDescription::Constant(other) => {
            return Err(parameter_error(
                what,
                format!("expected an RGB value, got {other:?}"),
            ));
        }
        TextureDescription::Bitmap { .. } => {
            let (source, lookup) = bitmap_parts(description)
                .ok_or_else(|| parameter_error(what, "not an image texture"))?;
            RgbTexture::Bitmap(RgbBitmap::load(&source, lookup, what)?)
        }
        TextureDescription::Checkerboard { even, odd, to_uv } => {
            RgbTexture::Checkerboard(Box::new(Checkerboard {
                even: build_rgb_texture(even, what)?,
                odd: build_rgb_texture(odd, what)?,
                to_uv: *to_uv,
            }))
        }
    })
}
