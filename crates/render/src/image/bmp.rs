//! Windows BMP files: uncompressed 24- and 32-bit colour (32-bit also with
//! `BI_BITFIELDS` masks) and 8-bit palette images, bottom-up or top-down,
//! decoded to 8-bit RGB tagged sRGB. Run-length-encoded and other bit depths
//! are reported as unsupported. Layout: Microsoft's `BITMAPFILEHEADER` (14
//! bytes) followed by a `BITMAPINFOHEADER` (40 bytes) or one of its larger
//! successors (V4: 108, V5: 124 bytes), optional masks and palette, then rows
//! padded to multiples of 4 bytes.

use std::path::Path;

use super::ImageError;
use super::texture_image::{TextureImage, TransferCurve, read_bytes};

const FORMAT: &str = "BMP";
const FILE_HEADER_SIZE: usize = 14;
/// `BI_RGB`: uncompressed.
const COMPRESSION_NONE: u32 = 0;
/// `BI_BITFIELDS`: uncompressed with channel masks.
const COMPRESSION_BITFIELDS: u32 = 3;

fn u16_at(bytes: &[u8], offset: usize) -> Option<u16> {
    Some(u16::from_le_bytes(
        bytes.get(offset..offset + 2)?.try_into().ok()?,
    ))
}

fn u32_at(bytes: &[u8], offset: usize) -> Option<u32> {
    Some(u32::from_le_bytes(
        bytes.get(offset..offset + 4)?.try_into().ok()?,
    ))
}

/// Extracts the channel selected by `mask` from a 32-bit pixel, scaled to 0–255.
fn masked_channel(pixel: u32, mask: u32) -> u8 {
    if mask == 0 {
        return 0;
    }
    let shift = mask.trailing_zeros();
    let maximum = mask >> shift;
    let value = (pixel & mask) >> shift;
    ((value as u64 * 255 + maximum as u64 / 2) / maximum as u64) as u8
}

/// Reads a BMP file as an sRGB-encoded RGB texture image.
pub fn read_bmp(path: impl AsRef<Path>) -> Result<TextureImage, ImageError> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    decode_bmp(&bytes).map_err(|(truncated, reason)| {
        if truncated {
            ImageError::Truncated {
                path: path.to_path_buf(),
                format: FORMAT,
                reason,
            }
        } else {
            ImageError::InvalidFormat {
                path: path.to_path_buf(),
                format: FORMAT,
                reason,
            }
        }
    })
}

