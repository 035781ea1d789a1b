//! Environment maps: radiance at infinity read from an RGB image, in
//! Mitsuba 3's latitude–longitude or pbrt-v4's equal-area octahedral
//! parameterisation, importance-sampled in proportion to luminance.
//!
//! **Lookup.** Texels become spectra as illuminants: the Jakob–Hanika
//! sigmoid of `rgb / (2 max rgb)` times `2 max rgb` times D65 (what the
//! constant environment and Mitsuba 3's `envmap` do). Conventions, checked
//! against Mitsuba 3.9.1 (`scripts/envmap_reference.py`):
//!
//! - [`EnvironmentProjection::MitsubaEquirectangular`]: in the light frame
//!   (+y up), `u = atan2(x, −z)/(2π)` mod 1 and `v = acos(y)/π`. Column `i`
//!   sits at `u = (i + ½)/W` (periodic in u), row `j` at `v = j/(H − 1)`, so
//!   the first and last rows are the poles. The lookup is bilinear; as in
//!   Mitsuba, the sigmoid spectra and the scales `2 max rgb` are
//!   interpolated separately and multiplied.
//! - [`EnvironmentProjection::PbrtEqualArea`]: a square image in Clarberg's
//!   equal-area octahedral map of the light frame (+z up), pixel (0, 0) at
//!   the top left, looked up at the nearest pixel (pbrt-v4's `imagemap`
//!   light).
//!
//! **Sampling.** A [`PiecewiseConstant2D`] over the cells on which the
//! radiance is interpolated: for the lat-long map the W × (H − 1) cells
//! between texel centres, each weighted by the mean luminance of its four
//! corners times its solid angle (the sin θ weighting), and sampled
//! uniformly in φ and cos θ inside the cell, so that the solid-angle
//! density is constant per cell: `P(cell) / Ω(cell)`. For the equal-area
//! map every pixel subtends 4π/N², so the weights are the pixels'
//! luminances and the density is `p(u, v) / 4π`.

use std::f32::consts::{PI, TAU};
use std::path::Path;

use glam::{Affine3A, Vec2, Vec3};

use super::equal_area::{equal_area_sphere_to_square, equal_area_square_to_sphere};
use super::error::LightError;
use super::piecewise_constant::PiecewiseConstant2D;
use crate::image::{Image, read_image};
use crate::spectrum::{
    SampledSpectrum, SampledWavelengths, SpectrumUsage, d65_illuminant, linear_srgb_luminance,
};
use crate::texture::SigmoidTexel;

/// How an environment map's image covers the sphere of directions.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum EnvironmentProjection {
    /// Mitsuba 3's latitude–longitude map: u = atan2(d.x, −d.z)/(2π) (mod 1),
    /// v = acos(d.y)/π in the light frame (+y up); pixel columns are centred
    /// at u = (i + ½)/W, rows at v = j/(H − 1) (the first and last rows sit on
    /// the poles); bilinear interpolation, as Mitsuba 3's `envmap`.
    MitsubaEquirectangular,
    /// pbrt-v4's equal-area octahedral square map (Clarberg 2008), +z up,
    /// nearest-pixel lookup, as pbrt-v4's `imagemap` infinite light.
    PbrtEqualArea,
}

/// An image-based light at infinity.
#[derive(Debug, Clone)]
pub struct EnvironmentMap {
    projection: EnvironmentProjection,
    width: usize,
    height: usize,
    /// Per texel, row-major, top row first.
    texels: Vec<SigmoidTexel>,
    /// Factor on the radiance.
    scale: f32,
    /// Light frame to world (rotation; any scale is removed).
    to_world: Affine3A,
    to_light: Affine3A,
    /// Over the interpolation cells (see the module docs).
    distribution: PiecewiseConstant2D,
    /// ∫ luminance dω / 4π: the mean luminance over the sphere (with `scale`).
    mean_luminance: f32,
}

/// A direction drawn from an [`EnvironmentMap`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct EnvironmentSample {
    /// World-space unit direction towards the environment.
    pub direction: Vec3,
    /// Its density per unit solid angle.
    pub pdf: f32,
}

