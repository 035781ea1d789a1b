//! Which of the classes marked for exploration a render explores, measured
//! by a pilot before it starts (`--class-selection measured`, the default).
//!
//! Exploring a class pays at equal time only if the variance it removes
//! from the image is worth what its members cost. Both sides depend on
//! where the members land: a set spread over several pixels smooths a rare
//! bright path (a caustic) over its neighbourhood, but it also takes from
//! each pixel the stratification of its own seeds, and a set that stays in
//! one pixel only averages its members. So the pilot measures the image
//! itself: it renders [`PILOT_BLOCKS`]² blocks of [`PILOT_BLOCK`]² pixels
//! spread over the image, [`PILOT_PASSES`] passes of one seed per pixel,
//! exploring every candidate class, and keeps per pixel and pass
//!
//! - the path-traced image: each seed's value as the path tracer adds it
//!   (its unexplored events plus its own value of each explored one) in its
//!   own pixel;
//! - per class `c`, the image that exploring `c` alone gives: the path-traced
//!   one without the seeds' own values of `c`'s explored events, with the
//!   splats of `c`'s sets in the pixels they land in.
//!
//! `V` and `V_c` are the variances of a pixel across the passes, the mean
//! over the blocks' inner pixels ([`PILOT_MARGIN`] pixels from a block's
//! edge, where sets seeded outside the block would land too) and the
//! channels. `T` is a seed's cost and `t_c` what `c`'s members add per
//! seed, in rays plus evaluated vertices (a count, not a time, so that the
//! choice and the image do not depend on the machine or its load). At equal
//! cost the mean squared error is proportional to variance times cost, so
//! `c` is explored iff `V_c (T + t_c) < V T`, each class judged alone.
//!
//! Unbiased: the pilot's sampler has its own seed (an independent
//! randomization; with `--randomize none` its points are the render's
//! first ones) and its samples are not in the image, so the choice is a
//! constant of the render, which then explores a fixed set of classes as
//! `--class-selection fixed` would. Deterministic: the pilot's sums are
//! taken in a fixed order of blocks, whatever the threads. The pilot's time
//! counts in a render's time budget; blocks not begun when it runs out (or
//! the render is interrupted) are left out.

use super::classification::PathClass;
use super::exploration::{LqmcContext, LqmcScratch, render_pixel_sample};
use super::seed_film::SeedFilm;
use super::seed_screen::screens_seeds;
use super::settings::LqmcSettings;
use super::statistics::LqmcStatistics;
use crate::film::{FilmTile, PixelBounds, SplatBuffer};
use crate::integrators::TraceCounters;
use crate::integrators::driver::{RenderError, RunControl, UnitOutput};
use crate::integrators::estimator::PathSettings;
use crate::scene::Scene;
use rayon::prelude::*;

/// Blocks across (and down) the image.
pub const PILOT_BLOCKS: u32 = 3;

/// A block's side in pixels (smaller where the image is).
pub const PILOT_BLOCK: u32 = 20;

/// Pixels at a block's edge left out of its variances.
pub const PILOT_MARGIN: u32 = 5;

/// Seeds per pixel of each of the pilot's two replications.
pub const PILOT_PASSES: u64 = 4;

/// Classes with fewer explorations in the pilot are too rare to measure:
/// they keep their setting.
pub const PILOT_MIN_EXPLORATIONS: u64 = 16;

/// Keys the pilot's seed apart from the render's.
const PILOT_SEED_KEY: u64 = 0x7069_6c6f_7400_0000;

/// What the pilot's seeds and explorations give, filled by
/// [`super::exploration`] when a scratch carries one.
#[derive(Debug, Default, Clone)]
pub struct PilotRecord {
    /// The current seed's value as the path tracer adds it (linear sRGB).
    pub seed_value: [f64; 3],
    /// The current seed's own values of its explored events, per class
    /// ([`PathClass::index`]).
    pub explored_seed_value: [[f64; 3]; 4],
    /// Per class: the splats of its sets (raster position, weighted value)
    /// since the pilot last took them.
    pub splats: [Vec<([f32; 2], [f32; 3])>; 4],
    /// Per class: its members' cost in rays plus walked vertices.
    pub member_cost: [f64; 4],
    /// Per class: explorations.
    pub explorations: [u64; 4],
}

impl PilotRecord {
    /// Adds `rgb` to the current seed's value.
    #[inline]
    pub fn add_seed_value(&mut self, rgb: [f32; 3]) {
        add_to(&mut self.seed_value, &rgb.map(f64::from), 1.0);
    }

    /// Adds the seed's own value `rgb` of an explored event of `class`.
    pub fn add_explored_seed_value(&mut self, class: PathClass, rgb: [f32; 3]) {
        let rgb = rgb.map(f64::from);
        add_to(&mut self.seed_value, &rgb, 1.0);
        add_to(&mut self.explored_seed_value[class.index()], &rgb, 1.0);
    }

