//! Surface scattering: BSDFs in the local shading frame and the materials that
//! produce them, modelled on pbrt-v4 (Pharr, Jakob and Humphreys, *Physically
//! Based Rendering*, 4th ed., chapter 9).
//!
//! - [`ShadingFrame`]: the orthonormal basis (z = shading normal) in which
//!   BSDFs work.
//! - [`Bsdf`]: evaluate / sample / pdf of a [`BsdfModel`] — Lambertian
//!   [`DiffuseBsdf`], smooth [`ConductorBsdf`] (complex Fresnel or ideal
//!   mirror) and smooth [`DielectricBsdf`] (Fresnel reflection and Snell
//!   refraction, with dispersion) — for radiance or importance transport
//!   ([`TransportMode`]); rough conductors and dielectrics on a
//!   [`MicrofacetDistribution`] (GGX or Beckmann, anisotropic, visible-normal
//!   sampling), thin dielectrics, and Mitsuba 3's plastic and rough plastic
//!   (a diffuse base under a dielectric coating), and pbrt-v4's stochastic
//!   layered `coateddiffuse` and `coatedconductor`. [`SurfaceBsdf`] wraps one
//!   with its frame for world-space directions; [`Bsdf::roughness`] gives
//!   LQMC each vertex's effective roughness.
//! - Measured metals: [`measured_conductor`] gives η and κ spectra of the
//!   metals Mitsuba 3 and pbrt-v4 know by name.
//! - [`Material`]: what a scene stores per shape; [`Material::bsdf`] turns it
//!   into a BSDF for a path's wavelengths.
//!
//! BSDFs never draw random numbers: sampling takes its numbers from the
//! caller, one for the lobe choice and two for the direction, from the
//! dimensions the [`crate::sampler::layout`] assigns to each path vertex.

mod bsdf;
mod bsdf_sample;
mod coated_conductor;
mod conductor;
mod dielectric;
mod diffuse;
mod error;
mod flags;
mod fresnel;
mod layered;
mod measured_conductors;
mod microfacet;
mod plastic;
mod principled;
mod principled_material;
mod principled_thin;
mod rough_conductor;
mod rough_dielectric;
mod rough_plastic;
mod shading_frame;
mod sides;
mod surface_adapter;
mod surface_material;
mod thin_dielectric;

/// The warps BSDFs sample with, re-exported from [`crate::sampling`].
pub use crate::sampling::{
    UNIFORM_SPHERE_PDF, cosine_hemisphere_pdf, sample_cosine_hemisphere,
    sample_uniform_disk_concentric, sample_uniform_sphere,
};
pub use bsdf::{Bsdf, BsdfModel, SurfaceBsdf};
pub use bsdf_sample::BsdfSample;
pub use coated_conductor::CoatedConductorBsdf;
pub use conductor::{ConductorBsdf, ConductorReflectance};
pub use dielectric::DielectricBsdf;
pub use diffuse::DiffuseBsdf;
pub use error::MaterialError;
pub use flags::{BsdfFlags, TransportMode};
pub use fresnel::{
    Refraction, fresnel_complex, fresnel_complex_spectrum, fresnel_dielectric,
    fresnel_diffuse_reflectance, reflect_about_normal, refract,
};
pub use layered::CoatedDiffuseBsdf;
pub use measured_conductors::{MeasuredConductor, measured_conductor, measured_conductor_names};
pub use microfacet::{MicrofacetDistribution, MicrofacetKind, SMOOTH_ALPHA_THRESHOLD};
pub use plastic::PlasticBsdf;
pub use principled::{PrincipledBsdf, PrincipledParameters, principled_eta_from_specular};
pub use principled_material::{PrincipledMaterial, PrincipledSamplingRates};
pub use principled_thin::{PrincipledThinBsdf, PrincipledThinParameters};
pub use rough_conductor::RoughConductorBsdf;
pub use rough_dielectric::RoughDielectricBsdf;
pub use rough_plastic::{RoughPlasticBsdf, RoughPlasticTables, TRANSMITTANCE_TABLE_SIZE};
pub use shading_frame::{ShadingFrame, abs_cos_theta, cos_theta, same_hemisphere};
pub use surface_adapter::{
    PerturbationOptions, SurfaceAdapter, bump_mapped_frame, normal_mapped_frame,
};
pub use surface_material::{Material, Roughness};
pub use thin_dielectric::ThinDielectricBsdf;
