//! [`CoatedDiffuseBsdf`]: pbrt-v4's `coateddiffuse`, a diffuse base under a
//! dielectric coating with an optional scattering medium between them,
//! evaluated stochastically by random walks through the layer (pbrt-v4, 4th
//! ed., §14.3 "Scattering from Layered Surfaces"; implemented from the book's
//! description, not from its code).
//!
//! # The model
//!
//! A slab of optical thickness `thickness` (extinction 1, so light crossing
//! it at cosine μ keeps e^(−thickness/μ)) lies between two interfaces: at its
//! top (z = thickness) a dielectric of relative index η, smooth or rough
//! (Trowbridge–Reitz/GGX, [`super::RoughDielectricBsdf`]), and at its bottom
//! (z = 0) a Lambertian reflector of albedo `reflectance` — or, for
//! `coatedconductor` ([`super::CoatedConductorBsdf`]), a smooth or rough
//! conductor: the walk (`LayeredBsdf`) takes any `LayerBase`. The slab's medium
//! scatters with single-scattering albedo `albedo` and a Henyey–Greenstein
//! phase function of asymmetry `g`; with albedo 0 it only absorbs.
//!
//! No closed form exists, so the three operations are Monte Carlo estimates:
//!
//! - [`CoatedDiffuseBsdf::evaluate`]: f(wo, wi) is the top's reflection plus
//!   the mean over `samples` random walks that enter through the top towards
//!   wo's side, bounce between base, coating and medium (at most
//!   `max_depth` events, Russian roulette after 3) and at every event add
//!   the contribution of leaving towards wi by next-event estimation — once
//!   through a direction sampled from the coating's transmission seen from wi
//!   (for the adjoint transport mode), and, for a rough coating, once through
//!   the direction the walk itself sampled, the two combined with the power
//!   heuristic. The estimate is unbiased; its mean is the layered BSDF.
//!   Two corrections to pbrt-v4's text make it so: the power heuristic of
//!   the walk's own exit weighs the walk's density of the inside direction
//!   against the presampled exit's density of the same inside direction
//!   (pbrt-v4 takes the coating's density of wi given the inside direction,
//!   a density of another variable, and its rough coatings come out a few
//!   per cent off: see `LayeredBsdf::exit_weight`); and with a smooth
//!   coating over a delta base a medium scattering event also adds the
//!   delta chains towards wi that no walk can reach
//!   (`LayeredBsdf::delta_chain`; pbrt-v4 drops them).
//! - [`CoatedDiffuseBsdf::sample`]: samples the coating; a reflection is
//!   returned as is, a transmission starts a walk that follows the sampled
//!   interactions until it leaves through the top. The returned `value` and
//!   `pdf` are the walk's path throughput and path density: their ratio is
//!   an unbiased weight, but `pdf` is not the density of `wi`
//!   ([`BsdfSample::pdf_is_proportional`] is set; integrators take
//!   [`CoatedDiffuseBsdf::pdf`] for MIS).
//! - [`CoatedDiffuseBsdf::pdf`]: pbrt-v4's approximation of the sampling
//!   density for MIS weights: the coating's reflection density plus a
//!   transmission–reflection–transmission estimate from `samples` walks of one
//!   base bounce, mixed 9 : 1 with a uniform density so that it is never 0
//!   where `wi` can be sampled. It ignores the internal multiple reflections,
//!   so it is not normalised (it serves only as a MIS weight, which needs the
//!   same value from both techniques, not the exact density).
//!
//! # Determinism
//!
//! The walks need many random numbers, more than the sampler's dimension
//! layout gives a vertex. As pbrt-v4 does, each call draws them from its own
//! PCG32 stream ([`qmc::random::SeekablePcg`]) seeded by a hash of the call's
//! inputs — `wo` and `wi` for `evaluate` and `pdf`, `wo` and the sample's
//! numbers for `sample` — never from a global generator. The same query
//! always gives the same estimate, whatever the thread or the order of
//! calls, so images stay deterministic for a seed, and next-event estimation
//! and BSDF sampling see the same MIS density for the same pair of
//! directions.
//!
//! Two-sided: seen from below, both directions are negated (pbrt-v4's coated
//! materials are two-sided). The base is opaque, so there is no transmission.

use glam::Vec3;
use qmc::hash::{hash2, hash3};
use qmc::random::SeekablePcg;

use super::bsdf_sample::BsdfSample;
use super::diffuse::DiffuseBsdf;
use super::flags::{BsdfFlags, TransportMode};
use super::fresnel::{fresnel_dielectric, reflect_about_normal, refract};
use super::microfacet::MicrofacetDistribution;
use super::rough_dielectric::{RoughDielectricBsdf, refract_about};
use super::shading_frame::{abs_cos_theta, same_hemisphere};
use crate::medium::PhaseFunction;
use crate::spectrum::SampledSpectrum;

/// The lobes an interface may sample or give the density of (pbrt-v4's
/// reflection/transmission restriction).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Lobes {
    All,
    Reflection,
    Transmission,
}

impl Lobes {
    fn reflection(self) -> bool {
        self != Lobes::Transmission
    }

    fn transmission(self) -> bool {
        self != Lobes::Reflection
    }
}

/// The adjoint transport mode (radiance ↔ importance).
fn adjoint(mode: TransportMode) -> TransportMode {
    match mode {
        TransportMode::Radiance => TransportMode::Importance,
        TransportMode::Importance => TransportMode::Radiance,
    }
}

/// The dielectric coating: smooth (`distribution` `None`) or rough.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Coating {
    eta: f32,
    distribution: Option<MicrofacetDistribution>,
}

impl Coating {
    fn is_specular(&self) -> bool {
        self.distribution.is_none()
    }

    fn rough(&self) -> Option<RoughDielectricBsdf> {
        self.distribution
            .map(|distribution| RoughDielectricBsdf::new(distribution, self.eta, false))
    }

    /// f(wo, wi) of the rough coating (0 for a smooth one, whose lobes are
    /// deltas).
    fn evaluate(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        match self.rough() {
            Some(rough) => rough.evaluate(wo, wi, mode)[0],
            None => 0.0,
        }
    }

    /// The density of `wi` when sampling only `lobes` (0 for a smooth
    /// coating).
    fn pdf(&self, wo: Vec3, wi: Vec3, lobes: Lobes) -> f32 {
        let Some(rough) = self.rough() else {
            return 0.0;
        };
        let Some(half) = rough.half_vector(wo, wi) else {
            return 0.0;
        };
        let density = rough.pdf(wo, wi);
        let reflectance = fresnel_dielectric(wo.dot(half.normal), self.eta);
        // `density` includes the choice probability F (reflection) or 1 − F
        // (transmission) of unrestricted sampling; restricted sampling
        // chooses among the allowed lobes only.
        match (half.reflection, lobes) {
            (_, Lobes::All) => density,
            (true, Lobes::Reflection) if reflectance > 0.0 => density / reflectance,
            (false, Lobes::Transmission) if reflectance < 1.0 => density / (1.0 - reflectance),
            _ => 0.0,
        }
    }

    /// Samples `wi` among `lobes`.
    fn sample(
        &self,
        wo: Vec3,
        u_component: f32,
        u: [f32; 2],
        mode: TransportMode,
        lobes: Lobes,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        match self.rough() {
            None => self.sample_smooth(wo, u_component, mode, lobes),
            Some(rough) => self.sample_rough(&rough, wo, u_component, u, mode, lobes),
        }
    }

