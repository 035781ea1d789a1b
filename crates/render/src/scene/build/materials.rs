//! Render-time materials from the scene description's
//! [`MaterialDescription`]s: spectra and textures built for their use,
//! indices of refraction checked, the material validated.

use super::parameter_error;
use super::textures::{build_float_texture, build_rgb_texture, build_spectrum_texture};
use crate::material::{Material, MicrofacetKind, PrincipledMaterial, Roughness};
use crate::scene::SceneError;
use crate::scene::description::{
    MaterialDescription, MicrofacetDistribution, PrincipledDescription, RoughnessDescription,
    SpectrumDescription, TextureDescription,
};
use crate::scene::spectra::{SpectrumUsage, build_spectrum};
use crate::spectrum::{ConstantSpectrum, Spectrum};
use crate::texture::SpectrumTexture;

/// The render-time roughness of a roughness description.
fn roughness(description: &RoughnessDescription) -> Result<Roughness, SceneError> {
    Ok(Roughness {
        kind: match description.distribution {
            MicrofacetDistribution::Ggx => MicrofacetKind::Ggx,
            MicrofacetDistribution::Beckmann => MicrofacetKind::Beckmann,
        },
        alpha_u: build_float_texture(&description.alpha_u, "roughness alpha_u")?,
        alpha_v: build_float_texture(&description.alpha_v, "roughness alpha_v")?,
        remap: description.remap,
    })
}

/// `interior / exterior`, the relative index of an interface, or a parameter
/// error naming `what` if either index is not a positive finite number.
fn relative_index(interior: f32, exterior: f32, what: &str) -> Result<f32, SceneError> {
    if !(interior.is_finite() && interior > 0.0 && exterior.is_finite() && exterior > 0.0) {
        return Err(parameter_error(
            what,
            format!(
                "indices of refraction must be positive and finite, got interior {interior}, \
                 exterior {exterior}"
            ),
        ));
    }
    Ok(interior / exterior)
}

