//! `Material`, `MakeNamedMaterial` and `Texture`: pbrt-v4's `diffuse`,
//! `conductor`, `dielectric`, `thindielectric`, `coateddiffuse`,
//! `coatedconductor`, `interface`
//! (and `mix`, read as its first material), with the `displacement` (bump)
//! and `normalmap` every material may have; textures `imagemap`,
//! `checkerboard`, `constant` and `scale` (of constants).
//!
//! Defaults (pbrt-v4's file-format reference): diffuse reflectance 0.5;
//! conductor `eta` = `metal-Cu-eta`, `k` = `metal-Cu-k`, roughness 0;
//! dielectric `eta` 1.5; coateddiffuse reflectance 0.5, roughness 0,
//! thickness 0.01, `eta` 1.5, albedo 0, g 0, maxdepth 10, nsamples 1;
//! coatedconductor `interface.roughness` 0, `interface.eta` 1.5,
//! `conductor.eta` = `metal-Cu-eta`, `conductor.k` = `metal-Cu-k` (or
//! `reflectance`, as for `conductor`), `conductor.roughness` 0, thickness
//! 0.01, albedo 0, g 0, maxdepth 10, nsamples 1; `remaproughness` true;
//! `uroughness` and `vroughness` default to `roughness` (likewise with the
//! `interface.` and `conductor.` prefixes).

use super::parameters::{ParameterList, Position};
use super::parser::Loader;
use crate::scene::description::{
    ColourEncoding, MaterialDescription, MicrofacetDistribution, RoughnessDescription,
    SpectrumDescription, TextureDescription, TextureFilter, TextureWrap,
};
use crate::scene::loader::SceneFileError;
use crate::spectrum::{CIE_LAMBDA_MAX, CIE_LAMBDA_MIN, RgbAlbedoSpectrum};
use glam::{Affine2, Vec2};

/// Below this α a microfacet surface is treated as smooth (pbrt-v4's
/// `TrowbridgeReitzDistribution::EffectivelySmooth`).
const SMOOTH_ALPHA: f32 = 1.0e-3;

fn constant(value: f32) -> TextureDescription {
    TextureDescription::Constant(SpectrumDescription::Constant(value))
}

/// The constant value of a float texture, if it is one.
fn constant_value(texture: &TextureDescription) -> Option<f32> {
    match texture {
        TextureDescription::Constant(SpectrumDescription::Constant(value)) => Some(*value),
        _ => None,
    }
}

impl Loader {
    /// A float texture called `name`.
    pub fn float_texture_named(
        &self,
        name: &str,
        position: &Position,
    ) -> Result<TextureDescription, SceneFileError> {
        self.float_textures.get(name).cloned().ok_or_else(|| {
            position.error(format!(
                "no float texture named \"{name}\" (expected a Texture \"{name}\" \"float\" ... before)"
            ))
        })
    }

    /// A float-valued, texturable parameter: `"float name"` or
    /// `"texture name"`; `None` if absent.
    pub fn float_texture(
        &self,
        parameters: &ParameterList,
        name: &str,
    ) -> Result<Option<TextureDescription>, SceneFileError> {
        if let Some(texture) = parameters.texture_reference(name)? {
            let position = parameters.find(name).expect("present").position.clone();
            return self.float_texture_named(&texture, &position).map(Some);
        }
        Ok(parameters.optional_float(name)?.map(constant))
    }

    /// A spectrum-valued, texturable parameter: `rgb`, `spectrum`,
    /// `blackbody` or `texture`; `None` if absent.
    pub fn spectrum_texture(
        &self,
        parameters: &ParameterList,
        name: &str,
    ) -> Result<Option<TextureDescription>, SceneFileError> {
        let Some(parameter) = parameters.find(name) else {
            return Ok(None);
        };
        if parameter.type_name == "texture" {
            let texture = parameters
                .texture_reference(name)?
                .expect("a texture parameter");
            return self
                .spectrum_textures
                .get(&texture)
                .cloned()
                .map(Some)
                .ok_or_else(|| {
                    parameter.position.error(format!(
                        "no spectrum texture named \"{texture}\" (expected a Texture \"{texture}\" \"spectrum\" ... before)"
                    ))
                });
        }
        if parameter.type_name == "float" {
            // pbrt-v4 reads a float where a spectrum texture is expected as
            // that constant.
            return Ok(parameters.optional_float(name)?.map(constant));
        }
        Ok(Some(TextureDescription::Constant(
            self.spectrum_of(parameter)?,
        )))
    }