impl EnvironmentMap {
    /// Reads the image at `path` (EXR, PFM or PNG); `what` names the light in errors.
    pub fn load(
        path: &Path,
        projection: EnvironmentProjection,
        to_world: Affine3A,
        scale: f32,
        what: &str,
    ) -> Result<Self, LightError> {
        let image = read_image(path).map_err(|error| LightError {
            what: what.to_string(),
            message: error.to_string(),
        })?;
        Self::from_image(&image, projection, to_world, scale).map_err(|message| LightError {
            what: what.to_string(),
            message: format!("'{}': {message}", path.display()),
        })
    }

    /// An environment map from linear RGB texels.
    pub fn from_image(
        image: &Image,
        projection: EnvironmentProjection,
        to_world: Affine3A,
        scale: f32,
    ) -> Result<Self, String> {
        let (width, height) = (image.width(), image.height());
        match projection {
            EnvironmentProjection::MitsubaEquirectangular if width < 2 || height < 3 => {
                return Err(format!(
                    "a latitude-longitude map needs at least 2×3 pixels, got {width}×{height}"
                ));
            }
            EnvironmentProjection::PbrtEqualArea if width != height || width == 0 => {
                return Err(format!(
                    "an equal-area map must be square, got {width}×{height}"
                ));
            }
            _ => {}
        }
        if !(scale.is_finite() && scale >= 0.0) {
            return Err(format!(
                "scale must be finite and non-negative, got {scale}"
            ));
        }
        if image
            .pixels()
            .iter()
            .any(|pixel| pixel.iter().any(|value| !value.is_finite()))
        {
            return Err("the image has infinite or NaN pixels".into());
        }
        let texels: Vec<SigmoidTexel> = image
            .pixels()
            .iter()
            .map(|&rgb| SigmoidTexel::new(rgb, SpectrumUsage::Illuminant))
            .collect();
        let luminance: Vec<f32> = image
            .pixels()
            .iter()
            .map(|&rgb| linear_srgb_luminance(rgb.map(|value| value.max(0.0))).max(0.0))
            .collect();
        let rotation = orthonormal_part(to_world)?;
        let (weights, columns, rows, integral) = match projection {
            EnvironmentProjection::MitsubaEquirectangular => {
                let (columns, rows) = (width, height - 1);
                let mut weights = Vec::with_capacity(columns * rows);
                let mut integral = 0.0f64;
                for row in 0..rows {
                    let solid_angle = cell_solid_angle(row, rows, columns);
                    for column in 0..columns {
                        let next = (column + 1) % width;
                        let mean = 0.25
                            * (luminance[row * width + column]
                                + luminance[row * width + next]
                                + luminance[(row + 1) * width + column]
                                + luminance[(row + 1) * width + next]);
                        weights.push(mean * solid_angle);
                        integral += (mean * solid_angle) as f64;
                    }
                }
                (weights, columns, rows, integral)
            }
            EnvironmentProjection::PbrtEqualArea => {
                let pixel_solid_angle = 4.0 * PI / (width * height) as f32;
                let integral: f64 = luminance
                    .iter()
                    .map(|&value| (value * pixel_solid_angle) as f64)
                    .sum();
                (luminance, width, height, integral)
            }
        };
        Ok(Self {
            projection,
            width,
            height,
            texels,
            scale,
            to_world: rotation,
            to_light: rotation.inverse(),
            distribution: PiecewiseConstant2D::new(&weights, columns, rows),
            mean_luminance: scale * (integral / (4.0 * std::f64::consts::PI)) as f32,
        })
    }

    /// The mean over the sphere of the luminance of the radiance (relative
    /// to D65 of luminance 1).
    pub fn mean_luminance(&self) -> f32 {
        self.mean_luminance
    }

    /// The image's size in pixels.
    pub fn resolution(&self) -> [usize; 2] {
        [self.width, self.height]
    }

