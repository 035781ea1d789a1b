//! The repository stands alone: no source file, test, benchmark or script
//! reaches for data outside the clone (the team's folder that once lay
//! beside the checkout). External scenes and references are
//! vendored under `scenes/external/` with their licences.

use std::fs;
use std::path::{Path, PathBuf};

/// The repository's root (this crate is `crates/cli`).
fn repository_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// Every file under `directory` with one of `extensions`, skipping build
/// output.
fn source_files(directory: &Path, extensions: &[&str], files: &mut Vec<PathBuf>) {
    let Ok(entries) = fs::read_dir(directory) else {
        return;
    };
    for entry in entries {
        let path = entry.expect("a directory entry").path();
        let name = path.file_name().unwrap_or_default().to_string_lossy();
        if path.is_dir() {
            if name != "target" && name != "__pycache__" && !name.starts_with('.') {
                source_files(&path, extensions, files);
            }
        } else if path
            .extension()
            .is_some_and(|extension| extensions.iter().any(|e| extension == *e))
        {
            files.push(path);
        }
    }
}

#[test]
fn no_source_reads_data_outside_the_repository() {
    let root = repository_root();
    let mut files = Vec::new();
    for directory in ["crates", "scripts", "deploy", "fuzz"] {
        source_files(
            &root.join(directory),
            &["rs", "py", "sh", "toml", "sbatch", "yaml", "yml"],
            &mut files,
        );
    }
    files.push(root.join(".ci/run"));
    assert!(
        files.len() > 100,
        "expected the sources, found {}",
        files.len()
    );
    // Built from parts, so that this file does not name them itself.
    let shared = ["shared", "/"].concat();
    let outside_paths = [["../", &shared].concat(), ["/work/", &shared].concat()];
    let mut offenders = Vec::new();
    for path in files {
        let Ok(text) = fs::read_to_string(&path) else {
            continue;
        };
        for (number, line) in text.lines().enumerate() {
            if outside_paths
                .iter()
                .any(|outside| line.contains(outside.as_str()))
            {
                offenders.push(format!(
                    "{}:{}: {}",
                    path.display(),
                    number + 1,
                    line.trim()
                ));
            }
        }
    }
    assert!(
        offenders.is_empty(),
        "files that reach outside the repository (vendor the data under scenes/external):\n{}",
        offenders.join("\n")
    );
}
