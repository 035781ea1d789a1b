//! Sampling rays leaving lights, for light tracing (particle tracing,
//! bidirectional path tracing): an origin with its density per unit area and
//! a direction with its density per unit solid angle, as pbrt-v4's
//! `SampleLe`/`PDF_Le`.
//!
//! - Area lights: a uniform point of the shape, a cosine-distributed
//!   direction about its front normal.
//! - Point lights: the position (delta), a uniform direction.
//! - Spot lights: the position (delta), a uniform direction in the cone of
//!   the cutoff about the world-space axis (Mitsuba's `sample_ray`); the
//!   transform is assumed rigid (as `lookat` gives).
//! - Directional lights: a uniform point of the scene's bounding disk
//!   facing the light, a delta direction.
//! - Environments: a direction towards the environment (uniform, or the
//!   map's importance sampling), then a uniform point of the bounding disk
//!   perpendicular to it, one radius out from the scene's centre; the ray
//!   travels the opposite way into the scene.
//!
//! Delta components report density 1 in the sample (they cancel with the
//! delta in the estimator) and 0 from [`Light::pdf_emission`] (no other
//! strategy can produce them), as pbrt-v4 does.

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::Light;
use crate::geometry::{Geometry, coordinate_frame};
use crate::sampling::{
    cosine_hemisphere_pdf, sample_cosine_hemisphere, sample_uniform_disk_concentric_trigonometric,
    sample_uniform_sphere,
};
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// A ray leaving a light.
#[derive(Debug, Clone, Copy)]
pub struct EmissionSample {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Its unit direction.
    pub direction: Vec3,
    /// The light's front normal at the origin (area lights), the direction
    /// for lights whose origins lie on a disk (directional, environments),
    /// zero for point and spot lights.
    pub normal: Vec3,
    /// Radiance along the ray (area lights, environments), or intensity
    /// (point, spot) or irradiance (directional) for delta components.
    pub radiance: SampledSpectrum,
    /// Density of the origin per unit area (1 for a delta position).
    pub pdf_position: f32,
    /// Density of the direction per unit solid angle (1 for a delta direction).
    pub pdf_direction: f32,
    /// The origin is a fixed point (point and spot lights).
    pub is_delta_position: bool,
    /// The direction is fixed (directional lights).
    pub is_delta_direction: bool,
}

/// The densities of a ray leaving a light (see [`Light::pdf_emission`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EmissionPdf {
    /// Per unit area of the origin (0 for delta positions).
    pub position: f32,
    /// Per unit solid angle of the direction (0 for delta directions).
    pub direction: f32,
}

/// The origin on the disk of radius `radius` perpendicular to `towards_light`,
/// one radius from `center` on the light's side.
fn disk_origin(center: Vec3, radius: f32, towards_light: Vec3, u: [f32; 2]) -> Vec3 {
    let (s, t) = coordinate_frame(towards_light);
    let disk = sample_uniform_disk_concentric_trigonometric(u);
    center + radius * (towards_light + disk.x * s + disk.y * t)
}

fn disk_pdf(radius: f32) -> f32 {
    if radius > 0.0 {
        1.0 / (PI * radius * radius)
    } else {
        0.0
    }
}

/// The uniform density over a cone of half-angle with cosine `cos_cutoff`.
fn cone_pdf(cos_cutoff: f32) -> f32 {
    1.0 / (2.0 * PI * (1.0 - cos_cutoff))
}

