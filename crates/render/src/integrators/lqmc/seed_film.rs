//! Where LQMC's seeds lie on the image and how their values reach the
//! film: by default as the path tracer's camera samples, with
//! `--splat-film` spread uniformly and splatted (Mitsuba's film).
//!
//! A seed's events that are not explored are valued as the path tracer
//! values them; by default they also land as its sample would, so that a
//! render that explores little costs and looks like path tracing: the seed
//! is placed by filter importance sampling around its pixel's centre and
//! its unexplored value added to that pixel as one camera sample of weight
//! one. Every seed adds its sample, zero or not: the pixel's weights then
//! count its samples, as the path tracer's do.
//!
//! Explored members land anywhere and are splatted with the filter. The
//! set estimator (Eq. 9) divides by the density with which each member
//! would have been drawn as a seed, so that density, which filter
//! importance sampling makes uneven, enters it: per pixel of the image it
//! is `D(x) = Σ_p f(x − c_p)` ([`crate::film::Filter::sample_density`]),
//! the sum of the filter's weights of a splat at `x`. A member's `q` is
//! multiplied by `D(x_j)` and its splat divided by it. With the default box
//! filter `D = 1` inside the image; with the Gaussian it is near one inside
//! and falls off across the border. Why the splat is `C / D`: a seed's
//! raster density is `D(x) / (W H)`, so `C = L · W H / D`; the film divides
//! splats by the `W H · spp` seeds' `spp`, leaving `L / D` per splat.
//!
//! With `--splat-film` each seed is uniform in its pixel's share of the
//! [`ImagePlane`] (the image grown by the filter's reach), its density the
//! same everywhere (it cancels in Eq. 9), and every value is splatted
//! scaled by the plane's area over the image's.

use crate::film::{FilmFrame, Filter, ImagePlane};
use crate::scene::Scene;
use glam::Vec2;

/// How a render's seeds are placed and where their values land.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SeedFilm {
    /// As the path tracer's camera samples (the default).
    Pixel {
        /// The film's filter.
        filter: Filter,
        /// The image's resolution.
        resolution: [u32; 2],
    },
    /// Uniform in each pixel's share of the image plane, all splatted.
    Splat {
        /// The image plane (its area scale: its area over the image's).
        image_plane: ImagePlane,
    },
}

impl SeedFilm {
    /// The seed film of `scene`: splatted with `splat_film`.
    pub fn new(scene: &Scene, splat_film: bool) -> Self {
        if splat_film {
            Self::Splat {
                image_plane: ImagePlane::new(scene),
            }
        } else {
            Self::Pixel {
                filter: scene.filter,
                resolution: scene.resolution(),
            }
        }
    }

    /// The raster position of `pixel`'s seed with film numbers `u`.
    #[inline]
    pub fn seed_raster(&self, scene: &Scene, pixel: (u32, u32), u: [f32; 2]) -> Vec2 {
        match self {
            Self::Pixel { filter, .. } => {
                let offset = filter.sample(u).offset;
                Vec2::new(
                    pixel.0 as f32 + 0.5 + offset[0],
                    pixel.1 as f32 + 0.5 + offset[1],
                )
            }
            Self::Splat { image_plane } => image_plane.seed_raster(scene, pixel, u),
        }
    }

    /// Whether the seed's unexplored value goes to its pixel as a camera
    /// sample (else it is splatted).
    pub fn adds_camera_samples(&self) -> bool {
        matches!(self, Self::Pixel { .. })
    }

    /// The factor of a seed's unexplored value: one for a camera sample,
    /// the area scale for a splat.
    #[inline]
    pub fn unexplored_scale(&self) -> f32 {
        match self {
            Self::Pixel { .. } => 1.0,
            Self::Splat { image_plane } => image_plane.area_scale,
        }
    }

    /// The density, up to a factor the whole render shares, with which a
    /// seed lies at `raster` (`D(x)` for camera samples, one for splats).
    #[inline]
    pub fn seed_density(&self, raster: Vec2) -> f64 {
        match self {
            Self::Pixel { filter, resolution } => {
                filter.sample_density(*resolution, raster.to_array())
            }
            Self::Splat { .. } => 1.0,
        }
    }

    /// The factor of a member's splat at a point of seed density
    /// `density` ([`SeedFilm::seed_density`]): `1 / D` for camera samples,
    /// the area scale for splats.
    #[inline]
    pub fn member_scale(&self, density: f64) -> f32 {
        match self {
            Self::Pixel { .. } => (1.0 / density) as f32,
            Self::Splat { image_plane } => image_plane.area_scale,
        }
    }
}