    fn sample_smooth(
        &self,
        wo: Vec3,
        u_component: f32,
        mode: TransportMode,
        lobes: Lobes,
    ) -> Option<BsdfSample> {
        let reflectance = fresnel_dielectric(wo.z, self.eta);
        let reflect_weight = if lobes.reflection() { reflectance } else { 0.0 };
        let transmit_weight = if lobes.transmission() {
            1.0 - reflectance
        } else {
            0.0
        };
        let total = reflect_weight + transmit_weight;
        if total <= 0.0 {
            return None;
        }
        if u_component * total < reflect_weight {
            let wi = reflect_about_normal(wo);
            return Some(BsdfSample {
                wi,
                value: SampledSpectrum::splat(reflectance / abs_cos_theta(wi)),
                pdf: reflect_weight / total,
                flags: BsdfFlags::REFLECTION | BsdfFlags::SPECULAR,
                eta: 1.0,
                pdf_is_proportional: false,
            });
        }
        let refraction = refract(wo, self.eta)?;
        let wi = refraction.direction;
        if wi.z == 0.0 {
            return None;
        }
        let mut value = (1.0 - reflectance) / abs_cos_theta(wi);
        if mode == TransportMode::Radiance {
            value /= refraction.relative_eta * refraction.relative_eta;
        }
        Some(BsdfSample {
            wi,
            value: SampledSpectrum::splat(value),
            pdf: transmit_weight / total,
            flags: BsdfFlags::TRANSMISSION | BsdfFlags::SPECULAR,
            eta: refraction.relative_eta,
            pdf_is_proportional: false,
        })
    }

    fn sample_rough(
        &self,
        rough: &RoughDielectricBsdf,
        wo: Vec3,
        u_component: f32,
        u: [f32; 2],
        mode: TransportMode,
        lobes: Lobes,
    ) -> Option<BsdfSample> {
        let m = rough
            .distribution()
            .sample_visible_normal(RoughDielectricBsdf::upper(wo), u);
        let reflectance = fresnel_dielectric(wo.dot(m), self.eta);
        let reflect_weight = if lobes.reflection() { reflectance } else { 0.0 };
        let transmit_weight = if lobes.transmission() {
            1.0 - reflectance
        } else {
            0.0
        };
        let total = reflect_weight + transmit_weight;
        if total <= 0.0 {
            return None;
        }
        let (wi, flags) = if u_component * total < reflect_weight {
            let wi = 2.0 * wo.dot(m) * m - wo;
            if wi.z * wo.z <= 0.0 {
                return None;
            }
            (wi, BsdfFlags::REFLECTION | BsdfFlags::GLOSSY)
        } else {
            let wi = refract_about(wo, m, self.eta)?;
            if wi.z * wo.z >= 0.0 {
                return None;
            }
            (wi, BsdfFlags::TRANSMISSION | BsdfFlags::GLOSSY)
        };
        let eta = match (flags.is_transmissive(), wo.z > 0.0) {
            (false, _) => 1.0,
            (true, true) => self.eta,
            (true, false) => 1.0 / self.eta,
        };
        Some(BsdfSample {
            wi,
            value: SampledSpectrum::splat(self.evaluate(wo, wi, mode)),
            pdf: self.pdf(wo, wi, lobes),
            flags,
            eta,
            pdf_is_proportional: false,
        })
    }
}

/// A sample that can continue a walk: finite, positive density, non-zero
/// value, off the tangent plane.
fn usable(sample: Option<BsdfSample>) -> Option<BsdfSample> {
    sample.filter(|sample| {
        sample.pdf > 0.0 && sample.pdf.is_finite() && !sample.value.is_black() && sample.wi.z != 0.0
    })
}

/// Transmittance e^(−|Δz / cos θ|) through a slab of optical depth |Δz|
/// (extinction 1) along `w`.
fn transmittance(depth: f32, w: Vec3) -> f32 {
    if depth.abs() <= f32::MIN_POSITIVE {
        return 1.0;
    }
    (-(depth / w.z).abs()).exp()
}

/// The power heuristic (exponent 2) of `own` against `other`.
fn power_heuristic(own: f32, other: f32) -> f32 {
    crate::sampling::MisHeuristic::Power.weight(own, other)
}

/// A 64-bit hash of a direction's bits.
fn direction_hash(w: Vec3) -> u64 {
    hash3(
        u64::from(w.x.to_bits()),
        u64::from(w.y.to_bits()),
        u64::from(w.z.to_bits()),
    )
}

/// Stream selectors, so that evaluate, pdf and sample of the same directions
/// draw independent numbers.
const EVALUATE_STREAM: u64 = 0x6576_616c;
const PDF_STREAM: u64 = 0x7064_6600;
const SAMPLE_STREAM: u64 = 0x7361_6d70;

/// The walk's own uniform numbers in [0, 1), from a hashed PCG32 stream.
struct WalkNumbers(SeekablePcg);

impl WalkNumbers {
    fn new(seed: u64, stream: u64) -> Self {
        Self(SeekablePcg::new(seed, stream))
    }

    fn next(&mut self) -> f32 {
        self.0.next_f32()
    }

    fn next_2d(&mut self) -> [f32; 2] {
        [self.next(), self.next()]
    }
}

/// What lies under the layer: the bottom interface of pbrt-v4's
/// `LayeredBxDF`, an opaque reflector seen from inside the layer (both
/// directions in the upper hemisphere). Implemented by the diffuse base of
/// `coateddiffuse` and the conductor base of `coatedconductor`
/// ([`super::coated_conductor`]).
pub(super) trait LayerBase: Copy {
    /// f(wo, wi) without the cosine factor (0 for a delta lobe).
    fn evaluate(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum;
    /// The density with which [`Self::sample`] produces `wi` (0 for a delta
    /// lobe).
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32;
    /// Samples a reflected direction.
    fn sample(&self, wo: Vec3, u_component: f32, u: [f32; 2]) -> Option<BsdfSample>;
    /// Whether the base reflects only in a delta lobe (no next-event
    /// estimation through it is possible).
    fn is_specular(&self) -> bool;
    /// The base's lobes.
    fn flags(&self) -> BsdfFlags;
    /// The base's effective roughness for LQMC (see [`super::Bsdf::roughness`]).
    fn roughness(&self) -> f32;
}

impl LayerBase for DiffuseBsdf {
    fn evaluate(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        DiffuseBsdf::evaluate(self, wo, wi)
    }

    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        DiffuseBsdf::pdf(self, wo, wi)
    }

    fn sample(&self, wo: Vec3, _u_component: f32, u: [f32; 2]) -> Option<BsdfSample> {
        DiffuseBsdf::sample(self, wo, u)
    }

    fn is_specular(&self) -> bool {
        false
    }

    fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE
    }

    fn roughness(&self) -> f32 {
        1.0
    }
}

/// pbrt-v4's `LayeredBxDF` with a dielectric top and an opaque `base`:
/// the random walks shared by [`CoatedDiffuseBsdf`] and
/// [`super::CoatedConductorBsdf`] (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct LayeredBsdf<B> {
    coating: Coating,
    base: B,
    thickness: f32,
    albedo: SampledSpectrum,
    phase: PhaseFunction,
    max_depth: u32,
    samples: u32,
}

