//! [`TextureImage`]: an image file decoded for use as a texture, with its
//! values as stored (not yet linearised) and the transfer curve the file
//! declares, so that the texture can honour an explicit encoding (Mitsuba's
//! `raw`, pbrt's `encoding`) instead of the file's.
//!
//! [`read_texture_image`] dispatches on the extension: PNG (8/16 bit, with
//! its `sRGB`/`gAMA` chunks), JPEG and BMP (8 bit, sRGB), OpenEXR and PFM
//! (linear floats). Alpha channels are dropped, as Mitsuba 3 does for
//! textures; grey images keep one channel.

use std::path::Path;

use super::{ImageError, read_exr, read_pfm};

/// The transfer curve with which a file stores its values.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum TransferCurve {
    /// Values are linear.
    Linear,
    /// The sRGB curve (IEC 61966-2-1).
    Srgb,
}

/// A decoded texture image: `channels` (1 or 3) values per texel, row-major
/// with the top row first, as stored in the file (8/16-bit levels scaled to
/// [0, 1]).
#[derive(Debug, Clone, PartialEq)]
pub struct TextureImage {
    /// Width in texels.
    pub width: usize,
    /// Height in texels.
    pub height: usize,
    /// Values per texel: 1 (grey) or 3 (RGB).
    pub channels: usize,
    /// `width · height · channels` values, texel `(x, y)` channel `c` at
    /// `(y · width + x) · channels + c`.
    pub values: Vec<f32>,
    /// How the file encodes the values.
    pub transfer: TransferCurve,
}

impl TextureImage {
    /// The texel at column `x`, row `y` (top row 0) as RGB (grey replicated).
    pub fn rgb(&self, x: usize, y: usize) -> [f32; 3] {
        let index = (y * self.width + x) * self.channels;
        if self.channels == 1 {
            [self.values[index]; 3]
        } else {
            [
                self.values[index],
                self.values[index + 1],
                self.values[index + 2],
            ]
        }
    }

    /// An image from interleaved 8-bit samples with `stored_channels` per
    /// texel (1–4; a second channel of two, or the fourth, is alpha and
    /// dropped).
    pub(crate) fn from_levels<T: Copy + Into<f32>>(
        width: usize,
        height: usize,
        stored_channels: usize,
        samples: &[T],
        maximum: f32,
        transfer: TransferCurve,
    ) -> Self {
        let channels = if stored_channels >= 3 { 3 } else { 1 };
        let mut values = Vec::with_capacity(width * height * channels);
        for texel in samples.chunks_exact(stored_channels) {
            for &sample in &texel[..channels] {
                values.push(sample.into() / maximum);
            }
        }
        Self {
            width,
            height,
            channels,
            values,
            transfer,
        }
    }
}

/// Reads a texture image, choosing the format from the extension
/// (case-insensitive): `.png`, `.jpg`/`.jpeg`, `.bmp`, `.exr`, `.pfm`.
pub fn read_texture_image(path: impl AsRef<Path>) -> Result<TextureImage, ImageError> {
    let path = path.as_ref();
    let extension = path
        .extension()
        .and_then(|extension| extension.to_str())
        .map(|extension| extension.to_ascii_lowercase());
    let linear = |image: super::Image| TextureImage {
        width: image.width(),
        height: image.height(),
        channels: 3,
        values: image.into_pixels().into_iter().flatten().collect(),
        transfer: TransferCurve::Linear,
    };
    match extension.as_deref() {
        Some("png") => super::png_texture::read_png_texture(path),
        Some("jpg" | "jpeg") => super::jpeg::read_jpeg(path),
        Some("bmp") => super::bmp::read_bmp(path),
        Some("exr") => read_exr(path).map(|contents| linear(contents.image)),
        Some("pfm") => read_pfm(path).map(linear),
        _ => Err(ImageError::UnsupportedExtension {
            path: path.to_path_buf(),
        }),
    }
}

/// Reads the whole file, naming it in the error.
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>, ImageError> {
    std::fs::read(path).map_err(|source| ImageError::Read {
        path: path.to_path_buf(),
        source,
    })
}