    /// Radiance arriving from world direction `direction` (towards the
    /// environment; need not be normalised).
    pub fn radiance(&self, direction: Vec3, wavelengths: &SampledWavelengths) -> SampledSpectrum {
        let local = self
            .to_light
            .transform_vector3(direction)
            .normalize_or_zero();
        if local == Vec3::ZERO {
            return SampledSpectrum::zero();
        }
        let unscaled = match self.projection {
            EnvironmentProjection::MitsubaEquirectangular => {
                let (u, v) = lat_long_uv(local);
                let (width, height) = (self.width, self.height);
                let x = (u - 0.5 / width as f32).rem_euclid(1.0) * width as f32;
                let x0 = (x as usize).min(width - 1);
                let fx = (x - x0 as f32).clamp(0.0, 1.0);
                let x1 = (x0 + 1) % width;
                let y = v * (height - 1) as f32;
                let y0 = (y.max(0.0) as usize).min(height - 2);
                let fy = (y - y0 as f32).clamp(0.0, 1.0);
                let corners = [
                    (y0 * width + x0, (1.0 - fx) * (1.0 - fy)),
                    (y0 * width + x1, fx * (1.0 - fy)),
                    ((y0 + 1) * width + x0, (1.0 - fx) * fy),
                    ((y0 + 1) * width + x1, fx * fy),
                ];
                let mut spectrum = SampledSpectrum::zero();
                let mut texel_scale = 0.0f32;
                for (index, weight) in corners {
                    if weight != 0.0 {
                        let texel = &self.texels[index];
                        spectrum += texel.polynomial.sample(wavelengths) * weight;
                        texel_scale += texel.scale * weight;
                    }
                }
                spectrum * texel_scale
            }
            EnvironmentProjection::PbrtEqualArea => {
                let p = equal_area_sphere_to_square(local);
                let n = self.width;
                let x = ((p.x * n as f32).max(0.0) as usize).min(n - 1);
                let y = ((p.y * n as f32).max(0.0) as usize).min(n - 1);
                let texel = &self.texels[y * n + x];
                texel.polynomial.sample(wavelengths) * texel.scale
            }
        };
        unscaled * d65_illuminant().sample(wavelengths) * self.scale
    }

    /// Draws a direction with density proportional to the luminance
    /// (piecewise constant per cell, see the module docs).
    pub fn sample(&self, u: [f32; 2]) -> Option<EnvironmentSample> {
        let sample = self.distribution.sample(u);
        if sample.pdf <= 0.0 {
            return None;
        }
        let [columns, rows] = self.distribution.resolution();
        let local = match self.projection {
            EnvironmentProjection::MitsubaEquirectangular => {
                let [column, row] = sample.cell;
                let fraction_x = sample.point[0] * columns as f32 - column as f32;
                let fraction_y = (sample.point[1] * rows as f32 - row as f32).clamp(0.0, 1.0);
                // Column i of cells starts at texel i's centre, u = (i + ½)/W.
                let u = (column as f32 + 0.5 + fraction_x) / self.width as f32;
                let (cos_top, cos_bottom) = row_cosines(row, rows);
                let cos_theta = cos_top + (cos_bottom - cos_top) * fraction_y;
                lat_long_direction(u, cos_theta)
            }
            EnvironmentProjection::PbrtEqualArea => {
                equal_area_square_to_sphere(Vec2::from(sample.point))
            }
        };
        let pdf = self.pdf_of_cell(sample.cell, columns, rows);
        if !(pdf > 0.0 && pdf.is_finite()) {
            return None;
        }
        Some(EnvironmentSample {
            direction: self.to_world.transform_vector3(local).normalize(),
            pdf,
        })
    }

    /// The solid-angle density with which [`Self::sample`] picks world
    /// direction `direction`.
    pub fn pdf(&self, direction: Vec3) -> f32 {
        let local = self
            .to_light
            .transform_vector3(direction)
            .normalize_or_zero();
        if local == Vec3::ZERO {
            return 0.0;
        }
        let [columns, rows] = self.distribution.resolution();
        let cell = match self.projection {
            EnvironmentProjection::MitsubaEquirectangular => {
                let (u, v) = lat_long_uv(local);
                let x = (u - 0.5 / self.width as f32).rem_euclid(1.0) * self.width as f32;
                let column = (x as usize).min(columns - 1);
                let row = ((v * rows as f32).max(0.0) as usize).min(rows - 1);
                [column, row]
            }
            EnvironmentProjection::PbrtEqualArea => {
                let p = equal_area_sphere_to_square(local);
                self.distribution.cell_of([p.x, p.y])
            }
        };
        self.pdf_of_cell(cell, columns, rows)
    }

