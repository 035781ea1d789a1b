//! One pixel sample of LQMC (Alg. 1 around a Halton-seeded path tracer):
//! trace the seed path, and for each of its splat events either splat it as
//! it is or explore it with a lattice set and splat every member with its
//! estimator weight.

use super::class_selection::PilotRecord;
use super::classification::{
    EventPath, PathClass, breakup_probability, breakup_weights, classify, draw_breakup,
    long_enough_to_explore,
};
use super::estimator::member_weights;
use super::explored_dimensions::{DimensionKind, ExploredDimension, explored_dimensions};
use super::lattice_step::{LatticeMembers, TileGrid, lattice_members};
use super::path_record::{CameraVertex, SplatEvent, SurfaceVertex};
use super::path_walk::{WalkInput, walk};
use super::prefix_rebuild::{ImagePlane, MemberCamera, MemberSource, rebuild_member};
use super::seed_film::SeedFilm;
use super::seed_path::{SeedPath, seed_camera, trace_seed_path};
use super::seed_screen::{ScreenScratch, path_traced_seed};
use super::segment_cache::{SegmentCache, SegmentReuse};
use super::settings::{BreakupChoice, LatticeScramble, LqmcSettings};
use super::statistics::{FailureReason, LqmcStatistics};
use crate::film::SplatBuffer;
use crate::integrators::TraceCounters;
use crate::integrators::driver::UnitOutput;
use crate::integrators::estimator::PathSettings;
use crate::sampler::{DynSource, SampleSource, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths, to_linear_srgb};
use qmc::hash::{below, hash2, hash3, to_unit_f64};
use qmc::lattice_table::lqmc_lattice_entry;

/// One exploration in this many has its member loop timed (`--stats`).
const MEMBER_TIMING_PERIOD: u64 = 16;

/// Purposes of the deterministic random choices (hash keys).
const BREAKUP_KEY: u64 = 0x6272_6561_6b75_7000;
const JITTER_KEY: u64 = 0x6a69_7474_6572_0000;
const SCRAMBLE_KEY: u64 = 0x7363_7261_6d62_6c65;

/// What every pixel sample of a render shares.
#[derive(Debug, Clone, Copy)]
pub struct LqmcContext<'a> {
    /// The scene.
    pub scene: &'a Scene,
    /// LQMC's settings.
    pub settings: &'a LqmcSettings,
    /// The seed path tracer's settings.
    pub path_settings: PathSettings,
    /// The render's seed (keys the tile jitter, the breakup draw and the
    /// dimension scrambling).
    pub seed: u64,
    /// Where seeds lie and how their values land.
    pub film: SeedFilm,
    /// Whether seeds are path-traced first and recorded only where an
    /// event could be explored ([`super::seed_screen::screens_seeds`]).
    pub screen_seeds: bool,
}

/// The sample density per class (the paper's Fig. 11): one splat of value
/// one per splatted member, in the channel of its class (`rgb`: normal,
/// caustic, depth of field) or, for next-event paths, in all channels of
/// `next_event`.
#[derive(Debug, Default, Clone)]
pub struct ClassDensity {
    /// Normal, caustic and depth-of-field members as red, green, blue.
    pub rgb: SplatBuffer,
    /// Next-event members (grey).
    pub next_event: SplatBuffer,
}

/// Buffers reused from one pixel sample to the next.
#[derive(Debug, Default)]
pub struct LqmcScratch {
    /// The sample density per class, gathered when set.
    pub density: Option<ClassDensity>,
    /// What the class-selection pilot measures, when set.
    pub pilot: Option<PilotRecord>,
    screen: ScreenScratch,
    seed_path: SeedPath,
    member_vertices: Vec<SurfaceVertex>,
    dimensions: Vec<ExploredDimension>,
    probe_dimensions: Vec<ExploredDimension>,
    breakup_weights: Vec<f64>,
    member_breakup_weights: Vec<f64>,
    segment_cache: SegmentCache,
    seed_numbers: Vec<f64>,
    tiles: Vec<u32>,
    jitter: Vec<f64>,
    lattice_dimension: Vec<usize>,
    query: Vec<f64>,
    members: LatticeMembers,
    overrides: Vec<(usize, f32)>,
    member_splats: Vec<([f32; 2], [f32; 3])>,
    member_densities: Vec<f64>,
    weights: Vec<f64>,
    /// The sum of the sample's events not explored: the seed's camera
    /// sample (or one splat at its raster position with `--splat-film`),
    /// as the path tracer's.
    unexplored: UnexploredSum,
}

/// The values of a seed's events that are not explored, summed as the path
/// tracer sums its sample's: spectrally while the wavelengths stay the
/// same (one conversion to RGB per sample, and the same sum, term by
/// term), in RGB across a change of wavelengths (a dispersive vertex
/// terminated the secondary ones).
#[derive(Debug, Default)]
struct UnexploredSum {
    spectral: Option<(SampledSpectrum, SampledWavelengths)>,
    rgb: [f32; 3],
}

impl UnexploredSum {
    /// Starts an empty sum.
    fn clear(&mut self) {
        self.spectral = None;
        self.rgb = [0.0; 3];
    }

