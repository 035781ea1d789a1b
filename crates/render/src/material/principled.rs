//! [`PrincipledBsdf`]: Mitsuba 3's `principled` BSDF, the Disney model
//! (Burley 2012, "Physically Based Shading at Disney"; Burley 2015,
//! "Extending the Disney BRDF to a BSDF with Integrated Subsurface
//! Scattering") in the parameterisation and with the lobe formulas of
//! Mitsuba 3.9.1's plugin documentation and source (formulas only).
//!
//! With `wo` the camera-side direction, `wi` the light direction, h the
//! (generalised) half vector oriented to +z, F the dielectric Fresnel term
//! F(wo·h, η) and the weights brdf = (1 − metallic)(1 − spec_trans),
//! bsdf = (1 − metallic) spec_trans, f (without cosine) is the sum of
//!
//! - main specular reflection F_p D G / (4 |cos θo cos θi|), GGX with
//!   α_x = r²/a, α_y = r² a, a = √(1 − 0.9 anisotropic) (both ≥ 10⁻³), and
//!   F_p = (1 − metallic)(1 − spec_tint) F + metallic S(base) +
//!   (1 − metallic) spec_tint S(c_tint R0(η)) on the front (S: Schlick's
//!   approximation, evaluated at the transmitted angle when η < 1;
//!   c_tint = base/luminance(base)); bsdf · F from behind;
//! - main specular transmission √base · bsdf · the Walter et al. BTDF with
//!   (1 − F) (divided by η'² for radiance);
//! - clearcoat 0.25 clearcoat · Schlick(0.04) · GTR1(h; α_c) · G1(wo) G1(wi)
//!   (GGX G1 with α = 0.25; α_c = lerp(0.1, 0.001, clearcoat_gloss)), front
//!   only — Mitsuba's form, without the 1/(4 cos θo cos θi) of a microfacet
//!   BRDF;
//! - diffuse brdf · base/π · lerp(f_diff + f_retro, f_ss, flatness) with
//!   Burley's retro-reflection and Hanrahan–Krueger-like "fake subsurface",
//!   front only;
//! - sheen sheen (1 − metallic) lerp(1, c_tint, sheen_tint) (1 − cos θd)⁵,
//!   front only, where brdf > 0.
//!
//! Sampling (Mitsuba's scheme): a normal m visible from `wo` (mirrored
//! upwards) fixes F(wo·m); then on the front the lobes are chosen with
//! weights diffuse brdf·w_d, clearcoat 0.25 clearcoat·w_c, transmission
//! w_s bsdf (1 − F) and reflection w_s (1 − bsdf (1 − F)) (w: the sampling
//! rates), from behind reflection F and transmission 1 − F. The density is
//! the mixture with the same weights taken at the half vector of (wo, wi).
//! From behind with bsdf = 0 the BSDF is black and samples nothing.

use std::f32::consts::{FRAC_1_PI, PI};

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::flags::{BsdfFlags, TransportMode};
use super::fresnel::fresnel_dielectric;
use super::microfacet::{MicrofacetDistribution, MicrofacetKind};
use super::rough_dielectric::refract_about;
use crate::sampling::{cosine_hemisphere_pdf, sample_cosine_hemisphere};
use crate::spectrum::{SampledSpectrum, SampledWavelengths, cie_y};

/// The parameters of a principled BSDF at one hit (textures evaluated).
/// All weights are in [0, 1] in normal use; they are not clamped (Mitsuba
/// does not clamp them either).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipledParameters {
    /// The colour of diffuse, metallic and transmitted light.
    pub base_color: SampledSpectrum,
    /// Roughness r of the main specular lobes (α = r²).
    pub roughness: f32,
    /// Degree of anisotropy of the main specular lobes.
    pub anisotropic: f32,
    /// Blend from dielectric to (Schlick) metal.
    pub metallic: f32,
    /// Blend from the BRDF to the transmissive BSDF.
    pub spec_trans: f32,
    /// Interior over exterior index of refraction.
    pub eta: f32,
    /// Tint of the dielectric reflection towards the base colour.
    pub spec_tint: f32,
    /// Weight of the sheen lobe.
    pub sheen: f32,
    /// Tint of the sheen towards the base colour.
    pub sheen_tint: f32,
    /// Weight of the clearcoat lobe.
    pub clearcoat: f32,
    /// Glossiness of the clearcoat (α from 0.1 to 0.001).
    pub clearcoat_gloss: f32,
    /// Blend from the diffuse lobe to the fake subsurface lobe.
    pub flatness: f32,
    /// Relative sampling weight of the main specular lobes.
    pub main_specular_sampling_rate: f32,
    /// Relative sampling weight of the clearcoat.
    pub clearcoat_sampling_rate: f32,
    /// Relative sampling weight of the diffuse lobe.
    pub diffuse_reflectance_sampling_rate: f32,
}