    /// A non-texturable spectrum (conductor `eta`, `k`; dielectric `eta`):
    /// a float is a constant; a texture is not supported.
    fn plain_spectrum(
        &mut self,
        parameters: &ParameterList,
        name: &str,
    ) -> Result<Option<SpectrumDescription>, SceneFileError> {
        let Some(parameter) = parameters.find(name) else {
            return Ok(None);
        };
        match parameter.type_name {
            "float" => Ok(parameters
                .optional_float(name)?
                .map(SpectrumDescription::Constant)),
            "texture" => {
                let position = parameter.position.clone();
                self.warn(
                    &position,
                    format!("parameter \"{name}\": textured values are not supported here; the default is used"),
                );
                Ok(None)
            }
            _ => self.spectrum_of(parameter).map(Some),
        }
    }

    /// The microfacet roughness of a material (`roughness`, `uroughness`,
    /// `vroughness`, `remaproughness`), `None` when effectively smooth.
    fn roughness(
        &self,
        parameters: &ParameterList,
    ) -> Result<Option<RoughnessDescription>, SceneFileError> {
        self.prefixed_roughness(parameters, "")
    }

    /// [`Self::roughness`] of the parameters named with `prefix`
    /// (`interface.`, `conductor.`: `interface.roughness`, ...); the
    /// `remaproughness` flag has no prefix.
    fn prefixed_roughness(
        &self,
        parameters: &ParameterList,
        prefix: &str,
    ) -> Result<Option<RoughnessDescription>, SceneFileError> {
        let roughness = self
            .float_texture(parameters, &format!("{prefix}roughness"))?
            .unwrap_or(constant(0.0));
        let alpha_u = self
            .float_texture(parameters, &format!("{prefix}uroughness"))?
            .unwrap_or_else(|| roughness.clone());
        let alpha_v = self
            .float_texture(parameters, &format!("{prefix}vroughness"))?
            .unwrap_or(roughness);
        let remap = parameters.bool("remaproughness", true)?;
        let effective = |texture: &TextureDescription| {
            constant_value(texture).map(|r| if remap { r.max(0.0).sqrt() } else { r })
        };
        match (effective(&alpha_u), effective(&alpha_v)) {
            (Some(u), Some(v)) if u < SMOOTH_ALPHA && v < SMOOTH_ALPHA => Ok(None),
            _ => Ok(Some(RoughnessDescription {
                distribution: MicrofacetDistribution::Ggx,
                alpha_u,
                alpha_v,
                remap,
            })),
        }
    }

    /// A dielectric's `eta` as a single number (coated diffuse, thin dielectric).
    fn scalar_eta(
        &mut self,
        parameters: &ParameterList,
        position: &Position,
        what: &str,
    ) -> Result<f32, SceneFileError> {
        self.scalar_index(parameters, "eta", position, what)
    }

    /// The index of refraction called `name` as a single number (default
    /// 1.5; a spectrum is warned about and replaced by 1.5).
    fn scalar_index(
        &mut self,
        parameters: &ParameterList,
        name: &str,
        position: &Position,
        what: &str,
    ) -> Result<f32, SceneFileError> {
        Ok(match self.plain_spectrum(parameters, name)? {
            None => 1.5,
            Some(SpectrumDescription::Constant(eta)) => eta,
            Some(_) => {
                self.warn(
                    position,
                    format!("{what}: a spectrally varying eta is not supported here; 1.5 is used"),
                );
                1.5
            }
        })
    }

