//! Vertex connection and merging (Georgiev, Křivánek, Davidovič &
//! Slusallek 2012; SmallVCM): bidirectional path tracing whose camera
//! subpaths also merge with nearby light vertices of every light subpath of
//! the iteration, progressive photon mapping's density estimation, all
//! weighted by one multiple-importance heuristic.
//!
//! # An iteration
//!
//! Each pass of the splat driver is one iteration, one sample per pixel:
//!
//! 1. before the pass ([`SplatEstimator::begin_pass`]), one light subpath
//!    per pixel is traced by the path-space walk with the pixel sample's
//!    numbers (the light blocks of the layout, as BDPT's), and its vertices
//!    are kept; those that can be merged at (surfaces that are not purely
//!    specular) go into a hash grid of cell side 2r;
//! 2. per pixel, the camera subpath is traced, connected to the pixel's own
//!    light subpath by every BDPT strategy, and each of its vertices merges
//!    with the light vertices within r of it.
//!
//! The radius shrinks over the iterations, r_i = r₁ · i^((α−1)/2) (Knaus
//! & Zwicker 2011; SmallVCM's `r₁ / i^((1−α)/2)`), so the merges' bias
//! vanishes as the iterations grow: VCM is consistent, not unbiased. Each
//! merge is normalised by 1/(π r² N), N the light subpaths of the
//! iteration (the pixels), and every technique is weighted by the MIS of
//! [`super::bdpt::mis::technique_weight`] with η = π r² N.
//!
//! All subpaths of an iteration share its wavelengths (and its time, with
//! motion blur), taken from pixel (0, 0)'s numbers of that sample, so that
//! any light vertex can merge with any camera subpath; a merge with a light
//! subpath that dropped its secondary wavelengths (dispersion) is converted
//! with the hero wavelength only.
//!
//! # Modes (`--vcm-mode`)
//!
//! - `vcm`: every connection and every merge;
//! - `bpt`: connections only — BDPT with the iteration's shared
//!   wavelengths, equal to `bdpt` in expectation;
//! - `bpm`: bidirectional photon mapping, merges at every camera vertex and
//!   light reached by the camera subpath, weighted by MIS;
//! - `ppm`: progressive photon mapping, merges at the first camera vertex
//!   that is not purely specular, and light reached only through specular
//!   chains, no MIS.
//!
//! Participating media: the walks are volumetric and connections carry the
//! transmittance as in BDPT, but merging happens on surfaces only.

use super::bdpt::mis::{Strategies, VertexDensities};
use super::bdpt::{Bidirectional, BidirectionalScratch, LightOrigin};
use super::driver::{PassWork, PixelSampleIndex, SplatEstimator, render_splat_paths};
use super::path::PathSettings;
use super::path_space::{Scatterer, Vertex};
use super::{Integrator, IntegratorDetails, IntegratorRender, RenderError, RunControl};
use super::{MisHeuristic, TraceCounters};
use crate::film::SplatBuffer;
use crate::sampler::{PixelSampler, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;
use std::sync::{Arc, RwLock};

/// Which techniques a VCM render uses (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum VcmMode {
    /// Every connection and merge.
    #[default]
    Vcm,
    /// Connections only (BDPT).
    Bpt,
    /// Merges and light reached by the camera subpath, with MIS.
    Bpm,
    /// Merges at the first non-specular camera vertex, no MIS.
    Ppm,
}

impl VcmMode {
    /// Every mode with its command-line name.
    pub const ALL: [(VcmMode, &'static str); 4] = [
        (VcmMode::Vcm, "vcm"),
        (VcmMode::Bpt, "bpt"),
        (VcmMode::Bpm, "bpm"),
        (VcmMode::Ppm, "ppm"),
    ];

    /// The mode called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(m, _)| *m)
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(m, _)| *m == self).unwrap().1
    }

    /// Whether the mode connects subpaths.
    fn connects(self) -> bool {
        matches!(self, VcmMode::Vcm | VcmMode::Bpt)
    }

    /// Whether the mode merges.
    fn merges(self) -> bool {
        !matches!(self, VcmMode::Bpt)
    }
}