impl PrincipledParameters {
    /// Mitsuba's defaults: base colour 0.5, roughness 0.5, η = 1.5 (its
    /// default `specular` 0.5 gives η ≈ 1.4964; callers set it), all other
    /// weights 0 and sampling rates 1.
    pub fn new(base_color: SampledSpectrum) -> Self {
        Self {
            base_color,
            roughness: 0.5,
            anisotropic: 0.0,
            metallic: 0.0,
            spec_trans: 0.0,
            eta: 1.5,
            spec_tint: 0.0,
            sheen: 0.0,
            sheen_tint: 0.0,
            clearcoat: 0.0,
            clearcoat_gloss: 0.0,
            flatness: 0.0,
            main_specular_sampling_rate: 1.0,
            clearcoat_sampling_rate: 1.0,
            diffuse_reflectance_sampling_rate: 1.0,
        }
    }
}

/// Mitsuba's relation between `specular` and η:
/// η = 2/(1 − √(0.08 specular)) − 1 (the inverse of Schlick's
/// R0 = 0.08 specular).
pub fn principled_eta_from_specular(specular: f32) -> f32 {
    2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
}

/// The GGX roughness of the main specular lobes (Burley 2012's mapping):
/// α = r², stretched by 1/a and a along tangent and bitangent with
/// a = √(1 − 0.9 anisotropic), each at least 10⁻³.
pub(super) fn specular_distribution(roughness: f32, anisotropic: f32) -> MicrofacetDistribution {
    let alpha = roughness * roughness;
    let aspect = (1.0 - 0.9 * anisotropic).sqrt();
    MicrofacetDistribution::new(
        MicrofacetKind::Ggx,
        (alpha / aspect).max(1e-3),
        (alpha * aspect).max(1e-3),
    )
}