    /// Solid-angle density inside a cell of the distribution.
    fn pdf_of_cell(&self, cell: [usize; 2], columns: usize, rows: usize) -> f32 {
        let probability = self.distribution.cell_probability(cell);
        let solid_angle = match self.projection {
            EnvironmentProjection::MitsubaEquirectangular => {
                cell_solid_angle(cell[1], rows, columns)
            }
            EnvironmentProjection::PbrtEqualArea => 4.0 * PI / (columns * rows) as f32,
        };
        if solid_angle > 0.0 {
            probability / solid_angle
        } else {
            0.0
        }
    }
}

/// Mitsuba's lat-long coordinates of a light-frame unit direction.
fn lat_long_uv(local: Vec3) -> (f32, f32) {
    let u = local.x.atan2(-local.z) / TAU;
    let v = local.y.clamp(-1.0, 1.0).acos() / PI;
    (u.rem_euclid(1.0), v)
}

/// The light-frame direction at lat-long `u` with polar cosine `cos_theta`.
fn lat_long_direction(u: f32, cos_theta: f32) -> Vec3 {
    let phi = TAU * u;
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    Vec3::new(phi.sin() * sin_theta, cos_theta, -phi.cos() * sin_theta)
}

/// cos θ at the top and bottom of cell row `row` of `rows` (θ from 0 to π).
fn row_cosines(row: usize, rows: usize) -> (f32, f32) {
    let theta_top = PI * row as f32 / rows as f32;
    let theta_bottom = PI * (row + 1) as f32 / rows as f32;
    (theta_top.cos(), theta_bottom.cos())
}

/// The solid angle of a lat-long cell in row `row` of `rows`, `columns` wide.
fn cell_solid_angle(row: usize, rows: usize, columns: usize) -> f32 {
    let (cos_top, cos_bottom) = row_cosines(row, rows);
    TAU / columns as f32 * (cos_top - cos_bottom).max(0.0)
}

