//! The directive loop: reads tokens, parses each directive's arguments and
//! parameter list, keeps the graphics state, and hands shapes, materials,
//! lights and the camera to their modules ([`super::shapes`],
//! [`super::materials`], [`super::lights`], [`super::camera`]).

use super::camera::CameraSettings;
use super::graphics_state::{CurrentMaterial, GraphicsState, look_at};
use super::parameters::{Parameter, ParameterList, Position, ValueKind, Values, canonical_type};
use super::tokenizer::{Token, TokenKind, tokenize};
use crate::scene::description::{
    MaterialDescription, MediumDescription, ShapeDescription, TextureDescription,
};
use crate::scene::loader::SceneFileError;
use glam::{DMat4, DVec3};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

/// Nested `Include`/`Import` beyond this depth is an error (a file that
/// includes itself).
const MAXIMUM_INCLUDE_DEPTH: usize = 32;

/// More included files than this in one scene is an error (files that
/// include themselves several times would otherwise take exponential time).
const MAXIMUM_INCLUDED_FILES: usize = 10_000;

/// The tokens of one file and a read position.
pub struct Cursor {
    tokens: Vec<Token>,
    index: usize,
    pub file: Arc<Path>,
}

impl Cursor {
    /// Tokenizes `bytes`, the contents of `file`.
    pub fn new(bytes: &[u8], file: &Path) -> Result<Self, SceneFileError> {
        Ok(Self {
            tokens: tokenize(bytes, file)?,
            index: 0,
            file: Arc::from(file),
        })
    }

    fn peek(&self) -> Option<&Token> {
        self.tokens.get(self.index)
    }

    fn next(&mut self) -> Option<Token> {
        let token = self.tokens.get(self.index).cloned();
        self.index += usize::from(token.is_some());
        token
    }

    /// The position of `line` in this file.
    pub fn at(&self, line: u32) -> Position {
        Position {
            file: self.file.clone(),
            line,
        }
    }

    /// The line of the last token (for errors at the end of the file).
    fn last_line(&self) -> u32 {
        self.tokens.last().map_or(1, |t| t.line)
    }

    fn expect_string(&mut self, directive: &str, what: &str) -> Result<String, SceneFileError> {
        match self.next() {
            Some(Token {
                kind: TokenKind::String,
                text,
                ..
            }) => Ok(text),
            Some(other) => Err(self.at(other.line).error(format!(
                "{directive}: expected {what} (a quoted string), found {}",
                other.describe()
            ))),
            None => Err(self.at(self.last_line()).error(format!(
                "{directive}: expected {what} (a quoted string), found the end of the file"
            ))),
        }
    }

    fn expect_number(&mut self, directive: &str) -> Result<f64, SceneFileError> {
        match self.next() {
            Some(token) if token.kind == TokenKind::Word => {
                parse_number(&token.text).ok_or_else(|| {
                    self.at(token.line).error(format!(
                        "{directive}: expected a number, found {}",
                        token.describe()
                    ))
                })
            }
            Some(other) => Err(self.at(other.line).error(format!(
                "{directive}: expected a number, found {}",
                other.describe()
            ))),
            None => Err(self.at(self.last_line()).error(format!(
                "{directive}: expected a number, found the end of the file"
            ))),
        }
    }

    /// `count` numbers, optionally enclosed in brackets.
    fn expect_numbers(
        &mut self,
        directive: &str,
        count: usize,
    ) -> Result<Vec<f64>, SceneFileError> {
        let bracketed = matches!(self.peek(), Some(t) if t.kind == TokenKind::OpenBracket);
        if bracketed {
            self.next();
        }
        let numbers = (0..count)
            .map(|_| self.expect_number(directive))
            .collect::<Result<Vec<_>, _>>()?;
        if bracketed {
            match self.next() {
                Some(t) if t.kind == TokenKind::CloseBracket => {}
                Some(t) => {
                    return Err(self.at(t.line).error(format!(
                        "{directive}: expected ']' after {count} numbers, found {}",
                        t.describe()
                    )));
                }
                None => {
                    return Err(self.at(self.last_line()).error(format!(
                        "{directive}: expected ']', found the end of the file"
                    )));
                }
            }
        }
        Ok(numbers)
    }