impl Light {
    /// Samples a ray leaving the light: `u_primitive` picks a mesh triangle,
    /// `u_position` the origin and `u_direction` the direction.
    pub fn sample_emission(
        &self,
        geometry: &Geometry,
        u_primitive: f32,
        u_position: [f32; 2],
        u_direction: [f32; 2],
        wavelengths: &SampledWavelengths,
    ) -> Option<EmissionSample> {
        match self {
            Light::Area {
                shape_index,
                radiance,
                flip_normals,
                ..
            } => {
                let shape = &geometry.shapes()[*shape_index as usize];
                let sample = shape.sample_area(u_primitive, Vec2::from(u_position))?;
                let normal = if *flip_normals {
                    -sample.normal
                } else {
                    sample.normal
                };
                let local = sample_cosine_hemisphere(u_direction);
                let (s, t) = coordinate_frame(normal);
                let direction = (local.x * s + local.y * t + local.z * normal).normalize();
                let pdf_direction = cosine_hemisphere_pdf(local.z);
                if !(pdf_direction > 0.0 && sample.pdf_area > 0.0) {
                    return None;
                }
                Some(EmissionSample {
                    origin: sample.point,
                    direction,
                    normal,
                    radiance: radiance.sample(wavelengths),
                    pdf_position: sample.pdf_area,
                    pdf_direction,
                    is_delta_position: false,
                    is_delta_direction: false,
                })
            }
            Light::Point {
                position,
                intensity,
            } => Some(EmissionSample {
                origin: *position,
                direction: sample_uniform_sphere(u_direction),
                normal: Vec3::ZERO,
                radiance: intensity.sample(wavelengths),
                pdf_position: 1.0,
                pdf_direction: 1.0 / (4.0 * PI),
                is_delta_position: true,
                is_delta_direction: false,
            }),
            Light::Spot(spot) => {
                let axis = spot.axis();
                let cos_cutoff = spot.cutoff.cos();
                // Uniform in the cone: cos θ uniform in [cos c, 1].
                let cos_theta = 1.0 - u_direction[0] * (1.0 - cos_cutoff);
                let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
                let phi = 2.0 * PI * u_direction[1];
                let (s, t) = coordinate_frame(axis);
                let direction =
                    (sin_theta * (phi.cos() * s + phi.sin() * t) + cos_theta * axis).normalize();
                Some(EmissionSample {
                    origin: spot.position,
                    direction,
                    normal: Vec3::ZERO,
                    radiance: spot.intensity_towards(direction, wavelengths),
                    pdf_position: 1.0,
                    pdf_direction: cone_pdf(cos_cutoff),
                    is_delta_position: true,
                    is_delta_direction: false,
                })
            }
            Light::Directional {
                direction,
                irradiance,
                scene_center,
                scene_radius,
            } => Some(EmissionSample {
                origin: disk_origin(*scene_center, *scene_radius, -*direction, u_position),
                direction: *direction,
                normal: *direction,
                radiance: irradiance.sample(wavelengths),
                pdf_position: disk_pdf(*scene_radius),
                pdf_direction: 1.0,
                is_delta_position: false,
                is_delta_direction: true,
            }),
            Light::ConstantEnvironment {
                radiance,
                scene_center,
                scene_radius,
            } => {
                let towards_light = sample_uniform_sphere(u_direction);
                Some(EmissionSample {
                    origin: disk_origin(*scene_center, *scene_radius, towards_light, u_position),
                    direction: -towards_light,
                    normal: -towards_light,
                    radiance: radiance.sample(wavelengths),
                    pdf_position: disk_pdf(*scene_radius),
                    pdf_direction: 1.0 / (4.0 * PI),
                    is_delta_position: false,
                    is_delta_direction: false,
                })
            }
            Light::EnvironmentMap {
                map,
                scene_center,
                scene_radius,
            } => {
                let sample = map.sample(u_direction)?;
                let towards_light = sample.direction;
                Some(EmissionSample {
                    origin: disk_origin(*scene_center, *scene_radius, towards_light, u_position),
                    direction: -towards_light,
                    normal: -towards_light,
                    radiance: map.radiance(towards_light, wavelengths),
                    pdf_position: disk_pdf(*scene_radius),
                    pdf_direction: sample.pdf,
                    is_delta_position: false,
                    is_delta_direction: false,
                })
            }
            Light::TexturedArea(light) => {
                let shape = &geometry.shapes()[light.shape_index as usize];
                let (sample, uv) =
                    super::sample_with_uv(shape, None, u_primitive, Vec2::from(u_position))?;
                let normal = light.front(sample.normal);
                let local = sample_cosine_hemisphere(u_direction);
                let (s, t) = coordinate_frame(normal);
                let direction = (local.x * s + local.y * t + local.z * normal).normalize();
                let pdf_direction = cosine_hemisphere_pdf(local.z);
                if !(pdf_direction > 0.0 && sample.pdf_area > 0.0) {
                    return None;
                }
                Some(EmissionSample {
                    origin: sample.point,
                    direction,
                    normal,
                    radiance: light.radiance_at(uv, wavelengths),
                    pdf_position: sample.pdf_area,
                    pdf_direction,
                    is_delta_position: false,
                    is_delta_direction: false,
                })
            }
            Light::Projector(projector) => {
                let (direction, pdf_direction) = projector.sample_direction(u_direction)?;
                Some(EmissionSample {
                    origin: projector.position,
                    direction,
                    normal: Vec3::ZERO,
                    radiance: projector.intensity_towards(direction, wavelengths),
                    pdf_position: 1.0,
                    pdf_direction,
                    is_delta_position: true,
                    is_delta_direction: false,
                })
            }
        }
    }