    /// Records an exploration of `class`: its members' splats (raster
    /// position, value) with their weights, and the members' cost.
    pub fn add_exploration(
        &mut self,
        class: PathClass,
        splats: &[([f32; 2], [f32; 3])],
        weights: &[f64],
        cost: f64,
    ) {
        let index = class.index();
        for ((raster, rgb), &weight) in splats.iter().zip(weights) {
            if weight > 0.0 {
                self.splats[index].push((*raster, rgb.map(|value| value * weight as f32)));
            }
        }
        self.member_cost[index] += cost;
        self.explorations[index] += 1;
    }
}

/// One class's measurement and the choice made from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClassMeasurement {
    /// The class.
    pub class: PathClass,
    /// Explorations in the pilot.
    pub explorations: u64,
    /// `V_c / V`: the image's variance with the class explored over the
    /// path-traced image's.
    pub variance_ratio: f64,
    /// `(T + t_c) / T`: the cost with the class explored over the seeds'.
    pub cost_ratio: f64,
    /// Whether the pilot explored it often enough to judge
    /// ([`PILOT_MIN_EXPLORATIONS`]); if not, it keeps its setting.
    pub measured: bool,
    /// Whether the render explores it.
    pub explored: bool,
}

/// What the pilot measured and chose.
#[derive(Debug, Clone, PartialEq)]
pub struct ClassSelectionReport {
    /// Pilot pixels whose variance was measured.
    pub measured_pixels: u64,
    /// Pilot seeds.
    pub pilot_seeds: u64,
    /// `V`: the variance of the path-traced image's mean of
    /// [`PILOT_PASSES`] samples per pixel.
    pub path_traced_variance: f64,
    /// `T`: a seed's cost in rays plus vertices.
    pub seed_cost: f64,
    /// The candidate classes.
    pub classes: Vec<ClassMeasurement>,
}

impl ClassSelectionReport {
    /// The report's lines for `--stats` and the log.
    pub fn lines(&self) -> Vec<String> {
        let mut lines = vec![format!(
            "LQMC class selection (pilot: {} seeds, variance over {} pixels): path-traced variance {:.4e}, a seed's cost {:.1} rays and vertices",
            self.pilot_seeds, self.measured_pixels, self.path_traced_variance, self.seed_cost
        )];
        for class in &self.classes {
            lines.push(format!(
                "  {:<8} {:>6} explorations: variance x{:.3}, cost x{:.3}, error at equal cost x{:.3}: {}",
                class.class.name(),
                class.explorations,
                class.variance_ratio,
                class.cost_ratio,
                class.variance_ratio * class.cost_ratio,
                match (class.measured, class.explored) {
                    (false, _) => "too rare to measure: explored",
                    (true, true) => "explored",
                    (true, false) => "not explored",
                }
            ));
        }
        lines
    }
}

/// Whether exploring pays: variance times cost falls.
pub fn exploration_pays(variance_ratio: f64, cost_ratio: f64) -> bool {
    variance_ratio * cost_ratio < 1.0
}