    /// The parameter list that follows a directive's fixed arguments.
    pub fn parameter_list(&mut self) -> Result<ParameterList, SceneFileError> {
        let mut parameters = Vec::new();
        while let Some(token) = self.peek() {
            if token.kind != TokenKind::String {
                break;
            }
            let declaration = self.next().expect("peeked");
            let position = self.at(declaration.line);
            let words: Vec<&str> = declaration.text.split_whitespace().collect();
            let [declared_type, name] = words[..] else {
                return Err(position.error(format!(
                    "expected a parameter declaration \"type name\", found \"{}\"",
                    declaration.text
                )));
            };
            let (type_name, kind) = canonical_type(declared_type).ok_or_else(|| {
                position.error(format!(
                    "unknown parameter type '{declared_type}' in \"{}\" (expected integer, float, point2, vector2, point3, vector3, normal, rgb, spectrum, blackbody, bool, string or texture)",
                    declaration.text
                ))
            })?;
            let mut value_tokens = Vec::new();
            match self.next() {
                Some(t) if t.kind == TokenKind::OpenBracket => loop {
                    match self.next() {
                        Some(t) if t.kind == TokenKind::CloseBracket => break,
                        Some(t) if t.kind == TokenKind::OpenBracket => {
                            return Err(self.at(t.line).error(format!(
                                "parameter \"{}\": '[' inside a value list",
                                declaration.text
                            )));
                        }
                        Some(t) => value_tokens.push(t),
                        None => {
                            return Err(position.error(format!(
                                "parameter \"{}\": expected ']' to close its values, found the end of the file",
                                declaration.text
                            )));
                        }
                    }
                },
                Some(t) if t.kind != TokenKind::CloseBracket => value_tokens.push(t),
                Some(t) => {
                    return Err(self.at(t.line).error(format!(
                        "parameter \"{}\": expected a value, found ']'",
                        declaration.text
                    )));
                }
                None => {
                    return Err(position.error(format!(
                        "parameter \"{}\": expected a value, found the end of the file",
                        declaration.text
                    )));
                }
            }
            let values = self.values(&declaration.text, kind, &value_tokens)?;
            parameters.push(Parameter::new(
                type_name,
                name.to_string(),
                values,
                position,
            ));
        }
        Ok(ParameterList { parameters })
    }

    fn values(
        &self,
        declaration: &str,
        kind: ValueKind,
        tokens: &[Token],
    ) -> Result<Values, SceneFileError> {
        let numbers = || {
            tokens
                .iter()
                .map(|t| {
                    (t.kind == TokenKind::Word)
                        .then(|| parse_number(&t.text))
                        .flatten()
                        .ok_or_else(|| {
                            self.at(t.line).error(format!(
                                "parameter \"{declaration}\": expected a number, found {}",
                                t.describe()
                            ))
                        })
                })
                .collect::<Result<Vec<f64>, _>>()
                .map(Values::Numbers)
        };
        let strings = || {
            tokens
                .iter()
                .map(|t| {
                    if t.kind == TokenKind::String {
                        Ok(t.text.clone())
                    } else {
                        Err(self.at(t.line).error(format!(
                            "parameter \"{declaration}\": expected a quoted string, found {}",
                            t.describe()
                        )))
                    }
                })
                .collect::<Result<Vec<String>, _>>()
                .map(Values::Strings)
        };
        match kind {
            ValueKind::Numbers => numbers(),
            ValueKind::Strings => strings(),
            ValueKind::NumbersOrString => {
                if tokens.first().is_some_and(|t| t.kind == TokenKind::String) {
                    strings()
                } else {
                    numbers()
                }
            }
            ValueKind::Bools => tokens
                .iter()
                .map(|t| match t.text.as_str() {
                    "true" => Ok(true),
                    "false" => Ok(false),
                    _ => Err(self.at(t.line).error(format!(
                        "parameter \"{declaration}\": expected true or false, found {}",
                        t.describe()
                    ))),
                })
                .collect::<Result<Vec<bool>, _>>()
                .map(Values::Bools),
        }
    }

