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
//!    are kept: whole (with their BSDFs) for the pixel's own connections,
//!    and as compact [`LightVertexRecord`]s for merges; those that can be
//!    merged at (surfaces that are not purely specular) go into a hash grid
//!    of cell side 2r;
//! 2. per pixel, the camera subpath is traced, connected to the pixel's own
//!    light subpath by every BDPT strategy (the kept vertices: the subpath
//!    is not traced twice), and each of its vertices merges with the light
//!    vertices within r of it.
//!
//! # Memory for speed
//!
//! The store costs about 0.8 kB per light vertex (the whole vertex and its
//! record): at 256 × 256 pixels on the Cornell box, 154 000 vertices and
//! about 140 MB, reused from iteration to iteration (the tiles' vectors are
//! kept). Merges are cache misses on the grid and the records; a camera
//! subpath's queries are answered together, stage by stage, with
//! prefetches, before its connections are traced, so that the misses are
//! waited for while the connections run.
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

mod merging;

use super::bdpt::mis::{Strategies, VertexDensities};
use super::bdpt::{BdptSettings, Bidirectional, BidirectionalScratch, LightOrigin};
use super::driver::{PassWork, PixelSampleIndex, SplatEstimator, render_splat_paths};
use super::estimator::PathSettings;
use super::path_space::{Scatterer, Vertex};
use super::{Integrator, IntegratorDetails, IntegratorRender, RenderError, RunControl};
use super::{MisHeuristic, TraceCounters};
use crate::film::SplatBuffer;
use crate::sampler::{PixelSampler, layout};
use crate::scene::Scene;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};
use glam::Vec3;
use merging::{MergeScratch, MergingPass};
use rayon::prelude::*;
use std::sync::{Arc, Mutex, RwLock};

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
    /// Its vertices' records: `first .. first + count` of its tile's
    /// (none without merging).
    first: u32,
    count: u32,
    /// Its vertices: `first_vertex .. first_vertex + vertex_count` of its
    /// tile's `vertices`.
    first_vertex: u32,
    vertex_count: u32,
    /// Its walk dropped the secondary wavelengths.
    pub secondary_terminated: bool,
}

/// An iteration's light subpaths, one per pixel sample, and a hash grid
/// over the vertices that can be merged at.
pub(crate) struct LightStore {
    /// The light pass's tiles, in tile order: their light subpaths and
    /// vertices, where the pass left them (not copied into one array).
    tiles: Vec<LightPassTile>,
    /// Per pixel (row by row), its light subpath: (tile, path in the tile).
    pixel_paths: Vec<(u32, u32)>,
    /// The image's width.
    width: usize,
    /// The grid over the mergeable vertices (empty without merging).
    grid: HashGrid,
}

impl LightStore {
    /// Asks the cache for what [`Self::vertex`] will read of the light
    /// vertices `found` (from [`Self::find_near`]): their records and
    /// paths. The loads are independent, so their misses overlap instead of
    /// following one another merge by merge.
    pub fn prefetch(&self, found: &[(u32, GridPoint)]) {
        for (_, point) in found {
            let tile = &self.tiles[point.tile as usize];
            prefetch_bytes(&tile.records[point.vertex as usize]);
            prefetch_bytes(&tile.paths[point.path as usize]);
        }
    }

    /// The light vertex `point` found in the grid: its path, the path's
    /// vertices and its place `k` on them.
    pub fn vertex(&self, point: &GridPoint) -> (&StoredLightPath, &[LightVertexRecord], usize) {
        let tile = &self.tiles[point.tile as usize];
        let path = &tile.paths[point.path as usize];
        let records = &tile.records[path.first as usize..(path.first + path.count) as usize];
        (path, records, (point.vertex - path.first) as usize)
    }

    /// The light subpath the iteration traced for `pixel`, and its
    /// vertices: what the pixel's camera subpath connects to.
    pub fn pixel_path(&self, pixel: (u32, u32)) -> (&StoredLightPath, &[Vertex]) {
        let (tile, path) = self.pixel_paths[pixel.1 as usize * self.width + pixel.0 as usize];
        let tile = &self.tiles[tile as usize];
        let path = &tile.paths[path as usize];
        let first = path.first_vertex as usize;
        (
            path,
            &tile.vertices[first..first + path.vertex_count as usize],
        )
    }

    /// Asks the cache for the vertices of `pixel`'s light subpath
    /// ([`Self::pixel_path`]), read after its camera subpath is traced.
    pub fn prefetch_pixel_path(&self, pixel: (u32, u32)) {
        let (path, vertices) = self.pixel_path(pixel);
        prefetch_bytes(path);
        for vertex in vertices {
            prefetch_bytes(vertex);
        }
    }

