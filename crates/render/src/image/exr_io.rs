//! OpenEXR files through the `exr` crate.
//!
//! Writing: one part, scan lines with ZIP compression (lossless, read by
//! every EXR tool), 32-bit float channels `R`, `G`, `B`, and for each extra
//! layer named `name` the channels `name.R`, `name.G`, `name.B` (the EXR
//! convention for layers inside one part, shown as layers by viewers such
//! as tev). The film's per-pixel variance goes in the layer
//! [`VARIANCE_LAYER`]. Metadata entries become custom string attributes of
//! the header.
//!
//! Reading: every part and every channel group; a group is RGB when it has
//! `R`, `G` and `B` channels (an `A` is ignored) and grey when it has only
//! `Y` (replicated). Half, float and unsigned-integer samples are all
//! converted to `f32`. The size is that of the data window; pixels are
//! stored top row first. All string attributes become metadata.

use std::collections::BTreeMap;
use std::fs;
use std::io::{BufReader, BufWriter};
use std::path::Path;

use exr::meta::attribute::{AttributeValue, Text};
use exr::prelude::{
    AnyChannel, AnyChannels, Encoding, FlatSamples, Image as ExrImage, Layer, LayerAttributes,
    ReadChannels, ReadLayers, SmallVec, WritableImage,
};

use super::{Image, ImageError, Metadata};

const FORMAT: &str = "OpenEXR";

/// The layer name under which the film's variance image is stored.
pub const VARIANCE_LAYER: &str = "variance";

/// Everything [`read_exr`] found in a file.
#[derive(Debug, Clone, PartialEq)]
pub struct ExrContents {
    /// The main RGB image: the channel group without a layer prefix, or
    /// else the first RGB (or grey) group of the file.
    pub image: Image,
    /// The other RGB (or grey) channel groups, keyed by layer name (for a
    /// multi-part file, `part.layer`).
    pub layers: BTreeMap<String, Image>,
    /// The string attributes of the headers (for example what
    /// [`write_exr`] stored: integrator, sampler, spp, seed, render time).
    pub metadata: Metadata,
}

/// Writes `image` as 32-bit float RGB, with each `(name, image)` of
/// `extra_layers` as channels `name.R`, `name.G`, `name.B` and `metadata`
/// as custom string attributes. Layers must have the main image's size;
/// names and metadata must be Latin-1, and metadata keys must not be one
/// of the attribute names the EXR standard reserves (`channels`, `owner`,
/// ...).
pub fn write_exr(
    path: impl AsRef<Path>,
    image: &Image,
    extra_layers: &[(&str, &Image)],
    metadata: &Metadata,
) -> Result<(), ImageError> {
    let path = path.as_ref();
    let unwritable = |reason: String| ImageError::Unwritable {
        path: path.to_path_buf(),
        reason,
    };
    if image.width() == 0 || image.height() == 0 {
        return Err(unwritable(format!(
            "an OpenEXR file cannot hold an empty {}x{} image",
            image.width(),
            image.height()
        )));
    }

    let mut channels: SmallVec<[AnyChannel<FlatSamples>; 4]> = SmallVec::new();
    let mut add_group = |prefix: &str, group: &Image| -> Result<(), ImageError> {
        if group.width() != image.width() || group.height() != image.height() {
            return Err(unwritable(format!(
                "layer '{prefix}' is {}x{} but the image is {}x{}",
                group.width(),
                group.height(),
                image.width(),
                image.height()
            )));
        }
        for (channel, letter) in ["R", "G", "B"].into_iter().enumerate() {
            let name = if prefix.is_empty() {
                letter.to_string()
            } else {
                format!("{prefix}.{letter}")
            };
            let name = Text::new_or_none(&name)
                .ok_or_else(|| unwritable(format!("the channel name '{name}' is not Latin-1")))?;
            let samples = group.pixels().iter().map(|pixel| pixel[channel]).collect();
            channels.push(AnyChannel::new(name, FlatSamples::F32(samples)));
        }
        Ok(())
    };
    add_group("", image)?;
    for (name, layer) in extra_layers {
        if name.is_empty() || name.contains('.') {
            return Err(unwritable(format!(
                "the layer name '{name}' must be non-empty and contain no '.'"
            )));
        }
        add_group(name, layer)?;
    }

    let mut attributes = LayerAttributes::default();
    for (key, value) in metadata {
        let reserved = exr::meta::header::standard_names::ALL
            .iter()
            .any(|name| name.eq_ignore_ascii_case(key.as_bytes()));
        if key.is_empty() || reserved {
            return Err(unwritable(format!(
                "the metadata key '{key}' is empty or a reserved OpenEXR attribute name"
            )));
        }
        let (Some(key_text), Some(value_text)) = (Text::new_or_none(key), Text::new_or_none(value))
        else {
            return Err(unwritable(format!(
                "the metadata entry '{key}' is not Latin-1 text"
            )));
        };
        attributes
            .other
            .insert(key_text, AttributeValue::Text(value_text));
    }

    let layer = Layer::new(
        (image.width(), image.height()),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels),
    );
    let file = fs::File::create(path).map_err(|source| ImageError::Write {
        path: path.to_path_buf(),
        source,
    })?;
    ExrImage::from_layer(layer)
        .write()
        .to_buffered(BufWriter::new(file))
        .map_err(|error| match error {
            exr::error::Error::Io(source) => ImageError::Write {
                path: path.to_path_buf(),
                source,
            },
            other => unwritable(other.to_string()),
        })
}

