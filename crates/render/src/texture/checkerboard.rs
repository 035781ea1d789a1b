//! [`Checkerboard`]: two textures in alternating unit squares of the
//! transformed uv.
//!
//! Square `(⌊s⌋, ⌊t⌋)` of `(s, t)` = `to_uv(uv)` shows `even` when
//! `⌊s⌋ + ⌊t⌋` is even (pbrt-v4's `checkerboard`: `tex1` there). Mitsuba 3's
//! `checkerboard` has squares of side ½ in its transformed uv with `color0`
//! in the square at the origin, so its loader maps it to `even = color0`,
//! `odd = color1` and a `to_uv` scaled by 2 after Mitsuba's own (checked
//! against Mitsuba by `scripts/texture_reference.py`).

use glam::{Affine2, Vec2};

/// Alternating squares of two textures of the same kind.
#[derive(Debug, Clone, PartialEq)]
pub struct Checkerboard<T> {
    /// The texture of the squares with an even index sum (the one at the origin).
    pub even: T,
    /// The texture of the other squares.
    pub odd: T,
    /// Maps the surface's uv to the board's (one square per unit).
    pub to_uv: Affine2,
}

impl<T> Checkerboard<T> {
    /// Whether the square containing surface uv `uv` is an even one.
    pub fn is_even(&self, uv: Vec2) -> bool {
        let st = self.to_uv.transform_point2(uv);
        let sum = st.x.floor() + st.y.floor();
        sum.rem_euclid(2.0) == 0.0 || !sum.is_finite()
    }

    /// The texture shown at surface uv `uv`.
    pub fn select(&self, uv: Vec2) -> &T {
        if self.is_even(uv) {
            &self.even
        } else {
            &self.odd
        }
    }
}