/// The options of VCM (defaults SmallVCM's).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VcmSettings {
    /// The techniques.
    pub mode: VcmMode,
    /// The first iteration's merging radius as a fraction of the radius of
    /// the scene's bounding sphere (SmallVCM: 0.003).
    pub radius_fraction: f32,
    /// The radius reduction's α in (0, 1]: r_i = r₁ · i^((α−1)/2)
    /// (SmallVCM: 0.75; 1 keeps the radius).
    pub alpha: f32,
}

impl Default for VcmSettings {
    fn default() -> Self {
        Self {
            mode: VcmMode::Vcm,
            radius_fraction: 0.003,
            alpha: 0.75,
        }
    }
}

impl VcmSettings {
    /// The merging radius of iteration `iteration` (from 1) for a scene of
    /// bounding radius `scene_radius`.
    pub fn radius(&self, scene_radius: f32, iteration: u64) -> f32 {
        let first = self.radius_fraction * scene_radius;
        first * (iteration as f64).powf(f64::from(self.alpha - 1.0) / 2.0) as f32
    }
}

/// A light subpath's vertex as an iteration keeps it for merging: what a
/// merge and its weight need (not the BSDF: a merge evaluates the camera
/// vertex's), about a quarter of a [`Vertex`].
#[derive(Debug, Clone, Copy)]
pub(crate) struct LightVertexRecord {
    /// The point.
    pub point: Vec3,
    /// The geometric normal (zero in a medium).
    pub geometric_normal: Vec3,
    /// Unit direction towards the previous vertex: where the light came
    /// from.
    pub wo: Vec3,
    /// The subpath's throughput on arrival (over its origin's
    /// `beta_scale`).
    pub beta: SampledSpectrum,
    /// [`Vertex::pdf_forward`].
    pub pdf_forward: f32,
    /// [`Vertex::arrival_transmittance`].
    pub arrival_transmittance: SampledSpectrum,
    /// [`Vertex::extinction`].
    pub extinction: SampledSpectrum,
    /// [`Vertex::spectral_density_ratio`].
    pub spectral_density_ratio: SampledSpectrum,
    /// Its densities on the subpath, as BDPT's weights see them.
    pub densities: VertexDensities,
}

impl LightVertexRecord {
    /// The record of `vertex`, whose densities on its subpath are
    /// `densities`.
    fn new(vertex: &Vertex, densities: VertexDensities) -> Self {
        Self {
            point: vertex.point,
            geometric_normal: vertex.geometric_normal,
            wo: vertex.wo,
            beta: vertex.beta,
            pdf_forward: vertex.pdf_forward,
            arrival_transmittance: vertex.arrival_transmittance,
            extinction: vertex.extinction,
            spectral_density_ratio: vertex.spectral_density_ratio,
            densities,
        }
    }
}

/// A light subpath of an iteration, kept for the camera subpaths' merges.
#[derive(Debug, Clone, Copy)]
pub(crate) struct StoredLightPath {
    /// Its origin on the light (`None`: no light emits).
    pub origin: Option<LightOrigin>,
    /// Its vertices: `first .. first + count` of the store's.
    first: u32,
    count: u32,
    /// Its walk dropped the secondary wavelengths.
    pub secondary_terminated: bool,
}

/// An iteration's light subpaths, one per pixel sample, and a hash grid
/// over the vertices that can be merged at.
pub(crate) struct LightStore {
    /// The light subpaths, in tile order.
    paths: Vec<StoredLightPath>,
    /// Every light subpath's vertices.
    records: Vec<LightVertexRecord>,
    /// Per vertex, the index of its path.
    vertex_path: Vec<u32>,
    /// The grid over the mergeable vertices (empty without merging).
    grid: HashGrid,
}

impl LightStore {
    /// The vertices of `path`.
    pub fn records_of(&self, path: &StoredLightPath) -> &[LightVertexRecord] {
        &self.records[path.first as usize..(path.first + path.count) as usize]
    }

