//! [`RoughPlasticBsdf`]: a diffuse base under a rough dielectric coating,
//! Mitsuba 3's `roughplastic` model (implemented from its documented
//! behaviour; Weidlich and Wilkie 2007, "Arbitrarily Layered Micro-Facet
//! Surfaces", in the simplified form Mitsuba uses).
//!
//! - Specular lobe: the rough dielectric reflection
//!   F(wo·h) D(h) G(wo, wi, h) / (4 cos θo cos θi).
//! - Diffuse lobe: d_eff t(cos θo) t(cos θi) / (π η²), where t(μ) is the
//!   fraction of light that the rough coating transmits at incidence μ,
//!   t(μ) = E_m~D_w[(1 − F(w·m)) G1(w_t, m)] over the normals visible from
//!   w (w_t the refracted direction), tabulated at 64 cosines and
//!   interpolated linearly, and d_eff = d/(1 − R_int) or d/(1 − d R_int)
//!   (`nonlinear`) with the coating's internal hemispherical reflectance
//!   R_int = 2 ∫ r(μ) μ dμ, r(μ) = E_m~D_w[F(w·m, 1/η) G1(w_r, m)] the
//!   rough reflectance seen from inside.
//! - Sampling: the specular lobe (visible normals) with probability
//!   ∝ (1 − t(cos θo)) w_s, the diffuse one ∝ t(cos θo)(1 − w_s).
//!
//! The tables depend only on the distribution and η, so they are computed
//! once per distinct coating and kept for the rest of the process
//! ([`RoughPlasticTables::shared`]).

use std::collections::HashMap;
use std::sync::{Mutex, OnceLock};

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::flags::BsdfFlags;
use super::fresnel::fresnel_dielectric;
use super::microfacet::{MicrofacetDistribution, MicrofacetKind};
use super::plastic::PlasticBase;
use super::sides::{flip_z, front_side, front_side_pair};
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::SampledSpectrum;

/// Number of cosines at which the coating's transmittance is tabulated
/// (Mitsuba 3 uses 64).
pub const TRANSMITTANCE_TABLE_SIZE: usize = 64;

/// Gauss–Legendre nodes per dimension of the integrals over visible normals
/// (entering the coating; leaving it needs more for its total internal
/// reflection).
const QUADRATURE_NODES_ENTERING: usize = 32;
const QUADRATURE_NODES_LEAVING: usize = 64;

/// What a rough coating transmits and reflects, for one distribution and η.
#[derive(Debug, Clone, PartialEq)]
pub struct RoughPlasticTables {
    /// t(μ) at μ = i/(N − 1) (μ = 10⁻⁶ for i = 0).
    pub external_transmittance: [f32; TRANSMITTANCE_TABLE_SIZE],
    /// R_int, the internal hemispherical reflectance.
    pub internal_reflectance: f32,
}

impl RoughPlasticTables {
    /// Computes the tables for isotropic `distribution` and relative index
    /// `eta` by Gauss–Legendre quadrature over the unit square of
    /// visible-normal samples.
    pub fn compute(distribution: &MicrofacetDistribution, eta: f32) -> Self {
        let cosines = (0..TRANSMITTANCE_TABLE_SIZE)
            .map(|index| (index as f32 / (TRANSMITTANCE_TABLE_SIZE - 1) as f32).max(1e-6));
        let mut external_transmittance = [0.0; TRANSMITTANCE_TABLE_SIZE];
        let mut internal_sum = 0.0_f64;
        for (index, mu) in cosines.enumerate() {
            let w = Vec3::new((1.0 - mu * mu).max(0.0).sqrt(), 0.0, mu);
            external_transmittance[index] =
                coating_transmittance(distribution, w, eta, QUADRATURE_NODES_ENTERING) as f32;
            internal_sum +=
                coating_reflectance(distribution, w, 1.0 / eta, QUADRATURE_NODES_LEAVING)
                    * f64::from(mu);
        }
        // 2 ∫ r(μ) μ dμ as twice the mean over the uniform grid of cosines
        // (Mitsuba 3's rule).
        let internal_reflectance = (2.0 * internal_sum / TRANSMITTANCE_TABLE_SIZE as f64) as f32;
        Self {
            external_transmittance,
            internal_reflectance,
        }
    }

