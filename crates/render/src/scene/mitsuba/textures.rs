//! Mitsuba's textures (`bitmap`, `checkerboard`, `rawconstant`) and texture-valued
//! parameters, which may also be a constant (`<rgb>`, `<float>`, ...) or a
//! `<ref>` to a texture defined earlier.

use super::super::description::{
    SpectrumDescription, TextureDescription, TextureFilter, TextureWrap,
};
use super::super::loader::SceneFileError;
use super::transforms::to_uv_2d;
use super::values::Properties;
use super::xml::Element;
use super::{Loader, NamedObject};
use glam::{Affine2, Vec2};

impl Loader {
    /// Reads a `<texture>` plugin (and registers its id).
    pub(super) fn texture(
        &mut self,
        element: &Element,
    ) -> Result<TextureDescription, SceneFileError> {
        let properties = Properties::new(element);
        let to_uv = properties
            .optional_transform("to_uv")?
            .map_or(Affine2::IDENTITY, to_uv_2d);
        let texture = match properties.plugin_type() {
            "bitmap" => {
                let name = properties.optional_string("filename")?.ok_or_else(|| {
                    element
                        .location
                        .error("bitmap texture needs a 'filename' string")
                })?;
                let filename = self.resolve(element, name, "texture")?;
                let raw = properties.boolean("raw", false)?;
                let filter = match properties.optional_string("filter_type")? {
                    None | Some("bilinear") => TextureFilter::Bilinear,
                    Some("nearest") => TextureFilter::Nearest,
                    Some(other) => {
                        return Err(element.location.error(format!(
                            "filter_type '{other}': expected bilinear or nearest"
                        )));
                    }
                };
                let wrap = match properties.optional_string("wrap_mode")? {
                    None | Some("repeat") => TextureWrap::Repeat,
                    Some("mirror") => TextureWrap::Mirror,
                    Some("clamp") => TextureWrap::Clamp,
                    Some(other) => {
                        return Err(element.location.error(format!(
                            "wrap_mode '{other}': expected repeat, mirror or clamp"
                        )));
                    }
                };
                properties.ignore(&["format"]);
                TextureDescription::Bitmap {
                    filename,
                    // Mitsuba: 8-bit images are sRGB-encoded unless `raw`;
                    // float images are linear either way.
                    encoding: raw.then_some(super::super::description::ColourEncoding::Linear),
                    filter,
                    wrap,
                    to_uv,
                    // Mitsuba's uv (0, 0) is the image's top-left corner.
                    flip_vertically: false,
                    scale: 1.0,
                    invert: false,
                }
            }
            "checkerboard" => {
                let even = self.texture_parameter(&properties, "color0")?.unwrap_or(
                    TextureDescription::Constant(SpectrumDescription::Constant(0.4)),
                );
                let odd = self.texture_parameter(&properties, "color1")?.unwrap_or(
                    TextureDescription::Constant(SpectrumDescription::Constant(0.2)),
                );
                // Mitsuba's squares are ½ wide in its transformed uv; the
                // description's are 1 wide (see `texture::checkerboard`).
                TextureDescription::Checkerboard {
                    even: Box::new(even),
                    odd: Box::new(odd),
                    to_uv: Affine2::from_scale(Vec2::splat(2.0)) * to_uv,
                }
            }
            "rawconstant" => {
                // A value used as is (no colour conversion): normal maps' constant.
                let value = match properties.optional_vector("value")? {
                    Some(vector) => SpectrumDescription::Rgb(vector.to_array()),
                    None => {
                        let read = |element: &Element, file: &str| self.read_text(element, file);
                        properties
                            .optional_spectrum("value", &read)?
                            .unwrap_or(SpectrumDescription::Constant(1.0))
                    }
                };
                TextureDescription::Constant(value)
            }
            other => {
                self.warn(
                    element,
                    format!("unknown texture type '{other}': replaced by a constant 0.5"),
                );
                TextureDescription::Constant(SpectrumDescription::Constant(0.5))
            }
        };
        self.finish(&properties);
        self.register(element, NamedObject::Texture(texture.clone()))?;
        Ok(texture)
    }

    /// A texture-valued parameter: a nested `<texture name>`, a
    /// `<ref name id>` to a texture, or a constant value.
    pub(super) fn texture_parameter(
        &mut self,
        properties: &Properties,
        name: &str,
    ) -> Result<Option<TextureDescription>, SceneFileError> {
        let read = |element: &Element, file: &str| self.read_text(element, file);
        if let Some(spectrum) = properties.optional_spectrum(name, &read)? {
            return Ok(Some(TextureDescription::Constant(spectrum)));
        }
        let Some(element) = properties.get(name) else {
            return Ok(None);
        };
        match element.tag.as_str() {
            "texture" => self.texture(element).map(Some),
            "ref" => match self.referenced(element)? {
                NamedObject::Texture(texture) => Ok(Some(texture)),
                other => Err(element.location.error(format!(
                    "parameter '{name}' refers to a {}, expected a texture",
                    other.kind()
                ))),
            },
            other => Err(element.location.error(format!(
                "parameter '{name}' must be a texture or a spectral value, got <{other}>"
            ))),
        }
    }

    /// A texture parameter that Mitsuba reads as a float (`eval_1`: the
    /// roughness of the rough BSDFs), with a constant default.
    ///
    /// Mitsuba 3's `checkerboard` is inconsistent between its evaluations:
    /// `eval` (spectrum) gives `color0` in the square at the origin but
    /// `eval_1` (float) gives `color1` there (Mitsuba 3.9.1, scalar_rgb and
    /// scalar_spectral: color0 = 0.05, color1 = 0.3 at uv (0.1, 0.1) give
    /// `eval` 0.05 and `eval_1` 0.3). Its reference images follow `eval_1`
    /// for textured roughness (bsdf_spheres/test_textured_roughconductor), so
    /// a checkerboard read here has its two textures swapped.
    pub(super) fn float_texture_or(
        &mut self,
        properties: &Properties,
        name: &str,
        default: f32,
    ) -> Result<TextureDescription, SceneFileError> {
        Ok(match self.texture_or(properties, name, default)? {
            TextureDescription::Checkerboard { even, odd, to_uv } => {
                TextureDescription::Checkerboard {
                    even: odd,
                    odd: even,
                    to_uv,
                }
            }
            other => other,
        })
    }

    /// A texture parameter with a constant default.
    pub(super) fn texture_or(
        &mut self,
        properties: &Properties,
        name: &str,
        default: f32,
    ) -> Result<TextureDescription, SceneFileError> {
        Ok(self
            .texture_parameter(properties, name)?
            .unwrap_or(TextureDescription::Constant(SpectrumDescription::Constant(
                default,
            ))))
    }

    /// A spectral parameter that must not vary over the surface (e.g. an
    /// emitter's intensity, an index of refraction).
    pub(super) fn spectrum_parameter(
        &mut self,
        properties: &Properties,
        name: &str,
    ) -> Result<Option<SpectrumDescription>, SceneFileError> {
        let element = properties.element;
        match self.texture_parameter(properties, name)? {
            None => Ok(None),
            Some(TextureDescription::Constant(spectrum)) => Ok(Some(spectrum)),
            Some(_) => Err(element.location.error(format!(
                "parameter '{name}' of {} '{}' must be a constant (rgb, spectrum, float), not a texture",
                element.tag,
                properties.plugin_type()
            ))),
        }
    }
}
