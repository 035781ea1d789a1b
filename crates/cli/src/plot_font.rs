//! The font of every plot. Plotters' `ab_glyph` text backend knows no
//! system fonts: it lays out and (for PNG plots) draws text only with fonts
//! registered by name, so the binary carries one and registers it as
//! `sans-serif`, the family the plots ask for, before drawing anything.
//!
//! `assets/DejaVuSans.ttf` is DejaVu Sans 2.37, copied from Debian's
//! `fonts-dejavu-core` package (`/usr/share/fonts/truetype/dejavu/`;
//! upstream <https://dejavu-fonts.github.io/>); its licence is
//! `assets/DejaVuSans-LICENSE.txt`.

use crate::error::CliError;
use plotters::style::{FontStyle, register_font};
use std::sync::OnceLock;

/// The font family the plots name.
pub const PLOT_FONT_FAMILY: &str = "sans-serif";

/// DejaVu Sans, built into the binary.
static DEJAVU_SANS: &[u8] = include_bytes!("../assets/DejaVuSans.ttf");

/// Registers the plots' font once per process; later calls return the
/// first call's outcome.
pub fn register_plot_font() -> Result<(), CliError> {
    static REGISTERED: OnceLock<bool> = OnceLock::new();
    let registered = *REGISTERED
        .get_or_init(|| register_font(PLOT_FONT_FAMILY, FontStyle::Normal, DEJAVU_SANS).is_ok());
    if registered {
        Ok(())
    } else {
        Err(CliError::Failure(
            "the built-in plot font (DejaVu Sans) could not be read".into(),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_in_font_registers() {
        assert!(register_plot_font().is_ok());
        assert!(register_plot_font().is_ok());
    }
}