    /// A conductor's complex index: `{prefix}eta` and `{prefix}k` (default
    /// copper), or pbrt-v4's artist `reflectance` (a constant), not both;
    /// `kind` names the material in errors.
    fn conductor_index(
        &mut self,
        parameters: &ParameterList,
        position: &Position,
        kind: &str,
        prefix: &str,
    ) -> Result<(SpectrumDescription, SpectrumDescription), SceneFileError> {
        let eta_name = format!("{prefix}eta");
        let k_name = format!("{prefix}k");
        if let Some(reflectance) = self.spectrum_texture(parameters, "reflectance")? {
            if parameters.has(&eta_name) || parameters.has(&k_name) {
                return Err(position.error(format!(
                    "Material \"{kind}\": give either \"reflectance\" or \"{eta_name}\" and \"{k_name}\", not both"
                )));
            }
            return artist_conductor(&reflectance).ok_or_else(|| {
                position.error(format!(
                    "Material \"{kind}\": a textured \"reflectance\" is not supported (expected a constant rgb or spectrum)"
                ))
            });
        }
        Ok((
            self.plain_spectrum(parameters, &eta_name)?
                .unwrap_or(SpectrumDescription::Named("metal-Cu-eta".into())),
            self.plain_spectrum(parameters, &k_name)?
                .unwrap_or(SpectrumDescription::Named("metal-Cu-k".into())),
        ))
    }

    /// The material of type `kind`.
    pub fn material(
        &mut self,
        kind: &str,
        parameters: &ParameterList,
        position: &Position,
    ) -> Result<MaterialDescription, SceneFileError> {
        let base = match kind {
            "diffuse" => MaterialDescription::Diffuse {
                reflectance: self
                    .spectrum_texture(parameters, "reflectance")?
                    .unwrap_or(constant(0.5)),
                two_sided: true,
            },
            "conductor" => {
                let roughness = self.roughness(parameters)?;
                let (eta, k) = self.conductor_index(parameters, position, kind, "")?;
                MaterialDescription::Conductor {
                    eta,
                    k,
                    specular_reflectance: None,
                    roughness,
                    two_sided: true,
                }
            }
            "dielectric" => MaterialDescription::Dielectric {
                interior_ior: self
                    .plain_spectrum(parameters, "eta")?
                    .unwrap_or(SpectrumDescription::Constant(1.5)),
                exterior_ior: 1.0,
                roughness: self.roughness(parameters)?,
            },
            "thindielectric" => MaterialDescription::ThinDielectric {
                interior_ior: self.scalar_eta(
                    parameters,
                    position,
                    "Material \"thindielectric\"",
                )?,
                exterior_ior: 1.0,
            },
            "coateddiffuse" => {
                let (max_depth, samples, thickness) = layer_parameters(parameters, position, kind)?;
                MaterialDescription::CoatedDiffuse {
                    reflectance: self
                        .spectrum_texture(parameters, "reflectance")?
                        .unwrap_or(constant(0.5)),
                    interior_ior: self.scalar_eta(
                        parameters,
                        position,
                        "Material \"coateddiffuse\"",
                    )?,
                    roughness: self.roughness(parameters)?,
                    thickness,
                    albedo: self
                        .spectrum_texture(parameters, "albedo")?
                        .unwrap_or(constant(0.0)),
                    g: parameters.float("g", 0.0)?,
                    max_depth,
                    samples,
                }
            }
            "coatedconductor" => {
                let (max_depth, samples, thickness) = layer_parameters(parameters, position, kind)?;
                let (conductor_eta, conductor_k) =
                    self.conductor_index(parameters, position, kind, "conductor.")?;
                MaterialDescription::CoatedConductor {
                    interface_ior: self.scalar_index(
                        parameters,
                        "interface.eta",
                        position,
                        "Material \"coatedconductor\"",
                    )?,
                    interface_roughness: self.prefixed_roughness(parameters, "interface.")?,
                    conductor_eta,
                    conductor_k,
                    conductor_roughness: self.prefixed_roughness(parameters, "conductor.")?,
                    thickness,
                    albedo: self
                        .spectrum_texture(parameters, "albedo")?
                        .unwrap_or(constant(0.0)),
                    g: parameters.float("g", 0.0)?,
                    max_depth,
                    samples,
                }
            }
            "interface" | "" | "none" => MaterialDescription::Interface,
            "mix" => {
                let names = parameters.strings("materials")?.unwrap_or_default();
                parameters.find("amount");
                self.warn(
                    position,
                    "Material \"mix\" is not supported; its first material is used",
                );
                match names.first() {
                    Some(name) => self.named_materials.get(name).cloned().ok_or_else(|| {
                        position.error(format!("Material \"mix\": no material named \"{name}\""))
                    })?,
                    None => {
                        return Err(position.error(
                            "Material \"mix\": expected a \"string materials\" parameter with two names",
                        ));
                    }
                }
            }
            other => {
                self.warn(
                    position,
                    format!("Material \"{other}\" is not supported; a diffuse material of reflectance 0.5 is used"),
                );
                for parameter in &parameters.parameters {
                    parameters.find(&parameter.name);
                }
                return Ok(super::graphics_state::default_material());
            }
        };
        let mut material = base;
        if let Some(height) = self.float_texture(parameters, "displacement")? {
            material = MaterialDescription::BumpMap {
                height,
                scale: 1.0,
                nested: Box::new(material),
                options: crate::material::PerturbationOptions::default(),
            };
        }
        if let Some(filename) = parameters.string("normalmap")? {
            let path = self.resolve(&filename, position);
            if !path.is_file() {
                return Err(position.error(format!(
                    "normal map \"{filename}\" not found (looked for {})",
                    path.display()
                )));
            }
            material = MaterialDescription::NormalMap {
                normals: TextureDescription::Bitmap {
                    filename: path,
                    encoding: Some(ColourEncoding::Linear),
                    filter: TextureFilter::Bilinear,
                    wrap: TextureWrap::Repeat,
                    to_uv: Affine2::IDENTITY,
                    flip_vertically: true,
                    scale: 1.0,
                    invert: false,
                },
                nested: Box::new(material),
                options: crate::material::PerturbationOptions::default(),
            };
        }
        Ok(material)
    }

