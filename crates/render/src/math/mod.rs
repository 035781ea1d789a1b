//! Special functions that more than one layer needs: the error function and
//! its inverse (the Gaussian reconstruction filter samples a truncated
//! Gaussian with them; Beckmann microfacets use them for their slope
//! distribution and shadowing). A leaf module: it imports nothing of the
//! renderer.

mod error_function;

pub use error_function::{erf, inverse_erf};
