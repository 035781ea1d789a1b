//! Reading Mitsuba XML files into an owned element tree, with the file-level
//! directives already applied in document order:
//!
//! - `<default name="..." value="..."/>` sets a parameter unless the command
//!   line (`-D name=value`) or an earlier default set it;
//! - `$name` in any attribute value is replaced by the parameter's value (an
//!   undefined parameter is an error naming file and line);
//! - `<include filename="..."/>` is replaced by the included file's elements
//!   (the children of its `<scene>`), the file found relative to the
//!   including file first, then along the search path;
//! - `<path value="..."/>` adds a directory (relative to the file it is in)
//!   to the search path used for includes, meshes and textures.
//!
//! Scenes of version 0.x/1.x (Mitsuba 0.6) name parameters in camelCase
//! (`toWorld`, `intIOR`, `maxDepth`); their `name` attributes are converted
//! to Mitsuba 2/3's snake_case as Mitsuba 3's upgrade does. Versions 2.x and
//! 3.x use the same names.

use super::super::loader::SceneFileError;
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Where an element comes from.
#[derive(Debug, Clone, PartialEq)]
pub struct Location {
    pub file: Arc<PathBuf>,
    /// 1-based line.
    pub line: u32,
}

impl Location {
    /// An error at this location.
    pub fn error(&self, message: impl Into<String>) -> SceneFileError {
        SceneFileError::Syntax {
            file: self.file.as_ref().clone(),
            line: self.line,
            message: message.into(),
        }
    }

    /// A warning text naming file and line.
    pub fn warning(&self, message: impl std::fmt::Display) -> String {
        format!("{}:{}: {message}", self.file.display(), self.line)
    }

    /// The directory of the file the element is in.
    pub fn directory(&self) -> &Path {
        self.file.parent().unwrap_or(Path::new(""))
    }
}

/// An XML element after parameter substitution and include expansion.
#[derive(Debug, Clone)]
pub struct Element {
    pub tag: String,
    pub attributes: Vec<(String, String)>,
    pub children: Vec<Element>,
    pub location: Location,
}

impl Element {
    /// The attribute's value, if present.
    pub fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|(key, _)| key == name)
            .map(|(_, value)| value.as_str())
    }

    /// The attribute's value, or an error naming it.
    pub fn required(&self, name: &str) -> Result<&str, SceneFileError> {
        self.attribute(name).ok_or_else(|| {
            self.location
                .error(format!("<{}> needs a '{name}' attribute", self.tag))
        })
    }
}

/// The directories searched for files named by the scene.
#[derive(Debug, Clone, Default)]
pub struct SearchPath {
    /// `<path>` directories, most recently added first (as Mitsuba's file
    /// resolver prepends them).
    pub directories: Vec<PathBuf>,
    /// The directory of the scene file given to the loader, searched last
    /// (Mitsuba resolves names in included files against it: its test
    /// scenes' `include/` fragments name `include/preamble.xml`).
    pub scene_directory: Option<PathBuf>,
}

impl SearchPath {
    /// Finds `name`: absolute as is; else relative to `directory` (the file
    /// that names it), then to each `<path>` directory, then to the scene
    /// file's directory. On failure the error lists every place looked.
    pub fn resolve(
        &self,
        name: &str,
        directory: &Path,
        location: &Location,
        what: &str,
    ) -> Result<PathBuf, SceneFileError> {
        let path = Path::new(name);
        let mut candidates: Vec<PathBuf> = Vec::new();
        if path.is_absolute() {
            candidates.push(path.to_path_buf());
        } else {
            for base in std::iter::once(directory)
                .chain(self.directories.iter().map(PathBuf::as_path))
                .chain(self.scene_directory.as_deref())
            {
                let candidate = base.join(path);
                if !candidates.contains(&candidate) {
                    candidates.push(candidate);
                }
            }
        }
        if let Some(found) = candidates.iter().find(|candidate| candidate.is_file()) {
            return Ok(found.clone());
        }
        let looked: Vec<String> = candidates.iter().map(|c| c.display().to_string()).collect();
        Err(location.error(format!(
            "{what} '{name}' not found (looked for {})",
            looked.join(", ")
        )))
    }
}

