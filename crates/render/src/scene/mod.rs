//! Scenes: the renderer-independent [`description`] that built-in scenes and
//! loaders produce, the [`builtin`] scenes, and [`Scene`], what integrators
//! trace: geometry with its acceleration structure, a material and an
//! optional light per shape, the lights and the camera.

pub mod builtin;
pub mod description;
pub mod loader;
pub mod mesh_files;
pub mod mitsuba;
pub mod pbrt;
pub mod spectra;

use crate::camera::{CameraError, PerspectiveCamera};
use crate::film::{BoxFilter, Filter, GaussianFilter, TriangleFilter};
use crate::geometry::{Disk, Geometry, GeometryError, Shape, Sphere, Transform, TriangleMesh};
use crate::light::{
    EnvironmentMap, Light, LightSampler, ProjectorLight, SpotLight, TexturedAreaLight,
};
use crate::material::{Material, MicrofacetKind, Roughness};
use crate::medium::{HomogeneousMedium, MediumInterface, MediumSpectra, PhaseFunction};
use crate::texture::SpectrumTexture;
use description::{
    FilterDescription, LightDescription, MaterialDescription, MediumCoefficients,
    MediumDescription, MicrofacetDistribution, PhaseDescription, RoughnessDescription,
    SceneDescription, ShapeGeometry, SpectrumDescription, SpotFalloff, TextureDescription,
};
use glam::{Affine3A, Mat4};
use spectra::{SpectrumUsage, build_spectrum};

/// Why a scene cannot be built from its description.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A shape's geometry is invalid.
    #[error("shape {index}: {source}")]
    Geometry {
        index: usize,
        #[source]
        source: GeometryError,
    },
    /// The acceleration structure could not be built.
    #[error("{0}")]
    Accelerator(GeometryError),
    /// A colour or material parameter is invalid.
    #[error("{what}: {message}")]
    Parameter { what: String, message: String },
    /// The camera is invalid.
    #[error(transparent)]
    Camera(#[from] CameraError),
    /// The description uses a feature the renderer does not have (yet).
    #[error("not supported: {what}")]
    Unsupported { what: String },
    /// The scene emits no light.
    #[error("the scene has no light sources")]
    NoLights,
}

/// What a shape is made of.
#[derive(Debug, Clone)]
pub struct ShapeInfo {
    /// The material (`None` for a black surface that absorbs everything).
    pub material: Option<Material>,
    /// The index of the shape's area light in [`Scene::lights`].
    pub light: Option<u32>,
    /// The shape's front is the side opposite its stored normals.
    pub flip_normals: bool,
    /// The media on its two sides if the shape is a medium transition (see
    /// [`crate::medium`]); `None` keeps the ray's medium when crossing it.
    pub medium_interface: Option<MediumInterface>,
    /// An index-matched boundary (`MaterialDescription::Interface`): rays
    /// pass straight through; it only changes the medium.
    pub is_interface: bool,
}

/// A scene ready for rendering.
#[derive(Debug)]
pub struct Scene {
    /// The scene's name.
    pub name: String,
    /// Surfaces and their acceleration structure.
    pub geometry: Geometry,
    /// Per shape (same order as the geometry's shapes).
    pub shapes: Vec<ShapeInfo>,
    /// All lights: area lights first, in shape order, then the others.
    pub lights: Vec<Light>,
    /// Chooses lights for next-event estimation.
    pub light_sampler: LightSampler,
    /// Indices of the lights at infinity (seen by rays that escape).
    pub environment_lights: Vec<u32>,
    /// Participating media, referred to by [`ShapeInfo::medium_interface`]
    /// and [`Scene::camera_medium`].
    pub media: Vec<HomogeneousMedium>,
    /// The medium the camera sits in (`None`: vacuum).
    pub camera_medium: Option<u32>,
    /// The camera.
    pub camera: PerspectiveCamera,
    /// The pixel reconstruction filter.
    pub filter: Filter,
    /// The scene's suggested maximum depth (Mitsuba's convention).
    pub max_depth: Option<u32>,
    /// The scene's suggested samples per pixel.
    pub samples_per_pixel: Option<u64>,
    /// The scene's suggested Russian-roulette depth (Mitsuba's `rr_depth`).
    pub russian_roulette_depth: Option<u32>,
}

