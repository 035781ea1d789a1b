//! The shell of the camera-path integrators (path, volpath): one camera
//! path per pixel sample, started from the film
//! ([`CameraPathStart::for_film`]), its radiance added to its pixel or, with
//! [`PathSettings::splat_film`], splatted over the filter's footprint, run
//! by the tile driver. The integrators differ only in their radiance
//! estimate, a [`CameraPathRadiance`]: [`super::path`]'s over surfaces,
//! [`super::volpath`]'s through media.

use super::driver::{
    CameraPathStart, PixelSampleEstimator, PixelSampleIndex, UnitOutput, render_pixel_samples,
};
use super::estimator::PathSettings;
use super::path_space::{WalkObserver, WalkSettings, WalkStart, walk};
use super::progression_variance::ProgressionVariance;
use super::{Integrator, IntegratorRender, RenderError, RunControl, TraceCounters};
use crate::film::Film;
use crate::geometry::Ray;
use crate::sampler::{PixelSampler, SampleSource};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, to_linear_srgb};
use std::marker::PhantomData;

/// A camera-path integrator's radiance estimate: the path-space walk from
/// the camera with an observer that adds up what the path finds.
pub trait CameraPathRadiance {
    /// The walk traces participating media and passes null surfaces (the
    /// volumetric path tracer's), starting in the camera's medium.
    const MEDIA: bool;

    /// The walk's observer, which sums the path's radiance.
    type Observer<'a>: WalkObserver;

    /// Checks `scene` before a render (warnings about what the estimate
    /// ignores).
    fn check_scene(_scene: &Scene) {}

    /// The observer of one camera path.
    fn observer<'a>(scene: &'a Scene, settings: &'a PathSettings) -> Self::Observer<'a>;

    /// The radiance `observer` summed.
    fn radiance(observer: Self::Observer<'_>) -> SampledSpectrum;
}

/// Estimates the radiance along the camera ray `ray` for `wavelengths`
/// (which the estimate may change: dispersion terminates the secondary
/// ones) with the numbers of `sampler`: the path-space walk with `R`'s
/// observer.
///
/// Generic over the sampler so that a concrete sampler's numbers (a hash
/// for the independent one) inline into the walk; `dyn SampleSource`
/// works as well. Always inlined, so that it is compiled into the AVX2
/// tile loop of the driver (`render_unit_avx2`).
#[inline(always)]
pub fn radiance<R: CameraPathRadiance, S: SampleSource + ?Sized>(
    scene: &Scene,
    settings: &PathSettings,
    ray: Ray,
    wavelengths: &mut SampledWavelengths,
    sampler: &mut S,
    counters: &mut TraceCounters,
) -> SampledSpectrum {
    let mut observer = R::observer(scene, settings);
    walk(
        scene,
        WalkStart::camera(ray, if R::MEDIA { scene.camera_medium } else { None }),
        &WalkSettings::camera(
            WalkSettings::camera_vertices(settings.max_depth),
            settings.russian_roulette_depth,
            R::MEDIA,
            R::MEDIA,
        ),
        wavelengths,
        sampler,
        counters,
        &mut observer,
    );
    R::radiance(observer)
}

/// A camera-path integrator as an [`Integrator`], run by the tile driver:
/// [`super::path::PathIntegrator`] and [`super::volpath::VolPathIntegrator`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CameraPathIntegrator<R> {
    settings: PathSettings,
    radiance: PhantomData<fn() -> R>,
}

impl<R> CameraPathIntegrator<R> {
    /// The integrator with `settings`.
    pub fn new(settings: PathSettings) -> Self {
        Self {
            settings,
            radiance: PhantomData,
        }
    }
}

impl<R: CameraPathRadiance> Integrator for CameraPathIntegrator<R> {
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError> {
        R::check_scene(scene);
        let estimator = CameraPathEstimator::<R> {
            scene,
            settings: &self.settings,
            radiance: PhantomData,
        };
        render_pixel_samples(&estimator, scene, run).map(IntegratorRender::from_camera_paths)
    }
}

/// One camera path per pixel sample, its radiance added to its pixel.
struct CameraPathEstimator<'a, R> {
    scene: &'a Scene,
    settings: &'a PathSettings,
    radiance: PhantomData<fn() -> R>,
}

impl<R: CameraPathRadiance> PixelSampleEstimator for CameraPathEstimator<'_, R> {
    type Unit = ();
    type Total = Option<ProgressionVariance>;

    /// One progression per pass when splatting (the variance layer needs
    /// each progression's image), else the driver's default.
    fn pass_size(&self, samples_per_pixel: u64, timed: bool) -> u64 {
        if self.settings.splat_film || timed {
            1
        } else {
            samples_per_pixel.clamp(1, 4)
        }
    }

    fn new_total(&self, resolution: [usize; 2]) -> Result<Self::Total, RenderError> {
        Ok(self
            .settings
            .splat_film
            .then(|| ProgressionVariance::new(resolution)))
    }

    fn new_unit(&self) {}

    fn merge_unit(&self, _total: &mut Self::Total, _unit: (), _kept: bool) {}

    fn end_pass(&self, total: &mut Self::Total, film: &Film, complete: bool) {
        if let Some(progressions) = total {
            progressions.end_progression(film, complete);
        }
    }

    /// Always inlined into the driver's tile loop, so that the AVX2 copy of
    /// that loop compiles the path in it (see [`radiance`]).
    #[inline(always)]
    fn estimate<S: PixelSampler + ?Sized>(
        &self,
        _unit: &mut (),
        sample: PixelSampleIndex,
        sampler: &mut S,
        output: &mut UnitOutput,
    ) {
        let splat_film = self.settings.splat_film;
        let start = CameraPathStart::for_film(self.scene, sample.pixel, sampler, splat_film);
        let mut wavelengths = start.wavelengths;
        let radiance = radiance::<R, S>(
            self.scene,
            self.settings,
            start.ray,
            &mut wavelengths,
            sampler,
            &mut output.counters,
        );
        output.add_camera_path(
            &start,
            sample.pixel,
            to_linear_srgb(&radiance, &wavelengths),
            splat_film,
        );
    }
}
