//! The portable float map (PFM): a text header and raw 32-bit floats.
//!
//! Layout: `PF` (RGB) or `Pf` (one grey channel), whitespace, width and
//! height, whitespace, a scale whose sign gives the byte order (negative:
//! little-endian, positive: big-endian), one whitespace character, then the
//! samples with rows stored bottom to top. The magnitude of the scale is
//! ignored on reading (as pbrt-v4 does) and written as 1. Grey images are
//! read with the value replicated into R, G and B.

use std::fs;
use std::io::Write;
use std::path::Path;

use super::{Image, ImageError};

const FORMAT: &str = "PFM";

/// Writes `image` as a little-endian RGB PFM (scale `-1`), bit exact.
pub fn write_pfm(path: impl AsRef<Path>, image: &Image) -> Result<(), ImageError> {
    let path = path.as_ref();
    let header = format!("PF\n{} {}\n-1\n", image.width(), image.height());
    let mut bytes = Vec::with_capacity(header.len() + image.pixels().len() * 12);
    bytes.extend_from_slice(header.as_bytes());
    for row in (0..image.height()).rev() {
        let start = row * image.width();
        for pixel in &image.pixels()[start..start + image.width()] {
            for channel in pixel {
                bytes.extend_from_slice(&channel.to_le_bytes());
            }
        }
    }
    let write_error = |source| ImageError::Write {
        path: path.to_path_buf(),
        source,
    };
    let mut file = fs::File::create(path).map_err(write_error)?;
    file.write_all(&bytes).map_err(write_error)
}

/// Reads a PFM file (`PF` or `Pf`, either byte order) into an RGB image,
/// top row first.
pub fn read_pfm(path: impl AsRef<Path>) -> Result<Image, ImageError> {
    let path = path.as_ref();
    let bytes = fs::read(path).map_err(|source| ImageError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let invalid = |reason: String| ImageError::InvalidFormat {
        path: path.to_path_buf(),
        format: FORMAT,
        reason,
    };

    let mut cursor = 0usize;
    let mut tokens = Vec::with_capacity(4);
    while tokens.len() < 4 {
        while cursor < bytes.len() && bytes[cursor].is_ascii_whitespace() {
            cursor += 1;
        }
        let start = cursor;
        while cursor < bytes.len() && !bytes[cursor].is_ascii_whitespace() {
            cursor += 1;
        }
        if start == cursor {
            return Err(ImageError::Truncated {
                path: path.to_path_buf(),
                format: FORMAT,
                reason: format!("the header ends after {} of its 4 fields", tokens.len()),
            });
        }
        let token = String::from_utf8_lossy(&bytes[start..cursor]).into_owned();
        if tokens.is_empty() && token != "PF" && token != "Pf" {
            return Err(invalid(format!(
                "the header starts with '{}' instead of 'PF' or 'Pf'",
                token.chars().take(16).collect::<String>()
            )));
        }
        tokens.push(token);
    }
    let channels = if tokens[0] == "PF" { 3 } else { 1 };
    let parse_dimension = |token: &str, name: &str| {
        token
            .parse::<usize>()
            .ok()
            .filter(|&value| value > 0)
            .ok_or_else(|| invalid(format!("the {name} '{token}' is not a positive integer")))
    };
    let width = parse_dimension(&tokens[1], "width")?;
    let height = parse_dimension(&tokens[2], "height")?;
    let scale: f32 = tokens[3]
        .parse()
        .ok()
        .filter(|scale: &f32| scale.is_finite() && *scale != 0.0)
        .ok_or_else(|| {
            invalid(format!(
                "the scale '{}' is not a non-zero number",
                tokens[3]
            ))
        })?;
    let little_endian = scale < 0.0;
    // Exactly one whitespace character separates the header from the data.
    if cursor >= bytes.len() {
        return Err(ImageError::Truncated {
            path: path.to_path_buf(),
            format: FORMAT,
            reason: "no pixel data follows the header".to_string(),
        });
    }
    cursor += 1;

    let sample_count = width
        .checked_mul(height)
        .and_then(|pixels| pixels.checked_mul(channels))
        .ok_or_else(|| invalid(format!("the size {width}x{height} is too large")))?;
    let data = &bytes[cursor..];
    let expected_bytes = sample_count as u128 * 4;
    if (data.len() as u128) < expected_bytes {
        return Err(ImageError::Truncated {
            path: path.to_path_buf(),
            format: FORMAT,
            reason: format!(
                "{width}x{height} pixels of {channels} channel(s) need {expected_bytes} bytes of data, \
                 but the file has {}",
                data.len()
            ),
        });
    }

    let sample = |index: usize| {
        let word: [u8; 4] = data[index * 4..index * 4 + 4].try_into().unwrap_or([0; 4]);
        if little_endian {
            f32::from_le_bytes(word)
        } else {
            f32::from_be_bytes(word)
        }
    };
    let mut pixels = Vec::with_capacity(width * height);
    for row in 0..height {
        let file_row = height - 1 - row;
        for column in 0..width {
            let first = (file_row * width + column) * channels;
            pixels.push(if channels == 3 {
                [sample(first), sample(first + 1), sample(first + 2)]
            } else {
                let grey = sample(first);
                [grey; 3]
            });
        }
    }
    Image::from_pixels(width, height, pixels)
}
