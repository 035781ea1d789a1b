//! Helpers for the crate's unit tests.

// The definition is shared with the integration tests (see the file).
#[path = "../tests/support/scratch_directory.rs"]
mod scratch_directory;
pub(crate) use scratch_directory::ScratchDirectory;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scratch_directory_is_removed_when_dropped() {
        let directory = ScratchDirectory::new("scratch-test");
        std::fs::write(directory.join("file"), b"contents").unwrap();
        let path = directory.to_path_buf();
        assert!(path.join("file").exists());
        drop(directory);
        assert!(!path.exists());
    }
}