    /// The tables for `distribution` (isotropic: α_x is used) and `eta`,
    /// computed on first use and shared (leaked: one small table per distinct
    /// coating of the scenes loaded by the process).
    pub fn shared(distribution: &MicrofacetDistribution, eta: f32) -> &'static RoughPlasticTables {
        type Key = (MicrofacetKind, u32, u32);
        static CACHE: OnceLock<Mutex<HashMap<Key, &'static RoughPlasticTables>>> = OnceLock::new();
        let key = (
            distribution.kind(),
            distribution.alpha_x().to_bits(),
            eta.to_bits(),
        );
        let cache = CACHE.get_or_init(|| Mutex::new(HashMap::new()));
        if let Some(tables) = cache.lock().unwrap_or_else(|e| e.into_inner()).get(&key) {
            return tables;
        }
        let isotropic = MicrofacetDistribution::new(
            distribution.kind(),
            distribution.alpha_x(),
            distribution.alpha_x(),
        );
        let tables: &'static RoughPlasticTables =
            Box::leak(Box::new(Self::compute(&isotropic, eta)));
        let mut guard = cache.lock().unwrap_or_else(|e| e.into_inner());
        let &mut shared = guard.entry(key).or_insert(tables);
        shared
    }

    /// t(μ) by linear interpolation in the table.
    pub fn transmittance(&self, cos_theta: f32) -> f32 {
        let x = cos_theta.clamp(0.0, 1.0) * (TRANSMITTANCE_TABLE_SIZE - 1) as f32;
        let index = (x as usize).min(TRANSMITTANCE_TABLE_SIZE - 2);
        let t = x - index as f32;
        let table = &self.external_transmittance;
        table[index] * (1.0 - t) + table[index + 1] * t
    }
}

/// Gauss–Legendre nodes and weights on [0, 1] (weights sum to 1), by
/// Newton's method on the Legendre polynomial (Numerical Recipes, 3rd ed.,
/// §4.6).
fn gauss_legendre_unit(count: usize) -> Vec<(f64, f64)> {
    let mut rule = Vec::with_capacity(count);
    for i in 0..count {
        let mut x = (std::f64::consts::PI * (i as f64 + 0.75) / (count as f64 + 0.5)).cos();
        let mut derivative = 1.0;
        for _ in 0..100 {
            let (mut p0, mut p1) = (1.0, 0.0);
            for j in 0..count {
                let p2 = p1;
                p1 = p0;
                p0 = ((2 * j + 1) as f64 * x * p1 - j as f64 * p2) / (j + 1) as f64;
            }
            derivative = count as f64 * (x * p0 - p1) / (x * x - 1.0);
            let step = p0 / derivative;
            x -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        let weight = 2.0 / ((1.0 - x * x) * derivative * derivative);
        rule.push((0.5 * (x + 1.0), 0.5 * weight));
    }
    rule
}

/// E over the normals visible from `w` of `integrand(m)`, by a product
/// Gauss–Legendre rule with `nodes` points per dimension.
fn visible_normal_expectation(
    distribution: &MicrofacetDistribution,
    w: Vec3,
    nodes: usize,
    integrand: impl Fn(Vec3) -> f64,
) -> f64 {
    let rule = gauss_legendre_unit(nodes);
    let mut sum = 0.0;
    for &(u0, w0) in &rule {
        for &(u1, w1) in &rule {
            let m = distribution.sample_visible_normal(w, [u0 as f32, u1 as f32]);
            sum += w0 * w1 * integrand(m);
        }
    }
    sum
}

/// The rough reflectance r(w) = E[F(w·m, η) G1(w_r, m)] of an interface of
/// relative index `eta` seen from `w`.
fn coating_reflectance(
    distribution: &MicrofacetDistribution,
    w: Vec3,
    eta: f32,
    nodes: usize,
) -> f64 {
    visible_normal_expectation(distribution, w, nodes, |m| {
        let cos = w.dot(m);
        let reflected = 2.0 * cos * m - w;
        if reflected.z <= 0.0 {
            return 0.0;
        }
        f64::from(fresnel_dielectric(cos, eta) * distribution.g1(reflected, m))
    })
}

/// The rough transmittance t(w) = E[(1 − F(w·m, η)) G1(w_t, m)] into an
/// interface of relative index `eta` seen from `w`.
fn coating_transmittance(
    distribution: &MicrofacetDistribution,
    w: Vec3,
    eta: f32,
    nodes: usize,
) -> f64 {
    visible_normal_expectation(distribution, w, nodes, |m| {
        let cos_i = w.dot(m);
        if cos_i <= 0.0 {
            return 0.0;
        }
        let sin2_t = (1.0 - cos_i * cos_i) / (eta * eta);
        if sin2_t >= 1.0 {
            return 0.0;
        }
        let cos_t = (1.0 - sin2_t).sqrt();
        let transmitted = -w / eta + (cos_i / eta - cos_t) * m;
        f64::from((1.0 - fresnel_dielectric(cos_i, eta)) * distribution.g1(transmitted, m))
    })
}

/// A rough plastic.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoughPlasticBsdf {
    distribution: MicrofacetDistribution,
    tables: &'static RoughPlasticTables,
    base: PlasticBase,
    eta: f32,
    two_sided: bool,
}