impl<B: LayerBase> LayeredBsdf<B> {
    /// A coating of relative index `eta` (> 0), rough with `distribution`
    /// or smooth for `None`, over `base`, with a layer of optical thickness
    /// `thickness` (clamped to at least the smallest positive f32, as
    /// pbrt-v4 does) whose medium has albedo `albedo` and Henyey–Greenstein
    /// asymmetry `g`; walks of at most `max_depth` (≥ 1) events, `samples`
    /// (≥ 1) walks per call.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn new(
        eta: f32,
        distribution: Option<MicrofacetDistribution>,
        base: B,
        thickness: f32,
        albedo: SampledSpectrum,
        g: f32,
        max_depth: u32,
        samples: u32,
    ) -> Self {
        Self {
            coating: Coating {
                eta,
                distribution: distribution.filter(|d| !d.is_effectively_smooth()),
            },
            base,
            thickness: thickness.max(f32::MIN_POSITIVE),
            albedo,
            phase: PhaseFunction::henyey_greenstein(g),
            max_depth: max_depth.max(1),
            samples: samples.max(1),
        }
    }

    /// The coating's microfacet distribution (`None` if smooth).
    pub(super) fn distribution(&self) -> Option<&MicrofacetDistribution> {
        self.coating.distribution.as_ref()
    }

    /// Whether the coating is smooth.
    #[cfg(test)]
    pub(super) fn coating_is_specular(&self) -> bool {
        self.coating.is_specular()
    }

    /// Both directions on the front (the model is two-sided).
    fn to_front(wo: Vec3, wi: Vec3) -> (Vec3, Vec3) {
        if wo.z < 0.0 { (-wo, -wi) } else { (wo, wi) }
    }

    /// Russian roulette on a walk's throughput after its third event:
    /// `false` if the walk ends, otherwise the survival probability the
    /// throughput must be divided by.
    fn survive(depth: u32, throughput: f32, numbers: &mut WalkNumbers) -> Option<f32> {
        if depth > 3 && throughput < 0.25 {
            let q = (1.0 - throughput).max(0.0);
            if numbers.next() < q {
                return None;
            }
            return Some(1.0 - q);
        }
        Some(1.0)
    }

    /// The power-heuristic weight of leaving through the coating towards
    /// `wi` along the inside direction `-w` (`w` pointing up, towards the
    /// coating) reached by a technique of density `own` (the base's or the
    /// phase function's sample of `w`), against the presampled exit: that
    /// technique's density of the same inside direction, i.e. the coating's
    /// transmission density of `-w` sampled from `wi`. (pbrt-v4's text uses
    /// the density of `wi` given `-w`, a density over the outside
    /// direction; the two weights then do not sum to 1 and a rough coating
    /// is biased by a few per cent.)
    fn exit_weight(&self, own: f32, w: Vec3, wi: Vec3) -> f32 {
        power_heuristic(own, self.coating.pdf(wi, -w, Lobes::Transmission))
    }

    /// With a smooth coating over a delta base, the light a medium
    /// scattering event at height `z` (arriving along `w`) sends out
    /// through the presampled `exit` by the delta chains no walk can
    /// reach (pbrt-v4's estimator omits them): up along the exit's inside
    /// direction v, or down along v mirrored to the base and back up, then
    /// any number of round trips (internal reflection F(v) at the coating,
    /// base reflectance B, the slab's transmittance twice), a geometric
    /// series. Without the medium factor (albedo) and the walk's throughput.
    fn delta_chain(&self, w: Vec3, z: f32, exit: &BsdfSample) -> SampledSpectrum {
        let up = -exit.wi;
        let down = Vec3::new(up.x, up.y, -up.z);
        let Some(bounce) = usable(self.base.sample(-down, 0.5, [0.5, 0.5])) else {
            return self.phase.evaluate(-w, up) * transmittance(self.thickness - z, up) / exit.pdf
                * exit.value;
        };
        let base = bounce.value * (abs_cos_theta(bounce.wi) / bounce.pdf);
        let slab = transmittance(self.thickness, up);
        let round_trip = base * (fresnel_dielectric(-up.z, self.coating.eta) * slab * slab);
        let first_up = SampledSpectrum::splat(
            self.phase.evaluate(-w, up) * transmittance(self.thickness - z, up),
        );
        let first_down = base * (self.phase.evaluate(-w, down) * transmittance(z, down) * slab);
        let series = SampledSpectrum::splat(1.0) - round_trip;
        // The direct way up is the ordinary next-event estimate (added by
        // the caller); only the rest of the series is added here.
        let all = (first_up + first_down).safe_div(&series);
        (all - first_up) * exit.value / exit.pdf
    }

    /// An unbiased estimate of f(wo, wi) (without the cosine factor).
    pub(super) fn evaluate(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        let (wo, wi) = Self::to_front(wo, wi);
        if wo.z == 0.0 || !same_hemisphere(wo, wi) {
            return SampledSpectrum::zero();
        }
        let samples = self.samples as f32;
        let mut f = SampledSpectrum::splat(self.coating.evaluate(wo, wi, mode) * samples);
        let mut numbers = WalkNumbers::new(
            hash2(direction_hash(wo), EVALUATE_STREAM),
            direction_hash(wi),
        );
        let thickness = self.thickness;
        // The walk enters and leaves through the top.
        let exit_z = thickness;
        let coating_specular = self.coating.is_specular();
        let base_specular = self.base.is_specular();
        let scattering = !self.albedo.is_black();
        for _ in 0..self.samples {
            let Some(entered) = usable(self.coating.sample(
                wo,
                numbers.next(),
                numbers.next_2d(),
                mode,
                Lobes::Transmission,
            )) else {
                continue;
            };
            // The way out towards wi, sampled from wi's side with the
            // adjoint mode, for next-event estimation.
            let Some(exit) = usable(self.coating.sample(
                wi,
                numbers.next(),
                numbers.next_2d(),
                adjoint(mode),
                Lobes::Transmission,
            )) else {
                continue;
            };
            let mut beta = entered.value * (abs_cos_theta(entered.wi) / entered.pdf);
            let mut z = thickness;
            let mut w = entered.wi;
            for depth in 0..self.max_depth {
                let Some(survival) = Self::survive(depth, beta.max_component(), &mut numbers)
                else {
                    break;
                };
                beta /= survival;
                if !scattering {
                    z = if z == thickness { 0.0 } else { thickness };
                    beta *= transmittance(thickness, w);
                } else {
                    // Free flight in the medium (extinction 1).
                    let distance = -(1.0 - numbers.next()).ln() * abs_cos_theta(w);
                    let next_z = if w.z > 0.0 {
                        z + distance
                    } else {
                        z - distance
                    };
                    if next_z == z {
                        continue;
                    }
                    if 0.0 < next_z && next_z < thickness {
                        // Scattering in the medium: leave towards wi through
                        // the presampled exit, then continue with the phase
                        // function.
                        let weight = if coating_specular {
                            1.0
                        } else {
                            power_heuristic(exit.pdf, self.phase.pdf(-w, -exit.wi))
                        };
                        f += beta
                            * self.albedo
                            * (self.phase.evaluate(-w, -exit.wi)
                                * weight
                                * transmittance(next_z - exit_z, exit.wi)
                                / exit.pdf)
                            * exit.value;
                        if coating_specular && base_specular {
                            f += beta * self.albedo * self.delta_chain(w, next_z, &exit);
                        }
                        let phase_sample = self.phase.sample(-w, numbers.next_2d());
                        if phase_sample.pdf == 0.0 || phase_sample.wi.z == 0.0 {
                            continue;
                        }
                        beta *= self.albedo * (phase_sample.value / phase_sample.pdf);
                        w = phase_sample.wi;
                        z = next_z;
                        if z < exit_z && w.z > 0.0 && !coating_specular {
                            // Leave towards wi along the phase function's
                            // own direction.
                            let f_exit = self.coating.evaluate(-w, wi, mode);
                            if f_exit > 0.0 {
                                let weight = self.exit_weight(phase_sample.pdf, w, wi);
                                f += beta * (transmittance(z - exit_z, w) * f_exit * weight);
                            }
                        }
                        continue;
                    }
                    z = next_z.clamp(0.0, thickness);
                }
                if z == exit_z {
                    // Internal reflection at the coating.
                    let Some(reflected) = usable(self.coating.sample(
                        -w,
                        numbers.next(),
                        numbers.next_2d(),
                        mode,
                        Lobes::Reflection,
                    )) else {
                        break;
                    };
                    beta *= reflected.value * (abs_cos_theta(reflected.wi) / reflected.pdf);
                    w = reflected.wi;
                } else {
                    if !base_specular {
                        // The base: leave towards wi through the presampled
                        // exit.
                        let weight = if coating_specular {
                            1.0
                        } else {
                            power_heuristic(exit.pdf, self.base.pdf(-w, -exit.wi))
                        };
                        f += beta
                            * self.base.evaluate(-w, -exit.wi)
                            * (abs_cos_theta(exit.wi) * weight * transmittance(thickness, exit.wi)
                                / exit.pdf)
                            * exit.value;
                    }
                    let Some(bounce) =
                        usable(self.base.sample(-w, numbers.next(), numbers.next_2d()))
                    else {
                        break;
                    };
                    beta *= bounce.value * (abs_cos_theta(bounce.wi) / bounce.pdf);
                    w = bounce.wi;
                    if !coating_specular {
                        // Leave towards wi along the bounce's own direction
                        // (the only way out after a delta base).
                        let f_exit = self.coating.evaluate(-w, wi, mode);
                        if f_exit > 0.0 {
                            let weight = if base_specular {
                                1.0
                            } else {
                                self.exit_weight(bounce.pdf, w, wi)
                            };
                            f += beta * (transmittance(thickness, w) * f_exit * weight);
                        }
                    }
                }
            }
        }
        f / samples
    }

    /// pbrt-v4's estimate of the sampling density, for MIS weights (see the
    /// module docs): not normalised, but the same for the same directions.
    pub(super) fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let (wo, wi) = Self::to_front(wo, wi);
        if wo.z == 0.0 || !same_hemisphere(wo, wi) {
            return 0.0;
        }
        let samples = self.samples as f32;
        let mut numbers =
            WalkNumbers::new(hash2(direction_hash(wi), PDF_STREAM), direction_hash(wo));
        let mut density = samples * self.coating.pdf(wo, wi, Lobes::Reflection);
        for _ in 0..self.samples {
            // Transmission in, one base bounce, transmission out.
            let entered = usable(self.coating.sample(
                wo,
                numbers.next(),
                numbers.next_2d(),
                TransportMode::Radiance,
                Lobes::Transmission,
            ));
            let exit = usable(self.coating.sample(
                wi,
                numbers.next(),
                numbers.next_2d(),
                TransportMode::Importance,
                Lobes::Transmission,
            ));
            let (Some(entered), Some(exit)) = (entered, exit) else {
                continue;
            };
            if self.coating.is_specular() {
                density += self.base.pdf(-entered.wi, -exit.wi);
                continue;
            }
            let Some(bounce) = usable(self.base.sample(
                -entered.wi,
                numbers.next(),
                numbers.next_2d(),
            )) else {
                continue;
            };
            let coating_pdf = self.coating.pdf(-bounce.wi, wi, Lobes::All);
            if self.base.is_specular() {
                density += coating_pdf;
                continue;
            }
            // MIS between the base's sample and the presampled exit, both
            // weighted by their densities of the inside direction.
            let base_pdf = self.base.pdf(-entered.wi, -exit.wi);
            density += power_heuristic(exit.pdf, base_pdf) * base_pdf;
            density += self.exit_weight(bounce.pdf, bounce.wi, wi) * coating_pdf;
        }
        // Mixed with the uniform density of the upper hemisphere.
        let uniform = std::f32::consts::FRAC_1_PI * 0.5;
        0.1 * uniform + 0.9 * (density / samples)
    }

    /// Samples the coating; a transmission continues as a random walk until
    /// it leaves through the top. The sample's `value`/`pdf` ratio is an
    /// unbiased weight; `pdf` is proportional, not the density (use
    /// [`Self::pdf`] for MIS), except for an all-specular path, whose
    /// sample is a delta as usual.
    pub(super) fn sample(
        &self,
        wo: Vec3,
        u_component: f32,
        u: [f32; 2],
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        let flip = wo.z < 0.0;
        let wo = if flip { -wo } else { wo };
        if wo.z == 0.0 {
            return None;
        }
        let orient = |w: Vec3| if flip { -w } else { w };
        let entered = usable(self.coating.sample(wo, u_component, u, mode, Lobes::All))?;
        if entered.is_reflection() {
            let specular = entered.is_specular();
            return Some(BsdfSample {
                wi: orient(entered.wi),
                pdf_is_proportional: !specular,
                ..entered
            });
        }
        let mut numbers = WalkNumbers::new(
            hash2(direction_hash(wo), SAMPLE_STREAM),
            hash3(
                u64::from(u_component.to_bits()),
                u64::from(u[0].to_bits()),
                u64::from(u[1].to_bits()),
            ),
        );
        let thickness = self.thickness;
        let mut value = entered.value * abs_cos_theta(entered.wi);
        let mut pdf = entered.pdf;
        let mut w = entered.wi;
        let mut z = thickness;
        let mut specular_path = entered.is_specular();
        let scattering = !self.albedo.is_black();
        for depth in 0..self.max_depth {
            let survival = Self::survive(depth, value.max_component() / pdf, &mut numbers)?;
            pdf *= survival;
            if w.z == 0.0 {
                return None;
            }
            if scattering {
                let distance = -(1.0 - numbers.next()).ln() * abs_cos_theta(w);
                let next_z = if w.z > 0.0 {
                    z + distance
                } else {
                    z - distance
                };
                if next_z == z {
                    return None;
                }
                if 0.0 < next_z && next_z < thickness {
                    let phase_sample = self.phase.sample(-w, numbers.next_2d());
                    if phase_sample.pdf == 0.0 || phase_sample.wi.z == 0.0 {
                        return None;
                    }
                    value *= self.albedo * phase_sample.value;
                    pdf *= phase_sample.pdf;
                    specular_path = false;
                    w = phase_sample.wi;
                    z = next_z;
                    continue;
                }
                z = next_z.clamp(0.0, thickness);
            } else {
                z = if z == thickness { 0.0 } else { thickness };
                value *= transmittance(thickness, w);
            }
            let interaction = if z == 0.0 {
                usable(self.base.sample(-w, numbers.next(), numbers.next_2d()))?
            } else {
                usable(self.coating.sample(
                    -w,
                    numbers.next(),
                    numbers.next_2d(),
                    mode,
                    Lobes::All,
                ))?
            };
            value *= interaction.value;
            pdf *= interaction.pdf;
            if !(1e-10..=1e10).contains(&pdf) {
                // Long walks between peaked lobes (a nearly smooth rough
                // coating over a mirror traps light by total internal
                // reflection) would overflow value and pdf; only their
                // ratio matters, so rescale both.
                value /= pdf;
                pdf = 1.0;
            }
            specular_path &= interaction.is_specular();
            w = interaction.wi;
            if interaction.is_transmission() {
                // Left through the top, on wo's side.
                let kind = if specular_path {
                    BsdfFlags::SPECULAR
                } else {
                    BsdfFlags::GLOSSY
                };
                return Some(BsdfSample {
                    wi: orient(w),
                    value,
                    pdf,
                    flags: BsdfFlags::REFLECTION | kind,
                    eta: 1.0,
                    pdf_is_proportional: !specular_path,
                });
            }
            value *= abs_cos_theta(w);
        }
        None
    }

    /// Reflection: specular if the coating is smooth (for a smooth coating
    /// over a delta base and a clear layer the whole BSDF is a delta),
    /// glossy if the coating or the base is rough, diffuse if the base is
    /// diffuse or the medium scatters (pbrt-v4's rule, keeping both of
    /// glossy and diffuse where both occur).
    pub(super) fn flags(&self) -> BsdfFlags {
        let base = self.base.flags();
        let mut flags = BsdfFlags::REFLECTION;
        if self.coating.is_specular() {
            flags |= BsdfFlags::SPECULAR;
        } else {
            flags |= BsdfFlags::GLOSSY;
        }
        if base.is_glossy() {
            flags |= BsdfFlags::GLOSSY;
        }
        if base.is_diffuse() || !self.albedo.is_black() {
            flags |= BsdfFlags::DIFFUSE;
        }
        flags
    }

    /// The effective roughness for LQMC: the smoother of the coating (0 if
    /// smooth, else its α) and the base.
    pub(super) fn roughness(&self) -> f32 {
        let coating = self
            .coating
            .distribution
            .as_ref()
            .map_or(0.0, MicrofacetDistribution::roughness);
        coating.min(self.base.roughness())
    }
}

