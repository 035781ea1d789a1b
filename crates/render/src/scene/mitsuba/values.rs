//! A plugin's parameters (Mitsuba's `Properties`): its named value children
//! (`<float>`, `<integer>`, `<boolean>`, `<string>`, `<rgb>`, `<srgb>`,
//! `<spectrum>`, `<blackbody>`, `<point>`, `<vector>`, `<transform>`, named
//! `<texture>`s and `<ref>`s) and its nested plugins, with typed accessors
//! that apply the plugin's defaults and errors that name file and line.
//!
//! Every parameter read is marked; [`Properties::finish`] warns about the
//! ones a plugin did not read (Mitsuba 3 fails on those; a warning keeps a
//! scene with an extra option renderable).

use super::super::description::SpectrumDescription;
use super::super::loader::SceneFileError;
use super::transforms::parse_transform;
use super::xml::Element;
use glam::{Affine3A, Vec3};
use std::cell::RefCell;
use std::collections::HashSet;

/// Tags of value elements (which carry a `name`).
const VALUE_TAGS: &[&str] = &[
    "float",
    "integer",
    "boolean",
    "string",
    "rgb",
    "srgb",
    "spectrum",
    "blackbody",
    "point",
    "vector",
    "transform",
];

/// The numbers of a list separated by commas and/or white space.
pub fn parse_numbers(text: &str) -> Result<Vec<f32>, String> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|part| !part.is_empty())
        .map(|part| {
            part.parse::<f32>()
                .map_err(|_| format!("'{part}' is not a number"))
        })
        .collect()
}

/// One number.
pub fn parse_number(text: &str) -> Result<f32, String> {
    let numbers = parse_numbers(text)?;
    match numbers.as_slice() {
        [value] => Ok(*value),
        _ => Err(format!("expected one number, got '{text}'")),
    }
}

/// The parameters of one plugin element.
#[derive(Debug)]
pub struct Properties<'a> {
    pub element: &'a Element,
    named: Vec<(&'a str, &'a Element)>,
    used: RefCell<HashSet<&'a str>>,
    /// Nested plugins and unnamed references, in document order.
    pub objects: Vec<&'a Element>,
}

impl<'a> Properties<'a> {
    /// Sorts `element`'s children into named values and nested objects.
    pub fn new(element: &'a Element) -> Self {
        let mut named = Vec::new();
        let mut objects = Vec::new();
        for child in &element.children {
            match child.attribute("name") {
                Some(name)
                    if VALUE_TAGS.contains(&child.tag.as_str())
                        || matches!(child.tag.as_str(), "texture" | "ref") =>
                {
                    named.push((name, child));
                }
                _ => objects.push(child),
            }
        }
        Self {
            element,
            named,
            used: RefCell::new(HashSet::new()),
            objects,
        }
    }