    /// Calls `visit(path, k)` for every mergeable light vertex within the
    /// grid's radius of `point`: vertex `k` of `path`.
    pub fn for_each_near(&self, point: Vec3, mut visit: impl FnMut(&StoredLightPath, usize)) {
        let radius_squared = self.grid.radius * self.grid.radius;
        self.grid.for_each_candidate(point, |index, candidate| {
            if (candidate - point).length_squared() <= radius_squared {
                let path = &self.paths[self.vertex_path[index as usize] as usize];
                visit(path, (index - path.first) as usize);
            }
        });
    }

    /// The bytes the store holds (vertices, paths, grid).
    fn bytes(&self) -> usize {
        self.records.capacity() * std::mem::size_of::<LightVertexRecord>()
            + self.paths.capacity() * std::mem::size_of::<StoredLightPath>()
            + self.vertex_path.capacity() * 4
            + self.grid.bytes()
    }
}

/// A hash grid over points (SmallVCM's): cells of side 2r hashed into
/// buckets, the points sorted by bucket; a query visits the 2 × 2 × 2 cells
/// nearest its point, which hold every point within r. Queries are cache
/// misses (a camera vertex's buckets are anywhere in memory), so: four
/// buckets per point (the power of two above), few of them occupied, with a
/// bitmap of the occupied ones small enough for the cache, checked first;
/// and the points' positions kept with their indices, so a query reads
/// only its buckets and touches a record only for a point within r.
#[derive(Debug, Default)]
struct HashGrid {
    radius: f32,
    inverse_cell_size: f32,
    /// One bit per bucket: whether it holds a point.
    occupied: Vec<u64>,
    /// Per bucket, the end of its points in `entries` (its start is the
    /// previous bucket's end).
    bucket_ends: Vec<u32>,
    /// The points (index and position), by bucket.
    entries: Vec<(u32, Vec3)>,
}

impl HashGrid {
    /// The grid of radius `radius` over `points` (index, position).
    fn build(points: &[(u32, Vec3)], radius: f32) -> Self {
        let buckets = (4 * points.len()).max(1).next_power_of_two();
        let inverse_cell_size = 1.0 / (2.0 * radius);
        let mut grid = HashGrid {
            radius,
            inverse_cell_size,
            occupied: vec![0; buckets.div_ceil(64)],
            bucket_ends: vec![0; buckets],
            entries: vec![(0, Vec3::ZERO); points.len()],
        };
        let bucket_of = |point: Vec3| grid.bucket(grid.cell(point));
        let point_buckets: Vec<u32> = points.iter().map(|&(_, p)| bucket_of(p)).collect();
        for &bucket in &point_buckets {
            grid.bucket_ends[bucket as usize] += 1;
            grid.occupied[bucket as usize / 64] |= 1 << (bucket % 64);
        }
        let mut sum = 0;
        for end in grid.bucket_ends.iter_mut() {
            sum += *end;
            *end = sum;
        }
        // Fill from the back, so each bucket keeps the points' order.
        let mut next = grid.bucket_ends.clone();
        for (&point, &bucket) in points.iter().zip(&point_buckets).rev() {
            next[bucket as usize] -= 1;
            grid.entries[next[bucket as usize] as usize] = point;
        }
        grid
    }

    /// The integer cell of `point`.
    fn cell(&self, point: Vec3) -> [i32; 3] {
        let scaled = point * self.inverse_cell_size;
        [
            scaled.x.floor() as i32,
            scaled.y.floor() as i32,
            scaled.z.floor() as i32,
        ]
    }

    /// The bucket of a cell (the hash of Teschner et al. 2003, as
    /// SmallVCM's).
    fn bucket(&self, cell: [i32; 3]) -> u32 {
        let hash = (cell[0] as u32).wrapping_mul(73_856_093)
            ^ (cell[1] as u32).wrapping_mul(19_349_663)
            ^ (cell[2] as u32).wrapping_mul(83_492_791);
        // The number of buckets is a power of two.
        hash & (self.bucket_ends.len() as u32 - 1)
    }