/// pbrt-v4's `coateddiffuse` at a hit, for a path's wavelengths.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CoatedDiffuseBsdf {
    layered: LayeredBsdf<DiffuseBsdf>,
}

impl CoatedDiffuseBsdf {
    /// A coated diffuse surface: base albedo `reflectance` (in [0, 1]) under
    /// a coating of relative index `eta` (> 0; 1 is accepted and makes the
    /// coating invisible), rough with `distribution` or smooth for `None`,
    /// over a layer of optical thickness `thickness` (clamped to at least
    /// the smallest positive f32, as pbrt-v4 does) whose medium has albedo
    /// `albedo` and Henyey–Greenstein asymmetry `g`. Walks take at most
    /// `max_depth` (≥ 1) events; `samples` (≥ 1) walks are averaged per call.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        reflectance: SampledSpectrum,
        eta: f32,
        distribution: Option<MicrofacetDistribution>,
        thickness: f32,
        albedo: SampledSpectrum,
        g: f32,
        max_depth: u32,
        samples: u32,
    ) -> Self {
        Self {
            layered: LayeredBsdf::new(
                eta,
                distribution,
                DiffuseBsdf::new_unchecked(reflectance, true),
                thickness,
                albedo,
                g,
                max_depth,
                samples,
            ),
        }
    }

    /// The coating's microfacet distribution (`None` if smooth).
    pub fn distribution(&self) -> Option<&MicrofacetDistribution> {
        self.layered.distribution()
    }

    /// An unbiased estimate of f(wo, wi) (without the cosine factor).
    pub fn evaluate(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        self.layered.evaluate(wo, wi, mode)
    }

    /// pbrt-v4's estimate of the sampling density, for MIS weights (see the
    /// module docs): not normalised, but the same for the same directions.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        self.layered.pdf(wo, wi)
    }

    /// Samples the coating; a transmission continues as a random walk until
    /// it leaves through the top. The sample's `value`/`pdf` ratio is an
    /// unbiased weight; `pdf` is proportional, not the density (use
    /// [`Self::pdf`] for MIS).
    pub fn sample(
        &self,
        wo: Vec3,
        u_component: f32,
        u: [f32; 2],
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        self.layered.sample(wo, u_component, u, mode)
    }

    /// Reflection: specular (smooth coating) or glossy (rough) at the
    /// coating, diffuse from the base.
    pub fn flags(&self) -> BsdfFlags {
        self.layered.flags()
    }

    /// The effective roughness for LQMC: the coating's α (0 if smooth).
    pub fn roughness(&self) -> f32 {
        self.layered.roughness()
    }
}

