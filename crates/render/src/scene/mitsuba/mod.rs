//! The Mitsuba 3 (and 2) XML scene loader.
//!
//! [`xml`] reads the files (parameters, includes, search paths) into an
//! element tree; [`values`] and [`transforms`] read plugin parameters; one
//! module per plugin family turns plugins into the
//! [`SceneDescription`](super::description::SceneDescription):
//! [`bsdfs`], [`textures`], [`shapes`], [`emitters`], [`sensor`] (sensor,
//! film, filter, sampler), [`media`] and [`integrator`].
//!
//! What the loader does not know (a plugin type, an element, a parameter) is
//! a warning naming file and line, and the scene still loads; malformed
//! values, missing files and dangling references are errors naming file,
//! line and what was expected.

mod bsdfs;
mod emitters;
mod integrator;
mod media;
mod named_values;
mod sensor;
mod shapes;
mod textures;
mod transforms;
mod values;
mod xml;

#[cfg(test)]
mod tests;

pub use named_values::{conductor_spectra, named_ior};
pub use transforms::mitsuba_look_at;

use super::description::{
    FilterDescription, MaterialDescription, SceneDescription, TextureDescription,
};
use super::loader::{LoadOptions, LoadedScene, SceneFileError};
use crate::camera::PerspectiveSettings;
use std::collections::{HashMap, HashSet};
use std::path::{Path, PathBuf};
use values::Properties;
use xml::{Element, Reader, SearchPath};

/// An object a `<ref id="..."/>` can name.
#[derive(Debug, Clone)]
#[allow(clippy::large_enum_variant)] // a few per scene; boxing buys nothing
enum NamedObject {
    Bsdf(MaterialDescription),
    Texture(TextureDescription),
    /// An index into the description's media.
    Medium(usize),
    /// An `area` emitter's radiance (`None`: one that cannot be represented).
    AreaEmitter(Option<super::description::TextureDescription>),
    /// Something else with an id (a shape, an emitter): not referable here.
    Other(String),
}

impl NamedObject {
    fn kind(&self) -> &str {
        match self {
            NamedObject::Bsdf(_) => "bsdf",
            NamedObject::Texture(_) => "texture",
            NamedObject::Medium(_) => "medium",
            NamedObject::AreaEmitter(_) => "area emitter",
            NamedObject::Other(tag) => tag,
        }
    }
}

/// The state of turning a scene's elements into a description.
struct Loader {
    search_path: SearchPath,
    warnings: Vec<String>,
    objects: HashMap<String, NamedObject>,
    /// The scene's top-level elements with an id, for references to
    /// objects defined later in the file (Mitsuba allows them).
    declared: HashMap<String, Element>,
    /// Ids of top-level elements read early for such a reference (skipped
    /// when the walk reaches them).
    read_early: HashSet<String>,
    /// Mesh files read so far (scenes often place one mesh many times).
    meshes: HashMap<PathBuf, std::sync::Arc<super::mesh_files::MeshData>>,
    description: SceneDescription,
    have_sensor: bool,
}

/// Mitsuba's defaults where the file names no sensor: a 768 × 576 film with
/// a Gaussian filter, a 45° horizontal field of view, 4 samples per pixel.
fn default_description(name: String) -> SceneDescription {
    SceneDescription {
        name,
        camera: PerspectiveSettings {
            resolution: [768, 576],
            ..PerspectiveSettings::default()
        },
        filter: FilterDescription::Gaussian {
            radius: 2.0,
            sigma: 0.5,
        },
        shapes: Vec::new(),
        lights: Vec::new(),
        media: Vec::new(),
        camera_medium: None,
        max_depth: None,
        samples_per_pixel: None,
        russian_roulette_depth: None,
        integrator: None,
    }
}

impl Loader {
    /// Records a warning at `element`.
    fn warn(&mut self, element: &Element, message: impl std::fmt::Display) {
        self.warnings.push(element.location.warning(message));
    }

    /// Warns about the plugin's unread parameters.
    fn finish(&mut self, properties: &Properties) {
        properties.finish(&mut self.warnings);
    }

    /// Finds a file named by `element`'s scene file.
    fn resolve(
        &self,
        element: &Element,
        name: &str,
        what: &str,
    ) -> Result<PathBuf, SceneFileError> {
        self.search_path
            .resolve(name, element.location.directory(), &element.location, what)
    }

