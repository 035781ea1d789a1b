//! Errors raised when shapes or transforms are built from invalid input.

use thiserror::Error;

/// What went wrong while building geometry from user input.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GeometryError {
    /// A matrix that must be inverted is singular (or not finite).
    #[error("transform matrix is singular or not finite: {0}")]
    SingularTransform(String),
    /// A matrix that must be affine has a non-trivial projective row.
    #[error("transform matrix is not affine (last row must be 0 0 0 1)")]
    NotAffine,
    /// A sphere transform was more than a translation and a uniform scale.
    #[error("sphere transform must be a translation and a uniform positive scale only")]
    SphereTransformNotSimilarity,
    /// A radius (or other length) was not a positive finite number.
    #[error("{what} must be positive and finite, got {value}")]
    NonPositiveLength {
        /// Which quantity.
        what: &'static str,
        /// The offending value.
        value: f32,
    },
    /// Mesh index buffer problems.
    #[error("triangle mesh: {0}")]
    InvalidMesh(String),
    /// A coordinate or parameter was NaN or infinite.
    #[error("non-finite value in {0}")]
    NonFinite(&'static str),
}