/// Test helpers shared by the layered BSDFs' tests (here and in
/// [`super::coated_conductor`]): test inputs, sampled and evaluated
/// integrals, a weighted chi-square test, reciprocity estimates.
#[cfg(test)]
pub(super) mod test_support {
    use super::*;
    use crate::statistics::chi_square_survival;
    use std::f64::consts::PI;

    /// The p-value below which a chi-square test fails (as the other BSDF
    /// tests).
    pub const P_VALUE_THRESHOLD: f64 = 1e-4;

    /// SplitMix64 uniforms for test inputs (the BSDF itself never sees
    /// this generator).
    pub struct Uniforms(pub u64);

    impl Uniforms {
        pub fn next(&mut self) -> f32 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
        }

        pub fn next_2d(&mut self) -> [f32; 2] {
            [self.next(), self.next()]
        }

        /// A uniform direction in the upper hemisphere (density 1/(2π)).
        pub fn hemisphere(&mut self) -> Vec3 {
            let [a, b] = self.next_2d();
            Self::direction(a, b)
        }

        /// The direction of cosine `z` (at least 10⁻⁴) and azimuth 2π`b`.
        pub fn direction(z: f32, b: f32) -> Vec3 {
            let z = z.max(1e-4);
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = 2.0 * std::f32::consts::PI * b;
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        }