    /// Skips the arguments of a directive this loader does not know: every
    /// token up to the next word that is not a number or a boolean.
    fn skip_arguments(&mut self) {
        while let Some(token) = self.peek() {
            let is_value = token.kind != TokenKind::Word
                || parse_number(&token.text).is_some()
                || token.text == "true"
                || token.text == "false";
            if !is_value {
                break;
            }
            self.next();
        }
    }
}

/// A number as pbrt writes them (decimal, optional exponent); `None` for
/// anything else, including `inf` and `nan`.
pub fn parse_number(text: &str) -> Option<f64> {
    let looks_numeric = text
        .chars()
        .all(|c| c.is_ascii_digit() || matches!(c, '+' | '-' | '.' | 'e' | 'E'));
    if !looks_numeric {
        return None;
    }
    text.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// What an `AttributeBegin`-like directive pushed.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Scope {
    Attribute,
    /// pbrt-v3's `TransformBegin` (only the CTM is restored).
    Transform,
    /// `ObjectBegin` (implies an attribute scope in pbrt-v4).
    Object,
}

/// An object definition (`ObjectBegin`): its shapes in world space as if
/// instanced with the identity.
#[derive(Debug, Clone)]
pub struct ObjectDefinition {
    pub shapes: Vec<ShapeDescription>,
}

/// Everything the loader keeps while reading.
pub struct Loader {
    /// Relative file names resolve against the main file's directory, as in
    /// pbrt-v4 (then against the including file's, as a convenience).
    pub search_directory: PathBuf,
    pub warnings: Vec<String>,
    pub state: GraphicsState,
    stack: Vec<(GraphicsState, Position, Scope)>,
    named_coordinate_systems: HashMap<String, DMat4>,
    pub named_materials: HashMap<String, MaterialDescription>,
    pub float_textures: HashMap<String, TextureDescription>,
    pub spectrum_textures: HashMap<String, TextureDescription>,
    pub named_media: HashMap<String, usize>,
    pub media: Vec<MediumDescription>,
    objects: HashMap<String, ObjectDefinition>,
    /// The object being defined, with the position of its `ObjectBegin`.
    pub current_object: Option<(String, ObjectDefinition, Position)>,
    pub shapes: Vec<ShapeDescription>,
    pub lights: Vec<crate::scene::description::LightDescription>,
    pub camera: CameraSettings,
    /// Whether `WorldBegin` has been seen.
    pub in_world: bool,
    include_depth: usize,
    included_files: usize,
}

impl Loader {
    /// A loader for the scene whose main file is `main_file`.
    pub fn new(main_file: &Path) -> Self {
        Self {
            search_directory: main_file
                .parent()
                .map(Path::to_path_buf)
                .unwrap_or_default(),
            warnings: Vec::new(),
            state: GraphicsState::default(),
            stack: Vec::new(),
            named_coordinate_systems: HashMap::new(),
            named_materials: HashMap::new(),
            float_textures: HashMap::new(),
            spectrum_textures: HashMap::new(),
            named_media: HashMap::new(),
            media: Vec::new(),
            objects: HashMap::new(),
            current_object: None,
            shapes: Vec::new(),
            lights: Vec::new(),
            camera: CameraSettings::default(),
            in_world: false,
            include_depth: 0,
            included_files: 0,
        }
    }

    /// Records a warning at `position`.
    pub fn warn(&mut self, position: &Position, message: impl std::fmt::Display) {
        self.warnings.push(position.warning(message));
    }

    /// Warns about every parameter of `parameters` nobody read.
    pub fn warn_unused(&mut self, parameters: &ParameterList, directive: &str) {
        let unused: Vec<String> = parameters
            .unused()
            .map(|p| {
                p.position.warning(format!(
                    "{directive}: parameter {} is not used (unknown to this loader or ignored)",
                    p.describe()
                ))
            })
            .collect();
        self.warnings.extend(unused);
    }

