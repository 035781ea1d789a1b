//! The options of the LQMC integrator, with the defaults of the paper
//! (Tessari, Hanika & Dachsbacher, Sec. 3.4) and of the authors' renderer
//! (`docs/integrators/lqmc.md`, "Implementation notes").

use super::classification::PathClass;

/// The effects (groups of primary-sample-space dimensions) LQMC may explore.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ExploredEffects {
    /// Lens position (2 dimensions; only for a thin lens).
    pub aperture: bool,
    /// Hero wavelength (1 dimension).
    pub wavelength: bool,
    /// Time in the shutter interval (1 dimension).
    pub time: bool,
    /// Image-plane position (2 dimensions, breakup vertex b ≥ 1).
    pub image: bool,
    /// Outgoing directions of the non-specular vertices before the breakup
    /// vertex (2 dimensions each).
    pub direction: bool,
    /// Free-flight distances of the segments that end at medium vertices
    /// of the prefix (1 dimension each).
    pub free_flight: bool,
}

impl Default for ExploredEffects {
    /// Aperture, wavelength, image plane, directions and free flights; time
    /// is optional
    /// (as in the authors' renderer).
    fn default() -> Self {
        Self {
            aperture: true,
            wavelength: true,
            time: false,
            image: true,
            direction: true,
            free_flight: true,
        }
    }
}

impl ExploredEffects {
    /// Every effect by its command-line name.
    pub const NAMES: [&'static str; 6] = [
        "aperture",
        "wavelength",
        "time",
        "image",
        "direction",
        "free-flight",
    ];

    /// No effect at all.
    pub fn none() -> Self {
        Self {
            aperture: false,
            wavelength: false,
            time: false,
            image: false,
            direction: false,
            free_flight: false,
        }
    }

    /// Parses a comma-separated list such as `aperture,wavelength,time`.
    pub fn parse(list: &str) -> Result<Self, String> {
        let mut effects = Self::none();
        for name in list
            .split(',')
            .map(str::trim)
            .filter(|name| !name.is_empty())
        {
            match name {
                "aperture" => effects.aperture = true,
                "wavelength" => effects.wavelength = true,
                "time" => effects.time = true,
                "image" => effects.image = true,
                "direction" => effects.direction = true,
                "free-flight" => effects.free_flight = true,
                other => {
                    return Err(format!(
                        "unknown effect `{other}` (expected a list of {})",
                        Self::NAMES.join(", ")
                    ));
                }
            }
        }
        Ok(effects)
    }
}

/// Lattice size and tiles per dimension of one path class.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClassParameters {
    /// Points of the rank-1 lattice: 7, 23, 97 or 313.
    pub lattice_size: u64,
    /// Tiles per lens dimension.
    pub aperture_tiles: u32,
    /// Tiles across the image width (the height gets the same tile size).
    pub image_tiles: u32,
    /// Tiles per outgoing-direction dimension.
    pub direction_tiles: u32,
    /// Whether paths of this class are explored at all (otherwise splatted
    /// as they are).
    pub explore: bool,
}

/// How the breakup vertex is chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum BreakupChoice {
    /// Always this vertex (0: the camera); paths too short for it or whose
    /// vertex `b` or `b + 1` is specular are splatted unexplored.
    Fixed(usize),
    /// Always the path's last vertex `x_k` (`--breakup k`): the full-path
    /// breakup, where every explored dimension of the path is perturbed and
    /// the light vertex is sampled again (paths ending in the environment
    /// by BSDF sampling, or at a delta light, are splatted unexplored).
    FullPath,
    /// Drawn from the roughness CDF of the paper (Sec. 3.3, 3.4).
    Roughness,
}

/// Which of the classes marked for exploration a render explores.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ClassSelection {
    /// Each, if a pilot measures that its exploration pays at equal cost
    /// (the default; see [`super::class_selection`]).
    Measured,
    /// Each, always (`--class-selection fixed`).
    Fixed,
}

impl ClassSelection {
    /// Every selection with its command-line name.
    pub const ALL: [(ClassSelection, &'static str); 2] = [
        (ClassSelection::Measured, "measured"),
        (ClassSelection::Fixed, "fixed"),
    ];
}

/// How an exploration maps its explored dimensions to the lattice's
/// dimensions: the paper's Sec. 5 remedy against visible lattice structure
/// is a random permutation of that mapping, drawn per set (keyed on what
/// every member of the set shares, so that each member, had it been the
/// seed, would draw the same one and Eq. (9)'s weights stay a partition of
/// unity). A permuted rank-1 lattice is again a rank-1 lattice.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LatticeScramble {
    /// Explored dimension i takes lattice dimension i: every set of a
    /// dimension count shows the same two-dimensional projection on the
    /// image plane.
    None,
    /// The two image-plane dimensions swap lattice dimensions with two
    /// other explored dimensions chosen at random; the others keep theirs
    /// (nothing is swapped when fewer than two other dimensions are
    /// explored, e.g. b = 1 with a pinhole camera: wavelength and image).
    Image,
    /// A uniformly random permutation of the whole mapping (Fisher–Yates).
    All,
}