    /// Finds, for every point of `queries`, the mergeable light vertices
    /// within the radius: `search.found` becomes the pairs (query, vertex
    /// index), by query.
    pub fn find_near(&self, queries: &[Vec3], search: &mut NearbySearch) {
        self.grid.find_near(queries, search);
    }

    /// The light vertices stored.
    fn vertex_count(&self) -> usize {
        self.tiles.iter().map(|tile| tile.records.len()).sum()
    }

    /// The bytes the store holds (vertices, paths, grid).
    fn bytes(&self) -> usize {
        self.tiles
            .iter()
            .map(|tile| {
                tile.records.capacity() * std::mem::size_of::<LightVertexRecord>()
                    + tile.vertices.capacity() * std::mem::size_of::<Vertex>()
                    + tile.paths.capacity() * std::mem::size_of::<StoredLightPath>()
                    + tile.mergeable.capacity() * std::mem::size_of::<GridPoint>()
            })
            .sum::<usize>()
            + self.pixel_paths.capacity() * 8
            + self.grid.bytes()
    }
}

/// A hash grid over points (SmallVCM's): cells of side 2r hashed into
/// buckets, the points sorted by bucket; a query visits the 2 × 2 × 2 cells
/// nearest its point, which hold every point within r. Queries are cache
/// misses, so: two buckets per point (the power of two above), with a
/// bitmap of the occupied ones small enough for the cache, checked first;
/// buckets in space order within blocks of cells ([`Self::bucket`]); and
/// the points' positions kept with their tile, record and path indices, so
/// a query reads only its buckets and touches a record only for a point
/// within r.
#[derive(Debug, Default)]
struct HashGrid {
    radius: f32,
    inverse_cell_size: f32,
    /// The bits per axis of a cell's Morton code in [`Self::bucket`].
    bits_per_axis: u32,
    /// One bit per bucket: whether it holds a point.
    occupied: Vec<u64>,
    /// Per bucket, the start of its points in `entries` (its end is the
    /// next bucket's start; one more for the last's end).
    bucket_starts: Vec<u32>,
    /// The points, by bucket.
    entries: Vec<GridPoint>,
}

impl HashGrid {
    /// The grid of radius `radius` over `points`, in the memory of
    /// `previous` (a grid no longer needed).
    fn build(points: &[GridPoint], radius: f32, previous: HashGrid) -> Self {
        let buckets = (2 * points.len()).max(1).next_power_of_two();
        let inverse_cell_size = 1.0 / (2.0 * radius);
        let mut grid = HashGrid {
            radius,
            inverse_cell_size,
            bits_per_axis: (buckets.trailing_zeros() / 3).clamp(1, 10),
            occupied: zeroed(previous.occupied, buckets.div_ceil(64)),
            bucket_starts: zeroed(previous.bucket_starts, buckets + 1),
            entries: previous.entries,
        };
        grid.entries.clear();
        grid.entries.resize(points.len(), GridPoint::default());
        let point_buckets: Vec<u32> = points
            .par_iter()
            .map(|point| grid.bucket(grid.cell(point.position)))
            .collect();
        // A counting sort: each bucket's count, summed up to its end, then
        // moved down to its start as its points are placed (from the back,
        // so each bucket keeps the points' order).
        for &bucket in &point_buckets {
            grid.bucket_starts[bucket as usize] += 1;
            grid.occupied[bucket as usize / 64] |= 1 << (bucket % 64);
        }
        let mut sum = 0;
        for end in grid.bucket_starts.iter_mut() {
            sum += *end;
            *end = sum;
        }
        for (&point, &bucket) in points.iter().zip(&point_buckets).rev() {
            let start = &mut grid.bucket_starts[bucket as usize];
            *start -= 1;
            grid.entries[*start as usize] = point;
        }
        grid
    }

    /// The integer cell of `point`.
    fn cell(&self, point: Vec3) -> [i32; 3] {
        let scaled = point * self.inverse_cell_size;
        // ⌊x⌋ by truncation and a correction below zero: `f32::floor` is a
        // library call on x86_64 without SSE 4.1.
        let floor = |x: f32| {
            let truncated = x as i32;
            truncated - i32::from(x < truncated as f32)
        };
        [floor(scaled.x), floor(scaled.y), floor(scaled.z)]
    }

