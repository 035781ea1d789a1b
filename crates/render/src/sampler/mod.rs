//! The primary sample space: every integrator builds its paths from numbers
//! it asks a [`SampleSource`] for, dimension by dimension, so that QMC point
//! sets, Metropolis mutations and LQMC's local lattice exploration all drive
//! the same path construction. Integrators never draw random numbers on
//! their own.
//!
//! # Dimension layout
//!
//! This is the one statement of the layout; `docs/architecture.md` points
//! here. Each path vertex owns a fixed block of [`layout::VERTEX_BLOCK`]
//! dimensions whether or not it uses all of them, so that dimension `d`
//! always means the same decision of the same vertex: a prefix of a path can
//! be rebuilt from new numbers and reconnected to a kept suffix (Metropolis,
//! LQMC). [`layout`] has the dimensions as constants.
//!
//! | dimensions | camera subpath (path, volpath, lqmc) | light subpath (light) |
//! |---|---|---|
//! | 0, 1 | film position inside the pixel (filter importance sampling) | film position of the environment camera ray |
//! | 2, 3 | lens position (thin lens) | lens point of the light vertex's connection |
//! | 4 | time in the shutter interval | time |
//! | 5 | hero wavelength | hero wavelength |
//! | 6 | vertex blocks start | light choice ([`layout::LIGHT_CHOICE`]) |
//! | 7 | | unused, so pairs stay aligned (MMLT's strategy choice) |
//! | 8, 9 | | point on the light |
//! | 10, 11 | | direction of emission |
//! | B + 8k + 0, 1 | vertex k: scattering direction (BSDF or phase function) | the same |
//! | B + 8k + 2 | vertex k: BSDF component (lobe) selection | the same |
//! | B + 8k + 3 | vertex k: Russian roulette | the same |
//! | B + 8k + 4, 5 | vertex k: position on the light (next-event estimation) | vertex k: lens point of its camera connection |
//! | B + 8k + 6 | vertex k: light selection (next-event estimation) | |
//! | B + 8k + 7 | vertex k: free-flight distance in a medium | the same |
//!
//! B = 6 for camera subpaths and 12 for light subpaths. Every subpath's
//! blocks are a [`crate::integrators::path_space::SubpathLayout`] (first
//! block and stride): interleaving a camera and a light subpath as Kollig &
//! Keller do is a stride of two blocks.
//!
//! - **Bidirectional samples** (`bdpt`) use the camera's dimensions 0–5 and
//!   the light's choice, point and direction 6–11 as above, then the lens
//!   point of the light vertex's connection to the camera (12, 13), then the
//!   two subpaths' vertex blocks interleaved, as Kollig & Keller order them:
//!   camera block k at 14 + 16k, light block k at 22 + 16k, each with the
//!   offsets of the table (a camera block's light-position pair is its
//!   next-event connection, a light block's its lens point).
//! - **Multiplexed MLT** (`mmlt`) takes the bidirectional layout and picks
//!   its one strategy with dimension 7 ([`layout::MULTIPLEXED_STRATEGY`]),
//!   which light subpaths leave unused.
//! - **Vertex connection and merging** (`vcm`) takes the bidirectional
//!   layout per pixel sample; an iteration's wavelengths and time, shared by
//!   all its subpaths, are pixel (0, 0)'s [`layout::WAVELENGTH`] and
//!   [`layout::TIME`] of that sample.
//! - **Pairs.** Every 2-D decision (film, lens, light point, emission and
//!   scattering directions, lens point of a connection) is a pair of
//!   dimensions `(2k, 2k + 1)`: the padded samplers ([`PaddedSampler`]) fill
//!   each pair from one 2-D pattern, as Kollig & Keller's padded
//!   replications do per 2-D subproblem.
//! - **Vertices.** Vertex 0 is the first surface (or medium) interaction
//!   seen from the camera. Medium interactions are vertices like surface
//!   ones: the phase function is sampled with the scattering-direction pair,
//!   next-event estimation and Russian roulette use their usual offsets. The
//!   free-flight dimension of block k samples the segment that *ends* at
//!   vertex k: one optical depth τ = −ln(1 − u) at the hero wavelength for
//!   the whole segment, used up piece by piece across index-matched (`null`)
//!   boundaries, which are therefore no vertices and use no dimension (see
//!   [`crate::integrators::volpath`]). It is only asked for when the segment
//!   enters a medium.
//! - **Metropolis** integrators read the same layout from a chain's state
//!   ([`MetropolisSampler`]): a mutation moves the numbers of the dimensions
//!   the path reads, so a small step moves the same decisions of the same
//!   vertices.
//!
//! The QMC samplers put the most important decisions into the lowest
//! dimensions of their sequences, where they are best distributed.
//!
//! # Seeds and randomization
//!
//! The numbers depend only on the seed, the pixel, the sample index and the
//! dimension. [`Randomization`] says whether the seed randomizes the QMC
//! points: by default ([`Randomization::Seeded`]) it does for every
//! sampler, so renders with different seeds are independent replications
//! with unbiased pixel estimates (error bars, randomized QMC):
//!
//! - [`HaltonSampler`]: Faure's permutations followed by a random digital
//!   shift in base b per dimension and digit position; the per-pixel
//!   enumeration inverts the shifts of dimensions 0 and 1;
//! - [`SobolSampler`]: the per-pixel Owen scrambling, keyed by seed, pixel
//!   and dimension;
//! - [`SamplerKind::Lattice`] ([`PointSetSampler`]): the per-pixel
//!   Cranley–Patterson shift, keyed by seed, pixel and dimension;
//! - [`IndependentSampler`]: SplitMix64 keyed by the seed;
//! - [`GlobalSequenceSampler`] (`global-sobol`, `global-niederreiter`): the
//!   whole sequence Owen-scrambled, keyed by the seed;
//! - [`SamplerKind::Hammersley`], [`PaddedSampler`]: a Cranley–Patterson
//!   rotation per pixel, replication and dimension, keyed by the seed.
//!
//! # Replications
//!
//! With a pattern size `m` (`--pattern-size`), the samplers built on a
//! finite point set (`hammersley`, `padded`, `latin-supercube`, `lattice`,
//! `sobol`) and `independent` give each pixel `r` independent replications
//! of `m` points (Kollig & Keller, Eq. 5): sample `j` is point `j mod m` of
//! replication `⌊j / m⌋`, randomized on its own. The drivers then render one
//! replication per pass and estimate each pixel's variance from the
//! replication images (Eq. 6). The sequences (`halton`, `global-sobol`,
//! `global-niederreiter`) are one randomization per render: their
//! replications are renders with different seeds.
//!
//! [`Randomization::None`] keeps the deterministic QMC points: Halton is the
//! LQMC paper's Faure-permuted sequence (bit for bit the sampler before the
//! seed randomized it), Sobol and the lattice use seed 0's per-pixel
//! scrambles and shifts (pixels must still be decorrelated), and the seed
//! reaches only pseudo-random numbers (MT19937 past Halton's 256
//! dimensions, the PCG streams past a point set, the independent sampler).

