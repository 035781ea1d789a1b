//! The pbrt-v4 scene loader, written from pbrt-v4's file-format reference
//! (<https://pbrt.org/fileformat-v4>): a [`tokenizer`] that keeps lines, typed
//! [`parameters`], the [`graphics_state`] (CTM, `ReverseOrientation`,
//! material, area light, media), and a [`parser`] that runs the directives
//! and hands them to [`camera`] (camera, film, sampler, filter, integrator),
//! [`shapes`], [`materials`] (and textures) and [`lights`] (and media).
//!
//! What the renderer cannot show becomes a warning naming file and line
//! (unknown directives, shapes, materials, lights, integrators, parameters
//! no one reads); malformed input is an error naming file, line and what was
//! expected; a missing include, mesh, texture or spectrum file names the
//! path that was looked for.
//!
//! Conventions: pbrt's `maxdepth` counts scattering events (default 5), the
//! project counts path segments (Mitsuba): depth = maxdepth + 1. Relative
//! file names resolve against the main file's directory (pbrt-v4), falling
//! back to the directory of the file that names them.

pub mod camera;
pub mod graphics_state;
pub mod lights;
pub mod materials;
pub mod parameters;
pub mod parser;
pub mod shapes;
pub mod spectrum_values;
pub mod tokenizer;

use super::description::SceneDescription;
use super::loader::{LoadOptions, LoadedScene, SceneFileError};
use camera::segments_from_pbrt_depth;
use parser::Loader;
use std::path::Path;

/// Loads a pbrt-v4 scene.
pub fn load(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneFileError> {
    let mut loader = Loader::new(path);
    for (name, _) in &options.parameters {
        loader.warnings.push(format!(
            "{}: parameter '{name}' given on the command line: pbrt-v4 files have no parameters",
            path.display()
        ));
    }
    loader.run_file(path, None)?;
    loader.finish_blocks()?;
    let camera_medium = match loader.camera.medium.clone() {
        None => None,
        Some(name) => match loader.named_media.get(&name) {
            Some(&index) => Some(index),
            None => {
                loader.warnings.push(format!(
                    "{}: the camera's medium \"{name}\" is not defined; vacuum is used",
                    path.display()
                ));
                None
            }
        },
    };
    let mut warnings = std::mem::take(&mut loader.warnings);
    let camera = loader.camera.perspective(&mut warnings);
    let description = SceneDescription {
        name: path
            .file_stem()
            .and_then(|stem| stem.to_str())
            .unwrap_or("pbrt scene")
            .to_string(),
        camera,
        filter: loader.camera.filter,
        shapes: loader.shapes,
        lights: loader.lights,
        media: loader.media,
        camera_medium,
        max_depth: Some(segments_from_pbrt_depth(loader.camera.pbrt_max_depth)),
        samples_per_pixel: Some(loader.camera.samples_per_pixel),
        russian_roulette_depth: None,
        integrator: loader.camera.integrator.clone(),
    };
    Ok(LoadedScene {
        description,
        warnings,
    })
}

#[cfg(test)]
mod tests;
