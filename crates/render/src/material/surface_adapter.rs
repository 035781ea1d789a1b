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
//!
//! Since Mitsuba 3.7.1 (commit `e32d718`, "Improve bump and normal
//! mapping") both adapters also have, on by default:
//! - `flip_invalid_normals`: where the direction towards the camera lies on
//!   different sides of the unperturbed and the perturbed normal, the
//!   perturbed normal is turned by 180° about the unperturbed one (its
//!   tangential components negated, after Schüssler et al. 2017), so that
//!   the camera sees the side it lights;
//! - `use_shadowing_function`: the value is multiplied by the microfacet
//!   shadowing term of Conty Estevez, Lecocq and Stein (Ray Tracing Gems
//!   2019, ch. 12), `G = 2 / (1 + √(1 + α² tan²θ_l))` with `α² = min(tan²θ_n
//!   / 8, 1)`, θ_n the perturbed normal's angle to the unperturbed one and
//!   θ_l the light-side direction's, which softens the terminator.
//!
//! Mitsuba's test references are rendered with both; scenes from Mitsuba
//! files take them from the file (`flip_invalid_normals`,
//! `use_shadowing_function`), pbrt files and built-in scenes go without.
//! The flip makes the frame depend on the camera-side direction, so a
//! light subpath, which samples that direction, samples from the two frames
//! with probability ½ each ([`super::SurfaceBsdf`]).

use glam::{Vec2, Vec3};

use super::bsdf_sample::BsdfSample;
use super::flags::BsdfFlags;
use super::shading_frame::ShadingFrame;
use crate::spectrum::SampledSpectrum;

/// Mitsuba 3.7.1's two options of `bumpmap` and `normalmap` (module
/// docs): on for scenes from Mitsuba files unless the file says otherwise,
/// off elsewhere ([`Default`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct PerturbationOptions {
    /// `flip_invalid_normals`.
    pub flip_invalid_normals: bool,
    /// `use_shadowing_function`.
    pub shadowing_function: bool,
}

impl PerturbationOptions {
    /// Mitsuba 3's defaults (both on).
    pub const MITSUBA: Self = Self {
        flip_invalid_normals: true,
        shadowing_function: true,
    };
}

/// Mask opacity and the unperturbed normal of a [`super::SurfaceBsdf`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceAdapter {
    /// Probability of scattering with the BSDF (1: opaque, 0: invisible).
    pub opacity: f32,
    /// The shading normal before bump or normal mapping (world space), if the
    /// frame was perturbed.
    pub unperturbed_normal: Option<Vec3>,
    /// The unperturbed frame's tangent (world space): the perturbed frames'
    /// tangents are it made orthogonal to their normals.
    pub unperturbed_tangent: Vec3,
    /// The perturbed normal before Mitsuba's flip (world space).
    pub perturbed_normal: Vec3,
    /// Mitsuba's `flip_invalid_normals` (module docs).
    pub flip_invalid_normals: bool,
    /// Mitsuba's `use_shadowing_function` (module docs).
    pub shadowing_function: bool,
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
        unperturbed_tangent: Vec3::ZERO,
        perturbed_normal: Vec3::ZERO,
        flip_invalid_normals: false,
        shadowing_function: false,
    };

    /// Records that `unperturbed` was replaced by `perturbed` (a bump or
    /// normal map) with `options`; an enclosing perturbation's unperturbed
    /// frame is kept.
    pub fn perturb(
        &mut self,
        unperturbed: &ShadingFrame,
        perturbed: &ShadingFrame,
        options: PerturbationOptions,
    ) {
        if self.unperturbed_normal.is_none() {
            self.unperturbed_normal = Some(unperturbed.normal());
            self.unperturbed_tangent = unperturbed.tangent();
        }
        self.perturbed_normal = perturbed.normal();
        self.flip_invalid_normals |= options.flip_invalid_normals;
        self.shadowing_function |= options.shadowing_function;
    }

    /// Opaque and unperturbed: the BSDF as it is (what [`Self::NONE`] says;
    /// the other fields matter only for perturbed frames).
    #[inline]
    pub fn is_none(&self) -> bool {
        self.opacity == 1.0 && self.unperturbed_normal.is_none()
    }

    /// Whether a perturbed frame has either of Mitsuba 3.7.1's options
    /// (otherwise the BSDF takes its frame as it is).
    #[inline]
    pub fn has_mitsuba_options(&self) -> bool {
        self.flip_invalid_normals || self.shadowing_function
    }

    /// Whether the frame depends on the camera-side direction (a perturbed
    /// frame with `flip_invalid_normals`).
    #[inline]
    pub fn flips(&self) -> bool {
        self.flip_invalid_normals && self.unperturbed_normal.is_some()
    }

    /// Whether Mitsuba's flip applies for the camera-side direction
    /// `to_camera`: it lies on different sides of the unperturbed and the
    /// perturbed normal (or in the plane of either).
    #[inline]
    pub fn flipped_for(&self, to_camera: Vec3) -> bool {
        match self.unperturbed_normal {
            Some(normal) if self.flip_invalid_normals => {
                to_camera.dot(normal) * to_camera.dot(self.perturbed_normal) <= 0.0
            }
            _ => false,
        }
    }

    /// The perturbed frame, turned by 180° about the unperturbed normal if
    /// `flipped`, with the unperturbed tangent made orthogonal to its
    /// normal (Mitsuba's construction); `fallback` where that degenerates
    /// or the frame is not perturbed.
    pub fn perturbed_frame(&self, flipped: bool, fallback: ShadingFrame) -> ShadingFrame {
        let Some(unperturbed) = self.unperturbed_normal else {
            return fallback;
        };
        let normal = if flipped {
            2.0 * self.perturbed_normal.dot(unperturbed) * unperturbed - self.perturbed_normal
        } else {
            self.perturbed_normal
        };
        ShadingFrame::from_normal_and_tangent(normal, self.unperturbed_tangent).unwrap_or(fallback)
    }

    /// The shadowing term of `use_shadowing_function` for the light-side
    /// direction `to_light` (1 without it).
    #[inline]
    pub fn shadowing(&self, to_light: Vec3) -> f32 {
        let Some(unperturbed) = self.unperturbed_normal else {
            return 1.0;
        };
        if !self.shadowing_function {
            return 1.0;
        }
        let tan2 = |cosine: f32| {
            let cos2 = cosine * cosine;
            (1.0 - cos2).max(0.0) / cos2
        };
        let alpha2 = (0.125 * tan2(self.perturbed_normal.dot(unperturbed))).min(1.0);
        let value = 2.0 / (1.0 + (1.0 + alpha2 * tan2(to_light.dot(unperturbed))).sqrt());
        if value.is_finite() { value } else { 0.0 }
    }

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
/// `geometric_normal`, and `frame`'s tangent made orthogonal to n' (as for
/// a normal map, and as Mitsuba 3.7.1 builds the flipped frames). Returns
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
    ShadingFrame::from_normal_and_tangent(bumped, frame.tangent()).unwrap_or(*frame)
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