    /// The plugin's `type` attribute.
    pub fn plugin_type(&self) -> &'a str {
        self.element.attribute("type").unwrap_or("")
    }

    /// The value element called `name`, marked as read.
    pub fn get(&self, name: &str) -> Option<&'a Element> {
        let (key, element) = self.named.iter().rev().find(|(key, _)| *key == name)?;
        self.used.borrow_mut().insert(key);
        Some(element)
    }

    /// Marks parameters as read without reading them (ones that do not
    /// change the image, such as `far_clip` or `pixel_format`).
    pub fn ignore(&self, names: &[&str]) {
        for name in names {
            let _ = self.get(name);
        }
    }

    /// Whether the plugin has a parameter `name` (without marking it).
    pub fn has(&self, name: &str) -> bool {
        self.named.iter().any(|(key, _)| *key == name)
    }

    fn error(&self, element: &Element, message: impl Into<String>) -> SceneFileError {
        element.location.error(message)
    }

    fn value_text(&self, element: &'a Element, name: &str) -> Result<&'a str, SceneFileError> {
        element.attribute("value").ok_or_else(|| {
            self.error(
                element,
                format!(
                    "<{} name=\"{name}\"> needs a 'value' attribute",
                    element.tag
                ),
            )
        })
    }

    fn expect_tag(
        &self,
        element: &Element,
        name: &str,
        tags: &[&str],
    ) -> Result<(), SceneFileError> {
        if tags.contains(&element.tag.as_str()) {
            Ok(())
        } else {
            Err(self.error(
                element,
                format!(
                    "parameter '{name}' of {} '{}' must be {}, got <{}>",
                    self.element.tag,
                    self.plugin_type(),
                    tags.iter()
                        .map(|t| format!("<{t}>"))
                        .collect::<Vec<_>>()
                        .join(" or "),
                    element.tag
                ),
            ))
        }
    }

    /// A number (`<float>` or `<integer>`), if given.
    pub fn optional_float(&self, name: &str) -> Result<Option<f32>, SceneFileError> {
        let Some(element) = self.get(name) else {
            return Ok(None);
        };
        self.expect_tag(element, name, &["float", "integer"])?;
        let text = self.value_text(element, name)?;
        parse_number(text)
            .map(Some)
            .map_err(|message| self.error(element, format!("parameter '{name}': {message}")))
    }

    /// A number with a default.
    pub fn float(&self, name: &str, default: f32) -> Result<f32, SceneFileError> {
        Ok(self.optional_float(name)?.unwrap_or(default))
    }

    /// An integer, if given.
    pub fn optional_integer(&self, name: &str) -> Result<Option<i64>, SceneFileError> {
        let Some(element) = self.get(name) else {
            return Ok(None);
        };
        self.expect_tag(element, name, &["integer"])?;
        let text = self.value_text(element, name)?;
        text.trim().parse::<i64>().map(Some).map_err(|_| {
            self.error(
                element,
                format!("parameter '{name}': '{text}' is not an integer"),
            )
        })
    }

    /// A boolean with a default.
    pub fn boolean(&self, name: &str, default: bool) -> Result<bool, SceneFileError> {
        let Some(element) = self.get(name) else {
            return Ok(default);
        };
        self.expect_tag(element, name, &["boolean"])?;
        match self
            .value_text(element, name)?
            .trim()
            .to_ascii_lowercase()
            .as_str()
        {
            "true" | "1" => Ok(true),
            "false" | "0" => Ok(false),
            other => Err(self.error(
                element,
                format!("parameter '{name}': expected true or false, got '{other}'"),
            )),
        }
    }

    /// A string, if given.
    pub fn optional_string(&self, name: &str) -> Result<Option<&'a str>, SceneFileError> {
        let Some(element) = self.get(name) else {
            return Ok(None);
        };
        self.expect_tag(element, name, &["string"])?;
        self.value_text(element, name).map(Some)
    }

    /// A point or vector (`x`, `y`, `z` attributes or `value="x, y, z"`).
    pub fn optional_vector(&self, name: &str) -> Result<Option<Vec3>, SceneFileError> {
        let Some(element) = self.get(name) else {
            return Ok(None);
        };
        self.expect_tag(element, name, &["point", "vector"])?;
        parse_vector(element, 0.0).map(Some)
    }

    /// A transform (`<transform name="...">`), if given.
    pub fn optional_transform(&self, name: &str) -> Result<Option<Affine3A>, SceneFileError> {
        let Some(element) = self.get(name) else {
            return Ok(None);
        };
        self.expect_tag(element, name, &["transform"])?;
        parse_transform(element).map(Some)
    }

    /// A spectral value (`<rgb>`, `<srgb>`, `<spectrum>`, `<blackbody>` or
    /// `<float>`), if given as a value (textures are read by the caller).
    pub fn optional_spectrum(
        &self,
        name: &str,
        read_file: &dyn Fn(&Element, &str) -> Result<String, SceneFileError>,
    ) -> Result<Option<SpectrumDescription>, SceneFileError> {
        let Some(element) = self.named.iter().rev().find(|(key, _)| *key == name) else {
            return Ok(None);
        };
        let element = element.1;
        if matches!(element.tag.as_str(), "texture" | "ref") {
            return Ok(None);
        }
        let _ = self.get(name);
        self.expect_tag(
            element,
            name,
            &["rgb", "srgb", "spectrum", "blackbody", "float", "integer"],
        )?;
        parse_spectrum(element, read_file).map(Some)
    }

    /// Warns about every parameter the plugin did not read.
    pub fn finish(&self, warnings: &mut Vec<String>) {
        let used = self.used.borrow();
        for (name, element) in &self.named {
            if !used.contains(name) {
                warnings.push(element.location.warning(format!(
                    "parameter '{name}' of {} '{}' is not used by this renderer",
                    self.element.tag,
                    self.plugin_type()
                )));
            }
        }
    }
}

