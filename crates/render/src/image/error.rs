//! The error type of image reading and writing: every variant that concerns
//! a file names it.

use std::path::PathBuf;

/// What went wrong reading or writing an image, and with which file.
#[derive(Debug, thiserror::Error)]
pub enum ImageError {
    /// The file could not be opened or read (missing, unreadable, ...).
    #[error("cannot read image file '{}': {source}", path.display())]
    Read {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The file could not be created or written.
    #[error("cannot write image file '{}': {source}", path.display())]
    Write {
        /// The file.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The file is not a valid file of the expected format, or uses a
    /// feature of it that is not supported.
    #[error("'{}' is not a valid {format} file: {reason}", path.display())]
    InvalidFormat {
        /// The file.
        path: PathBuf,
        /// The expected format ("OpenEXR", "PFM", "PNG").
        format: &'static str,
        /// What is wrong.
        reason: String,
    },
    /// The file ends before all of its pixel data.
    #[error("'{}' is a truncated {format} file: {reason}", path.display())]
    Truncated {
        /// The file.
        path: PathBuf,
        /// The format ("OpenEXR", "PFM", "PNG").
        format: &'static str,
        /// How much was expected and found.
        reason: String,
    },
    /// The extension names no supported format.
    #[error(
        "'{}': unsupported image file extension (supported: .exr, .pfm, .png)",
        path.display()
    )]
    UnsupportedExtension {
        /// The file.
        path: PathBuf,
    },
    /// The image or its metadata cannot be stored in the file's format.
    #[error("cannot write '{}': {reason}", path.display())]
    Unwritable {
        /// The file.
        path: PathBuf,
        /// Why (empty image, metadata not representable, ...).
        reason: String,
    },
    /// The pixel count does not match the dimensions.
    #[error("an image of {width}x{height} pixels cannot be made from {pixel_count} pixels")]
    DimensionMismatch {
        /// Requested width.
        width: usize,
        /// Requested height.
        height: usize,
        /// Number of pixels given.
        pixel_count: usize,
    },
    /// Two images that must have the same size do not.
    #[error("{what} is {}x{}, expected {}x{}", found.0, found.1, expected.0, expected.1)]
    SizeMismatch {
        /// Which image is off.
        what: String,
        /// The size of the image it is compared with.
        expected: (usize, usize),
        /// Its size.
        found: (usize, usize),
    },
}