/// Schlick's weight (1 − cos)⁵, with 1 − cos clamped to [0, 1].
pub(super) fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// Schlick's R0 of relative index η: ((η − 1)/(η + 1))².
pub(super) fn schlick_r0(eta: f32) -> f32 {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

/// Schlick's Fresnel approximation R0 + (1 − R0)(1 − cos)⁵ at the
/// microfacet cosine `cos` of an interface of index `eta`; from the denser
/// side (η' < 1) the transmitted angle's cosine is used (Mitsuba's rule).
pub(super) fn schlick_fresnel(r0: SampledSpectrum, cos: f32, eta: f32) -> SampledSpectrum {
    let eta_incident = if cos >= 0.0 { eta } else { 1.0 / eta };
    let weight = if eta_incident > 1.0 {
        schlick_weight(cos.abs())
    } else {
        let cos_t2 = 1.0 - (1.0 - cos * cos) / (eta_incident * eta_incident);
        schlick_weight(cos_t2.max(0.0).sqrt())
    };
    r0 * (1.0 - weight) + SampledSpectrum::splat(weight)
}

/// Mitsuba's spectral luminance of `value`: the mean over the path's
/// wavelengths of ȳ(λ) value(λ).
pub(super) fn spectral_luminance(value: SampledSpectrum, wavelengths: &SampledWavelengths) -> f32 {
    (cie_y().sample(wavelengths) * value).average()
}

/// The base colour normalised by its luminance (1 where that is 0).
pub(super) fn tint_color(base_color: SampledSpectrum, luminance: f32) -> SampledSpectrum {
    if luminance > 0.0 {
        base_color / luminance
    } else {
        SampledSpectrum::splat(1.0)
    }
}

/// Whether `m` can connect `wo` and `wi` (a reflection: both on the side of
/// `m` that faces `wo`'s hemisphere; a transmission: `wi` on the other).
pub(super) fn microfacet_compatible(m: Vec3, wo: Vec3, wi: Vec3, reflection: bool) -> bool {
    let facing = if wo.z < 0.0 { -m } else { m };
    let wi_side = if reflection {
        wi.dot(facing)
    } else {
        -wi.dot(facing)
    };
    wo.dot(facing) > 0.0 && wi_side > 0.0
}

/// `w` mirrored into the upper hemisphere.
pub(super) fn upper(w: Vec3) -> Vec3 {
    if w.z < 0.0 { -w } else { w }
}

/// Burley's diffuse with retro-reflection, blended with the fake subsurface
/// lobe by `flatness`, for |cos θo|, |cos θi| and the cosine θd of `wi`
/// with the half vector (the factor multiplying base/π).
pub(super) fn diffuse_shape(
    cos_o: f32,
    cos_i: f32,
    cos_d: f32,
    roughness: f32,
    flatness: f32,
) -> f32 {
    let (weight_o, weight_i) = (schlick_weight(cos_o), schlick_weight(cos_i));
    let diffuse = (1.0 - 0.5 * weight_o) * (1.0 - 0.5 * weight_i);
    let retro_roughness = 2.0 * roughness * cos_d * cos_d;
    let retro =
        retro_roughness * (weight_o + weight_i + weight_o * weight_i * (retro_roughness - 1.0));
    if flatness == 0.0 {
        return diffuse + retro;
    }
    let subsurface_90 = 0.5 * retro_roughness;
    let subsurface_fresnel =
        (1.0 + (subsurface_90 - 1.0) * weight_i) * (1.0 + (subsurface_90 - 1.0) * weight_o);
    let subsurface = 1.25 * (subsurface_fresnel * (1.0 / (cos_o + cos_i) - 0.5) + 0.5);
    (diffuse + retro) * (1.0 - flatness) + subsurface * flatness
}

/// The sheen colour lerp(1, c_tint, sheen_tint).
pub(super) fn sheen_color(tint: SampledSpectrum, sheen_tint: f32) -> SampledSpectrum {
    SampledSpectrum::splat(1.0 - sheen_tint) + tint * sheen_tint
}

/// Burley's GTR1 ("generalised Trowbridge–Reitz" with γ = 1) normal
/// distribution of the clearcoat, D(m) = (α² − 1)/(π ln α² (1 + (α² − 1)
/// cos² θm)), sampled by its cos θm-weighted density.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Gtr1 {
    alpha: f32,
}

impl Gtr1 {
    fn d(&self, m: Vec3) -> f32 {
        let alpha2 = self.alpha * self.alpha;
        let value = (alpha2 - 1.0) / (PI * alpha2.ln() * (1.0 + (alpha2 - 1.0) * m.z * m.z));
        if value * m.z > 1e-20 { value } else { 0.0 }
    }

    /// D(m) cos θm, the density of [`Self::sample`] per solid angle of m.
    fn pdf(&self, m: Vec3) -> f32 {
        if m.z < 0.0 { 0.0 } else { m.z * self.d(m) }
    }

    /// Inverts the CDF of θm: cos² θ = (1 − α^(2(1 − u₁)))/(1 − α²).
    fn sample(&self, u: [f32; 2]) -> Vec3 {
        let alpha2 = self.alpha * self.alpha;
        let phi = 2.0 * PI * u[0];
        let cos2 = ((1.0 - alpha2.powf(1.0 - u[1])) / (1.0 - alpha2)).max(0.0);
        let sin = (1.0 - cos2).max(0.0).sqrt();
        Vec3::new(phi.cos() * sin, phi.sin() * sin, cos2.sqrt())
    }
}

/// The GGX G1 of the clearcoat, with fixed α = 0.25 (Burley 2012):
/// 2/(1 + √(1 + α² tan² θ)), 0 where `w` sees the back of `m`.
fn clearcoat_g1(w: Vec3, m: Vec3) -> f32 {
    if w.dot(m) * w.z <= 0.0 {
        return 0.0;
    }
    let cos2 = w.z * w.z;
    let tan2 = (1.0 - cos2) / cos2;
    2.0 / (1.0 + (1.0 + 0.0625 * tan2).sqrt())
}

