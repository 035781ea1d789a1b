//! [`RoughDielectricBsdf`]: a rough interface between two dielectrics,
//! Walter, Marschner, Li and Torrance 2007 ("Microfacet Models for
//! Refraction through Rough Surfaces"): microfacet reflection and refraction
//! with the dielectric Fresnel term, as Mitsuba 3's `roughdielectric` and
//! pbrt-v4's `DielectricBxDF` (rough case).
//!
//! With η' the relative index along the path (η_wi side / η_wo side), the
//! generalised half vector h ∝ wo + η' wi (oriented to +z) and
//! F = F(wo·h):
//!
//! - reflection: f = F D(h) G(wo, wi, h) / (4 |cos θo cos θi|);
//! - transmission: f = (1 − F) D(h) G(wo, wi, h) |wi·h| |wo·h|
//!   / (|cos θi cos θo| (wi·h + wo·h/η')²), divided by η'² for radiance
//!   (the BSDF's adjoint for importance has no such factor; Veach 1997 §5.2).
//!
//! Sampling draws a normal visible from `wo` (Heitz 2018; Heitz and d'Eon
//! 2014), then reflects with probability F and refracts otherwise, so the
//! density is F D_wo(h)/(4|wo·h|) or (1 − F) D_wo(h) |wi·h| / (wi·h + wo·h/η')².

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::flags::{BsdfFlags, TransportMode};
use super::fresnel::fresnel_dielectric;
use super::microfacet::MicrofacetDistribution;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// A rough dielectric interface with relative index η = η_inside /
/// η_outside (the normal points outside) at the hero wavelength.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughDielectricBsdf {
    distribution: MicrofacetDistribution,
    eta: f32,
    dispersive: bool,
}

/// The generalised half vector of a pair of directions, with what both
/// evaluation and density need.
pub(super) struct HalfVector {
    /// The microfacet normal, in the upper hemisphere.
    pub(super) normal: Vec3,
    /// Whether `wi` is on the side of `wo`.
    pub(super) reflection: bool,
    /// The relative index along the path (1 for reflection).
    pub(super) relative_eta: f32,
}

impl RoughDielectricBsdf {
    /// An interface with microfacets `distribution` and relative index `eta`
    /// (> 0, finite; callers validate). A dispersive interface terminates the
    /// secondary wavelengths when it is sampled.
    pub fn new(distribution: MicrofacetDistribution, eta: f32, dispersive: bool) -> Self {
        Self {
            distribution,
            eta,
            dispersive,
        }
    }

    /// The microfacet distribution.
    pub fn distribution(&self) -> &MicrofacetDistribution {
        &self.distribution
    }

    /// The relative index of refraction (inside over outside).
    pub fn eta(&self) -> f32 {
        self.eta
    }

    /// The half vector of `wo` and `wi`, or `None` where no microfacet can
    /// connect them (grazing, the half vector on the wrong side of either).
    pub(super) fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<HalfVector> {
        let (cos_o, cos_i) = (wo.z, wi.z);
        if cos_o == 0.0 || cos_i == 0.0 {
            return None;
        }
        let reflection = cos_o * cos_i > 0.0;
        let relative_eta = if reflection {
            1.0
        } else if cos_o > 0.0 {
            self.eta
        } else {
            1.0 / self.eta
        };
        let half = wo + wi * relative_eta;
        if half.length_squared() == 0.0 {
            return None;
        }
        let mut normal = half.normalize();
        if normal.z < 0.0 {
            normal = -normal;
        }
        if !normal.is_finite() || normal.dot(wi) * cos_i <= 0.0 || normal.dot(wo) * cos_o <= 0.0 {
            return None;
        }
        Some(HalfVector {
            normal,
            reflection,
            relative_eta,
        })
    }

    /// `w` mirrored into the upper hemisphere, where visible normals are
    /// sampled from.
    pub(super) fn upper(w: Vec3) -> Vec3 {
        if w.z < 0.0 { -w } else { w }
    }

