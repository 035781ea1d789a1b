//! The pbrt-v4 scene loader. (To be written.)

use super::loader::{LoadOptions, LoadedScene, SceneFileError};
use std::path::Path;

/// Loads a pbrt-v4 scene.
pub fn load(path: &Path, _options: &LoadOptions) -> Result<LoadedScene, SceneFileError> {
    Err(SceneFileError::Syntax {
        file: path.to_path_buf(),
        line: 1,
        message: "pbrt-v4 scenes are not supported yet".into(),
    })
}
