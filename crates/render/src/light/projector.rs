//! Projector lights: a point projecting an image through a perspective
//! frustum (Mitsuba 3's `projector` emitter), a delta light in position.
//!
//! The conventions are those measured on Mitsuba 3.9.1 (`scalar_spectral`,
//! `emitter.sample_direction` on points in front of a projector with known
//! textures; not its code):
//!
//! - the light looks along its frame's +z; a light-frame direction
//!   (x, y, z) with z > 0 meets the image plane z = 1 at (x/z, y/z), which
//!   maps to the texture's
//!   `uv = (½ − ½ x / (z tan(fx/2)), ½ − ½ y / (z tan(fy/2)))` (both axes
//!   mirrored, as Mitsuba's cameras), `fx` the horizontal field of view
//!   and `tan(fy/2) = tan(fx/2) · height / width` of the texture; outside
//!   [0, 1]² nothing is emitted (no wrapping);
//! - the radiant intensity is `I(ω) = π · scale · T(uv) / cos³θ`, so that the
//!   irradiance on the plane z = 1 is `π · scale · T(uv)` (the probe gave
//!   `π · scale` on the axis for a white texture at any field of view and
//!   aspect, and the 1/cos³θ off axis);
//! - the texture `T` is evaluated as a reflectance-like bitmap (no D65);
//! - without a `fov`, Mitsuba's default focal length of 50 mm on 35 mm film
//!   gives the diagonal field of view (the loader converts it).
//!
//! Emission sampling for light tracing picks a uniform point of the image
//! rectangle on the plane z = 1, i.e. the direction density
//! `1 / (A cos³θ)` with `A = 4 tan(fx/2) tan(fy/2)`; then `I / pdf =
//! π · scale · T · A`, without the cosine.

use std::f32::consts::PI;

use glam::{Affine3A, Vec2, Vec3};

use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use crate::texture::{SpectrumTexture, TextureContext};

/// A projector at the origin of its frame, looking along +z.
#[derive(Debug, Clone)]
pub struct ProjectorLight {
    /// The light's position in world space.
    pub position: Vec3,
    /// Light frame to world (assumed rigid, as `lookat` gives).
    pub to_world: Affine3A,
    /// World to light frame.
    pub to_light: Affine3A,
    /// The projected image (Mitsuba's `irradiance`).
    pub texture: SpectrumTexture,
    /// Factor on the irradiance.
    pub scale: f32,
    /// tan of half the horizontal field of view.
    pub tan_half_x: f32,
    /// tan of half the vertical field of view.
    pub tan_half_y: f32,
    /// The mean over the image of the spectrum's largest value.
    mean_texture: f32,
}

/// Side of the grid on which [`ProjectorLight::new`] averages the image.
const POWER_GRID: usize = 64;

impl ProjectorLight {
    /// A projector with horizontal field of view `fov_x_degrees` in (0, 180)
    /// and an image of aspect `width / height` = `aspect` (both checked by
    /// the caller); `to_world` must be invertible.
    pub fn new(
        to_world: Affine3A,
        texture: SpectrumTexture,
        scale: f32,
        fov_x_degrees: f32,
        aspect: f32,
    ) -> Self {
        let tan_half_x = (0.5 * fov_x_degrees.to_radians()).tan();
        let wavelengths = SampledWavelengths::sample_visible(0.5);
        let mut sum = 0.0f64;
        for y in 0..POWER_GRID {
            for x in 0..POWER_GRID {
                let uv = Vec2::new(
                    (x as f32 + 0.5) / POWER_GRID as f32,
                    (y as f32 + 0.5) / POWER_GRID as f32,
                );
                sum += texture
                    .evaluate(
                        &TextureContext {
                            uv,
                            point: Vec3::ZERO,
                        },
                        &wavelengths,
                    )
                    .max_component() as f64;
            }
        }
        Self {
            position: to_world.translation.into(),
            to_world,
            to_light: to_world.inverse(),
            texture,
            scale,
            tan_half_x,
            tan_half_y: tan_half_x / aspect,
            mean_texture: (sum / (POWER_GRID * POWER_GRID) as f64) as f32,
        }
    }

