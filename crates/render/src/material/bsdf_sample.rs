//! [`BsdfSample`]: the outcome of importance-sampling a BSDF.

use glam::Vec3;

use super::flags::BsdfFlags;
use crate::spectrum::SampledSpectrum;

/// A sampled incident direction with the BSDF value and density there.
///
/// The Monte Carlo weight of the sample is `value · |cos θi| / pdf`. For a
/// specular (delta) lobe `value` and `pdf` are both "per delta": their ratio is
/// meaningful, each alone is not (pdf is the discrete probability of choosing
/// the lobe, as in pbrt-v4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BsdfSample {
    /// The incident direction (local frame, unit length, pointing away from
    /// the surface).
    pub wi: Vec3,
    /// The BSDF value f(wo, wi) (without the cosine factor).
    pub value: SampledSpectrum,
    /// The density of `wi` per unit solid angle (or the lobe's discrete
    /// probability for a specular lobe).
    pub pdf: f32,
    /// The sampled lobe: reflection or transmission, and its kind.
    pub flags: BsdfFlags,
    /// The relative index of refraction η_t/η_i along the path for a
    /// transmission, 1 otherwise. Path tracers track the product of these to
    /// undo the η² radiance scaling in Russian roulette (pbrt-v4 §14.1).
    pub eta: f32,
    /// Whether `pdf` is only proportional to the true density (for stochastic
    /// BSDFs such as layered ones, which cannot be used with MIS). Always
    /// false for the BSDFs of this module.
    pub pdf_is_proportional: bool,
}

impl BsdfSample {
    /// Whether the sampled lobe is a Dirac delta.
    pub fn is_specular(&self) -> bool {
        self.flags.is_specular()
    }

    /// Whether `wi` is on the same side as `wo`.
    pub fn is_reflection(&self) -> bool {
        self.flags.is_reflective()
    }

    /// Whether `wi` crossed the surface.
    pub fn is_transmission(&self) -> bool {
        self.flags.is_transmissive()
    }

    /// Whether the sample carries light: a positive density, a non-black
    /// value and a `wi` off the tangent plane (local frame). Samples failing
    /// this are reported as no scattering, as pbrt-v4 does.
    #[inline]
    pub fn scatters(&self) -> bool {
        self.pdf != 0.0 && !self.value.is_black() && self.wi.z != 0.0
    }

    /// The sample's Monte Carlo weight f · |cos θi| / pdf (0 if pdf is 0).
    pub fn weight(&self) -> SampledSpectrum {
        (self.value * self.wi.z.abs()).safe_div_scalar(self.pdf)
    }
}
