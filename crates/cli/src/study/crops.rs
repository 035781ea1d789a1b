//! A strip of crops: the same rectangle of several images side by side,
//! enlarged so that small renders can be looked at, for comparing noise
//! and bias by eye.

use super::equal_time::write_failure;
use crate::error::{CliError, usage};
use crate::json::Json;
use render::image::{Image, Metadata, write_png};
use std::path::Path;

/// The smallest height in pixels of a crop in the strip: crops are
/// enlarged by the smallest integer factor that reaches it.
pub const MINIMUM_PANEL_HEIGHT: usize = 128;

/// Pixels between two crops in the strip (white).
pub const GAP: usize = 4;

/// A rectangle of an image, in pixels (row 0 at the top).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct CropRectangle {
    /// The left column.
    pub x: usize,
    /// The top row.
    pub y: usize,
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
}

impl CropRectangle {
    /// The square of side min(width, height) / 2 centred in a
    /// `width`×`height` image (at least one pixel).
    pub fn centred_square(width: usize, height: usize) -> Self {
        let side = (width.min(height) / 2).max(1);
        Self {
            x: (width - side.min(width)) / 2,
            y: (height - side.min(height)) / 2,
            width: side,
            height: side,
        }
    }

    /// Parses `X,Y,W,H` (`--crop`), which must lie inside a
    /// `width`×`height` image.
    pub fn parse(text: &str, width: usize, height: usize) -> Result<Self, CliError> {
        let numbers: Vec<usize> = text
            .split(',')
            .map(|part| part.trim().parse::<usize>())
            .collect::<Result<_, _>>()
            .map_err(|_| {
                usage(format!(
                    "--crop: expected X,Y,W,H in pixels (non-negative integers), got `{text}`"
                ))
            })?;
        let [x, y, crop_width, crop_height] = numbers[..] else {
            return Err(usage(format!(
                "--crop: expected four numbers X,Y,W,H, got `{text}`"
            )));
        };
        if crop_width == 0 || crop_height == 0 {
            return Err(usage("--crop: the width and height must be at least 1"));
        }
        if x.saturating_add(crop_width) > width || y.saturating_add(crop_height) > height {
            return Err(usage(format!(
                "--crop {x},{y},{crop_width},{crop_height} lies outside the {width}x{height} image"
            )));
        }
        Ok(Self {
            x,
            y,
            width: crop_width,
            height: crop_height,
        })
    }

    /// The integer factor that enlarges the crop to at least
    /// [`MINIMUM_PANEL_HEIGHT`] pixels tall.
    pub fn enlargement(&self) -> usize {
        MINIMUM_PANEL_HEIGHT.div_ceil(self.height).max(1)
    }

    /// The rectangle and its enlargement as a JSON object (the studies'
    /// tables).
    pub fn json(&self) -> Json {
        Json::object(vec![
            ("x", Json::Integer(self.x as u64)),
            ("y", Json::Integer(self.y as u64)),
            ("width", Json::Integer(self.width as u64)),
            ("height", Json::Integer(self.height as u64)),
            ("enlargement", Json::Integer(self.enlargement() as u64)),
        ])
    }
}

/// Writes to `path` the strip of the crop `rectangle` of each panel's
/// image ([`crop_strip`]), tone-mapped as `lqmc render`'s PNG, with the
/// panels' names, the crop, its enlargement and `extra` in its metadata.
pub fn write_crop_strip(
    path: &Path,
    panels: &[(String, &Image)],
    rectangle: CropRectangle,
    extra: &[(&str, String)],
) -> Result<(), CliError> {
    let images: Vec<&Image> = panels.iter().map(|(_, image)| *image).collect();
    let strip = crop_strip(&images, rectangle);
    let mut metadata = Metadata::new();
    let names: Vec<&str> = panels.iter().map(|(name, _)| name.as_str()).collect();
    metadata.insert("panels".into(), names.join(", "));
    metadata.insert(
        "crop".into(),
        format!(
            "{},{},{},{}",
            rectangle.x, rectangle.y, rectangle.width, rectangle.height
        ),
    );
    metadata.insert("enlargement".into(), rectangle.enlargement().to_string());
    for (key, value) in extra {
        metadata.insert((*key).to_string(), value.clone());
    }
    write_png(path, &strip, 0.0, &metadata).map_err(|error| write_failure(path, error))
}

/// The crop `rectangle` of each of `images`, enlarged by
/// [`CropRectangle::enlargement`] (nearest neighbour), side by side in the
/// order given with [`GAP`] white pixels between them. Panics if the
/// rectangle is not inside every image.
pub fn crop_strip(images: &[&Image], rectangle: CropRectangle) -> Image {
    let factor = rectangle.enlargement();
    let panel_width = rectangle.width * factor;
    let panel_height = rectangle.height * factor;
    let count = images.len().max(1);
    let strip_width = count * panel_width + (count - 1) * GAP;
    let mut strip = Image::from_pixels(
        strip_width,
        panel_height,
        vec![[1.0; 3]; strip_width * panel_height],
    )
    .expect("the strip's pixel count matches its size");
    for (panel, image) in images.iter().enumerate() {
        assert!(
            rectangle.x + rectangle.width <= image.width()
                && rectangle.y + rectangle.height <= image.height(),
            "the crop lies inside every image"
        );
        let left = panel * (panel_width + GAP);
        for row in 0..panel_height {
            for column in 0..panel_width {
                let source_x = rectangle.x + column / factor;
                let source_y = rectangle.y + row / factor;
                let value = image
                    .pixel(source_x, source_y)
                    .expect("the crop lies inside the image");
                strip.set_pixel(left + column, row, value);
            }
        }
    }
    strip
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_default_crop_is_a_centred_square() {
        let crop = CropRectangle::centred_square(24, 18);
        assert_eq!(
            crop,
            CropRectangle {
                x: 7,
                y: 4,
                width: 9,
                height: 9
            }
        );
        assert_eq!(CropRectangle::centred_square(1, 1).width, 1);
    }

    #[test]
    fn crops_outside_the_image_are_refused() {
        assert!(CropRectangle::parse("0,0,24,18", 24, 18).is_ok());
        assert!(CropRectangle::parse("1,0,24,18", 24, 18).is_err());
        assert!(CropRectangle::parse("0,0,0,5", 24, 18).is_err());
        assert!(CropRectangle::parse("0,0,5", 24, 18).is_err());
        assert!(CropRectangle::parse("a,0,5,5", 24, 18).is_err());
    }

    #[test]
    fn the_strip_enlarges_each_crop_with_gaps() {
        let first =
            Image::from_pixels(2, 2, vec![[0.0; 3], [0.25; 3], [0.5; 3], [0.75; 3]]).unwrap();
        let second = Image::from_pixels(2, 2, vec![[2.0; 3]; 4]).unwrap();
        let rectangle = CropRectangle {
            x: 1,
            y: 0,
            width: 1,
            height: 2,
        };
        let strip = crop_strip(&[&first, &second], rectangle);
        assert_eq!(rectangle.enlargement(), 64);
        assert_eq!((strip.width(), strip.height()), (64 * 2 + GAP, 128));
        assert_eq!(strip.pixel(0, 0), Some([0.25; 3]));
        assert_eq!(strip.pixel(63, 127), Some([0.75; 3]));
        assert_eq!(strip.pixel(64, 0), Some([1.0; 3]));
        assert_eq!(strip.pixel(64 + GAP, 5), Some([2.0; 3]));
    }
}
