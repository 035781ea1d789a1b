//! What one render is asked for, as the renderer's settings (shared with
//! the studies), and the metadata its images carry.

use crate::error::{CliError, usage};
use render::image::Metadata;
use render::integrators::{IntegratorSettings, MisHeuristic};
use render::renderer::{RenderSettings, RenderStatistics};
use render::sampler::{Randomization, SamplerKind};
use render::scene::Scene;
use std::time::Duration;

/// A time budget in seconds from the option `option`: positive and finite.
pub fn parse_time_budget(option: &str, seconds: f64) -> Result<Duration, CliError> {
    if seconds > 0.0 && seconds.is_finite() {
        Ok(Duration::from_secs_f64(seconds))
    } else {
        Err(usage(format!(
            "{option} must be a positive number of seconds, got {seconds}"
        )))
    }
}

/// What one render is asked for on the command line; [`Self::settings`]
/// fills in the scene's suggestions and the defaults where it says nothing.
#[derive(Debug, Clone)]
pub struct RenderRequest {
    /// The integrator with its settings.
    pub integrator: IntegratorSettings,
    /// The sampler.
    pub sampler: SamplerKind,
    /// Points per replication, if each pixel's samples are replications.
    pub pattern_size: Option<u64>,
    /// Samples per pixel (default: unlimited with a time budget, else the
    /// scene's suggestion, else 16).
    pub samples_per_pixel: Option<u64>,
    /// Stop after this much time.
    pub time_budget: Option<Duration>,
    /// The seed of every random choice.
    pub seed: u64,
    /// Whether the seed randomizes the QMC samplers.
    pub randomization: Randomization,
    /// Maximum path depth (default: the scene's, else 6).
    pub max_depth: Option<u32>,
    /// Russian roulette depth (default: the scene's, else 3).
    pub russian_roulette_depth: Option<u32>,
    /// The MIS heuristic.
    pub heuristic: MisHeuristic,
    /// path, volpath: splat each sample over its filter's pixels.
    pub splat_film: bool,
    /// Worker threads (0: all cores).
    pub threads: usize,
}

impl RenderRequest {
    /// The renderer's settings for `scene`.
    pub fn settings(&self, scene: &Scene) -> RenderSettings {
        let samples_per_pixel = match (self.samples_per_pixel, self.time_budget) {
            (Some(spp), _) => spp,
            // As good as unlimited: the time budget ends the render.
            (None, Some(_)) => u64::MAX / (1 << 32),
            (None, None) => scene.samples_per_pixel.unwrap_or(16),
        };
        RenderSettings {
            integrator: self.integrator.clone(),
            sampler: self.sampler,
            pattern_size: self.pattern_size,
            samples_per_pixel,
            time_budget: self.time_budget,
            seed: self.seed,
            randomization: self.randomization,
            max_depth: self.max_depth.or(scene.max_depth).unwrap_or(6),
            heuristic: self.heuristic,
            russian_roulette_depth: self
                .russian_roulette_depth
                .or(scene.russian_roulette_depth)
                .unwrap_or(3),
            splat_film: self.splat_film,
            threads: self.threads,
            ..RenderSettings::default()
        }
    }
}

/// The metadata `lqmc render` writes into its images: integrator, sampler,
/// whole passes (`spp`), seed, randomization, render time, scene and depths.
pub fn render_metadata(
    scene_name: &str,
    settings: &RenderSettings,
    statistics: &RenderStatistics,
) -> Metadata {
    let seconds = statistics.elapsed.as_secs_f64().max(1e-9);
    let mut metadata = Metadata::new();
    metadata.insert("integrator".into(), settings.integrator.name().into());
    metadata.insert("sampler".into(), settings.sampler.name().into());
    metadata.insert(
        "spp".into(),
        statistics.completed_samples_per_pixel.to_string(),
    );
    metadata.insert("seed".into(), settings.seed.to_string());
    if settings.splat_film {
        metadata.insert("film".into(), "splat".into());
    }
    metadata.insert("randomization".into(), settings.randomization.name().into());
    if let Some(pattern_size) = settings.pattern_size {
        metadata.insert("patternSize".into(), pattern_size.to_string());
        metadata.insert(
            "replications".into(),
            (statistics.completed_samples_per_pixel / pattern_size).to_string(),
        );
    }
    metadata.insert("renderTimeSeconds".into(), format!("{seconds:.3}"));
    metadata.insert("scene".into(), scene_name.to_string());
    metadata.insert("maxDepth".into(), settings.max_depth.to_string());
    metadata.insert(
        "rrDepth".into(),
        settings.russian_roulette_depth.to_string(),
    );
    if let Some(memory) = statistics.memory {
        metadata.insert(
            "peakResidentBytes".into(),
            memory.peak_resident_bytes.to_string(),
        );
        metadata.insert(
            "residentBytesAtStart".into(),
            memory.resident_bytes_at_start.to_string(),
        );
    }
    metadata
}

/// Pixel samples traced per pixel, a partial last pass included (the
/// metadata's `spp` counts the whole passes).
pub fn traced_samples_per_pixel(scene: &Scene, statistics: &RenderStatistics) -> f64 {
    let [width, height] = scene.camera.resolution();
    statistics.samples as f64 / (width as f64 * height as f64)
}
