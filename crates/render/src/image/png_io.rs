//! PNG files: 8-bit sRGB output for viewing, and 8/16-bit input decoded to
//! linear floats (for tests and textures).
//!
//! Writing scales each linear value by `2^exposure`, applies the sRGB
//! transfer function, clamps to `[0, 1]` and rounds to the nearest of the
//! 256 levels (NaN becomes 0); the file is tagged with an `sRGB` chunk and
//! carries the metadata as `tEXt` chunks. Reading expands palettes and
//! low bit depths, replicates grey into RGB, ignores alpha (colours are
//! taken as stored, not un-premultiplied), and always inverts the sRGB
//! transfer function, whatever `gAMA`/`iCCP` chunks say.

use std::fs;
use std::io::BufReader;
use std::path::Path;

use super::srgb::{linear_to_srgb, srgb_to_linear};
use super::{Image, ImageError, Metadata};

const FORMAT: &str = "PNG";

/// Writes `image` as an 8-bit sRGB PNG, each value scaled by
/// `2^exposure_stops` before encoding; `metadata` becomes `tEXt` chunks
/// (keys of 1–79 Latin-1 characters, values Latin-1).
pub fn write_png(
    path: impl AsRef<Path>,
    image: &Image,
    exposure_stops: f32,
    metadata: &Metadata,
) -> Result<(), ImageError> {
    let path = path.as_ref();
    let unwritable = |reason: String| ImageError::Unwritable {
        path: path.to_path_buf(),
        reason,
    };
    let width = u32::try_from(image.width()).ok().filter(|&width| width > 0);
    let height = u32::try_from(image.height())
        .ok()
        .filter(|&height| height > 0);
    let (Some(width), Some(height)) = (width, height) else {
        return Err(unwritable(format!(
            "a PNG cannot hold a {}x{} image",
            image.width(),
            image.height()
        )));
    };
    let scale = exposure_stops.exp2();
    let encode = |value: f32| {
        let encoded = linear_to_srgb(value * scale);
        if encoded.is_nan() {
            0u8
        } else {
            (encoded.clamp(0.0, 1.0) * 255.0).round() as u8
        }
    };
    let data: Vec<u8> = image
        .pixels()
        .iter()
        .flat_map(|pixel| pixel.map(encode))
        .collect();

    let file = fs::File::create(path).map_err(|source| ImageError::Write {
        path: path.to_path_buf(),
        source,
    })?;
    let mut encoder = png::Encoder::new(std::io::BufWriter::new(file), width, height);
    encoder.set_color(png::ColorType::Rgb);
    encoder.set_depth(png::BitDepth::Eight);
    encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
    for (key, value) in metadata {
        let latin1 = |text: &str| text.chars().all(|character| (character as u32) < 256);
        if key.is_empty() || key.chars().count() > 79 || !latin1(key) || !latin1(value) {
            return Err(unwritable(format!(
                "the metadata entry '{key}' cannot be a PNG text chunk \
                 (keys need 1-79 Latin-1 characters, values Latin-1)"
            )));
        }
        encoder
            .add_text_chunk(key.clone(), value.clone())
            .map_err(|error| unwritable(format!("metadata entry '{key}': {error}")))?;
    }
    let encoding_error = |error: png::EncodingError| match error {
        png::EncodingError::IoError(source) => ImageError::Write {
            path: path.to_path_buf(),
            source,
        },
        other => unwritable(other.to_string()),
    };
    let mut writer = encoder.write_header().map_err(encoding_error)?;
    writer.write_image_data(&data).map_err(encoding_error)?;
    writer.finish().map_err(encoding_error)
}

/// Reads a PNG (any bit depth, grey, grey+alpha, RGB, RGBA or palette) into
/// linear RGB floats by inverting the sRGB transfer function; alpha is
/// dropped.
pub fn read_png(path: impl AsRef<Path>) -> Result<Image, ImageError> {
    let path = path.as_ref();
    let file = fs::File::open(path).map_err(|source| ImageError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let decoding_error = |error: png::DecodingError| match error {
        png::DecodingError::IoError(source)
            if source.kind() == std::io::ErrorKind::UnexpectedEof =>
        {
            ImageError::Truncated {
                path: path.to_path_buf(),
                format: FORMAT,
                reason: source.to_string(),
            }
        }
        png::DecodingError::IoError(source) => ImageError::Read {
            path: path.to_path_buf(),
            source,
        },
        other => ImageError::InvalidFormat {
            path: path.to_path_buf(),
            format: FORMAT,
            reason: other.to_string(),
        },
    };
    let mut decoder = png::Decoder::new(BufReader::new(file));
    decoder.set_transformations(png::Transformations::EXPAND);
    let mut reader = decoder.read_info().map_err(decoding_error)?;
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
    let samples: Vec<f32> = match frame.bit_depth {
        png::BitDepth::Eight => {
            let table: Vec<f32> = (0..256)
                .map(|level| srgb_to_linear(level as f32 / 255.0))
                .collect();
            buffer[..frame.buffer_size()]
                .iter()
                .map(|&level| table[level as usize])
                .collect()
        }
        png::BitDepth::Sixteen => buffer[..frame.buffer_size()]
            .chunks_exact(2)
            .map(|word| srgb_to_linear(u16::from_be_bytes([word[0], word[1]]) as f32 / 65535.0))
            .collect(),
        other => {
            return Err(ImageError::InvalidFormat {
                path: path.to_path_buf(),
                format: FORMAT,
                reason: format!("bit depth {other:?} was not expanded to 8 bits"),
            });
        }
    };
    let row_samples = width * channels;
    let line_size = frame.line_size
        / if frame.bit_depth == png::BitDepth::Sixteen {
            2
        } else {
            1
        };
    let mut pixels = Vec::with_capacity(width * height);
    for row in 0..height {
        let line = &samples[row * line_size..row * line_size + row_samples];
        for pixel in line.chunks_exact(channels) {
            pixels.push(if channels < 3 {
                [pixel[0]; 3]
            } else {
                [pixel[0], pixel[1], pixel[2]]
            });
        }
    }
    Image::from_pixels(width, height, pixels)
}