    /// The bucket of a cell. Cells are grouped in blocks of 2^b cells per
    /// axis (b = a third of the buckets' bits): within a block a cell's
    /// bucket is its Morton code, so cells near each other (a query's
    /// eight, and the queries of neighbouring pixels) share cache lines of
    /// `bucket_starts` and, the points being sorted by bucket, of `entries`;
    /// the block's coordinates, hashed as SmallVCM's cells are (Teschner et
    /// al. 2003), are XORed in, which permutes the block's buckets without
    /// breaking up aligned runs of codes.
    fn bucket(&self, cell: [i32; 3]) -> u32 {
        let bits = self.bits_per_axis;
        let mask = (1u32 << bits) - 1;
        let morton = spread_bits(cell[0] as u32 & mask)
            | spread_bits(cell[1] as u32 & mask) << 1
            | spread_bits(cell[2] as u32 & mask) << 2;
        let block = cell.map(|coordinate| (coordinate >> bits) as u32);
        let hash = block[0].wrapping_mul(73_856_093)
            ^ block[1].wrapping_mul(19_349_663)
            ^ block[2].wrapping_mul(83_492_791);
        // The number of buckets is a power of two.
        (morton ^ hash.rotate_left(3 * bits)) & (self.bucket_starts.len() as u32 - 2)
    }

    /// Finds, for every point of `queries`, the points within the radius:
    /// `search.found` becomes the pairs (query, point), by query. The
    /// queries are answered together, stage by stage (their buckets, the
    /// buckets' ranges, the points in them):
    /// each stage's loads are independent of each other, so their cache
    /// misses overlap instead of following one another.
    pub fn find_near(&self, queries: &[Vec3], search: &mut NearbySearch) {
        search.found.clear();
        let grid = self;
        if grid.entries.is_empty() {
            return;
        }
        search.buckets.clear();
        for (query, &point) in queries.iter().enumerate() {
            grid.push_buckets(point, query as u32, &mut search.buckets);
        }
        search.ranges.clear();
        search
            .ranges
            .extend(search.buckets.iter().filter_map(|&(query, bucket)| {
                let (start, end) = grid.bucket_range(bucket);
                // Read by the points' stage.
                prefetch_bytes(&grid.entries[start as usize]);
                (start < end).then_some((query, start, end))
            }));
        let radius_squared = grid.radius * grid.radius;
        for &(query, start, end) in &search.ranges {
            let point = queries[query as usize];
            for candidate in &grid.entries[start as usize..end as usize] {
                if (candidate.position - point).length_squared() <= radius_squared {
                    search.found.push((query, *candidate));
                }
            }
        }
    }

    /// Pushes (query, bucket) for the occupied buckets of the 2 × 2 × 2
    /// cells nearest `point`, which hold every point within the radius,
    /// each bucket once.
    fn push_buckets(&self, point: Vec3, query: u32, buckets: &mut Vec<(u32, u32)>) {
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
        let first = buckets.len();
        for corner in 0..8 {
            let candidate = std::array::from_fn(|axis| {
                if corner >> axis & 1 == 0 {
                    cell[axis]
                } else {
                    other[axis]
                }
            });
            let bucket = self.bucket(candidate);
            if self.occupied[bucket as usize / 64] & (1 << (bucket % 64)) != 0
                && !buckets[first..].iter().any(|&(_, seen)| seen == bucket)
            {
                buckets.push((query, bucket));
                // Read by the ranges' stage.
                prefetch_bytes(&self.bucket_starts[bucket as usize]);
            }
        }
    }

    /// The range of `entries` that holds the points of `bucket`.
    #[inline]
    fn bucket_range(&self, bucket: u32) -> (u32, u32) {
        (
            self.bucket_starts[bucket as usize],
            self.bucket_starts[bucket as usize + 1],
        )
    }

    fn bytes(&self) -> usize {
        self.bucket_starts.capacity() * 4
            + self.occupied.capacity() * 8
            + self.entries.capacity() * std::mem::size_of::<GridPoint>()
    }
}

/// `vector` with `length` zeros, in its memory.
fn zeroed<T: Copy + Default>(mut vector: Vec<T>, length: usize) -> Vec<T> {
    vector.clear();
    vector.resize(length, T::default());
    vector
}

/// Asks the cache to load the lines of `value`: a hint, without effect on
/// what the program computes.
#[inline(always)]
fn prefetch_bytes<T>(value: &T) {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        let start = std::ptr::from_ref(value).cast::<i8>();
        for offset in (0..std::mem::size_of::<T>()).step_by(64) {
            // SAFETY: a prefetch reads nothing and cannot fault (the
            // address is within `value` anyway); SSE is part of x86_64.
            unsafe { _mm_prefetch::<_MM_HINT_T0>(start.wrapping_add(offset)) };
        }
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = value;
}