mod global_sequence;
mod halton;
mod independent;
mod metropolis;
mod padded;
mod pixel_randomization;
mod point_set;
mod sobol;

pub use global_sequence::GlobalSequenceSampler;
pub use halton::HaltonSampler;
pub use independent::IndependentSampler;
pub use metropolis::{MetropolisSampler, MutationSettings, SmallStep};
pub use padded::{PaddedSampler, Padding};
pub use point_set::PointSetSampler;
pub use sobol::SobolSampler;

use qmc::radical_inverse::ONE_MINUS_EPSILON_F32;

/// The dimension layout of a camera path sample (see the module docs).
pub mod layout {
    /// Film position inside the pixel: 2 dimensions.
    pub const FILM: usize = 0;
    /// Lens position: 2 dimensions.
    pub const LENS: usize = 2;
    /// Time in the shutter interval.
    pub const TIME: usize = 4;
    /// The hero wavelength.
    pub const WAVELENGTH: usize = 5;
    /// Dimensions used before the first vertex.
    pub const CAMERA_DIMENSIONS: usize = 6;
    /// Dimensions owned by each path vertex.
    pub const VERTEX_BLOCK: usize = 8;
    /// Offset in a vertex block: scattering direction, 2 dimensions.
    pub const SCATTER_DIRECTION: usize = 0;
    /// Offset in a vertex block: BSDF component selection.
    pub const SCATTER_COMPONENT: usize = 2;
    /// Offset in a vertex block: Russian roulette.
    pub const RUSSIAN_ROULETTE: usize = 3;
    /// Offset in a vertex block: light position, 2 dimensions.
    pub const LIGHT_POSITION: usize = 4;
    /// Offset in a vertex block: light selection.
    pub const LIGHT_SELECTION: usize = 6;
    /// Offset in a vertex block: free-flight distance.
    pub const FREE_FLIGHT: usize = 7;

