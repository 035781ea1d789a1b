//! Next-event estimation (Veach 1997 §9.2; pbrt-v4's `SampleLd`): at a
//! path vertex, choose a light with the light sampler, sample a point on it
//! as seen from the vertex, and estimate the light arriving from it — the
//! scattering value times the light's radiance, the shadow ray's
//! visibility or transmittance, and the MIS weight against the vertex's
//! own sampling over the light's density.

use super::PathSettings;
use super::shadow::{ShadowTarget, shadow_ray, shadow_transmittance_with, unoccluded};
use crate::geometry::{OffsetPoint, SurfaceHit};
use crate::integrators::path_space::medium_leaving;
use crate::integrators::{MisHeuristic, TraceCounters};
use crate::light::LightSample;
use crate::material::SurfaceBsdf;
use crate::medium::PhaseFunction;
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, Spectrum};
use glam::Vec3;

/// An area light's radiance at one path's wavelengths, kept for the rest of
/// the path: every next-event sample and every emitter hit of the path needs
/// it, and evaluating an RGB illuminant spectrum at four wavelengths cost
/// more than the rest of a light sample. One entry (scenes usually have one
/// area light or a few); a miss evaluates and replaces it. The wavelengths
/// never change along a path (terminating the secondary ones changes their
/// densities, not the wavelengths), so entries stay valid.
#[derive(Debug, Clone, Copy)]
pub(crate) struct AreaRadianceCache {
    light_index: usize,
    radiance: SampledSpectrum,
}

impl AreaRadianceCache {
    pub(crate) fn new() -> Self {
        Self {
            light_index: usize::MAX,
            radiance: SampledSpectrum::zero(),
        }
    }

    /// The radiance of light `light_index`, whose spectrum is `spectrum`, at
    /// `wavelengths` (the path's).
    #[inline]
    pub(crate) fn radiance(
        &mut self,
        light_index: usize,
        spectrum: &Spectrum,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        if self.light_index != light_index {
            self.light_index = light_index;
            self.radiance = spectrum.sample(wavelengths);
        }
        self.radiance
    }
}

/// A light chosen for next-event estimation at a path vertex and the point
/// sampled on it, with the numbers that made both (LQMC keeps them).
#[derive(Debug, Clone, Copy)]
pub(crate) struct VertexLightSample {
    pub light_index: usize,
    pub selection_probability: f32,
    pub u_primitive: f32,
    pub u_position: [f32; 2],
    pub sample: LightSample,
}

/// Chooses a light and samples it as seen from `reference`, with the light
/// dimensions of vertex `depth`; `None` when nothing is chosen or the
/// sampled radiance is black. Every integrator's next-event estimation
/// starts here.
pub(crate) fn sample_vertex_light(
    scene: &Scene,
    reference: Vec3,
    depth: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut dyn SampleSource,
) -> Option<VertexLightSample> {
    sample_vertex_light_with_cache(
        scene,
        reference,
        depth,
        wavelengths,
        sampler,
        &mut AreaRadianceCache::new(),
    )
}

/// [`sample_vertex_light`] taking area lights' radiance from a path's
/// `area_radiance` cache.
pub(crate) fn sample_vertex_light_with_cache<S: SampleSource + ?Sized>(
    scene: &Scene,
    reference: Vec3,
    depth: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut S,
    area_radiance: &mut AreaRadianceCache,
) -> Option<VertexLightSample> {
    let u_select = sampler.get(layout::vertex(depth as usize, layout::LIGHT_SELECTION));
    let u_position = sampler.get_2d(layout::vertex(depth as usize, layout::LIGHT_POSITION));
    choose_and_sample_light(
        scene,
        reference,
        u_select,
        || u_position,
        wavelengths,
        area_radiance,
    )
}

/// Chooses a light with the number `u_select` (the light sampler's
/// probabilities) and samples a point on it as seen from `reference` with
/// the numbers `u_position` gives (asked only once a light is chosen);
/// `None` when nothing is chosen or the sampled radiance is black. Area
/// lights' radiance comes from `area_radiance`.
#[inline(always)]
pub(crate) fn choose_and_sample_light(
    scene: &Scene,
    reference: Vec3,
    u_select: f32,
    u_position: impl FnOnce() -> [f32; 2],
    wavelengths: &SampledWavelengths,
    area_radiance: &mut AreaRadianceCache,
) -> Option<VertexLightSample> {
    let (light_index, selection_probability, u_primitive) = scene.light_sampler.sample(u_select)?;
    let u_position = u_position();
    let sample = scene.lights[light_index].sample_incident_with_area_radiance(
        &scene.geometry,
        reference,
        u_primitive,
        u_position,
        wavelengths,
        |spectrum| area_radiance.radiance(light_index, spectrum, wavelengths),
    )?;
    if sample.radiance.is_black() {
        return None;
    }
    Some(VertexLightSample {
        light_index,
        selection_probability,
        u_primitive,
        u_position,
        sample,
    })
}

