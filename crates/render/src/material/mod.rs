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
//!   ([`TransportMode`]). [`SurfaceBsdf`] wraps one with its frame for
//!   world-space directions.
//! - [`Material`]: what a scene stores per shape; [`Material::bsdf`] turns it
//!   into a BSDF for a path's wavelengths.
//!
//! BSDFs never draw random numbers: sampling takes its numbers from the
//! caller, one for the lobe choice and two for the direction, from the
//! dimensions the [`crate::sampler::layout`] assigns to each path vertex.

mod bsdf;
mod bsdf_sample;
mod conductor;
mod dielectric;
mod diffuse;
mod error;
mod flags;
mod fresnel;
mod sampling;
mod shading_frame;
mod surface_adapter;
mod surface_material;

pub use bsdf::{Bsdf, BsdfModel, SurfaceBsdf};
pub use bsdf_sample::BsdfSample;
pub use conductor::{ConductorBsdf, ConductorReflectance};
pub use dielectric::DielectricBsdf;
pub use diffuse::DiffuseBsdf;
pub use error::MaterialError;
pub use flags::{BsdfFlags, TransportMode};
pub use fresnel::{
    Refraction, fresnel_complex, fresnel_complex_spectrum, fresnel_dielectric,
    reflect_about_normal, refract,
};
pub use sampling::{
    UNIFORM_SPHERE_PDF, cosine_hemisphere_pdf, sample_cosine_hemisphere,
    sample_uniform_disk_concentric, sample_uniform_sphere,
};
pub use shading_frame::{ShadingFrame, abs_cos_theta, cos_theta, same_hemisphere};
pub use surface_adapter::{SurfaceAdapter, bump_mapped_frame, normal_mapped_frame};
pub use surface_material::Material;