    /// Adds an event's `contribution` at `wavelengths`.
    #[inline]
    fn add(&mut self, contribution: &SampledSpectrum, wavelengths: &SampledWavelengths) {
        match &mut self.spectral {
            Some((sum, summed_at)) if summed_at == wavelengths => *sum += *contribution,
            _ => {
                self.flush();
                self.spectral = Some((*contribution, *wavelengths));
            }
        }
    }

    /// Moves the spectral part into the RGB part.
    fn flush(&mut self) {
        if let Some((sum, wavelengths)) = self.spectral.take() {
            let rgb = to_linear_srgb(&sum, &wavelengths);
            for (total, value) in self.rgb.iter_mut().zip(rgb) {
                *total += value;
            }
        }
    }

    /// The sum in linear sRGB.
    fn rgb(&mut self) -> [f32; 3] {
        self.flush();
        self.rgb
    }
}

/// Renders one pixel sample: `sampler` is positioned at it.
///
/// Generic over the sampler and always inlined, so that a screened seed
/// (most seeds, where screening applies) is traced by code compiled as the
/// path tracer's: with the concrete sampler, into the driver's AVX2 tile
/// loop. A recorded seed goes on in [`render_recorded_seed`].
#[inline(always)]
pub fn render_pixel_sample<S: SampleSource + ?Sized>(
    context: &LqmcContext<'_>,
    pixel: (u32, u32),
    sample_index: u64,
    sampler: &mut S,
    scratch: &mut LqmcScratch,
    output: &mut UnitOutput,
    statistics: &mut LqmcStatistics,
) {
    let raster = context
        .film
        .seed_raster(context.scene, pixel, sampler.get_2d(layout::FILM));
    if context.screen_seeds {
        let UnitOutput {
            tile,
            splats,
            counters,
        } = &mut *output;
        let (camera, ray, wavelengths) = seed_camera(context.scene, raster, sampler);
        if let Some((radiance, wavelengths)) = path_traced_seed(
            context.scene,
            context.settings,
            &context.path_settings,
            camera.origin,
            ray,
            wavelengths,
            sampler,
            counters,
            &mut scratch.screen,
        ) {
            statistics.screened_seeds += 1;
            let rgb = to_linear_srgb(&radiance, &wavelengths);
            if let Some(pilot) = &mut scratch.pilot {
                pilot.add_seed_value(rgb);
            }
            land_unexplored(context, pixel, raster, rgb, tile, splats);
            return;
        }
        // An event could be explored: the seed is traced again, from the
        // same numbers along the same path, and recorded.
        statistics.retraced_seeds += 1;
    }
    render_recorded_seed(
        context,
        pixel,
        sample_index,
        raster,
        &mut DynSource(sampler),
        scratch,
        output,
        statistics,
    );
}

/// Renders one pixel sample whose seed path goes through `raster`: records
/// the seed and explores its events or adds them as they are.
#[allow(clippy::too_many_arguments)]
fn render_recorded_seed(
    context: &LqmcContext<'_>,
    pixel: (u32, u32),
    sample_index: u64,
    raster: glam::Vec2,
    sampler: &mut dyn SampleSource,
    scratch: &mut LqmcScratch,
    output: &mut UnitOutput,
    statistics: &mut LqmcStatistics,
) {
    let UnitOutput {
        tile,
        splats,
        counters,
    } = output;
    let mut seed_path = std::mem::take(&mut scratch.seed_path);
    trace_seed_path(
        context.scene,
        &context.path_settings,
        raster,
        sampler,
        counters,
        &mut seed_path,
    );
    let seed_wavelengths = seed_path.wavelengths;
    scratch.unexplored.clear();
    for (event_index, event) in seed_path.events.iter().enumerate() {
        // The key of the event's random choices, hashed only for events
        // that come to a breakup draw.
        let event_key = || {
            let sample_key = hash3(context.seed, crate::sampler::pixel_key(pixel), sample_index);
            hash2(sample_key, event_index as u64)
        };
        handle_event(
            context,
            &seed_path,
            event,
            seed_path.event_values[event_index],
            seed_wavelengths,
            sample_index,
            event_key,
            sampler,
            scratch,
            splats,
            statistics,
            counters,
        );
    }
    let unexplored = scratch.unexplored.rgb();
    if let Some(pilot) = &mut scratch.pilot {
        pilot.add_seed_value(unexplored);
    }
    land_unexplored(context, pixel, raster, unexplored, tile, splats);
    scratch.seed_path = seed_path;
}

/// Adds a seed's unexplored value `rgb`: to its pixel as its camera
/// sample, or splatted at its raster position with `--splat-film` (scaled
/// by [`SeedFilm::unexplored_scale`]).
fn land_unexplored(
    context: &LqmcContext<'_>,
    pixel: (u32, u32),
    raster: glam::Vec2,
    rgb: [f32; 3],
    tile: &mut crate::film::FilmTile,
    splats: &mut SplatBuffer,
) {
    if context.film.adds_camera_samples() {
        let _ = tile.add_sample([pixel.0 as usize, pixel.1 as usize], rgb, 1.0);
    } else if rgb != [0.0; 3] {
        let scale = context.film.unexplored_scale();
        let _ = splats.add(raster.to_array(), rgb.map(|channel| channel * scale));
    }
}

