//! The film: reconstruction filters, per-pixel accumulation of camera
//! samples in tiles owned by render threads, splats to arbitrary pixels,
//! and the final RGB and variance images.
//!
//! Conventions: pixel `(x, y)` covers the raster square
//! `[x, x + 1) × [y, y + 1)` with its centre at `(x + 0.5, y + 0.5)`; row 0
//! is the top row. Camera samples use filter importance sampling (each
//! sample is placed by sampling the filter around its pixel's centre and
//! counts for that pixel only); splats are spread over the pixels around
//! them with the filter. See [`Film`] for determinism.

mod film_tile;
mod filter;
mod image_plane;
mod pixel_statistics;
mod rgb_film;
mod splat_buffer;

pub use film_tile::{FilmTile, PixelBounds, SampleOutcome};
pub use filter::{BoxFilter, Filter, FilterSample, GaussianFilter, TriangleFilter};
pub use image_plane::{FilmFrame, ImagePlane};
pub use pixel_statistics::PixelStatistics;
pub use rgb_film::{CameraSamplePosition, Film};
pub use splat_buffer::{Splat, SplatBuffer};

/// What went wrong building or filling a film.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum FilmError {
    /// A film needs a positive width and height.
    #[error("film resolution {}x{} is invalid: width and height must be positive", resolution[0], resolution[1])]
    InvalidResolution {
        /// The requested `[width, height]`.
        resolution: [usize; 2],
    },
    /// Tiles need a positive size.
    #[error("the tile size must be positive")]
    InvalidTileSize,
    /// A tile must lie inside its film.
    #[error("tile {bounds} does not fit in a film of {}x{} pixels", resolution[0], resolution[1])]
    TileOutsideFilm {
        /// The tile's pixels.
        bounds: PixelBounds,
        /// The film's `[width, height]`.
        resolution: [usize; 2],
    },
    /// A sample was added to a tile that does not cover its pixel.
    #[error("pixel ({}, {}) is outside the tile {bounds}", pixel[0], pixel[1])]
    PixelOutsideTile {
        /// The pixel.
        pixel: [usize; 2],
        /// The tile's pixels.
        bounds: PixelBounds,
    },
    /// A filter parameter must be positive and finite.
    #[error("filter parameter {name} = {value} must be positive and finite")]
    InvalidFilterParameter {
        /// The parameter ("box radius", "gaussian sigma", ...).
        name: &'static str,
        /// The value given.
        value: f32,
    },
}
