//! Reading scene files: the entry point that picks the format by the file's
//! extension (`.xml`: Mitsuba 3 (and 2) XML, [`super::mitsuba`]; `.pbrt`:
//! pbrt-v4, [`super::pbrt`]) and the error and warning types both loaders
//! share.

use super::description::SceneDescription;
use std::path::{Path, PathBuf};

/// Why a scene file cannot be loaded. Every variant names the file; syntax
/// and semantic errors also name the line (1-based) and say what was expected.
#[derive(Debug, thiserror::Error)]
pub enum SceneFileError {
    /// A file (the scene, an include, a mesh or a texture) cannot be read.
    #[error("cannot read {path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    /// The file is malformed or a value is invalid.
    #[error("{file}:{line}: {message}")]
    Syntax {
        file: PathBuf,
        line: u32,
        message: String,
    },
    /// The file's extension names no format this renderer reads.
    #[error("{path}: unknown scene format (expected .xml for Mitsuba 3 or .pbrt for pbrt-v4)")]
    UnknownFormat { path: PathBuf },
}

/// Options of a load.
#[derive(Debug, Clone, Default)]
pub struct LoadOptions {
    /// Values for the file's parameters (Mitsuba's `$name` with `<default>`;
    /// like `mitsuba -D name=value`), overriding the file's defaults.
    pub parameters: Vec<(String, String)>,
}

/// A loaded scene and what the loader could not use.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    /// The scene.
    pub description: SceneDescription,
    /// Elements the loader skipped or replaced, each naming file and line
    /// (e.g. an unknown plugin, or an integrator it does not know).
    pub warnings: Vec<String>,
}

/// Loads the scene file at `path`, choosing the format by its extension.
pub fn load_scene_file(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneFileError> {
    let extension = path
        .extension()
        .and_then(|extension| extension.to_str())
        .map(str::to_ascii_lowercase);
    match extension.as_deref() {
        Some("xml") => super::mitsuba::load(path, options),
        Some("pbrt") => super::pbrt::load(path, options),
        _ => Err(SceneFileError::UnknownFormat {
            path: path.to_path_buf(),
        }),
    }
}
