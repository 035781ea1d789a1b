//! [`TexelLookup`]: where a texture coordinate falls in an image — which
//! texels a lookup reads and with which weights — for nearest and bilinear
//! filtering and the repeat, mirror and clamp wrap modes.
//!
//! Conventions (those of Mitsuba 3's `bitmap` texture, checked numerically
//! against it by `scripts/texture_reference.py`): the transformed coordinate
//! `(u, v)` = `to_uv(uv)` puts (0, 0) at the top-left corner of the image
//! and (1, 1) at the bottom-right; texel `(x, y)` covers
//! `[x/W, (x+1)/W) × [y/H, (y+1)/H)` and its value sits at the centre.
//! Nearest filtering reads texel `(⌊uW⌋, ⌊vH⌋)`; bilinear interpolates the
//! four texels around `(uW − ½, vH − ½)`. Texel indices outside the image
//! wrap: repeat takes them modulo the size, clamp to the edge, mirror
//! reflects every other copy (index `i` of period `2W` maps to `2W − 1 − i`
//! in the second half).

use glam::{Affine2, Vec2};

/// How texture lookups between texels are filtered.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureFilter {
    /// The nearest texel.
    Nearest,
    /// Bilinear interpolation of the four nearest texels (the default).
    Bilinear,
}

/// What a texture lookup outside [0, 1]² does.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TextureWrap {
    /// Tile the image (the default).
    Repeat,
    /// Tile with every other copy mirrored.
    Mirror,
    /// Clamp to the edge texels.
    Clamp,
}

/// How one image is addressed: size, filter, wrap mode and uv transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexelLookup {
    /// Width in texels (≥ 1).
    pub width: usize,
    /// Height in texels (≥ 1).
    pub height: usize,
    /// Nearest or bilinear.
    pub filter: TextureFilter,
    /// What indices outside the image do.
    pub wrap: TextureWrap,
    /// Maps the surface's uv to the image's.
    pub to_uv: Affine2,
}

/// The texels a lookup reads: up to four `(texel index, weight)` pairs whose
/// weights sum to 1.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TexelFootprint {
    /// Row-major texel indices (`y · width + x`).
    pub texels: [usize; 4],
    /// Their weights.
    pub weights: [f32; 4],
    /// How many of the pairs are used (1 or 4).
    pub count: usize,
}

/// Wraps a texel index into `0..size`.
fn wrap_index(index: i64, size: usize, wrap: TextureWrap) -> usize {
    let size = size as i64;
    let wrapped = match wrap {
        TextureWrap::Repeat => index.rem_euclid(size),
        TextureWrap::Clamp => index.clamp(0, size - 1),
        TextureWrap::Mirror => {
            let period = index.rem_euclid(2 * size);
            if period >= size {
                2 * size - 1 - period
            } else {
                period
            }
        }
    };
    wrapped as usize
}

/// `⌊x⌋` as an integer, saturating for huge or NaN inputs (NaN gives 0).
fn floor_index(x: f32) -> i64 {
    if x.is_nan() { 0 } else { x.floor() as i64 }
}

impl TexelLookup {
    /// The image coordinate `to_uv(uv)`.
    pub fn image_uv(&self, uv: Vec2) -> Vec2 {
        self.to_uv.transform_point2(uv)
    }

    /// The row-major index of texel `(x, y)` after wrapping.
    fn index(&self, x: i64, y: i64) -> usize {
        wrap_index(y, self.height, self.wrap) * self.width + wrap_index(x, self.width, self.wrap)
    }

    /// Bilinear corner (x₀, y₀) and fractional weights for image coordinate `st`.
    fn bilinear_corner(&self, st: Vec2) -> (i64, i64, f32, f32) {
        let x = st.x * self.width as f32 - 0.5;
        let y = st.y * self.height as f32 - 0.5;
        let (x0, y0) = (floor_index(x), floor_index(y));
        let fx = if x.is_finite() { x - x0 as f32 } else { 0.0 };
        let fy = if y.is_finite() { y - y0 as f32 } else { 0.0 };
        (x0, y0, fx, fy)
    }

    /// The texels and weights of a lookup at surface uv `uv`.
    pub fn footprint(&self, uv: Vec2) -> TexelFootprint {
        let st = self.image_uv(uv);
        match self.filter {
            TextureFilter::Nearest => {
                let x = floor_index(st.x * self.width as f32);
                let y = floor_index(st.y * self.height as f32);
                TexelFootprint {
                    texels: [self.index(x, y), 0, 0, 0],
                    weights: [1.0, 0.0, 0.0, 0.0],
                    count: 1,
                }
            }
            TextureFilter::Bilinear => {
                let (x0, y0, fx, fy) = self.bilinear_corner(st);
                TexelFootprint {
                    texels: [
                        self.index(x0, y0),
                        self.index(x0 + 1, y0),
                        self.index(x0, y0 + 1),
                        self.index(x0 + 1, y0 + 1),
                    ],
                    weights: [
                        (1.0 - fx) * (1.0 - fy),
                        fx * (1.0 - fy),
                        (1.0 - fx) * fy,
                        fx * fy,
                    ],
                    count: 4,
                }
            }
        }
    }

    /// The gradient with respect to the surface's uv of the bilinear
    /// interpolant of `value` (one scalar per texel) at `uv`: the exact
    /// derivative of the interpolation within the texel cell, mapped back
    /// through the linear part of `to_uv` (as Mitsuba 3's `eval_1_grad`).
    /// Zero for nearest filtering, which is piecewise constant.
    pub fn gradient(&self, uv: Vec2, value: impl Fn(usize) -> f32) -> Vec2 {
        if self.filter == TextureFilter::Nearest {
            return Vec2::ZERO;
        }
        let (x0, y0, fx, fy) = self.bilinear_corner(self.image_uv(uv));
        let f00 = value(self.index(x0, y0));
        let f10 = value(self.index(x0 + 1, y0));
        let f01 = value(self.index(x0, y0 + 1));
        let f11 = value(self.index(x0 + 1, y0 + 1));
        // Derivatives with respect to the image coordinate (s, t) ∈ [0, 1]².
        let d_ds = ((1.0 - fy) * (f10 - f00) + fy * (f11 - f01)) * self.width as f32;
        let d_dt = ((1.0 - fx) * (f01 - f00) + fx * (f11 - f10)) * self.height as f32;
        // Chain rule: ∂f/∂uv = Jᵀ ∂f/∂st with J the linear part of to_uv.
        self.to_uv.matrix2.transpose() * Vec2::new(d_ds, d_dt)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn wrap_modes() {
        let repeat: Vec<usize> = (-3..7)
            .map(|i| wrap_index(i, 3, TextureWrap::Repeat))
            .collect();
        assert_eq!(repeat, [0, 1, 2, 0, 1, 2, 0, 1, 2, 0]);
        let clamp: Vec<usize> = (-2..5)
            .map(|i| wrap_index(i, 3, TextureWrap::Clamp))
            .collect();
        assert_eq!(clamp, [0, 0, 0, 1, 2, 2, 2]);
        let mirror: Vec<usize> = (-3..9)
            .map(|i| wrap_index(i, 3, TextureWrap::Mirror))
            .collect();
        assert_eq!(mirror, [2, 1, 0, 0, 1, 2, 2, 1, 0, 0, 1, 2]);
    }
}
