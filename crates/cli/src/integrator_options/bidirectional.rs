//! The options of the bidirectional integrators, `--integrator bdpt` and
//! `--integrator vcm` (VCM's defaults are SmallVCM's; see
//! `render::integrators::vcm`), and their settings from them.

use super::headings;
use crate::error::{CliError, usage};
use crate::named_values::NamedValues;
use clap::Args;
use render::integrators::bdpt::BdptSettings;
use render::integrators::vcm::{VcmMode, VcmSettings};
use std::path::PathBuf;

/// Options of `--integrator bdpt`.
#[derive(Args, Debug, Default)]
#[command(next_help_heading = headings::BDPT)]
pub struct BdptArgs {
    /// Leave out the strategies that connect light subpath vertices to the
    /// camera (light tracing, t = 1), as Kollig & Keller do for OFFICE.
    #[arg(long)]
    pub bdpt_skip_eye_connections: bool,
    /// Write one weighted image per strategy to DIR/s{s}_t{t}.exr (s light
    /// and t camera vertices; they sum to the image), as pbrt-v4's
    /// `visualizestrategies`.
    #[arg(long, value_name = "DIR")]
    pub strategy_images: Option<PathBuf>,
}

impl BdptArgs {
    /// BDPT's settings.
    pub fn settings(&self) -> BdptSettings {
        BdptSettings {
            camera_connections: !self.bdpt_skip_eye_connections,
            strategy_images: self.strategy_images.is_some(),
        }
    }
}

/// Options of `--integrator vcm`.
#[derive(Args, Debug, Default)]
#[command(next_help_heading = headings::VCM)]
pub struct VcmArgs {
    /// The techniques, `vcm` (connections and merges; default), `bpt`
    /// (connections only), `bpm` (merges with MIS) or `ppm` (merges at the
    /// first non-specular vertex, no MIS).
    #[arg(long, value_name = "vcm|bpt|bpm|ppm", value_parser = NamedValues::new(VcmMode::ALL))]
    pub vcm_mode: Option<VcmMode>,
    /// The first iteration's merging radius as a fraction of the scene's
    /// bounding-sphere radius (default 0.003).
    #[arg(long, value_name = "FRACTION")]
    pub vcm_radius: Option<f32>,
    /// The radius reduction's alpha, r_i = r_1 i^((alpha-1)/2), in (0, 1]
    /// (default 0.75).
    #[arg(long, value_name = "ALPHA")]
    pub vcm_alpha: Option<f32>,
}

impl VcmArgs {
    /// VCM's settings.
    pub fn settings(&self) -> Result<VcmSettings, CliError> {
        let mut settings = VcmSettings::default();
        if let Some(mode) = self.vcm_mode {
            settings.mode = mode;
        }
        if let Some(fraction) = self.vcm_radius {
            if !(fraction > 0.0 && fraction.is_finite()) {
                return Err(usage(format!(
                    "--vcm-radius must be a positive fraction, got {fraction}"
                )));
            }
            settings.radius_fraction = fraction;
        }
        if let Some(alpha) = self.vcm_alpha {
            if !(alpha > 0.0 && alpha <= 1.0) {
                return Err(usage(format!("--vcm-alpha must be in (0, 1], got {alpha}")));
            }
            settings.alpha = alpha;
        }
        Ok(settings)
    }
}