    /// The area of the image rectangle on the plane at unit distance.
    pub fn image_plane_area(&self) -> f32 {
        4.0 * self.tan_half_x * self.tan_half_y
    }

    /// A scalar proportional to the emitted power:
    /// ∫ I dω = π · scale · ∫ T dA over the unit-distance image plane.
    pub fn power(&self) -> f32 {
        PI * self.scale * self.mean_texture * self.image_plane_area()
    }

    /// The image coordinates of light-frame direction `local`, if it passes
    /// through the image.
    fn image_uv(&self, local: Vec3) -> Option<Vec2> {
        if local.z <= 0.0 {
            return None;
        }
        let uv = Vec2::new(
            0.5 - 0.5 * local.x / (local.z * self.tan_half_x),
            0.5 - 0.5 * local.y / (local.z * self.tan_half_y),
        );
        ((0.0..=1.0).contains(&uv.x) && (0.0..=1.0).contains(&uv.y)).then_some(uv)
    }

    /// The radiant intensity towards world direction `direction` (from the
    /// light; need not be normalised).
    pub fn intensity_towards(
        &self,
        direction: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        let local = self.to_light.transform_vector3(direction);
        let length = local.length();
        let Some(uv) = self.image_uv(local).filter(|_| length > 0.0) else {
            return SampledSpectrum::zero();
        };
        let cos_theta = local.z / length;
        let texel = self.texture.evaluate(
            &TextureContext {
                uv,
                point: self.position,
            },
            wavelengths,
        );
        texel * (PI * self.scale / (cos_theta * cos_theta * cos_theta))
    }

    /// A world direction through a uniform point of the image rectangle on
    /// the unit-distance plane, and its solid-angle density.
    pub fn sample_direction(&self, u: [f32; 2]) -> Option<(Vec3, f32)> {
        let local = Vec3::new(
            (2.0 * u[0] - 1.0) * self.tan_half_x,
            (2.0 * u[1] - 1.0) * self.tan_half_y,
            1.0,
        );
        let direction = self.to_world.transform_vector3(local).normalize_or_zero();
        let pdf = self.pdf_direction(direction);
        (pdf > 0.0 && direction != Vec3::ZERO).then_some((direction, pdf))
    }