/// The state of reading a scene and its includes.
#[derive(Debug, Default)]
pub struct Reader {
    /// Parameter values: the command line's first, then defaults.
    pub parameters: HashMap<String, String>,
    pub search_path: SearchPath,
    pub warnings: Vec<String>,
    /// Files being read (to reject include cycles).
    stack: Vec<PathBuf>,
}

/// Deepest include nesting accepted.
const MAXIMUM_INCLUDE_DEPTH: usize = 32;

/// The line of a byte offset.
fn line_of(document: &roxmltree::Document, position: usize) -> u32 {
    document.text_pos_at(position).row
}

/// `toWorld` → `to_world`, `intIOR` → `int_ior`.
fn snake_case(name: &str) -> String {
    let mut result = String::with_capacity(name.len() + 4);
    let characters: Vec<char> = name.chars().collect();
    for (index, &c) in characters.iter().enumerate() {
        if c.is_ascii_uppercase() {
            let previous_lower = index > 0 && characters[index - 1].is_ascii_lowercase();
            if previous_lower {
                result.push('_');
            }
            result.push(c.to_ascii_lowercase());
        } else {
            result.push(c);
        }
    }
    result
}

impl Reader {
    /// A reader with the command line's parameters.
    pub fn new(parameters: &[(String, String)]) -> Self {
        Self {
            parameters: parameters.iter().cloned().collect(),
            ..Self::default()
        }
    }

    /// Replaces every `$name` in `value`.
    fn substitute(&self, value: &str, location: &Location) -> Result<String, SceneFileError> {
        if !value.contains('$') {
            return Ok(value.to_string());
        }
        let mut result = String::with_capacity(value.len());
        let mut rest = value;
        while let Some(dollar) = rest.find('$') {
            result.push_str(&rest[..dollar]);
            let after = &rest[dollar + 1..];
            let length = after
                .char_indices()
                .find(|(_, c)| !(c.is_ascii_alphanumeric() || *c == '_'))
                .map_or(after.len(), |(index, _)| index);
            if length == 0 {
                result.push('$');
                rest = after;
                continue;
            }
            let name = &after[..length];
            let replacement = self.parameters.get(name).ok_or_else(|| {
                location.error(format!(
                    "parameter ${name} is not defined (give it with -D {name}=VALUE or a <default>)"
                ))
            })?;
            result.push_str(replacement);
            rest = &after[length..];
        }
        result.push_str(rest);
        Ok(result)
    }