        /// `w` tilted by about 10⁻⁴ rad: a different hash, so another
        /// independent estimate, at practically the same directions.
        pub fn jitter(&mut self, w: Vec3) -> Vec3 {
            (w + Vec3::new(self.next() - 0.5, self.next() - 0.5, self.next() - 0.5) * 2e-4)
                .normalize()
        }
    }

    /// Mean and standard error of the mean.
    pub fn mean_and_error(values: &[f64]) -> (f64, f64) {
        let n = values.len() as f64;
        let mean = values.iter().sum::<f64>() / n;
        let variance = values.iter().map(|v| (v - mean) * (v - mean)).sum::<f64>() / (n - 1.0);
        (mean, (variance / n).sqrt())
    }

    /// Sample weights f cos / pdf times `g(wi)` of `count` samples from
    /// `wo`: mean and standard error.
    pub fn sampled_integral<B: LayerBase>(
        bsdf: &LayeredBsdf<B>,
        wo: Vec3,
        count: usize,
        seed: u64,
        g: impl Fn(Vec3) -> f64,
    ) -> (f64, f64) {
        let mut uniforms = Uniforms(seed);
        let values: Vec<f64> = (0..count)
            .map(|_| {
                let u_component = uniforms.next();
                let u = uniforms.next_2d();
                match bsdf.sample(wo, u_component, u, TransportMode::Radiance) {
                    Some(sample) if sample.pdf > 0.0 => {
                        let weight = sample.value[0] * abs_cos_theta(sample.wi) / sample.pdf;
                        f64::from(weight) * g(sample.wi)
                    }
                    _ => 0.0,
                }
            })
            .collect();
        mean_and_error(&values)
    }

    /// ∫ f cos g over the upper hemisphere by uniform directions (plus,
    /// for a smooth coating, the specular reflection F g(reflect(wo)),
    /// exact). Delta paths through the layer (a smooth coating over a delta
    /// base) are not in it.
    pub fn evaluated_integral<B: LayerBase>(
        bsdf: &LayeredBsdf<B>,
        wo: Vec3,
        count: usize,
        seed: u64,
        g: impl Fn(Vec3) -> f64,
    ) -> (f64, f64) {
        let mut uniforms = Uniforms(seed);
        let values: Vec<f64> = (0..count)
            .map(|_| {
                let wi = uniforms.hemisphere();
                let f = bsdf.evaluate(wo, wi, TransportMode::Radiance)[0];
                f64::from(f * wi.z) * 2.0 * PI * g(wi)
            })
            .collect();
        let (mean, error) = mean_and_error(&values);
        (
            mean + specular_albedo(bsdf, wo) * g(reflect_about_normal(wo)),
            error,
        )
    }

    /// The albedo of the delta paths, all leaving along the mirror
    /// direction of `wo`: for a smooth coating its reflection F, plus, over
    /// a delta base, the unscattered round trips R + (1 − R)² B T² / (1 − R
    /// B T²) − R with B the base's reflectance at the refracted cosine μt
    /// and T = e^(−τ/μt) (the coating reflects F from inside as well).
    pub fn specular_albedo<B: LayerBase>(bsdf: &LayeredBsdf<B>, wo: Vec3) -> f64 {
        if !bsdf.coating_is_specular() {
            return 0.0;
        }
        let reflected = f64::from(fresnel_dielectric(wo.z, bsdf.coating.eta));
        if !bsdf.base.is_specular() {
            return reflected;
        }
        let inside = refract(wo, bsdf.coating.eta).expect("no total reflection from outside");
        let up = -inside.direction;
        let base = bsdf
            .base
            .sample(up, 0.5, [0.5, 0.5])
            .map_or(0.0, |s| f64::from(s.value[0] * abs_cos_theta(s.wi) / s.pdf));
        let t2 = f64::from(transmittance(bsdf.thickness, up)).powi(2);
        reflected + (1.0 - reflected).powi(2) * base * t2 / (1.0 - reflected * base * t2)
    }

    /// Asserts that sample weights and evaluation agree (4σ + 2·10⁻³) for
    /// several test functions g: in effect a histogram of the sampled
    /// directions weighted by their weights.
    pub fn assert_sampling_matches_evaluation<B: LayerBase>(
        name: &str,
        bsdf: &LayeredBsdf<B>,
        wo: Vec3,
        count: usize,
    ) {
        type TestFunction = (&'static str, fn(Vec3) -> f64);
        let tests: [TestFunction; 3] = [
            ("1", |_| 1.0),
            ("cos²", |w| f64::from(w.z * w.z)),
            ("x > 0.3", |w| f64::from(u8::from(w.x > 0.3))),
        ];
        for (index, (g_name, g)) in tests.iter().enumerate() {
            let seed = 11 + index as u64;
            let (sampled, sampled_error) = sampled_integral(bsdf, wo, count, seed, g);
            let (evaluated, evaluated_error) = evaluated_integral(bsdf, wo, count, seed, g);
            let sigma = (sampled_error.powi(2) + evaluated_error.powi(2)).sqrt();
            eprintln!(
                "{name}, g = {g_name}: sampled {sampled:.4} ± {sampled_error:.4}, \
                 evaluated {evaluated:.4} ± {evaluated_error:.4}"
            );
            assert!(
                (sampled - evaluated).abs() < 4.0 * sigma + 2e-3,
                "{name}, g = {g_name}: sampled {sampled} vs evaluated {evaluated} (σ {sigma})"
            );
        }
    }

    /// The p-value of a weighted chi-square test of the sampler: the upper
    /// hemisphere is cut into `bins` × `bins` cells of equal solid angle
    /// (uniform in cos θ and φ); per cell, the mean sample weight of
    /// `count` samples landing there (f cos / pdf, delta samples left out)
    /// is compared with ∫_cell f cos dω by `evaluations` stratified
    /// evaluations per cell. With both standard errors estimated from the
    /// same values, Σ (sampled − evaluated)² / (σ²_s + σ²_e) over the cells
    /// is asymptotically χ² with one degree of freedom per cell. Unlike a
    /// histogram of counts, this also tests the sample weights — needed
    /// because a stochastic BSDF's samples do not carry their density.
    pub fn weighted_chi_square<B: LayerBase>(
        bsdf: &LayeredBsdf<B>,
        wo: Vec3,
        bins: usize,
        count: usize,
        evaluations: usize,
        seed: u64,
    ) -> f64 {
        let cells = bins * bins;
        let cell_of = |w: Vec3| -> usize {
            let z = ((w.z.clamp(0.0, 1.0) * bins as f32) as usize).min(bins - 1);
            let phi = w.y.atan2(w.x).rem_euclid(2.0 * std::f32::consts::PI);
            let p = ((phi / (2.0 * std::f32::consts::PI) * bins as f32) as usize).min(bins - 1);
            z * bins + p
        };
        let mut sums = vec![0.0f64; cells];
        let mut squares = vec![0.0f64; cells];
        let mut uniforms = Uniforms(seed);
        for _ in 0..count {
            let u_component = uniforms.next();
            let u = uniforms.next_2d();
            let Some(sample) = bsdf.sample(wo, u_component, u, TransportMode::Radiance) else {
                continue;
            };
            if sample.is_specular() || sample.pdf <= 0.0 || sample.wi.z <= 0.0 {
                continue;
            }
            let weight = f64::from(sample.value[0] * abs_cos_theta(sample.wi) / sample.pdf);
            let cell = cell_of(sample.wi);
            sums[cell] += weight;
            squares[cell] += weight * weight;
        }
        let cell_solid_angle = 2.0 * PI / cells as f64;
        let mut statistic = 0.0;
        let mut degrees_of_freedom = 0;
        let mut worst = (0.0, 0, 0.0, 0.0);
        for cell in 0..cells {
            let n = count as f64;
            let sampled = sums[cell] / n;
            let sampled_variance = (squares[cell] / n - sampled * sampled).max(0.0) / n;
            let (z_index, phi_index) = (cell / bins, cell % bins);
            let values: Vec<f64> = (0..evaluations)
                .map(|_| {
                    let [a, b] = uniforms.next_2d();
                    let wi = Uniforms::direction(
                        (z_index as f32 + a) / bins as f32,
                        (phi_index as f32 + b) / bins as f32,
                    );
                    f64::from(bsdf.evaluate(wo, wi, TransportMode::Radiance)[0] * wi.z)
                        * cell_solid_angle
                })
                .collect();
            let (evaluated, evaluated_error) = mean_and_error(&values);
            let variance = sampled_variance + evaluated_error * evaluated_error;
            if variance > 0.0 {
                let term = (sampled - evaluated).powi(2) / variance;
                if term > worst.0 {
                    worst = (term, cell, sampled, evaluated);
                }
                statistic += term;
                degrees_of_freedom += 1;
            } else {
                assert!(sampled == 0.0 && evaluated == 0.0, "cell {cell}");
            }
        }
        let p = chi_square_survival(statistic, degrees_of_freedom.max(1));
        eprintln!(
            "weighted χ² {statistic:.1} on {degrees_of_freedom} cells: p = {p:.3e} \
             (largest term {:.1} in cell {}: sampled {:.5}, evaluated {:.5})",
            worst.0, worst.1, worst.2, worst.3
        );
        p
    }

    /// Mean and standard error of f(wo, wi) over `count` evaluations at
    /// jittered directions.
    pub fn evaluation_mean<B: LayerBase>(
        bsdf: &LayeredBsdf<B>,
        wo: Vec3,
        wi: Vec3,
        count: usize,
        uniforms: &mut Uniforms,
    ) -> (f64, f64) {
        let values: Vec<f64> = (0..count)
            .map(|_| {
                let (wo, wi) = (uniforms.jitter(wo), uniforms.jitter(wi));
                f64::from(bsdf.evaluate(wo, wi, TransportMode::Radiance)[0])
            })
            .collect();
        mean_and_error(&values)
    }

    /// Asserts f(a, b) = f(b, a) within 4σ for two pairs of directions.
    pub fn assert_reciprocal<B: LayerBase>(name: &str, bsdf: &LayeredBsdf<B>) {
        let pairs = [
            (Vec3::new(0.3, 0.2, 0.9), Vec3::new(-0.6, 0.1, 0.5)),
            (Vec3::new(0.8, 0.0, 0.3), Vec3::new(0.1, -0.4, 0.7)),
        ];
        for (a, b) in pairs {
            let (a, b) = (a.normalize(), b.normalize());
            let mut uniforms = Uniforms(21);
            let (forward, forward_error) = evaluation_mean(bsdf, a, b, 20_000, &mut uniforms);
            let (backward, backward_error) = evaluation_mean(bsdf, b, a, 20_000, &mut uniforms);
            let sigma = (forward_error.powi(2) + backward_error.powi(2)).sqrt();
            eprintln!(
                "{name}: f(a, b) {forward:.4} ± {forward_error:.4}, f(b, a) {backward:.4} ± {backward_error:.4}"
            );
            assert!(
                (forward - backward).abs() < 4.0 * sigma + 1e-4,
                "{name}: {forward} vs {backward} (σ {sigma})"
            );
        }
    }
}

#[cfg(test)]
mod tests {
    use super::test_support::*;
    use super::*;
    use crate::material::{
        MicrofacetKind, PlasticBsdf, RoughPlasticBsdf, RoughPlasticTables, fresnel_dielectric,
    };
    use crate::statistics::chi_square_test;
    use std::f64::consts::PI;

    fn ggx(alpha: f32) -> MicrofacetDistribution {
        MicrofacetDistribution::new(MicrofacetKind::Ggx, alpha, alpha)
    }

    fn coated(
        reflectance: f32,
        alpha: Option<f32>,
        thickness: f32,
        albedo: f32,
        g: f32,
        max_depth: u32,
    ) -> CoatedDiffuseBsdf {
        CoatedDiffuseBsdf::new(
            SampledSpectrum::splat(reflectance),
            1.5,
            alpha.map(ggx),
            thickness,
            SampledSpectrum::splat(albedo),
            g,
            max_depth,
            1,
        )
    }

    /// The cases the tests run through: smooth and rough coatings over
    /// clear and scattering layers.
    fn cases() -> Vec<(&'static str, CoatedDiffuseBsdf)> {
        vec![
            ("smooth, clear", coated(0.8, None, 0.01, 0.0, 0.0, 10)),
            ("smooth, scattering", coated(0.6, None, 0.5, 0.8, 0.3, 10)),
            ("rough, clear", coated(0.8, Some(0.3), 0.01, 0.0, 0.0, 10)),
            (
                "rough, scattering",
                coated(0.6, Some(0.2), 0.5, 0.8, -0.2, 10),
            ),
        ]
    }