    /// Reads a text file named by `element` (e.g. a `.spd` spectrum).
    fn read_text(&self, element: &Element, name: &str) -> Result<String, SceneFileError> {
        let path = self.resolve(element, name, "spectrum file")?;
        std::fs::read_to_string(&path).map_err(|source| SceneFileError::Io { path, source })
    }

    /// Registers `object` under `element`'s `id`, if it has one.
    fn register(&mut self, element: &Element, object: NamedObject) -> Result<(), SceneFileError> {
        if let Some(id) = element.attribute("id") {
            if self.objects.contains_key(id) {
                return Err(element
                    .location
                    .error(format!("the id '{id}' is defined twice")));
            }
            self.objects.insert(id.to_string(), object);
        }
        Ok(())
    }

    /// The object a `<ref>` names; one defined later at the top level of
    /// the scene is read now.
    fn referenced(&mut self, element: &Element) -> Result<NamedObject, SceneFileError> {
        let id = element.required("id")?;
        if !self.objects.contains_key(id)
            && let Some(declared) = self.declared.remove(id)
        {
            match declared.tag.as_str() {
                "emitter" => {
                    let _ = self.area_emitter(&declared)?;
                }
                _ => self.scene_child(&declared)?,
            }
            self.read_early.insert(id.to_string());
        }
        self.objects.get(id).cloned().ok_or_else(|| {
            element.location.error(format!(
                "<ref id=\"{id}\">: no bsdf, texture, medium or area emitter has this id"
            ))
        })
    }

    /// Handles one child of `<scene>`.
    fn scene_child(&mut self, element: &Element) -> Result<(), SceneFileError> {
        if let Some(id) = element.attribute("id") {
            if self.read_early.remove(id) {
                // Read already, for a reference that came before it.
                return Ok(());
            }
            self.declared.remove(id);
        }
        match element.tag.as_str() {
            "integrator" => self.integrator(element),
            "sensor" => self.sensor(element),
            "shape" => self.shape(element),
            "emitter" => self.emitter(element),
            "bsdf" => self.bsdf(element).map(|_| ()),
            "texture" => {
                let _ = self.texture(element)?;
                Ok(())
            }
            "medium" => {
                let _ = self.medium(element)?;
                Ok(())
            }
            other => {
                self.warn(
                    element,
                    format!("unknown element <{other}> in <scene> is ignored"),
                );
                Ok(())
            }
        }
    }
}

/// Loads a Mitsuba XML scene.
pub fn load(path: &Path, options: &LoadOptions) -> Result<LoadedScene, SceneFileError> {
    let mut reader = Reader::new(&options.parameters);
    let root = reader.read_file(path, None)?;
    load_root(reader, root, path)
}

/// Loads a Mitsuba XML scene from its text, named `path` in messages (its
/// relative file references resolve from `path`'s directory): the built-in
/// scenes that are Mitsuba files ([`crate::scene::builtin`]).
pub fn load_text(
    text: &str,
    path: &Path,
    options: &LoadOptions,
) -> Result<LoadedScene, SceneFileError> {
    let mut reader = Reader::new(&options.parameters);
    let root = reader.read_text(text, path, None)?;
    load_root(reader, root, path)
}

/// Builds the scene of a root element read by `reader` from `path`.
fn load_root(reader: Reader, root: Element, path: &Path) -> Result<LoadedScene, SceneFileError> {
    if root.tag != "scene" {
        return Err(root.location.error(format!(
            "the root element is <{}>, expected <scene>",
            root.tag
        )));
    }
    let name = path
        .file_stem()
        .map(|stem| stem.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scene".into());
    let mut loader = Loader {
        search_path: reader.search_path,
        warnings: reader.warnings,
        objects: HashMap::new(),
        declared: root
            .children
            .iter()
            .filter_map(|child| Some((child.attribute("id")?.to_string(), child.clone())))
            .collect(),
        read_early: HashSet::new(),
        meshes: HashMap::new(),
        description: default_description(name),
        have_sensor: false,
    };
    for child in &root.children {
        loader.scene_child(child)?;
    }
    if !loader.have_sensor {
        loader.warnings.push(root.location.warning(
            "the scene has no <sensor>: using Mitsuba's default camera at the origin looking along +z",
        ));
    }
    Ok(LoadedScene {
        description: loader.description,
        warnings: loader.warnings,
    })
}
