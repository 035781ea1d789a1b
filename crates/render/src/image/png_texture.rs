//! PNG files as textures: 8- or 16-bit values as stored, with the transfer
//! curve the file declares. As pbrt-v4 and Mitsuba 3 do, a `gAMA` chunk of
//! exactly 1 means linear values; anything else (an `sRGB` chunk, another
//! gamma, or nothing) means sRGB.

use std::io::Cursor;
use std::path::Path;

use super::ImageError;
use super::texture_image::{TextureImage, TransferCurve, read_bytes};

const FORMAT: &str = "PNG";

/// Reads a PNG (grey, grey+alpha, RGB, RGBA or palette, any bit depth) into a
/// texture image; alpha is dropped.
pub fn read_png_texture(path: impl AsRef<Path>) -> Result<TextureImage, ImageError> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    let decoding_error = |error: png::DecodingError| match error {
        png::DecodingError::IoError(source) => ImageError::Truncated {
            path: path.to_path_buf(),
            format: FORMAT,
            reason: source.to_string(),
        },
        other => ImageError::InvalidFormat {
            path: path.to_path_buf(),
            format: FORMAT,
            reason: other.to_string(),
        },
    };
    let mut decoder = png::Decoder::new(Cursor::new(&bytes[..]));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(decoding_error)?;
    let linear = reader.info().srgb.is_none()
        && reader
            .info()
            .source_gamma
            .is_some_and(|gamma| gamma.into_scaled() == png::ScaledFloat::SCALING as u32);
    let transfer = if linear {
        TransferCurve::Linear
    } else {
        TransferCurve::Srgb
    };
    let buffer_size = reader
        .output_buffer_size()
        .ok_or_else(|| ImageError::InvalidFormat {
            path: path.to_path_buf(),
            format: FORMAT,
            reason: "the image is too large to decode".to_string(),
        })?;
    let mut buffer = vec![0u8; buffer_size];
    let frame = reader.next_frame(&mut buffer).map_err(decoding_error)?;
    let (width, height) = (frame.width as usize, frame.height as usize);
    let channels = match frame.color_type {
        png::ColorType::Grayscale => 1,
        png::ColorType::GrayscaleAlpha => 2,
        png::ColorType::Rgb => 3,
        png::ColorType::Rgba => 4,
        png::ColorType::Indexed => {
            return Err(ImageError::InvalidFormat {
                path: path.to_path_buf(),
                format: FORMAT,
                reason: "the palette was not expanded".to_string(),
            });
        }
    };
    let row_samples = width * channels;
    match frame.bit_depth {
        png::BitDepth::Eight => {
            let mut samples = Vec::with_capacity(row_samples * height);
            for row in buffer[..frame.buffer_size()].chunks_exact(frame.line_size) {
                samples.extend_from_slice(&row[..row_samples]);
            }
            Ok(TextureImage::from_levels(
                width, height, channels, &samples, 255.0, transfer,
            ))
        }
        png::BitDepth::Sixteen => {
            let mut samples: Vec<u16> = Vec::with_capacity(row_samples * height);
            for row in buffer[..frame.buffer_size()].chunks_exact(frame.line_size) {
                samples.extend(
                    row[..2 * row_samples]
                        .chunks_exact(2)
                        .map(|word| u16::from_be_bytes([word[0], word[1]])),
                );
            }
            Ok(TextureImage::from_levels(
                width, height, channels, &samples, 65535.0, transfer,
            ))
        }
        other => Err(ImageError::InvalidFormat {
            path: path.to_path_buf(),
            format: FORMAT,
            reason: format!("bit depth {other:?} was not expanded to 8 bits"),
        }),
    }
}