    /// The densities with which [`Light::sample_emission`] produces a ray
    /// from `origin` along unit `direction`; `normal` is the light's normal
    /// at the origin as stored in the geometry (area lights; ignored by the
    /// others). Delta components have density 0.
    pub fn pdf_emission(
        &self,
        geometry: &Geometry,
        origin: Vec3,
        direction: Vec3,
        normal: Vec3,
    ) -> EmissionPdf {
        // Every origin density here is uniform over its domain.
        let _ = origin;
        match self {
            Light::Area {
                shape_index,
                flip_normals,
                ..
            } => {
                let shape = &geometry.shapes()[*shape_index as usize];
                let front = if *flip_normals { -normal } else { normal };
                let cosine = front.dot(direction);
                let area = shape.surface_area();
                EmissionPdf {
                    position: if area > 0.0 { 1.0 / area } else { 0.0 },
                    direction: if cosine > 0.0 {
                        cosine_hemisphere_pdf(cosine)
                    } else {
                        0.0
                    },
                }
            }
            Light::Point { .. } => EmissionPdf {
                position: 0.0,
                direction: 1.0 / (4.0 * PI),
            },
            Light::Spot(spot) => {
                let cos_cutoff = spot.cutoff.cos();
                EmissionPdf {
                    position: 0.0,
                    direction: if spot.axis().dot(direction) >= cos_cutoff {
                        cone_pdf(cos_cutoff)
                    } else {
                        0.0
                    },
                }
            }
            Light::Directional { scene_radius, .. } => EmissionPdf {
                position: disk_pdf(*scene_radius),
                direction: 0.0,
            },
            Light::ConstantEnvironment { scene_radius, .. } => EmissionPdf {
                position: disk_pdf(*scene_radius),
                direction: 1.0 / (4.0 * PI),
            },
            Light::EnvironmentMap {
                map, scene_radius, ..
            } => EmissionPdf {
                position: disk_pdf(*scene_radius),
                direction: map.pdf(-direction),
            },
            Light::TexturedArea(light) => {
                let area = geometry.shapes()[light.shape_index as usize].surface_area();
                let cosine = light.front(normal).dot(direction);
                EmissionPdf {
                    position: if area > 0.0 { 1.0 / area } else { 0.0 },
                    direction: if cosine > 0.0 {
                        cosine_hemisphere_pdf(cosine)
                    } else {
                        0.0
                    },
                }
            }
            Light::Projector(projector) => EmissionPdf {
                position: 0.0,
                direction: projector.pdf_direction(direction),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Shape, Transform, TriangleMesh};
    use crate::image::Image;
    use crate::light::{EnvironmentMap, ProjectorLight, SpotLight, TexturedAreaLight};
    use crate::light::{EnvironmentProjection, SpotFalloff};
    use crate::spectrum::{ConstantSpectrum, Spectrum};
    use crate::statistics::chi_square_test;
    use crate::texture::{Checkerboard, SpectrumTexture};
    use glam::{Affine3A, Mat4};
    use qmc::random::SeekablePcg;
    use std::sync::Arc;

    fn constant(value: f32) -> Spectrum {
        Spectrum::Constant(ConstantSpectrum::new(value).unwrap())
    }

    /// A texture that varies over uv: a checkerboard of 0.2 and 1.5.
    fn checkerboard() -> SpectrumTexture {
        SpectrumTexture::Checkerboard(Box::new(Checkerboard {
            even: SpectrumTexture::Constant(constant(0.2)),
            odd: SpectrumTexture::Constant(constant(1.5)),
            to_uv: glam::Affine2::from_scale(glam::Vec2::splat(4.0)),
        }))
    }

    /// A tilted rectangle (the only shape) and every kind of light.
    fn setup() -> (Geometry, Vec<Light>) {
        let to_world =
            Affine3A::from_rotation_x(0.5) * Affine3A::from_scale(Vec3::new(2.0, 1.0, 1.0));
        let mesh = TriangleMesh::rectangle(&Transform::from_matrix(Mat4::from(to_world)).unwrap())
            .unwrap();
        let geometry = Geometry::new(vec![Shape::Mesh(mesh)]).unwrap();
        let (scene_center, scene_radius) = geometry.bounds().bounding_sphere();
        let mut pixels = Vec::new();
        for y in 0..6 {
            for x in 0..10 {
                pixels.push([1.0 + x as f32, 0.5 + (y * x) as f32, 0.2]);
            }
        }
        let map = EnvironmentMap::from_image(
            &Image::from_pixels(10, 6, pixels).unwrap(),
            EnvironmentProjection::MitsubaEquirectangular,
            Affine3A::from_rotation_z(0.3),
            1.0,
        )
        .unwrap();
        let spot = SpotLight::new(
            Affine3A::from_translation(Vec3::new(0.0, 1.0, 2.0)) * Affine3A::from_rotation_x(2.0),
            constant(3.0),
            None,
            SpotFalloff::PbrtSmoothstep,
            35.0,
            25.0,
        );
        let lights = vec![
            Light::Area {
                shape_index: 0,
                radiance: constant(1.0),
                flip_normals: true,
                scale: 1.0,
            },
            Light::Point {
                position: Vec3::new(0.3, 0.2, 1.0),
                intensity: constant(2.0),
            },
            Light::Spot(Box::new(spot)),
            Light::Directional {
                direction: Vec3::new(0.3, -1.0, 0.2).normalize(),
                irradiance: constant(1.0),
                scene_center,
                scene_radius,
            },
            Light::ConstantEnvironment {
                radiance: constant(1.0),
                scene_center,
                scene_radius,
            },
            Light::EnvironmentMap {
                map: Arc::new(map),
                scene_center,
                scene_radius,
            },
            Light::TexturedArea(Box::new(TexturedAreaLight::new(0, checkerboard(), true))),
            Light::Projector(Box::new(ProjectorLight::new(
                Affine3A::from_translation(Vec3::new(0.5, -1.0, 1.0))
                    * Affine3A::from_rotation_x(2.2),
                checkerboard(),
                3.0,
                50.0,
                1.5,
            ))),
        ];
        (geometry, lights)
    }

    /// Sample densities equal the reported ones, directions are unit
    /// vectors, and origins of disk-sampled rays lie on the bounding disk.
    #[test]
    fn sampled_densities_match_pdf_emission() {
        let (geometry, lights) = setup();
        let (center, radius) = geometry.bounds().bounding_sphere();
        let wavelengths = SampledWavelengths::sample_visible(0.3);
        let mut random = SeekablePcg::new(4, 0);
        for light in &lights {
            for _ in 0..2000 {
                let u = |random: &mut SeekablePcg| [random.next_f32(), random.next_f32()];
                let (a, b, c) = (random.next_f32(), u(&mut random), u(&mut random));
                let Some(sample) = light.sample_emission(&geometry, a, b, c, &wavelengths) else {
                    continue;
                };
                assert!((sample.direction.length() - 1.0).abs() < 1e-4);
                let stored_normal = match light {
                    Light::Area { .. } | Light::TexturedArea(_) => -sample.normal,
                    _ => sample.normal,
                };
                let pdf =
                    light.pdf_emission(&geometry, sample.origin, sample.direction, stored_normal);
                let close = |a: f32, b: f32| (a - b).abs() <= 2e-3 * b.abs();
                if sample.is_delta_position {
                    assert_eq!(pdf.position, 0.0);
                } else {
                    assert!(close(pdf.position, sample.pdf_position), "{light:?}");
                }
                if sample.is_delta_direction {
                    assert_eq!(pdf.direction, 0.0);
                } else {
                    assert!(
                        close(pdf.direction, sample.pdf_direction),
                        "{pdf:?} vs {} for {light:?}",
                        sample.pdf_direction
                    );
                }
                if light.is_infinite() {
                    // On the disk one radius out, perpendicular to the direction.
                    let offset = sample.origin - center;
                    assert!((offset.dot(-sample.direction) - radius).abs() < 1e-3 * radius);
                    assert!(offset.length() <= radius * 2f32.sqrt() * (1.0 + 1e-4));
                }
            }
        }
    }

    /// Chi-square of emitted directions over (cos θ, φ) bins against the
    /// reported direction density, for every light whose direction density
    /// does not depend on the origin (all but the delta direction).
    #[test]
    fn emitted_directions_follow_their_density() {
        let (geometry, lights) = setup();
        let wavelengths = SampledWavelengths::sample_visible(0.6);
        let (bins_z, bins_phi) = (10usize, 20usize);
        let bin = |d: Vec3| {
            let z = (((d.z + 1.0) / 2.0 * bins_z as f32) as usize).min(bins_z - 1);
            let phi = d.y.atan2(d.x).rem_euclid(2.0 * PI);
            let p = ((phi / (2.0 * PI) * bins_phi as f32) as usize).min(bins_phi - 1);
            z * bins_phi + p
        };
        for light in &lights {
            if matches!(
                light,
                Light::Directional { .. } | Light::Spot(_) | Light::Projector(_)
            ) {
                continue;
            }
            let mut random = SeekablePcg::new(8, 1);
            let samples = 100_000u64;
            let mut observed = vec![0u64; bins_z * bins_phi];
            let mut stored_normal = Vec3::ZERO;
            for _ in 0..samples {
                let sample = light
                    .sample_emission(
                        &geometry,
                        random.next_f32(),
                        [random.next_f32(), random.next_f32()],
                        [random.next_f32(), random.next_f32()],
                        &wavelengths,
                    )
                    .unwrap();
                stored_normal = -sample.normal;
                observed[bin(sample.direction)] += 1;
            }
            let refine = 16usize;
            let mut expected = vec![0.0f64; bins_z * bins_phi];
            let cell = 2.0 / (bins_z * refine) as f64 * 2.0 * std::f64::consts::PI
                / (bins_phi * refine) as f64;
            for zi in 0..bins_z * refine {
                let z = -1.0 + 2.0 * (zi as f32 + 0.5) / (bins_z * refine) as f32;
                let r = (1.0 - z * z).sqrt();
                for pi in 0..bins_phi * refine {
                    let phi = 2.0 * PI * (pi as f32 + 0.5) / (bins_phi * refine) as f32;
                    let d = Vec3::new(r * phi.cos(), r * phi.sin(), z);
                    let pdf = light.pdf_emission(&geometry, Vec3::ZERO, d, stored_normal);
                    expected[bin(d)] += pdf.direction as f64 * cell * samples as f64;
                }
            }
            let result = chi_square_test(&observed, &expected);
            assert!(result.p_value > 1e-3, "{light:?}: {result:?}");
        }
    }

    /// Spot directions are uniform in the cutoff cone about the axis: in the
    /// axis frame, (cos θ − cos c)/(1 − cos c) and φ/2π are uniform.
    #[test]
    fn spot_directions_are_uniform_in_the_cone() {
        let (geometry, lights) = setup();
        let Light::Spot(spot) = &lights[2] else {
            unreachable!()
        };
        let axis = spot.axis();
        let (s, t) = coordinate_frame(axis);
        let cos_cutoff = spot.cutoff.cos();
        let wavelengths = SampledWavelengths::sample_visible(0.6);
        let mut random = SeekablePcg::new(8, 2);
        let (bins, samples) = (16usize, 64_000u64);
        let mut observed = vec![0u64; bins * bins];
        for _ in 0..samples {
            let sample = lights[2]
                .sample_emission(
                    &geometry,
                    0.5,
                    [0.5, 0.5],
                    [random.next_f32(), random.next_f32()],
                    &wavelengths,
                )
                .unwrap();
            let d = sample.direction;
            let a = ((d.dot(axis) - cos_cutoff) / (1.0 - cos_cutoff)).clamp(0.0, 0.999_999);
            let phi = d.dot(t).atan2(d.dot(s)).rem_euclid(2.0 * PI) / (2.0 * PI);
            let (i, j) = (
                (a * bins as f32) as usize,
                ((phi * bins as f32) as usize).min(bins - 1),
            );
            observed[i * bins + j] += 1;
            // Inside the cone the reported intensity is the profile's.
            let falloff = spot.falloff_factor(d.dot(axis));
            assert!((sample.radiance[0] - 3.0 * falloff).abs() < 1e-3);
        }
        let expected = vec![samples as f64 / (bins * bins) as f64; bins * bins];
        let result = chi_square_test(&observed, &expected);
        assert!(result.p_value > 1e-3, "{result:?}");
    }
}