impl LatticeScramble {
    /// Every mode with its command-line name.
    pub const ALL: [(LatticeScramble, &'static str); 3] = [
        (LatticeScramble::None, "none"),
        (LatticeScramble::Image, "image"),
        (LatticeScramble::All, "all"),
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        Self::ALL
            .iter()
            .find(|(mode, _)| *mode == self)
            .map(|(_, name)| *name)
            .expect("every mode is listed")
    }

    /// The mode called `name`.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL
            .iter()
            .find(|(_, known)| *known == name)
            .map(|(mode, _)| *mode)
    }
}

/// Settings of the LQMC integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LqmcSettings {
    /// The explored effects (default: aperture, wavelength, image,
    /// direction).
    pub effects: ExploredEffects,
    /// The breakup vertex (default: the roughness CDF).
    pub breakup: BreakupChoice,
    /// Normal paths: N = 23, 2×2 aperture tiles, 24 image tiles, 155
    /// direction tiles; not explored by default (`--explore-class normal`):
    /// against the seeds' own splats (the same estimator as path tracing
    /// with `--splat-film`) their exploration lowered the error at equal
    /// samples by under 1 % on dof-spheres and 5 % on glass-sphere-box, for
    /// 1.5 to 2.7 times the time (README, "LQMC at equal time").
    pub normal: ClassParameters,
    /// Caustic paths: N = 97, 4×4 aperture tiles, 48 image tiles, 55
    /// direction tiles; explored (on glass-sphere-box it halves the error
    /// at equal samples and pays at equal time).
    pub caustic: ClassParameters,
    /// Depth-of-field paths: N = 7, tiles as normal paths (the paper's
    /// N = 23 over a circle of confusion of a few pixels puts about three
    /// members in a pixel); not explored by default (`--explore-class
    /// dof`): on dof-spheres its exploration *raised* the error at 256
    /// samples per pixel (RMSE 5.25e-3 against 4.83e-3 without), as the
    /// members that land in a pixel come from other pixels' seeds and so
    /// lose the stratification of the pixel's Halton points (LQMC's error
    /// fell as n^-0.6 against the seeds' n^-0.75); on translucent-spheres
    /// it lowered the MSE by 44 % for 2.2 times the time.
    pub depth_of_field: ClassParameters,
    /// Next-event-estimation paths: N = 7 (the authors' renderer), tiles as
    /// normal paths; not explored by default (the paper's rule: next-event
    /// paths are explored only as depth-of-field paths, whose class takes
    /// precedence; `--explore-class nee` turns them on).
    pub next_event: ClassParameters,
    /// Tiles per wavelength dimension (default 1: the whole spectrum).
    pub wavelength_tiles: u32,
    /// Tiles per time dimension (default 1: the whole shutter interval).
    pub time_tiles: u32,
    /// Tiles per free-flight dimension (default 1000, the authors' value).
    pub free_flight_tiles: u32,
    /// Tiles across the image width, for every class, when the camera is
    /// inside a medium, so that the first segment is (default 12, the
    /// authors' value: a member's first free flight moves it far more than
    /// a pixel step does).
    pub medium_image_tiles: u32,
    /// A first hit whose circle of confusion exceeds this many pixels makes
    /// the path a depth-of-field path (default 2).
    pub depth_of_field_threshold_pixels: f32,
    /// The factor on the breakup weight of b = 0 for depth-of-field paths
    /// (default 16).
    pub depth_of_field_camera_weight: f32,
    /// Roughness below which a vertex counts as (near-)specular for the
    /// caustic class (default 0.05).
    pub caustic_roughness: f32,
    /// Relative distance within which a reconnection must land on the
    /// seed's vertex (default 1e-3).
    pub reconnection_tolerance: f32,
    /// Whether the roughness CDF includes the full-path breakup b = k
    /// (default on: its mass is min(roughness(x_k), roughness(x_{k+1})) = 1,
    /// the light vertex and the nothing after it counting as rough; the
    /// paper's caustic paths mostly break up there, Sec. 3.4).
    pub full_path_breakup: bool,
    /// Whether a breakup whose only explored dimension is the wavelength
    /// may be drawn (default off: with a pinhole camera, b = 0 would walk
    /// N members at other wavelengths into the seed's own pixel, which
    /// costs N walks and reduces only colour noise; `--explore-wavelength-alone`).
    pub explore_wavelength_alone: bool,
    /// Whether b = 0 may be drawn for paths that are not depth-of-field
    /// paths (default off: an in-focus first hit's circle of confusion is
    /// under [`LqmcSettings::depth_of_field_threshold_pixels`], so the
    /// members of an exploration of the lens, wavelength and time land in
    /// the seed's pixel; on dof-spheres they were 57 % of all members for
    /// no lower error; `--explore-camera-in-focus`).
    pub explore_camera_in_focus: bool,
    /// How explored dimensions map to lattice dimensions per set (default
    /// [`LatticeScramble::Image`]; `--lattice-scramble`).
    pub lattice_scramble: LatticeScramble,
    /// Jitter the tile grid once per progression (default on; Sec. 3.4).
    pub jitter_tiles: bool,
    /// Gather the sample density per class, returned as the render's
    /// `density` image (default off; `--lqmc-density`).
    pub gather_density: bool,
    /// Whether the classes marked for exploration are explored always or
    /// only where a pilot measures that it pays (default: measured).
    pub class_selection: ClassSelection,
    /// Trace seeds with the path tracer first and record only those with
    /// an event that could be explored, where explorations are rare
    /// (default on; see `lqmc::seed_screen`; off only to test that it
    /// changes nothing).
    pub screen_seeds: bool,
}

