//! Shadow rays: the segment from a vertex to a light sample, and its
//! transmittance through homogeneous media and the null lobes of thin
//! sheets and masks (Mitsuba 3's `volpath`; pbrt-v4's `VolPathIntegrator`
//! estimates the same transmittance by ratio tracking, which is exact here
//! since the media are homogeneous).

use crate::geometry::{Ray, SurfaceHit, offset_ray_origin, spawn_ray, spawn_ray_to_point};
use crate::integrators::TraceCounters;
use crate::integrators::path_space::{MAX_INTERFACE_CROSSINGS, null_transmission, oriented_hit};
use crate::light::LightSample;
use crate::medium::medium_after;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// The shadow ray of a light sample and its extent: from a surface hit
/// offset towards the light, or from a medium point.
pub(crate) fn shadow_ray(
    reference: Vec3,
    hit: Option<&SurfaceHit>,
    sample: &LightSample,
) -> Option<(Ray, f32)> {
    match hit {
        Some(hit) if sample.is_infinite => Some((spawn_ray(hit, sample.wi), f32::INFINITY)),
        Some(hit) => spawn_ray_to_point(hit, sample.point, sample.normal),
        None if sample.is_infinite => Some((Ray::new(reference, sample.wi), f32::INFINITY)),
        None => {
            let target = if sample.normal == Vec3::ZERO {
                sample.point
            } else {
                offset_ray_origin(sample.point, sample.normal, reference - sample.point)
            };
            let offset = target - reference;
            let distance = offset.length();
            if distance <= 0.0 || !distance.is_finite() {
                return None;
            }
            Some((
                Ray::new(reference, offset / distance),
                distance * (1.0 - crate::geometry::SHADOW_EPSILON),
            ))
        }
    }
}

/// The transmittance along a shadow ray of extent `t_max` starting in
/// `medium`: the product of exp(−σt d) over the pieces between
/// index-matched boundaries and the weights of the null lobes of surfaces
/// that have one (thin sheets, masks), zero if any other surface blocks it.
/// For walks with null crossings
/// ([`crate::integrators::path_space::WalkSettings::null_crossings`]).
pub(crate) fn shadow_transmittance(
    scene: &Scene,
    ray: Ray,
    t_max: f32,
    medium: Option<u32>,
    wavelengths: &SampledWavelengths,
    counters: &mut TraceCounters,
) -> SampledSpectrum {
    shadow_transmittance_with(scene, ray, t_max, medium, true, wavelengths, counters)
}

/// [`shadow_transmittance`], with surfaces that have a null lobe passed
/// with its weight only when `null_crossings` (the walk's setting): a walk
/// that makes such a surface a specular vertex reaches the light behind it
/// by sampling that vertex, so its shadow rays must stop there, or the
/// light through the sheet would be counted twice.
pub(crate) fn shadow_transmittance_with(
    scene: &Scene,
    mut ray: Ray,
    mut t_max: f32,
    mut medium: Option<u32>,
    null_crossings: bool,
    wavelengths: &SampledWavelengths,
    counters: &mut TraceCounters,
) -> SampledSpectrum {
    let mut result = SampledSpectrum::splat(1.0);
    for _ in 0..MAX_INTERFACE_CROSSINGS {
        counters.shadow_rays += 1;
        let hit = scene.geometry.intersect(&ray, t_max);
        if let Some(medium_index) = medium {
            let distance = hit.map_or(t_max, |hit| hit.t);
            result *= scene.media[medium_index as usize].transmittance(distance, wavelengths);
            if result.is_black() {
                return result;
            }
        }
        let Some(raw_hit) = hit else {
            return result;
        };
        let info = &scene.shapes[raw_hit.shape_index as usize];
        let oriented = oriented_hit(scene, &raw_hit);
        if !info.is_interface {
            // A surface with a null lobe lets the shadow ray through with
            // its weight (Mitsuba 3's `eval_null_transmission`).
            if !null_crossings {
                return SampledSpectrum::zero();
            }
            let Some(material) = &info.material else {
                return SampledSpectrum::zero();
            };
            let bsdf = material.surface_bsdf_at(&oriented, wavelengths);
            let weight = null_transmission(&bsdf, -ray.direction);
            if weight <= 0.0 {
                return SampledSpectrum::zero();
            }
            result *= weight;
        }
        medium = medium_after(
            info.medium_interface.as_ref(),
            oriented.geometric_normal,
            ray.direction,
            medium,
        );
        let next = spawn_ray(&raw_hit, ray.direction);
        t_max -= (next.origin - ray.origin).dot(ray.direction);
        if t_max <= 0.0 {
            return result;
        }
        ray = next;
    }
    SampledSpectrum::zero()
}