    /// Light subpaths (light tracing): the light's choice.
    pub const LIGHT_CHOICE: usize = 6;
    /// Light subpaths: the point on the light, 2 dimensions (a pair: 7 is
    /// unused).
    pub const LIGHT_EMISSION_POSITION: usize = 8;
    /// Light subpaths: the direction of emission, 2 dimensions.
    pub const LIGHT_EMISSION_DIRECTION: usize = 10;
    /// Light subpaths: the first dimension of vertex 0's block.
    pub const LIGHT_SUBPATH_VERTICES: usize = 12;
    /// Offset in a light-subpath vertex block: the lens point of the
    /// vertex's connection to the camera, 2 dimensions (the slot camera
    /// subpaths use for the light point of next-event estimation).
    pub const CAMERA_CONNECTION: usize = LIGHT_POSITION;

    /// Bidirectional path tracing: the lens point of the light vertex's
    /// connection to the camera, 2 dimensions (the camera subpath has the
    /// lens pair 2, 3 for itself).
    pub const BIDIRECTIONAL_LIGHT_VERTEX_LENS: usize = 12;
    /// Multiplexed MLT: the choice of the strategy (s, t) among a path
    /// depth's (the dimension light subpaths leave unused, so that pairs
    /// stay aligned).
    pub const MULTIPLEXED_STRATEGY: usize = 7;
    /// Bidirectional path tracing: the first dimension of the interleaved
    /// vertex blocks (camera block k at 14 + 16k, light block k at
    /// 22 + 16k).
    pub const BIDIRECTIONAL_VERTICES: usize = 14;

    /// The dimension of `offset` in the block of path vertex `vertex`.
    #[inline]
    pub const fn vertex(vertex: usize, offset: usize) -> usize {
        CAMERA_DIMENSIONS + vertex * VERTEX_BLOCK + offset
    }
}

/// A source of primary-sample-space numbers for one path sample.
pub trait SampleSource {
    /// The number in `[0, 1)` of `dimension` for the current sample. Asking
    /// for the same dimension twice gives the same number.
    fn get(&mut self, dimension: usize) -> f32;

    /// Dimensions `dimension` and `dimension + 1`.
    #[inline]
    fn get_2d(&mut self, dimension: usize) -> [f32; 2] {
        [self.get(dimension), self.get(dimension + 1)]
    }
}

/// A sampler seen as `dyn SampleSource`, for integrators that take one: a
/// reference to a generic, possibly unsized sampler does not coerce to it.
pub struct DynSource<'a, S: ?Sized>(pub &'a mut S);

impl<S: SampleSource + ?Sized> SampleSource for DynSource<'_, S> {
    #[inline]
    fn get(&mut self, dimension: usize) -> f32 {
        self.0.get(dimension)
    }

    #[inline]
    fn get_2d(&mut self, dimension: usize) -> [f32; 2] {
        self.0.get_2d(dimension)
    }
}

/// A sampler for image synthesis: positioned at a pixel and a sample index,
/// it is the [`SampleSource`] of that pixel sample. The numbers depend only
/// on the seed, the pixel, the sample index and the dimension, so images do
/// not depend on the number of threads or the order of work.
pub trait PixelSampler: SampleSource + Send + Sync {
    /// Positions the sampler at sample `sample_index` of `pixel`.
    fn start_pixel_sample(&mut self, pixel: (u32, u32), sample_index: u64);

    /// A fresh sampler with the same settings, for another thread.
    fn clone_sampler(&self) -> Box<dyn PixelSampler>;

    /// The sampler's name for logs and metadata.
    fn name(&self) -> String;
}

/// Whether the seed randomizes the quasi-Monte Carlo points (see the
/// docs/samplers.md for what each sampler does).
///
/// - [`Randomization::Seeded`] (the default): every sampler is a
///   randomization keyed by the seed, so renders with different seeds are
///   independent replications with unbiased pixel estimates. Halton:
///   Faure's permutations followed by a random digital shift in base b per
///   dimension and digit position ([`qmc::halton::HaltonScramble::FaureShifted`]);
///   Sobol: the per-pixel Owen scrambling keyed by seed and pixel; lattice:
///   the per-pixel Cranley–Patterson shift keyed by seed and pixel.
/// - [`Randomization::None`]: the deterministic constructions; the seed
///   reaches only the pseudo-random numbers (the independent sampler,
///   Halton's MT19937 past dimension 256, the PCG streams past a point
///   set's dimensions or points). Halton is the unscrambled Faure-permuted
///   sequence of the LQMC paper (bit for bit the sampler before seeds
///   randomized it); Sobol and lattice keep their per-pixel scramble or
///   shift, which decorrelates pixels, but fixed: those of seed 0.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Randomization {
    /// The QMC points are randomized by the seed.
    #[default]
    Seeded,
    /// The QMC points do not depend on the seed.
    None,
}