    /// Calls `visit` with every point (index, position) in the buckets of
    /// the 2 × 2 × 2 cells nearest `point`, each bucket once.
    fn for_each_candidate(&self, point: Vec3, mut visit: impl FnMut(u32, Vec3)) {
        if self.entries.is_empty() {
            return;
        }
        let scaled = point * self.inverse_cell_size;
        let cell = self.cell(point);
        // Per axis, the cell and its neighbour on the side of the point.
        let other: [i32; 3] = std::array::from_fn(|axis| {
            let fraction = scaled[axis] - cell[axis] as f32;
            if fraction < 0.5 {
                cell[axis] - 1
            } else {
                cell[axis] + 1
            }
        });
        let mut visited = [u32::MAX; 8];
        let mut count = 0;
        for corner in 0..8 {
            let candidate = std::array::from_fn(|axis| {
                if corner >> axis & 1 == 0 {
                    cell[axis]
                } else {
                    other[axis]
                }
            });
            let bucket = self.bucket(candidate);
            if self.occupied[bucket as usize / 64] & (1 << (bucket % 64)) == 0
                || visited[..count].contains(&bucket)
            {
                continue;
            }
            visited[count] = bucket;
            count += 1;
            let start = if bucket == 0 {
                0
            } else {
                self.bucket_ends[bucket as usize - 1]
            };
            for &(index, position) in
                &self.entries[start as usize..self.bucket_ends[bucket as usize] as usize]
            {
                visit(index, position);
            }
        }
    }

    fn bytes(&self) -> usize {
        self.bucket_ends.capacity() * 4
            + self.occupied.capacity() * 8
            + self.entries.capacity() * std::mem::size_of::<(u32, Vec3)>()
    }
}

/// What a camera subpath of an iteration needs of it.
pub(crate) struct MergingPass<'a> {
    /// The iteration's wavelengths.
    pub wavelengths: SampledWavelengths,
    /// The iteration's time sample (0.5 without motion blur).
    pub time_sample: f32,
    /// The techniques and η.
    pub strategies: Strategies,
    /// Photon mapping: merge at the first non-specular vertex, no MIS.
    pub first_merge_only: bool,
    /// 1 / (π r² N).
    pub normalisation: f32,
    /// The light subpaths.
    pub lights: &'a LightStore,
}

/// An iteration: its shared numbers and its light subpaths.
struct Iteration {
    wavelengths: SampledWavelengths,
    time_sample: f32,
    strategies: Strategies,
    normalisation: f32,
    lights: LightStore,
}

/// Vertex connection and merging.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VcmIntegrator {
    vcm: VcmSettings,
    settings: PathSettings,
}

impl VcmIntegrator {
    /// VCM with its options `vcm` and the shared path settings.
    pub fn new(vcm: VcmSettings, settings: PathSettings) -> Self {
        Self { vcm, settings }
    }
}

/// The splat estimator of a VCM render.
struct VcmEstimator<'a> {
    bidirectional: Bidirectional<'a>,
    vcm: VcmSettings,
    heuristic: MisHeuristic,
    scene_radius: f32,
    resolution: [usize; 2],
    /// The current iteration, set before its pass.
    iteration: RwLock<Option<Arc<Iteration>>>,
    /// Light vertices stored, the largest store's bytes, and iterations.
    light_pass: RwLock<LightPassStatistics>,
}

#[derive(Debug, Clone, Copy, Default)]
struct LightPassStatistics {
    iterations: u64,
    light_vertices: u64,
    largest_store_bytes: usize,
    first_radius: f32,
    last_radius: f32,
}

/// A tile's share of an iteration's light pass: its light subpaths'
/// records (indices relative to the tile) and a scratch subpath.
#[derive(Default)]
struct LightPassTile {
    vertices: Vec<Vertex>,
    densities: Vec<VertexDensities>,
    records: Vec<LightVertexRecord>,
    paths: Vec<StoredLightPath>,
    mergeable: Vec<u32>,
}