/// The lobe weights of the sampling mixture (normalised), for a `wo` on the
/// front or not and the Fresnel reflectance at the chosen microfacet.
struct LobeProbabilities {
    diffuse: f32,
    clearcoat: f32,
    transmission: f32,
    reflection: f32,
}

/// The lobe a sample comes from.
enum Lobe {
    Diffuse,
    Clearcoat,
    Transmission,
    Reflection,
}

/// Mitsuba's principled BSDF at one hit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PrincipledBsdf {
    parameters: PrincipledParameters,
    distribution: MicrofacetDistribution,
    clearcoat_distribution: Gtr1,
    /// luminance(base colour) for the tints.
    luminance: f32,
}

impl PrincipledBsdf {
    /// The BSDF of `parameters` for the path's `wavelengths` (the tints
    /// normalise the base colour by its luminance over them, as Mitsuba's
    /// spectral variants do).
    pub fn new(parameters: PrincipledParameters, wavelengths: &SampledWavelengths) -> Self {
        let needs_luminance = parameters.spec_tint != 0.0 || parameters.sheen_tint != 0.0;
        Self {
            distribution: specular_distribution(parameters.roughness, parameters.anisotropic),
            clearcoat_distribution: Gtr1 {
                alpha: 0.1 + (0.001 - 0.1) * parameters.clearcoat_gloss,
            },
            luminance: if needs_luminance {
                spectral_luminance(parameters.base_color, wavelengths)
            } else {
                1.0
            },
            parameters,
        }
    }

    /// The parameters.
    pub fn parameters(&self) -> &PrincipledParameters {
        &self.parameters
    }

    /// The main specular lobes' microfacets.
    pub fn distribution(&self) -> &MicrofacetDistribution {
        &self.distribution
    }

    fn brdf_weight(&self) -> f32 {
        (1.0 - self.parameters.metallic) * (1.0 - self.parameters.spec_trans)
    }

    fn bsdf_weight(&self) -> f32 {
        (1.0 - self.parameters.metallic) * self.parameters.spec_trans
    }

    /// The half vector (upper hemisphere) of `wo`, `wi` and the relative
    /// index along the path; `None` for grazing directions.
    fn half_vector(&self, wo: Vec3, wi: Vec3) -> Option<(Vec3, bool, f32)> {
        if wo.z == 0.0 || wi.z == 0.0 {
            return None;
        }
        let reflection = wo.z * wi.z > 0.0;
        let eta_path = if wo.z > 0.0 {
            self.parameters.eta
        } else {
            1.0 / self.parameters.eta
        };
        let half = (wo + wi * if reflection { 1.0 } else { eta_path }).normalize();
        if !half.is_finite() {
            return None;
        }
        Some((upper(half), reflection, eta_path))
    }

    /// The principled Fresnel term F_p of the main specular reflection.
    fn specular_fresnel(&self, fresnel: f32, cos_oh: f32, front: bool) -> SampledSpectrum {
        let p = &self.parameters;
        if !front {
            return SampledSpectrum::splat(self.bsdf_weight() * fresnel);
        }
        let mut value = SampledSpectrum::splat((1.0 - p.metallic) * (1.0 - p.spec_tint) * fresnel);
        if p.metallic != 0.0 {
            value += schlick_fresnel(p.base_color, cos_oh, p.eta) * p.metallic;
        }
        if p.spec_tint != 0.0 {
            let eta_incident = if cos_oh >= 0.0 { p.eta } else { 1.0 / p.eta };
            let r0 = tint_color(p.base_color, self.luminance) * schlick_r0(eta_incident);
            value += schlick_fresnel(r0, cos_oh, p.eta) * ((1.0 - p.metallic) * p.spec_tint);
        }
        value
    }