impl Randomization {
    /// Every randomization with its command-line and metadata name.
    pub const ALL: [(Randomization, &'static str); 2] = [
        (Randomization::Seeded, "seeded"),
        (Randomization::None, "none"),
    ];

    /// The randomization called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(r, _)| *r)
    }

    /// One line on what the randomization does (the command line's help).
    pub fn help(self) -> &'static str {
        match self {
            Randomization::Seeded => {
                "The seed randomizes every sampler: Halton's digits get a random digital shift, Sobol's per-pixel Owen scrambles and the lattice's per-pixel shifts are keyed by it. Renders with different seeds are independent replications"
            }
            Randomization::None => {
                "Deterministic QMC points: Faure-permuted Halton as in the LQMC paper, Sobol's and the lattice's per-pixel scrambles and shifts of seed 0; the seed changes only pseudo-random numbers"
            }
        }
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(r, _)| *r == self).unwrap().1
    }

    /// The seed of the per-pixel scrambles and shifts: the render's seed,
    /// or 0 without randomization.
    pub(crate) fn scramble_seed(self, seed: u64) -> u64 {
        match self {
            Randomization::Seeded => seed,
            Randomization::None => 0,
        }
    }
}

/// The samplers a user can choose.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SamplerKind {
    /// Independent uniform random numbers: SplitMix64 outputs addressed by
    /// pixel sample and dimension (always keyed by the seed).
    Independent,
    /// Faure-permuted Halton with per-pixel enumeration (the LQMC paper's),
    /// randomized by a random digital shift per dimension and digit
    /// position unless [`Randomization::None`]. Kollig & Keller's
    /// "scrambled Halton": each pixel takes its own subsequence of the one
    /// image-wide sequence.
    Halton,
    /// Sobol, Owen-scrambled per pixel (hash-based), keyed by the seed
    /// unless [`Randomization::None`].
    Sobol,
    /// A rank-1 lattice rule with N = samples per pixel rounded up to a power
    /// of two (fast CBC, 32 dimensions, γ_j = 1/32), rotated per pixel
    /// (Cranley–Patterson): randomized QMC as in Kollig & Keller. N is at
    /// most 2^16 (built in about 25 ms); samples past N, as a time budget
    /// may ask for, fall back to independent numbers.
    Lattice,
    /// The image-wide Sobol sequence, a consecutive block per pixel
    /// ([`GlobalSequenceSampler`]), Owen-scrambled by the seed unless
    /// [`Randomization::None`].
    GlobalSobol,
    /// The image-wide Niederreiter sequence in base 2, a consecutive block
    /// per pixel, as [`SamplerKind::GlobalSobol`].
    GlobalNiederreiter,
    /// The Faure-scrambled Hammersley set of `m` points (the pattern size,
    /// else the samples per pixel), rotated per pixel and replication:
    /// Kollig & Keller's Cranley–Patterson rotations (Sect. 4.1).
    Hammersley,
    /// Padded replications of the 2-D Hammersley pattern ([`PaddedSampler`]).
    Padded,
    /// Latin supercube samples of the 2-D Hammersley pattern
    /// ([`PaddedSampler`]); unshifted with [`Randomization::None`].
    LatinSupercube,
}

/// The largest point set the point-set samplers (`hammersley`, `padded`,
/// `latin-supercube`) make for the samples per pixel when no pattern size
/// is given.
pub const LARGEST_DEFAULT_PATTERN: u64 = 1 << 16;

/// Their pattern size when the samples per pixel are more than
/// [`LARGEST_DEFAULT_PATTERN`] (a time budget without `--spp`): each pixel's
/// samples are then replications of this many points.
pub const TIMED_PATTERN_SIZE: u64 = 16;

/// Why a sampler cannot be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum SamplerError {
    /// A sequence sampler was asked for replications.
    #[error(
        "the {0} sampler is one randomization of a sequence and has no replications \
         (--pattern-size); render with different seeds, or use independent, sobol, \
         lattice, hammersley, padded or latin-supercube"
    )]
    NoReplications(&'static str),
    /// The pattern size is zero or too large.
    #[error("the pattern size must be between 1 and 2^32, not {0}")]
    PatternSize(u64),
}

