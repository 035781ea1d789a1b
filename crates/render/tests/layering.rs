//! Layers point one way: the renderer's lower layers (geometry, materials,
//! lights, textures, film, spectra, camera, media) do not name the scene
//! description or the integrators; the scene builder and the integrators
//! import them, never the other way round.
//!
//! The check reads the source of every `.rs` file under those folders and
//! looks at its production code only, found by a simple heuristic that
//! relies on rustfmt's layout:
//!
//! - a line whose first non-blank characters are `//` (comments, doc
//!   comments) is skipped, and so is the rest of a line from `//` on;
//! - a `#[cfg(test)]` at the start of a line followed by a module with a
//!   body (`mod tests {`, `pub(super) mod test_support {`) skips everything
//!   up to the module's closing `}`, the next line that is exactly `}`
//!   (rustfmt puts only a module-level closing brace at the start of a
//!   line); followed by `mod tests;` it excludes the file of that module;
//! - everything else counts, `#[cfg(test)]` helpers inside impls included.
//!
//! Production code fails the check if it names `crate::scene` or
//! `crate::integrators`, reaches them through `super::` (`super::scene`,
//! `super::super::integrators`, ...), or lists them in a grouped import
//! (`use crate::{geometry::Ray, scene::Scene}`).

use std::collections::HashSet;
use std::fs;
use std::path::{Path, PathBuf};

/// The folders of `crates/render/src` below the scene and the integrators.
const LOWER_LAYERS: [&str; 8] = [
    "geometry", "material", "light", "texture", "film", "spectrum", "camera", "medium",
];

/// The modules the lower layers must not name.
const UPPER_MODULES: [&str; 2] = ["scene", "integrators"];

/// Every `.rs` file under `directory`, sorted.
fn rust_files(directory: &Path) -> Vec<PathBuf> {
    let mut files = Vec::new();
    let mut pending = vec![directory.to_path_buf()];
    while let Some(directory) = pending.pop() {
        for entry in fs::read_dir(&directory).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|extension| extension == "rs") {
                files.push(path);
            }
        }
    }
    files.sort();
    files
}

/// The line without its `//` comment, if any.
fn without_comment(line: &str) -> &str {
    line.find("//").map_or(line, |start| &line[..start])
}

/// The name of the module a line declares (`mod tests {`, `pub(super) mod
/// test_support {`, `mod tests;`) and whether it has a body here.
fn declared_module(line: &str) -> Option<(&str, bool)> {
    let after_mod = line.split_once("mod ")?.1;
    let (name, body) = if let Some(name) = after_mod.strip_suffix(" {") {
        (name, true)
    } else {
        (after_mod.strip_suffix(';')?, false)
    };
    name.chars()
        .all(|c| c.is_alphanumeric() || c == '_')
        .then_some((name, body))
}

/// The production lines of one file (1-based numbers), and the files of
/// test modules it declares without a body (to be skipped).
fn production_lines(path: &Path, source: &str) -> (Vec<(usize, String)>, Vec<PathBuf>) {
    let lines: Vec<&str> = source.lines().collect();
    let mut production = Vec::new();
    let mut test_files = Vec::new();
    let mut index = 0;
    while index < lines.len() {
        let line = lines[index];
        let test_module = lines
            .get(index + 1)
            .filter(|_| line == "#[cfg(test)]")
            .and_then(|next| declared_module(next));
        if let Some((name, has_body)) = test_module {
            if has_body {
                let end = lines[index + 2..]
                    .iter()
                    .position(|line| *line == "}")
                    .unwrap_or_else(|| {
                        panic!(
                            "{}:{}: the test module `{name}` has no closing `}}` at the \
                             start of a line; the heuristic of this test needs one",
                            path.display(),
                            index + 2
                        )
                    });
                index += 2 + end + 1;
            } else {
                let directory = path.parent().unwrap();
                test_files.push(directory.join(format!("{name}.rs")));
                test_files.push(directory.join(name).join("mod.rs"));
                index += 2;
            }
            continue;
        }
        if !line.trim_start().starts_with("//") {
            production.push((index + 1, without_comment(line).to_string()));
        }
        index += 1;
    }
    (production, test_files)
}

/// Whether `rest` starts with `word` as a whole identifier.
fn starts_with_word(rest: &str, word: &str) -> bool {
    rest.strip_prefix(word)
        .is_some_and(|after| !after.starts_with(|c: char| c.is_alphanumeric() || c == '_'))
}

/// Where `code` (with its whitespace removed) names an upper module by
/// path: after `crate::` or `super::` (so also `super::super::scene`), or
/// as an item of a `crate::{...}` / `super::{...}` group. Byte offsets of
/// the module's name, with the name.
fn upper_module_mentions(code: &str) -> Vec<(usize, &'static str)> {
    let mut mentions = Vec::new();
    for prefix in ["crate::", "super::"] {
        for (start, _) in code.match_indices(prefix) {
            let at = start + prefix.len();
            let rest = &code[at..];
            if let Some(module) = UPPER_MODULES
                .into_iter()
                .find(|module| starts_with_word(rest, module))
            {
                mentions.push((at, module));
            } else if rest.starts_with('{') {
                // The group's items at its top level.
                let mut depth = 0;
                let mut item_start = false;
                for (offset, c) in rest.char_indices() {
                    if depth == 1
                        && item_start
                        && let Some(module) = UPPER_MODULES
                            .into_iter()
                            .find(|module| starts_with_word(&rest[offset..], module))
                    {
                        mentions.push((at + offset, module));
                    }
                    match c {
                        '{' => depth += 1,
                        '}' => depth -= 1,
                        _ => {}
                    }
                    if depth == 0 {
                        break;
                    }
                    item_start = c == ',' || c == '{';
                }
            }
        }
    }
    mentions.sort();
    mentions
}