    /// Resolves a file name from the scene: absolute names as they are,
    /// relative ones against the main file's directory, falling back to the
    /// directory of the file that names it when only that one exists.
    pub fn resolve(&self, name: &str, position: &Position) -> PathBuf {
        let path = Path::new(name);
        if path.is_absolute() {
            return path.to_path_buf();
        }
        let primary = self.search_directory.join(path);
        if !primary.exists()
            && let Some(local) = position.file.parent().map(|d| d.join(path))
            && local.exists()
        {
            return local;
        }
        primary
    }

    /// Reads and runs a whole file (the main file or an included one).
    pub fn run_file(&mut self, path: &Path, from: Option<&Position>) -> Result<(), SceneFileError> {
        let bytes = std::fs::read(path).map_err(|source| match from {
            None => SceneFileError::Io {
                path: path.to_path_buf(),
                source,
            },
            Some(position) => position.error(format!(
                "cannot read the included file {}: {source}",
                path.display()
            )),
        })?;
        let mut cursor = Cursor::new(&bytes, path)?;
        while let Some(token) = cursor.next() {
            let position = cursor.at(token.line);
            if token.kind != TokenKind::Word {
                return Err(position.error(format!(
                    "expected a directive (such as Shape or WorldBegin), found {}",
                    token.describe()
                )));
            }
            self.directive(&token.text, &position, &mut cursor)?;
        }
        Ok(())
    }

    fn transform_by(&mut self, matrix: DMat4) {
        self.state.ctm *= matrix;
    }

