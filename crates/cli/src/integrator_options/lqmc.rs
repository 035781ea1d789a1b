//! The options of `--integrator lqmc` and LQMC's settings from them
//! (defaults: the paper's and the authors' renderer's; see
//! `render::integrators::lqmc::settings`).

use super::headings;
use crate::error::CliError;
use crate::named_values::NamedValues;
use clap::Args;
use render::integrators::lqmc::{
    BreakupChoice, ClassSelection, ExploredEffects, LatticeScramble, LqmcSettings, PathClass,
};
use std::path::PathBuf;

/// Options of `--integrator lqmc`.
#[derive(Args, Debug, Default)]
#[command(next_help_heading = headings::LQMC)]
pub struct LqmcArgs {
    /// Explored effects, a comma-separated list of aperture, wavelength,
    /// time, image, direction, free-flight (default
    /// aperture,wavelength,image,direction,free-flight).
    #[arg(long, value_name = "LIST", value_parser = parse_effects)]
    pub explore: Option<ExploredEffects>,
    /// The breakup vertex, a number (0: the camera), `k` for the full path
    /// (the light vertex sampled again) or `cdf` for the roughness CDF
    /// (default cdf, which includes b = k).
    #[arg(long, value_name = "B|k|cdf", value_parser = parse_breakup)]
    pub breakup: Option<BreakupChoice>,
    /// Lattice size N ∈ {7, 23, 97, 313} of a class (normal, caustic, dof,
    /// nee), e.g. `normal=23`; may be repeated.
    #[arg(long, value_name = "CLASS=N", value_parser = parse_lattice_size)]
    pub lattice_size: Vec<(PathClass, u32)>,
    /// Tiles per lens dimension of a class, e.g. `caustic=4`.
    #[arg(long, value_name = "CLASS=K", value_parser = parse_class_count)]
    pub aperture_tiles: Vec<(PathClass, u32)>,
    /// Tiles across the image width of a class, e.g. `normal=24`.
    #[arg(long, value_name = "CLASS=K", value_parser = parse_class_count)]
    pub image_tiles: Vec<(PathClass, u32)>,
    /// Tiles per outgoing-direction dimension of a class.
    #[arg(long, value_name = "CLASS=K", value_parser = parse_class_count)]
    pub direction_tiles: Vec<(PathClass, u32)>,
    /// Tiles per wavelength dimension (default 1).
    #[arg(long, value_name = "K")]
    pub wavelength_tiles: Option<u32>,
    /// Tiles per time dimension (default 1).
    #[arg(long, value_name = "K")]
    pub time_tiles: Option<u32>,
    /// Tiles across the image width when the camera is inside a medium,
    /// for every class (default 12).
    #[arg(long, value_name = "K")]
    pub medium_image_tiles: Option<u32>,
    /// A class whose paths are splatted without exploration; may be
    /// repeated.
    #[arg(long, value_name = "CLASS", value_parser = path_classes())]
    pub skip_class: Vec<PathClass>,
    /// A class to explore that is not explored by default (normal, dof,
    /// nee; only caustic paths are explored by default, see
    /// docs/integrators/lqmc.md, "Which classes explore"); may be repeated. `--explore-class normal
    /// --explore-class dof --class-selection fixed` gives the paper's classes.
    #[arg(long, value_name = "CLASS", value_parser = path_classes())]
    pub explore_class: Vec<PathClass>,
    /// Also explore breakups whose only explored dimension is the
    /// wavelength (b = 0 with a pinhole camera).
    #[arg(long)]
    pub explore_wavelength_alone: bool,
    /// Also explore the camera vertex (b = 0) of paths whose first hit is
    /// in focus (not depth-of-field paths).
    #[arg(long)]
    pub explore_camera_in_focus: bool,
    /// Which of the classes marked for exploration are explored: `measured`
    /// (default) keeps those a short pilot before the render measures to
    /// pay at equal cost (variance times rays); `fixed` explores them all.
    #[arg(long, value_name = "WHICH", value_parser = class_selections())]
    pub class_selection: Option<ClassSelection>,
    /// No tile jitter.
    #[arg(long)]
    pub no_jitter: bool,
    /// How each set maps the explored dimensions to the lattice's (the
    /// paper's Sec. 5 remedy against visible lattice structure, drawn per
    /// set so that the estimator stays unbiased): `none`, `image` (the
    /// image-plane pair swapped with two random other dimensions) or `all`
    /// (a random permutation of every dimension); default image.
    #[arg(long, value_name = "MODE", value_parser = lattice_scrambles())]
    pub lattice_scramble: Option<LatticeScramble>,
    /// Print explorations per class, set sizes, failures and the
    /// closest-point search time.
    #[arg(long)]
    pub stats: bool,
    /// Write the sample density per class to this EXR (splatted members per
    /// pixel and sample: normal, caustic, depth of field as R, G, B;
    /// next-event paths in the layer `nee`), the paper's Fig. 11.
    #[arg(long, value_name = "FILE.exr")]
    pub density: Option<PathBuf>,
}