    /// `Texture "name" "spectrum"|"float" "class" ...`.
    pub fn texture_directive(
        &mut self,
        name: &str,
        value_type: &str,
        class: &str,
        parameters: &ParameterList,
        position: &Position,
    ) -> Result<(), SceneFileError> {
        let is_float = match value_type {
            "float" => true,
            "spectrum" | "color" | "rgb" => false,
            other => {
                return Err(position.error(format!(
                    "Texture \"{name}\": expected the type \"spectrum\" or \"float\", found \"{other}\""
                )));
            }
        };
        let to_uv = self.texture_mapping(parameters, position)?;
        let texture = match class {
            "imagemap" => {
                let filename = parameters.string("filename")?.ok_or_else(|| {
                    position.error(format!(
                        "Texture \"{name}\" \"imagemap\": expected a \"string filename\" parameter"
                    ))
                })?;
                let path = self.resolve(&filename, position);
                if !path.is_file() {
                    return Err(position.error(format!(
                        "Texture \"{name}\": image \"{filename}\" not found (looked for {})",
                        path.display()
                    )));
                }
                let encoding = match parameters.string("encoding")?.as_deref() {
                    None => None,
                    Some("sRGB") | Some("srgb") => Some(ColourEncoding::Srgb),
                    Some("linear") => Some(ColourEncoding::Linear),
                    Some(other) => match other
                        .strip_prefix("gamma ")
                        .and_then(|g| g.trim().parse::<f32>().ok())
                    {
                        Some(gamma) => Some(ColourEncoding::Gamma(gamma)),
                        None => {
                            return Err(position.error(format!(
                                "Texture \"{name}\": unknown encoding \"{other}\" (expected \"sRGB\", \"linear\" or \"gamma G\")"
                            )));
                        }
                    },
                };
                let filter = match parameters.string("filter")?.as_deref() {
                    Some("point") => TextureFilter::Nearest,
                    _ => TextureFilter::Bilinear,
                };
                let wrap = match parameters.string("wrap")?.as_deref() {
                    None | Some("repeat") => TextureWrap::Repeat,
                    Some("clamp") => TextureWrap::Clamp,
                    Some("black") => {
                        self.warn(
                            position,
                            "Texture: wrap \"black\" is not supported; \"clamp\" is used",
                        );
                        TextureWrap::Clamp
                    }
                    Some(other) => {
                        self.warn(
                            position,
                            format!(
                                "Texture: wrap \"{other}\" is not supported; \"repeat\" is used"
                            ),
                        );
                        TextureWrap::Repeat
                    }
                };
                parameters.float("maxanisotropy", 8.0)?;
                TextureDescription::Bitmap {
                    filename: path,
                    encoding,
                    filter,
                    wrap,
                    to_uv,
                    // pbrt-v4 looks images up with v = 0 at the bottom row.
                    flip_vertically: true,
                    scale: parameters.float("scale", 1.0)?,
                    invert: parameters.bool("invert", false)?,
                }
            }
            "checkerboard" => {
                let dimension = parameters.integer("dimension", 2)?;
                if dimension != 2 {
                    self.warn(
                        position,
                        "Texture \"checkerboard\": only dimension 2 is supported",
                    );
                }
                let (even, odd) = if is_float {
                    (
                        self.float_texture(parameters, "tex1")?
                            .unwrap_or(constant(1.0)),
                        self.float_texture(parameters, "tex2")?
                            .unwrap_or(constant(0.0)),
                    )
                } else {
                    (
                        self.spectrum_texture(parameters, "tex1")?
                            .unwrap_or(constant(1.0)),
                        self.spectrum_texture(parameters, "tex2")?
                            .unwrap_or(constant(0.0)),
                    )
                };
                TextureDescription::Checkerboard {
                    even: Box::new(even),
                    odd: Box::new(odd),
                    to_uv,
                }
            }
            "constant" => {
                if is_float {
                    constant(parameters.float("value", 1.0)?)
                } else {
                    self.spectrum_texture(parameters, "value")?
                        .unwrap_or(constant(1.0))
                }
            }
            "scale" => {
                let texture = if is_float {
                    self.float_texture(parameters, "tex")?
                } else {
                    self.spectrum_texture(parameters, "tex")?
                }
                .unwrap_or(constant(1.0));
                let scale = self
                    .float_texture(parameters, "scale")?
                    .unwrap_or(constant(1.0));
                match (constant_value(&scale), texture) {
                    (Some(factor), TextureDescription::Constant(spectrum)) => {
                        TextureDescription::Constant(super::spectrum_values::scaled(
                            spectrum, factor,
                        ))
                    }
                    (
                        Some(factor),
                        TextureDescription::Bitmap {
                            filename,
                            encoding,
                            filter,
                            wrap,
                            to_uv,
                            flip_vertically,
                            scale,
                            invert,
                        },
                    ) if !invert => TextureDescription::Bitmap {
                        filename,
                        encoding,
                        filter,
                        wrap,
                        to_uv,
                        flip_vertically,
                        scale: scale * factor,
                        invert,
                    },
                    (_, texture) => {
                        self.warn(position, "Texture \"scale\": only constant scales of constants and image maps are supported; the texture is used unscaled");
                        texture
                    }
                }
            }
            other => {
                self.warn(
                    position,
                    format!(
                        "Texture class \"{other}\" is not supported; \"{name}\" is the constant 0.5"
                    ),
                );
                for parameter in &parameters.parameters {
                    parameters.find(&parameter.name);
                }
                constant(0.5)
            }
        };
        let textures = if is_float {
            &mut self.float_textures
        } else {
            &mut self.spectrum_textures
        };
        if textures.insert(name.to_string(), texture).is_some() {
            self.warn(position, format!("texture \"{name}\" redefined"));
        }
        Ok(())
    }

