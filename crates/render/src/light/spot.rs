//! Spot lights: a point emitting into a cone around its axis, with the
//! falloff profile of Mitsuba 3 or of pbrt-v4 and Mitsuba's optional
//! projected texture.
//!
//! - Mitsuba 3 `spot` (documented in its `src/emitters/spot.cpp`): the
//!   intensity is full inside `beam_width` of the axis and ramps down
//!   *linearly in the angle* to 0 at `cutoff_angle`:
//!   `f(θ) = (cutoff − θ) / (cutoff − beam)`. A `texture` multiplies the
//!   intensity, looked up at `uv = (½ + ½ x / (z tan cutoff), ½ + ½ y / (z tan
//!   cutoff))` for the light-frame direction (x, y, z).
//! - pbrt-v4 `spot` (its `SpotLight::I`): `smoothstep(cos coneangle,
//!   cos(coneangle − conedeltaangle), cos θ)`, smooth in the *cosine*.
//!
//! Both are delta lights in position: next-event estimation is their only
//! strategy, and their densities for MIS are 0.

use std::f32::consts::TAU;

use glam::{Affine3A, Vec2, Vec3};

use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use crate::texture::{SpectrumTexture, TextureContext};

/// How a spot light's intensity falls off between the start of the falloff
/// (angle β from the axis) and the cutoff (angle c).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SpotFalloff {
    /// Mitsuba 3's `spot`: `(c − θ) / (c − β)`, linear in the angle θ.
    MitsubaLinearAngle,
    /// pbrt-v4's `spot`: `smoothstep(cos c, cos β, cos θ)`, in the cosine.
    PbrtSmoothstep,
}

/// A spot light at the origin of its frame shining along its +z.
#[derive(Debug, Clone)]
pub struct SpotLight {
    /// The light's position in world space.
    pub position: Vec3,
    /// Light frame to world (as given: may include a scale).
    pub to_world: Affine3A,
    /// World to light frame.
    pub to_light: Affine3A,
    /// Radiant intensity on the axis.
    pub intensity: Spectrum,
    /// A factor on the intensity over the cone's image (Mitsuba's `texture`).
    pub texture: Option<SpectrumTexture>,
    /// The falloff profile.
    pub falloff: SpotFalloff,
    /// Angle of the cone's edge, beyond which nothing is emitted (radians).
    pub cutoff: f32,
    /// Angle up to which the intensity is full (radians, ≤ `cutoff`).
    pub falloff_start: f32,
    cos_cutoff: f32,
    cos_falloff_start: f32,
    tan_cutoff: f32,
}

impl SpotLight {
    /// A spot light; angles in degrees with `0 ≤ falloff_start ≤ cutoff < 180`
    /// (checked by the caller). `to_world` must be invertible.
    pub fn new(
        to_world: Affine3A,
        intensity: Spectrum,
        texture: Option<SpectrumTexture>,
        falloff: SpotFalloff,
        cutoff_degrees: f32,
        falloff_start_degrees: f32,
    ) -> Self {
        let cutoff = cutoff_degrees.to_radians();
        let falloff_start = falloff_start_degrees.to_radians().min(cutoff);
        Self {
            position: to_world.translation.into(),
            to_world,
            to_light: to_world.inverse(),
            intensity,
            texture,
            falloff,
            cutoff,
            falloff_start,
            cos_cutoff: cutoff.cos(),
            cos_falloff_start: falloff_start.cos(),
            tan_cutoff: cutoff.tan(),
        }
    }

    /// The unit axis of the cone in world space.
    pub fn axis(&self) -> Vec3 {
        self.to_world.transform_vector3(Vec3::Z).normalize()
    }

    /// The factor in [0, 1] of the profile at angle θ from the axis, given
    /// cos θ.
    pub fn falloff_factor(&self, cos_theta: f32) -> f32 {
        match self.falloff {
            SpotFalloff::MitsubaLinearAngle => {
                if cos_theta >= self.cos_falloff_start {
                    1.0
                } else if cos_theta > self.cos_cutoff {
                    let theta = cos_theta.clamp(-1.0, 1.0).acos();
                    ((self.cutoff - theta) / (self.cutoff - self.falloff_start)).clamp(0.0, 1.0)
                } else {
                    0.0
                }
            }
            SpotFalloff::PbrtSmoothstep => {
                smoothstep(self.cos_cutoff, self.cos_falloff_start, cos_theta)
            }
        }
    }

    /// ∫ over the sphere of the profile, in steradians: the power per unit
    /// axial intensity (without the texture).
    pub fn profile_solid_angle(&self) -> f32 {
        let (cutoff, start) = (self.cutoff, self.falloff_start);
        match self.falloff {
            // 2π [∫₀^β sin θ dθ + ∫_β^c (c − θ)/(c − β) sin θ dθ]
            //   = 2π [1 − (sin c − sin β) / (c − β)] (integration by parts).
            SpotFalloff::MitsubaLinearAngle => {
                if cutoff - start > 1e-6 {
                    TAU * (1.0 - (cutoff.sin() - start.sin()) / (cutoff - start))
                } else {
                    TAU * (1.0 - cutoff.cos())
                }
            }
            // The smoothstep averages ½ over [cos c, cos β] (pbrt-v4's Phi).
            SpotFalloff::PbrtSmoothstep => {
                TAU * ((1.0 - self.cos_falloff_start)
                    + 0.5 * (self.cos_falloff_start - self.cos_cutoff))
            }
        }
    }

