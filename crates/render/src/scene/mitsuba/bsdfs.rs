//! Mitsuba's BSDFs: `diffuse`, `conductor`/`roughconductor`,
//! `dielectric`/`roughdielectric`, `thindielectric`,
//! `plastic`/`roughplastic`, `twosided`, `bumpmap`, `normalmap`, `mask`,
//! `null`, `principled` and `principledthin`.
//!
//! Conventions carried over: Mitsuba's diffuse, conductor and plastic are
//! one-sided (black from behind) unless wrapped in `twosided`; dielectrics
//! scatter from both sides. Only the ratio of interior to exterior index
//! matters to Mitsuba, so indices are stored as that ratio with an exterior
//! of 1. Rough materials default to Beckmann with α = 0.1.

use super::super::description::{
    MaterialDescription, MicrofacetDistribution, PrincipledDescription, RoughnessDescription,
    SpectrumDescription, TextureDescription,
};
use super::super::loader::SceneFileError;
use super::named_values::{conductor_spectra, named_ior};
use super::values::Properties;
use super::xml::Element;
use super::{Loader, NamedObject};

/// `bumpmap` and `normalmap`'s `flip_invalid_normals` and
/// `use_shadowing_function` (Mitsuba 3.7.1; both default to true).
fn perturbation_options(
    properties: &Properties,
) -> Result<crate::material::PerturbationOptions, SceneFileError> {
    Ok(crate::material::PerturbationOptions {
        flip_invalid_normals: properties.boolean("flip_invalid_normals", true)?,
        shadowing_function: properties.boolean("use_shadowing_function", true)?,
    })
}

/// `material` wrapped so that both sides scatter (Mitsuba `twosided` with
/// one child).
fn two_sided(material: MaterialDescription) -> MaterialDescription {
    use MaterialDescription as M;
    match material {
        M::Diffuse { reflectance, .. } => M::Diffuse {
            reflectance,
            two_sided: true,
        },
        M::Conductor {
            eta,
            k,
            specular_reflectance,
            roughness,
            ..
        } => M::Conductor {
            eta,
            k,
            specular_reflectance,
            roughness,
            two_sided: true,
        },
        M::Plastic {
            diffuse_reflectance,
            interior_ior,
            exterior_ior,
            roughness,
            nonlinear,
            ..
        } => M::Plastic {
            diffuse_reflectance,
            interior_ior,
            exterior_ior,
            roughness,
            nonlinear,
            two_sided: true,
        },
        M::BumpMap {
            height,
            scale,
            nested,
            options,
        } => M::BumpMap {
            height,
            scale,
            nested: Box::new(two_sided(*nested)),
            options,
        },
        M::NormalMap {
            normals,
            nested,
            options,
        } => M::NormalMap {
            normals,
            nested: Box::new(two_sided(*nested)),
            options,
        },
        M::Mask { opacity, nested } => M::Mask {
            opacity,
            nested: Box::new(two_sided(*nested)),
        },
        // Mirror, dielectrics, null and black look the same from both sides.
        other => other,
    }
}

impl Loader {
    /// An index of refraction: a number or one of Mitsuba's names.
    fn ior(
        &self,
        properties: &Properties,
        name: &str,
        default: &str,
    ) -> Result<f32, SceneFileError> {
        let Some(element) = properties.get(name) else {
            return Ok(named_ior(default).expect("the default IOR name is in the table"));
        };
        let text = element.required("value")?;
        match element.tag.as_str() {
            "string" => named_ior(text).ok_or_else(|| {
                element.location.error(format!(
                    "unknown index of refraction '{text}' for '{name}' (expected a number or a name such as bk7, water, air, diamond)"
                ))
            }),
            "float" | "integer" => super::values::parse_number(text)
                .map_err(|message| element.location.error(format!("'{name}': {message}"))),
            other => Err(element.location.error(format!(
                "'{name}' must be <float> or <string>, got <{other}>"
            ))),
        }
    }