/// A point or vector element; missing coordinates are `default`.
pub fn parse_vector(element: &Element, default: f32) -> Result<Vec3, SceneFileError> {
    let error = |message: String| element.location.error(message);
    if let Some(value) = element.attribute("value") {
        let numbers = parse_numbers(value).map_err(&error)?;
        return match numbers.as_slice() {
            [x, y, z] => Ok(Vec3::new(*x, *y, *z)),
            [v] => Ok(Vec3::splat(*v)),
            _ => Err(error(format!(
                "<{}> value '{value}': expected 3 numbers",
                element.tag
            ))),
        };
    }
    let mut result = Vec3::splat(default);
    for (index, axis) in ["x", "y", "z"].iter().enumerate() {
        if let Some(text) = element.attribute(axis) {
            result[index] = parse_number(text).map_err(|m| error(format!("'{axis}': {m}")))?;
        }
    }
    Ok(result)
}

/// An sRGB-encoded colour: `#rrggbb` or three numbers in [0, 1], linearised.
fn parse_srgb(text: &str) -> Result<[f32; 3], String> {
    let encoded = if let Some(hex) = text.trim().strip_prefix('#') {
        if hex.len() != 6 || !hex.is_ascii() {
            return Err(format!("'{text}' is not a #rrggbb colour"));
        }
        let channel = |i: usize| {
            u8::from_str_radix(&hex[2 * i..2 * i + 2], 16)
                .map(|v| v as f32 / 255.0)
                .map_err(|_| format!("'{text}' is not a #rrggbb colour"))
        };
        [channel(0)?, channel(1)?, channel(2)?]
    } else {
        match parse_numbers(text)?.as_slice() {
            [v] => [*v; 3],
            [r, g, b] => [*r, *g, *b],
            _ => return Err(format!("expected 1 or 3 numbers, got '{text}'")),
        }
    };
    Ok(encoded.map(crate::image::srgb_to_linear))
}

/// `λ:value, λ:value, ...` pairs (or an `.spd` file's `λ value` lines).
fn parse_sampled(text: &str, separator: char) -> Result<SpectrumDescription, String> {
    let mut wavelengths = Vec::new();
    let mut values = Vec::new();
    let pairs: Vec<&str> = if separator == ':' {
        text.split(',').filter(|p| !p.trim().is_empty()).collect()
    } else {
        text.lines()
            .map(|line| line.split('#').next().unwrap_or(""))
            .filter(|line| !line.trim().is_empty())
            .collect()
    };
    for pair in pairs {
        let parts: Vec<&str> = if separator == ':' {
            pair.split(':').collect()
        } else {
            pair.split_whitespace().collect()
        };
        let [wavelength, value] = parts.as_slice() else {
            return Err(format!("'{pair}' is not a wavelength:value pair"));
        };
        let wavelength = parse_number(wavelength)?;
        if wavelengths.last().is_some_and(|&last| wavelength <= last) {
            return Err(format!(
                "wavelengths must increase ({wavelength} follows {})",
                wavelengths.last().copied().unwrap_or(0.0)
            ));
        }
        wavelengths.push(wavelength);
        values.push(parse_number(value)?);
    }
    if wavelengths.is_empty() {
        return Err("the spectrum has no samples".into());
    }
    Ok(SpectrumDescription::Sampled {
        wavelengths,
        values,
    })
}

