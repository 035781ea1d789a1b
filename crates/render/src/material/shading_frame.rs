//! [`ShadingFrame`]: the orthonormal basis in which BSDFs work, with the
//! shading normal as the z axis, and the trigonometric helpers of that local
//! frame.
//!
//! In the local frame a direction `w` has cos θ = `w.z`, and two directions lie
//! on the same side of the surface when their z components have the same sign.
//! Directions always point *away* from the surface (both the outgoing `wo` and
//! the incident `wi`), as in pbrt-v4.

use glam::Vec3;

use super::error::MaterialError;

/// A right-handed orthonormal basis (`tangent`, `bitangent`, `normal`):
/// `tangent × bitangent = normal`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadingFrame {
    tangent: Vec3,
    bitangent: Vec3,
    normal: Vec3,
}

impl ShadingFrame {
    /// The frame around a unit normal, with tangents chosen by the branchless
    /// construction of Duff et al. 2017 ("Building an Orthonormal Basis,
    /// Revisited", JCGT 6(1)), which is continuous everywhere except across
    /// the plane z = 0 and free of the precision loss of Frisvad's original near
    /// n = (0, 0, −1).
    ///
    /// `normal` must have unit length (checked in debug builds); use
    /// [`Self::from_normal`] for unnormalised or untrusted input.
    pub fn from_unit_normal(normal: Vec3) -> Self {
        debug_assert!(
            (normal.length_squared() - 1.0).abs() < 1e-3,
            "normal {normal} is not unit length"
        );
        let sign = 1.0_f32.copysign(normal.z);
        let a = -1.0 / (sign + normal.z);
        let b = normal.x * normal.y * a;
        let tangent = Vec3::new(
            1.0 + sign * normal.x * normal.x * a,
            sign * b,
            -sign * normal.x,
        );
        let bitangent = Vec3::new(b, sign + normal.y * normal.y * a, -normal.y);
        Self {
            tangent,
            bitangent,
            normal,
        }
    }

    /// The frame around `normal` (normalised here). Fails if `normal` is zero,
    /// NaN or infinite.
    pub fn from_normal(normal: Vec3) -> Result<Self, MaterialError> {
        Ok(Self::from_unit_normal(normalise("shading normal", normal)?))
    }

    /// The frame around `normal` whose tangent is `tangent` made orthogonal to
    /// the normal (Gram–Schmidt), e.g. the surface's ∂p/∂u so that anisotropic
    /// BSDFs line up with the texture. If the tangent is (nearly) parallel to
    /// the normal, zero or not finite, the tangent of [`Self::from_unit_normal`]
    /// is used instead. Fails if `normal` is zero, NaN or infinite.
    pub fn from_normal_and_tangent(normal: Vec3, tangent: Vec3) -> Result<Self, MaterialError> {
        let normal = normalise("shading normal", normal)?;
        let projected = tangent - normal * normal.dot(tangent);
        let length = projected.length();
        // Relative threshold: below it the projection has lost most digits.
        if !length.is_finite() || length <= 1e-4 * tangent.length() || length == 0.0 {
            return Ok(Self::from_unit_normal(normal));
        }
        let tangent = projected / length;
        Ok(Self {
            tangent,
            bitangent: normal.cross(tangent),
            normal,
        })
    }

    /// The local x axis (world space).
    pub fn tangent(&self) -> Vec3 {
        self.tangent
    }

    /// The local y axis (world space).
    pub fn bitangent(&self) -> Vec3 {
        self.bitangent
    }

    /// The local z axis (world space): the shading normal.
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// The coordinates of the world-space vector `world` in this frame.
    #[inline]
    pub fn to_local(&self, world: Vec3) -> Vec3 {
        Vec3::new(
            world.dot(self.tangent),
            world.dot(self.bitangent),
            world.dot(self.normal),
        )
    }

    /// The world-space vector with coordinates `local` in this frame.
    #[inline]
    pub fn to_world(&self, local: Vec3) -> Vec3 {
        self.tangent * local.x + self.bitangent * local.y + self.normal * local.z
    }
}

/// cos θ of a local-frame direction: its z component.
#[inline]
pub fn cos_theta(direction: Vec3) -> f32 {
    direction.z
}

/// |cos θ| of a local-frame direction.
#[inline]
pub fn abs_cos_theta(direction: Vec3) -> f32 {
    direction.z.abs()
}

/// Whether two local-frame directions lie strictly on the same side of the
/// surface.
#[inline]
pub fn same_hemisphere(a: Vec3, b: Vec3) -> bool {
    a.z * b.z > 0.0
}

