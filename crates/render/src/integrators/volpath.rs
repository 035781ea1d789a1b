//! Volumetric path tracing: the surface path tracer of [`super::path`]
//! extended to homogeneous participating media, with next-event estimation
//! through media (transmittance along shadow rays that pass index-matched
//! boundaries) and multiple importance sampling of light sampling against
//! BSDF and phase-function sampling. The model is pbrt-v4's
//! `VolPathIntegrator` (Pharr, Jakob & Humphreys, *Physically Based
//! Rendering*, 4th ed., §14.2.2 "Improving the Sampling Techniques", where
//! the `VolPathIntegrator` and its spectral MIS for chromatic media are
//! introduced):
//!
//! # Spectral MIS over the hero wavelengths
//!
//! Free-flight distances are sampled with the hero wavelength's extinction
//! σt₀, p₀(t) = σt₀ exp(−σt₀ t), although σt differs between the four
//! wavelengths of a path in a chromatic medium. As in pbrt-v4, each
//! wavelength's estimate is weighted by the one-sample balance heuristic
//! over the four wavelengths' distance densities: the path keeps its
//! throughput `beta` = f / p₀ and the *rescaled path probabilities* `r_u`
//! (pᵢ / p₀ per wavelength i, multiplied along the path), and a
//! contribution is `beta · L / mean(r_u)`, i.e. f / mean over i of pᵢ.
//! Light sampling joins the same balance heuristic with `r_l` (the rescaled
//! probability of having reached the vertex by light sampling): emission
//! found by BSDF or phase sampling is weighted by 1 / mean(r_u + r_l), next
//! events by 1 / mean(r_l + r_u) with the roles swapped. The MIS heuristic
//! is therefore always the balance heuristic (`--mis` applies to `path`
//! only); without media `r_u` stays 1 and this is the usual two-technique
//! balance heuristic.
//!
//! # Homogeneous media
//!
//! Since the media are homogeneous, the majorant equals σt and there are no
//! null collisions (pbrt-v4's delta tracking reduces to sampling the
//! exponential distance), and the transmittance of shadow rays is the closed
//! form exp(−σt d) per wavelength rather than a ratio-tracking estimate.
//! Absorption is not sampled as an event (pbrt-v4 chooses absorption,
//! scattering or null with one more number): a scattering vertex multiplies
//! the throughput by σs / σt instead, as Mitsuba 3's `volpath` does, so a
//! vertex uses no dimension beyond its block; Russian roulette ends paths of
//! low throughput. The media do not emit.
//!
//! # Dimensions
//!
//! Each scattering vertex k (a surface or a medium interaction) owns block k
//! of [`layout`]. The free-flight distance of the segment that ends at
//! vertex k is drawn from `FREE_FLIGHT` of block k as an optical depth
//! τ = −ln(1 − u) at the hero wavelength, once per segment: the segment is
//! marched through the homogeneous pieces between index-matched boundaries,
//! each using up σt₀ times its length of τ, and the vertex is where τ runs
//! out (exact, since the optical depth is additive). Crossing a `null`
//! boundary therefore uses no dimension and does not count as a vertex or
//! towards the depth. Phase-function sampling uses `SCATTER_DIRECTION`, next
//! events `LIGHT_SELECTION` and `LIGHT_POSITION`, Russian roulette
//! `RUSSIAN_ROULETTE` of the vertex's block, as surface vertices do.
//!
//! Depth follows Mitsuba's convention as in [`super::path`]: medium
//! interactions count like surface ones.
//!
//! # Null lobes
//!
//! Mitsuba 3's `volpath` has "special support for index-matched transmission
//! events": a thin dielectric's straight transmission and a mask's
//! pass-through are `Null` lobes there (its documentation of `volpath`, and
//! `thindielectric`'s component flags as its Python API reports them). Such
//! a crossing is chosen by BSDF sampling at the surface as usual, but it is
//! no path vertex: it does not count towards the depth, and the MIS state
//! (`r_l`, the previous vertex, whether it was a delta) stays that of the
//! last real vertex; shadow rays pass such surfaces with the lobe's weight
//! (1 − R' of the sheet, 1 − α of a mask). Counting the crossings as depth
//! would end paths in a medium enclosed by thin sheets earlier than Mitsuba
//! (−11 % to −13 % on its `test_homo_*` scenes with `thindielectric` at
//! depth 16). Every vertex, null or not, still takes its own dimension
//! block, so the block index runs ahead of the depth.

