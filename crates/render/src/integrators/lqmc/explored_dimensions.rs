//! Which primary-sample-space dimensions an exploration perturbs and in how
//! many tiles each is cut (the paper's Sec. 3.1 and 3.4): wavelength, time
//! and aperture always (breakup b = 0), the image plane from b ≥ 1, and the
//! outgoing direction of every non-specular vertex x_1 .. x_{b−1} (which
//! places x_2 .. x_b). Specular vertices consume no explored dimension;
//! Russian roulette and component selection keep the seed's numbers.
//! In media, the free-flight distance of each segment that ends at a
//! medium vertex x_1 .. x_b is explored too (1000 tiles, the authors'
//! value); a segment that reaches a surface through a medium keeps the
//! seed's free-flight number, a discrete decision like Russian roulette.

use super::classification::EventPath;
use super::path_record::Terminal;
use super::settings::{ClassParameters, LqmcSettings};
use crate::sampler::layout;
use crate::scene::Scene;

/// One explored dimension.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DimensionKind {
    /// Lens position, axis 0 or 1.
    Lens(usize),
    /// Hero wavelength.
    Wavelength,
    /// Time.
    Time,
    /// Image plane, axis 0 (width) or 1 (height), as a fraction of the image.
    Image(usize),
    /// Outgoing direction of layout vertex `vertex`, axis 0 or 1.
    Direction {
        /// The layout vertex (x_{vertex+1} in the paper's numbering).
        vertex: usize,
        /// The axis.
        axis: usize,
    },
    /// Free-flight distance of the segment that ends at layout vertex
    /// `vertex` (a medium vertex).
    FreeFlight {
        /// The layout vertex.
        vertex: usize,
    },
    /// Light-position number `axis` of next-event estimation at layout
    /// vertex `vertex` (the full-path breakup b = k of a next-event path:
    /// the light point is sampled again).
    LightPosition {
        /// The layout vertex.
        vertex: usize,
        /// The axis.
        axis: usize,
    },
}

impl DimensionKind {
    /// A number that identifies the dimension (its layout dimension; the
    /// image plane uses the film dimensions), for the tile jitter.
    pub fn key(self) -> u64 {
        match self {
            DimensionKind::Lens(axis) => (layout::LENS + axis) as u64,
            DimensionKind::Wavelength => layout::WAVELENGTH as u64,
            DimensionKind::Time => layout::TIME as u64,
            DimensionKind::Image(axis) => (layout::FILM + axis) as u64,
            DimensionKind::Direction { vertex, axis } => {
                layout::vertex(vertex, layout::SCATTER_DIRECTION + axis) as u64
            }
            DimensionKind::FreeFlight { vertex } => {
                layout::vertex(vertex, layout::FREE_FLIGHT) as u64
            }
            DimensionKind::LightPosition { vertex, axis } => {
                layout::vertex(vertex, layout::LIGHT_POSITION + axis) as u64
            }
        }
    }
}

/// An explored dimension and its tile count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExploredDimension {
    /// Which dimension.
    pub kind: DimensionKind,
    /// Tiles along it (≥ 1).
    pub tiles: u32,
}

/// The explored dimensions for breakup vertex `b` of `path` with the
/// parameters of its class.
pub fn explored_dimensions(
    scene: &Scene,
    settings: &LqmcSettings,
    parameters: &ClassParameters,
    path: &EventPath<'_>,
    breakup: usize,
    dimensions: &mut Vec<ExploredDimension>,
) {
    dimensions.clear();
    // An index-matched emitting boundary is passed, not hit: no rebuilt
    // ray ends there, so its emission events have no full-path breakup.
    if breakup >= path.event.last_vertex()
        && let Terminal::Emission { .. } = path.event.terminal
        && path.vertices.last().is_some_and(|emitter| {
            !emitter.is_medium() && scene.shapes[emitter.raw_hit.shape_index as usize].is_interface
        })
    {
        return;
    }
    let effects = settings.effects;
    let camera = &scene.camera;
    if effects.aperture && camera.lens_radius() > 0.0 {
        for axis in 0..2 {
            dimensions.push(ExploredDimension {
                kind: DimensionKind::Lens(axis),
                tiles: parameters.aperture_tiles.max(1),
            });
        }
    }
    if effects.wavelength {
        dimensions.push(ExploredDimension {
            kind: DimensionKind::Wavelength,
            tiles: settings.wavelength_tiles.max(1),
        });
    }
    if effects.time {
        dimensions.push(ExploredDimension {
            kind: DimensionKind::Time,
            tiles: settings.time_tiles.max(1),
        });
    }
    if breakup >= 1 {
        if effects.image {
            let [width, height] = camera.resolution();
            // The notes' image tiles: the class's, or 12 when the first
            // segment is in a medium (the same for every member of a set).
            let across = if scene.camera_medium.is_some() {
                settings.medium_image_tiles.max(1)
            } else {
                parameters.image_tiles.max(1)
            };
            let down = ((across as f64 * height as f64 / width as f64).round() as u32).max(1);
            for (axis, tiles) in [across, down].into_iter().enumerate() {
                dimensions.push(ExploredDimension {
                    kind: DimensionKind::Image(axis),
                    tiles,
                });
            }
        }
        if effects.direction {
            // Vertex x_{m+1} (layout vertex m) samples the direction to
            // x_{m+2}; at the full-path breakup b = k of an emission path
            // that includes the direction to the emitter, never a direction
            // past the last recorded vertex.
            let placing = breakup
                .saturating_sub(1)
                .min(path.vertices.len().saturating_sub(1));
            for vertex in 0..placing {
                if path.vertices[vertex].sampled.is_specular() {
                    continue;
                }
                for axis in 0..2 {
                    dimensions.push(ExploredDimension {
                        kind: DimensionKind::Direction { vertex, axis },
                        tiles: parameters.direction_tiles.max(1),
                    });
                }
            }
        }
        // The full-path breakup of a next-event path samples the light
        // point again (with the class's direction tiles: it places the
        // last segment's direction).
        if effects.direction
            && breakup > path.vertices.len()
            && let Terminal::NextEvent(connection) = path.event.terminal
            && !connection.is_delta
        {
            let vertex = path.vertices.len() - 1;
            for axis in 0..2 {
                dimensions.push(ExploredDimension {
                    kind: DimensionKind::LightPosition { vertex, axis },
                    tiles: parameters.direction_tiles.max(1),
                });
            }
        }
        if effects.free_flight {
            // The segment ending at x_{m+1} (layout vertex m) places it.
            for vertex in 0..breakup.min(path.vertices.len()) {
                if path.vertices[vertex].is_medium() {
                    dimensions.push(ExploredDimension {
                        kind: DimensionKind::FreeFlight { vertex },
                        tiles: settings.free_flight_tiles.max(1),
                    });
                }
            }
        }
    }
}
