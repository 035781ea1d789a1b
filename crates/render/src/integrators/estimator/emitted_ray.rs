//! The start of a light subpath (light tracing, BDPT): a light chosen by
//! the light sampler, a ray sampled leaving it, and the subpath's first
//! throughput β₁ = Le |cos θ| / (p_choice p_position p_direction) (Veach
//! 1997 §10.2; pbrt-v4's `LightPathIntegrator` and `BDPTIntegrator`).

use crate::geometry::OffsetPoint;
use crate::light::EmissionSample;
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// A ray leaving a light, with the light's choice.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EmittedRay {
    /// The light.
    pub light_index: usize,
    /// The probability of choosing it.
    pub choice_probability: f32,
    /// The ray and its densities.
    pub emission: EmissionSample,
    /// The ray leaves a light's surface (an area light): its cosine counts,
    /// and its origin is offset off the surface.
    pub on_surface: bool,
}

/// Chooses a light with the number of [`layout::LIGHT_CHOICE`] and samples
/// a ray leaving it with those of [`layout::LIGHT_EMISSION_POSITION`] and
/// [`layout::LIGHT_EMISSION_DIRECTION`]; `None` where nothing is chosen or
/// nothing is emitted.
pub(crate) fn sample_emitted_ray<S: SampleSource + ?Sized>(
    scene: &Scene,
    sampler: &mut S,
    wavelengths: &SampledWavelengths,
) -> Option<EmittedRay> {
    let (light_index, choice_probability, u_primitive) = scene
        .light_sampler
        .sample(sampler.get(layout::LIGHT_CHOICE))?;
    let light = &scene.lights[light_index];
    let emission = light.sample_emission(
        &scene.geometry,
        u_primitive,
        sampler.get_2d(layout::LIGHT_EMISSION_POSITION),
        sampler.get_2d(layout::LIGHT_EMISSION_DIRECTION),
        wavelengths,
    )?;
    if emission.radiance.is_black() || choice_probability <= 0.0 {
        return None;
    }
    let on_surface =
        !emission.is_delta_position && !light.is_infinite() && emission.normal != Vec3::ZERO;
    Some(EmittedRay {
        light_index,
        choice_probability,
        emission,
        on_surface,
    })
}

impl EmittedRay {
    /// The first throughput β₁ = Le |cos θ| / (p_choice p_position
    /// p_direction) (delta components report a density and a cosine of 1)
    /// over its largest component, and that component; `None` where it is
    /// zero or not finite. A light subpath carries β relative to its start
    /// and its connections scale it back, so that Russian roulette decides
    /// on the product of the scatterings' f |cos| / p, as from the camera:
    /// on β itself, which carries the emitted power over the densities
    /// (thousands in the Cornell box), the roulette never fired.
    pub(crate) fn scaled_throughput(&self) -> Option<(SampledSpectrum, f32)> {
        let emission = &self.emission;
        let cosine = if self.on_surface {
            emission.normal.dot(emission.direction).abs()
        } else {
            1.0
        };
        let beta = emission.radiance
            * (cosine / (self.choice_probability * emission.pdf_position * emission.pdf_direction));
        let scale = beta.max_component();
        (scale > 0.0 && scale.is_finite()).then(|| (beta / scale, scale))
    }

    /// The ray's origin: on a light's surface, offset off it towards the
    /// direction.
    pub(crate) fn ray_origin(&self) -> Vec3 {
        let emission = &self.emission;
        if self.on_surface {
            OffsetPoint::new(emission.origin, emission.normal, emission.direction)
                .towards(emission.direction)
        } else {
            emission.origin
        }
    }
}
