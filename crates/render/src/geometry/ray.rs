//! A semi-infinite ray `origin + t * direction`, `t >= 0`, with a time for motion blur.

use glam::Vec3;

/// A ray `origin + t * direction` (`t >= 0`). The direction is not required to be
/// unit length by the type, but the scene queries expect it to be (see
/// [`crate::geometry`]); `time` is carried for cameras with shutters and is
/// otherwise ignored by the static geometry.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Which way it goes.
    pub direction: Vec3,
    /// The instant the ray exists at (seconds within the shutter interval).
    pub time: f32,
}

impl Ray {
    /// A ray at time 0.
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        Self {
            origin,
            direction,
            time: 0.0,
        }
    }

    /// A ray at a given time.
    pub fn with_time(origin: Vec3, direction: Vec3, time: f32) -> Self {
        Self {
            origin,
            direction,
            time,
        }
    }

    /// The point at parameter `t`.
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.direction
    }
}
