//! Scenes: the renderer-independent [`description`] that built-in scenes and
//! loaders produce, and the [`builtin`] scenes.

pub mod builtin;
pub mod description;