    /// The solid-angle density of [`ProjectorLight::sample_direction`] for a
    /// world direction: `1 / (A cos³θ)` inside the frustum.
    pub fn pdf_direction(&self, direction: Vec3) -> f32 {
        let local = self.to_light.transform_vector3(direction);
        let length = local.length();
        if length == 0.0 || self.image_uv(local).is_none() {
            return 0.0;
        }
        let cos_theta = local.z / length;
        1.0 / (self.image_plane_area() * cos_theta * cos_theta * cos_theta)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::{ConstantSpectrum, Spectrum};

    fn projector(value: f32) -> ProjectorLight {
        ProjectorLight::new(
            Affine3A::from_translation(Vec3::new(0.0, 0.0, 0.0)),
            SpectrumTexture::Constant(Spectrum::Constant(ConstantSpectrum::new(value).unwrap())),
            2.0,
            40.0,
            2.0,
        )
    }

    /// The numbers Mitsuba 3.9.1 gave (see the module docs): a constant
    /// texture gives irradiance π · scale · T on a plane facing the light at
    /// unit distance, `I / d²` = π · scale / (d² cos³θ) off axis, and nothing
    /// outside the frustum (x half-width tan 20° = 0.364, y half of it).
    #[test]
    fn intensity_matches_mitsuba_probe() {
        let light = projector(1.0);
        let wavelengths = SampledWavelengths::sample_visible(0.2);
        let at =
            |point: Vec3| light.intensity_towards(point, &wavelengths)[0] / point.length_squared();
        assert!((at(Vec3::new(0.0, 0.0, 1.0)) - 2.0 * PI).abs() < 1e-4);
        // Mitsuba: 0.7001 at (0.2, 0.1, 3) and 6.7421 at (0.35, 0.17, 1).
        assert!((at(Vec3::new(0.2, 0.1, 3.0)) - 0.7001).abs() < 1e-3);
        assert!((at(Vec3::new(0.35, 0.17, 1.0)) - 6.7421).abs() < 2e-3);
        assert_eq!(at(Vec3::new(0.5, 0.0, 1.0)), 0.0);
        assert_eq!(at(Vec3::new(0.0, 0.2, 1.0)), 0.0);
        assert_eq!(at(Vec3::new(0.0, 0.0, -1.0)), 0.0);
    }

    /// Closed form: the power is π · scale · T · A, and a midpoint rule of
    /// the intensity over the sphere agrees.
    #[test]
    fn power_is_the_integral_of_the_intensity() {
        let light = projector(0.5);
        let wavelengths = SampledWavelengths::sample_visible(0.2);
        let expected = PI * 2.0 * 0.5 * light.image_plane_area();
        assert!((light.power() - expected).abs() < 1e-4 * expected);
        let (steps_theta, steps_phi) = (800usize, 400usize);
        let mut integral = 0.0f64;
        let theta_max = 0.7f64;
        for i in 0..steps_theta {
            let theta = (i as f64 + 0.5) / steps_theta as f64 * theta_max;
            for j in 0..steps_phi {
                let phi = (j as f64 + 0.5) / steps_phi as f64 * std::f64::consts::TAU;
                let d = Vec3::new(
                    (theta.sin() * phi.cos()) as f32,
                    (theta.sin() * phi.sin()) as f32,
                    theta.cos() as f32,
                );
                integral += light.intensity_towards(d, &wavelengths)[0] as f64
                    * theta.sin()
                    * (theta_max / steps_theta as f64)
                    * (std::f64::consts::TAU / steps_phi as f64);
            }
        }
        assert!(
            (integral - expected as f64).abs() < 5e-3 * expected as f64,
            "{integral} vs {expected}"
        );
    }

    /// The direction density integrates to 1 over the sphere (midpoint rule
    /// in θ and φ about the axis), and sampled directions are uniform over
    /// the image (chi-square over 8 × 8 cells of uv, `render::statistics`).
    #[test]
    fn direction_density_is_normalised_and_sampling_is_uniform_over_the_image() {
        let light = ProjectorLight::new(
            Affine3A::from_rotation_y(0.7),
            SpectrumTexture::Constant(Spectrum::Constant(ConstantSpectrum::new(1.0).unwrap())),
            1.0,
            50.0,
            1.5,
        );
        let (steps_theta, steps_phi) = (1000usize, 500usize);
        let theta_max = 0.8f64;
        let mut integral = 0.0f64;
        for i in 0..steps_theta {
            let theta = (i as f64 + 0.5) / steps_theta as f64 * theta_max;
            for j in 0..steps_phi {
                let phi = (j as f64 + 0.5) / steps_phi as f64 * std::f64::consts::TAU;
                let local = Vec3::new(
                    (theta.sin() * phi.cos()) as f32,
                    (theta.sin() * phi.sin()) as f32,
                    theta.cos() as f32,
                );
                let world = light.to_world.transform_vector3(local);
                integral += light.pdf_direction(world) as f64
                    * theta.sin()
                    * (theta_max / steps_theta as f64)
                    * (std::f64::consts::TAU / steps_phi as f64);
            }
        }
        assert!((integral - 1.0).abs() < 5e-3, "{integral}");
        let cells = 8usize;
        let samples = 64_000u64;
        let mut observed = vec![0u64; cells * cells];
        let mut random = qmc::random::SeekablePcg::new(3, 0);
        for _ in 0..samples {
            let (direction, pdf) = light
                .sample_direction([random.next_f32(), random.next_f32()])
                .unwrap();
            assert!((pdf - light.pdf_direction(direction)).abs() <= 1e-4 * pdf);
            let uv = light
                .image_uv(light.to_light.transform_vector3(direction))
                .unwrap();
            let x = ((uv.x * cells as f32) as usize).min(cells - 1);
            let y = ((uv.y * cells as f32) as usize).min(cells - 1);
            observed[y * cells + x] += 1;
        }
        let expected = vec![samples as f64 / (cells * cells) as f64; cells * cells];
        let result = crate::statistics::chi_square_test(&observed, &expected);
        assert!(result.p_value > 1e-3, "{result:?}");
    }
}