    /// f(wo, wi) without the cosine factor, for transport `mode`.
    pub fn evaluate(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        let Some((half, reflection, eta_path)) = self.half_vector(wo, wi) else {
            return SampledSpectrum::zero();
        };
        let p = &self.parameters;
        let front = wo.z > 0.0;
        let (brdf, bsdf) = (self.brdf_weight(), self.bsdf_weight());
        let (cos_o, cos_i) = (wo.z.abs(), wi.z.abs());
        let cos_oh = wo.dot(half);
        let fresnel = fresnel_dielectric(cos_oh, p.eta);
        let compatible = microfacet_compatible(half, wo, wi, reflection);
        let mut value = SampledSpectrum::zero();
        if compatible {
            let d = self.distribution.d(half);
            let g = self.distribution.g(wo, wi, half);
            if reflection && fresnel > 0.0 {
                value +=
                    self.specular_fresnel(fresnel, cos_oh, front) * (d * g / (4.0 * cos_o * cos_i));
            }
            if !reflection && bsdf > 0.0 && fresnel < 1.0 {
                let cos_ih = wi.dot(half);
                let denominator = cos_oh + eta_path * cos_ih;
                let scale = match mode {
                    TransportMode::Radiance => 1.0 / (eta_path * eta_path),
                    TransportMode::Importance => 1.0,
                };
                let btdf =
                    (scale * (1.0 - fresnel) * d * g * eta_path * eta_path * cos_oh * cos_ih
                        / (cos_o * cos_i * denominator * denominator))
                        .abs();
                value += p.base_color.sqrt() * (bsdf * btdf);
            }
            if reflection && front && p.clearcoat > 0.0 {
                let fresnel_coat = schlick_fresnel(SampledSpectrum::splat(0.04), cos_oh, p.eta)[0];
                let d_coat = self.clearcoat_distribution.d(half);
                let g_coat = clearcoat_g1(wo, half) * clearcoat_g1(wi, half);
                value +=
                    SampledSpectrum::splat(0.25 * p.clearcoat * fresnel_coat * d_coat * g_coat);
            }
        }
        if reflection && front && brdf > 0.0 {
            let cos_d = half.dot(wi);
            let shape = diffuse_shape(cos_o, cos_i, cos_d, p.roughness, p.flatness);
            value += p.base_color * (brdf * FRAC_1_PI * shape);
            if p.sheen > 0.0 && 1.0 - p.metallic > 0.0 {
                let weight = p.sheen * (1.0 - p.metallic) * schlick_weight(cos_d.abs());
                let color = if p.sheen_tint != 0.0 {
                    sheen_color(tint_color(p.base_color, self.luminance), p.sheen_tint)
                } else {
                    SampledSpectrum::splat(1.0)
                };
                value += color * weight;
            }
        }
        value
    }

    /// The lobe probabilities for `wo` on the `front` and Fresnel `fresnel`.
    fn lobe_probabilities(&self, front: bool, fresnel: f32) -> Option<LobeProbabilities> {
        let p = &self.parameters;
        let bsdf = self.bsdf_weight();
        let (diffuse, clearcoat, transmission, reflection) = if front {
            (
                self.brdf_weight() * p.diffuse_reflectance_sampling_rate,
                0.25 * p.clearcoat * p.clearcoat_sampling_rate,
                p.main_specular_sampling_rate * bsdf * (1.0 - fresnel),
                p.main_specular_sampling_rate * (1.0 - bsdf * (1.0 - fresnel)),
            )
        } else {
            (0.0, 0.0, 1.0 - fresnel, fresnel)
        };
        let total = diffuse + clearcoat + transmission + reflection;
        (total > 0.0 && total.is_finite()).then(|| LobeProbabilities {
            diffuse: diffuse / total,
            clearcoat: clearcoat / total,
            transmission: transmission / total,
            reflection: reflection / total,
        })
    }

