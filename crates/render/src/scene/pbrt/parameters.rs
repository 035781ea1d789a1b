//! pbrt-v4 parameter lists: `"type name" value` or `"type name" [ values ]`
//! after a directive, with typed accessors that apply explicit defaults and
//! name file and line when a value has the wrong type or count.
//!
//! Types (pbrt-v4's file-format reference): `integer`, `float`, `point2`,
//! `vector2`, `point3`, `vector3`, `normal` (also `normal3`), `bool`,
//! `string`, `texture` (a named texture), and the spectral types `rgb`,
//! `spectrum` (wavelength–value pairs, a named spectrum or a file) and
//! `blackbody` (a temperature in kelvin). pbrt-v3's `color`, `point`,
//! `vector` are read as `rgb`, `point3`, `vector3`.

use crate::scene::loader::SceneFileError;
use std::cell::Cell;
use std::path::Path;
use std::sync::Arc;

/// Where something is in the scene files.
#[derive(Debug, Clone, PartialEq)]
pub struct Position {
    pub file: Arc<Path>,
    pub line: u32,
}

impl Position {
    /// An error at this position.
    pub fn error(&self, message: impl Into<String>) -> SceneFileError {
        SceneFileError::Syntax {
            file: self.file.to_path_buf(),
            line: self.line,
            message: message.into(),
        }
    }

    /// A warning at this position, as `LoadedScene::warnings` holds them.
    pub fn warning(&self, message: impl std::fmt::Display) -> String {
        format!("{}:{}: {message}", self.file.display(), self.line)
    }
}

/// The values of one parameter.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    Numbers(Vec<f64>),
    Strings(Vec<String>),
    Bools(Vec<bool>),
}

impl Values {
    fn len(&self) -> usize {
        match self {
            Values::Numbers(v) => v.len(),
            Values::Strings(v) => v.len(),
            Values::Bools(v) => v.len(),
        }
    }
}

/// The value kind a parameter type holds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ValueKind {
    Numbers,
    Strings,
    Bools,
    /// `spectrum`: numbers (pairs) or one string (a name or a file).
    NumbersOrString,
}

/// The canonical name and value kind of a declared type, or `None` if pbrt
/// has no such type.
pub fn canonical_type(declared: &str) -> Option<(&'static str, ValueKind)> {
    Some(match declared {
        "integer" => ("integer", ValueKind::Numbers),
        "float" => ("float", ValueKind::Numbers),
        "point2" => ("point2", ValueKind::Numbers),
        "vector2" => ("vector2", ValueKind::Numbers),
        "point3" | "point" => ("point3", ValueKind::Numbers),
        "vector3" | "vector" => ("vector3", ValueKind::Numbers),
        "normal" | "normal3" => ("normal", ValueKind::Numbers),
        "rgb" | "color" => ("rgb", ValueKind::Numbers),
        "blackbody" => ("blackbody", ValueKind::Numbers),
        "spectrum" => ("spectrum", ValueKind::NumbersOrString),
        "bool" => ("bool", ValueKind::Bools),
        "string" => ("string", ValueKind::Strings),
        "texture" => ("texture", ValueKind::Strings),
        _ => return None,
    })
}

/// One parameter as declared in the file.
#[derive(Debug, Clone)]
pub struct Parameter {
    /// The canonical type (`point3` for pbrt-v3's `point`, ...).
    pub type_name: &'static str,
    pub name: String,
    pub values: Values,
    pub position: Position,
    used: Cell<bool>,
}

impl Parameter {
    /// A parameter (unused so far).
    pub fn new(type_name: &'static str, name: String, values: Values, position: Position) -> Self {
        Self {
            type_name,
            name,
            values,
            position,
            used: Cell::new(false),
        }
    }

    fn error(&self, message: impl std::fmt::Display) -> SceneFileError {
        self.position.error(format!(
            "parameter \"{} {}\": {message}",
            self.type_name, self.name
        ))
    }

    /// The numbers, checking the count is a multiple of `group` (and not 0).
    fn numbers(&self, group: usize) -> Result<&[f64], SceneFileError> {
        match &self.values {
            Values::Numbers(numbers)
                if !numbers.is_empty() && numbers.len().is_multiple_of(group) =>
            {
                Ok(numbers)
            }
            Values::Numbers(numbers) => Err(self.error(format!(
                "expected a multiple of {group} numbers, found {}",
                numbers.len()
            ))),
            _ => Err(self.error("expected numbers")),
        }
    }

    fn single_number(&self) -> Result<f64, SceneFileError> {
        match &self.values {
            Values::Numbers(numbers) if numbers.len() == 1 => Ok(numbers[0]),
            other => Err(self.error(format!("expected one value, found {}", other.len()))),
        }
    }

    /// The spectrum values: numbers, or the string naming a spectrum or file.
    pub fn spectrum_values(&self) -> &Values {
        &self.values
    }

