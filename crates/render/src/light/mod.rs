//! Lights: diffuse area lights on shapes, point and spot lights, directional
//! lights, a constant environment and image environment maps, with the
//! sampling that next-event estimation needs and the densities that multiple
//! importance sampling needs.
//!
//! All densities returned here are per unit solid angle at the reference
//! point, and do not include the probability of choosing the light (see
//! [`LightSampler`]).

mod emission;
mod environment_map;
mod equal_area;
mod error;
mod light_sampler;
mod piecewise_constant;
mod projector;
mod spot;
mod textured_area;

pub use emission::{EmissionPdf, EmissionSample};
pub use environment_map::{EnvironmentMap, EnvironmentProjection, EnvironmentSample};
pub use equal_area::{equal_area_sphere_to_square, equal_area_square_to_sphere};
pub use error::LightError;
pub use light_sampler::LightSampler;
pub use piecewise_constant::{PiecewiseConstant1D, PiecewiseConstant2D, Sample1D, Sample2D};
pub use projector::ProjectorLight;
pub use spot::{SpotFalloff, SpotLight, smoothstep};
pub use textured_area::{TexturedAreaLight, sample_with_uv};

use std::f32::consts::PI;
use std::sync::Arc;

use crate::geometry::{Geometry, Shape};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum, d65_illuminant};
use glam::{Vec2, Vec3};

/// A light source.
#[derive(Debug, Clone)]
pub enum Light {
    /// A shape emitting `radiance` from its front side (the side its
    /// geometric normal points to, after `flip_normals`).
    Area {
        shape_index: u32,
        radiance: Spectrum,
        /// Emission and sampling use the reversed normal.
        flip_normals: bool,
        /// The emitted radiance's luminance-like scale, for light selection.
        scale: f32,
    },
    /// A point light with radiant intensity `intensity` (W/sr per unit).
    Point { position: Vec3, intensity: Spectrum },
    /// Radiance from every direction at infinity.
    ConstantEnvironment {
        radiance: Spectrum,
        /// The scene's bounding sphere, to place sampled points and weigh power.
        scene_center: Vec3,
        scene_radius: f32,
    },
    /// A point emitting into a cone (see [`SpotLight`]).
    Spot(Box<SpotLight>),
    /// Parallel light: irradiance `irradiance` on a surface facing it,
    /// travelling along the unit vector `direction` (a delta in direction).
    Directional {
        direction: Vec3,
        irradiance: Spectrum,
        /// The scene's bounding sphere: power is irradiance × its disk.
        scene_center: Vec3,
        scene_radius: f32,
    },
    /// Radiance at infinity from an image (see [`EnvironmentMap`]).
    EnvironmentMap {
        map: Arc<EnvironmentMap>,
        /// The scene's bounding sphere, to place sampled points and weigh power.
        scene_center: Vec3,
        scene_radius: f32,
    },
    /// A shape emitting a radiance texture (see [`TexturedAreaLight`]).
    TexturedArea(Box<TexturedAreaLight>),
    /// A point projecting an image (see [`ProjectorLight`]).
    Projector(Box<ProjectorLight>),
}

/// A light sample for next-event estimation.
#[derive(Debug, Clone, Copy)]
pub struct LightSample {
    /// Incident radiance arriving at the reference point from the sample.
    pub radiance: SampledSpectrum,
    /// Unit direction from the reference point towards the light.
    pub wi: Vec3,
    /// The point on the light (far away for infinite lights), the end of the
    /// shadow ray.
    pub point: Vec3,
    /// The light's surface normal at the point (zero for point and infinite lights).
    pub normal: Vec3,
    /// The surface coordinates of the point (area lights; zero otherwise).
    pub uv: Vec2,
    /// Density per unit solid angle (1 for a delta light).
    pub pdf: f32,
    /// True for lights that cannot be hit by rays (point, spot and
    /// directional lights).
    pub is_delta: bool,
    /// True for lights at infinity: the shadow ray is unbounded.
    pub is_infinite: bool,
}

impl Light {
    /// True for lights with a delta distribution (never hit by rays, no MIS).
    pub fn is_delta(&self) -> bool {
        matches!(
            self,
            Light::Point { .. } | Light::Spot(_) | Light::Directional { .. } | Light::Projector(_)
        )
    }

    /// True for lights at infinity.
    pub fn is_infinite(&self) -> bool {
        matches!(
            self,
            Light::ConstantEnvironment { .. }
                | Light::Directional { .. }
                | Light::EnvironmentMap { .. }
        )
    }