/// Splats one event, explored or not.
#[allow(clippy::too_many_arguments)]
fn handle_event(
    context: &LqmcContext<'_>,
    seed_path: &SeedPath,
    event: &SplatEvent,
    recorded_value: Option<(SampledSpectrum, SampledWavelengths)>,
    seed_wavelengths: Option<SampledWavelengths>,
    sample_index: u64,
    event_key: impl FnOnce() -> u64,
    sampler: &mut dyn SampleSource,
    scratch: &mut LqmcScratch,
    splats: &mut SplatBuffer,
    statistics: &mut LqmcStatistics,
    counters: &mut TraceCounters,
) {
    let scene = context.scene;
    let settings = context.settings;
    let camera = seed_path.camera.as_ref().expect("traced");
    let vertices = &seed_path.vertices[event.vertex_range()];
    // The event added as it is: with the path tracer's value the seed's
    // walk computed, or else (index-matched emitters) its value walk's.
    let direct = |unexplored: &mut UnexploredSum,
                  statistics: &mut LqmcStatistics,
                  sampler: &mut dyn SampleSource,
                  segment_cache: &mut SegmentCache| {
        match recorded_value {
            Some((contribution, wavelengths)) => {
                if contribution.is_black() {
                    return;
                }
                unexplored.add(&contribution, &wavelengths);
            }
            None => {
                segment_cache.clear();
                let Ok(walked) = walk(
                    scene,
                    &context.path_settings,
                    &seed_walk_input(context, camera, vertices, event, seed_wavelengths),
                    sampler,
                    &mut SegmentReuse::None,
                ) else {
                    return;
                };
                unexplored.add(&walked.contribution, &walked.wavelengths);
            }
        }
        statistics.events += 1;
        statistics.direct_splats += 1;
    };
    if !long_enough_to_explore(event.last_vertex()) {
        return direct(
            &mut scratch.unexplored,
            statistics,
            sampler,
            &mut scratch.segment_cache,
        );
    }
    let path = EventPath {
        camera,
        vertices,
        event,
    };
    let class = classify(scene, settings, &path);
    let parameters = *settings.class_parameters(class);
    if !parameters.explore {
        return direct(
            &mut scratch.unexplored,
            statistics,
            sampler,
            &mut scratch.segment_cache,
        );
    }
    let probe = &mut scratch.probe_dimensions;
    let mut weights = std::mem::take(&mut scratch.breakup_weights);
    breakup_weights(
        settings,
        &path,
        class,
        |b| {
            explored_dimensions(scene, settings, &parameters, &path, b, probe);
            settings.explorable(probe)
        },
        &mut weights,
    );
    let breakup = draw_breakup(&weights, to_unit_f64(hash2(event_key(), BREAKUP_KEY)));
    scratch.breakup_weights = weights;
    let Some(breakup) = breakup else {
        return direct(
            &mut scratch.unexplored,
            statistics,
            sampler,
            &mut scratch.segment_cache,
        );
    };
    // The seed's value walk, recording what its members reuse. Where it
    // fails on the seed's own path (a decision on a knife's edge comes out
    // otherwise when recomputed), the seed is splatted as the path tracer
    // valued it: returning here would lose its contribution. The walk of
    // the same path as a member of another set fails alike, so the seed's
    // whole share is this direct splat.
    scratch.segment_cache.clear();
    let Ok(walked) = walk(
        scene,
        &context.path_settings,
        &seed_walk_input(context, camera, vertices, event, seed_wavelengths),
        sampler,
        &mut SegmentReuse::Record(&mut scratch.segment_cache),
    ) else {
        statistics.unevaluable_seeds += 1;
        return direct(
            &mut scratch.unexplored,
            statistics,
            sampler,
            &mut scratch.segment_cache,
        );
    };
    debug_assert!(
        matches!(
            settings.breakup,
            BreakupChoice::Roughness | BreakupChoice::FullPath
        ) || settings.breakup == BreakupChoice::Fixed(breakup)
    );
    let explored = explore(
        context,
        seed_path,
        event,
        class,
        breakup,
        sample_index,
        sampler,
        scratch,
        splats,
        statistics,
        counters,
    );
    statistics.events += 1;
    if !explored {
        statistics.direct_splats += 1;
        scratch
            .unexplored
            .add(&walked.contribution, &walked.wavelengths);
    } else if let Some(pilot) = &mut scratch.pilot {
        pilot.add_explored_seed_value(
            class,
            to_linear_srgb(&walked.contribution, &walked.wavelengths),
        );
    }
}

/// The value walk's input for the seed's own path of `event`.
fn seed_walk_input<'a>(
    context: &LqmcContext<'_>,
    camera: &'a CameraVertex,
    vertices: &'a [SurfaceVertex],
    event: &'a SplatEvent,
    seed_wavelengths: Option<SampledWavelengths>,
) -> WalkInput<'a> {
    WalkInput {
        camera,
        vertices,
        terminal: &event.terminal,
        rebuilt_vertices: 0,
        breakup: None,
        tolerance: context.settings.reconnection_tolerance,
        wavelengths: seed_wavelengths,
        first_projection: None,
    }
}