/// What scatters light at a vertex, as next-event estimation evaluates it.
#[derive(Debug, Clone, Copy)]
pub(crate) enum VertexScatter<'a> {
    /// A surface's BSDF.
    Surface(&'a SurfaceBsdf),
    /// A medium's phase function.
    Medium(PhaseFunction),
}

impl VertexScatter<'_> {
    /// The value of scattering from `wo` into `wi` — the BSDF times |cos θ|
    /// with the shading normal, or the phase function — and the density
    /// with which the vertex's own sampling picks `wi`.
    #[inline(always)]
    pub(crate) fn towards(
        &self,
        wo: Vec3,
        wi: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        match self {
            VertexScatter::Surface(bsdf) => {
                let (value, pdf) = bsdf.evaluate_with_pdf(wo, wi, wavelengths);
                (value * wi.dot(bsdf.frame.normal()).abs(), pdf)
            }
            VertexScatter::Medium(phase) => {
                let value = phase.evaluate(wo, wi);
                (SampledSpectrum::splat(value), value)
            }
        }
    }
}

/// One light sample's terms at a vertex, whoever drew it (the path tracers
/// with their numbers, LQMC's value walks from a fixed light point): what
/// the vertex scatters towards the light, and the densities the MIS weights
/// compare. A next event's contribution is `β · scattered · Le · V` (V the
/// visibility or transmittance) times [`Self::weight_over_density`], or,
/// through media, over [`Self::balance_denominator`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct NextEventTerms {
    /// The scattering value towards the light ([`VertexScatter::towards`]).
    pub scattered: SampledSpectrum,
    /// The density with which the vertex's own sampling picks the light's
    /// direction.
    pub scatter_pdf: f32,
    /// The probability of choosing the light.
    pub selection_probability: f32,
    /// The solid-angle density of the light's direction (1 for a delta).
    pub solid_angle_pdf: f32,
    /// A delta light: no other technique makes the path.
    pub is_delta: bool,
}

impl NextEventTerms {
    /// The terms of the light direction `wi` (solid-angle density
    /// `solid_angle_pdf`, a delta when `is_delta`) of a light chosen with
    /// probability `selection_probability`, at a vertex where `scatter`
    /// scatters from `wo`.
    #[inline(always)]
    pub(crate) fn new(
        scatter: VertexScatter<'_>,
        wo: Vec3,
        wi: Vec3,
        wavelengths: &SampledWavelengths,
        selection_probability: f32,
        solid_angle_pdf: f32,
        is_delta: bool,
    ) -> Self {
        let (scattered, scatter_pdf) = scatter.towards(wo, wi, wavelengths);
        Self {
            scattered,
            scatter_pdf,
            selection_probability,
            solid_angle_pdf,
            is_delta,
        }
    }

    /// The terms of `light`, drawn by [`sample_vertex_light`].
    #[inline(always)]
    pub(crate) fn of_sample(
        scatter: VertexScatter<'_>,
        wo: Vec3,
        light: &VertexLightSample,
        wavelengths: &SampledWavelengths,
    ) -> Self {
        Self::new(
            scatter,
            wo,
            light.sample.wi,
            wavelengths,
            light.selection_probability,
            light.sample.pdf,
            light.sample.is_delta,
        )
    }

    /// The light technique's density: selection times direction.
    #[inline(always)]
    pub(crate) fn light_pdf(&self) -> f32 {
        self.selection_probability * self.solid_angle_pdf
    }

    /// The MIS weight of the light technique against the vertex's sampling
    /// with `heuristic` (1 for a delta light).
    #[inline(always)]
    pub(crate) fn weight(&self, heuristic: MisHeuristic) -> f32 {
        if self.is_delta {
            1.0
        } else {
            heuristic.weight(self.light_pdf(), self.scatter_pdf)
        }
    }

    /// [`Self::weight`] over the light's density, what the estimate
    /// multiplies by, in one division where the heuristic allows
    /// ([`MisHeuristic::weight_over_density`]; the path tracer's hot path).
    /// LQMC's value walks divide [`Self::weight`] by [`Self::light_pdf`]
    /// instead, which rounds differently: their images stay as they were
    /// measured.
    #[inline(always)]
    pub(crate) fn weight_over_density(&self, heuristic: MisHeuristic) -> f32 {
        let light_pdf = self.light_pdf();
        if self.is_delta {
            1.0 / light_pdf
        } else {
            heuristic.weight_over_density(light_pdf, self.scatter_pdf)
        }
    }