use super::driver::{
    CameraPathStart, PixelSampleEstimator, PixelSampleIndex, UnitOutput, render_pixel_samples,
};
use super::path::{PathSettings, oriented_hit};
use super::{Integrator, IntegratorRender, RenderError, RunControl, TraceCounters};
use crate::geometry::{Ray, SurfaceHit, offset_ray_origin, spawn_ray, spawn_ray_to_point};
use crate::light::LightSample;
use crate::material::{BsdfModel, BsdfSample, SurfaceBsdf};
use crate::medium::{medium_after, transmittance};
use crate::sampler::{DynSource, PixelSampler, SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, to_linear_srgb};
use glam::Vec3;

/// Shadow rays stop after this many index-matched boundaries (a guard
/// against rays stuck in coincident surfaces).
const MAX_INTERFACE_CROSSINGS: u32 = 256;

/// What the free flight of one path segment ended at.
enum SegmentEnd {
    /// A scattering event in a medium at `point`.
    Medium { point: Vec3 },
    /// A surface that is not an index-matched boundary.
    Surface { raw_hit: SurfaceHit },
    /// The ray left the scene.
    Escaped,
    /// The throughput became zero.
    Dead,
}

/// The state of a camera path between vertices.
struct PathState {
    radiance: SampledSpectrum,
    /// Throughput divided by the hero wavelength's sampling densities.
    beta: SampledSpectrum,
    /// Rescaled unidirectional path probabilities per wavelength.
    r_u: SampledSpectrum,
    /// Rescaled light-sampling path probabilities (without the light's
    /// own density, multiplied in when an emitter is found).
    r_l: SampledSpectrum,
    /// The last vertex's direction was a delta (or there is none yet).
    specular_bounce: bool,
    /// Where the light density of found emission is measured from.
    previous_point: Vec3,
    /// The medium the path is in.
    medium: Option<u32>,
}

impl PathState {
    /// Adds emission `emitted` found after the last vertex, balance-weighted
    /// against next-event estimation with light density `light_pdf` (the
    /// selection probability included; ignored after a delta bounce).
    fn add_emission(&mut self, emitted: SampledSpectrum, light_pdf: f32) {
        if emitted.is_black() {
            return;
        }
        let denominator = if self.specular_bounce {
            self.r_u.average()
        } else {
            (self.r_u + self.r_l * light_pdf).average()
        };
        if denominator > 0.0 {
            self.radiance += self.beta * emitted / denominator;
        }
    }
}

/// The volumetric path tracer as an [`Integrator`], run by the tile driver.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VolPathIntegrator {
    settings: PathSettings,
}

impl VolPathIntegrator {
    /// The volumetric path tracer with `settings`.
    pub fn new(settings: PathSettings) -> Self {
        Self { settings }
    }
}

impl Integrator for VolPathIntegrator {
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError> {
        let estimator = VolPathEstimator {
            scene,
            settings: &self.settings,
        };
        render_pixel_samples(&estimator, scene, run).map(IntegratorRender::from_driver)
    }
}

/// One volumetric camera path per pixel sample, added to its pixel.
struct VolPathEstimator<'a> {
    scene: &'a Scene,
    settings: &'a PathSettings,
}