    /// The roughness parameters of a rough BSDF (`distribution`, `alpha` or
    /// `alpha_u`/`alpha_v`); `anisotropic` says whether `alpha_u`/`alpha_v`
    /// are accepted.
    fn roughness(
        &mut self,
        properties: &Properties,
        anisotropic: bool,
    ) -> Result<RoughnessDescription, SceneFileError> {
        let distribution = match properties.optional_string("distribution")? {
            None | Some("beckmann") => MicrofacetDistribution::Beckmann,
            Some("ggx") => MicrofacetDistribution::Ggx,
            Some(other) => {
                return Err(properties
                    .element
                    .location
                    .error(format!("distribution '{other}': expected beckmann or ggx")));
            }
        };
        properties.ignore(&["sample_visible"]);
        let (alpha_u, alpha_v) = if anisotropic && properties.has("alpha_u") {
            let u = self.float_texture_or(properties, "alpha_u", 0.1)?;
            let v = if properties.has("alpha_v") {
                self.float_texture_or(properties, "alpha_v", 0.1)?
            } else {
                u.clone()
            };
            (u, v)
        } else {
            let alpha = self.float_texture_or(properties, "alpha", 0.1)?;
            (alpha.clone(), alpha)
        };
        Ok(RoughnessDescription {
            distribution,
            alpha_u,
            alpha_v,
            remap: false,
        })
    }

    /// The one nested BSDF of an adapter (`twosided`, `bumpmap`, ...).
    fn nested_bsdfs(
        &mut self,
        properties: &Properties,
    ) -> Result<Vec<MaterialDescription>, SceneFileError> {
        let mut nested = Vec::new();
        for object in &properties.objects {
            match object.tag.as_str() {
                "bsdf" => nested.push(self.bsdf(object)?),
                "ref" => match self.referenced(object)? {
                    NamedObject::Bsdf(material) => nested.push(material),
                    other => {
                        return Err(object.location.error(format!(
                            "a {} '{}' can only refer to BSDFs here, not to a {}",
                            properties.element.tag,
                            properties.plugin_type(),
                            other.kind()
                        )));
                    }
                },
                other => self.warn(
                    object,
                    format!(
                        "<{other}> inside bsdf '{}' is ignored",
                        properties.plugin_type()
                    ),
                ),
            }
        }
        Ok(nested)
    }

    fn one_nested(
        &mut self,
        properties: &Properties,
    ) -> Result<MaterialDescription, SceneFileError> {
        let mut nested = self.nested_bsdfs(properties)?;
        match nested.len() {
            1 => Ok(nested.remove(0)),
            count => Err(properties.element.location.error(format!(
                "bsdf '{}' needs exactly one nested bsdf, has {count}",
                properties.plugin_type()
            ))),
        }
    }

