//! Participating media: homogeneous media with spectral absorption and
//! scattering ([`HomogeneousMedium`]), phase functions ([`PhaseFunction`]),
//! transmittance, and the bookkeeping of which medium a ray travels in
//! ([`MediumInterface`]).
//!
//! # Medium tracking
//!
//! A ray starts in the camera's medium (the scene's camera medium; `None`
//! is vacuum). A shape whose description names an interior or
//! exterior medium is a *medium transition*: a ray leaving one of its
//! surface points in direction `d` travels in the exterior medium if `d`
//! points to the side of the shape's (oriented, i.e. after `flip_normals`)
//! geometric normal, else in the interior one, whether it was reflected or
//! transmitted. A medium not named is vacuum. Crossing a shape that names no
//! medium keeps the current one. This is the rule of Mitsuba 3
//! (`SurfaceInteraction::target_medium`) and pbrt-v4 (`MediumInterface`).
//!
//! Index-matched boundaries (Mitsuba `null`, pbrt `interface`) are shapes
//! the scene marks as interfaces: rays pass straight
//! through them (only the medium changes) and they are not path vertices.

mod homogeneous;
mod phase;

pub use homogeneous::{HomogeneousMedium, MediumProperties, MediumSpectra, transmittance};
pub use phase::{PhaseFunction, PhaseSample};

use glam::Vec3;

/// The media on the two sides of a shape that is a medium transition, as
/// indices into the scene's list of media (`None`: vacuum).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct MediumInterface {
    /// The medium on the side opposite the oriented normal.
    pub interior: Option<u32>,
    /// The medium on the side the oriented normal points to.
    pub exterior: Option<u32>,
}

impl MediumInterface {
    /// The medium a ray leaving the surface in `direction` enters, given the
    /// surface's oriented geometric normal.
    #[inline]
    pub fn target(&self, oriented_normal: Vec3, direction: Vec3) -> Option<u32> {
        if direction.dot(oriented_normal) > 0.0 {
            self.exterior
        } else {
            self.interior
        }
    }
}

/// The medium after leaving a surface in `direction`: the transition's
/// target medium, or `current` for a shape that is no transition.
#[inline]
pub fn medium_after(
    interface: Option<&MediumInterface>,
    oriented_normal: Vec3,
    direction: Vec3,
    current: Option<u32>,
) -> Option<u32> {
    match interface {
        Some(interface) => interface.target(oriented_normal, direction),
        None => current,
    }
}
