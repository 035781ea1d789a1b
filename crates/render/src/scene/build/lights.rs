//! Render-time lights from the scene description: the area light of an
//! emitting shape, the lights the description lists (points, spots,
//! directional lights, environments, projectors) with their parameters
//! checked, and the sampler that picks among them by power.

use std::sync::Arc;

use glam::{Affine3A, Vec3};

use super::parameter_error;
use super::textures::build_spectrum_texture;
use crate::geometry::Geometry;
use crate::light::{
    EnvironmentMap, Light, LightSampler, ProjectorLight, SpotLight, TexturedAreaLight,
};
use crate::scene::SceneError;
use crate::scene::description::{
    LightDescription, ProjectorFovAxis, ShapeDescription, SpectrumDescription, SpotFalloff,
    TextureDescription,
};
use crate::scene::spectra::{SpectrumUsage, build_spectrum};
use crate::texture::SpectrumTexture;

/// The area light of shape `index`, `None` if it does not emit (no
/// emission, or an emission that is black everywhere).
pub(in crate::scene) fn area_light(
    shape: &ShapeDescription,
    index: usize,
) -> Result<Option<Light>, SceneError> {
    Ok(match (&shape.emission_texture, &shape.emission) {
        (Some(texture), _) => {
            let radiance =
                build_spectrum_texture(texture, SpectrumUsage::Albedo, "emitted radiance")?;
            let light = TexturedAreaLight::new(index as u32, radiance, shape.flip_normals);
            (light.mean_scale > 0.0).then(|| Light::TexturedArea(Box::new(light)))
        }
        (None, Some(emission)) => {
            let radiance = build_spectrum(emission, SpectrumUsage::Illuminant, "emitted radiance")?;
            let scale = radiance.max_value();
            (scale > 0.0).then_some(Light::Area {
                shape_index: index as u32,
                radiance,
                flip_normals: shape.flip_normals,
                scale,
            })
        }
        (None, None) => None,
    })
}

/// Appends the description's lights to `lights` (after the area lights),
/// those at infinity bounding the scene `geometry`; returns the indices of
/// the lights at infinity that escaping rays see.
pub(in crate::scene) fn push_listed_lights(
    descriptions: &[LightDescription],
    geometry: &Geometry,
    lights: &mut Vec<Light>,
) -> Result<Vec<u32>, SceneError> {
    let (scene_center, scene_radius) = geometry.bounds().bounding_sphere();
    let mut environment_lights = Vec::new();
    for light in descriptions {
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
                if !direction.is_finite() || direction == Vec3::ZERO {
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
                    map: Arc::new(EnvironmentMap::load(
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
    Ok(environment_lights)
}

/// The sampler that picks `lights` for next-event estimation, in
/// proportion to their power (with the share of those at infinity).
pub(in crate::scene) fn light_sampler(lights: &[Light], geometry: &Geometry) -> LightSampler {
    let powers: Vec<f32> = lights.iter().map(|light| light.power(geometry)).collect();
    LightSampler::with_infinite_share(
        &powers,
        &lights.iter().map(Light::is_infinite).collect::<Vec<_>>(),
    )
}

/// A projector from its description: the image's aspect ratio turns the
/// field of view along `fov_axis` into the horizontal one.
fn projector_light(
    to_world: Affine3A,
    irradiance: &TextureDescription,
    scale: f32,
    fov_degrees: f32,
    fov_axis: ProjectorFovAxis,
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
    let texture =
        build_spectrum_texture(irradiance, SpectrumUsage::Albedo, "projector irradiance")?;
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
        .map(|texture| build_spectrum_texture(texture, SpectrumUsage::Albedo, "spot light texture"))
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