/// Runs the pilot for the classes `settings` marks for exploration and
/// returns the settings with those that do not pay switched off.
pub fn select_classes(
    scene: &Scene,
    settings: &LqmcSettings,
    path_settings: PathSettings,
    run: &RunControl<'_>,
) -> Result<(LqmcSettings, ClassSelectionReport), RenderError> {
    let [width, height] = scene.camera.resolution();
    let pilot_seed = qmc::hash::hash2(run.seed, PILOT_SEED_KEY);
    // Two independent randomizations: the spread of their means is the
    // error of a mean of PILOT_PASSES samples, quasi-Monte Carlo's included.
    let prototypes = [
        run.sampler.create(
            pilot_seed,
            run.randomization,
            (width, height),
            PILOT_PASSES,
            None,
        )?,
        run.sampler.create(
            qmc::hash::hash2(pilot_seed, 1),
            run.randomization,
            (width, height),
            PILOT_PASSES,
            None,
        )?,
    ];
    let context = LqmcContext {
        scene,
        settings,
        path_settings,
        seed: pilot_seed,
        film: SeedFilm::new(scene, path_settings.splat_film),
        screen_seeds: screens_seeds(scene, settings),
    };
    let blocks: Vec<PixelBounds> = pilot_blocks(width, height);
    let block_results: Vec<BlockPilot> = blocks
        .par_iter()
        .map(|bounds| {
            // Out of time or interrupted: the blocks not begun are left
            // out (a render with a time budget depends on the time anyway).
            if run.out_of_time() {
                return BlockPilot::default();
            }
            let mut samplers = prototypes
                .each_ref()
                .map(|prototype| prototype.clone_sampler());
            pilot_block(&context, *bounds, &mut samplers)
        })
        .collect();
    // Summed in block order: the same sums whatever the threads.
    let mut total = BlockPilot::default();
    for block in &block_results {
        total.add(block);
    }
    let seeds = total.seeds.max(1) as f64;
    let pixels = total.measured_pixels.max(1) as f64;
    let path_traced_variance = total.path_traced_variance / pixels;
    let seed_cost = total.seed_cost / seeds;
    let mut selected = *settings;
    let mut classes = Vec::new();
    for class in PathClass::ALL {
        if !settings.class_parameters(class).explore {
            continue;
        }
        let index = class.index();
        let variance_ratio = if path_traced_variance > 0.0 {
            total.class_variance[index] / pixels / path_traced_variance
        } else {
            1.0
        };
        let cost_ratio = if seed_cost > 0.0 {
            1.0 + total.member_cost[index] / seeds / seed_cost
        } else {
            1.0
        };
        let measured = total.explorations[index] >= PILOT_MIN_EXPLORATIONS;
        let explored = !measured || exploration_pays(variance_ratio, cost_ratio);
        selected.class_parameters_mut(class).explore = explored;
        classes.push(ClassMeasurement {
            class,
            explorations: total.explorations[index],
            variance_ratio,
            cost_ratio,
            measured,
            explored,
        });
    }
    let report = ClassSelectionReport {
        measured_pixels: total.measured_pixels,
        pilot_seeds: total.seeds,
        path_traced_variance,
        seed_cost,
        classes,
    };
    Ok((selected, report))
}

/// The pilot's blocks: up to [`PILOT_BLOCKS`]² blocks of [`PILOT_BLOCK`]²
/// pixels, centred in equal parts of the image (one block of the whole
/// image where it is smaller than a block).
fn pilot_blocks(width: u32, height: u32) -> Vec<PixelBounds> {
    let axis = |size: u32| -> Vec<(usize, usize)> {
        if size <= PILOT_BLOCK {
            return vec![(0, size as usize)];
        }
        let count = PILOT_BLOCKS.min(size / PILOT_BLOCK).max(1);
        (0..count)
            .map(|index| {
                let centre = (2 * index + 1) * size / (2 * count);
                let start = centre
                    .saturating_sub(PILOT_BLOCK / 2)
                    .min(size - PILOT_BLOCK);
                (start as usize, (start + PILOT_BLOCK) as usize)
            })
            .collect()
    };
    let mut blocks = Vec::new();
    for &(y0, y1) in &axis(height) {
        for &(x0, x1) in &axis(width) {
            blocks.push(PixelBounds {
                min: [x0, y0],
                max: [x1, y1],
            });
        }
    }
    blocks
}