    /// Reads a `<bsdf>` plugin (or the `<ref>` of one) and registers its id.
    pub(super) fn bsdf(
        &mut self,
        element: &Element,
    ) -> Result<MaterialDescription, SceneFileError> {
        if element.tag == "ref" {
            return match self.referenced(element)? {
                NamedObject::Bsdf(material) => Ok(material),
                other => Err(element.location.error(format!(
                    "expected a reference to a bsdf, '{}' is a {}",
                    element.attribute("id").unwrap_or(""),
                    other.kind()
                ))),
            };
        }
        let properties = Properties::new(element);
        let kind = properties.plugin_type();
        let material = match kind {
            "diffuse" => MaterialDescription::Diffuse {
                reflectance: self.texture_or(&properties, "reflectance", 0.5)?,
                two_sided: false,
            },
            "conductor" | "roughconductor" => {
                let roughness = if kind == "roughconductor" {
                    Some(self.roughness(&properties, true)?)
                } else {
                    None
                };
                let specular_reflectance =
                    self.texture_parameter(&properties, "specular_reflectance")?;
                let eta = self.spectrum_parameter(&properties, "eta")?;
                let k = self.spectrum_parameter(&properties, "k")?;
                let material_name = properties.optional_string("material")?;
                let (eta, k) = match (eta, k, material_name) {
                    (Some(eta), Some(k), _) => (eta, k),
                    (None, None, None | Some("none")) => {
                        if roughness.is_none() && specular_reflectance.is_none() {
                            return self.finish_bsdf(element, &properties, MaterialDescription::Mirror);
                        }
                        // η = 0, k = 1 reflects everything (Mitsuba's "none").
                        (SpectrumDescription::Constant(0.0), SpectrumDescription::Constant(1.0))
                    }
                    (None, None, Some(name)) => conductor_spectra(name).ok_or_else(|| {
                        element.location.error(format!(
                            "unknown conductor material '{name}' (expected one of Mitsuba's names, e.g. Au, Ag, Al, Cu, Cr, a-C, or none)"
                        ))
                    })?,
                    _ => {
                        return Err(element.location.error(
                            "a conductor needs both 'eta' and 'k', or a 'material' name",
                        ));
                    }
                };
                MaterialDescription::Conductor {
                    eta,
                    k,
                    specular_reflectance,
                    roughness,
                    two_sided: false,
                }
            }
            "dielectric" | "roughdielectric" => {
                let interior = self.ior(&properties, "int_ior", "bk7")?;
                let exterior = self.ior(&properties, "ext_ior", "air")?;
                let roughness = if kind == "roughdielectric" {
                    Some(self.roughness(&properties, true)?)
                } else {
                    None
                };
                self.unsupported_factor(&properties, "specular_reflectance");
                self.unsupported_factor(&properties, "specular_transmittance");
                MaterialDescription::Dielectric {
                    interior_ior: SpectrumDescription::Constant(interior / exterior),
                    exterior_ior: 1.0,
                    roughness,
                }
            }
            "thindielectric" => {
                let interior = self.ior(&properties, "int_ior", "bk7")?;
                let exterior = self.ior(&properties, "ext_ior", "air")?;
                self.unsupported_factor(&properties, "specular_reflectance");
                self.unsupported_factor(&properties, "specular_transmittance");
                MaterialDescription::ThinDielectric {
                    interior_ior: interior / exterior,
                    exterior_ior: 1.0,
                }
            }
            "plastic" | "roughplastic" => {
                let interior = self.ior(&properties, "int_ior", "polypropylene")?;
                let exterior = self.ior(&properties, "ext_ior", "air")?;
                let roughness = if kind == "roughplastic" {
                    Some(self.roughness(&properties, false)?)
                } else {
                    None
                };
                self.unsupported_factor(&properties, "specular_reflectance");
                MaterialDescription::Plastic {
                    diffuse_reflectance: self.texture_or(
                        &properties,
                        "diffuse_reflectance",
                        0.5,
                    )?,
                    interior_ior: interior / exterior,
                    exterior_ior: 1.0,
                    roughness,
                    nonlinear: properties.boolean("nonlinear", false)?,
                    two_sided: false,
                }
            }
            "twosided" => {
                let mut nested = self.nested_bsdfs(&properties)?;
                match nested.len() {
                    1 => two_sided(nested.remove(0)),
                    2 => {
                        let back = nested.remove(1);
                        let front = nested.remove(0);
                        MaterialDescription::TwoSided {
                            front: Box::new(front),
                            back: Box::new(back),
                        }
                    }
                    count => {
                        return Err(element.location.error(format!(
                            "bsdf 'twosided' needs one or two nested bsdfs, has {count}"
                        )));
                    }
                }
            }
            "bumpmap" => {
                let scale = properties.float("scale", 1.0)?;
                // The height texture is the one nested texture, whatever its name.
                let mut height = None;
                for child in &element.children {
                    let texture = match child.tag.as_str() {
                        "texture" => Some(self.texture(child)?),
                        "ref" => match self.referenced(child)? {
                            NamedObject::Texture(texture) => Some(texture),
                            _ => None,
                        },
                        _ => None,
                    };
                    if let Some(texture) = texture {
                        if let Some(name) = child.attribute("name") {
                            let _ = properties.get(name);
                        }
                        height = Some(texture);
                        break;
                    }
                }
                let height = height.ok_or_else(|| {
                    element
                        .location
                        .error("bsdf 'bumpmap' needs a nested height <texture>")
                })?;
                let nested = self.one_nested_ignoring_textures(&properties)?;
                let options = perturbation_options(&properties)?;
                MaterialDescription::BumpMap {
                    height,
                    scale,
                    nested: Box::new(nested),
                    options,
                }
            }
            "normalmap" => {
                let normals = self
                    .texture_parameter(&properties, "normalmap")?
                    .ok_or_else(|| {
                        element
                            .location
                            .error("bsdf 'normalmap' needs a <texture name=\"normalmap\">")
                    })?;
                let nested = self.one_nested(&properties)?;
                let options = perturbation_options(&properties)?;
                MaterialDescription::NormalMap {
                    normals,
                    nested: Box::new(nested),
                    options,
                }
            }
            "mask" => {
                let opacity = self.texture_or(&properties, "opacity", 0.5)?;
                let nested = self.one_nested(&properties)?;
                MaterialDescription::Mask {
                    opacity,
                    nested: Box::new(nested),
                }
            }
            "null" => MaterialDescription::Interface,
            "principled" | "principledthin" => {
                self.principled(&properties, kind == "principledthin")?
            }
            other => {
                self.warn(
                    element,
                    format!(
                        "unknown bsdf type '{other}': replaced by a diffuse bsdf of reflectance 0.5"
                    ),
                );
                return self.finish_bsdf_silently(
                    element,
                    MaterialDescription::Diffuse {
                        reflectance: TextureDescription::Constant(SpectrumDescription::Constant(
                            0.5,
                        )),
                        two_sided: false,
                    },
                );
            }
        };
        self.finish_bsdf(element, &properties, material)
    }