    /// True for lights that rays escaping the scene see
    /// ([`Light::environment_radiance`] is not always zero).
    pub fn is_environment(&self) -> bool {
        matches!(
            self,
            Light::ConstantEnvironment { .. } | Light::EnvironmentMap { .. }
        )
    }

    /// A scalar proportional to the emitted power, for choosing lights in
    /// proportion to it (Σ of the spectrum's maximum is enough for that).
    pub fn power(&self, geometry: &Geometry) -> f32 {
        match self {
            Light::Area {
                shape_index, scale, ..
            } => {
                let area = geometry.shapes()[*shape_index as usize].surface_area();
                scale * area * std::f32::consts::PI
            }
            Light::Point { intensity, .. } => 4.0 * std::f32::consts::PI * intensity.max_value(),
            Light::ConstantEnvironment {
                radiance,
                scene_radius,
                ..
            } => {
                std::f32::consts::PI
                    * scene_radius
                    * scene_radius
                    * std::f32::consts::PI
                    * radiance.max_value()
            }
            Light::Spot(spot) => spot.power(),
            // Everything crossing the scene's bounding disk.
            Light::Directional {
                irradiance,
                scene_radius,
                ..
            } => PI * scene_radius * scene_radius * irradiance.max_value(),
            // As the constant environment, with the mean radiance: luminance
            // relative to D65 times D65's maximum (RGB white gives the
            // constant environment's figure).
            Light::EnvironmentMap {
                map, scene_radius, ..
            } => {
                PI * scene_radius
                    * scene_radius
                    * PI
                    * map.mean_luminance()
                    * d65_illuminant().max_value()
            }
            Light::TexturedArea(light) => {
                let area = geometry.shapes()[light.shape_index as usize].surface_area();
                light.mean_scale * area * PI
            }
            Light::Projector(projector) => projector.power(),
        }
    }

    /// Samples incident radiance at `reference` with the light-position
    /// numbers `u` and a number `u_primitive` choosing a triangle of a mesh.
    pub fn sample_incident(
        &self,
        geometry: &Geometry,
        reference: Vec3,
        u_primitive: f32,
        u: [f32; 2],
        wavelengths: &SampledWavelengths,
    ) -> Option<LightSample> {
        self.sample_incident_with_area_radiance(
            geometry,
            reference,
            u_primitive,
            u,
            wavelengths,
            |radiance| radiance.sample(wavelengths),
        )
    }

    /// [`Light::sample_incident`] with an area light's radiance spectrum (the
    /// same at every point and direction of its front side) evaluated at
    /// `wavelengths` by `area_radiance`, which may return a value a path
    /// computed before for the same wavelengths (the path tracer's
    /// per-path cache). Called only for samples that are kept.
    #[inline]
    pub fn sample_incident_with_area_radiance(
        &self,
        geometry: &Geometry,
        reference: Vec3,
        u_primitive: f32,
        u: [f32; 2],
        wavelengths: &SampledWavelengths,
        area_radiance: impl FnOnce(&Spectrum) -> SampledSpectrum,
    ) -> Option<LightSample> {
        match self {
            Light::Area {
                shape_index,
                radiance,
                flip_normals,
                ..
            } => {
                let shape: &Shape = &geometry.shapes()[*shape_index as usize];
                let sample = shape.sample_from(reference, u_primitive, Vec2::from(u))?;
                let normal = if *flip_normals {
                    -sample.normal
                } else {
                    sample.normal
                };
                let (wi, pdf) = area_sample_direction(shape, reference, &sample, normal)?;
                Some(LightSample {
                    radiance: area_radiance(radiance),
                    wi,
                    point: sample.point,
                    normal,
                    uv: Vec2::ZERO,
                    pdf,
                    is_delta: false,
                    is_infinite: false,
                })
            }
            _ => self.sample_incident_not_area(geometry, reference, u_primitive, u, wavelengths),
        }
    }