    /// pbrt's `mapping "uv"` with `uscale`, `vscale`, `udelta`, `vdelta`.
    fn texture_mapping(
        &mut self,
        parameters: &ParameterList,
        position: &Position,
    ) -> Result<Affine2, SceneFileError> {
        let mapping = parameters.string("mapping")?.unwrap_or_else(|| "uv".into());
        if mapping != "uv" {
            self.warn(
                position,
                format!("Texture: mapping \"{mapping}\" is not supported; \"uv\" is used"),
            );
        }
        let scale = Vec2::new(
            parameters.float("uscale", 1.0)?,
            parameters.float("vscale", 1.0)?,
        );
        let delta = Vec2::new(
            parameters.float("udelta", 0.0)?,
            parameters.float("vdelta", 0.0)?,
        );
        Ok(Affine2::from_scale_angle_translation(scale, 0.0, delta))
    }
}

/// The parameters of pbrt-v4's layered materials (`coateddiffuse`,
/// `coatedconductor`): `maxdepth` (default 10) and `nsamples` (1), at least
/// 1, and `thickness` (0.01), finite and non-negative.
fn layer_parameters(
    parameters: &ParameterList,
    position: &Position,
    kind: &str,
) -> Result<(u32, u32, f32), SceneFileError> {
    let count = |name: &str, default: i64| -> Result<u32, SceneFileError> {
        let value = parameters.integer(name, default)?;
        u32::try_from(value)
            .ok()
            .filter(|&v| v >= 1)
            .ok_or_else(|| {
                position.error(format!(
                    "Material \"{kind}\": \"{name}\" must be at least 1, got {value}"
                ))
            })
    };
    let max_depth = count("maxdepth", 10)?;
    let samples = count("nsamples", 1)?;
    let thickness = parameters.float("thickness", 0.01)?;
    if !(thickness.is_finite() && thickness >= 0.0) {
        return Err(position.error(format!(
            "Material \"{kind}\": \"thickness\" must be finite and non-negative, got {thickness}"
        )));
    }
    Ok((max_depth, samples, thickness))
}

