//! Shadow rays: the segment from a vertex to a light sample, and its
//! transmittance through homogeneous media and the null lobes of thin
//! sheets and masks (Mitsuba 3's `volpath`; pbrt-v4's `VolPathIntegrator`
//! estimates the same transmittance by ratio tracking, which is exact here
//! since the media are homogeneous).

use crate::geometry::{
    Ray, SurfaceHit, occlusion_segment_to_point, offset_ray_origin, spawn_ray, spawn_ray_to_point,
};
use crate::integrators::TraceCounters;
use crate::integrators::path_space::{MAX_INTERFACE_CROSSINGS, null_transmission, oriented_hit};
use crate::light::LightSample;
use crate::medium::medium_after;
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;

/// Where a shadow ray (or a connection's segment) ends.
#[derive(Debug, Clone, Copy)]
pub(crate) enum ShadowTarget {
    /// At a point with its unit normal (zero for a point without a
    /// surface): the segment stops short of it, offset off its surface.
    Point(Vec3, Vec3),
    /// At infinity, in a unit direction.
    Infinity(Vec3),
}

impl ShadowTarget {
    /// The end of a light sample's shadow ray.
    #[inline(always)]
    pub(crate) fn of_sample(sample: &LightSample) -> Self {
        if sample.is_infinite {
            ShadowTarget::Infinity(sample.wi)
        } else {
            ShadowTarget::Point(sample.point, sample.normal)
        }
    }
}

/// Whether nothing blocks the segment from `origin` (already offset off
/// its surface) at `time` to `target`: one occlusion query, traced along
/// the unnormalised segment
/// ([`crate::geometry::occlusion_segment_to_point`]). The shadow ray of the
/// path tracer and of BDPT's connections without media; the caller counts
/// it.
#[inline(always)]
pub(crate) fn unoccluded(scene: &Scene, origin: Vec3, time: f32, target: ShadowTarget) -> bool {
    match target {
        ShadowTarget::Point(point, normal) => {
            match occlusion_segment_to_point(origin, time, point, normal) {
                Some((ray, t_max)) => !scene.geometry.occluded(&ray, t_max),
                None => false,
            }
        }
        ShadowTarget::Infinity(direction) => {
            let ray = Ray::with_time(origin, direction, time);
            !scene.geometry.occluded(&ray, f32::INFINITY)
        }
    }
}

/// Whether nothing blocks the light `sample` from the surface `hit`: a
/// ray spawned off the hit (LQMC's records keep hits, not offset points;
/// the [`shadow_ray`] of a surface), one occlusion query. It asks what
/// [`unoccluded`] asks, with a unit direction, which rounds differently;
/// LQMC's seeds and value walks keep it so that their images stay as they
/// were measured. The caller counts it.
#[inline(always)]
pub(crate) fn light_visible_from_hit(
    scene: &Scene,
    hit: &SurfaceHit,
    sample: &LightSample,
) -> bool {
    if sample.is_infinite {
        let ray = spawn_ray(hit, sample.wi);
        !scene.geometry.occluded(&ray, f32::INFINITY)
    } else {
        match spawn_ray_to_point(hit, sample.point, sample.normal) {
            Some((ray, t_max)) => !scene.geometry.occluded(&ray, t_max),
            None => false,
        }
    }
}

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
