//! Axis-aligned bounding boxes.

use glam::{Vec3, Vec3A};

/// An axis-aligned box `[min, max]`. The empty box has `min = +inf`, `max = -inf`
/// so that any union with a point or box yields that point or box.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds3 {
    /// Lower corner.
    pub min: Vec3,
    /// Upper corner.
    pub max: Vec3,
}

impl Default for Bounds3 {
    fn default() -> Self {
        Self::EMPTY
    }
}

impl Bounds3 {
    /// The empty box (identity of [`Bounds3::union`]).
    pub const EMPTY: Self = Self {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    /// The box spanned by two corners given in any order.
    pub fn new(a: Vec3, b: Vec3) -> Self {
        Self {
            min: a.min(b),
            max: a.max(b),
        }
    }

    /// The smallest box containing all `points` (empty if there are none).
    pub fn from_points(points: impl IntoIterator<Item = Vec3>) -> Self {
        points.into_iter().fold(Self::EMPTY, |b, p| b.including(p))
    }

    /// Whether the box contains no point.
    pub fn is_empty(&self) -> bool {
        self.min.cmpgt(self.max).any()
    }

    /// This box grown to contain `point`.
    pub fn including(self, point: Vec3) -> Self {
        Self {
            min: self.min.min(point),
            max: self.max.max(point),
        }
    }

    /// The smallest box containing both boxes.
    pub fn union(self, other: Self) -> Self {
        Self {
            min: self.min.min(other.min),
            max: self.max.max(other.max),
        }
    }

    /// Whether `point` lies inside or on the boundary.
    pub fn contains(&self, point: Vec3) -> bool {
        point.cmpge(self.min).all() && point.cmple(self.max).all()
    }

    /// `max - min`.
    pub fn diagonal(&self) -> Vec3 {
        self.max - self.min
    }

    /// The centre of the box.
    pub fn centroid(&self) -> Vec3 {
        0.5 * (self.min + self.max)
    }

    /// Surface area (0 for an empty box).
    pub fn surface_area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let d = self.diagonal();
        2.0 * (d.x * d.y + d.y * d.z + d.z * d.x)
    }

    /// A sphere (centre, radius) enclosing the box, as pbrt's `BoundingSphere`.
    pub fn bounding_sphere(&self) -> (Vec3, f32) {
        let centre = self.centroid();
        let radius = if self.is_empty() {
            0.0
        } else {
            centre.distance(self.max)
        };
        (centre, radius)
    }

    /// The box in obvhs' representation.
    pub(crate) fn to_aabb(self) -> obvhs::aabb::Aabb {
        obvhs::aabb::Aabb::new(Vec3A::from(self.min), Vec3A::from(self.max))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn union_and_contains() {
        let b = Bounds3::from_points([Vec3::ZERO, Vec3::new(1.0, 2.0, 3.0)]);
        assert!(b.contains(Vec3::new(0.5, 1.0, 1.5)));
        assert!(!b.contains(Vec3::new(-0.1, 1.0, 1.5)));
        assert_eq!(b.surface_area(), 2.0 * (2.0 + 6.0 + 3.0));
        assert!(Bounds3::EMPTY.is_empty());
        assert_eq!(Bounds3::EMPTY.union(b), b);
    }
}