/// The ten low bits of `value` spread to every third bit (bit i to bit
/// 3i): one axis of a Morton code.
fn spread_bits(value: u32) -> u32 {
    let mut x = value & 0x3ff;
    x = (x | x << 16) & 0x0300_00ff;
    x = (x | x << 8) & 0x0300_f00f;
    x = (x | x << 4) & 0x030c_30c3;
    (x | x << 2) & 0x0924_9249
}

/// The scratch space of [`LightStore::find_near`], kept from search to
/// search.
#[derive(Debug, Default)]
pub(crate) struct NearbySearch {
    /// (query, bucket) of the queries' occupied buckets.
    buckets: Vec<(u32, u32)>,
    /// (query, start, end): the buckets' ranges of entries.
    ranges: Vec<(u32, u32, u32)>,
    /// (query, light vertex) within the radius, by query.
    pub found: Vec<(u32, GridPoint)>,
}

/// A point of the grid: a mergeable light vertex.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct GridPoint {
    /// Its tile of the light pass.
    pub tile: u32,
    /// Its record's index in the tile.
    pub vertex: u32,
    /// Its path's index in its tile (so that a merge finds the path
    /// without reading the vertex first).
    pub path: u32,
    /// Where it is.
    pub position: Vec3,
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

/// A tile's share of an iteration's light pass: its light subpaths, their
/// vertices and records (indices relative to the tile), and scratch
/// densities.
#[derive(Default)]
struct LightPassTile {
    vertices: Vec<Vertex>,
    densities: Vec<VertexDensities>,
    records: Vec<LightVertexRecord>,
    paths: Vec<StoredLightPath>,
    /// Its index among the pass's tiles.
    index: u32,
    /// The grid points of its mergeable vertices.
    mergeable: Vec<GridPoint>,
}