impl SamplerKind {
    /// Every sampler with its command-line name.
    pub const ALL: [(SamplerKind, &'static str); 9] = [
        (SamplerKind::Independent, "independent"),
        (SamplerKind::Halton, "halton"),
        (SamplerKind::Sobol, "sobol"),
        (SamplerKind::Lattice, "lattice"),
        (SamplerKind::GlobalSobol, "global-sobol"),
        (SamplerKind::GlobalNiederreiter, "global-niederreiter"),
        (SamplerKind::Hammersley, "hammersley"),
        (SamplerKind::Padded, "padded"),
        (SamplerKind::LatinSupercube, "latin-supercube"),
    ];

    /// The sampler called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.iter().find(|(_, n)| *n == name).map(|(k, _)| *k)
    }

    /// One line on what the sampler is (the command line's help).
    pub fn help(self) -> &'static str {
        match self {
            SamplerKind::Independent => {
                "Independent random numbers (SplitMix64 of the pixel sample and dimension)"
            }
            SamplerKind::Halton => "Faure-permuted Halton, per-pixel enumeration (LQMC's)",
            SamplerKind::Sobol => "Owen-scrambled Sobol per pixel",
            SamplerKind::Lattice => {
                "Randomized rank-1 lattice (CBC, N = spp rounded up to a power of two)"
            }
            SamplerKind::GlobalSobol => {
                "The image-wide Sobol sequence, a consecutive block per pixel (Owen-scrambled by the seed unless --randomize none)"
            }
            SamplerKind::GlobalNiederreiter => {
                "The image-wide Niederreiter sequence (base 2), a consecutive block per pixel (Owen-scrambled by the seed unless --randomize none)"
            }
            SamplerKind::Hammersley => {
                "Faure-scrambled Hammersley set of --pattern-size points (else spp), a Cranley–Patterson rotation per pixel and replication"
            }
            SamplerKind::Padded => {
                "Padded replications of the 2-D Hammersley pattern (Kollig & Keller)"
            }
            SamplerKind::LatinSupercube => {
                "Latin supercube samples of the 2-D Hammersley pattern (unshifted with --randomize none)"
            }
        }
    }

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL.iter().find(|(k, _)| *k == self).unwrap().1
    }

    /// Whether a pixel's samples can be independent replications of a
    /// pattern (see the module docs).
    pub fn has_replications(self) -> bool {
        !matches!(
            self,
            SamplerKind::Halton | SamplerKind::GlobalSobol | SamplerKind::GlobalNiederreiter
        )
    }

    /// Checks that the sampler can have replications of `pattern_size`
    /// points, if one is given.
    pub fn check_pattern_size(self, pattern_size: Option<u64>) -> Result<(), SamplerError> {
        match pattern_size {
            None => Ok(()),
            Some(size) if size == 0 || size > 1 << 32 => Err(SamplerError::PatternSize(size)),
            Some(_) if !self.has_replications() => Err(SamplerError::NoReplications(self.name())),
            Some(_) => Ok(()),
        }
    }

    /// Builds the sampler for an image of `resolution` pixels and
    /// `samples_per_pixel` samples (which sizes the lattice and the
    /// sequences' blocks), randomized by `seed` as `randomization` says,
    /// its samples replications of `pattern_size` points if given.
    pub fn create(
        self,
        seed: u64,
        randomization: Randomization,
        resolution: (u32, u32),
        samples_per_pixel: u64,
        pattern_size: Option<u64>,
    ) -> Result<Box<dyn PixelSampler>, SamplerError> {
        self.check_pattern_size(pattern_size)?;
        // Without a pattern size a point set has the samples per pixel, but
        // a time budget's unlimited samples get replications of a default
        // size instead of one vast set.
        let timed_pattern =
            (samples_per_pixel > LARGEST_DEFAULT_PATTERN).then_some(TIMED_PATTERN_SIZE);
        let point_count = pattern_size
            .or(timed_pattern)
            .unwrap_or(samples_per_pixel)
            .max(1);
        let points_sampler = |points: std::sync::Arc<dyn qmc::PointSet>, pattern: Option<u64>| {
            Box::new(PointSetSampler::new(
                points,
                self.name(),
                seed,
                randomization,
                pattern,
            ))
        };
        Ok(match self {
            SamplerKind::Independent => Box::new(IndependentSampler::new(seed)),
            SamplerKind::Halton => Box::new(HaltonSampler::new(seed, randomization, resolution)),
            SamplerKind::Sobol => Box::new(SobolSampler::new(seed, randomization, pattern_size)),
            SamplerKind::Lattice => {
                const LATTICE_DIMENSIONS: usize = 32;
                // Replications use the pattern size itself; one rotation per
                // pixel rounds the samples up to a power of two.
                let point_count = match pattern_size {
                    Some(size) => size.max(2),
                    None => samples_per_pixel.clamp(4, 1 << 16).next_power_of_two(),
                };
                let lattice = qmc::cbc::cbc(
                    point_count,
                    LATTICE_DIMENSIONS,
                    &qmc::cbc::ProductWeights::lqmc_default(LATTICE_DIMENSIONS),
                )
                .map_err(|_| SamplerError::PatternSize(point_count))?
                .lattice;
                points_sampler(std::sync::Arc::new(lattice), pattern_size)
            }
            SamplerKind::GlobalSobol | SamplerKind::GlobalNiederreiter => {
                let sequence: std::sync::Arc<dyn qmc::digital_scramble::DigitalSequence> =
                    if self == SamplerKind::GlobalSobol {
                        std::sync::Arc::new(
                            qmc::sobol::Sobol::new(
                                sobol::SOBOL_DIMENSIONS,
                                qmc::digital_scramble::DigitalOrder::Natural,
                            )
                            .expect("1024 Sobol dimensions are supported"),
                        )
                    } else {
                        std::sync::Arc::new(
                            qmc::niederreiter::Niederreiter::new(
                                qmc::niederreiter::MAX_DIMENSIONS,
                                qmc::digital_scramble::DigitalOrder::Natural,
                            )
                            .expect("the Niederreiter sequence's own dimension count"),
                        )
                    };
                Box::new(GlobalSequenceSampler::new(
                    sequence,
                    self.name(),
                    resolution,
                    samples_per_pixel,
                    seed,
                    randomization,
                ))
            }
            SamplerKind::Hammersley => {
                let hammersley = qmc::hammersley::Hammersley::new(
                    point_count,
                    halton::HALTON_DIMENSIONS,
                    qmc::halton::HaltonScramble::Faure,
                    0,
                )
                .map_err(|_| SamplerError::PatternSize(point_count))?;
                points_sampler(
                    std::sync::Arc::new(hammersley),
                    pattern_size.or(timed_pattern),
                )
            }
            SamplerKind::Padded => Box::new(PaddedSampler::new(
                point_count,
                Padding::Replications,
                seed,
                randomization,
            )),
            SamplerKind::LatinSupercube => Box::new(PaddedSampler::new(
                point_count,
                Padding::LatinSupercube,
                seed,
                randomization,
            )),
        })
    }
}