/// Decodes BMP bytes; the error says whether the data ended early and why.
fn decode_bmp(bytes: &[u8]) -> Result<TextureImage, (bool, String)> {
    let truncated = |what: &str| (true, format!("the file ends inside the {what}"));
    let invalid = |reason: String| (false, reason);
    if bytes.get(0..2) != Some(b"BM") {
        return Err(invalid("the file does not start with 'BM'".into()));
    }
    let data_offset = u32_at(bytes, 10).ok_or_else(|| truncated("file header"))? as usize;
    let header_size =
        u32_at(bytes, FILE_HEADER_SIZE).ok_or_else(|| truncated("info header"))? as usize;
    if header_size < 40 {
        return Err(invalid(format!(
            "info header of {header_size} bytes (OS/2 bitmaps are not supported)"
        )));
    }
    let field = |offset: usize| u32_at(bytes, FILE_HEADER_SIZE + offset);
    let width = field(4).ok_or_else(|| truncated("info header"))? as i32;
    let height = field(8).ok_or_else(|| truncated("info header"))? as i32;
    let bits = u16_at(bytes, FILE_HEADER_SIZE + 14).ok_or_else(|| truncated("info header"))?;
    let compression = field(16).ok_or_else(|| truncated("info header"))?;
    let palette_used = field(32).ok_or_else(|| truncated("info header"))? as usize;
    if width <= 0 || height == 0 {
        return Err(invalid(format!("invalid size {width}x{height}")));
    }
    let top_down = height < 0;
    let (width, height) = (width as usize, height.unsigned_abs() as usize);
    let masks = match (bits, compression) {
        (24 | 32 | 8, COMPRESSION_NONE) => None,
        (32, COMPRESSION_BITFIELDS) => {
            // The masks follow a 40-byte header, or are part of a V4/V5 one.
            let at = FILE_HEADER_SIZE + 40;
            let mask =
                |index: usize| u32_at(bytes, at + 4 * index).ok_or_else(|| truncated("masks"));
            Some([mask(0)?, mask(1)?, mask(2)?])
        }
        _ => {
            return Err(invalid(format!(
                "{bits}-bit images with compression {compression} are not supported \
                 (only uncompressed 8-bit palette, 24- and 32-bit)"
            )));
        }
    };
    let palette: Vec<[u8; 3]> = if bits == 8 {
        let count = if palette_used == 0 {
            256
        } else {
            palette_used.min(256)
        };
        let start = FILE_HEADER_SIZE + header_size;
        let table = bytes
            .get(start..start + 4 * count)
            .ok_or_else(|| truncated("palette"))?;
        table.chunks_exact(4).map(|e| [e[2], e[1], e[0]]).collect()
    } else {
        Vec::new()
    };
    let bytes_per_pixel = bits as usize / 8;
    let row_size = (width * bytes_per_pixel).div_ceil(4) * 4;
    let data = bytes
        .get(data_offset..)
        .filter(|data| data.len() >= row_size * (height - 1) + width * bytes_per_pixel)
        .ok_or_else(|| truncated("pixel data"))?;
    let mut samples = Vec::with_capacity(width * height * 3);
    for y in 0..height {
        let stored_row = if top_down { y } else { height - 1 - y };
        let row = &data[stored_row * row_size..stored_row * row_size + width * bytes_per_pixel];
        for pixel in row.chunks_exact(bytes_per_pixel) {
            let rgb = match (bits, masks) {
                (8, _) => *palette
                    .get(pixel[0] as usize)
                    .ok_or_else(|| invalid(format!("palette index {} out of range", pixel[0])))?,
                (32, Some(masks)) => {
                    let value = u32::from_le_bytes([pixel[0], pixel[1], pixel[2], pixel[3]]);
                    masks.map(|mask| masked_channel(value, mask))
                }
                _ => [pixel[2], pixel[1], pixel[0]],
            };
            samples.extend_from_slice(&rgb);
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A BMP file of the given header fields, palette and rows (already padded).
    fn bmp(width: i32, height: i32, bits: u16, palette: &[[u8; 4]], rows: &[u8]) -> Vec<u8> {
        let data_offset = 14 + 40 + 4 * palette.len();
        let mut file = Vec::new();
        file.extend_from_slice(b"BM");
        file.extend_from_slice(&((data_offset + rows.len()) as u32).to_le_bytes());
        file.extend_from_slice(&0u32.to_le_bytes());
        file.extend_from_slice(&(data_offset as u32).to_le_bytes());
        file.extend_from_slice(&40u32.to_le_bytes());
        file.extend_from_slice(&width.to_le_bytes());
        file.extend_from_slice(&height.to_le_bytes());
        file.extend_from_slice(&1u16.to_le_bytes());
        file.extend_from_slice(&bits.to_le_bytes());
        file.extend_from_slice(&0u32.to_le_bytes());
        file.extend_from_slice(&(rows.len() as u32).to_le_bytes());
        file.extend_from_slice(&[0; 8]);
        file.extend_from_slice(&(palette.len() as u32).to_le_bytes());
        file.extend_from_slice(&0u32.to_le_bytes());
        for entry in palette {
            file.extend_from_slice(entry);
        }
        file.extend_from_slice(rows);
        file
    }

    #[test]
    fn bottom_up_24_bit_with_padding() {
        // 2×2: bottom row (stored first) red, green; top row blue, white.
        let rows = [
            0, 0, 255, 0, 255, 0, 0, 0, // bottom row + 2 bytes padding
            255, 0, 0, 255, 255, 255, 0, 0,
        ];
        let image = decode_bmp(&bmp(2, 2, 24, &[], &rows)).unwrap();
        assert_eq!((image.width, image.height, image.channels), (2, 2, 3));
        assert_eq!(image.rgb(0, 0), [0.0, 0.0, 1.0]);
        assert_eq!(image.rgb(1, 0), [1.0, 1.0, 1.0]);
        assert_eq!(image.rgb(0, 1), [1.0, 0.0, 0.0]);
        assert_eq!(image.rgb(1, 1), [0.0, 1.0, 0.0]);
        assert_eq!(image.transfer, TransferCurve::Srgb);
    }

    #[test]
    fn top_down_palette() {
        let palette = [[0, 0, 0, 0], [51, 102, 255, 0]];
        let rows = [1, 0, 0, 0, 0, 1, 0, 0];
        let image = decode_bmp(&bmp(2, -2, 8, &palette, &rows)).unwrap();
        assert_eq!(image.rgb(0, 0), [1.0, 0.4, 0.2]);
        assert_eq!(image.rgb(1, 0), [0.0; 3]);
        assert_eq!(image.rgb(1, 1), [1.0, 0.4, 0.2]);
    }

    #[test]
    fn bad_files_are_errors() {
        assert!(decode_bmp(b"PNG").is_err());
        let mut file = bmp(2, 2, 24, &[], &[0; 16]);
        file.truncate(file.len() - 4);
        assert!(decode_bmp(&file).unwrap_err().0);
        assert!(!decode_bmp(&bmp(2, 2, 16, &[], &[0; 16])).unwrap_err().0);
    }
}