/// Explores one event with breakup vertex `breakup` (Alg. 1) and splats its
/// members; returns false, having splatted nothing, when the seed's own
/// member fails (the caller then splats the seed as it is).
///
/// Why that keeps the estimator unbiased: Eq. (9)'s weights form a
/// partition of unity only if the seeds that trigger an exploration of a
/// set are exactly its valid members. A seed that fails in its own set (its
/// rebuilt path changes class, misses the reconnection tolerance, ...) is,
/// by the same deterministic test, invalid in every set it belongs to, so
/// it must neither trigger the exploration (that would over-weight the
/// other members) nor lose its contribution: it is splatted directly with
/// weight 1, which is its whole share.
#[allow(clippy::too_many_arguments)]
fn explore(
    context: &LqmcContext<'_>,
    seed_path: &SeedPath,
    event: &SplatEvent,
    class: PathClass,
    breakup: usize,
    sample_index: u64,
    sampler: &mut dyn SampleSource,
    scratch: &mut LqmcScratch,
    splats: &mut SplatBuffer,
    statistics: &mut LqmcStatistics,
    counters: &mut TraceCounters,
) -> bool {
    let scene = context.scene;
    let settings = context.settings;
    let camera = seed_path.camera.as_ref().expect("traced");
    let vertices = &seed_path.vertices[event.vertex_range()];
    let parameters = *settings.class_parameters(class);
    let path = EventPath {
        camera,
        vertices,
        event,
    };
    explored_dimensions(
        scene,
        settings,
        &parameters,
        &path,
        breakup,
        &mut scratch.dimensions,
    );
    let dimension_count = scratch.dimensions.len();
    let image_plane = ImagePlane::new(scene);
    let seed_image_numbers = image_plane.numbers(camera.raster);
    let seed_density = context.film.seed_density(camera.raster);

    // The seed's explored numbers, tiles, jitter and lattice dimensions.
    scratch.seed_numbers.clear();
    scratch.tiles.clear();
    scratch.jitter.clear();
    scratch.lattice_dimension.clear();
    for (index, dimension) in scratch.dimensions.iter().enumerate() {
        let value = match dimension.kind {
            DimensionKind::Lens(axis) => camera.u_lens[axis],
            DimensionKind::Wavelength => camera.u_wavelength,
            DimensionKind::Time => camera.u_time,
            DimensionKind::Image(0) => seed_image_numbers.x,
            DimensionKind::Image(_) => seed_image_numbers.y,
            DimensionKind::Direction { vertex, axis } => {
                sampler.get(layout::vertex(vertex, layout::SCATTER_DIRECTION + axis))
            }
            DimensionKind::FreeFlight { vertex } => {
                sampler.get(layout::vertex(vertex, layout::FREE_FLIGHT))
            }
            DimensionKind::LightPosition { vertex, axis } => {
                sampler.get(layout::vertex(vertex, layout::LIGHT_POSITION + axis))
            }
        };
        scratch
            .seed_numbers
            .push((value as f64).clamp(0.0, 1.0 - f64::EPSILON));
        scratch.tiles.push(dimension.tiles);
        let jitter = if settings.jitter_tiles {
            to_unit_f64(hash3(
                context.seed ^ JITTER_KEY,
                sample_index,
                dimension.kind.key(),
            )) / dimension.tiles as f64
        } else {
            0.0
        };
        scratch.jitter.push(jitter);
        scratch.lattice_dimension.push(index);
    }
    if settings.lattice_scramble != LatticeScramble::None {
        let key = set_key(
            context.seed,
            sample_index,
            class,
            breakup,
            &scratch.dimensions,
            &scratch.seed_numbers,
            &scratch.jitter,
        );
        scramble_lattice_dimensions(
            settings.lattice_scramble,
            &scratch.dimensions,
            &mut scratch.lattice_dimension,
            key,
        );
    }
    let Ok(entry) = lqmc_lattice_entry(parameters.lattice_size, dimension_count) else {
        return false;
    };
    let found = lattice_members(
        entry,
        &TileGrid {
            tiles: &scratch.tiles,
            jitter: &scratch.jitter,
            lattice_dimension: &scratch.lattice_dimension,
        },
        &scratch.seed_numbers,
        &mut scratch.query,
        &mut scratch.members,
        &mut statistics.closest_point,
    );
    if found.is_err() {
        return false;
    }
    // The seed's own member takes the seed's numbers exactly (the lattice
    // mapping reproduces them only up to rounding).
    let seed_member = scratch.members.seed_member;
    scratch.members.numbers[seed_member * dimension_count..(seed_member + 1) * dimension_count]
        .copy_from_slice(&scratch.seed_numbers);
    statistics.explorations[class.index()] += 1;
    statistics.breakups[breakup.min(3)] += 1;
    if scratch
        .dimensions
        .iter()
        .any(|dimension| matches!(dimension.kind, DimensionKind::FreeFlight { .. }))
    {
        statistics.medium_explorations += 1;
    }

    let member_count = scratch.members.numbers.len() / dimension_count;
    scratch.member_splats.clear();
    scratch.member_densities.clear();
    let mut probe = std::mem::take(&mut scratch.probe_dimensions);
    // `handle_event` left the seed's breakup weights here.
    let seed_breakup_weights = std::mem::take(&mut scratch.breakup_weights);
    let mut member_breakup_weights = std::mem::take(&mut scratch.member_breakup_weights);
    let mut seed_member_valid = false;
    let rays_before = counters.rays();
    // Vertices the members' walks evaluated (the pilot's cost measure).
    let mut walked_vertices = 0usize;
    // The member loop of every 16th exploration of a work unit (its 1st,
    // 17th, ...) is timed: two clock reads per timed loop, not per member.
    let explorations_so_far: u64 = statistics.explorations.iter().sum();
    let timed = (explorations_so_far % MEMBER_TIMING_PERIOD == 1).then(std::time::Instant::now);
    for j in 0..member_count {
        let numbers = &scratch.members.numbers[j * dimension_count..(j + 1) * dimension_count];
        let mut member_camera = MemberCamera {
            raster: camera.raster,
            u_lens: camera.u_lens,
            u_time: camera.u_time,
            u_wavelength: camera.u_wavelength,
        };
        scratch.overrides.clear();
        let mut image_numbers = seed_image_numbers;
        for (dimension, value) in scratch.dimensions.iter().zip(numbers) {
            let value = crate::sampler::to_f32(*value);
            match dimension.kind {
                DimensionKind::Lens(axis) => member_camera.u_lens[axis] = value,
                DimensionKind::Wavelength => member_camera.u_wavelength = value,
                DimensionKind::Time => member_camera.u_time = value,
                DimensionKind::Image(0) => image_numbers.x = value,
                DimensionKind::Image(_) => image_numbers.y = value,
                DimensionKind::Direction { vertex, axis } => scratch.overrides.push((
                    layout::vertex(vertex, layout::SCATTER_DIRECTION + axis),
                    value,
                )),
                DimensionKind::FreeFlight { vertex } => scratch
                    .overrides
                    .push((layout::vertex(vertex, layout::FREE_FLIGHT), value)),
                DimensionKind::LightPosition { vertex, axis } => scratch
                    .overrides
                    .push((layout::vertex(vertex, layout::LIGHT_POSITION + axis), value)),
            }
        }
        if image_numbers != seed_image_numbers {
            member_camera.raster = image_plane.raster(image_numbers);
        }
        let mut source = MemberSource {
            seed: &mut *sampler,
            overrides: &scratch.overrides,
        };
        statistics.members[class.index()] += 1;
        let wavelengths = SampledWavelengths::sample_visible(member_camera.u_wavelength);
        let member = rebuild_member(
            scene,
            settings.reconnection_tolerance,
            &image_plane,
            &seed_path.vertices,
            event,
            breakup,
            &member_camera,
            wavelengths,
            &mut source,
            counters,
            &mut scratch.member_vertices,
        )
        .and_then(|rebuilt| {
            let member_vertex = rebuilt.camera;
            let walked = walk(
                scene,
                &context.path_settings,
                &WalkInput {
                    camera: &member_vertex,
                    vertices: &scratch.member_vertices,
                    terminal: &event.terminal,
                    rebuilt_vertices: breakup,
                    breakup: Some(breakup),
                    tolerance: settings.reconnection_tolerance,
                    wavelengths: Some(wavelengths),
                    first_projection: rebuilt.first_projection,
                },
                &mut source,
                &mut SegmentReuse::Reuse {
                    cache: &scratch.segment_cache,
                    first: breakup + 1,
                },
            )?;
            // P(c | X_j): the member's own class and breakup probability.
            let member_path = EventPath {
                camera: &member_vertex,
                vertices: &scratch.member_vertices,
                event,
            };
            let member_class = classify(scene, settings, &member_path);
            if member_class != class {
                return Err(FailureReason::ClassChange);
            }
            // P(b | X_j) depends on the vertices' sampled lobes, roughness
            // and media (and the class): where they are the seed's, as for
            // every member with b = 0, the weights are the seed's.
            let weights = if same_breakup_inputs(&scratch.member_vertices, vertices) {
                &seed_breakup_weights
            } else {
                breakup_weights(
                    settings,
                    &member_path,
                    class,
                    |b| {
                        explored_dimensions(
                            scene,
                            settings,
                            &parameters,
                            &member_path,
                            b,
                            &mut probe,
                        );
                        settings.explorable(&probe)
                    },
                    &mut member_breakup_weights,
                );
                &member_breakup_weights
            };
            let probability = breakup_probability(weights, breakup);
            if probability <= 0.0 {
                return Err(FailureReason::ClassChange);
            }
            walked_vertices += if walked.reused_seed_steps {
                (breakup + 2).min(scratch.member_vertices.len())
            } else {
                scratch.member_vertices.len()
            };
            Ok((member_vertex, walked, probability))
        });
        match member {
            Ok((member_vertex, walked, probability)) => {
                // The density with which the member would have been drawn
                // as a seed (`seed_film`): the same for every member that
                // keeps the seed's raster position.
                let position_density = if member_vertex.raster == camera.raster {
                    seed_density
                } else {
                    context.film.seed_density(member_vertex.raster)
                };
                let density = probability * walked.suffix_density * position_density;
                if !(density > 0.0 && density.is_finite()) {
                    statistics.fail(FailureReason::Evaluation);
                    if j == seed_member {
                        statistics.seed_failures[FailureReason::Evaluation.index()] += 1;
                    }
                    continue;
                }
                statistics.valid_members[class.index()] += 1;
                statistics.reusing_members += u64::from(walked.reused_seed_steps);
                seed_member_valid |= j == seed_member;
                scratch.member_splats.push((
                    member_vertex.raster.to_array(),
                    to_linear_srgb(&walked.contribution, &walked.wavelengths)
                        .map(|channel| channel * context.film.member_scale(position_density)),
                ));
                scratch.member_densities.push(density);
            }
            Err(reason) => {
                statistics.fail(reason);
                if j == seed_member {
                    statistics.seed_failures[reason.index()] += 1;
                }
            }
        }
    }
    let member_rays = counters.rays() - rays_before;
    statistics.member_rays += member_rays;
    if let Some(started) = timed {
        statistics.timed_members += member_count as u64;
        statistics.timed_member_nanoseconds += started.elapsed().as_nanos() as u64;
    }
    scratch.probe_dimensions = probe;
    scratch.breakup_weights = seed_breakup_weights;
    scratch.member_breakup_weights = member_breakup_weights;
    if !seed_member_valid {
        statistics.empty_explorations += 1;
        return false;
    }
    member_weights(&scratch.member_densities, &mut scratch.weights);
    if let Some(pilot) = &mut scratch.pilot {
        pilot.add_exploration(
            class,
            &scratch.member_splats,
            &scratch.weights,
            (member_rays as usize + walked_vertices) as f64,
        );
    }
    for ((raster, rgb), weight) in scratch.member_splats.iter().zip(&scratch.weights) {
        let weight = *weight as f32;
        let _ = splats.add(*raster, rgb.map(|channel| channel * weight));
    }
    if let Some(density) = &mut scratch.density {
        let (buffer, value) = match class {
            PathClass::Normal => (&mut density.rgb, [1.0, 0.0, 0.0]),
            PathClass::Caustic => (&mut density.rgb, [0.0, 1.0, 0.0]),
            PathClass::DepthOfField => (&mut density.rgb, [0.0, 0.0, 1.0]),
            PathClass::NextEvent => (&mut density.next_event, [1.0; 3]),
        };
        for (raster, _) in &scratch.member_splats {
            let _ = buffer.add(*raster, value);
        }
    }
    true
}

