//! Where the samples of a splatting render lie on the film.

use glam::Vec2;

/// What an [`ImagePlane`] needs to know of a render: the image's size and
/// the reach of its reconstruction filter. The scene provides both (its
/// camera's resolution, its filter's radius).
pub trait FilmFrame {
    /// `[width, height]` in pixels.
    fn resolution(&self) -> [u32; 2];
    /// The reconstruction filter's radius along x and y, in pixels.
    fn filter_radius(&self) -> [f32; 2];
}

/// The image-plane domain of a splatting render's primary sample space
/// (LQMC's, and the path tracers' with `splat_film`): the image grown by
/// the filter's reach beyond the border pixels' centres (radius − ½), so
/// that splatting with the filter gives the image that filter importance
/// sampling gives, border pixels included.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImagePlane {
    /// Raster position of the domain's corner (≤ 0).
    pub origin: Vec2,
    /// Its size in pixels.
    pub size: Vec2,
    /// Domain area over image area: the factor on every splat, since seeds
    /// are spread over the larger domain.
    pub area_scale: f32,
}

impl ImagePlane {
    /// The domain for the image and filter of `frame`.
    pub fn new(frame: &(impl FilmFrame + ?Sized)) -> Self {
        let [width, height] = frame.resolution().map(|size| size as f32);
        let radius = frame.filter_radius();
        let margin = Vec2::new((radius[0] - 0.5).max(0.0), (radius[1] - 0.5).max(0.0));
        let size = Vec2::new(width, height) + 2.0 * margin;
        Self {
            origin: -margin,
            size,
            area_scale: size.x * size.y / (width * height),
        }
    }

    /// The raster position of image-plane numbers `g ∈ [0, 1)²`.
    pub fn raster(&self, g: Vec2) -> Vec2 {
        (self.origin + g * self.size).min(self.origin + self.size - Vec2::splat(1e-3))
    }

    /// The image-plane numbers of a raster position.
    pub fn numbers(&self, raster: Vec2) -> Vec2 {
        (raster - self.origin) / self.size
    }

    /// Whether a raster position lies in the domain.
    pub fn contains(&self, raster: Vec2) -> bool {
        let g = self.numbers(raster);
        g.x >= 0.0 && g.y >= 0.0 && g.x < 1.0 && g.y < 1.0
    }

    /// The seed's raster position for film numbers `u` of `pixel`: the
    /// pixel's share of the domain (of `frame`'s image).
    pub fn seed_raster(
        &self,
        frame: &(impl FilmFrame + ?Sized),
        pixel: (u32, u32),
        u: [f32; 2],
    ) -> Vec2 {
        let [width, height] = frame.resolution().map(|size| size as f32);
        let g = Vec2::new(
            (pixel.0 as f32 + u[0]) / width,
            (pixel.1 as f32 + u[1]) / height,
        );
        self.raster(g)
    }
}