impl PixelSampleEstimator for VolPathEstimator<'_> {
    type Unit = ();
    type Total = ();

    fn new_total(&self, _resolution: [usize; 2]) -> Result<(), RenderError> {
        Ok(())
    }

    fn new_unit(&self) {}

    fn merge_unit(&self, _total: &mut (), _unit: (), _kept: bool) {}

    fn estimate<S: PixelSampler + ?Sized>(
        &self,
        _unit: &mut (),
        sample: PixelSampleIndex,
        sampler: &mut S,
        output: &mut UnitOutput,
    ) {
        let start = CameraPathStart::new(self.scene, sample.pixel, sampler);
        let mut wavelengths = start.wavelengths;
        let radiance = radiance(
            self.scene,
            self.settings,
            start.ray,
            &mut wavelengths,
            &mut DynSource(sampler),
            &mut output.counters,
        );
        output.add_camera_sample(
            [sample.pixel.0 as usize, sample.pixel.1 as usize],
            to_linear_srgb(&radiance, &wavelengths),
            start.position.weight,
        );
    }
}

/// Estimates the radiance along the camera ray `ray` for `wavelengths`,
/// starting in the scene's camera medium.
pub fn radiance(
    scene: &Scene,
    settings: &PathSettings,
    ray: Ray,
    wavelengths: &mut SampledWavelengths,
    sampler: &mut dyn SampleSource,
    counters: &mut TraceCounters,
) -> SampledSpectrum {
    let mut state = PathState {
        radiance: SampledSpectrum::zero(),
        beta: SampledSpectrum::splat(1.0),
        r_u: SampledSpectrum::splat(1.0),
        r_l: SampledSpectrum::splat(1.0),
        specular_bounce: true,
        previous_point: ray.origin,
        medium: scene.camera_medium,
    };
    let mut ray = ray;
    let mut eta_scale = 1.0f32;
    // Mitsuba's depth (scattering events; null crossings do not count) and
    // the dimension block of the current vertex (every vertex, null or not).
    let mut depth = 0u32;
    let mut block = 0u32;
    loop {
        let end = free_flight(
            scene,
            &mut state,
            &mut ray,
            block,
            wavelengths,
            sampler,
            counters,
        );
        let wo = -ray.direction;
        match end {
            SegmentEnd::Dead => break,
            SegmentEnd::Escaped => {
                add_environment(scene, &mut state, ray.direction, wavelengths);
                break;
            }
            SegmentEnd::Medium { point } => {
                if depth + 2 > settings.max_depth {
                    break;
                }
                let medium =
                    &scene.media[state.medium.expect("scattering happens in a medium") as usize];
                let phase = medium.phase;
                let scatter = |wi: Vec3| {
                    let value = phase.evaluate(wo, wi);
                    (SampledSpectrum::splat(value), value)
                };
                let next_event = sample_light(
                    scene,
                    point,
                    None,
                    state.medium,
                    &scatter,
                    state.r_u,
                    block,
                    wavelengths,
                    sampler,
                    counters,
                );
                state.radiance += state.beta * next_event;
                let sample = phase.sample(
                    wo,
                    sampler.get_2d(layout::vertex(block as usize, layout::SCATTER_DIRECTION)),
                );
                if sample.pdf <= 0.0 {
                    break;
                }
                state.beta *= sample.value / sample.pdf;
                state.r_l = state.r_u / sample.pdf;
                state.specular_bounce = false;
                state.previous_point = point;
                ray = Ray::with_time(point, sample.wi, ray.time);
            }
            SegmentEnd::Surface { raw_hit } => {
                let hit = oriented_hit(scene, &raw_hit);
                let info = &scene.shapes[hit.shape_index as usize];
                if let Some(light_index) = info.light {
                    let emitted = scene.lights[light_index as usize].emitted_radiance(
                        raw_hit.geometric_normal,
                        raw_hit.uv,
                        wo,
                        wavelengths,
                    );
                    let light_pdf = light_density(
                        scene,
                        light_index,
                        &state,
                        raw_hit.point,
                        raw_hit.geometric_normal,
                    );
                    state.add_emission(emitted, light_pdf);
                }
                let Some(material) = &info.material else {
                    break;
                };
                let bsdf = material.surface_bsdf_at(&hit, wavelengths);
                let u_component =
                    sampler.get(layout::vertex(block as usize, layout::SCATTER_COMPONENT));
                if null_transmission(&bsdf, wo) > 0.0 {
                    // A surface with a null lobe (a thin dielectric's
                    // transmission, a mask's pass-through): choose it with
                    // its probability first; it is no vertex and no depth.
                    let u =
                        sampler.get_2d(layout::vertex(block as usize, layout::SCATTER_DIRECTION));
                    let mut probe = *wavelengths;
                    if let Some(sample) = bsdf.sample(wo, u_component, u, &mut probe)
                        && is_null_sample(&bsdf, u_component, &sample)
                    {
                        state.medium = medium_after(
                            info.medium_interface.as_ref(),
                            hit.geometric_normal,
                            -wo,
                            state.medium,
                        );
                        ray = spawn_ray(&raw_hit, -wo);
                        block += 1;
                        continue;
                    }
                }
                if depth + 2 > settings.max_depth {
                    break;
                }
                let flags = bsdf.flags();
                let reference = offset_ray_origin(hit.point, hit.geometric_normal, wo);
                if flags.is_non_specular() {
                    let normal = bsdf.frame.normal();
                    let scatter = |wi: Vec3| {
                        (
                            bsdf.evaluate(wo, wi, wavelengths) * wi.dot(normal).abs(),
                            bsdf.pdf(wo, wi),
                        )
                    };
                    let next_event = sample_light(
                        scene,
                        reference,
                        Some(&hit),
                        state.medium,
                        &scatter,
                        state.r_u,
                        block,
                        wavelengths,
                        sampler,
                        counters,
                    );
                    state.radiance += state.beta * next_event;
                }
                let u = sampler.get_2d(layout::vertex(block as usize, layout::SCATTER_DIRECTION));
                let Some(sample) = bsdf.sample(wo, u_component, u, wavelengths) else {
                    break;
                };
                if sample.pdf <= 0.0 || sample.value.is_black() {
                    break;
                }
                let cosine = sample.wi.dot(bsdf.frame.normal()).abs();
                state.beta *= sample.value * (cosine / sample.pdf);
                let pdf_for_mis = if sample.pdf_is_proportional {
                    bsdf.pdf(wo, sample.wi)
                } else {
                    sample.pdf
                };
                state.r_l = state.r_u / pdf_for_mis;
                state.specular_bounce = sample.is_specular();
                state.previous_point = reference;
                if sample.is_transmission() {
                    eta_scale *= sample.eta * sample.eta;
                }
                state.medium = medium_after(
                    info.medium_interface.as_ref(),
                    hit.geometric_normal,
                    sample.wi,
                    state.medium,
                );
                ray = spawn_ray(&raw_hit, sample.wi);
            }
        }

        // Russian roulette on the MIS-rescaled throughput without the
        // refraction scaling (pbrt-v4's rrBeta).
        let r_u_mean = state.r_u.average();
        if r_u_mean <= 0.0 {
            break;
        }
        let roulette_throughput = (state.beta * (eta_scale / r_u_mean)).max_component();
        match crate::integrators::path::russian_roulette(
            roulette_throughput,
            depth,
            settings.russian_roulette_depth,
            || sampler.get(layout::vertex(block as usize, layout::RUSSIAN_ROULETTE)),
        ) {
            Some(survival) => state.beta /= survival,
            None => break,
        }
        if state.beta.is_black() {
            break;
        }
        depth += 1;
        block += 1;
    }
    state.radiance
}