    /// The declared type as a description for messages.
    pub fn describe(&self) -> String {
        format!("\"{} {}\"", self.type_name, self.name)
    }
}

fn to_f32(parameter: &Parameter, value: f64) -> Result<f32, SceneFileError> {
    let single = value as f32;
    if single.is_finite() {
        Ok(single)
    } else {
        Err(parameter.error(format!("{value} is not a finite single-precision number")))
    }
}

fn to_integer(parameter: &Parameter, value: f64) -> Result<i64, SceneFileError> {
    if value.fract() == 0.0 && value.abs() < 9.0e15 {
        Ok(value as i64)
    } else {
        Err(parameter.error(format!("{value} is not an integer")))
    }
}

/// The parameters of one directive.
#[derive(Debug, Clone)]
pub struct ParameterList {
    pub parameters: Vec<Parameter>,
}

impl ParameterList {
    /// The parameter called `name`, marked as used.
    pub fn find(&self, name: &str) -> Option<&Parameter> {
        // pbrt lets a later declaration of the same name win.
        let parameter = self.parameters.iter().rev().find(|p| p.name == name)?;
        parameter.used.set(true);
        Some(parameter)
    }

    /// The parameter called `name` if it has one of `types`; an error if it
    /// has another type.
    fn typed(&self, name: &str, types: &[&str]) -> Result<Option<&Parameter>, SceneFileError> {
        match self.find(name) {
            None => Ok(None),
            Some(parameter) if types.contains(&parameter.type_name) => Ok(Some(parameter)),
            Some(parameter) => Err(parameter.error(format!(
                "has type '{}' but '{}' needs {}",
                parameter.type_name,
                name,
                types
                    .iter()
                    .map(|t| format!("'{t}'"))
                    .collect::<Vec<_>>()
                    .join(" or ")
            ))),
        }
    }

    /// Whether a parameter called `name` is present (without marking it used).
    pub fn has(&self, name: &str) -> bool {
        self.parameters.iter().any(|p| p.name == name)
    }

    /// A `float`.
    pub fn float(&self, name: &str, default: f32) -> Result<f32, SceneFileError> {
        match self.typed(name, &["float"])? {
            None => Ok(default),
            Some(p) => to_f32(p, p.single_number()?),
        }
    }

    /// A `float` that must be present to have an effect.
    pub fn optional_float(&self, name: &str) -> Result<Option<f32>, SceneFileError> {
        match self.typed(name, &["float"])? {
            None => Ok(None),
            Some(p) => Ok(Some(to_f32(p, p.single_number()?)?)),
        }
    }

    /// Every value of a `float` array.
    pub fn floats(&self, name: &str) -> Result<Option<Vec<f32>>, SceneFileError> {
        match self.typed(name, &["float"])? {
            None => Ok(None),
            Some(p) => p
                .numbers(1)?
                .iter()
                .map(|&v| to_f32(p, v))
                .collect::<Result<Vec<_>, _>>()
                .map(Some),
        }
    }

    /// An `integer`.
    pub fn integer(&self, name: &str, default: i64) -> Result<i64, SceneFileError> {
        match self.typed(name, &["integer"])? {
            None => Ok(default),
            Some(p) => to_integer(p, p.single_number()?),
        }
    }

    /// Every value of an `integer` array.
    pub fn integers(&self, name: &str) -> Result<Option<Vec<i64>>, SceneFileError> {
        match self.typed(name, &["integer"])? {
            None => Ok(None),
            Some(p) => p
                .numbers(1)?
                .iter()
                .map(|&v| to_integer(p, v))
                .collect::<Result<Vec<_>, _>>()
                .map(Some),
        }
    }

    /// A `bool`.
    pub fn bool(&self, name: &str, default: bool) -> Result<bool, SceneFileError> {
        match self.typed(name, &["bool"])? {
            None => Ok(default),
            Some(p) => match &p.values {
                Values::Bools(values) if values.len() == 1 => Ok(values[0]),
                other => Err(p.error(format!("expected one value, found {}", other.len()))),
            },
        }
    }

    /// A `string`.
    pub fn string(&self, name: &str) -> Result<Option<String>, SceneFileError> {
        self.string_of_types(name, &["string"])
    }

    fn string_of_types(
        &self,
        name: &str,
        types: &[&str],
    ) -> Result<Option<String>, SceneFileError> {
        match self.typed(name, types)? {
            None => Ok(None),
            Some(p) => match &p.values {
                Values::Strings(values) if values.len() == 1 => Ok(Some(values[0].clone())),
                other => Err(p.error(format!("expected one string, found {}", other.len()))),
            },
        }
    }