    /// f(wo, wi) without the cosine factor, for transport `mode`.
    pub fn evaluate(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        let Some(half) = self.half_vector(wo, wi) else {
            return SampledSpectrum::zero();
        };
        let m = half.normal;
        let d = self.distribution.d(m);
        let g = self.distribution.g(wo, wi, m);
        if d == 0.0 || g == 0.0 {
            return SampledSpectrum::zero();
        }
        let fresnel = fresnel_dielectric(wo.dot(m), self.eta);
        let value = if half.reflection {
            fresnel * d * g / (4.0 * (wo.z * wi.z).abs())
        } else {
            let denominator = wi.dot(m) + wo.dot(m) / half.relative_eta;
            let mut value = (1.0 - fresnel) * d * g * (wi.dot(m) * wo.dot(m)).abs()
                / ((wo.z * wi.z).abs() * denominator * denominator);
            if mode == TransportMode::Radiance {
                value /= half.relative_eta * half.relative_eta;
            }
            value
        };
        SampledSpectrum::splat(value)
    }

    /// The density with which [`Self::sample`] produces `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some(half) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let m = half.normal;
        let visible = self.distribution.visible_normal_pdf(Self::upper(wo), m);
        let fresnel = fresnel_dielectric(wo.dot(m), self.eta);
        if half.reflection {
            fresnel * visible / (4.0 * wo.dot(m).abs())
        } else {
            let denominator = wi.dot(m) + wo.dot(m) / half.relative_eta;
            (1.0 - fresnel) * visible * wi.dot(m).abs() / (denominator * denominator)
        }
    }

    /// Draws a visible microfacet normal with `u`, then reflects
    /// (`u_component` < F) or refracts through it.
    pub fn sample(
        &self,
        wo: Vec3,
        u_component: f32,
        u: [f32; 2],
        wavelengths: &mut SampledWavelengths,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let m = self.distribution.sample_visible_normal(Self::upper(wo), u);
        let cos_o = wo.dot(m);
        let fresnel = fresnel_dielectric(cos_o, self.eta);
        let (wi, flags) = if u_component < fresnel {
            let wi = 2.0 * cos_o * m - wo;
            if wi.z * wo.z <= 0.0 {
                return None;
            }
            (wi, BsdfFlags::REFLECTION | BsdfFlags::GLOSSY)
        } else {
            if self.dispersive {
                wavelengths.terminate_secondary();
            }
            let wi = refract_about(wo, m, self.eta)?;
            if wi.z * wo.z >= 0.0 {
                return None;
            }
            (wi, BsdfFlags::TRANSMISSION | BsdfFlags::GLOSSY)
        };
        let eta = if flags.is_transmissive() {
            if wo.z > 0.0 { self.eta } else { 1.0 / self.eta }
        } else {
            1.0
        };
        Some(BsdfSample {
            wi,
            value: self.evaluate(wo, wi, mode),
            pdf: self.pdf(wo, wi),
            flags,
            eta,
            pdf_is_proportional: false,
        })
    }

    /// Glossy reflection and transmission.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::TRANSMISSION | BsdfFlags::GLOSSY
    }
}

/// Refracts `wo` through the microfacet with normal `m` (upper hemisphere) of
/// an interface with relative index `eta` (below over above); `None` on total
/// internal reflection.
pub(super) fn refract_about(wo: Vec3, m: Vec3, eta: f32) -> Option<Vec3> {
    let mut cos_i = wo.dot(m);
    let (mut normal, mut relative_eta) = (m, eta);
    if cos_i < 0.0 {
        // wo on the back of the microfacet: swap the media.
        normal = -m;
        relative_eta = 1.0 / eta;
        cos_i = -cos_i;
    }
    let sin2_t = (1.0 - cos_i * cos_i).max(0.0) / (relative_eta * relative_eta);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((-wo / relative_eta + (cos_i / relative_eta - cos_t) * normal).normalize())
}