    /// The density with which [`Self::sample`] produces `wi`.
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        let Some((half, reflection, eta_path)) = self.half_vector(wo, wi) else {
            return 0.0;
        };
        let front = wo.z > 0.0;
        if !front && self.bsdf_weight() <= 0.0 {
            return 0.0;
        }
        let fresnel = fresnel_dielectric(wo.dot(half), self.parameters.eta);
        let Some(probabilities) = self.lobe_probabilities(front, fresnel) else {
            return 0.0;
        };
        let cos_ih = wi.dot(half);
        let jacobian = if reflection {
            (1.0 / (4.0 * cos_ih)).abs()
        } else {
            let denominator = wo.dot(half) + eta_path * cos_ih;
            (eta_path * eta_path * cos_ih / (denominator * denominator)).abs()
        };
        let compatible = microfacet_compatible(half, wo, wi, reflection);
        let mut pdf = 0.0;
        if compatible {
            let visible = self.distribution.visible_normal_pdf(upper(wo), half);
            if reflection {
                pdf += probabilities.reflection * visible * jacobian;
                pdf += probabilities.clearcoat * self.clearcoat_distribution.pdf(half) * jacobian;
            } else {
                pdf += probabilities.transmission * visible * jacobian;
            }
        }
        if reflection {
            pdf += probabilities.diffuse * cosine_hemisphere_pdf(wi.z.abs());
        }
        pdf
    }

    /// Draws the microfacet normal with `u`, chooses the lobe with
    /// `u_component` and places `wi` (the diffuse and clearcoat lobes reuse
    /// `u`: their probabilities do not depend on the normal).
    pub fn sample(
        &self,
        wo: Vec3,
        u_component: f32,
        u: [f32; 2],
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        if wo.z == 0.0 {
            return None;
        }
        let front = wo.z > 0.0;
        if !front && self.bsdf_weight() <= 0.0 {
            return None;
        }
        let eta = self.parameters.eta;
        let m = self.distribution.sample_visible_normal(upper(wo), u);
        let fresnel = fresnel_dielectric(wo.dot(m), eta);
        let probabilities = self.lobe_probabilities(front, fresnel)?;
        let lobe = if u_component < probabilities.diffuse {
            Lobe::Diffuse
        } else if u_component < probabilities.diffuse + probabilities.clearcoat {
            Lobe::Clearcoat
        } else if u_component
            < probabilities.diffuse + probabilities.clearcoat + probabilities.transmission
        {
            Lobe::Transmission
        } else {
            Lobe::Reflection
        };
        let (wi, flags) = match lobe {
            Lobe::Diffuse => (
                sample_cosine_hemisphere(u),
                BsdfFlags::REFLECTION | BsdfFlags::DIFFUSE,
            ),
            Lobe::Clearcoat => {
                let m_coat = self.clearcoat_distribution.sample(u);
                let wi = 2.0 * wo.dot(m_coat) * m_coat - wo;
                if !microfacet_compatible(m_coat, wo, wi, true) {
                    return None;
                }
                (wi, BsdfFlags::REFLECTION | BsdfFlags::GLOSSY)
            }
            Lobe::Transmission => {
                let wi = refract_about(wo, m, eta)?;
                if !microfacet_compatible(m, wo, wi, false) {
                    return None;
                }
                (wi, BsdfFlags::TRANSMISSION | BsdfFlags::GLOSSY)
            }
            Lobe::Reflection => {
                let wi = 2.0 * wo.dot(m) * m - wo;
                if !microfacet_compatible(m, wo, wi, true) {
                    return None;
                }
                (wi, BsdfFlags::REFLECTION | BsdfFlags::GLOSSY)
            }
        };
        if wi.z * wo.z == 0.0 || (wi.z * wo.z > 0.0) != flags.is_reflective() {
            return None;
        }
        let relative_eta = if flags.is_transmissive() {
            if front { eta } else { 1.0 / eta }
        } else {
            1.0
        };
        Some(BsdfSample {
            wi,
            value: self.evaluate(wo, wi, mode),
            pdf: self.pdf(wo, wi),
            flags,
            eta: relative_eta,
            pdf_is_proportional: false,
        })
    }

    /// Diffuse and glossy reflection, glossy transmission where spec_trans
    /// weighs in.
    pub fn flags(&self) -> BsdfFlags {
        let reflection = BsdfFlags::REFLECTION | BsdfFlags::GLOSSY | BsdfFlags::DIFFUSE;
        if self.bsdf_weight() > 0.0 {
            reflection | BsdfFlags::TRANSMISSION
        } else {
            reflection
        }
    }

    /// The smoothest lobe's roughness for LQMC: the main specular α
    /// (max of α_x, α_y), or the clearcoat's α where it is present.
    pub fn roughness(&self) -> f32 {
        let specular = self.distribution.roughness();
        if self.parameters.clearcoat > 0.0 {
            specular.min(self.clearcoat_distribution.alpha)
        } else {
            specular
        }
    }
}