/// Renders one block's passes of both replications and returns its sums.
fn pilot_block(
    context: &LqmcContext<'_>,
    bounds: PixelBounds,
    samplers: &mut [Box<dyn crate::sampler::PixelSampler>; 2],
) -> BlockPilot {
    let [block_width, block_height] = bounds.size();
    let area = block_width * block_height;
    let mut scratch = LqmcScratch::default();
    scratch.pilot = Some(PilotRecord::default());
    let mut statistics = LqmcStatistics::default();
    let mut output = UnitOutput {
        tile: FilmTile::new(bounds),
        splats: SplatBuffer::new(),
        counters: TraceCounters::default(),
    };
    // Per pixel and replication: the sums over passes of the path-traced
    // image and of each class's image's difference from it.
    let mut path_traced = vec![[[0.0f64; 3]; 2]; area];
    let mut difference = vec![[[[0.0f64; 3]; 4]; 2]; area];
    let mut block = BlockPilot::default();
    let index_of = |x: usize, y: usize| (y - bounds.min[1]) * block_width + (x - bounds.min[0]);
    for (replication, sampler) in samplers.iter_mut().enumerate() {
        for pass in 0..PILOT_PASSES {
            for y in bounds.min[1]..bounds.max[1] {
                for x in bounds.min[0]..bounds.max[0] {
                    sampler.start_pixel_sample((x as u32, y as u32), pass);
                    let pilot = scratch.pilot.as_mut().expect("set above");
                    pilot.seed_value = [0.0; 3];
                    pilot.explored_seed_value = [[0.0; 3]; 4];
                    let member_cost_before: f64 = pilot.member_cost.iter().sum();
                    let before = output.counters;
                    render_pixel_sample(
                        context,
                        (x as u32, y as u32),
                        pass,
                        sampler.as_mut(),
                        &mut scratch,
                        &mut output,
                        &mut statistics,
                    );
                    let pilot = scratch.pilot.as_ref().expect("set above");
                    let index = index_of(x, y);
                    add_to(&mut path_traced[index][replication], &pilot.seed_value, 1.0);
                    for (class, own) in pilot.explored_seed_value.iter().enumerate() {
                        add_to(&mut difference[index][replication][class], own, -1.0);
                    }
                    let member_cost = pilot.member_cost.iter().sum::<f64>() - member_cost_before;
                    let closest = output.counters.closest_hit_rays - before.closest_hit_rays;
                    let shadow = output.counters.shadow_rays - before.shadow_rays;
                    // A closest hit is a ray and a vertex evaluated; the
                    // members' rays are in their cost already.
                    block.seed_cost += ((2 * closest + shadow) as f64 - member_cost).max(0.0);
                    block.seeds += 1;
                }
            }
            // The film's own splats are not the pilot's measure.
            output.splats.clear();
            let pilot = scratch.pilot.as_mut().expect("set above");
            for (class, splats) in pilot.splats.iter_mut().enumerate() {
                for (raster, rgb) in splats.drain(..) {
                    let (x, y) = (raster[0].floor(), raster[1].floor());
                    if x < bounds.min[0] as f32
                        || y < bounds.min[1] as f32
                        || x >= bounds.max[0] as f32
                        || y >= bounds.max[1] as f32
                    {
                        continue;
                    }
                    let rgb = rgb.map(f64::from);
                    add_to(
                        &mut difference[index_of(x as usize, y as usize)][replication][class],
                        &rgb,
                        1.0,
                    );
                }
            }
        }
    }
    let margin =
        if block_width > 2 * PILOT_MARGIN as usize && block_height > 2 * PILOT_MARGIN as usize {
            PILOT_MARGIN as usize
        } else {
            0
        };
    let passes = PILOT_PASSES as f64;
    // The variance of a mean from two independent ones: (a − b)² / 2, the
    // mean over channels.
    let variance = |a: [f64; 3], b: [f64; 3]| {
        (0..3)
            .map(|channel| ((a[channel] - b[channel]) / passes).powi(2) / 2.0)
            .sum::<f64>()
            / 3.0
    };
    for y in margin..block_height - margin {
        for x in margin..block_width - margin {
            let index = y * block_width + x;
            let [a, b] = path_traced[index];
            block.path_traced_variance += variance(a, b);
            for (class, class_variance) in block.class_variance.iter_mut().enumerate() {
                let with_class = |replication: usize| {
                    let mut sum = path_traced[index][replication];
                    add_to(&mut sum, &difference[index][replication][class], 1.0);
                    sum
                };
                *class_variance += variance(with_class(0), with_class(1));
            }
            block.measured_pixels += 1;
        }
    }
    let pilot = scratch.pilot.take().expect("set above");
    block.member_cost = pilot.member_cost;
    block.explorations = pilot.explorations;
    block
}

/// `total += factor · value`, per channel.
fn add_to(total: &mut [f64; 3], value: &[f64; 3], factor: f64) {
    for (total, value) in total.iter_mut().zip(value) {
        *total += factor * value;
    }
}

/// The pilot's sums over one block.
#[derive(Debug, Default, Clone)]
struct BlockPilot {
    seeds: u64,
    measured_pixels: u64,
    path_traced_variance: f64,
    class_variance: [f64; 4],
    seed_cost: f64,
    member_cost: [f64; 4],
    explorations: [u64; 4],
}

impl BlockPilot {
    fn add(&mut self, other: &BlockPilot) {
        self.seeds += other.seeds;
        self.measured_pixels += other.measured_pixels;
        self.path_traced_variance += other.path_traced_variance;
        self.seed_cost += other.seed_cost;
        for class in 0..4 {
            self.class_variance[class] += other.class_variance[class];
            self.member_cost[class] += other.member_cost[class];
            self.explorations[class] += other.explorations[class];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn exploring_pays_when_variance_times_cost_falls() {
        // Half the variance for a third more cost.
        assert!(exploration_pays(0.5, 4.0 / 3.0));
        // Four fifths of the variance for twice the cost.
        assert!(!exploration_pays(0.8, 2.0));
    }

    #[test]
    fn blocks_lie_inside_the_image() {
        for (width, height) in [(320, 240), (16, 12), (33, 100), (64, 64)] {
            let blocks = pilot_blocks(width, height);
            assert!(!blocks.is_empty());
            for block in &blocks {
                assert!(block.max[0] <= width as usize && block.max[1] <= height as usize);
                assert!(block.min[0] < block.max[0] && block.min[1] < block.max[1]);
            }
        }
        assert_eq!(pilot_blocks(320, 240).len(), 9);
        assert_eq!(pilot_blocks(320, 240)[4].min, [150, 110]);
        assert_eq!(pilot_blocks(16, 12).len(), 1);
    }
}