    #[test]
    fn sample_weights_match_evaluation() {
        let wo = Vec3::new(0.5, 0.1, 0.8).normalize();
        for (name, bsdf) in cases() {
            assert_sampling_matches_evaluation(name, &bsdf.layered, wo, 40_000);
        }
    }

    /// Formerly known wrong (6 % bias, not reciprocal): the MIS weight of
    /// the exit along the walk's own direction took the coating's density
    /// of `wi` given the inside direction, a density over another variable
    /// than the presampled exit's (see `LayeredBsdf::exit_weight`). Here
    /// at three angles, grazing included.
    #[test]
    fn rough_coatings_sample_what_they_evaluate() {
        for cos in [0.95f32, 0.5, 0.15] {
            let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
            for (name, bsdf) in cases().into_iter().skip(2) {
                let layered = &bsdf.layered;
                let (sampled, sampled_error) = sampled_integral(layered, wo, 40_000, 11, |_| 1.0);
                let (evaluated, evaluated_error) =
                    evaluated_integral(layered, wo, 40_000, 11, |_| 1.0);
                let sigma = (sampled_error.powi(2) + evaluated_error.powi(2)).sqrt();
                eprintln!(
                    "{name}, cos θo {cos}: sampled {sampled:.4} ± {sampled_error:.4}, evaluated {evaluated:.4} ± {evaluated_error:.4}"
                );
                assert!(
                    (sampled - evaluated).abs() < 4.0 * sigma + 2e-3,
                    "{name}: sampled {sampled} vs evaluated {evaluated} (σ {sigma})"
                );
            }
        }
    }

    #[test]
    fn rough_and_scattering_sampling_passes_a_weighted_chi_square_test() {
        for cos in [0.9f32, 0.3] {
            let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
            for (name, bsdf) in cases() {
                eprint!("{name}, cos θo {cos}: ");
                let p = weighted_chi_square(&bsdf.layered, wo, 8, 100_000, 400, 61);
                assert!(p > P_VALUE_THRESHOLD, "{name}, cos θo {cos}: p = {p}");
            }
        }
    }

    /// The internal diffuse reflectance 2 ∫₀¹ F(μ, 1/η) μ dμ of the smooth
    /// coating seen from inside (midpoint rule, 20 000 steps).
    fn internal_diffuse_reflectance(eta: f32) -> f64 {
        let steps = 20_000;
        (0..steps)
            .map(|i| {
                let mu = (i as f64 + 0.5) / steps as f64;
                2.0 * f64::from(fresnel_dielectric(-(mu as f32), eta)) * mu / steps as f64
            })
            .sum()
    }

    #[test]
    fn a_white_clear_smooth_layer_samples_its_closed_form_density() {
        // White base, smooth coating, clear layer of thickness 0: every
        // sample has weight 1 (each step is sampled in proportion to its
        // value), so the sampled directions are distributed as f cos, whose
        // closed form is F(μo) δ(reflection) + T(μo) T(μi) μi / (π η² (1 −
        // F_dr)): a plain (count) chi-square test in cells of cos θi.
        let eta = 1.5f32;
        let bsdf = coated(1.0, None, 0.0, 0.0, 0.0, 400);
        let wo = Vec3::new(0.6, 0.0, 0.8);
        let internal = internal_diffuse_reflectance(eta);
        let bins = 40;
        let count = 100_000;
        let mut observed = vec![0u64; bins + 1];
        let mut uniforms = Uniforms(71);
        for _ in 0..count {
            let u_component = uniforms.next();
            let u = uniforms.next_2d();
            let Some(sample) = bsdf.sample(wo, u_component, u, TransportMode::Radiance) else {
                continue;
            };
            let weight = sample.value[0] * abs_cos_theta(sample.wi) / sample.pdf;
            assert!((weight - 1.0).abs() < 1e-3, "weight {weight}");
            if sample.is_specular() {
                observed[bins] += 1;
            } else {
                let cell = ((sample.wi.z * bins as f32) as usize).min(bins - 1);
                observed[cell] += 1;
            }
        }
        let transmitted_in = 1.0 - f64::from(fresnel_dielectric(wo.z, eta));
        let scale = transmitted_in / (f64::from(eta * eta) * (1.0 - internal));
        // ∫ over a cell of μ T(μ) (2π/π) dμ by the midpoint rule.
        let mut expected: Vec<f64> = (0..bins)
            .map(|cell| {
                let steps = 200;
                (0..steps)
                    .map(|step| {
                        let mu = (cell as f64 + (step as f64 + 0.5) / steps as f64) / bins as f64;
                        let t = 1.0 - f64::from(fresnel_dielectric(mu as f32, eta));
                        2.0 * mu * t / (steps * bins) as f64
                    })
                    .sum::<f64>()
                    * scale
                    * count as f64
            })
            .collect();
        expected.push(f64::from(fresnel_dielectric(wo.z, eta)) * count as f64);
        let total: f64 = expected.iter().sum();
        eprintln!("expected total {:.5} of the samples", total / count as f64);
        let result = chi_square_test(&observed, &expected);
        eprintln!(
            "χ² {:.1} on {} dof, p = {:.3e}",
            result.statistic, result.degrees_of_freedom, result.p_value
        );
        assert!(result.p_value > P_VALUE_THRESHOLD, "{result:?}");
    }

    #[test]
    fn energy_is_conserved_and_a_white_clear_layer_loses_none() {
        // A white base under a smooth coating with a vanishing, clear layer
        // reflects everything (up to the walk's depth limit, 200 here): the
        // white furnace. Rough coatings lose the energy of their single-
        // scattering microfacet model (less for smaller α); absorbing or grey
        // layers lose more.
        for &cos in &[0.95f32, 0.6, 0.2] {
            let wo = Vec3::new((1.0 - cos * cos).sqrt(), 0.0, cos);
            let furnace = coated(1.0, None, 0.0, 0.0, 0.0, 200);
            let (albedo, error) = sampled_integral(&furnace.layered, wo, 20_000, 3, |_| 1.0);
            eprintln!("white furnace, cos θo = {cos}: albedo {albedo:.4} ± {error:.4}");
            assert!(
                (albedo - 1.0).abs() < 4.0 * error + 1e-3,
                "{albedo} ± {error}"
            );
            let scattering_white = coated(1.0, None, 0.3, 1.0, 0.5, 200);
            let (albedo, error) =
                sampled_integral(&scattering_white.layered, wo, 20_000, 4, |_| 1.0);
            eprintln!("white scattering layer: albedo {albedo:.4} ± {error:.4}");
            assert!(
                (albedo - 1.0).abs() < 4.0 * error + 1e-3,
                "{albedo} ± {error}"
            );
            let mut previous = 1.0 + 1e-3;
            for alpha in [0.05f32, 0.3, 0.6] {
                let rough_white = coated(1.0, Some(alpha), 0.0, 0.0, 0.0, 200);
                let layered = &rough_white.layered;
                let (albedo, error) = sampled_integral(layered, wo, 20_000, 5, |_| 1.0);
                let (evaluated, evaluated_error) =
                    evaluated_integral(layered, wo, 40_000, 6, |_| 1.0);
                eprintln!(
                    "rough white furnace α {alpha}, cos θo = {cos}: albedo {albedo:.4} ± {error:.4} (evaluated {evaluated:.4} ± {evaluated_error:.4})"
                );
                let sigma = (error.powi(2) + evaluated_error.powi(2)).sqrt();
                assert!((albedo - evaluated).abs() < 4.0 * sigma + 2e-3);
                assert!(
                    albedo <= previous + 4.0 * error,
                    "{albedo} after {previous}"
                );
                assert!(albedo > 0.3, "α {alpha}: {albedo}");
                if alpha == 0.05 {
                    assert!(albedo > 0.95, "α {alpha}: {albedo}");
                }
                previous = albedo;
            }
            for (name, bsdf) in cases() {
                let (albedo, error) = sampled_integral(&bsdf.layered, wo, 20_000, 5, |_| 1.0);
                assert!(albedo <= 1.0 + 4.0 * error, "{name}: {albedo} ± {error}");
            }
        }
    }