/// A work unit: the bidirectional and merging scratch and the iteration it
/// renders.
struct VcmUnit {
    scratch: BidirectionalScratch,
    merging: MergeScratch,
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
            bidirectional: Bidirectional::new(
                scene,
                &self.settings,
                BdptSettings::default(),
                "vcm",
            )?,
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
            merging: MergeScratch::default(),
            iteration: self
                .iteration
                .read()
                .expect("no panics hold the lock")
                .clone(),
        }
    }

    fn merge_unit(&self, total: &mut u64, unit: VcmUnit, _kept: bool) {
        *total += unit.merging.count;
    }

    /// One iteration per pass.
    fn pass_size(&self, _samples_per_pixel: u64, _timed: bool) -> u64 {
        1
    }

    /// Traces the iteration's light subpaths and builds its grid.
    fn begin_pass(&self, pass: &PassWork<'_>) -> TraceCounters {
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
        // The last iteration's tiles, emptied, hold this one's: their
        // memory is reused rather than allocated (and faulted in) again.
        let previous = self
            .iteration
            .write()
            .expect("no panics hold the lock")
            .take();
        let (pool, pixel_paths, grid) = match previous.and_then(Arc::into_inner) {
            Some(iteration) => (
                iteration.lights.tiles,
                iteration.lights.pixel_paths,
                iteration.lights.grid,
            ),
            None => Default::default(),
        };
        let pool = Mutex::new(pool);
        let start = |tile_index: usize| {
            let mut tile = pool
                .lock()
                .expect("no panics hold the lock")
                .pop()
                .unwrap_or_default();
            tile.vertices.clear();
            tile.records.clear();
            tile.paths.clear();
            tile.mergeable.clear();
            tile.index = tile_index as u32;
            tile
        };
        let trace = |tile: &mut LightPassTile,
                     _: PixelSampleIndex,
                     sampler: &mut dyn PixelSampler,
                     counters: &mut TraceCounters| {
            let mut path_wavelengths = wavelengths;
            let first_vertex = tile.vertices.len();
            let origin = self.bidirectional.trace_light_subpath(
                time,
                &mut path_wavelengths,
                sampler,
                counters,
                &mut tile.vertices,
                usize::MAX,
            );
            let walked = &tile.vertices[first_vertex..];
            let first = tile.records.len() as u32;
            if let Some(origin) = &origin
                && merging
                && !walked.is_empty()
            {
                let count = walked.len() + 1;
                self.bidirectional.subpath_densities(
                    origin.densities,
                    walked,
                    count,
                    &mut tile.densities,
                );
                for (vertex, densities) in walked.iter().zip(&tile.densities[1..]) {
                    if matches!(vertex.scatterer, Scatterer::Surface { .. })
                        && vertex.is_connectible()
                    {
                        tile.mergeable.push(GridPoint {
                            tile: tile.index,
                            vertex: tile.records.len() as u32,
                            path: tile.paths.len() as u32,
                            position: vertex.point,
                        });
                    }
                    tile.records
                        .push(LightVertexRecord::new(vertex, *densities));
                }
            }
            tile.paths.push(StoredLightPath {
                origin,
                first,
                count: tile.records.len() as u32 - first,
                first_vertex: first_vertex as u32,
                vertex_count: (tile.vertices.len() - first_vertex) as u32,
                secondary_terminated: path_wavelengths.secondary_terminated(),
            });
        };
        let (mut tiles, counters) = pass.for_each_pixel_sample(&start, &trace);
        // The grid's points in tile order: the same grid for any number of
        // threads.
        let mut mergeable = Vec::with_capacity(tiles.iter().map(|tile| tile.mergeable.len()).sum());
        for tile in &mut tiles {
            // At most a tenth more room than this iteration needed (the
            // first iteration's vectors grew by doubling): the next
            // iteration reuses it.
            fn trim<T>(vector: &mut Vec<T>) {
                if vector.capacity() > vector.len() + vector.len() / 4 {
                    vector.shrink_to(vector.len() + vector.len() / 10);
                }
            }
            trim(&mut tile.vertices);
            trim(&mut tile.records);
            mergeable.extend_from_slice(&tile.mergeable);
        }
        // Each pixel's light subpath: the tiles' pixels in rows, one sample
        // each (a pass is one iteration); the same tiles every pass.
        let width = self.resolution[0];
        let mut pixel_paths = pixel_paths;
        if pixel_paths.is_empty() {
            pixel_paths = vec![(0, 0); width * self.resolution[1]];
            for (tile_index, bounds) in pass.tiles().iter().enumerate() {
                let mut path = 0;
                for y in bounds.min[1]..bounds.max[1] {
                    for x in bounds.min[0]..bounds.max[0] {
                        pixel_paths[y * width + x] = (tile_index as u32, path);
                        path += 1;
                    }
                }
            }
        }
        let grid = HashGrid::build(&mergeable, radius, grid);
        let lights = LightStore {
            tiles,
            pixel_paths,
            width,
            grid,
        };
        let bytes = lights.bytes();
        let stored = lights.vertex_count() as u64;
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
        let mut pass = MergingPass {
            wavelengths: iteration.wavelengths,
            time_sample: iteration.time_sample,
            strategies: iteration.strategies,
            first_merge_only: self.vcm.mode == VcmMode::Ppm,
            normalisation: iteration.normalisation,
            lights: &iteration.lights,
            pixel: path.pixel,
            scratch: &mut unit.merging,
        };
        self.bidirectional.trace_pixel_sample(
            &mut unit.scratch,
            path.pixel,
            Some(&mut pass),
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
            points.push(GridPoint {
                tile: index % 7,
                vertex: index,
                path: index / 3,
                position: Vec3::new(next(), next(), next()),
            });
        }
        let radius = 0.1;
        let grid = HashGrid::build(&points, radius, HashGrid::default());
        let queries: Vec<Vec3> = (0..200)
            .map(|query| Vec3::new(next(), next(), next()) * if query % 2 == 0 { 1.0 } else { 1.1 })
            .collect();
        let mut search = NearbySearch::default();
        grid.find_near(&queries, &mut search);
        assert!(search.found.is_sorted_by_key(|&(query, _)| query));
        for (query, &point) in queries.iter().enumerate() {
            let mut found: Vec<u32> = search
                .found
                .iter()
                .filter(|&&(asked, _)| asked == query as u32)
                .map(|(_, point)| {
                    assert_eq!(point.path, point.vertex / 3);
                    assert_eq!(point.tile, point.vertex % 7);
                    point.vertex
                })
                .collect();
            let mut expected: Vec<u32> = points
                .iter()
                .filter(|p| (p.position - point).length_squared() <= radius * radius)
                .map(|p| p.vertex)
                .collect();
            found.sort_unstable();
            expected.sort_unstable();
            assert_eq!(found, expected, "query {point}");
        }
        // An empty grid finds nothing.
        let empty = HashGrid::build(&[], radius, grid);
        empty.find_near(&queries, &mut search);
        assert!(search.found.is_empty());
    }

    /// Morton bits: bit i of each axis goes to bit 3i.
    #[test]
    fn morton_bits_interleave() {
        assert_eq!(spread_bits(0b1), 0b1);
        assert_eq!(spread_bits(0b11), 0b1001);
        assert_eq!(spread_bits(0x3ff), 0x0924_9249);
        assert_eq!(spread_bits(0x400), 0);
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
