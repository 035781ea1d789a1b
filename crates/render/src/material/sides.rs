//! One- and two-sided reflectors: Mitsuba 3's opaque BSDFs (conductors,
//! plastics, diffuse) reflect only on the side the normal points to and are
//! black from behind, unless wrapped in `twosided`, which mirrors the
//! directions of the back onto the front. These helpers do that mirroring in
//! the local shading frame.

use glam::Vec3;

/// `direction` mirrored through the tangent plane (z negated).
#[inline]
pub(crate) fn flip_z(direction: Vec3) -> Vec3 {
    Vec3::new(direction.x, direction.y, -direction.z)
}

/// The `wo` a front-only reflector sees: `wo` itself if it is above the
/// surface, its mirror image if it is below and the reflector is two-sided,
/// `None` (black) otherwise. The flag says whether it was mirrored (the
/// sampled `wi` must then be mirrored back).
#[inline]
pub(crate) fn front_side(wo: Vec3, two_sided: bool) -> Option<(Vec3, bool)> {
    if wo.z > 0.0 {
        Some((wo, false))
    } else if wo.z < 0.0 && two_sided {
        Some((flip_z(wo), true))
    } else {
        None
    }
}

/// `wo` and `wi` as a front-only reflector sees them (both above the
/// surface), or `None` where it does not scatter.
#[inline]
pub(crate) fn front_side_pair(wo: Vec3, wi: Vec3, two_sided: bool) -> Option<(Vec3, Vec3)> {
    let (wo, flipped) = front_side(wo, two_sided)?;
    let wi = if flipped { flip_z(wi) } else { wi };
    (wi.z > 0.0).then_some((wo, wi))
}