    /// The nested BSDF of a bump map (whose texture child is not a BSDF).
    fn one_nested_ignoring_textures(
        &mut self,
        properties: &Properties,
    ) -> Result<MaterialDescription, SceneFileError> {
        let mut nested = Vec::new();
        for object in &properties.objects {
            match object.tag.as_str() {
                "bsdf" => nested.push(self.bsdf(object)?),
                "ref" => {
                    if let NamedObject::Bsdf(material) = self.referenced(object)? {
                        nested.push(material);
                    }
                }
                _ => {}
            }
        }
        match nested.len() {
            1 => Ok(nested.remove(0)),
            count => Err(properties.element.location.error(format!(
                "bsdf 'bumpmap' needs exactly one nested bsdf, has {count}"
            ))),
        }
    }

    /// Mitsuba's `principled` / `principledthin`: every weight a float or
    /// texture with Mitsuba's defaults; `principled` takes `eta` or
    /// `specular` (η = 2/(1 − √(0.08 specular)) − 1), not both.
    fn principled(
        &mut self,
        properties: &Properties,
        thin: bool,
    ) -> Result<MaterialDescription, SceneFileError> {
        use crate::material::{PrincipledSamplingRates, principled_eta_from_specular};
        let constant =
            |value: f32| TextureDescription::Constant(SpectrumDescription::Constant(value));
        // Mitsuba's `get_flag`: a lobe is on when its parameter is given and
        // is not the number 0.
        let given = |name: &str| {
            properties.get(name).is_some_and(|element| {
                element.tag != "float" || element.attribute("value").map(str::trim) != Some("0")
            })
        };
        let has_spec_trans = given("spec_trans");
        let eta = if thin {
            self.float_texture_or(properties, "eta", 1.5)?
        } else {
            if properties.has("eta") && properties.has("specular") {
                return Err(properties
                    .element
                    .location
                    .error("bsdf 'principled' takes either 'eta' or 'specular', not both"));
            }
            let eta = match properties.optional_float("eta")? {
                Some(eta) if has_spec_trans && eta == 1.0 => 1.001,
                Some(eta) => eta,
                None => {
                    let specular = properties.float("specular", 0.5)?;
                    let specular = if has_spec_trans && specular == 0.0 {
                        1e-3
                    } else {
                        specular
                    };
                    principled_eta_from_specular(specular)
                }
            };
            constant(eta)
        };
        let defaults = PrincipledSamplingRates::default();
        let sampling_rates = if thin {
            PrincipledSamplingRates {
                specular_reflection: properties.float(
                    "specular_reflectance_sampling_rate",
                    defaults.specular_reflection,
                )?,
                specular_transmission: properties.float(
                    "specular_transmittance_sampling_rate",
                    defaults.specular_transmission,
                )?,
                diffuse_reflection: properties.float(
                    "diffuse_reflectance_sampling_rate",
                    defaults.diffuse_reflection,
                )?,
                diffuse_transmission: properties.float(
                    "diffuse_transmittance_sampling_rate",
                    defaults.diffuse_transmission,
                )?,
                ..defaults
            }
        } else {
            PrincipledSamplingRates {
                specular_reflection: properties
                    .float("main_specular_sampling_rate", defaults.specular_reflection)?,
                clearcoat: properties.float("clearcoat_sampling_rate", defaults.clearcoat)?,
                diffuse_reflection: properties.float(
                    "diffuse_reflectance_sampling_rate",
                    defaults.diffuse_reflection,
                )?,
                ..defaults
            }
        };
        // metallic and the clearcoat belong to `principled` only, diff_trans to
        // the thin variant; the other variant takes 0.
        let parameter_if = |loader: &mut Self, name: &str, applies: bool| {
            if applies {
                loader.float_texture_or(properties, name, 0.0)
            } else {
                Ok(constant(0.0))
            }
        };
        Ok(MaterialDescription::Principled(Box::new(
            PrincipledDescription {
                thin,
                base_color: self.texture_or(properties, "base_color", 0.5)?,
                roughness: self.float_texture_or(properties, "roughness", 0.5)?,
                anisotropic: self.float_texture_or(properties, "anisotropic", 0.0)?,
                metallic: parameter_if(self, "metallic", !thin)?,
                spec_trans: self.float_texture_or(properties, "spec_trans", 0.0)?,
                eta,
                spec_tint: self.float_texture_or(properties, "spec_tint", 0.0)?,
                sheen: self.float_texture_or(properties, "sheen", 0.0)?,
                sheen_tint: self.float_texture_or(properties, "sheen_tint", 0.0)?,
                clearcoat: parameter_if(self, "clearcoat", !thin)?,
                clearcoat_gloss: parameter_if(self, "clearcoat_gloss", !thin)?,
                flatness: self.float_texture_or(properties, "flatness", 0.0)?,
                diff_trans: parameter_if(self, "diff_trans", thin)?,
                sampling_rates,
            },
        )))
    }

    /// Warns when a factor the description cannot hold is not 1.
    fn unsupported_factor(&mut self, properties: &Properties, name: &str) {
        if let Some(element) = properties.get(name) {
            let is_one = matches!(
                element.attribute("value").map(super::values::parse_numbers),
                Some(Ok(ref values)) if values.iter().all(|&v| v == 1.0)
            );
            if !is_one {
                self.warn(
                    element,
                    format!(
                        "'{name}' of bsdf '{}' is not supported and is taken as 1",
                        properties.plugin_type()
                    ),
                );
            }
        }
    }

    fn finish_bsdf(
        &mut self,
        element: &Element,
        properties: &Properties,
        material: MaterialDescription,
    ) -> Result<MaterialDescription, SceneFileError> {
        self.finish(properties);
        self.finish_bsdf_silently(element, material)
    }

    fn finish_bsdf_silently(
        &mut self,
        element: &Element,
        material: MaterialDescription,
    ) -> Result<MaterialDescription, SceneFileError> {
        self.register(element, NamedObject::Bsdf(material.clone()))?;
        Ok(material)
    }
}
