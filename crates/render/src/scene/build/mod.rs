//! Building a [`Scene`](super::Scene) from its description, one module per
//! kind of thing built: `shapes`, `materials`, [`textures`] (for materials
//! and lights), `lights`, `media` and the `film`'s filter.
//! This is the one place where the scene description meets the renderer's
//! layers (geometry, materials, lights, textures, film, spectra, media):
//! they know nothing of the description; the builders here translate it,
//! check it and turn the layers' own errors into [`SceneError`]s.

pub(super) mod film;
pub(super) mod lights;
pub(super) mod materials;
pub(super) mod media;
pub(super) mod shapes;
pub mod textures;

pub use textures::{build_float_texture, build_rgb_texture, build_spectrum_texture};

use super::SceneError;

/// A parameter error naming `what`, with `error`'s text as its message.
pub(super) fn parameter_error(what: &str, error: impl std::fmt::Display) -> SceneError {
    SceneError::Parameter {
        what: what.to_string(),
        message: error.to_string(),
    }
}