/// Follows `ray` from the last vertex (or the camera) through media and
/// index-matched boundaries to where the segment ends, drawing the optical
/// depth from `FREE_FLIGHT` of block `block` the first time a medium is met.
/// Updates `beta`, `r_u`, `r_l` with each piece's transmittance and
/// densities, the medium, and adds emission of boundaries passed.
#[allow(clippy::too_many_arguments)]
fn free_flight(
    scene: &Scene,
    state: &mut PathState,
    ray: &mut Ray,
    block: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut dyn SampleSource,
    counters: &mut TraceCounters,
) -> SegmentEnd {
    let mut optical_depth: Option<f32> = None;
    for _ in 0..MAX_INTERFACE_CROSSINGS {
        counters.closest_hit_rays += 1;
        let hit = scene.geometry.intersect(ray, f32::INFINITY);
        let distance = hit.map_or(f32::INFINITY, |hit| hit.t);
        if let Some(medium_index) = state.medium {
            let coefficients = scene.media[medium_index as usize].coefficients(wavelengths);
            let sigma_t = coefficients.sigma_t();
            let hero_sigma_t = sigma_t[0];
            let tau = *optical_depth.get_or_insert_with(|| {
                let u = sampler.get(layout::vertex(block as usize, layout::FREE_FLIGHT));
                -(1.0 - u).ln()
            });
            if hero_sigma_t > 0.0 && tau < hero_sigma_t * distance {
                // Scattering inside this piece: p₀(t) = σt₀ T₀(t).
                let t = tau / hero_sigma_t;
                let piece = transmittance(sigma_t, t);
                let hero_pdf = piece[0] * hero_sigma_t;
                if hero_pdf <= 0.0 {
                    return SegmentEnd::Dead;
                }
                state.beta *= piece * coefficients.sigma_s / hero_pdf;
                let ratio = piece * sigma_t / hero_pdf;
                state.r_u *= ratio;
                state.r_l *= ratio;
                if state.beta.is_black() {
                    return SegmentEnd::Dead;
                }
                return SegmentEnd::Medium { point: ray.at(t) };
            }
            // Passing through the whole piece: probability T₀(distance).
            optical_depth = Some(tau - hero_sigma_t * distance);
            let piece = transmittance(sigma_t, distance);
            if piece[0] <= 0.0 {
                return SegmentEnd::Dead;
            }
            let ratio = piece / piece[0];
            state.beta *= ratio;
            state.r_u *= ratio;
            state.r_l *= ratio;
        }
        let Some(raw_hit) = hit else {
            return SegmentEnd::Escaped;
        };
        let info = &scene.shapes[raw_hit.shape_index as usize];
        if !info.is_interface {
            return SegmentEnd::Surface { raw_hit };
        }
        // An index-matched boundary: emission it may carry, then straight on.
        if let Some(light_index) = info.light {
            let emitted = scene.lights[light_index as usize].emitted_radiance(
                raw_hit.geometric_normal,
                raw_hit.uv,
                -ray.direction,
                wavelengths,
            );
            let light_pdf = light_density(
                scene,
                light_index,
                state,
                raw_hit.point,
                raw_hit.geometric_normal,
            );
            state.add_emission(emitted, light_pdf);
        }
        let hit = oriented_hit(scene, &raw_hit);
        state.medium = medium_after(
            info.medium_interface.as_ref(),
            hit.geometric_normal,
            ray.direction,
            state.medium,
        );
        *ray = spawn_ray(&raw_hit, ray.direction);
    }
    SegmentEnd::Dead
}