/// The rotation of `to_world` (its linear part with the scale removed by
/// Gram–Schmidt); fails for a singular or mirroring transform.
fn orthonormal_part(to_world: Affine3A) -> Result<Affine3A, String> {
    let matrix = to_world.matrix3;
    let x = Vec3::from(matrix.x_axis).normalize_or_zero();
    let y = Vec3::from(matrix.y_axis);
    let y = (y - x * x.dot(y)).normalize_or_zero();
    let z = x.cross(y);
    if x == Vec3::ZERO || y == Vec3::ZERO || z.dot(Vec3::from(matrix.z_axis)) <= 0.0 {
        return Err("to_world must be an invertible transform without mirroring".into());
    }
    Ok(Affine3A::from_mat3(glam::Mat3::from_cols(x, y, z)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::sample_uniform_sphere;
    use crate::statistics::chi_square_test;
    use qmc::random::SeekablePcg;

    /// A small map with a bright spot, a dark band and a colour gradient.
    fn test_image(width: usize, height: usize) -> Image {
        let mut pixels = Vec::with_capacity(width * height);
        for y in 0..height {
            for x in 0..width {
                let (fx, fy) = (x as f32 / width as f32, y as f32 / height as f32);
                let mut rgb = [0.2 + fx, 0.5 * fy + 0.1, 0.3];
                if x == width / 3 && y == height / 3 {
                    rgb = [40.0, 30.0, 20.0];
                }
                if y == height / 2 + 1 {
                    rgb = [0.0; 3];
                }
                pixels.push(rgb);
            }
        }
        Image::from_pixels(width, height, pixels).unwrap()
    }

    fn rotated() -> Affine3A {
        Affine3A::from_rotation_x(0.4) * Affine3A::from_rotation_z(-1.1)
    }

    fn maps() -> Vec<EnvironmentMap> {
        vec![
            EnvironmentMap::from_image(
                &test_image(12, 7),
                EnvironmentProjection::MitsubaEquirectangular,
                rotated(),
                1.5,
            )
            .unwrap(),
            EnvironmentMap::from_image(
                &test_image(8, 8),
                EnvironmentProjection::PbrtEqualArea,
                rotated(),
                1.5,
            )
            .unwrap(),
        ]
    }

    /// ∫ pdf dω = 1, estimated with uniform directions (the pdf is bounded).
    #[test]
    fn pdf_integrates_to_one() {
        for map in maps() {
            let mut random = SeekablePcg::new(1, 0);
            let n = 400_000;
            let mut sum = 0.0f64;
            let mut sum_squares = 0.0f64;
            for _ in 0..n {
                let d = sample_uniform_sphere(Vec2::new(random.next_f32(), random.next_f32()));
                let value = (map.pdf(d) * 4.0 * PI) as f64;
                sum += value;
                sum_squares += value * value;
            }
            let mean = sum / n as f64;
            let standard_error = ((sum_squares / n as f64 - mean * mean) / n as f64).sqrt();
            assert!(
                (mean - 1.0).abs() < 4.0 * standard_error + 1e-4,
                "{:?}: {mean} ± {standard_error}",
                map.projection
            );
        }
    }

    /// Sampled directions follow the pdf: chi-square over (cos θ, φ) bins of
    /// the world frame, the expected counts integrated from `pdf`.
    #[test]
    fn sampling_matches_pdf() {
        for map in maps() {
            let (bins_z, bins_phi) = (10usize, 20usize);
            let bin = |d: Vec3| {
                let z = (((d.z + 1.0) / 2.0 * bins_z as f32) as usize).min(bins_z - 1);
                let phi = d.y.atan2(d.x).rem_euclid(TAU);
                let p = ((phi / TAU * bins_phi as f32) as usize).min(bins_phi - 1);
                z * bins_phi + p
            };
            let mut random = SeekablePcg::new(2, 0);
            let samples = 200_000u64;
            let mut observed = vec![0u64; bins_z * bins_phi];
            for _ in 0..samples {
                let sample = map.sample([random.next_f32(), random.next_f32()]).unwrap();
                assert!((sample.direction.length() - 1.0).abs() < 1e-4);
                let pdf = map.pdf(sample.direction);
                assert!(
                    (pdf - sample.pdf).abs() <= 2e-3 * sample.pdf,
                    "{:?}: pdf {pdf} vs sampled {}",
                    map.projection,
                    sample.pdf
                );
                observed[bin(sample.direction)] += 1;
            }
            // Expected counts by a fine midpoint rule in (z, φ) (each bin
            // has solid angle (2/bins_z)(2π/bins_phi)).
            let refine = 24usize;
            let mut expected = vec![0.0f64; bins_z * bins_phi];
            for zi in 0..bins_z * refine {
                let z = -1.0 + 2.0 * (zi as f32 + 0.5) / (bins_z * refine) as f32;
                let radius = (1.0 - z * z).sqrt();
                for pi in 0..bins_phi * refine {
                    let phi = TAU * (pi as f32 + 0.5) / (bins_phi * refine) as f32;
                    let d = Vec3::new(radius * phi.cos(), radius * phi.sin(), z);
                    let area = 2.0 / (bins_z * refine) as f64 * std::f64::consts::TAU
                        / (bins_phi * refine) as f64;
                    expected[bin(d)] += map.pdf(d) as f64 * area * samples as f64;
                }
            }
            let result = chi_square_test(&observed, &expected);
            assert!(result.p_value > 1e-3, "{:?}: {result:?}", map.projection);
        }
    }

    /// The lookup conventions of Mitsuba 3's envmap, checked numerically
    /// with Mitsuba 3.9.1 (`scripts/envmap_reference.py`): in a 4 × 3 map
    /// with R = column + 1, G = 10 (row + 1), column centres sit at
    /// u = (i + ½)/4 and rows at v = j/2.
    #[test]
    fn mitsuba_lookup_positions() {
        let mut pixels = Vec::new();
        for y in 0..3 {
            for x in 0..4 {
                pixels.push([(x + 1) as f32, 10.0 * (y + 1) as f32, 0.5]);
            }
        }
        let image = Image::from_pixels(4, 3, pixels).unwrap();
        let map = EnvironmentMap::from_image(
            &image,
            EnvironmentProjection::MitsubaEquirectangular,
            Affine3A::IDENTITY,
            1.0,
        )
        .unwrap();
        // Compare with a single-texel map of the interpolated RGB: equal
        // spectra where the interpolation weights sit on one texel.
        let wavelengths = SampledWavelengths::sample_visible(0.37);
        let at = |u: f32, v: f32| {
            let theta = PI * v;
            map.radiance(lat_long_direction(u, theta.cos()), &wavelengths)
        };
        let constant = |rgb: [f32; 3]| {
            let texel = SigmoidTexel::new(rgb, SpectrumUsage::Illuminant);
            texel.polynomial.sample(&wavelengths)
                * texel.scale
                * d65_illuminant().sample(&wavelengths)
        };
        for (u, v, rgb) in [
            (0.125, 0.5, [1.0, 20.0, 0.5]),
            (0.375, 0.0001, [2.0, 10.0, 0.5]),
            (0.875, 0.9999, [4.0, 30.0, 0.5]),
        ] {
            let got = at(u, v);
            let expected = constant(rgb);
            for i in 0..crate::spectrum::SPECTRUM_SAMPLE_COUNT {
                assert!(
                    (got[i] - expected[i]).abs() <= 2e-3 * expected[i].abs() + 1e-4,
                    "({u}, {v}): {got:?} vs {expected:?}"
                );
            }
        }
    }

    /// A constant image gives the constant environment's radiance in every
    /// direction, for both projections.
    #[test]
    fn constant_image_is_constant_radiance() {
        let wavelengths = SampledWavelengths::sample_visible(0.61);
        let rgb = [0.3, 0.6, 0.9];
        let expected = crate::spectrum::RgbIlluminantSpectrum::new(rgb)
            .unwrap()
            .sample(&wavelengths)
            * 2.0;
        for (projection, size) in [
            (EnvironmentProjection::MitsubaEquirectangular, (6, 5)),
            (EnvironmentProjection::PbrtEqualArea, (4, 4)),
        ] {
            let image = Image::from_pixels(size.0, size.1, vec![rgb; size.0 * size.1]).unwrap();
            let map = EnvironmentMap::from_image(&image, projection, rotated(), 2.0).unwrap();
            let mut random = SeekablePcg::new(9, 0);
            for _ in 0..100 {
                let d = sample_uniform_sphere(Vec2::new(random.next_f32(), random.next_f32()));
                let got = map.radiance(d, &wavelengths);
                for i in 0..crate::spectrum::SPECTRUM_SAMPLE_COUNT {
                    assert!((got[i] - expected[i]).abs() <= 1e-4 * expected[i]);
                }
                // Uniform luminance: the density is 1/4π everywhere.
                assert!((map.pdf(d) * 4.0 * PI - 1.0).abs() < 1e-3);
            }
            let luminance = linear_srgb_luminance(rgb) * 2.0;
            assert!((map.mean_luminance() - luminance).abs() < 1e-4 * luminance);
        }
    }

    #[test]
    fn rejects_bad_images() {
        let image = Image::from_pixels(4, 2, vec![[1.0; 3]; 8]).unwrap();
        assert!(
            EnvironmentMap::from_image(
                &image,
                EnvironmentProjection::MitsubaEquirectangular,
                Affine3A::IDENTITY,
                1.0
            )
            .is_err()
        );
        assert!(
            EnvironmentMap::from_image(
                &image,
                EnvironmentProjection::PbrtEqualArea,
                Affine3A::IDENTITY,
                1.0
            )
            .is_err()
        );
        let nan = Image::from_pixels(2, 3, vec![[f32::NAN; 3]; 6]).unwrap();
        assert!(
            EnvironmentMap::from_image(
                &nan,
                EnvironmentProjection::MitsubaEquirectangular,
                Affine3A::IDENTITY,
                1.0
            )
            .is_err()
        );
    }
}
