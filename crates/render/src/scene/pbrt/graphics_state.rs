//! pbrt-v4's graphics state: what `AttributeBegin` saves and `AttributeEnd`
//! restores: the current transformation matrix (CTM), `ReverseOrientation`,
//! the current material, the area light that shapes become, and the media
//! on either side of shapes. Named materials, textures, media, objects and
//! coordinate systems are not part of it (pbrt-v4 keeps them global).

use super::parameters::Position;
use crate::scene::description::{MaterialDescription, SpectrumDescription, TextureDescription};
use glam::{Affine3A, DMat3, DMat4, DVec3, Vec3};

/// The material that `Shape`s get.
#[derive(Debug, Clone, PartialEq)]
pub enum CurrentMaterial {
    /// From `Material` (or pbrt's default, diffuse with reflectance 0.5).
    Anonymous(Box<MaterialDescription>),
    /// From `NamedMaterial`, resolved when a shape uses it.
    Named { name: String, position: Position },
}

/// An `AreaLightSource "diffuse"` waiting for shapes.
#[derive(Debug, Clone, PartialEq)]
pub struct AreaLight {
    /// The emitted radiance before `scale` and `power` (`L`).
    pub radiance: SpectrumDescription,
    /// `scale` divided by the spectrum's luminance where pbrt normalises.
    pub scale: f32,
    /// `power`: the light's total emitted power, if given.
    pub power: Option<f32>,
    pub two_sided: bool,
    pub position: Position,
}

/// The state `AttributeBegin`/`AttributeEnd` save and restore.
#[derive(Debug, Clone, PartialEq)]
pub struct GraphicsState {
    /// The current transformation matrix: from the coordinates that follow to
    /// world space (before `WorldBegin`: to camera space).
    pub ctm: DMat4,
    pub reverse_orientation: bool,
    pub material: CurrentMaterial,
    pub area_light: Option<AreaLight>,
    /// `MediumInterface` names: inside and outside of shapes.
    pub inside_medium: Option<String>,
    pub outside_medium: Option<String>,
}

impl Default for GraphicsState {
    /// pbrt-v4's initial state: identity CTM, diffuse material of reflectance 0.5.
    fn default() -> Self {
        Self {
            ctm: DMat4::IDENTITY,
            reverse_orientation: false,
            material: CurrentMaterial::Anonymous(Box::new(default_material())),
            area_light: None,
            inside_medium: None,
            outside_medium: None,
        }
    }
}

/// pbrt-v4's default material: `diffuse` with reflectance 0.5.
pub fn default_material() -> MaterialDescription {
    MaterialDescription::Diffuse {
        reflectance: TextureDescription::Constant(SpectrumDescription::Constant(0.5)),
        two_sided: true,
    }
}

/// A transform and the quantities shapes need from it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShapeTransform {
    pub matrix: DMat4,
}

impl ShapeTransform {
    /// A point.
    pub fn point(&self, p: [f32; 3]) -> Vec3 {
        self.matrix
            .transform_point3(DVec3::new(p[0] as f64, p[1] as f64, p[2] as f64))
            .as_vec3()
    }

    /// A normal (by the inverse transpose), not normalised.
    pub fn normal(&self, n: [f32; 3]) -> Vec3 {
        let linear = DMat3::from_mat4(self.matrix);
        (linear.inverse().transpose() * DVec3::new(n[0] as f64, n[1] as f64, n[2] as f64)).as_vec3()
    }

    /// Whether the transform mirrors (its linear part has a negative determinant).
    pub fn swaps_handedness(&self) -> bool {
        DMat3::from_mat4(self.matrix).determinant() < 0.0
    }

    /// As a single-precision affine map (the projective row is dropped).
    pub fn affine(&self) -> Affine3A {
        Affine3A::from_mat4(self.matrix.as_mat4())
    }
}

/// pbrt-v4's `LookAt`: the camera-from-world matrix of an eye at `eye`
/// looking at `target`, with `up` projected to the image's up. The frame is
/// left-handed: right = normalize(up × view direction) (pbrt-v4's file-format
/// reference and book, Section 3.9).
pub fn look_at(eye: DVec3, target: DVec3, up: DVec3) -> Option<DMat4> {
    let direction = (target - eye).try_normalize()?;
    let right = up.try_normalize()?.cross(direction).try_normalize()?;
    let new_up = direction.cross(right);
    let world_from_camera = DMat4::from_cols(
        right.extend(0.0),
        new_up.extend(0.0),
        direction.extend(0.0),
        eye.extend(1.0),
    );
    Some(world_from_camera.inverse())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn look_at_maps_the_eye_to_the_origin_and_the_target_to_plus_z() {
        let camera_from_world = look_at(
            DVec3::new(0.0, 0.0, 5.0),
            DVec3::ZERO,
            DVec3::new(0.0, 1.0, 0.0),
        )
        .unwrap();
        let eye = camera_from_world.transform_point3(DVec3::new(0.0, 0.0, 5.0));
        assert!(eye.length() < 1e-12);
        let target = camera_from_world.transform_point3(DVec3::ZERO);
        assert!((target - DVec3::new(0.0, 0.0, 5.0)).length() < 1e-12);
        // pbrt's left-handed camera: world +x appears on the image's left
        // (camera −x) for a camera on +z looking down −z with +y up.
        let x = camera_from_world.transform_vector3(DVec3::X);
        assert!((x - DVec3::new(-1.0, 0.0, 0.0)).length() < 1e-12);
        let y = camera_from_world.transform_vector3(DVec3::Y);
        assert!((y - DVec3::Y).length() < 1e-12);
    }

    #[test]
    fn look_at_rejects_degenerate_input() {
        assert!(look_at(DVec3::ZERO, DVec3::ZERO, DVec3::Y).is_none());
        assert!(look_at(DVec3::ZERO, DVec3::Y, DVec3::Y).is_none());
    }

    #[test]
    fn normals_follow_the_inverse_transpose() {
        let transform = ShapeTransform {
            matrix: DMat4::from_scale(DVec3::new(2.0, 1.0, 1.0)),
        };
        let n = transform.normal([1.0, 1.0, 0.0]);
        assert!((n - Vec3::new(0.5, 1.0, 0.0)).length() < 1e-6);
        assert!(!transform.swaps_handedness());
        let mirror = ShapeTransform {
            matrix: DMat4::from_scale(DVec3::new(1.0, 1.0, -1.0)),
        };
        assert!(mirror.swaps_handedness());
    }
}