/// Whether `member`'s vertices give the breakup CDF and the explored
/// dimensions the same inputs as `seed`'s: the same sampled lobes, the same
/// roughness (bit for bit) and the same media, vertex by vertex
/// ([`breakup_weights`] and [`explored_dimensions`] read nothing else of
/// the vertices).
fn same_breakup_inputs(member: &[SurfaceVertex], seed: &[SurfaceVertex]) -> bool {
    member.len() == seed.len()
        && member.iter().zip(seed).all(|(member, seed)| {
            member.sampled == seed.sampled
                && member.roughness.to_bits() == seed.roughness.to_bits()
                && member.medium == seed.medium
        })
}

/// A key for what every member of an exploration's set shares, and
/// nothing else: the render's seed, the progression, the class, the
/// breakup vertex, and per explored dimension its kind and the tile the
/// seed's number lies in on the jittered grid (modulo the tile count: the
/// tile the grid wraps around is one tile). The lattice-dimension scramble
/// is keyed on it, so a member, had it been the seed, would draw the same
/// scramble and so have the same set: Eq. (9)'s weights then sum to one
/// for every set, not only on average over a per-seed hash.
fn set_key(
    render_seed: u64,
    sample_index: u64,
    class: PathClass,
    breakup: usize,
    dimensions: &[ExploredDimension],
    seed_numbers: &[f64],
    jitter: &[f64],
) -> u64 {
    let mut key = hash3(
        render_seed ^ SCRAMBLE_KEY,
        sample_index,
        class.index() as u64,
    );
    key = hash2(key, breakup as u64);
    for ((dimension, number), jitter) in dimensions.iter().zip(seed_numbers).zip(jitter) {
        let tiles = f64::from(dimension.tiles);
        let tile = ((number - jitter) * tiles).floor().rem_euclid(tiles) as u64;
        key = hash3(key, dimension.kind.key(), tile);
    }
    key
}