impl LqmcArgs {
    /// LQMC's settings.
    pub fn settings(&self) -> Result<LqmcSettings, CliError> {
        let mut settings = LqmcSettings::default();
        if let Some(effects) = self.explore {
            settings.effects = effects;
        }
        if let Some(breakup) = self.breakup {
            settings.breakup = breakup;
        }
        for &(class, size) in &self.lattice_size {
            settings.class_parameters_mut(class).lattice_size = u64::from(size);
        }
        for &(class, tiles) in &self.aperture_tiles {
            settings.class_parameters_mut(class).aperture_tiles = tiles;
        }
        for &(class, tiles) in &self.image_tiles {
            settings.class_parameters_mut(class).image_tiles = tiles;
        }
        for &(class, tiles) in &self.direction_tiles {
            settings.class_parameters_mut(class).direction_tiles = tiles;
        }
        for &class in &self.explore_class {
            settings.class_parameters_mut(class).explore = true;
        }
        for &class in &self.skip_class {
            settings.class_parameters_mut(class).explore = false;
        }
        settings.explore_wavelength_alone = self.explore_wavelength_alone;
        settings.explore_camera_in_focus = self.explore_camera_in_focus;
        if let Some(tiles) = self.wavelength_tiles {
            settings.wavelength_tiles = tiles.max(1);
        }
        if let Some(tiles) = self.time_tiles {
            settings.time_tiles = tiles.max(1);
        }
        if let Some(tiles) = self.medium_image_tiles {
            settings.medium_image_tiles = tiles.max(1);
        }
        if let Some(selection) = self.class_selection {
            settings.class_selection = selection;
        }
        settings.jitter_tiles = !self.no_jitter;
        if let Some(scramble) = self.lattice_scramble {
            settings.lattice_scramble = scramble;
        }
        settings.gather_density = self.density.is_some();
        Ok(settings)
    }
}

/// The class selections by name, as command-line values.
fn class_selections() -> NamedValues<ClassSelection> {
    NamedValues::new(ClassSelection::ALL)
}

/// The LQMC path classes by name, as command-line values.
fn path_classes() -> NamedValues<PathClass> {
    NamedValues::new(PathClass::ALL.map(|class| (class, class.name())))
}

/// The lattice scrambles by name, as command-line values.
fn lattice_scrambles() -> NamedValues<LatticeScramble> {
    NamedValues::with_help(LatticeScramble::ALL, |scramble| match scramble {
        LatticeScramble::None => "explored dimension i takes lattice dimension i",
        LatticeScramble::Image => {
            "the image-plane pair takes the lattice dimensions of two random other explored dimensions"
        }
        LatticeScramble::All => {
            "a random permutation of every explored dimension's lattice dimension"
        }
    })
}

/// The LQMC class called `name`.
fn parse_class(name: &str) -> Result<PathClass, String> {
    PathClass::ALL
        .into_iter()
        .find(|class| class.name() == name)
        .ok_or_else(|| {
            format!("unknown LQMC class `{name}` (expected normal, caustic, dof or nee)")
        })
}

/// Parses `CLASS=K` with a positive integer K.
fn parse_class_count(text: &str) -> Result<(PathClass, u32), String> {
    let (name, value) = text
        .split_once('=')
        .ok_or_else(|| format!("expected CLASS=VALUE, got `{text}`"))?;
    let value: u32 = value
        .parse()
        .ok()
        .filter(|value| *value > 0)
        .ok_or_else(|| format!("`{value}` is not a positive integer"))?;
    Ok((parse_class(name)?, value))
}

/// Parses `CLASS=N` of `--lattice-size`: N one of the tabulated sizes.
fn parse_lattice_size(text: &str) -> Result<(PathClass, u32), String> {
    let (class, size) = parse_class_count(text)?;
    if !qmc::lattice_table::LQMC_LATTICE_SIZES.contains(&u64::from(size)) {
        return Err(format!("N must be one of 7, 23, 97, 313, got {size}"));
    }
    Ok((class, size))
}

/// Parses `--breakup`: a vertex number, `k` or `cdf`.
fn parse_breakup(text: &str) -> Result<BreakupChoice, String> {
    match text {
        "cdf" => Ok(BreakupChoice::Roughness),
        "k" => Ok(BreakupChoice::FullPath),
        vertex => vertex.parse().map(BreakupChoice::Fixed).map_err(|_| {
            format!("expected a vertex number, `k` (the full path) or `cdf`, got `{text}`")
        }),
    }
}

/// Parses `--explore`: a comma-separated list of effects.
fn parse_effects(text: &str) -> Result<ExploredEffects, String> {
    ExploredEffects::parse(text)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn class_values_parse_and_refuse_nonsense() {
        assert_eq!(parse_class_count("caustic=4"), Ok((PathClass::Caustic, 4)));
        assert!(parse_class_count("caustic").is_err());
        assert!(parse_class_count("caustic=0").is_err());
        assert!(parse_class_count("glossy=4").is_err());
        assert_eq!(parse_lattice_size("nee=97"), Ok((PathClass::NextEvent, 97)));
        assert!(parse_lattice_size("nee=96").is_err());
    }

    #[test]
    fn breakups_are_numbers_k_or_cdf() {
        assert_eq!(parse_breakup("2"), Ok(BreakupChoice::Fixed(2)));
        assert_eq!(parse_breakup("k"), Ok(BreakupChoice::FullPath));
        assert_eq!(parse_breakup("cdf"), Ok(BreakupChoice::Roughness));
        assert!(parse_breakup("last").is_err());
    }
}