    /// Every value of a `string` array.
    pub fn strings(&self, name: &str) -> Result<Option<Vec<String>>, SceneFileError> {
        match self.typed(name, &["string"])? {
            None => Ok(None),
            Some(p) => match &p.values {
                Values::Strings(values) => Ok(Some(values.clone())),
                _ => Err(p.error("expected strings")),
            },
        }
    }

    /// Groups of `N` numbers of one of `types` (points, normals, ...).
    pub fn tuples<const N: usize>(
        &self,
        name: &str,
        types: &[&str],
    ) -> Result<Option<Vec<[f32; N]>>, SceneFileError> {
        match self.typed(name, types)? {
            None => Ok(None),
            Some(p) => {
                let numbers = p.numbers(N)?;
                let mut tuples = Vec::with_capacity(numbers.len() / N);
                for chunk in numbers.chunks_exact(N) {
                    let mut tuple = [0.0; N];
                    for (slot, &value) in tuple.iter_mut().zip(chunk) {
                        *slot = to_f32(p, value)?;
                    }
                    tuples.push(tuple);
                }
                Ok(Some(tuples))
            }
        }
    }

    /// One `point3`.
    pub fn point3(&self, name: &str, default: [f32; 3]) -> Result<[f32; 3], SceneFileError> {
        match self.tuples::<3>(name, &["point3"])? {
            None => Ok(default),
            Some(points) if points.len() == 1 => Ok(points[0]),
            Some(points) => Err(self
                .find(name)
                .expect("present")
                .error(format!("expected one point, found {}", points.len()))),
        }
    }

    /// The name of the texture bound to `name` (`"texture name" "value"`),
    /// if the parameter is a texture reference.
    pub fn texture_reference(&self, name: &str) -> Result<Option<String>, SceneFileError> {
        match self.parameters.iter().rev().find(|p| p.name == name) {
            Some(p) if p.type_name == "texture" => self.string_of_types(name, &["texture"]),
            _ => Ok(None),
        }
    }

    /// The parameters no accessor asked for.
    pub fn unused(&self) -> impl Iterator<Item = &Parameter> {
        self.parameters.iter().filter(|p| !p.used.get())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn list(parameters: Vec<(&'static str, &str, Values)>) -> ParameterList {
        let position = Position {
            file: Arc::from(Path::new("scene.pbrt")),
            line: 7,
        };
        ParameterList {
            parameters: parameters
                .into_iter()
                .map(|(t, n, v)| Parameter::new(t, n.into(), v, position.clone()))
                .collect(),
        }
    }

    #[test]
    fn defaults_apply_to_missing_parameters() {
        let parameters = list(vec![]);
        assert_eq!(parameters.float("radius", 1.0).unwrap(), 1.0);
        assert_eq!(parameters.integer("maxdepth", 5).unwrap(), 5);
        assert!(parameters.bool("twosided", true).unwrap());
        assert_eq!(parameters.string("filename").unwrap(), None);
        assert_eq!(parameters.point3("from", [0.0; 3]).unwrap(), [0.0; 3]);
    }

    #[test]
    fn type_errors_name_file_line_and_types() {
        let parameters = list(vec![("integer", "radius", Values::Numbers(vec![2.0]))]);
        let message = parameters.float("radius", 1.0).unwrap_err().to_string();
        assert!(message.starts_with("scene.pbrt:7:"), "{message}");
        assert!(
            message.contains("'integer'") && message.contains("'float'"),
            "{message}"
        );
        let parameters = list(vec![("float", "radius", Values::Numbers(vec![1.0, 2.0]))]);
        let message = parameters.float("radius", 1.0).unwrap_err().to_string();
        assert!(message.contains("expected one value, found 2"), "{message}");
        let parameters = list(vec![("integer", "n", Values::Numbers(vec![1.5]))]);
        assert!(parameters.integer("n", 1).is_err());
        let parameters = list(vec![("point3", "P", Values::Numbers(vec![1.0, 2.0]))]);
        let message = parameters
            .tuples::<3>("P", &["point3"])
            .unwrap_err()
            .to_string();
        assert!(message.contains("multiple of 3"), "{message}");
    }

    #[test]
    fn unused_parameters_are_reported() {
        let parameters = list(vec![
            ("float", "radius", Values::Numbers(vec![2.0])),
            ("float", "zmin", Values::Numbers(vec![0.0])),
        ]);
        assert_eq!(parameters.float("radius", 1.0).unwrap(), 2.0);
        let unused: Vec<&str> = parameters.unused().map(|p| p.name.as_str()).collect();
        assert_eq!(unused, ["zmin"]);
    }

    #[test]
    fn later_declarations_win() {
        let parameters = list(vec![
            ("float", "radius", Values::Numbers(vec![2.0])),
            ("float", "radius", Values::Numbers(vec![3.0])),
        ]);
        assert_eq!(parameters.float("radius", 1.0).unwrap(), 3.0);
    }
}
