//! JPEG files (baseline and progressive, via `zune-jpeg`), decoded to 8-bit
//! RGB and tagged sRGB, as JPEG images are.

use std::path::Path;

use zune_jpeg::JpegDecoder;
use zune_jpeg::zune_core::bytestream::ZCursor;
use zune_jpeg::zune_core::colorspace::ColorSpace;
use zune_jpeg::zune_core::options::DecoderOptions;

use super::ImageError;
use super::texture_image::{TextureImage, TransferCurve, read_bytes};

/// Reads a JPEG file as an sRGB-encoded RGB texture image.
pub fn read_jpeg(path: impl AsRef<Path>) -> Result<TextureImage, ImageError> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    let options = DecoderOptions::default().jpeg_set_out_colorspace(ColorSpace::RGB);
    let mut decoder = JpegDecoder::new_with_options(ZCursor::new(&bytes[..]), options);
    let invalid = |reason: String| ImageError::InvalidFormat {
        path: path.to_path_buf(),
        format: "JPEG",
        reason,
    };
    let samples = decoder
        .decode()
        .map_err(|error| invalid(error.to_string()))?;
    let info = decoder
        .info()
        .ok_or_else(|| invalid("no image header".to_string()))?;
    let (width, height) = (info.width as usize, info.height as usize);
    if samples.len() != width * height * 3 {
        return Err(ImageError::Truncated {
            path: path.to_path_buf(),
            format: "JPEG",
            reason: format!("{} samples decoded for {width}x{height} RGB", samples.len()),
        });
    }
    Ok(TextureImage::from_levels(
        width,
        height,
        3,
        &samples,
        255.0,
        TransferCurve::Srgb,
    ))
}