/// pbrt-v4's conductor from a `reflectance` r: η = 1 and
/// k = 2√r / √(1 − r), which gives normal-incidence Fresnel reflectance r
/// (pbrt-v4's `ConductorMaterial`). Constant reflectances only; an RGB one
/// is lifted to its reflectance spectrum first and tabulated every 5 nm.
fn artist_conductor(
    reflectance: &TextureDescription,
) -> Option<(SpectrumDescription, SpectrumDescription)> {
    let TextureDescription::Constant(spectrum) = reflectance else {
        return None;
    };
    let k_of = |r: f32| {
        let r = r.clamp(0.0, 0.9999);
        2.0 * r.sqrt() / (1.0 - r).sqrt()
    };
    let k = match spectrum {
        SpectrumDescription::Constant(r) => SpectrumDescription::Constant(k_of(*r)),
        SpectrumDescription::Rgb(rgb) => {
            let lifted = RgbAlbedoSpectrum::new(rgb.map(|c| c.clamp(0.0, 1.0))).ok()?;
            let wavelengths: Vec<f32> = (CIE_LAMBDA_MIN..=CIE_LAMBDA_MAX)
                .step_by(5)
                .map(|l| l as f32)
                .collect();
            let values = wavelengths
                .iter()
                .map(|&l| k_of(lifted.evaluate(l)))
                .collect();
            SpectrumDescription::Sampled {
                wavelengths,
                values,
            }
        }
        SpectrumDescription::Sampled {
            wavelengths,
            values,
        } => SpectrumDescription::Sampled {
            wavelengths: wavelengths.clone(),
            values: values.iter().map(|&r| k_of(r)).collect(),
        },
        _ => return None,
    };
    Some((SpectrumDescription::Constant(1.0), k))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn artist_conductor_reproduces_the_normal_incidence_reflectance() {
        let (eta, k) = artist_conductor(&constant(0.6)).unwrap();
        assert_eq!(eta, SpectrumDescription::Constant(1.0));
        let SpectrumDescription::Constant(k) = k else {
            panic!("constant k expected")
        };
        // Fresnel at normal incidence for η = 1: k² / (4 + k²).
        let r = k * k / (4.0 + k * k);
        assert!((r - 0.6).abs() < 1e-5, "{r}");
    }
}