/// Converts a coordinate in `[0, 1)` to `f32`, keeping it below 1.
#[inline]
pub(crate) fn to_f32(value: f64) -> f32 {
    (value as f32).min(ONE_MINUS_EPSILON_F32)
}

/// The pixel's coordinates packed into one word for hashing.
#[inline]
pub(crate) fn pixel_key(pixel: (u32, u32)) -> u64 {
    ((pixel.0 as u64) << 32) | pixel.1 as u64
}

/// A key for one pixel sample, hashed from the seed, the pixel and the index:
/// [`sample_key_in_pixel`] of [`pixel_part_of_key`].
#[inline]
pub(crate) fn pixel_sample_key(seed: u64, pixel: (u32, u32), sample_index: u64) -> u64 {
    sample_key_in_pixel(pixel_part_of_key(seed, pixel), sample_index)
}

/// The part of [`pixel_sample_key`] that does not depend on the sample index:
/// the seed and the pixel hashed together. Samplers that start many samples
/// of one pixel keep it.
#[inline]
pub(crate) fn pixel_part_of_key(seed: u64, pixel: (u32, u32)) -> u64 {
    qmc::hash::hash2(seed, pixel_key(pixel))
}

/// [`pixel_sample_key`] from its [`pixel_part_of_key`] and the sample index
/// (together `hash3(seed, pixel, index)`).
#[inline]
pub(crate) fn sample_key_in_pixel(pixel_part: u64, sample_index: u64) -> u64 {
    qmc::hash::hash2(pixel_part, sample_index)
}

#[cfg(test)]
mod tests;
