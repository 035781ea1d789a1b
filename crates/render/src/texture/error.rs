//! Why a texture cannot be made: its image file cannot be read or is empty.

/// An image texture that cannot be loaded: `what` names the parameter the
/// texture is for, `message` says what is wrong with the file (the path
/// included). Displayed as `what: message`, the text the scene builder's
/// parameter error shows.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{what}: {message}")]
pub struct TextureError {
    /// The parameter, e.g. `diffuse reflectance`.
    pub what: String,
    /// What went wrong.
    pub message: String,
}