/// The density (selection included) with which next-event estimation from
/// the path's previous vertex would have sampled `point` on light
/// `light_index`.
fn light_density(
    scene: &Scene,
    light_index: u32,
    state: &PathState,
    point: Vec3,
    normal: Vec3,
) -> f32 {
    if state.specular_bounce {
        return 0.0;
    }
    let light = &scene.lights[light_index as usize];
    scene.light_sampler.probability(light_index as usize)
        * light.pdf_incident(&scene.geometry, state.previous_point, point, normal)
}

/// Radiance of the lights at infinity reached by an escaping ray.
fn add_environment(
    scene: &Scene,
    state: &mut PathState,
    direction: Vec3,
    wavelengths: &SampledWavelengths,
) {
    for &index in &scene.environment_lights {
        let emitted = scene.lights[index as usize].environment_radiance(direction, wavelengths);
        let light_pdf = light_density(
            scene,
            index,
            state,
            state.previous_point + direction,
            Vec3::ZERO,
        );
        state.add_emission(emitted, light_pdf);
    }
}

/// Next-event estimation from `reference` (a medium point, or a surface
/// point offset off `hit`): one light sample, its transmittance through the
/// media and index-matched boundaries to the light, balance-weighted over
/// wavelengths and against `scatter`'s sampling. `scatter(wi)` gives the
/// scattering value (BSDF times cosine, or the phase function) and its
/// sampling density; `r_u` is the path's rescaled probability at the vertex.
/// The result still has to be multiplied by the path throughput.
#[allow(clippy::too_many_arguments)]
fn sample_light(
    scene: &Scene,
    reference: Vec3,
    hit: Option<&SurfaceHit>,
    medium: Option<u32>,
    scatter: &dyn Fn(Vec3) -> (SampledSpectrum, f32),
    r_u: SampledSpectrum,
    depth: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut dyn SampleSource,
    counters: &mut TraceCounters,
) -> SampledSpectrum {
    let Some(super::path::VertexLightSample {
        selection_probability,
        sample,
        ..
    }) = super::path::sample_vertex_light(scene, reference, depth, wavelengths, sampler)
    else {
        return SampledSpectrum::zero();
    };
    let (value, scatter_pdf) = scatter(sample.wi);
    if value.is_black() {
        return SampledSpectrum::zero();
    }
    let (ray, t_max) = match shadow_ray(reference, hit, &sample) {
        Some(segment) => segment,
        None => return SampledSpectrum::zero(),
    };
    // The medium the shadow ray starts in: at a surface, the side `wi` leaves to.
    let start_medium = match hit {
        Some(hit) => {
            let info = &scene.shapes[hit.shape_index as usize];
            medium_after(
                info.medium_interface.as_ref(),
                hit.geometric_normal,
                sample.wi,
                medium,
            )
        }
        None => medium,
    };
    let transmittance =
        shadow_transmittance(scene, ray, t_max, start_medium, wavelengths, counters);
    if transmittance.is_black() {
        return SampledSpectrum::zero();
    }
    let light_pdf = selection_probability * sample.pdf;
    let r_l = r_u * light_pdf;
    let denominator = if sample.is_delta {
        r_l.average()
    } else {
        (r_l + r_u * scatter_pdf).average()
    };
    if denominator <= 0.0 {
        return SampledSpectrum::zero();
    }
    value * transmittance * sample.radiance / denominator
}