    /// [`Light::sample_incident`] for every light but [`Light::Area`] (kept
    /// out of line so that the area light's path, the common one, inlines
    /// into next-event estimation).
    #[inline(never)]
    fn sample_incident_not_area(
        &self,
        geometry: &Geometry,
        reference: Vec3,
        u_primitive: f32,
        u: [f32; 2],
        wavelengths: &SampledWavelengths,
    ) -> Option<LightSample> {
        match self {
            Light::Area { .. } => {
                unreachable!("area lights are sampled by sample_incident_with_area_radiance")
            }
            Light::Point {
                position,
                intensity,
            } => {
                let to_light = *position - reference;
                let distance_squared = to_light.length_squared();
                if distance_squared == 0.0 {
                    return None;
                }
                Some(LightSample {
                    radiance: intensity.sample(wavelengths) / distance_squared,
                    wi: to_light / distance_squared.sqrt(),
                    point: *position,
                    normal: Vec3::ZERO,
                    uv: Vec2::ZERO,
                    pdf: 1.0,
                    is_delta: true,
                    is_infinite: false,
                })
            }
            Light::ConstantEnvironment {
                radiance,
                scene_radius,
                ..
            } => {
                let wi = crate::sampling::sample_uniform_sphere(u);
                Some(LightSample {
                    radiance: radiance.sample(wavelengths),
                    wi,
                    point: reference + wi * (4.0 * scene_radius.max(1.0)),
                    normal: Vec3::ZERO,
                    uv: Vec2::ZERO,
                    pdf: 1.0 / (4.0 * std::f32::consts::PI),
                    is_delta: false,
                    is_infinite: true,
                })
            }
            Light::Spot(spot) => directional_point_sample(spot.position, reference, |direction| {
                spot.intensity_towards(direction, wavelengths)
            }),
            Light::Directional {
                direction,
                irradiance,
                scene_center,
                scene_radius,
            } => {
                let wi = -*direction;
                Some(LightSample {
                    radiance: irradiance.sample(wavelengths),
                    wi,
                    point: reference + wi * far_distance(reference, *scene_center, *scene_radius),
                    normal: Vec3::ZERO,
                    uv: Vec2::ZERO,
                    pdf: 1.0,
                    is_delta: true,
                    is_infinite: true,
                })
            }
            Light::EnvironmentMap {
                map,
                scene_center,
                scene_radius,
            } => {
                let sample = map.sample(u)?;
                let wi = sample.direction;
                Some(LightSample {
                    radiance: map.radiance(wi, wavelengths),
                    wi,
                    point: reference + wi * far_distance(reference, *scene_center, *scene_radius),
                    normal: Vec3::ZERO,
                    uv: Vec2::ZERO,
                    pdf: sample.pdf,
                    is_delta: false,
                    is_infinite: true,
                })
            }
            Light::TexturedArea(light) => {
                let shape = &geometry.shapes()[light.shape_index as usize];
                let (sample, uv) =
                    sample_with_uv(shape, Some(reference), u_primitive, Vec2::from(u))?;
                let normal = light.front(sample.normal);
                let (wi, pdf) = area_sample_direction(shape, reference, &sample, normal)?;
                Some(LightSample {
                    radiance: light.radiance_at(uv, wavelengths),
                    wi,
                    point: sample.point,
                    normal,
                    uv,
                    pdf,
                    is_delta: false,
                    is_infinite: false,
                })
            }
            Light::Projector(projector) => {
                directional_point_sample(projector.position, reference, |direction| {
                    projector.intensity_towards(direction, wavelengths)
                })
            }
        }
    }

    /// The solid-angle density with which [`Light::sample_incident`] picks
    /// the point `point` (normal `normal`, as stored in the geometry, i.e.
    /// before any flip) seen from `reference`; for infinite lights the
    /// density of direction `point - reference`.
    pub fn pdf_incident(
        &self,
        geometry: &Geometry,
        reference: Vec3,
        point: Vec3,
        normal: Vec3,
    ) -> f32 {
        match self {
            Light::Area { shape_index, .. } => geometry.shapes()[*shape_index as usize]
                .pdf_solid_angle_from(reference, point, normal),
            Light::TexturedArea(light) => geometry.shapes()[light.shape_index as usize]
                .pdf_solid_angle_from(reference, point, normal),
            Light::Point { .. }
            | Light::Spot(_)
            | Light::Directional { .. }
            | Light::Projector(_) => 0.0,
            Light::ConstantEnvironment { .. } => 1.0 / (4.0 * std::f32::consts::PI),
            Light::EnvironmentMap { map, .. } => map.pdf(point - reference),
        }
    }

    /// Radiance emitted by an area light at a point with geometric normal
    /// `normal` (as stored in the geometry) and surface coordinates `uv`
    /// towards `wo`.
    pub fn emitted_radiance(
        &self,
        normal: Vec3,
        uv: Vec2,
        wo: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        self.emitted_radiance_with_area_radiance(normal, uv, wo, wavelengths, |radiance| {
            radiance.sample(wavelengths)
        })
    }