    #[test]
    fn evaluation_is_reciprocal_in_expectation() {
        for (name, bsdf) in cases() {
            assert_reciprocal(name, &bsdf.layered);
        }
    }

    #[test]
    fn a_thin_clear_smooth_layer_is_mitsubas_nonlinear_plastic() {
        // Thickness 0, albedo 0, smooth coating: the walk sums the internal
        // reflections exactly, f = R T(wo) T(wi) / (π η² (1 − R F_dr)), with
        // F_dr the internal diffuse reflectance — Mitsuba's `plastic` with
        // `nonlinear`, up to its polynomial fit of F_dr.
        let reflectance = 0.7f32;
        let eta = 1.5f32;
        let bsdf = coated(reflectance, None, 0.0, 0.0, 0.0, 400);
        let plastic = PlasticBsdf::new(SampledSpectrum::splat(reflectance), eta, true, true);
        let internal = internal_diffuse_reflectance(eta);
        let mut uniforms = Uniforms(31);
        for (wo, wi) in [
            (Vec3::new(0.2, 0.1, 0.95), Vec3::new(-0.5, 0.3, 0.6)),
            (Vec3::new(0.9, 0.0, 0.3), Vec3::new(0.2, 0.2, 0.9)),
        ] {
            let (wo, wi) = (wo.normalize(), wi.normalize());
            let (mean, error) = evaluation_mean(&bsdf.layered, wo, wi, 20_000, &mut uniforms);
            let transmitted = f64::from(
                (1.0 - fresnel_dielectric(wo.z, eta)) * (1.0 - fresnel_dielectric(wi.z, eta)),
            );
            let r = f64::from(reflectance);
            let exact = r * transmitted / (PI * f64::from(eta * eta) * (1.0 - r * internal));
            let mitsuba = f64::from(plastic.evaluate(wo, wi)[0]);
            eprintln!(
                "layered {mean:.5} ± {error:.5}, closed form {exact:.5}, Mitsuba plastic {mitsuba:.5}"
            );
            assert!(
                (mean - exact).abs() < 4.0 * error,
                "{mean} ± {error} vs {exact}"
            );
            // Mitsuba's fit of F_dr is good to about 0.5 % here.
            assert!((mean - mitsuba).abs() < 4.0 * error + 0.01 * mitsuba);
        }
    }

    #[test]
    fn a_thin_clear_rough_layer_is_mitsubas_nonlinear_rough_plastic() {
        // Thickness 0, albedo 0, rough GGX coating. With the base black,
        // only the coating's reflection F D G / (4 cos θo cos θi) remains,
        // Mitsuba's `roughplastic` specular lobe exactly. With a grey base
        // the layered walk also has a closed form here: the Lambertian base
        // responds only to the irradiance it receives, whatever the angular
        // shape of the light the rough coating transmits or reflects back,
        // so the internal reflections sum to R t(μo) t(μi) / (π η² (1 − R
        // R_int)), with t(μ) the coating's directional transmittance and
        // R_int its hemispherical internal reflectance (single-scattering
        // microfacet model, energy loss included) — which is Mitsuba's
        // `roughplastic` diffuse lobe with `nonlinear`, up to its tables (t
        // at 64 cosines, linearly interpolated; R_int by a 64-point rule).
        // With a layer of non-zero thickness, or a scattering medium, the
        // models differ (Mitsuba has no layer), so only this is compared.
        let eta = 1.5f32;
        let mut uniforms = Uniforms(33);
        for alpha in [0.1f32, 0.3] {
            let distribution = ggx(alpha);
            let tables = RoughPlasticTables::shared(&distribution, eta);
            for reflectance in [0.0f32, 0.7] {
                let bsdf = coated(reflectance, Some(alpha), 0.0, 0.0, 0.0, 400);
                let mitsuba = RoughPlasticBsdf::new(
                    distribution,
                    tables,
                    SampledSpectrum::splat(reflectance),
                    eta,
                    true,
                    true,
                );
                for (wo, wi) in [
                    (Vec3::new(0.2, 0.1, 0.95), Vec3::new(-0.5, 0.3, 0.6)),
                    (Vec3::new(0.6, 0.0, 0.8), Vec3::new(-0.55, 0.0, 0.83)),
                    (Vec3::new(0.9, 0.0, 0.3), Vec3::new(0.2, 0.2, 0.9)),
                ] {
                    let (wo, wi) = (wo.normalize(), wi.normalize());
                    let (mean, error) =
                        evaluation_mean(&bsdf.layered, wo, wi, 20_000, &mut uniforms);
                    let reference = f64::from(mitsuba.evaluate(wo, wi)[0]);
                    eprintln!(
                        "α {alpha}, R {reflectance}: layered {mean:.5} ± {error:.5}, Mitsuba roughplastic {reference:.5}"
                    );
                    if reflectance == 0.0 {
                        // Deterministic: the coating's reflection alone.
                        assert!(
                            (mean - reference).abs() < 1e-4 * reference + 1e-7,
                            "{mean} vs {reference}"
                        );
                    } else {
                        assert!(
                            (mean - reference).abs() < 4.0 * error + 0.01 * reference,
                            "{mean} ± {error} vs {reference}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn the_mis_density_is_positive_where_light_reflects_and_roughly_normalised() {
        // pbrt-v4's density estimate is an approximation (one internal
        // bounce, directions inside and outside mixed); it must be positive
        // over the upper hemisphere, zero below, deterministic, and its
        // integral is printed (it need not be 1, see the module docs).
        let wo = Vec3::new(0.4, -0.2, 0.85).normalize();
        for (name, bsdf) in cases() {
            let mut uniforms = Uniforms(41);
            let values: Vec<f64> = (0..20_000)
                .map(|_| {
                    let wi = uniforms.hemisphere();
                    let pdf = bsdf.pdf(wo, wi);
                    assert!(pdf > 0.0 && pdf.is_finite(), "{name}: pdf {pdf} at {wi}");
                    assert_eq!(pdf, bsdf.pdf(wo, wi));
                    f64::from(pdf) * 2.0 * PI
                })
                .collect();
            let (integral, error) = mean_and_error(&values);
            eprintln!("{name}: ∫ pdf = {integral:.3} ± {error:.3}");
            assert!(integral > 0.3 && integral < 3.0, "{name}: {integral}");
            assert_eq!(bsdf.pdf(wo, Vec3::new(0.0, 0.6, -0.8)), 0.0);
        }
    }

    #[test]
    fn queries_are_deterministic_and_two_sided() {
        for (_, bsdf) in cases() {
            let wo = Vec3::new(0.3, 0.4, 0.866).normalize();
            let wi = Vec3::new(-0.2, 0.5, 0.84).normalize();
            let mode = TransportMode::Radiance;
            assert_eq!(bsdf.evaluate(wo, wi, mode), bsdf.evaluate(wo, wi, mode));
            assert_eq!(bsdf.evaluate(wo, wi, mode), bsdf.evaluate(-wo, -wi, mode));
            assert_eq!(bsdf.pdf(wo, wi), bsdf.pdf(-wo, -wi));
            assert!(bsdf.evaluate(wo, -wi, mode).is_black());
            for u_component in [0.01, 0.3, 0.7, 0.95] {
                let sample = bsdf.sample(wo, u_component, [0.2, 0.9], mode);
                assert_eq!(sample, bsdf.sample(wo, u_component, [0.2, 0.9], mode));
                let below = bsdf.sample(-wo, u_component, [0.2, 0.9], mode);
                assert_eq!(below.map(|s| -s.wi), sample.map(|s| s.wi));
            }
        }
    }
}