pub(in crate::scene) fn material(
    description: &MaterialDescription,
) -> Result<Option<Material>, SceneError> {
    let material = match description {
        MaterialDescription::Diffuse {
            reflectance,
            two_sided,
        } => Ok(Material::Diffuse {
            reflectance: build_spectrum_texture(
                reflectance,
                SpectrumUsage::Albedo,
                "diffuse reflectance",
            )?,
            two_sided: *two_sided,
        }),
        MaterialDescription::Mirror => Ok(Material::Mirror),
        MaterialDescription::Conductor {
            eta,
            k,
            specular_reflectance: None,
            roughness: None,
            two_sided: true,
        } => Material::conductor(
            build_spectrum(eta, SpectrumUsage::Unbounded, "conductor eta")?,
            build_spectrum(k, SpectrumUsage::Unbounded, "conductor k")?,
        ),
        MaterialDescription::Conductor {
            eta,
            k,
            specular_reflectance,
            roughness: conductor_roughness,
            two_sided,
        } => {
            let material = Material::RoughConductor {
                eta: build_spectrum(eta, SpectrumUsage::Unbounded, "conductor eta")?,
                k: build_spectrum(k, SpectrumUsage::Unbounded, "conductor k")?,
                specular_reflectance: specular_reflectance
                    .as_ref()
                    .map(|texture| {
                        build_spectrum_texture(
                            texture,
                            SpectrumUsage::Albedo,
                            "conductor specular_reflectance",
                        )
                    })
                    .transpose()?,
                roughness: conductor_roughness.as_ref().map(roughness).transpose()?,
                two_sided: *two_sided,
            };
            material.validate().map(|()| material)
        }
        MaterialDescription::Dielectric {
            interior_ior,
            exterior_ior,
            roughness: dielectric_roughness,
        } => {
            if !(exterior_ior.is_finite() && *exterior_ior > 0.0) {
                return Err(parameter_error(
                    "dielectric exterior_ior",
                    format!("must be positive and finite, got {exterior_ior}"),
                ));
            }
            let interior = if *exterior_ior == 1.0 {
                interior_ior.clone()
            } else {
                SpectrumDescription::Scaled {
                    scale: 1.0 / exterior_ior,
                    spectrum: Box::new(interior_ior.clone()),
                }
            };
            let eta = build_spectrum(&interior, SpectrumUsage::Unbounded, "dielectric eta")?;
            match dielectric_roughness {
                None => Material::dielectric(eta),
                Some(description) => {
                    let material = Material::RoughDielectric {
                        eta,
                        roughness: roughness(description)?,
                    };
                    material.validate().map(|()| material)
                }
            }
        }
        MaterialDescription::ThinDielectric {
            interior_ior,
            exterior_ior,
        } => Ok(Material::ThinDielectric {
            eta: relative_index(*interior_ior, *exterior_ior, "thin dielectric")?,
        }),
        MaterialDescription::Plastic {
            diffuse_reflectance,
            interior_ior,
            exterior_ior,
            roughness: plastic_roughness,
            nonlinear,
            two_sided,
        } => {
            let coating = match plastic_roughness {
                None => None,
                Some(description) => Some(
                    roughness(description)?
                        .constant_distribution()
                        .ok_or_else(|| SceneError::Unsupported {
                            what: "rough plastic with a textured roughness (Mitsuba's \
                               roughplastic takes a constant alpha)"
                                .into(),
                        })?,
                ),
            };
            Ok(Material::Plastic {
                diffuse_reflectance: build_spectrum_texture(
                    diffuse_reflectance,
                    SpectrumUsage::Albedo,
                    "plastic diffuse_reflectance",
                )?,
                eta: relative_index(*interior_ior, *exterior_ior, "plastic")?,
                coating,
                nonlinear: *nonlinear,
                two_sided: *two_sided,
            })
        }
        MaterialDescription::CoatedDiffuse {
            reflectance,
            interior_ior,
            roughness: coating_roughness,
            thickness,
            albedo,
            g,
            max_depth,
            samples,
        } => {
            let material = Material::CoatedDiffuse {
                reflectance: build_spectrum_texture(
                    reflectance,
                    SpectrumUsage::Albedo,
                    "coated diffuse reflectance",
                )?,
                eta: relative_index(*interior_ior, 1.0, "coated diffuse")?,
                roughness: coating_roughness.as_ref().map(roughness).transpose()?,
                thickness: *thickness,
                albedo: build_spectrum_texture(
                    albedo,
                    SpectrumUsage::Albedo,
                    "coated diffuse albedo",
                )?,
                g: *g,
                max_depth: *max_depth,
                samples: *samples,
            };
            material.validate().map(|()| material)
        }
        MaterialDescription::CoatedConductor {
            interface_ior,
            interface_roughness,
            conductor_eta,
            conductor_k,
            conductor_roughness,
            thickness,
            albedo,
            g,
            max_depth,
            samples,
        } => {
            let material = Material::CoatedConductor {
                interface_eta: relative_index(*interface_ior, 1.0, "coated conductor")?,
                interface_roughness: interface_roughness.as_ref().map(roughness).transpose()?,
                conductor_eta: build_spectrum(
                    conductor_eta,
                    SpectrumUsage::Unbounded,
                    "coated conductor conductor.eta",
                )?,
                conductor_k: build_spectrum(
                    conductor_k,
                    SpectrumUsage::Unbounded,
                    "coated conductor conductor.k",
                )?,
                conductor_roughness: conductor_roughness.as_ref().map(roughness).transpose()?,
                thickness: *thickness,
                albedo: build_spectrum_texture(
                    albedo,
                    SpectrumUsage::Albedo,
                    "coated conductor albedo",
                )?,
                g: *g,
                max_depth: *max_depth,
                samples: *samples,
            };
            material.validate().map(|()| material)
        }
        MaterialDescription::TwoSided { front, back } => Ok(Material::TwoSided {
            front: Box::new(nested_material(front)?),
            back: Box::new(nested_material(back)?),
        }),
        MaterialDescription::BumpMap {
            height,
            scale,
            nested,
            options,
        } => Ok(Material::BumpMap {
            height: build_float_texture(height, "bump map height")?,
            scale: *scale,
            nested: Box::new(nested_material(nested)?),
            options: *options,
        }),
        MaterialDescription::NormalMap {
            normals,
            nested,
            options,
        } => Ok(Material::NormalMap {
            normals: build_rgb_texture(normals, "normal map")?,
            nested: Box::new(nested_material(nested)?),
            options: *options,
        }),
        MaterialDescription::Mask { opacity, nested } => Ok(Material::Mask {
            opacity: build_float_texture(opacity, "mask opacity")?,
            nested: Box::new(nested_material(nested)?),
        }),
        MaterialDescription::Principled(principled) => Ok(principled_material(principled)?),
        MaterialDescription::Black => return Ok(None),
        other => {
            return Err(SceneError::Unsupported {
                what: format!("material {other:?}"),
            });
        }
    };
    material
        .map(Some)
        .map_err(|e| parameter_error("material", e))
}

/// The render-time material of a principled BSDF description.
fn principled_material(description: &PrincipledDescription) -> Result<Material, SceneError> {
    let float = |texture: &TextureDescription, what: &str| {
        build_float_texture(texture, &format!("principled {what}"))
    };
    let d = description;
    Ok(Material::Principled(Box::new(PrincipledMaterial {
        thin: d.thin,
        base_color: build_spectrum_texture(
            &d.base_color,
            SpectrumUsage::Albedo,
            "principled base_color",
        )?,
        roughness: float(&d.roughness, "roughness")?,
        anisotropic: float(&d.anisotropic, "anisotropic")?,
        metallic: float(&d.metallic, "metallic")?,
        spec_trans: float(&d.spec_trans, "spec_trans")?,
        eta: float(&d.eta, "eta")?,
        spec_tint: float(&d.spec_tint, "spec_tint")?,
        sheen: float(&d.sheen, "sheen")?,
        sheen_tint: float(&d.sheen_tint, "sheen_tint")?,
        clearcoat: float(&d.clearcoat, "clearcoat")?,
        clearcoat_gloss: float(&d.clearcoat_gloss, "clearcoat_gloss")?,
        flatness: float(&d.flatness, "flatness")?,
        diff_trans: float(&d.diff_trans, "diff_trans")?,
        sampling_rates: d.sampling_rates,
    })))
}

/// The material inside a bump map, normal map or mask; black (`None`)
/// becomes a black diffuse surface so that the adapter still applies.
fn nested_material(description: &MaterialDescription) -> Result<Material, SceneError> {
    Ok(material(description)?.unwrap_or(Material::Diffuse {
        reflectance: SpectrumTexture::Constant(Spectrum::Constant(
            ConstantSpectrum::new(0.0).map_err(|e| parameter_error("black", e))?,
        )),
        two_sided: true,
    }))
}