    /// [`Light::emitted_radiance`] with the area light's radiance spectrum
    /// evaluated by `area_radiance` (see
    /// [`Light::sample_incident_with_area_radiance`]); a textured area light
    /// varies over its surface and is evaluated at `uv` without the cache.
    pub fn emitted_radiance_with_area_radiance(
        &self,
        normal: Vec3,
        uv: Vec2,
        wo: Vec3,
        wavelengths: &SampledWavelengths,
        area_radiance: impl FnOnce(&Spectrum) -> SampledSpectrum,
    ) -> SampledSpectrum {
        match self {
            Light::Area {
                radiance,
                flip_normals,
                ..
            } => {
                let front = if *flip_normals { -normal } else { normal };
                if front.dot(wo) > 0.0 {
                    area_radiance(radiance)
                } else {
                    SampledSpectrum::zero()
                }
            }
            Light::TexturedArea(light) => light.emitted_radiance(normal, uv, wo, wavelengths),
            _ => SampledSpectrum::zero(),
        }
    }

    /// Radiance arriving from infinity along `direction` (environment
    /// lights; `direction` points from the scene towards the environment).
    pub fn environment_radiance(
        &self,
        direction: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        match self {
            Light::ConstantEnvironment { radiance, .. } => radiance.sample(wavelengths),
            Light::EnvironmentMap { map, .. } => map.radiance(direction, wavelengths),
            _ => SampledSpectrum::zero(),
        }
    }
}

/// The unit direction from `reference` to the point `sample` drew on `shape`
/// and the solid-angle density of drawing it ([`Shape::pdf_solid_angle_from`]),
/// or `None` when the point is behind the light's front side (`front_normal`,
/// the sample's normal after any flip), coincides with the reference, or has
/// no usable density.
///
/// For meshes and disks, which sample by area, the density `pdf_area · d² /
/// cos θ` equals `pdf_area · d² · (d² · r)` and the direction is
/// `to_light · (d cos θ) · r` with `r = 1 / (d · d cos θ)`, where `d cos θ` is
/// the dot product the front-side test needs anyway: one square root and one
/// division for both. Spheres sample their cone of directions and keep their
/// own density.
#[inline]
fn area_sample_direction(
    shape: &Shape,
    reference: Vec3,
    sample: &crate::geometry::ShapeSample,
    front_normal: Vec3,
) -> Option<(Vec3, f32)> {
    let to_light = sample.point - reference;
    let distance_squared = to_light.length_squared();
    // Emission leaves the front side only; zero also when the points coincide
    // (and NaN rejects degenerate input).
    let cosine_times_distance = -front_normal.dot(to_light);
    if cosine_times_distance.is_nan() || cosine_times_distance <= 0.0 {
        return None;
    }
    let distance = distance_squared.sqrt();
    let (wi, pdf) = match shape {
        Shape::Sphere(_) => (
            to_light / distance,
            shape.pdf_solid_angle_from(reference, sample.point, sample.normal),
        ),
        Shape::Mesh(_) | Shape::Disk(_) => {
            let reciprocal = 1.0 / (distance * cosine_times_distance);
            (
                to_light * (cosine_times_distance * reciprocal),
                sample.pdf_area * distance_squared * (distance_squared * reciprocal),
            )
        }
    };
    // Rejects 0, infinity and NaN.
    if !(pdf > 0.0 && pdf < f32::INFINITY) {
        return None;
    }
    Some((wi, pdf))
}

/// A distance from `reference` that is outside the scene's bounding sphere
/// (the end of a sampled point at infinity).
fn far_distance(reference: Vec3, scene_center: Vec3, scene_radius: f32) -> f32 {
    2.0 * (scene_radius.max(1.0) + reference.distance(scene_center))
}

/// The incident-light sample of a point light at `position` whose intensity
/// depends on the direction of emission (spot, projector): the radiance
/// `intensity(−wi) / d²` towards `reference`, `None` where it is black.
fn directional_point_sample(
    position: Vec3,
    reference: Vec3,
    intensity: impl FnOnce(Vec3) -> SampledSpectrum,
) -> Option<LightSample> {
    let to_light = position - reference;
    let distance_squared = to_light.length_squared();
    if distance_squared == 0.0 {
        return None;
    }
    let wi = to_light / distance_squared.sqrt();
    let intensity = intensity(-wi);
    if intensity.is_black() {
        return None;
    }
    Some(LightSample {
        radiance: intensity / distance_squared,
        wi,
        point: position,
        normal: Vec3::ZERO,
        uv: Vec2::ZERO,
        pdf: 1.0,
        is_delta: true,
        is_infinite: false,
    })
}