fn parameter_error(what: &str, error: impl std::fmt::Display) -> SceneError {
    SceneError::Parameter {
        what: what.to_string(),
        message: error.to_string(),
    }
}

fn transform(matrix: Affine3A, index: usize) -> Result<Transform, SceneError> {
    Transform::from_matrix(Mat4::from(matrix))
        .map_err(|source| SceneError::Geometry { index, source })
}

/// The render-time texture a spectrum-valued texture description stands for.
fn spectrum_texture(
    description: &TextureDescription,
    usage: SpectrumUsage,
    what: &str,
) -> Result<SpectrumTexture, SceneError> {
    crate::texture::build_spectrum_texture(description, usage, what)
}

/// The render-time roughness of a roughness description.
fn roughness(description: &RoughnessDescription) -> Result<Roughness, SceneError> {
    Ok(Roughness {
        kind: match description.distribution {
            MicrofacetDistribution::Ggx => MicrofacetKind::Ggx,
            MicrofacetDistribution::Beckmann => MicrofacetKind::Beckmann,
        },
        alpha_u: crate::texture::build_float_texture(&description.alpha_u, "roughness alpha_u")?,
        alpha_v: crate::texture::build_float_texture(&description.alpha_v, "roughness alpha_v")?,
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

fn material(description: &MaterialDescription) -> Result<Option<Material>, SceneError> {
    let material = match description {
        MaterialDescription::Diffuse {
            reflectance,
            two_sided,
        } => Ok(Material::Diffuse {
            reflectance: spectrum_texture(
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
                        spectrum_texture(
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
                diffuse_reflectance: spectrum_texture(
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
                reflectance: spectrum_texture(
                    reflectance,
                    SpectrumUsage::Albedo,
                    "coated diffuse reflectance",
                )?,
                eta: relative_index(*interior_ior, 1.0, "coated diffuse")?,
                roughness: coating_roughness.as_ref().map(roughness).transpose()?,
                thickness: *thickness,
                albedo: spectrum_texture(albedo, SpectrumUsage::Albedo, "coated diffuse albedo")?,
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
                albedo: spectrum_texture(albedo, SpectrumUsage::Albedo, "coated conductor albedo")?,
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
            height: crate::texture::build_float_texture(height, "bump map height")?,
            scale: *scale,
            nested: Box::new(nested_material(nested)?),
            options: *options,
        }),
        MaterialDescription::NormalMap {
            normals,
            nested,
            options,
        } => Ok(Material::NormalMap {
            normals: crate::texture::build_rgb_texture(normals, "normal map")?,
            nested: Box::new(nested_material(nested)?),
            options: *options,
        }),
        MaterialDescription::Mask { opacity, nested } => Ok(Material::Mask {
            opacity: crate::texture::build_float_texture(opacity, "mask opacity")?,
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
fn principled_material(
    description: &description::PrincipledDescription,
) -> Result<Material, SceneError> {
    let float = |texture: &TextureDescription, what: &str| {
        crate::texture::build_float_texture(texture, &format!("principled {what}"))
    };
    let d = description;
    Ok(Material::Principled(Box::new(
        crate::material::PrincipledMaterial {
            thin: d.thin,
            base_color: spectrum_texture(
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
        },
    )))
}

/// The material inside a bump map, normal map or mask; black (`None`)
/// becomes a black diffuse surface so that the adapter still applies.
fn nested_material(description: &MaterialDescription) -> Result<Material, SceneError> {
    Ok(material(description)?.unwrap_or(Material::Diffuse {
        reflectance: SpectrumTexture::Constant(crate::spectrum::Spectrum::Constant(
            crate::spectrum::ConstantSpectrum::new(0.0).map_err(|e| parameter_error("black", e))?,
        )),
        two_sided: true,
    }))
}

/// A projector from its description: the image's aspect ratio turns the
/// field of view along `fov_axis` into the horizontal one.
fn projector_light(
    to_world: Affine3A,
    irradiance: &TextureDescription,
    scale: f32,
    fov_degrees: f32,
    fov_axis: crate::scene::description::ProjectorFovAxis,
) -> Result<Light, SceneError> {
    if to_world.matrix3.determinant().abs() <= f32::MIN_POSITIVE || !to_world.is_finite() {
        return Err(parameter_error(
            "projector",
            "to_world must be an invertible transform",
        ));
    }
    if !(scale >= 0.0 && scale.is_finite() && fov_degrees > 0.0 && fov_degrees < 180.0) {
        return Err(parameter_error(
            "projector",
            format!("need scale ≥ 0 ({scale}) and 0 < fov < 180° ({fov_degrees}°)"),
        ));
    }
    let texture = spectrum_texture(irradiance, SpectrumUsage::Albedo, "projector irradiance")?;
    let (width, height) = match &texture {
        SpectrumTexture::Bitmap(bitmap) => {
            let lookup = bitmap.lookup();
            (lookup.width as f32, lookup.height as f32)
        }
        _ => (1.0, 1.0),
    };
    let tan_half_x = fov_axis.tan_half_horizontal(fov_degrees, width, height);
    Ok(Light::Projector(Box::new(ProjectorLight::new(
        to_world,
        texture,
        scale,
        2.0 * tan_half_x.atan().to_degrees(),
        width / height,
    ))))
}

/// A spot light from its description; angles must satisfy
/// 0 ≤ start ≤ cutoff ≤ 180°, and cutoff < 90° with a texture (its
/// projection divides by tan cutoff).
fn spot_light(
    to_world: Affine3A,
    intensity: &SpectrumDescription,
    cutoff_degrees: f32,
    falloff_start_degrees: f32,
    falloff: SpotFalloff,
    texture: Option<&TextureDescription>,
) -> Result<Light, SceneError> {
    let cutoff_bound = if texture.is_some() {
        "below 90° with a texture"
    } else {
        "at most 180°"
    };
    let valid_angles = cutoff_degrees > 0.0
        && cutoff_degrees <= 180.0
        && (texture.is_none() || cutoff_degrees < 90.0)
        && (0.0..=cutoff_degrees).contains(&falloff_start_degrees);
    if !valid_angles {
        return Err(parameter_error(
            "spot light",
            format!(
                "need 0 ≤ falloff start ({falloff_start_degrees}°) ≤ cutoff \
                 ({cutoff_degrees}°), the cutoff {cutoff_bound}"
            ),
        ));
    }
    if to_world.matrix3.determinant().abs() <= f32::MIN_POSITIVE || !to_world.is_finite() {
        return Err(parameter_error(
            "spot light",
            "to_world must be an invertible transform",
        ));
    }
    let texture = texture
        .map(|texture| spectrum_texture(texture, SpectrumUsage::Albedo, "spot light texture"))
        .transpose()?;
    Ok(Light::Spot(Box::new(SpotLight::new(
        to_world,
        build_spectrum(intensity, SpectrumUsage::Illuminant, "spot light intensity")?,
        texture,
        falloff,
        cutoff_degrees,
        falloff_start_degrees,
    ))))
}

/// A shape's medium reference checked against the scene's media.
fn medium_index(
    medium: Option<usize>,
    description: &SceneDescription,
    shape: usize,
) -> Result<Option<u32>, SceneError> {
    match medium {
        Some(index) if index >= description.media.len() => Err(SceneError::Parameter {
            what: format!("shape {shape}"),
            message: format!(
                "medium {index} does not exist (the scene has {})",
                description.media.len()
            ),
        }),
        other => Ok(other.map(|index| index as u32)),
    }
}

/// The render-time medium of a description: spectra from colours (albedos
/// as reflectances, coefficients as unbounded quantities), checked scale
/// and phase parameter.
fn build_medium(
    description: &MediumDescription,
    index: usize,
) -> Result<HomogeneousMedium, SceneError> {
    let what = |name: &str| format!("medium {index} {name}");
    if !(description.scale.is_finite() && description.scale >= 0.0) {
        return Err(SceneError::Parameter {
            what: what("scale"),
            message: format!("must be finite and non-negative, not {}", description.scale),
        });
    }
    let spectra = match &description.coefficients {
        MediumCoefficients::AlbedoExtinction { albedo, sigma_t } => {
            MediumSpectra::AlbedoExtinction {
                albedo: build_spectrum(albedo, SpectrumUsage::Albedo, &what("albedo"))?,
                sigma_t: build_spectrum(sigma_t, SpectrumUsage::Unbounded, &what("sigma_t"))?,
            }
        }
        MediumCoefficients::AbsorptionScattering { sigma_a, sigma_s } => {
            MediumSpectra::AbsorptionScattering {
                sigma_a: build_spectrum(sigma_a, SpectrumUsage::Unbounded, &what("sigma_a"))?,
                sigma_s: build_spectrum(sigma_s, SpectrumUsage::Unbounded, &what("sigma_s"))?,
            }
        }
    };
    let phase = match description.phase {
        PhaseDescription::Isotropic => PhaseFunction::Isotropic,
        PhaseDescription::HenyeyGreenstein { g } => {
            if !(g.is_finite() && g > -1.0 && g < 1.0) {
                return Err(SceneError::Parameter {
                    what: what("phase function"),
                    message: format!("Henyey-Greenstein g must lie in (-1, 1), not {g}"),
                });
            }
            PhaseFunction::henyey_greenstein(g)
        }
    };
    Ok(HomogeneousMedium::new(spectra, description.scale, phase))
}

impl Scene {
    /// Whether the scene has participating media (the `path` integrator
    /// ignores them; `volpath` renders them).
    pub fn has_media(&self) -> bool {
        !self.media.is_empty()
    }

    /// Builds the scene: geometry and BVH, spectra from colours, lights.
    pub fn build(description: &SceneDescription) -> Result<Self, SceneError> {
        let mut shapes = Vec::with_capacity(description.shapes.len());
        let mut infos = Vec::with_capacity(description.shapes.len());
        let mut lights = Vec::new();
        for (index, shape) in description.shapes.iter().enumerate() {
            let geometry_error = |source| SceneError::Geometry { index, source };
            let built = match &shape.geometry {
                ShapeGeometry::Mesh {
                    positions,
                    normals,
                    uvs,
                    triangles,
                } => Shape::Mesh(
                    TriangleMesh::new(
                        positions.clone(),
                        normals.clone(),
                        uvs.clone(),
                        triangles.clone(),
                        &transform(Affine3A::IDENTITY, index)?,
                    )
                    .map_err(geometry_error)?,
                ),
                ShapeGeometry::Sphere { center, radius } => {
                    Shape::Sphere(Sphere::new(*center, *radius).map_err(geometry_error)?)
                }
                ShapeGeometry::Rectangle { to_world } => Shape::Mesh(
                    TriangleMesh::rectangle(&transform(*to_world, index)?)
                        .map_err(geometry_error)?,
                ),
                ShapeGeometry::Cube { to_world } => Shape::Mesh(
                    TriangleMesh::cube(&transform(*to_world, index)?).map_err(geometry_error)?,
                ),
                ShapeGeometry::Disk { to_world } => {
                    Shape::Disk(Disk::new(transform(*to_world, index)?).map_err(geometry_error)?)
                }
            };
            shapes.push(built);
            let light = match (&shape.emission_texture, &shape.emission) {
                (Some(texture), _) => {
                    let radiance =
                        spectrum_texture(texture, SpectrumUsage::Albedo, "emitted radiance")?;
                    let light = TexturedAreaLight::new(index as u32, radiance, shape.flip_normals);
                    if light.mean_scale > 0.0 {
                        lights.push(Light::TexturedArea(Box::new(light)));
                        Some(lights.len() as u32 - 1)
                    } else {
                        None
                    }
                }
                (None, Some(emission)) => {
                    let radiance =
                        build_spectrum(emission, SpectrumUsage::Illuminant, "emitted radiance")?;
                    let scale = radiance.max_value();
                    if scale > 0.0 {
                        lights.push(Light::Area {
                            shape_index: index as u32,
                            radiance,
                            flip_normals: shape.flip_normals,
                            scale,
                        });
                        Some(lights.len() as u32 - 1)
                    } else {
                        None
                    }
                }
                (None, None) => None,
            };
            let medium_interface =
                if shape.interior_medium.is_some() || shape.exterior_medium.is_some() {
                    Some(MediumInterface {
                        interior: medium_index(shape.interior_medium, description, index)?,
                        exterior: medium_index(shape.exterior_medium, description, index)?,
                    })
                } else {
                    None
                };
            let is_interface = matches!(shape.material, MaterialDescription::Interface);
            infos.push(ShapeInfo {
                material: if is_interface {
                    None
                } else {
                    material(&shape.material)?
                },
                light,
                flip_normals: shape.flip_normals,
                medium_interface,
                is_interface,
            });
        }
        let geometry = Geometry::new(shapes).map_err(SceneError::Accelerator)?;
        let (scene_center, scene_radius) = geometry.bounds().bounding_sphere();
        let mut environment_lights = Vec::new();
        for light in &description.lights {
            lights.push(match light {
                LightDescription::Point {
                    position,
                    intensity,
                } => Light::Point {
                    position: *position,
                    intensity: build_spectrum(
                        intensity,
                        SpectrumUsage::Illuminant,
                        "point light intensity",
                    )?,
                },
                LightDescription::ConstantEnvironment { radiance } => {
                    environment_lights.push(lights.len() as u32);
                    Light::ConstantEnvironment {
                        radiance: build_spectrum(
                            radiance,
                            SpectrumUsage::Illuminant,
                            "environment radiance",
                        )?,
                        scene_center,
                        scene_radius,
                    }
                }
                LightDescription::Spot {
                    to_world,
                    intensity,
                    cutoff_degrees,
                    falloff_start_degrees,
                    falloff,
                    texture,
                } => spot_light(
                    *to_world,
                    intensity,
                    *cutoff_degrees,
                    *falloff_start_degrees,
                    *falloff,
                    texture.as_ref(),
                )?,
                LightDescription::Directional {
                    direction,
                    irradiance,
                } => {
                    let direction = direction.normalize_or_zero();
                    if !direction.is_finite() || direction == glam::Vec3::ZERO {
                        return Err(parameter_error(
                            "directional light",
                            "the direction must be a non-zero vector",
                        ));
                    }
                    Light::Directional {
                        direction,
                        irradiance: build_spectrum(
                            irradiance,
                            SpectrumUsage::Illuminant,
                            "directional light irradiance",
                        )?,
                        scene_center,
                        scene_radius,
                    }
                }
                LightDescription::EnvironmentMap {
                    filename,
                    projection,
                    to_world,
                    scale,
                } => {
                    environment_lights.push(lights.len() as u32);
                    Light::EnvironmentMap {
                        map: std::sync::Arc::new(EnvironmentMap::load(
                            filename,
                            *projection,
                            *to_world,
                            *scale,
                            "environment map",
                        )?),
                        scene_center,
                        scene_radius,
                    }
                }
                LightDescription::Projector {
                    to_world,
                    irradiance,
                    scale,
                    fov_degrees,
                    fov_axis,
                } => projector_light(*to_world, irradiance, *scale, *fov_degrees, *fov_axis)?,
            });
        }
        let media = description
            .media
            .iter()
            .enumerate()
            .map(|(index, medium)| build_medium(medium, index))
            .collect::<Result<Vec<_>, _>>()?;
        let camera_medium = match description.camera_medium {
            Some(index) if index >= media.len() => {
                return Err(SceneError::Parameter {
                    what: "camera medium".into(),
                    message: format!(
                        "medium {index} does not exist (the scene has {})",
                        media.len()
                    ),
                });
            }
            other => other.map(|index| index as u32),
        };
        if lights.is_empty() {
            return Err(SceneError::NoLights);
        }
        let powers: Vec<f32> = lights.iter().map(|light| light.power(&geometry)).collect();
        let filter = match description.filter {
            FilterDescription::Box { radius } => BoxFilter::new([radius; 2]).map(Filter::Box),
            FilterDescription::Tent { radius } => {
                TriangleFilter::new([radius; 2]).map(Filter::Triangle)
            }
            FilterDescription::Gaussian { radius, sigma } => {
                GaussianFilter::new([radius; 2], sigma).map(Filter::Gaussian)
            }
        }
        .map_err(|e| parameter_error("filter", e))?;
        Ok(Self {
            name: description.name.clone(),
            geometry,
            shapes: infos,
            light_sampler: LightSampler::with_infinite_share(
                &powers,
                &lights.iter().map(Light::is_infinite).collect::<Vec<_>>(),
            ),
            lights,
            environment_lights,
            media,
            camera_medium,
            camera: PerspectiveCamera::new(&description.camera)?,
            filter,
            max_depth: description.max_depth,
            samples_per_pixel: description.samples_per_pixel,
            russian_roulette_depth: description.russian_roulette_depth,
        })
    }
}
