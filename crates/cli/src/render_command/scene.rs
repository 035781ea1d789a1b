//! The scene of a render: loaded from a file or the built-ins, built, and
//! the integrator it renders with when none is named.

use crate::error::{CliError, usage};
use render::integrators::IntegratorKind;
use render::scene::Scene;
use render::scene::builtin::{BUILTIN_SCENES, DEFAULT_SCENE, builtin_scene};
use render::scene::description::SceneDescription;
use render::scene::loader::{LoadOptions, load_scene_file};
use std::path::Path;

/// Loads the scene SCENE names: `builtin:NAME`, or a Mitsuba 3 / pbrt-v4
/// file with the `-D` parameter `definitions`; `resolution` (WxH) replaces
/// the camera's. The loader's warnings go to stderr unless `quiet`.
pub fn load_scene_description(
    scene_name: &str,
    definitions: &[(String, String)],
    resolution: Option<(u32, u32)>,
    quiet: bool,
) -> Result<SceneDescription, CliError> {
    let mut description = match scene_name.strip_prefix("builtin:") {
        Some(name) => builtin_scene(name).ok_or_else(|| {
            let names: Vec<&str> = BUILTIN_SCENES.iter().map(|(n, _)| *n).collect();
            usage(format!(
                "unknown built-in scene '{name}' (known: {})",
                names.join(", ")
            ))
        })?,
        None if Path::new(scene_name).exists() => {
            let options = LoadOptions {
                parameters: definitions.to_vec(),
            };
            let loaded = load_scene_file(Path::new(scene_name), &options)
                .map_err(|error| usage(error.to_string()))?;
            for warning in &loaded.warnings {
                if !quiet {
                    eprintln!("lqmc: warning: {warning}");
                }
            }
            loaded.description
        }
        None => {
            return Err(usage(format!(
                "no scene '{scene_name}': not a file, and built-in scenes are named builtin:NAME (default builtin:{DEFAULT_SCENE})"
            )));
        }
    };
    if let Some((width, height)) = resolution {
        if width == 0 || height == 0 {
            return Err(usage("--resolution needs a width and height of at least 1"));
        }
        description.camera.resolution = [width, height];
    }
    Ok(description)
}

/// Builds the renderable scene of `description` (`scene_name` names it in
/// errors).
pub fn build_scene(scene_name: &str, description: &SceneDescription) -> Result<Scene, CliError> {
    Scene::build(description).map_err(|error| usage(format!("{scene_name}: {error}")))
}

/// The integrator `lqmc render` uses when none is named: volpath for scenes
/// with participating media, light tracing for Mitsuba files that ask for
/// `ptracer`, else path.
pub fn default_integrator(description: &SceneDescription, scene: &Scene) -> IntegratorKind {
    if scene.has_media() {
        IntegratorKind::VolPath
    } else if description.integrator.as_deref() == Some("ptracer") {
        // Mitsuba's light tracer.
        IntegratorKind::Light
    } else {
        IntegratorKind::Path
    }
}

/// The path tracer for `scene`: volpath where it has participating media,
/// else path (what "path tracing" means in comparisons and references).
pub fn default_path_tracer(scene: &Scene) -> IntegratorKind {
    if scene.has_media() {
        IntegratorKind::VolPath
    } else {
        IntegratorKind::Path
    }
}