/// A work unit: the bidirectional scratch and the iteration it renders.
struct VcmUnit {
    scratch: BidirectionalScratch,
    iteration: Option<Arc<Iteration>>,
}

/// The statistics of a VCM render (`--stats`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct VcmStatistics {
    /// The mode.
    pub mode: Option<VcmMode>,
    /// Iterations (passes) traced.
    pub iterations: u64,
    /// Merges of a camera vertex with a light vertex.
    pub merges: u64,
    /// Light vertices stored over all iterations.
    pub light_vertices: u64,
    /// The largest iteration's light store, in bytes.
    pub largest_store_bytes: usize,
    /// The first and the last iteration's radius.
    pub radii: [f32; 2],
}

impl IntegratorDetails for VcmStatistics {
    fn report(&self, render_seconds: f64, _threads: usize) -> String {
        let seconds = render_seconds.max(1e-9);
        format!(
            "vcm ({}): {} iterations ({:.2}/s), {} merges ({:.3} M merges/s), {:.1} light vertices per iteration, light store {:.1} MB, radius {:.4} → {:.4}",
            self.mode.map_or("?", VcmMode::name),
            self.iterations,
            self.iterations as f64 / seconds,
            self.merges,
            self.merges as f64 / seconds / 1e6,
            self.light_vertices as f64 / self.iterations.max(1) as f64,
            self.largest_store_bytes as f64 / 1e6,
            self.radii[0],
            self.radii[1],
        )
    }

    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

impl Integrator for VcmIntegrator {
    fn render(&self, scene: &Scene, run: &RunControl<'_>) -> Result<IntegratorRender, RenderError> {
        if !(self.vcm.alpha > 0.0 && self.vcm.alpha <= 1.0) {
            return Err(RenderError::Unsupported(format!(
                "vcm: alpha must be in (0, 1], got {}",
                self.vcm.alpha
            )));
        }
        if !(self.vcm.radius_fraction > 0.0 && self.vcm.radius_fraction.is_finite()) {
            return Err(RenderError::Unsupported(format!(
                "vcm: the radius must be positive, got {}",
                self.vcm.radius_fraction
            )));
        }
        let [width, height] = scene.camera.resolution();
        let (_, scene_radius) = scene.geometry.bounds().bounding_sphere();
        let estimator = VcmEstimator {
            bidirectional: Bidirectional::for_vertex_merging(scene, &self.settings)?,
            vcm: self.vcm,
            heuristic: self.settings.heuristic,
            scene_radius,
            resolution: [width as usize, height as usize],
            iteration: RwLock::new(None),
            light_pass: RwLock::new(LightPassStatistics::default()),
        };
        let output = render_splat_paths(&estimator, scene, run)?;
        let light_pass = *estimator
            .light_pass
            .read()
            .expect("no panics hold the lock");
        let details = VcmStatistics {
            mode: Some(self.vcm.mode),
            iterations: light_pass.iterations,
            merges: output.total,
            light_vertices: light_pass.light_vertices,
            largest_store_bytes: light_pass.largest_store_bytes,
            radii: [light_pass.first_radius, light_pass.last_radius],
        };
        Ok(IntegratorRender {
            film: output.film,
            statistics: output.statistics,
            variance: None,
            auxiliary_images: Vec::new(),
            details: Some(Box::new(details)),
        })
    }
}

impl VcmEstimator<'_> {
    /// The strategies of an iteration of radius `radius`.
    fn strategies(&self, radius: f32) -> Strategies {
        let light_paths = (self.resolution[0] * self.resolution[1]) as f32;
        let mode = self.vcm.mode;
        Strategies {
            heuristic: self.heuristic,
            connections: mode.connects(),
            camera_connections: true,
            merging: mode
                .merges()
                .then_some(std::f32::consts::PI * radius * radius * light_paths),
        }
    }
}