/// The first upper module `text` names (see [`upper_module_mentions`]).
fn names_upper_module(text: &str) -> Option<&'static str> {
    let compact: String = text.chars().filter(|c| !c.is_whitespace()).collect();
    upper_module_mentions(&compact)
        .first()
        .map(|(_, module)| *module)
}

/// The violations in one file's production lines, as `file:line: text`.
/// The lines are read as one text with whitespace removed, so that paths
/// and grouped imports spanning lines (`use crate::{\n    scene::Scene,\n};`)
/// are seen; each violation is reported at the line of the module's name.
fn file_violations(shown: &str, lines: &[(usize, String)]) -> Vec<String> {
    let mut code = String::new();
    let mut line_of_byte = Vec::new();
    for (number, text) in lines {
        for c in text.chars().filter(|c| !c.is_whitespace()) {
            code.push(c);
            line_of_byte.extend(std::iter::repeat_n(*number, c.len_utf8()));
        }
    }
    upper_module_mentions(&code)
        .into_iter()
        .map(|(offset, module)| {
            let number = line_of_byte[offset];
            let text = &lines.iter().find(|(n, _)| *n == number).unwrap().1;
            format!("{shown}:{number}: names `{module}`: {}", text.trim())
        })
        .collect()
}

/// The violations in the production code of the lower layers.
fn violations(source_root: &Path) -> Vec<String> {
    let mut found = Vec::new();
    let mut files_read = 0;
    for layer in LOWER_LAYERS {
        let files = rust_files(&source_root.join(layer));
        assert!(!files.is_empty(), "no source files under {layer}");
        let mut test_files = HashSet::new();
        let mut per_file = Vec::new();
        for path in files {
            let source = fs::read_to_string(&path).unwrap();
            let (lines, tests) = production_lines(&path, &source);
            test_files.extend(tests);
            per_file.push((path, lines));
        }
        for (path, lines) in per_file {
            if test_files.contains(&path) {
                continue;
            }
            files_read += 1;
            let shown = path
                .strip_prefix(source_root)
                .unwrap()
                .display()
                .to_string();
            found.extend(file_violations(&shown, &lines));
        }
    }
    assert!(files_read > 50, "only {files_read} files read");
    found
}

#[test]
fn lower_layers_do_not_import_the_scene_or_the_integrators() {
    let source_root = Path::new(env!("CARGO_MANIFEST_DIR")).join("src");
    let found = violations(&source_root);
    assert!(
        found.is_empty(),
        "lower layers name the scene or the integrators (move what they need \
         down, and let the scene description re-export it):\n{}",
        found.join("\n")
    );
}

/// The detector itself: what it must find and what it must let pass.
#[test]
fn the_detector_finds_upward_paths_and_ignores_comments_and_tests() {
    for upward in [
        "use crate::scene::SceneError;",
        "use crate::integrators::MisHeuristic;",
        "    crate::integrators::MisHeuristic::Power.weight(a, b)",
        "use super::super::scene::description::SpotFalloff;",
        "use super::scene;",
        "use crate::{geometry::Ray, scene::Scene};",
        "use crate::{integrators, spectrum};",
        "use crate :: scene :: Scene;",
    ] {
        assert!(names_upper_module(upward).is_some(), "missed: {upward}");
    }
    for fine in [
        "use crate::geometry::Ray;",
        "let scene_radius = 1.0;",
        "use crate::scenery::Tree;",
        "use crate::{geometry::scene_bounds, spectrum};",
        "use super::sampling::sample_uniform_sphere;",
        "fn build(scene: &Scene) {}",
    ] {
        assert!(names_upper_module(fine).is_none(), "false alarm: {fine}");
    }
    let source = "use crate::geometry::Ray;\n\
                  /// See [`crate::scene::Scene`].\n\
                  let x = 1; // crate::scene\n\
                  #[cfg(test)]\n\
                  mod tests {\n\
                  \x20   use crate::scene::Scene;\n\
                  }\n\
                  use crate::integrators::Integrator;\n\
                  #[cfg(test)]\n\
                  mod more_tests;\n";
    let (lines, test_files) = production_lines(Path::new("src/light/example.rs"), source);
    let numbers: Vec<usize> = lines.iter().map(|(number, _)| *number).collect();
    assert_eq!(numbers, [1, 3, 8]);
    assert!(names_upper_module(&lines[1].1).is_none());
    assert!(names_upper_module(&lines[2].1).is_some());
    assert_eq!(test_files[0], Path::new("src/light/more_tests.rs"));
    let grouped = [
        "use crate::{",
        "    geometry::Ray,",
        "    scene::Scene,",
        "};",
    ];
    let lines: Vec<(usize, String)> = (1..).zip(grouped.map(String::from)).collect();
    let found = file_violations("light/example.rs", &lines);
    assert_eq!(found.len(), 1, "{found:?}");
    assert!(
        found[0].starts_with("light/example.rs:3: names `scene`"),
        "{found:?}"
    );
}
