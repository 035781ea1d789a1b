//! What the material adapters of Mitsuba 3 (`mask`, `bumpmap`, `normalmap`)
//! add to a placed BSDF ([`SurfaceAdapter`]), and the perturbed shading
//! frames of bump and normal mapping ([`bump_mapped_frame`],
//! [`normal_mapped_frame`]).
//!
//! # Mask
//! With opacity α the surface scatters with the nested BSDF with
//! probability α and otherwise lets light through unchanged. The
//! pass-through is a delta lobe (specular transmission, η = 1) chosen with
//! the component sample: `u < α` picks the nested BSDF (with `u / α` passed
//! on as its component sample), else the ray continues along `−wo` with
//! weight 1. Evaluation and density are α times the nested ones, so
//! next-event estimation and MIS see only the nested part; paths through
//! the mask are found by BSDF sampling (as in Mitsuba 3, whose `null` flag
//! counts as a delta lobe).
//!
//! # Perturbed frames
//! Bump and normal mapping replace the shading frame. A direction is then
//! only scattered into if it lies on the same side of the perturbed and of
//! the unperturbed shading normal (Mitsuba 3's check), which keeps light
//! from leaking through the surface where the tilted normal leans past it.

use glam::{Vec2, Vec3};

use super::bsdf_sample::BsdfSample;
use super::flags::BsdfFlags;
use super::shading_frame::ShadingFrame;
use crate::spectrum::SampledSpectrum;

/// Mask opacity and the unperturbed normal of a [`super::SurfaceBsdf`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceAdapter {
    /// Probability of scattering with the BSDF (1: opaque, 0: invisible).
    pub opacity: f32,
    /// The shading normal before bump or normal mapping (world space), if the
    /// frame was perturbed.
    pub unperturbed_normal: Option<Vec3>,
}

impl Default for SurfaceAdapter {
    fn default() -> Self {
        Self::NONE
    }
}

impl SurfaceAdapter {
    /// Opaque, unperturbed: the BSDF as it is.
    pub const NONE: SurfaceAdapter = SurfaceAdapter {
        opacity: 1.0,
        unperturbed_normal: None,
    };

    /// Whether world direction `wi` (local `wi_local`) is on the same side of
    /// the unperturbed and the perturbed normal.
    #[inline]
    pub fn sides_agree(&self, wi_world: Vec3, wi_local: Vec3) -> bool {
        match self.unperturbed_normal {
            Some(normal) => wi_world.dot(normal) * wi_local.z > 0.0,
            None => true,
        }
    }

    /// Whether the mask lets some light through.
    #[inline]
    pub fn passes_through(&self) -> bool {
        self.opacity < 1.0
    }

    /// The flags of the masked BSDF whose own flags are `flags`.
    pub fn flags(&self, flags: BsdfFlags) -> BsdfFlags {
        let pass_through = BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR;
        if self.opacity <= 0.0 {
            pass_through
        } else if self.passes_through() {
            flags | pass_through
        } else {
            flags
        }
    }

    /// The component sample for the nested BSDF, or `None` when `u_component`
    /// chooses the pass-through lobe.
    #[inline]
    pub fn nested_component_sample(&self, u_component: f32) -> Option<f32> {
        if !self.passes_through() {
            Some(u_component)
        } else if u_component < self.opacity {
            Some((u_component / self.opacity).min(1.0 - f32::EPSILON / 2.0))
        } else {
            None
        }
    }

    /// The pass-through sample for local `wo`: `wi = −wo`, chosen with
    /// probability 1 − α, weight 1 (`None` for a grazing `wo`).
    pub fn pass_through_sample(&self, wo_local: Vec3) -> Option<BsdfSample> {
        let probability = 1.0 - self.opacity;
        let cosine = wo_local.z.abs();
        if cosine == 0.0 || probability <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wi: -wo_local,
            value: SampledSpectrum::splat(probability / cosine),
            pdf: probability,
            flags: BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }
}

/// The shading frame of a bump map (Mitsuba 3's `bumpmap`): with `gradient`
/// = scale · (∂h/∂u, ∂h/∂v) of the height field and `frame`'s normal n, the
/// displaced surface's derivatives are ∂p/∂u' = ∂p/∂u + n (∂h/∂u − n·∂p/∂u)
/// and likewise for v, its normal n' = ∂p/∂u' × ∂p/∂v' turned to the side of
/// `geometric_normal`, and the tangent ∂p/∂u made orthogonal to n'. Returns
/// `frame` where the construction degenerates.
pub fn bump_mapped_frame(
    frame: &ShadingFrame,
    geometric_normal: Vec3,
    dpdu: Vec3,
    dpdv: Vec3,
    gradient: Vec2,
) -> ShadingFrame {
    let normal = frame.normal();
    let displaced_dpdu = dpdu + normal * (gradient.x - normal.dot(dpdu));
    let displaced_dpdv = dpdv + normal * (gradient.y - normal.dot(dpdv));
    let mut bumped = displaced_dpdu.cross(displaced_dpdv);
    if bumped.dot(geometric_normal) < 0.0 {
        bumped = -bumped;
    }
    ShadingFrame::from_normal_and_tangent(bumped, dpdu).unwrap_or(*frame)
}

/// The shading frame of a normal map (Mitsuba 3's `normalmap`): `rgb` in
/// [0, 1]³ encodes the tangent-space normal 2·rgb − 1 in `frame` (x along
/// the tangent, z along the normal); the tangent is ∂p/∂u made orthogonal to
/// the new normal (`frame`'s tangent is ∂p/∂u made orthogonal to the old
/// one). RGB (½, ½, 1) leaves the frame as it is. Returns `frame`
/// where the construction degenerates (a zero normal).
pub fn normal_mapped_frame(frame: &ShadingFrame, rgb: Vec3) -> ShadingFrame {
    let tangent_space = rgb * 2.0 - Vec3::ONE;
    let normal = frame.to_world(tangent_space);
    ShadingFrame::from_normal_and_tangent(normal, frame.tangent()).unwrap_or(*frame)
}