impl RoughPlasticBsdf {
    /// A rough plastic with base albedo `diffuse` under a coating of
    /// relative index `eta` and roughness `distribution`, whose `tables`
    /// were computed for them ([`RoughPlasticTables::shared`]).
    pub fn new(
        distribution: MicrofacetDistribution,
        tables: &'static RoughPlasticTables,
        diffuse: SampledSpectrum,
        eta: f32,
        nonlinear: bool,
        two_sided: bool,
    ) -> Self {
        Self {
            distribution,
            tables,
            base: PlasticBase::new(diffuse, eta, tables.internal_reflectance, nonlinear),
            eta,
            two_sided,
        }
    }

    /// The coating's microfacets.
    pub fn distribution(&self) -> &MicrofacetDistribution {
        &self.distribution
    }

    /// The specular lobe at front-side `wo`, `wi` (no cosine).
    fn specular(&self, wo: Vec3, wi: Vec3) -> f32 {
        let half = (wo + wi).normalize();
        if !half.is_finite() {
            return 0.0;
        }
        let d = self.distribution.d(half);
        let g = self.distribution.g(wo, wi, half);
        if d == 0.0 || g == 0.0 {
            return 0.0;
        }
        fresnel_dielectric(wo.dot(half), self.eta) * d * g / (4.0 * wo.z * wi.z)
    }

    /// Both lobes.
    pub fn evaluate(&self, wo: Vec3, wi: Vec3) -> SampledSpectrum {
        let Some((wo, wi)) = front_side_pair(wo, wi, self.two_sided) else {
            return SampledSpectrum::zero();
        };
        let transmitted = self.tables.transmittance(wo.z) * self.tables.transmittance(wi.z);
        self.base.lambertian * transmitted + SampledSpectrum::splat(self.specular(wo, wi))
    }

    /// The mixture density of both lobes' samples.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some((wo, wi)) = front_side_pair(wo, wi, self.two_sided) else {
            return 0.0;
        };
        let specular_probability = self
            .base
            .specular_probability(1.0 - self.tables.transmittance(wo.z));
        let half = (wo + wi).normalize();
        let specular_pdf = if half.is_finite() && wo.dot(half) > 0.0 {
            self.distribution.visible_normal_pdf(wo, half) / (4.0 * wo.dot(half))
        } else {
            0.0
        };
        specular_probability * specular_pdf
            + (1.0 - specular_probability) * cosine_hemisphere_pdf(wi.z)
    }

    /// Chooses the lobe with `u_component` and samples it with `u`.
    pub fn sample(&self, wo: Vec3, u_component: f32, u: [f32; 2]) -> Option<BsdfSample> {
        let (wo_front, flipped) = front_side(wo, self.two_sided)?;
        let specular_probability = self
            .base
            .specular_probability(1.0 - self.tables.transmittance(wo_front.z));
        let (wi_front, flags) = if u_component < specular_probability {
            let m = self.distribution.sample_visible_normal(wo_front, u);
            let wi = 2.0 * wo_front.dot(m) * m - wo_front;
            if wi.z <= 0.0 {
                return None;
            }
            (wi, BsdfFlags::REFLECTION | BsdfFlags::GLOSSY)
        } else {
            (
                sample_cosine_hemisphere(u),
                BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE,
            )
        };
        let wi = if flipped { flip_z(wi_front) } else { wi_front };
        Some(BsdfSample {
            wi,
            value: self.evaluate(wo, wi),
            pdf: self.pdf(wo, wi),
            flags,
            eta: 1.0,
            pdf_is_proportional: false,
        })
    }

    /// Glossy and diffuse reflection.
    pub fn flags(&self) -> BsdfFlags {
        BsdfFlags::REFLECTION | BsdfFlags::GLOSSY | BsdfFlags::DIFFUSE
    }
}