    fn directive(
        &mut self,
        name: &str,
        position: &Position,
        cursor: &mut Cursor,
    ) -> Result<(), SceneFileError> {
        match name {
            "Identity" => self.state.ctm = DMat4::IDENTITY,
            "Translate" => {
                let v = cursor.expect_numbers(name, 3)?;
                self.transform_by(DMat4::from_translation(DVec3::new(v[0], v[1], v[2])));
            }
            "Scale" => {
                let v = cursor.expect_numbers(name, 3)?;
                self.transform_by(DMat4::from_scale(DVec3::new(v[0], v[1], v[2])));
            }
            "Rotate" => {
                let v = cursor.expect_numbers(name, 4)?;
                let axis = DVec3::new(v[1], v[2], v[3])
                    .try_normalize()
                    .ok_or_else(|| position.error("Rotate: the rotation axis must not be zero"))?;
                self.transform_by(DMat4::from_axis_angle(axis, v[0].to_radians()));
            }
            "LookAt" => {
                let v = cursor.expect_numbers(name, 9)?;
                let matrix = look_at(
                    DVec3::new(v[0], v[1], v[2]),
                    DVec3::new(v[3], v[4], v[5]),
                    DVec3::new(v[6], v[7], v[8]),
                )
                .ok_or_else(|| {
                    position.error(
                        "LookAt: expected distinct eye and target points and an up vector not parallel to the view direction",
                    )
                })?;
                self.transform_by(matrix);
            }
            "ConcatTransform" | "Transform" => {
                let v = cursor.expect_numbers(name, 16)?;
                // pbrt lists the matrix column by column (the transpose of
                // its row-major reading); glam's arrays are column-major too.
                let array: [f64; 16] = v.try_into().expect("16 numbers");
                let matrix = DMat4::from_cols_array(&array);
                if name == "Transform" {
                    self.state.ctm = matrix;
                } else {
                    self.transform_by(matrix);
                }
            }
            "CoordinateSystem" => {
                let system = cursor.expect_string(name, "a coordinate system name")?;
                self.named_coordinate_systems.insert(system, self.state.ctm);
            }
            "CoordSysTransform" => {
                let system = cursor.expect_string(name, "a coordinate system name")?;
                match self.named_coordinate_systems.get(&system) {
                    Some(&matrix) => self.state.ctm = matrix,
                    None => self.warn(
                        position,
                        format!("CoordSysTransform: no coordinate system named \"{system}\"; the transform is unchanged"),
                    ),
                }
            }
            "ReverseOrientation" => {
                self.state.reverse_orientation = !self.state.reverse_orientation
            }
            "ActiveTransform" => {
                let which = match cursor.next() {
                    Some(t) if t.kind == TokenKind::Word => t.text,
                    _ => {
                        return Err(
                            position.error("ActiveTransform: expected StartTime, EndTime or All")
                        );
                    }
                };
                if which != "All" && which != "StartTime" && which != "EndTime" {
                    return Err(position.error(format!(
                        "ActiveTransform: expected StartTime, EndTime or All, found '{which}'"
                    )));
                }
                if which != "All" {
                    self.warn(
                        position,
                        "ActiveTransform: animated transforms are not supported; both times get the same transforms",
                    );
                }
            }
            "TransformTimes" => {
                cursor.expect_numbers(name, 2)?;
                self.warn(
                    position,
                    "TransformTimes: animated transforms are not supported",
                );
            }
            "AttributeBegin" | "TransformBegin" => {
                let scope = if name == "AttributeBegin" {
                    Scope::Attribute
                } else {
                    Scope::Transform
                };
                self.stack
                    .push((self.state.clone(), position.clone(), scope));
            }
            "AttributeEnd" | "TransformEnd" => {
                let wanted = if name == "AttributeEnd" {
                    Scope::Attribute
                } else {
                    Scope::Transform
                };
                match self.stack.pop() {
                    Some((saved, _, scope)) if scope == wanted => {
                        if scope == Scope::Transform {
                            self.state.ctm = saved.ctm;
                        } else {
                            self.state = saved;
                        }
                    }
                    Some((saved, begin, scope)) => {
                        self.stack.push((saved, begin.clone(), scope));
                        return Err(position.error(format!(
                            "{name} does not match the {} at line {}",
                            match scope {
                                Scope::Attribute => "AttributeBegin",
                                Scope::Transform => "TransformBegin",
                                Scope::Object => "ObjectBegin",
                            },
                            begin.line
                        )));
                    }
                    None => {
                        return Err(position.error(format!(
                            "{name} without a matching {}",
                            name.replace("End", "Begin")
                        )));
                    }
                }
            }
            "WorldBegin" => {
                if self.in_world {
                    return Err(position.error("WorldBegin appears twice"));
                }
                self.in_world = true;
                self.state.ctm = DMat4::IDENTITY;
                self.named_coordinate_systems
                    .insert("world".into(), DMat4::IDENTITY);
            }
            "WorldEnd" => {
                // pbrt-v3's end of the scene; pbrt-v4 ends at the end of file.
            }
            "Include" | "Import" => {
                let file = cursor.expect_string(name, "a file name")?;
                let path = self.resolve(&file, position);
                self.included_files += 1;
                if self.included_files > MAXIMUM_INCLUDED_FILES {
                    return Err(position.error(format!(
                        "{name} \"{file}\": more than {MAXIMUM_INCLUDED_FILES} included files"
                    )));
                }
                if self.include_depth >= MAXIMUM_INCLUDE_DEPTH {
                    return Err(position.error(format!(
                        "{name} \"{file}\": more than {MAXIMUM_INCLUDE_DEPTH} nested includes (does a file include itself?)"
                    )));
                }
                // Import's graphics-state changes stay in the imported file
                // (pbrt-v4); Include is textual.
                let saved = (name == "Import").then(|| (self.state.clone(), self.stack.len()));
                self.include_depth += 1;
                let result = self.run_file(&path, Some(position));
                self.include_depth -= 1;
                result?;
                if let Some((state, depth)) = saved {
                    self.state = state;
                    self.stack.truncate(depth);
                }
            }
            "ObjectBegin" => {
                let object = cursor.expect_string(name, "an object name")?;
                if let Some((_, _, begin)) = &self.current_object {
                    return Err(position.error(format!(
                        "ObjectBegin \"{object}\" inside the object begun at line {}",
                        begin.line
                    )));
                }
                self.stack
                    .push((self.state.clone(), position.clone(), Scope::Object));
                self.current_object = Some((
                    object,
                    ObjectDefinition { shapes: Vec::new() },
                    position.clone(),
                ));
            }
            "ObjectEnd" => {
                let Some((object, definition, _)) = self.current_object.take() else {
                    return Err(position.error("ObjectEnd without a matching ObjectBegin"));
                };
                match self.stack.pop() {
                    Some((saved, _, Scope::Object)) => self.state = saved,
                    Some(other) => {
                        self.stack.push(other);
                        return Err(position.error(
                            "ObjectEnd: an AttributeBegin or TransformBegin inside the object is still open",
                        ));
                    }
                    None => return Err(position.error("ObjectEnd without a matching ObjectBegin")),
                }
                if self.objects.insert(object.clone(), definition).is_some() {
                    self.warn(position, format!("object \"{object}\" redefined"));
                }
            }
            "ObjectInstance" => {
                let object = cursor.expect_string(name, "an object name")?;
                if self.current_object.is_some() {
                    return Err(position.error(
                        "ObjectInstance inside an object definition (pbrt does not nest instances)",
                    ));
                }
                let Some(definition) = self.objects.get(&object) else {
                    return Err(position.error(format!(
                        "ObjectInstance: no object named \"{object}\" (expected an ObjectBegin \"{object}\" before)"
                    )));
                };
                let transform = self.state.ctm;
                let shapes = definition.shapes.clone();
                for shape in shapes {
                    let instanced =
                        super::shapes::transform_shape(shape, transform).map_err(|message| {
                            position.error(format!("ObjectInstance \"{object}\": {message}"))
                        })?;
                    self.shapes.push(instanced);
                }
            }
            "Option" => {
                let parameters = cursor.parameter_list()?;
                for p in &parameters.parameters {
                    self.warnings.push(p.position.warning(format!(
                        "Option {}: rendering options are not used by this loader",
                        p.describe()
                    )));
                }
            }
            "ColorSpace" => {
                let space = cursor.expect_string(name, "a colour space name")?;
                if space != "srgb" {
                    self.warn(
                        position,
                        format!("ColorSpace \"{space}\": only srgb is supported; RGB values are read as linear sRGB"),
                    );
                }
            }
            "Attribute" => {
                let target =
                    cursor.expect_string(name, "shape, light, material, medium or texture")?;
                let parameters = cursor.parameter_list()?;
                if !parameters.parameters.is_empty() {
                    self.warn(
                        position,
                        format!("Attribute \"{target}\": default parameters for later directives are not supported and are ignored"),
                    );
                }
            }
            "Camera" => {
                let kind = cursor.expect_string(name, "a camera type")?;
                let parameters = cursor.parameter_list()?;
                if self.in_world {
                    return Err(position
                        .error("Camera inside the world block (expected before WorldBegin)"));
                }
                let camera_from_world = self.state.ctm;
                let world_from_camera = camera_from_world.inverse();
                if !world_from_camera.is_finite() {
                    return Err(position.error(
                        "Camera: the current transform is singular (expected an invertible world-to-camera transform)",
                    ));
                }
                self.named_coordinate_systems
                    .insert("camera".into(), world_from_camera);
                self.camera_directive(&kind, &parameters, world_from_camera, position)?;
                self.warn_unused(&parameters, &format!("Camera \"{kind}\""));
            }
            "Film" | "Sampler" | "PixelFilter" | "Integrator" | "Accelerator" => {
                let kind = cursor.expect_string(name, "a type name")?;
                let parameters = cursor.parameter_list()?;
                self.options_directive(name, &kind, &parameters, position)?;
                self.warn_unused(&parameters, &format!("{name} \"{kind}\""));
            }
            "MakeNamedMedium" => {
                let medium = cursor.expect_string(name, "a medium name")?;
                let parameters = cursor.parameter_list()?;
                self.make_named_medium(&medium, &parameters, position)?;
                self.warn_unused(&parameters, &format!("MakeNamedMedium \"{medium}\""));
            }
            "MediumInterface" => {
                let inside = cursor.expect_string(name, "the inside medium's name")?;
                let outside = match cursor.peek() {
                    Some(t) if t.kind == TokenKind::String => cursor.next().expect("peeked").text,
                    _ => inside.clone(),
                };
                self.state.inside_medium = (!inside.is_empty()).then_some(inside);
                self.state.outside_medium = (!outside.is_empty()).then_some(outside);
            }
            "Texture" => {
                let texture = cursor.expect_string(name, "a texture name")?;
                let value_type =
                    cursor.expect_string(name, "the texture's type, \"spectrum\" or \"float\"")?;
                let class = cursor.expect_string(name, "a texture class such as \"imagemap\"")?;
                let parameters = cursor.parameter_list()?;
                self.texture_directive(&texture, &value_type, &class, &parameters, position)?;
                self.warn_unused(&parameters, &format!("Texture \"{texture}\" \"{class}\""));
            }
            "Material" => {
                let kind = cursor.expect_string(name, "a material type")?;
                let parameters = cursor.parameter_list()?;
                let material = self.material(&kind, &parameters, position)?;
                self.state.material = CurrentMaterial::Anonymous(Box::new(material));
                self.warn_unused(&parameters, &format!("Material \"{kind}\""));
            }
            "MakeNamedMaterial" => {
                let material_name = cursor.expect_string(name, "a material name")?;
                let parameters = cursor.parameter_list()?;
                let kind = parameters.string("type")?.ok_or_else(|| {
                    position.error(format!(
                        "MakeNamedMaterial \"{material_name}\": expected a \"string type\" parameter"
                    ))
                })?;
                let material = self.material(&kind, &parameters, position)?;
                if self
                    .named_materials
                    .insert(material_name.clone(), material)
                    .is_some()
                {
                    self.warn(
                        position,
                        format!("named material \"{material_name}\" redefined"),
                    );
                }
                self.warn_unused(
                    &parameters,
                    &format!("MakeNamedMaterial \"{material_name}\""),
                );
            }
            "NamedMaterial" => {
                let material_name = cursor.expect_string(name, "a material name")?;
                self.state.material = CurrentMaterial::Named {
                    name: material_name,
                    position: position.clone(),
                };
            }
            "LightSource" => {
                let kind = cursor.expect_string(name, "a light type")?;
                let parameters = cursor.parameter_list()?;
                self.light_source(&kind, &parameters, position)?;
                self.warn_unused(&parameters, &format!("LightSource \"{kind}\""));
            }
            "AreaLightSource" => {
                let kind = cursor.expect_string(name, "an area light type")?;
                let parameters = cursor.parameter_list()?;
                self.area_light_source(&kind, &parameters, position)?;
                self.warn_unused(&parameters, &format!("AreaLightSource \"{kind}\""));
            }
            "Shape" => {
                let kind = cursor.expect_string(name, "a shape type")?;
                let parameters = cursor.parameter_list()?;
                self.shape(&kind, &parameters, position)?;
                self.warn_unused(&parameters, &format!("Shape \"{kind}\""));
            }
            other => {
                cursor.skip_arguments();
                self.warn(position, format!("unknown directive '{other}' skipped"));
            }
        }
        Ok(())
    }

    /// Checks the file ended with every block closed.
    pub fn finish_blocks(&mut self) -> Result<(), SceneFileError> {
        if let Some((_, _, position)) = &self.current_object {
            return Err(position.error("ObjectBegin without a matching ObjectEnd"));
        }
        if let Some((_, position, scope)) = self.stack.last() {
            let position = position.clone();
            let begin = match scope {
                Scope::Attribute => "AttributeBegin",
                Scope::Transform => "TransformBegin",
                Scope::Object => "ObjectBegin",
            };
            self.warn(
                &position,
                format!("{begin} without a matching end at the end of the scene"),
            );
        }
        Ok(())
    }

    /// The material a shape gets now: the anonymous one or the named one.
    pub fn current_material(&self) -> Result<MaterialDescription, SceneFileError> {
        match &self.state.material {
            CurrentMaterial::Anonymous(material) => Ok(material.as_ref().clone()),
            CurrentMaterial::Named { name, position } => {
                self.named_materials.get(name).cloned().ok_or_else(|| {
                    position.error(format!(
                        "NamedMaterial: no material named \"{name}\" (expected a MakeNamedMaterial \"{name}\" before the shapes that use it)"
                    ))
                })
            }
        }
    }
}