    /// A scalar proportional to the emitted power (the texture, a factor of
    /// at most about 1, is left out).
    pub fn power(&self) -> f32 {
        self.intensity.max_value() * self.profile_solid_angle()
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
        if length == 0.0 {
            return SampledSpectrum::zero();
        }
        let factor = self.falloff_factor(local.z / length);
        if factor <= 0.0 {
            return SampledSpectrum::zero();
        }
        let mut intensity = self.intensity.sample(wavelengths) * factor;
        if let Some(texture) = &self.texture {
            let scale = 0.5 / (local.z * self.tan_cutoff);
            let uv = Vec2::new(0.5 + local.x * scale, 0.5 + local.y * scale);
            intensity *= texture.evaluate(
                &TextureContext {
                    uv,
                    point: self.position,
                },
                wavelengths,
            );
        }
        intensity
    }
}

/// pbrt-v4's `SmoothStep(a, b, x)`: 0 below a, 1 above b, `t²(3 − 2t)` with
/// `t = (x − a)/(b − a)` between; a step at a when a = b.
pub fn smoothstep(a: f32, b: f32, x: f32) -> f32 {
    if a == b {
        return if x < a { 0.0 } else { 1.0 };
    }
    let t = ((x - a) / (b - a)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::ConstantSpectrum;

    fn spot(falloff: SpotFalloff) -> SpotLight {
        SpotLight::new(
            Affine3A::IDENTITY,
            Spectrum::Constant(ConstantSpectrum::new(2.0).unwrap()),
            None,
            falloff,
            30.0,
            20.0,
        )
    }

    #[test]
    fn mitsuba_falloff_is_linear_in_the_angle() {
        let light = spot(SpotFalloff::MitsubaLinearAngle);
        assert_eq!(light.falloff_factor(1.0), 1.0);
        assert_eq!(light.falloff_factor(19.9f32.to_radians().cos()), 1.0);
        for degrees in [21.0f32, 25.0, 29.0] {
            let expected = (30.0 - degrees) / 10.0;
            let got = light.falloff_factor(degrees.to_radians().cos());
            assert!(
                (got - expected).abs() < 1e-4,
                "{degrees}: {got} vs {expected}"
            );
        }
        assert_eq!(light.falloff_factor(30.1f32.to_radians().cos()), 0.0);
        assert_eq!(light.falloff_factor(-1.0), 0.0);
    }

    #[test]
    fn pbrt_falloff_is_a_smoothstep_in_the_cosine() {
        let light = spot(SpotFalloff::PbrtSmoothstep);
        let (cos_end, cos_start) = (30f32.to_radians().cos(), 20f32.to_radians().cos());
        assert_eq!(light.falloff_factor(cos_start + 1e-4), 1.0);
        assert_eq!(light.falloff_factor(cos_end - 1e-4), 0.0);
        let middle = 0.5 * (cos_end + cos_start);
        assert!((light.falloff_factor(middle) - 0.5).abs() < 1e-4);
        let quarter = cos_end + 0.25 * (cos_start - cos_end);
        assert!((light.falloff_factor(quarter) - 0.15625).abs() < 1e-3);
        assert_eq!(smoothstep(0.5, 0.5, 0.4), 0.0);
        assert_eq!(smoothstep(0.5, 0.5, 0.5), 1.0);
    }

    /// The closed-form solid angles against a midpoint rule in θ.
    #[test]
    fn profile_integrals_match_quadrature() {
        for falloff in [SpotFalloff::MitsubaLinearAngle, SpotFalloff::PbrtSmoothstep] {
            let light = spot(falloff);
            let steps = 200_000;
            let quadrature: f64 = (0..steps)
                .map(|i| {
                    let theta = (i as f64 + 0.5) / steps as f64 * std::f64::consts::PI;
                    light.falloff_factor(theta.cos() as f32) as f64
                        * theta.sin()
                        * std::f64::consts::PI
                        / steps as f64
                })
                .sum::<f64>()
                * std::f64::consts::TAU;
            let closed = light.profile_solid_angle() as f64;
            assert!((quadrature - closed).abs() < 1e-4 * closed, "{falloff:?}");
        }
        // A hard-edged cone is the cone's solid angle.
        let hard = SpotLight::new(
            Affine3A::IDENTITY,
            Spectrum::Constant(ConstantSpectrum::new(1.0).unwrap()),
            None,
            SpotFalloff::MitsubaLinearAngle,
            40.0,
            40.0,
        );
        let cone = TAU * (1.0 - 40f32.to_radians().cos());
        assert!((hard.profile_solid_angle() - cone).abs() < 1e-5);
    }

    #[test]
    fn intensity_follows_the_frame() {
        // Pointing along +x.
        let to_world = Affine3A::from_rotation_y(std::f32::consts::FRAC_PI_2) * Affine3A::IDENTITY;
        let light = SpotLight::new(
            Affine3A::from_translation(Vec3::new(1.0, 2.0, 3.0)) * to_world,
            Spectrum::Constant(ConstantSpectrum::new(2.0).unwrap()),
            None,
            SpotFalloff::MitsubaLinearAngle,
            30.0,
            20.0,
        );
        assert_eq!(light.position, Vec3::new(1.0, 2.0, 3.0));
        let wavelengths = SampledWavelengths::sample_visible(0.5);
        assert!((light.intensity_towards(Vec3::X, &wavelengths)[0] - 2.0).abs() < 1e-5);
        assert!(light.intensity_towards(Vec3::Z, &wavelengths).is_black());
        let oblique = Vec3::new(25f32.to_radians().cos(), 25f32.to_radians().sin(), 0.0);
        assert!((light.intensity_towards(oblique, &wavelengths)[0] - 1.0).abs() < 1e-3);
    }
}