/// A spectral value element. `read_file` reads a `<spectrum filename>`
/// (resolved along the search path).
pub fn parse_spectrum(
    element: &Element,
    read_file: &dyn Fn(&Element, &str) -> Result<String, SceneFileError>,
) -> Result<SpectrumDescription, SceneFileError> {
    let error = |message: String| {
        element
            .location
            .error(format!("<{}>: {message}", element.tag))
    };
    match element.tag.as_str() {
        "float" | "integer" => {
            let value = parse_number(element.required("value")?).map_err(error)?;
            Ok(SpectrumDescription::Constant(value))
        }
        "rgb" => {
            let text = element.required("value")?;
            if text.trim().starts_with('#') {
                return parse_srgb(text)
                    .map(SpectrumDescription::Rgb)
                    .map_err(error);
            }
            match parse_numbers(text).map_err(error)?.as_slice() {
                [v] => Ok(SpectrumDescription::Rgb([*v; 3])),
                [r, g, b] => Ok(SpectrumDescription::Rgb([*r, *g, *b])),
                _ => Err(error(format!("expected 1 or 3 numbers, got '{text}'"))),
            }
        }
        "srgb" => parse_srgb(element.required("value")?)
            .map(SpectrumDescription::Rgb)
            .map_err(error),
        "blackbody" => {
            let temperature = element.required("temperature")?;
            let temperature = temperature
                .trim()
                .trim_end_matches(['k', 'K'])
                .parse::<f32>()
                .map_err(|_| error(format!("'{temperature}' is not a temperature")))?;
            let blackbody = SpectrumDescription::Blackbody { temperature };
            match element.attribute("scale") {
                Some(scale) => Ok(SpectrumDescription::Scaled {
                    scale: parse_number(scale).map_err(error)?,
                    spectrum: Box::new(blackbody),
                }),
                None => Ok(blackbody),
            }
        }
        "spectrum" => {
            if let Some(filename) = element.attribute("filename") {
                let text = read_file(element, filename)?;
                return parse_sampled(&text, ' ').map_err(error);
            }
            let text = element.required("value")?;
            if text.contains(':') {
                parse_sampled(text, ':').map_err(error)
            } else {
                parse_number(text)
                    .map(SpectrumDescription::Constant)
                    .map_err(error)
            }
        }
        other => Err(error(format!("<{other}> is not a spectral value"))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::mitsuba::xml::Location;
    use std::path::PathBuf;
    use std::sync::Arc;

    fn element(tag: &str, attributes: &[(&str, &str)]) -> Element {
        Element {
            tag: tag.into(),
            attributes: attributes
                .iter()
                .map(|(k, v)| (k.to_string(), v.to_string()))
                .collect(),
            children: Vec::new(),
            location: Location {
                file: Arc::new(PathBuf::from("s.xml")),
                line: 7,
            },
        }
    }

    fn no_file(_: &Element, _: &str) -> Result<String, SceneFileError> {
        unreachable!()
    }

    #[test]
    fn spectral_values() {
        let spectrum = |tag, attributes: &[(&str, &str)]| {
            parse_spectrum(&element(tag, attributes), &no_file).unwrap()
        };
        assert_eq!(
            spectrum("rgb", &[("value", "0.1, 0.2 0.3")]),
            SpectrumDescription::Rgb([0.1, 0.2, 0.3])
        );
        assert_eq!(
            spectrum("rgb", &[("value", "0.5")]),
            SpectrumDescription::Rgb([0.5; 3])
        );
        assert_eq!(
            spectrum("spectrum", &[("value", "0.7")]),
            SpectrumDescription::Constant(0.7)
        );
        assert_eq!(
            spectrum("spectrum", &[("value", "400:0.1, 500:0.2")]),
            SpectrumDescription::Sampled {
                wavelengths: vec![400.0, 500.0],
                values: vec![0.1, 0.2]
            }
        );
        assert_eq!(
            spectrum("float", &[("value", "2")]),
            SpectrumDescription::Constant(2.0)
        );
        assert_eq!(
            spectrum("blackbody", &[("temperature", "6500K")]),
            SpectrumDescription::Blackbody {
                temperature: 6500.0
            }
        );
        let SpectrumDescription::Rgb(white) = spectrum("srgb", &[("value", "#ffffff")]) else {
            panic!()
        };
        assert!(white.iter().all(|&c| (c - 1.0).abs() < 1e-6));
        let SpectrumDescription::Rgb(grey) = spectrum("srgb", &[("value", "0.5")]) else {
            panic!()
        };
        assert!((grey[0] - 0.214).abs() < 1e-3, "{grey:?}");
    }

    #[test]
    fn bad_values_name_file_and_line() {
        let error = parse_spectrum(&element("rgb", &[("value", "1 2")]), &no_file)
            .unwrap_err()
            .to_string();
        assert!(error.starts_with("s.xml:7:"), "{error}");
        let error = parse_spectrum(&element("spectrum", &[("value", "500:1, 400:2")]), &no_file)
            .unwrap_err()
            .to_string();
        assert!(error.contains("increase"), "{error}");
    }

    #[test]
    fn vectors() {
        assert_eq!(
            parse_vector(&element("point", &[("x", "1"), ("z", "3")]), 0.0).unwrap(),
            Vec3::new(1.0, 0.0, 3.0)
        );
        assert_eq!(
            parse_vector(&element("vector", &[("value", "1,2,3")]), 0.0).unwrap(),
            Vec3::new(1.0, 2.0, 3.0)
        );
    }
}
