//! Why a light cannot be made from its data: an environment map whose image
//! cannot be read or does not fit its projection.

/// A light that cannot be loaded: `what` names the light, `message` says
/// what is wrong with its data (the file's path included). Displayed as
/// `what: message`, the text the scene builder's parameter error shows.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{what}: {message}")]
pub struct LightError {
    /// The light, e.g. `environment map`.
    pub what: String,
    /// What went wrong.
    pub message: String,
}