/// The paper's proposed remedy against visible lattice structure (Sec. 5),
/// applied to `lattice_dimension` (the identity on entry) with the random
/// choices drawn from the set's `key` ([`set_key`]):
/// [`LatticeScramble::Image`] swaps the two image-plane dimensions' lattice
/// dimensions with those of two other explored dimensions chosen at random,
/// [`LatticeScramble::All`] permutes the whole mapping uniformly
/// (Fisher–Yates), [`LatticeScramble::None`] leaves it.
fn scramble_lattice_dimensions(
    scramble: LatticeScramble,
    dimensions: &[ExploredDimension],
    lattice_dimension: &mut [usize],
    key: u64,
) {
    match scramble {
        LatticeScramble::None => {}
        LatticeScramble::Image => swap_image_lattice_dimensions(dimensions, lattice_dimension, key),
        LatticeScramble::All => {
            // Fisher–Yates: position i takes one of positions 0..=i.
            for i in (1..lattice_dimension.len()).rev() {
                let j = below(hash2(key, i as u64), i + 1);
                lattice_dimension.swap(i, j);
            }
        }
    }
}

/// [`LatticeScramble::Image`]: the two image-plane dimensions take the
/// lattice dimensions of two other explored dimensions chosen at random
/// (and those take theirs); nothing when fewer than two others exist.
fn swap_image_lattice_dimensions(
    dimensions: &[ExploredDimension],
    lattice_dimension: &mut [usize],
    key: u64,
) {
    let image: Vec<usize> = (0..dimensions.len())
        .filter(|&i| matches!(dimensions[i].kind, DimensionKind::Image(_)))
        .collect();
    let mut others: Vec<usize> = (0..dimensions.len())
        .filter(|&i| !matches!(dimensions[i].kind, DimensionKind::Image(_)))
        .collect();
    if image.len() != 2 || others.len() < 2 {
        return;
    }
    for (round, &image_index) in image.iter().enumerate() {
        let pick = (to_unit_f64(hash2(key, round as u64)) * others.len() as f64) as usize;
        let other = others.swap_remove(pick.min(others.len() - 1));
        lattice_dimension.swap(image_index, other);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampler::{Randomization, SamplerKind};
    use crate::scene::builtin::builtin_scene;
    use qmc::lattice_table::LQMC_MAX_DIMENSIONS;

    /// The value a seed records for an event (the path tracer's, `volpath`'s
    /// through media) is the value LQMC's value walk computes for the same
    /// path: the unexplored events and the explored sets weigh the
    /// techniques alike, which the estimator's unbiasedness needs.
    #[test]
    fn recorded_event_values_are_the_value_walks() {
        for name in ["cornell-box", "translucent-spheres", "volumetric-caustic"] {
            let mut description = builtin_scene(name).unwrap();
            description.camera.resolution = [16, 12];
            let scene = Scene::build(&description).unwrap();
            let settings = LqmcSettings::default();
            let context = LqmcContext {
                scene: &scene,
                settings: &settings,
                path_settings: PathSettings::default(),
                seed: 3,
                film: SeedFilm::new(&scene, false),
                screen_seeds: false,
            };
            let mut sampler = SamplerKind::Independent
                .create(3, Randomization::Seeded, (16, 12), 4, None)
                .unwrap();
            let mut seed_path = SeedPath::default();
            let mut counters = TraceCounters::default();
            let mut compared = 0;
            for y in 0..12 {
                for x in 0..16 {
                    for sample_index in 0..4 {
                        sampler.start_pixel_sample((x, y), sample_index);
                        let film = sampler.get_2d(layout::FILM);
                        let raster = context.film.seed_raster(&scene, (x, y), film);
                        trace_seed_path(
                            &scene,
                            &context.path_settings,
                            raster,
                            &mut *sampler,
                            &mut counters,
                            &mut seed_path,
                        );
                        let camera = seed_path.camera.as_ref().unwrap();
                        let wavelengths = SampledWavelengths::sample_visible(camera.u_wavelength);
                        for (event, recorded) in
                            seed_path.events.iter().zip(&seed_path.event_values)
                        {
                            let Some((recorded, _)) = recorded else {
                                continue;
                            };
                            let vertices = &seed_path.vertices[event.vertex_range()];
                            let walked = walk(
                                &scene,
                                &context.path_settings,
                                &seed_walk_input(
                                    &context,
                                    camera,
                                    vertices,
                                    event,
                                    Some(wavelengths),
                                ),
                                &mut *sampler,
                                &mut SegmentReuse::None,
                            );
                            let walked = walked
                                .map_or(SampledSpectrum::zero(), |walked| walked.contribution);
                            for lane in 0..crate::spectrum::SPECTRUM_SAMPLE_COUNT {
                                let (a, b) = (recorded[lane], walked[lane]);
                                assert!(
                                    (a - b).abs() <= 2e-3 * a.abs().max(b.abs()) + 1e-6,
                                    "{name} pixel ({x}, {y}) sample {sample_index}: \
                                     recorded {recorded:?}, walked {walked:?}, {event:?}"
                                );
                            }
                            compared += 1;
                        }
                    }
                }
            }
            assert!(compared > 10, "{name}: {compared} events compared");
        }
    }

    /// `count` explored dimensions as a deep path with a thin lens has
    /// them: lens, wavelength, image, then outgoing directions.
    fn deep_path_dimensions(count: usize) -> Vec<ExploredDimension> {
        let kinds = [
            DimensionKind::Lens(0),
            DimensionKind::Lens(1),
            DimensionKind::Wavelength,
            DimensionKind::Image(0),
            DimensionKind::Image(1),
        ]
        .into_iter()
        .chain((0..).map(|index| DimensionKind::Direction {
            vertex: index / 2,
            axis: index % 2,
        }));
        kinds
            .zip([2, 2, 1, 24, 18].into_iter().chain(std::iter::repeat(155)))
            .take(count)
            .map(|(kind, tiles)| ExploredDimension { kind, tiles })
            .collect()
    }

    /// The lattice dimensions of `dimensions` under `scramble` with `key`.
    fn scrambled(
        scramble: LatticeScramble,
        dimensions: &[ExploredDimension],
        key: u64,
    ) -> Vec<usize> {
        let mut lattice_dimension: Vec<usize> = (0..dimensions.len()).collect();
        scramble_lattice_dimensions(scramble, dimensions, &mut lattice_dimension, key);
        lattice_dimension
    }

    /// The full scramble is a permutation of the lattice dimensions for
    /// every dimension count, uniform over the permutations (all 6 of
    /// three dimensions about equally often); `image` moves only the image
    /// pair and two others, `none` nothing.
    #[test]
    fn the_full_scramble_is_a_uniform_permutation() {
        for count in 1..=LQMC_MAX_DIMENSIONS {
            let dimensions = deep_path_dimensions(count);
            for key in 0..200u64 {
                let key = hash2(key, count as u64);
                let mut permutation = scrambled(LatticeScramble::All, &dimensions, key);
                permutation.sort_unstable();
                assert_eq!(permutation, (0..count).collect::<Vec<_>>(), "{count}");
                let image = scrambled(LatticeScramble::Image, &dimensions, key);
                let moved = image.iter().enumerate().filter(|(i, d)| i != *d).count();
                assert!(moved == 0 || moved == 4, "{image:?}");
                let none = scrambled(LatticeScramble::None, &dimensions, key);
                assert_eq!(none, (0..count).collect::<Vec<_>>());
            }
        }
        let dimensions = deep_path_dimensions(3);
        let mut counts = std::collections::HashMap::new();
        let draws = 6000u64;
        for key in 0..draws {
            *counts
                .entry(scrambled(LatticeScramble::All, &dimensions, hash2(key, 77)))
                .or_insert(0u64) += 1;
        }
        assert_eq!(counts.len(), 6, "{counts:?}");
        // Binomial(6000, 1/6): standard deviation 28.9; 5 of them.
        for (permutation, count) in &counts {
            assert!(count.abs_diff(draws / 6) < 145, "{permutation:?}: {count}");
        }
        // Large dimension counts move most dimensions.
        let dimensions = deep_path_dimensions(LQMC_MAX_DIMENSIONS);
        let moved = scrambled(LatticeScramble::All, &dimensions, 12345)
            .iter()
            .enumerate()
            .filter(|(i, d)| i != *d)
            .count();
        assert!(moved > LQMC_MAX_DIMENSIONS / 2, "{moved}");
    }

    /// Every member of a set, had it been the seed, draws the set's key and
    /// so its scramble, and finds the same set (the same members, up to
    /// rounding): Eq. (9)'s weights are a partition of unity for every set.
    /// A seed in another tile, progression or class draws another key.
    #[test]
    fn members_of_a_set_draw_its_scramble_and_find_the_same_set() {
        use super::super::lattice_step::{LatticeMembers, TileGrid, lattice_members};
        use super::super::statistics::ClosestPointTiming;
        let dimensions = deep_path_dimensions(7);
        let tiles: Vec<u32> = dimensions.iter().map(|dimension| dimension.tiles).collect();
        let jitter: Vec<f64> = dimensions
            .iter()
            .enumerate()
            .map(|(index, dimension)| to_unit_f64(hash2(9, index as u64)) / dimension.tiles as f64)
            .collect();
        let entry = lqmc_lattice_entry(97, dimensions.len()).unwrap();
        let key_of =
            |numbers: &[f64]| set_key(5, 3, PathClass::Normal, 2, &dimensions, numbers, &jitter);
        let members_of = |numbers: &[f64], lattice_dimension: &[usize]| {
            let mut members = LatticeMembers::default();
            lattice_members(
                entry,
                &TileGrid {
                    tiles: &tiles,
                    jitter: &jitter,
                    lattice_dimension,
                },
                numbers,
                &mut Vec::new(),
                &mut members,
                &mut ClosestPointTiming::default(),
            )
            .unwrap();
            members.numbers
        };
        // Rows sorted, to compare sets.
        let sorted_rows = |numbers: Vec<f64>| {
            let mut rows: Vec<Vec<f64>> = numbers
                .chunks(dimensions.len())
                .map(<[f64]>::to_vec)
                .collect();
            rows.sort_by(|a, b| a.partial_cmp(b).unwrap());
            rows
        };
        for seed_index in 0..4u64 {
            // The last direction's number near 0, below its jitter: its
            // tile wraps around.
            let seed: Vec<f64> = (0..dimensions.len())
                .map(|d| {
                    if d + 1 == dimensions.len() && seed_index == 0 {
                        1e-6
                    } else {
                        to_unit_f64(hash3(seed_index, d as u64, 1))
                    }
                })
                .collect();
            let key = key_of(&seed);
            let mapping = scrambled(LatticeScramble::All, &dimensions, key);
            let set = members_of(&seed, &mapping);
            let set_rows = sorted_rows(set.clone());
            for member in set.chunks(dimensions.len()) {
                assert_eq!(key_of(member), key, "seed {seed_index}: {member:?}");
                let member_rows = sorted_rows(members_of(member, &mapping));
                for (a, b) in set_rows.iter().zip(&member_rows) {
                    for (x, y) in a.iter().zip(b) {
                        let distance = (x - y).abs();
                        assert!(distance.min(1.0 - distance) < 1e-9, "{a:?} against {b:?}");
                    }
                }
            }
            // Another tile of the image's x, another progression or class:
            // another key.
            let mut moved = seed.clone();
            moved[3] = (moved[3] + 1.0 / 24.0) % 1.0;
            assert_ne!(key_of(&moved), key);
            assert_ne!(
                set_key(5, 4, PathClass::Normal, 2, &dimensions, &seed, &jitter),
                key
            );
            assert_ne!(
                set_key(5, 3, PathClass::Caustic, 2, &dimensions, &seed, &jitter),
                key
            );
        }
    }
}