/// Reads an OpenEXR file: the main RGB image, the other RGB layers and the
/// string attributes (see the module documentation for what is accepted).
pub fn read_exr(path: impl AsRef<Path>) -> Result<ExrContents, ImageError> {
    let path = path.as_ref();
    let file = fs::File::open(path).map_err(|source| ImageError::Read {
        path: path.to_path_buf(),
        source,
    })?;
    let exr_image = exr::prelude::read()
        .no_deep_data()
        .largest_resolution_level()
        .all_channels()
        .all_layers()
        .all_attributes()
        .from_buffered(BufReader::new(file))
        .map_err(|error| match error {
            exr::error::Error::Io(source) if source.kind() == std::io::ErrorKind::UnexpectedEof => {
                ImageError::Truncated {
                    path: path.to_path_buf(),
                    format: FORMAT,
                    reason: source.to_string(),
                }
            }
            exr::error::Error::Io(source) => ImageError::Read {
                path: path.to_path_buf(),
                source,
            },
            other => ImageError::InvalidFormat {
                path: path.to_path_buf(),
                format: FORMAT,
                reason: other.to_string(),
            },
        })?;

    let mut metadata = Metadata::new();
    let mut collect_text = |attributes: &std::collections::HashMap<Text, AttributeValue>| {
        for (key, value) in attributes {
            if let AttributeValue::Text(text) = value {
                metadata.insert(key.to_string(), text.to_string());
            }
        }
    };
    collect_text(&exr_image.attributes.other);

    let mut main_image = None;
    let mut groups: Vec<(String, Image)> = Vec::new();
    for layer in &exr_image.layer_data {
        collect_text(&layer.attributes.other);
        let (width, height) = (layer.size.width(), layer.size.height());
        let part_name = layer
            .attributes
            .layer_name
            .as_ref()
            .map(|name| name.to_string())
            .unwrap_or_default();
        // Channel groups by prefix (everything before the last '.').
        let mut by_prefix: BTreeMap<String, BTreeMap<String, &FlatSamples>> = BTreeMap::new();
        for channel in &layer.channel_data.list {
            let name = channel.name.to_string();
            let (prefix, letter) = match name.rfind('.') {
                Some(dot) => (name[..dot].to_string(), name[dot + 1..].to_string()),
                None => (String::new(), name.clone()),
            };
            by_prefix
                .entry(prefix)
                .or_default()
                .insert(letter.to_ascii_uppercase(), &channel.sample_data);
        }
        for (prefix, letters) in by_prefix {
            let Some(pixels) = group_pixels(&letters, width * height) else {
                continue;
            };
            let image = Image::from_pixels(width, height, pixels)?;
            let full_name = match (part_name.is_empty(), prefix.is_empty()) {
                (true, _) => prefix,
                (false, true) => part_name.clone(),
                (false, false) => format!("{part_name}.{prefix}"),
            };
            if full_name.is_empty() && main_image.is_none() {
                main_image = Some(image);
            } else {
                groups.push((full_name, image));
            }
        }
    }
    let image = match main_image {
        Some(image) => image,
        None if !groups.is_empty() => groups.remove(0).1,
        None => {
            return Err(ImageError::InvalidFormat {
                path: path.to_path_buf(),
                format: FORMAT,
                reason: "no R, G, B (or Y) channels found".to_string(),
            });
        }
    };
    Ok(ExrContents {
        image,
        layers: groups.into_iter().collect(),
        metadata,
    })
}

/// The RGB pixels of one channel group, or `None` when it is neither RGB
/// nor grey (`Y`) or its sample count is not `pixel_count`.
fn group_pixels(
    letters: &BTreeMap<String, &FlatSamples>,
    pixel_count: usize,
) -> Option<Vec<[f32; 3]>> {
    let values = |letter: &str| -> Option<Vec<f32>> {
        let samples = letters.get(letter)?;
        let values: Vec<f32> = samples.values_as_f32().collect();
        (values.len() == pixel_count).then_some(values)
    };
    if let (Some(red), Some(green), Some(blue)) = (values("R"), values("G"), values("B")) {
        return Some(
            (0..pixel_count)
                .map(|index| [red[index], green[index], blue[index]])
                .collect(),
        );
    }
    let grey = values("Y")?;
    Some(grey.into_iter().map(|value| [value; 3]).collect())
}