/// The weight with which `bsdf` lets light arriving from `wo` pass straight
/// through as a *null* event, not a scattering one: Mitsuba 3 flags a thin
/// dielectric's transmission (weight 1 − R', see [`crate::material::ThinDielectricBsdf`]) and
/// a mask's pass-through (1 − α) `Null`, so that its `volpath` lets shadow
/// rays through them with this weight and does not count crossing them as
/// a bounce. Their expectation is the same as that of a specular vertex;
/// counting them in the depth would end paths earlier than Mitsuba does.
fn null_transmission(bsdf: &SurfaceBsdf, wo: Vec3) -> f32 {
    let opacity = bsdf.adapter.opacity.clamp(0.0, 1.0);
    let thin = match (bsdf.bsdf.model(), bsdf.bsdf.back_model()) {
        (BsdfModel::ThinDielectric(thin), None | Some(BsdfModel::ThinDielectric(_))) => {
            let cosine = wo.dot(bsdf.frame.normal());
            if cosine == 0.0 {
                0.0
            } else {
                let back = bsdf.bsdf.back_model();
                let sheet = match back {
                    Some(BsdfModel::ThinDielectric(back)) if cosine < 0.0 => back,
                    _ => thin,
                };
                1.0 - sheet.reflectance(cosine)
            }
        }
        _ => 0.0,
    };
    (1.0 - opacity) + opacity * thin
}

/// Whether `sample` (drawn with component sample `u_component`) took the
/// null lobe of [`null_transmission`]: a mask's pass-through, or a thin
/// dielectric's straight transmission.
fn is_null_sample(bsdf: &SurfaceBsdf, u_component: f32, sample: &BsdfSample) -> bool {
    if bsdf.adapter.nested_component_sample(u_component).is_none() {
        return true;
    }
    matches!(bsdf.bsdf.model(), BsdfModel::ThinDielectric(_)) && sample.is_transmission()
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
/// index-matched boundaries, zero if any other surface blocks it.
pub(crate) fn shadow_transmittance(
    scene: &Scene,
    mut ray: Ray,
    mut t_max: f32,
    mut medium: Option<u32>,
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
