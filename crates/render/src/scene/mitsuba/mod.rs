//! The Mitsuba 3 (and 2) XML scene loader. (To be written.)

use super::loader::{LoadOptions, LoadedScene, SceneFileError};
use std::path::Path;

/// Loads a Mitsuba XML scene.
pub fn load(path: &Path, _options: &LoadOptions) -> Result<LoadedScene, SceneFileError> {
    Err(SceneFileError::Syntax {
        file: path.to_path_buf(),
        line: 1,
        message: "Mitsuba XML scenes are not supported yet".into(),
    })
}
