//! RGB floating-point images and their files.
//!
//! An [`Image`] is a row-major grid of linear RGB `f32` triples, top row
//! first (the raster convention of the film and of every format here). It
//! is what the film produces and what reference renders (Tungsten, Mitsuba,
//! pbrt) are compared against, so the readers accept what those renderers
//! write and the writers are lossless where the format allows:
//!
//! - OpenEXR ([`write_exr`], [`read_exr`]): 32-bit float RGB, optional extra
//!   RGB layers (the film's variance image is stored as the channels
//!   `variance.R`, `variance.G`, `variance.B` of the same file), and the
//!   render's metadata as custom string attributes.
//! - PFM ([`write_pfm`], [`read_pfm`]): the portable float map, bit exact.
//! - PNG ([`write_png`], [`read_png`]): 8-bit sRGB for viewing, with an
//!   exposure in stops; read back (8 or 16 bit) into linear floats.
//!
//! - Textures ([`read_texture_image`]): PNG, JPEG, BMP, EXR and PFM decoded
//!   to values as stored, with the file's transfer curve ([`TextureImage`]).
//!
//! [`write_image`] and [`read_image`] choose the format from the extension.
//! Every error names the file and what went wrong.

mod bmp;
pub mod compare;
mod error;
mod exr_io;
mod jpeg;
mod pfm;
mod png_io;
mod png_texture;
mod srgb;
mod texture_image;

use std::collections::BTreeMap;
use std::path::Path;

pub use error::ImageError;
pub use exr_io::{ExrContents, VARIANCE_LAYER, read_exr, write_exr};
pub use pfm::{read_pfm, write_pfm};
pub use png_io::{read_png, write_png};
pub use srgb::{linear_to_srgb, srgb_to_linear};
pub use texture_image::{TextureImage, TransferCurve, read_texture_image};

/// Free-form text describing how an image was made (integrator, sampler,
/// samples per pixel, seed, render time, ...), keyed by name. Stored as
/// custom string attributes in EXR and as `tEXt` chunks in PNG; PFM has no
/// place for it.
pub type Metadata = BTreeMap<String, String>;

/// A linear RGB image with `f32` channels, stored row-major with the top
/// row first: pixel `(x, y)` is `pixels[y * width + x]`.
#[derive(Debug, Clone, PartialEq)]
pub struct Image {
    width: usize,
    height: usize,
    pixels: Vec<[f32; 3]>,
}

impl Image {
    /// A black image of `width × height` pixels.
    pub fn new(width: usize, height: usize) -> Self {
        Self {
            width,
            height,
            pixels: vec![[0.0; 3]; width * height],
        }
    }

    /// An image from row-major, top-row-first pixels; fails when
    /// `pixels.len() != width * height`.
    pub fn from_pixels(
        width: usize,
        height: usize,
        pixels: Vec<[f32; 3]>,
    ) -> Result<Self, ImageError> {
        if width.checked_mul(height) != Some(pixels.len()) {
            return Err(ImageError::DimensionMismatch {
                width,
                height,
                pixel_count: pixels.len(),
            });
        }
        Ok(Self {
            width,
            height,
            pixels,
        })
    }

    /// Width in pixels.
    pub fn width(&self) -> usize {
        self.width
    }

    /// Height in pixels.
    pub fn height(&self) -> usize {
        self.height
    }

    /// All pixels, row-major, top row first.
    pub fn pixels(&self) -> &[[f32; 3]] {
        &self.pixels
    }

    /// All pixels, mutable, row-major, top row first.
    pub fn pixels_mut(&mut self) -> &mut [[f32; 3]] {
        &mut self.pixels
    }

    /// Consumes the image and returns its pixels.
    pub fn into_pixels(self) -> Vec<[f32; 3]> {
        self.pixels
    }

    /// The pixel at column `x`, row `y` (row 0 at the top), or `None`
    /// outside the image.
    pub fn pixel(&self, x: usize, y: usize) -> Option<[f32; 3]> {
        (x < self.width && y < self.height).then(|| self.pixels[y * self.width + x])
    }

    /// Sets the pixel at `(x, y)`; returns `false` (and changes nothing)
    /// outside the image.
    pub fn set_pixel(&mut self, x: usize, y: usize, rgb: [f32; 3]) -> bool {
        if x < self.width && y < self.height {
            self.pixels[y * self.width + x] = rgb;
            true
        } else {
            false
        }
    }

    /// The mean of each channel over all pixels, accumulated in `f64`
    /// (zero for an empty image).
    pub fn mean(&self) -> [f64; 3] {
        let mut sum = [0.0f64; 3];
        for pixel in &self.pixels {
            for channel in 0..3 {
                sum[channel] += pixel[channel] as f64;
            }
        }
        let count = self.pixels.len().max(1) as f64;
        sum.map(|total| total / count)
    }
}

/// The image file formats this module reads and writes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImageFormat {
    /// OpenEXR (`.exr`).
    OpenExr,
    /// Portable float map (`.pfm`).
    Pfm,
    /// Portable network graphics (`.png`), 8-bit sRGB.
    Png,
}

impl ImageFormat {
    /// The format named by the file's extension (case-insensitive), or an
    /// [`ImageError::UnsupportedExtension`].
    pub fn from_path(path: &Path) -> Result<Self, ImageError> {
        let extension = path
            .extension()
            .and_then(|extension| extension.to_str())
            .map(|extension| extension.to_ascii_lowercase());
        match extension.as_deref() {
            Some("exr") => Ok(Self::OpenExr),
            Some("pfm") => Ok(Self::Pfm),
            Some("png") => Ok(Self::Png),
            _ => Err(ImageError::UnsupportedExtension {
                path: path.to_path_buf(),
            }),
        }
    }
}

/// Writes `image` in the format given by the extension of `path`: `.exr`
/// (32-bit float RGB with `metadata` as string attributes), `.pfm`
/// (metadata is dropped: the format has no place for it) or `.png` (8-bit
/// sRGB at exposure 0, metadata as text chunks).
pub fn write_image(
    path: impl AsRef<Path>,
    image: &Image,
    metadata: &Metadata,
) -> Result<(), ImageError> {
    let path = path.as_ref();
    match ImageFormat::from_path(path)? {
        ImageFormat::OpenExr => write_exr(path, image, &[], metadata),
        ImageFormat::Pfm => write_pfm(path, image),
        ImageFormat::Png => write_png(path, image, 0.0, metadata),
    }
}

/// Reads the RGB image of an `.exr`, `.pfm` or `.png` file (chosen by the
/// extension) as linear floats. For EXR this is the main RGB layer (see
/// [`read_exr`] for the extra layers and the metadata); for PNG the sRGB
/// transfer function is inverted.
pub fn read_image(path: impl AsRef<Path>) -> Result<Image, ImageError> {
    let path = path.as_ref();
    match ImageFormat::from_path(path)? {
        ImageFormat::OpenExr => read_exr(path).map(|contents| contents.image),
        ImageFormat::Pfm => read_pfm(path),
        ImageFormat::Png => read_png(path),
    }
}
