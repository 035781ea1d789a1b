//! Primary-sample-space Metropolis light transport (Kelemen et al. 2002,
//! "KMLT" in the LQMC paper): Markov chains over the numbers a path sample
//! is built from, run by the chain driver ([`super::markov_chain`]) over one
//! of two path samplers:
//!
//! - `--mlt-base path`: a camera path of the path tracer (volumetric where
//!   the scene has media) from a uniform point of the image plane, its
//!   radiance splatted there ([`CameraPathContribution`]);
//! - `--mlt-base bdpt`: a bidirectional sample of [`super::bdpt`] with every
//!   strategy, its splats where they land (Kelemen et al.'s and Mitsuba's
//!   `pssmlt` over BDPT). The target is the luminance of all of them.
//!
//! Defaults, with their sources: large steps with probability 0.3 (Kelemen
//! et al., pbrt-v4, Mitsuba), Kelemen's exponential small steps between
//! s1 = 1/1024 and s2 = 1/64 (pbrt-v4's normal kernel σ = 0.01 on
//! request), 100 000 bootstrap samples (pbrt-v4, Mitsuba), 1000 chains
//! (pbrt-v4), the path tracer as base. Samples per pixel are mutations per
//! pixel.

use super::bdpt::{BdptSettings, Bidirectional, BidirectionalScratch};
use super::camera_path::radiance;
use super::driver::{CameraPathStart, RenderError, RunControl};
use super::estimator::PathSettings;
use super::markov_chain::{
    ChainSettings, ChainStatistics, PathContribution, render_markov_chains,
    render_markov_chains_onto,
};
use super::path::PathTracing;
use super::volpath::VolumetricPathTracing;
use super::{Integrator, IntegratorRender, TraceCounters};
use crate::film::{CameraSamplePosition, ImagePlane, SplatBuffer};
use crate::sampler::{SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::to_linear_srgb;
use glam::Vec2;

/// Which path sampler the chains drive.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum MltBase {
    /// Unidirectional path tracing (volumetric in scenes with media).
    #[default]
    Path,
    /// Bidirectional path tracing, every strategy.
    Bidirectional,
}

impl MltBase {
    /// Every base with its command-line name.
    pub const ALL: [(MltBase, &'static str); 2] =
        [(MltBase::Path, "path"), (MltBase::Bidirectional, "bdpt")];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(base, _)| *base == self).unwrap().1
    }
}

/// PSSMLT's settings.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct PssmltSettings {
    /// The path sampler the chains drive.
    pub base: MltBase,
    /// Bootstrap, chains and mutations.
    pub chains: ChainSettings,
    /// Separate direct lighting (Mitsuba's `directSamples`): paths of 1 and
    /// 2 segments rendered by the path tracer at this many samples per
    /// pixel (the render's sampler), the chains' paths from 3 segments on.
    /// Default none (the chains render every path). Path base only.
    pub direct_samples_per_pixel: Option<u64>,
}

/// PSSMLT as an [`Integrator`].
#[derive(Debug, Clone, PartialEq)]
pub struct PssmltIntegrator {
    settings: PssmltSettings,
    path: PathSettings,
}

impl PssmltIntegrator {
    /// PSSMLT with `settings` over paths of `path`.
    pub fn new(settings: PssmltSettings, path: PathSettings) -> Self {
        Self { settings, path }
    }
}

impl Integrator for PssmltIntegrator {
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError> {
        if let Some(direct_spp) = self.settings.direct_samples_per_pixel {
            return self.render_with_direct_light(scene, run, direct_spp);
        }
        let output = match self.settings.base {
            MltBase::Path => render_markov_chains(
                &[CameraPathContribution::new(scene, self.path)],
                scene,
                run,
                &self.settings.chains,
            )?,
            MltBase::Bidirectional => render_markov_chains(
                &[Bidirectional::new(
                    scene,
                    &self.path,
                    BdptSettings::default(),
                    "pssmlt over bdpt",
                )?],
                scene,
                run,
                &self.settings.chains,
            )?,
        };
        Ok(output.into_render("pssmlt"))
    }
}