/// `vector` normalised, or [`MaterialError::InvalidDirection`].
fn normalise(what: &'static str, vector: Vec3) -> Result<Vec3, MaterialError> {
    let length = vector.length();
    if vector.is_finite() && length > 0.0 && length.is_finite() {
        Ok(vector / length)
    } else {
        Err(MaterialError::InvalidDirection {
            what,
            vector: vector.to_array(),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn assert_orthonormal_right_handed(frame: &ShadingFrame) {
        let (t, b, n) = (frame.tangent(), frame.bitangent(), frame.normal());
        for axis in [t, b, n] {
            assert!((axis.length() - 1.0).abs() < 1e-5, "{frame:?}");
        }
        assert!(t.dot(b).abs() < 1e-5 && t.dot(n).abs() < 1e-5 && b.dot(n).abs() < 1e-5);
        assert!(
            (t.cross(b) - n).length() < 1e-5,
            "{frame:?} not right-handed"
        );
    }

    #[test]
    fn duff_basis_is_orthonormal_everywhere() {
        // A spiral over the whole sphere, plus the poles and their neighbourhood
        // (where Frisvad's construction breaks down).
        let count = 2000;
        for index in 0..count {
            let z = 1.0 - 2.0 * (index as f32 + 0.5) / count as f32;
            let phi = index as f32 * 2.399_963;
            let radius = (1.0 - z * z).max(0.0).sqrt();
            let normal = Vec3::new(radius * phi.cos(), radius * phi.sin(), z);
            assert_orthonormal_right_handed(&ShadingFrame::from_unit_normal(normal.normalize()));
        }
        for normal in [
            Vec3::Z,
            -Vec3::Z,
            Vec3::X,
            Vec3::new(1e-7, -1e-7, -1.0).normalize(),
            Vec3::new(-3e-4, 2e-4, -1.0).normalize(),
            Vec3::new(0.0, 0.0, -0.0),
        ] {
            if normal.length() == 0.0 {
                assert!(ShadingFrame::from_normal(normal).is_err());
                continue;
            }
            assert_orthonormal_right_handed(&ShadingFrame::from_unit_normal(normal));
        }
    }

    #[test]
    fn local_and_world_are_inverse() {
        let frame = ShadingFrame::from_normal(Vec3::new(0.3, -0.5, 0.8)).unwrap();
        let world = Vec3::new(0.1, 0.7, -0.2);
        assert!((frame.to_world(frame.to_local(world)) - world).length() < 1e-6);
        assert!((frame.to_local(frame.normal()) - Vec3::Z).length() < 1e-6);
        let local = frame.to_local(world);
        assert!((local.z - world.dot(frame.normal())).abs() < 1e-7);
    }

    #[test]
    fn tangent_is_kept_when_valid() {
        let normal = Vec3::new(0.0, 0.0, 2.0);
        let frame =
            ShadingFrame::from_normal_and_tangent(normal, Vec3::new(1.0, 0.0, 0.5)).unwrap();
        assert_eq!(frame.tangent(), Vec3::X);
        assert_eq!(frame.bitangent(), Vec3::Y);
        assert_orthonormal_right_handed(&frame);
        // A tangent parallel to the normal falls back to the Duff basis.
        let fallback = ShadingFrame::from_normal_and_tangent(normal, Vec3::Z).unwrap();
        assert_eq!(fallback, ShadingFrame::from_unit_normal(Vec3::Z));
        let nan = ShadingFrame::from_normal_and_tangent(normal, Vec3::NAN).unwrap();
        assert_orthonormal_right_handed(&nan);
    }

    #[test]
    fn bad_normals_are_rejected() {
        assert!(ShadingFrame::from_normal(Vec3::ZERO).is_err());
        assert!(ShadingFrame::from_normal(Vec3::new(f32::NAN, 0.0, 1.0)).is_err());
        assert!(ShadingFrame::from_normal(Vec3::new(f32::INFINITY, 0.0, 1.0)).is_err());
        assert!(ShadingFrame::from_normal_and_tangent(Vec3::ZERO, Vec3::X).is_err());
    }

    #[test]
    fn hemisphere_helpers() {
        let up = Vec3::new(0.6, 0.0, 0.8);
        let down = Vec3::new(0.0, 0.6, -0.8);
        assert_eq!(cos_theta(down), -0.8);
        assert_eq!(abs_cos_theta(down), 0.8);
        assert!(same_hemisphere(up, up));
        assert!(!same_hemisphere(up, down));
        assert!(!same_hemisphere(up, Vec3::X));
    }
}