impl Default for LqmcSettings {
    fn default() -> Self {
        let normal = ClassParameters {
            lattice_size: 23,
            aperture_tiles: 2,
            image_tiles: 24,
            direction_tiles: 155,
            explore: false,
        };
        Self {
            effects: ExploredEffects::default(),
            breakup: BreakupChoice::Roughness,
            normal,
            caustic: ClassParameters {
                lattice_size: 97,
                aperture_tiles: 4,
                image_tiles: 48,
                direction_tiles: 55,
                explore: true,
            },
            depth_of_field: ClassParameters {
                lattice_size: 7,
                explore: false,
                ..normal
            },
            next_event: ClassParameters {
                lattice_size: 7,
                explore: false,
                ..normal
            },
            wavelength_tiles: 1,
            time_tiles: 1,
            free_flight_tiles: 1000,
            medium_image_tiles: 12,
            depth_of_field_threshold_pixels: 2.0,
            depth_of_field_camera_weight: 16.0,
            caustic_roughness: 0.05,
            reconnection_tolerance: 1e-3,
            full_path_breakup: true,
            explore_wavelength_alone: false,
            explore_camera_in_focus: false,
            lattice_scramble: LatticeScramble::Image,
            jitter_tiles: true,
            gather_density: false,
            class_selection: ClassSelection::Measured,
            screen_seeds: true,
        }
    }
}

impl LqmcSettings {
    /// The paper's classes explored: normal, caustic and depth-of-field
    /// paths (next-event paths only as depth-of-field paths), always, as
    /// the paper does, with the other defaults; `--explore-class normal
    /// --explore-class dof --class-selection fixed`.
    pub fn paper_classes() -> Self {
        let mut settings = Self::default();
        settings.normal.explore = true;
        settings.depth_of_field.explore = true;
        settings.class_selection = ClassSelection::Fixed;
        settings
    }

    /// Whether a breakup with the explored dimensions `dimensions` can be
    /// explored: between 1 and the lattice table's most dimensions, and not
    /// the wavelength alone unless [`LqmcSettings::explore_wavelength_alone`].
    pub fn explorable(&self, dimensions: &[super::explored_dimensions::ExploredDimension]) -> bool {
        use super::explored_dimensions::DimensionKind;
        (1..=qmc::lattice_table::LQMC_MAX_DIMENSIONS).contains(&dimensions.len())
            && (self.explore_wavelength_alone
                || !matches!(dimensions, [only] if only.kind == DimensionKind::Wavelength))
    }

    /// Whether no path can be explored: no class is, or no effect.
    pub fn explores_nothing(&self) -> bool {
        self.effects == ExploredEffects::none()
            || PathClass::ALL
                .iter()
                .all(|class| !self.class_parameters(*class).explore)
    }

    /// The parameters of `class`.
    pub fn class_parameters(&self, class: PathClass) -> &ClassParameters {
        match class {
            PathClass::Normal => &self.normal,
            PathClass::Caustic => &self.caustic,
            PathClass::DepthOfField => &self.depth_of_field,
            PathClass::NextEvent => &self.next_event,
        }
    }

    /// The parameters of `class`, mutable (for command-line overrides).
    pub fn class_parameters_mut(&mut self, class: PathClass) -> &mut ClassParameters {
        match class {
            PathClass::Normal => &mut self.normal,
            PathClass::Caustic => &mut self.caustic,
            PathClass::DepthOfField => &mut self.depth_of_field,
            PathClass::NextEvent => &mut self.next_event,
        }
    }
}