impl PssmltIntegrator {
    /// Direct light (paths of 1 and 2 segments) by the path tracer at
    /// `direct_spp` samples per pixel into the film's camera samples, then
    /// the chains over paths of 3 segments and more into its splats: the
    /// image is their sum (camera samples averaged per pixel, splats scaled
    /// by the mutation passes).
    fn render_with_direct_light(
        &self,
        scene: &Scene,
        run: &RunControl<'_>,
        direct_spp: u64,
    ) -> Result<IntegratorRender, RenderError> {
        if self.settings.base != MltBase::Path {
            return Err(RenderError::Unsupported(
                "pssmlt: separate direct light (--mlt-direct-spp) is for --mlt-base path".into(),
            ));
        }
        let direct_settings = PathSettings {
            max_depth: self.path.max_depth.min(2),
            splat_film: false,
            ..self.path
        };
        let direct_run = RunControl {
            sampler: run.sampler,
            pattern_size: None,
            seed: run.seed,
            randomization: run.randomization,
            samples_per_pixel: direct_spp.max(1),
            time_budget: None,
            tile_size: run.tile_size,
            stop: run.stop,
            progress: &|_, _| {},
            observer: None,
            start: run.start,
        };
        let integrator: Box<dyn Integrator> = if scene.has_media() {
            Box::new(super::volpath::VolPathIntegrator::new(direct_settings))
        } else {
            Box::new(super::path::PathIntegrator::new(direct_settings))
        };
        let direct = integrator.render(scene, &direct_run)?;
        let indirect = PathSettings {
            min_depth: 3,
            ..self.path
        };
        let mut output = if self.path.max_depth >= 3 {
            render_markov_chains_onto(
                direct.film,
                &[CameraPathContribution::new(scene, indirect)],
                scene,
                run,
                &self.settings.chains,
            )?
        } else {
            // No path of 3 segments: the direct light is the image.
            super::markov_chain::ChainOutput {
                film: direct.film,
                statistics: super::DriverStatistics {
                    completed_samples_per_pixel: run.samples_per_pixel,
                    ..Default::default()
                },
                chains: ChainStatistics::default(),
            }
        };
        output.statistics.samples += direct.statistics.samples;
        output.statistics.rays += direct.statistics.rays;
        Ok(output.into_render("pssmlt"))
    }
}

/// A camera path of the path tracer from a uniform point of the image
/// plane (grown by the filter's reach, [`ImagePlane`]): the film numbers
/// (dimensions 0, 1) place it on the whole plane instead of in one pixel,
/// and its radiance, times the plane's area over the image's, is splatted
/// there. Scenes with media take the volumetric path tracer's walk.
pub struct CameraPathContribution<'a> {
    scene: &'a Scene,
    settings: PathSettings,
    image_plane: ImagePlane,
    media: bool,
}

impl<'a> CameraPathContribution<'a> {
    /// Camera paths of `scene` with `settings`.
    pub fn new(scene: &'a Scene, settings: PathSettings) -> Self {
        Self {
            scene,
            settings,
            image_plane: ImagePlane::new(scene),
            media: scene.has_media(),
        }
    }
}

impl PathContribution for CameraPathContribution<'_> {
    type Scratch = ();

    fn new_scratch(&self) {}

    fn evaluate<S: SampleSource + ?Sized>(
        &self,
        _scratch: &mut (),
        source: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    ) {
        let raster = self
            .image_plane
            .raster(Vec2::from(source.get_2d(layout::FILM)));
        let position = CameraSamplePosition {
            raster_position: raster.to_array(),
            weight: self.image_plane.area_scale,
        };
        let start = CameraPathStart::at_position(self.scene, position, source);
        let mut wavelengths = start.wavelengths;
        // The volumetric path tracer's estimate where the scene has media.
        let radiance = if self.media {
            radiance::<VolumetricPathTracing, S>
        } else {
            radiance::<PathTracing, S>
        };
        let radiance = radiance(
            self.scene,
            &self.settings,
            start.ray,
            &mut wavelengths,
            source,
            counters,
        );
        let rgb = to_linear_srgb(&radiance, &wavelengths);
        if rgb != [0.0; 3] {
            let weight = position.weight;
            let _ = splats.add(position.raster_position, rgb.map(|value| value * weight));
        }
    }
}

/// A bidirectional sample of [`super::bdpt`] with every strategy, from a
/// uniform point of the whole image plane, its splats where they land:
/// the path sampler of `--mlt-base bdpt`.
impl PathContribution for Bidirectional<'_> {
    type Scratch = BidirectionalScratch;

    fn new_scratch(&self) -> BidirectionalScratch {
        BidirectionalScratch::default()
    }

    fn evaluate<S: SampleSource + ?Sized>(
        &self,
        scratch: &mut BidirectionalScratch,
        source: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    ) {
        self.trace_image_plane_sample(scratch, None, source, splats, counters);
    }
}