    /// Reads a whole file; returns its root element (`<scene>` for a scene).
    pub fn read_file(
        &mut self,
        path: &Path,
        location: Option<&Location>,
    ) -> Result<Element, SceneFileError> {
        if self.stack.len() >= MAXIMUM_INCLUDE_DEPTH || self.stack.iter().any(|p| p == path) {
            let message = format!("include cycle or nesting too deep at {}", path.display());
            return Err(match location {
                Some(location) => location.error(message),
                None => SceneFileError::Syntax {
                    file: path.to_path_buf(),
                    line: 1,
                    message,
                },
            });
        }
        let text = std::fs::read_to_string(path).map_err(|source| SceneFileError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        self.read_text(&text, path, location)
    }

    /// Reads the text of a whole file, named `path` in messages (and
    /// resolving relative paths from its directory); returns its root
    /// element.
    pub fn read_text(
        &mut self,
        text: &str,
        path: &Path,
        location: Option<&Location>,
    ) -> Result<Element, SceneFileError> {
        let document = roxmltree::Document::parse(text).map_err(|error| {
            let position = error.pos();
            SceneFileError::Syntax {
                file: path.to_path_buf(),
                line: position.row,
                message: format!("malformed XML: {error}"),
            }
        })?;
        let file = Arc::new(path.to_path_buf());
        if location.is_none() {
            self.search_path.scene_directory =
                Some(path.parent().unwrap_or(Path::new("")).to_path_buf());
        }
        let root = document.root_element();
        let root_location = Location {
            file: file.clone(),
            line: line_of(&document, root.range().start),
        };
        let version = root.attribute("version");
        let legacy_names = match version {
            Some(version) => {
                let major: Option<u32> = version.split('.').next().and_then(|m| m.parse().ok());
                match major {
                    Some(0 | 1) => true,
                    Some(2 | 3) => false,
                    _ => {
                        return Err(root_location.error(format!(
                            "unsupported scene version '{version}' (expected 0.x to 3.x)"
                        )));
                    }
                }
            }
            None => {
                if root.tag_name().name() == "scene" {
                    self.warnings.push(
                        root_location
                            .warning("<scene> has no version attribute; reading it as version 3"),
                    );
                }
                false
            }
        };
        self.stack.push(path.to_path_buf());
        let result = self.convert(&document, root, &file, legacy_names);
        self.stack.pop();
        let mut elements = result?;
        match elements.len() {
            1 => Ok(elements.remove(0)),
            _ => Err(root_location.error("expected one root element")),
        }
    }

    /// Converts `node` (one element, or several after an include).
    fn convert(
        &mut self,
        document: &roxmltree::Document,
        node: roxmltree::Node,
        file: &Arc<PathBuf>,
        legacy_names: bool,
    ) -> Result<Vec<Element>, SceneFileError> {
        let location = Location {
            file: file.clone(),
            line: line_of(document, node.range().start),
        };
        let tag = node.tag_name().name().to_string();
        let mut attributes = Vec::new();
        for attribute in node.attributes() {
            let mut value = self.substitute(attribute.value(), &location)?;
            if legacy_names && attribute.name() == "name" {
                value = snake_case(&value);
            }
            attributes.push((attribute.name().to_string(), value));
        }
        let get = |name: &str| {
            attributes
                .iter()
                .find(|(key, _)| key == name)
                .map(|(_, v): &(String, String)| v.clone())
        };
        match tag.as_str() {
            "default" => {
                let (Some(name), Some(value)) = (get("name"), get("value")) else {
                    return Err(location.error("<default> needs 'name' and 'value' attributes"));
                };
                self.parameters.entry(name).or_insert(value);
                return Ok(Vec::new());
            }
            "path" => {
                let value = get("value")
                    .ok_or_else(|| location.error("<path> needs a 'value' attribute"))?;
                let directory = location.directory().join(value);
                self.search_path.directories.insert(0, directory);
                return Ok(Vec::new());
            }
            "include" => {
                let name = get("filename")
                    .ok_or_else(|| location.error("<include> needs a 'filename' attribute"))?;
                let path = self.search_path.resolve(
                    &name,
                    location.directory(),
                    &location,
                    "included file",
                )?;
                let included = self.read_file(&path, Some(&location))?;
                return Ok(if included.tag == "scene" {
                    included.children
                } else {
                    vec![included]
                });
            }
            _ => {}
        }
        let mut children = Vec::new();
        for child in node.children().filter(|child| child.is_element()) {
            children.extend(self.convert(document, child, file, legacy_names)?);
        }
        Ok(vec![Element {
            tag,
            attributes,
            children,
            location,
        }])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn snake_case_of_legacy_names() {
        assert_eq!(snake_case("toWorld"), "to_world");
        assert_eq!(snake_case("intIOR"), "int_ior");
        assert_eq!(snake_case("maxDepth"), "max_depth");
        assert_eq!(snake_case("radiance"), "radiance");
    }

    #[test]
    fn substitution_replaces_every_parameter() {
        let mut reader = Reader::new(&[("a".into(), "1".into())]);
        reader.parameters.insert("bee".into(), "2".into());
        let location = Location {
            file: Arc::new(PathBuf::from("x.xml")),
            line: 3,
        };
        assert_eq!(
            reader.substitute("$a, $bee;$a$", &location).unwrap(),
            "1, 2;1$"
        );
        let error = reader.substitute("$nope", &location).unwrap_err();
        assert!(error.to_string().starts_with("x.xml:3:"), "{error}");
        assert!(error.to_string().contains("$nope"), "{error}");
    }
}