    /// The spectral balance heuristic's denominator of a next event through
    /// media: `mean(r_l + r_u p_scatter)` with `r_l = r_u p_light`, where
    /// `r_u` is the path's rescaled probability at the vertex (`mean(r_l)`
    /// for a delta light). The contribution is `β · scattered · T · Le`
    /// over it (see [`super::mis`]).
    #[inline(always)]
    pub(crate) fn balance_denominator(&self, r_u: SampledSpectrum) -> f32 {
        let r_l = r_u * self.light_pdf();
        if self.is_delta {
            r_l.average()
        } else {
            (r_l + r_u * self.scatter_pdf).average()
        }
    }
}

/// The path tracer's next-event estimation at `hit`: one light sample,
/// MIS-weighted against BSDF sampling with the settings' heuristic (not
/// weighted for delta lights), its shadow ray stopped by any surface.
/// `offsets` is the hit point offset to the side of `wo` (the reference
/// point of light sampling). The result still has to be multiplied by the
/// path throughput.
#[allow(clippy::too_many_arguments)]
pub(crate) fn next_event_at_surface<S: SampleSource + ?Sized>(
    scene: &Scene,
    settings: &PathSettings,
    hit: &SurfaceHit,
    offsets: &OffsetPoint,
    bsdf: &SurfaceBsdf,
    wo: Vec3,
    depth: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut S,
    counters: &mut TraceCounters,
    area_radiance: &mut AreaRadianceCache,
) -> SampledSpectrum {
    let Some(light) = sample_vertex_light_with_cache(
        scene,
        offsets.origin(),
        depth,
        wavelengths,
        sampler,
        area_radiance,
    ) else {
        return SampledSpectrum::zero();
    };
    let terms = NextEventTerms::of_sample(VertexScatter::Surface(bsdf), wo, &light, wavelengths);
    if terms.scattered.is_black() {
        return SampledSpectrum::zero();
    }
    let sample = &light.sample;
    counters.shadow_rays += 1;
    if !unoccluded(
        scene,
        offsets.towards(sample.wi),
        hit.time,
        ShadowTarget::of_sample(sample),
    ) {
        return SampledSpectrum::zero();
    }
    terms.scattered * sample.radiance * terms.weight_over_density(settings.heuristic)
}

/// The volumetric path tracer's next-event estimation from `reference` (a
/// medium point, or a surface point offset off `hit`) where `scatter`
/// scatters from `wo`: one light sample, its transmittance through the
/// media and index-matched boundaries to the light, balance-weighted over
/// wavelengths and against `scatter`'s sampling
/// ([`NextEventTerms::balance_denominator`]); `r_u` is the path's rescaled
/// probability at the vertex. Returns the light sample with the value,
/// which still has to be multiplied by the path throughput; `None` where no
/// light arrives: no light sample, `scatter` passes none of it towards the
/// light, or the shadow ray is blocked. `null_crossings` is the walk's
/// setting: whether shadow rays pass thin sheets and masks with their null
/// lobe's weight ([`shadow_transmittance_with`]); `volpath`'s walk does,
/// LQMC's seeds (which record the sample as the event's connection) do not.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
pub(crate) fn next_event_through_media(
    scene: &Scene,
    reference: Vec3,
    hit: Option<&SurfaceHit>,
    medium: Option<u32>,
    scatter: VertexScatter<'_>,
    wo: Vec3,
    r_u: SampledSpectrum,
    depth: u32,
    wavelengths: &SampledWavelengths,
    sampler: &mut dyn SampleSource,
    counters: &mut TraceCounters,
    null_crossings: bool,
) -> Option<(VertexLightSample, SampledSpectrum)> {
    let light = sample_vertex_light(scene, reference, depth, wavelengths, sampler)?;
    let terms = NextEventTerms::of_sample(scatter, wo, &light, wavelengths);
    if terms.scattered.is_black() {
        return None;
    }
    let sample = &light.sample;
    let (ray, t_max) = shadow_ray(reference, hit, sample)?;
    // The medium the shadow ray starts in: at a surface, the side `wi` leaves to.
    let start_medium = medium_leaving(scene, hit, medium, sample.wi);
    let transmittance = shadow_transmittance_with(
        scene,
        ray,
        t_max,
        start_medium,
        null_crossings,
        wavelengths,
        counters,
    );
    if transmittance.is_black() {
        return None;
    }
    let denominator = terms.balance_denominator(r_u);
    let value = if denominator > 0.0 {
        terms.scattered * transmittance * sample.radiance / denominator
    } else {
        SampledSpectrum::zero()
    };
    Some((light, value))
}