impl SplatEstimator for VcmEstimator<'_> {
    type Unit = VcmUnit;
    /// The merges.
    type Total = u64;

    fn new_total(&self, _resolution: [usize; 2]) -> Result<u64, RenderError> {
        Ok(0)
    }

    fn new_unit(&self) -> VcmUnit {
        VcmUnit {
            scratch: BidirectionalScratch::default(),
            iteration: self
                .iteration
                .read()
                .expect("no panics hold the lock")
                .clone(),
        }
    }

    fn merge_unit(&self, total: &mut u64, unit: VcmUnit, _kept: bool) {
        *total += unit.scratch.merges;
    }

    /// One iteration per pass.
    fn pass_size(&self, _samples_per_pixel: u64, _timed: bool) -> u64 {
        1
    }

    /// Traces the iteration's light subpaths and builds its grid.
    fn begin_pass(&self, pass: &PassWork<'_>) -> TraceCounters {
        // The last iteration's light subpaths are no longer needed.
        *self.iteration.write().expect("no panics hold the lock") = None;
        let scene = self.bidirectional.scene();
        let sample_index = pass.samples().start;
        let iteration_number = sample_index + 1;
        // The iteration's shared numbers: pixel (0, 0)'s.
        let mut shared = pass.sampler_at((0, 0), sample_index);
        let wavelengths = SampledWavelengths::sample_visible(shared.get(layout::WAVELENGTH));
        let time_sample = if scene.camera.uses_time_sample() {
            shared.get(layout::TIME)
        } else {
            0.5
        };
        let time = scene.camera.time(time_sample);
        let radius = self.vcm.radius(self.scene_radius, iteration_number);
        let strategies = self.strategies(radius);
        let light_paths = (self.resolution[0] * self.resolution[1]) as f32;
        let merging = strategies.merging.is_some();
        let start = || LightPassTile::default();
        let trace = |tile: &mut LightPassTile,
                     _: PixelSampleIndex,
                     sampler: &mut dyn PixelSampler,
                     counters: &mut TraceCounters| {
            let mut path_wavelengths = wavelengths;
            tile.vertices.clear();
            let origin = self.bidirectional.trace_light_subpath(
                time,
                &mut path_wavelengths,
                sampler,
                counters,
                &mut tile.vertices,
                usize::MAX,
            );
            let first = tile.records.len() as u32;
            if let Some(origin) = &origin
                && merging
                && !tile.vertices.is_empty()
            {
                let count = tile.vertices.len() + 1;
                self.bidirectional.subpath_densities(
                    origin.densities,
                    &tile.vertices,
                    count,
                    &mut tile.densities,
                );
                for (vertex, densities) in tile.vertices.iter().zip(&tile.densities[1..]) {
                    if matches!(vertex.scatterer, Scatterer::Surface { .. })
                        && vertex.is_connectible()
                    {
                        tile.mergeable.push(tile.records.len() as u32);
                    }
                    tile.records
                        .push(LightVertexRecord::new(vertex, *densities));
                }
            }
            tile.paths.push(StoredLightPath {
                origin,
                first,
                count: tile.records.len() as u32 - first,
                secondary_terminated: path_wavelengths.secondary_terminated(),
            });
        };
        let (tiles, counters) = pass.for_each_pixel_sample(&start, &trace);
        // The tiles' records one after the other (tile order: the same
        // store for any number of threads).
        let total: usize = tiles.iter().map(|tile| tile.records.len()).sum();
        let path_count: usize = tiles.iter().map(|tile| tile.paths.len()).sum();
        let mut records = Vec::with_capacity(total);
        let mut vertex_path = Vec::with_capacity(total);
        let mut paths = Vec::with_capacity(path_count);
        let mut mergeable = Vec::new();
        for tile in tiles {
            let offset = records.len() as u32;
            for index in tile.mergeable {
                let global = offset + index;
                mergeable.push((global, tile.records[index as usize].point));
            }
            for mut path in tile.paths {
                path.first += offset;
                vertex_path.extend(std::iter::repeat_n(paths.len() as u32, path.count as usize));
                paths.push(path);
            }
            records.extend(tile.records);
        }
        let grid = HashGrid::build(&mergeable, radius);
        let lights = LightStore {
            paths,
            records,
            vertex_path,
            grid,
        };
        let bytes = lights.bytes();
        let stored = lights.records.len() as u64;
        *self.iteration.write().expect("no panics hold the lock") = Some(Arc::new(Iteration {
            wavelengths,
            time_sample,
            strategies,
            normalisation: 1.0 / (std::f32::consts::PI * radius * radius * light_paths),
            lights,
        }));
        let mut statistics = self.light_pass.write().expect("no panics hold the lock");
        if statistics.iterations == 0 {
            statistics.first_radius = radius;
        }
        statistics.iterations += 1;
        statistics.light_vertices += stored;
        statistics.largest_store_bytes = statistics.largest_store_bytes.max(bytes);
        statistics.last_radius = radius;
        counters
    }

    fn trace<S: PixelSampler + ?Sized>(
        &self,
        unit: &mut VcmUnit,
        path: PixelSampleIndex,
        sampler: &mut S,
        splats: &mut SplatBuffer,
        counters: &mut TraceCounters,
    ) {
        let Some(iteration) = &unit.iteration else {
            return;
        };
        let pass = MergingPass {
            wavelengths: iteration.wavelengths,
            time_sample: iteration.time_sample,
            strategies: iteration.strategies,
            first_merge_only: self.vcm.mode == VcmMode::Ppm,
            normalisation: iteration.normalisation,
            lights: &iteration.lights,
        };
        self.bidirectional.trace_merging_sample(
            &mut unit.scratch,
            path.pixel,
            &pass,
            sampler,
            splats,
            counters,
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The grid finds exactly the points within the radius, each once,
    /// whatever the hash collisions.
    #[test]
    fn the_grid_finds_every_point_within_the_radius_once() {
        let mut points = Vec::new();
        let mut state = 12_345u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            ((state >> 40) as f32 / (1u64 << 24) as f32) * 2.0 - 1.0
        };
        for index in 0..2000u32 {
            points.push((index, Vec3::new(next(), next(), next())));
        }
        let radius = 0.1;
        let grid = HashGrid::build(&points, radius);
        for query in 0..200 {
            let point = Vec3::new(next(), next(), next()) * if query % 2 == 0 { 1.0 } else { 1.1 };
            let mut found = Vec::new();
            grid.for_each_candidate(point, |index, position| {
                assert_eq!(position, points[index as usize].1);
                if (position - point).length() <= radius {
                    found.push(index);
                }
            });
            let mut expected: Vec<u32> = points
                .iter()
                .filter(|(_, p)| (*p - point).length() <= radius)
                .map(|(index, _)| *index)
                .collect();
            found.sort_unstable();
            expected.sort_unstable();
            assert_eq!(found, expected, "query {point}");
        }
        // An empty grid finds nothing.
        let empty = HashGrid::build(&[], radius);
        empty.for_each_candidate(Vec3::ZERO, |_, _| panic!("no points"));
    }

    #[test]
    fn the_radius_shrinks_as_smallvcm_s() {
        let settings = VcmSettings::default();
        let first = settings.radius(10.0, 1);
        assert!((first - 0.03).abs() < 1e-6);
        // r_i = r₁ / i^((1 − α)/2) = r₁ / i^0.125.
        let hundredth = settings.radius(10.0, 100);
        assert!((hundredth - 0.03 / 100f32.powf(0.125)).abs() < 1e-6);
        let constant = VcmSettings {
            alpha: 1.0,
            ..settings
        };
        assert_eq!(constant.radius(10.0, 1000), constant.radius(10.0, 1));
    }

    #[test]
    fn modes_round_trip_their_names() {
        for (mode, name) in VcmMode::ALL {
            assert_eq!(VcmMode::from_name(name), Some(mode));
            assert_eq!(mode.name(), name);
        }
        assert_eq!(VcmMode::from_name("sppm"), None);
    }
}
