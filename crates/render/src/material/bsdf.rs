//! [`Bsdf`]: the scattering function at a surface point, in the local shading
//! frame (z = shading normal), with the operations every integrator needs:
//! evaluate, importance-sample, and the density of a sampled direction.
//!
//! # Conventions
//!
//! - `wo` is the direction towards the previous path vertex (the camera side
//!   for camera paths), `wi` the sampled or light direction; both point away
//!   from the surface and have unit length.
//! - [`Bsdf::evaluate`] returns f(wo, wi) *without* the cosine factor.
//! - Specular (delta) lobes are reached only by [`Bsdf::sample`]: for them
//!   `evaluate` and `pdf` are 0 (see [`BsdfSample`] for how value and pdf of a
//!   delta sample are to be read).
//!
//! # Reverse densities (BDPT, MIS)
//!
//! Bidirectional methods need the density of sampling the path in the other
//! direction: at a vertex where the path arrived from `wo` and continued to
//! `wi`, the forward density is `bsdf.pdf(wo, wi)` and the reverse one
//! (generating `wo` when sampling from `wi`) is `bsdf.pdf(wi, wo)`; the
//! matching value is `bsdf.evaluate(wi, wo)`. For the BSDFs here the pdf is
//! not symmetric in general (the diffuse pdf is |cos θi|/π), so both must be
//! evaluated. Delta lobes have no density either way; BDPT treats such
//! vertices as not connectible.
//!
//! # Transport mode
//!
//! The BSDF adjoint differs from the BSDF at refractive interfaces: radiance
//! is divided by η² on refraction, importance is not. A [`Bsdf`] carries its
//! [`TransportMode`] (radiance by default, which is what path tracing and the
//! camera subpaths of BDPT need); light subpaths use
//! [`Bsdf::with_transport_mode`]`(TransportMode::Importance)`.

use glam::Vec3;

use super::bsdf_sample::BsdfSample;
use super::coated_conductor::CoatedConductorBsdf;
use super::conductor::ConductorBsdf;
use super::dielectric::DielectricBsdf;
use super::diffuse::DiffuseBsdf;
use super::flags::{BsdfFlags, TransportMode};
use super::layered::CoatedDiffuseBsdf;
use super::plastic::PlasticBsdf;
use super::principled::PrincipledBsdf;
use super::principled_thin::PrincipledThinBsdf;
use super::rough_conductor::RoughConductorBsdf;
use super::rough_dielectric::RoughDielectricBsdf;
use super::rough_plastic::RoughPlasticBsdf;
use super::shading_frame::ShadingFrame;
use super::sides::flip_z;
use super::surface_adapter::SurfaceAdapter;
use super::thin_dielectric::ThinDielectricBsdf;
use crate::spectrum::{SampledSpectrum, SampledWavelengths};

/// The scattering models the renderer knows.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum BsdfModel {
    /// Lambertian reflection.
    Diffuse(DiffuseBsdf),
    /// A smooth metal or ideal mirror.
    Conductor(ConductorBsdf),
    /// A smooth glass-like interface.
    Dielectric(DielectricBsdf),
    /// A rough metal (microfacets).
    RoughConductor(RoughConductorBsdf),
    /// A rough glass-like interface (microfacets).
    RoughDielectric(RoughDielectricBsdf),
    /// A thin dielectric sheet.
    ThinDielectric(ThinDielectricBsdf),
    /// A diffuse base under a smooth coating.
    Plastic(PlasticBsdf),
    /// A diffuse base under a rough coating.
    RoughPlastic(RoughPlasticBsdf),
    /// Mitsuba's principled (Disney) BSDF.
    Principled(PrincipledBsdf),
    /// Mitsuba's thin principled BSDF.
    PrincipledThin(PrincipledThinBsdf),
    /// pbrt-v4's `coateddiffuse`: a stochastically evaluated layered BSDF.
    CoatedDiffuse(CoatedDiffuseBsdf),
    /// pbrt-v4's `coatedconductor`: a stochastically evaluated layered BSDF.
    CoatedConductor(CoatedConductorBsdf),
}

impl BsdfModel {
    #[inline]
    fn evaluate(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> SampledSpectrum {
        match self {
            BsdfModel::Diffuse(diffuse) => diffuse.evaluate(wo, wi),
            BsdfModel::Conductor(conductor) => conductor.evaluate(wo, wi),
            BsdfModel::Dielectric(dielectric) => dielectric.evaluate(wo, wi),
            BsdfModel::RoughConductor(conductor) => conductor.evaluate(wo, wi),
            BsdfModel::RoughDielectric(dielectric) => dielectric.evaluate(wo, wi, mode),
            BsdfModel::ThinDielectric(thin) => thin.evaluate(wo, wi),
            BsdfModel::Plastic(plastic) => plastic.evaluate(wo, wi),
            BsdfModel::RoughPlastic(plastic) => plastic.evaluate(wo, wi),
            BsdfModel::Principled(principled) => principled.evaluate(wo, wi, mode),
            BsdfModel::PrincipledThin(thin) => thin.evaluate(wo, wi),
            BsdfModel::CoatedDiffuse(coated) => coated.evaluate(wo, wi, mode),
            BsdfModel::CoatedConductor(coated) => coated.evaluate(wo, wi, mode),
        }
    }

    #[inline]
    fn sample(
        &self,
        wo: Vec3,
        u_component: f32,
        u: [f32; 2],
        wavelengths: &mut SampledWavelengths,
        mode: TransportMode,
    ) -> Option<BsdfSample> {
        match self {
            BsdfModel::Diffuse(diffuse) => diffuse.sample(wo, u),
            BsdfModel::Conductor(conductor) => conductor.sample(wo),
            BsdfModel::Dielectric(dielectric) => {
                dielectric.sample(wo, u_component, wavelengths, mode)
            }
            BsdfModel::RoughConductor(conductor) => conductor.sample(wo, u),
            BsdfModel::RoughDielectric(dielectric) => {
                dielectric.sample(wo, u_component, u, wavelengths, mode)
            }
            BsdfModel::ThinDielectric(thin) => thin.sample(wo, u_component),
            BsdfModel::Plastic(plastic) => plastic.sample(wo, u_component, u),
            BsdfModel::RoughPlastic(plastic) => plastic.sample(wo, u_component, u),
            BsdfModel::Principled(principled) => principled.sample(wo, u_component, u, mode),
            BsdfModel::PrincipledThin(thin) => thin.sample(wo, u_component, u),
            BsdfModel::CoatedDiffuse(coated) => coated.sample(wo, u_component, u, mode),
            BsdfModel::CoatedConductor(coated) => coated.sample(wo, u_component, u, mode),
        }
    }

    #[inline]
    fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self {
            BsdfModel::Diffuse(diffuse) => diffuse.pdf(wo, wi),
            BsdfModel::Conductor(conductor) => conductor.pdf(wo, wi),
            BsdfModel::Dielectric(dielectric) => dielectric.pdf(wo, wi),
            BsdfModel::RoughConductor(conductor) => conductor.pdf(wo, wi),
            BsdfModel::RoughDielectric(dielectric) => dielectric.pdf(wo, wi),
            BsdfModel::ThinDielectric(thin) => thin.pdf(wo, wi),
            BsdfModel::Plastic(plastic) => plastic.pdf(wo, wi),
            BsdfModel::RoughPlastic(plastic) => plastic.pdf(wo, wi),
            BsdfModel::Principled(principled) => principled.pdf(wo, wi),
            BsdfModel::PrincipledThin(thin) => thin.pdf(wo, wi),
            BsdfModel::CoatedDiffuse(coated) => coated.pdf(wo, wi),
            BsdfModel::CoatedConductor(coated) => coated.pdf(wo, wi),
        }
    }

    #[inline]
    fn flags(&self) -> BsdfFlags {
        match self {
            BsdfModel::Diffuse(diffuse) => diffuse.flags(),
            BsdfModel::Conductor(conductor) => conductor.flags(),
            BsdfModel::Dielectric(dielectric) => dielectric.flags(),
            BsdfModel::RoughConductor(conductor) => conductor.flags(),
            BsdfModel::RoughDielectric(dielectric) => dielectric.flags(),
            BsdfModel::ThinDielectric(thin) => thin.flags(),
            BsdfModel::Plastic(plastic) => plastic.flags(),
            BsdfModel::RoughPlastic(plastic) => plastic.flags(),
            BsdfModel::Principled(principled) => principled.flags(),
            BsdfModel::PrincipledThin(thin) => thin.flags(),
            BsdfModel::CoatedDiffuse(coated) => coated.flags(),
            BsdfModel::CoatedConductor(coated) => coated.flags(),
        }
    }

    /// The effective roughness in [0, 1] (see [`Bsdf::roughness`]).
    pub fn roughness(&self) -> f32 {
        match self {
            BsdfModel::Diffuse(_) => 1.0,
            BsdfModel::Conductor(_)
            | BsdfModel::Dielectric(_)
            | BsdfModel::ThinDielectric(_)
            | BsdfModel::Plastic(_) => 0.0,
            BsdfModel::RoughConductor(conductor) => conductor.distribution().roughness(),
            BsdfModel::RoughDielectric(dielectric) => dielectric.distribution().roughness(),
            BsdfModel::RoughPlastic(plastic) => plastic.distribution().roughness(),
            BsdfModel::Principled(principled) => principled.roughness(),
            BsdfModel::PrincipledThin(thin) => thin.roughness(),
            BsdfModel::CoatedDiffuse(coated) => coated.roughness(),
            BsdfModel::CoatedConductor(coated) => coated.roughness(),
        }
    }
}

/// A scattering model together with the quantity the path carries, in the
/// local shading frame. Built per hit (cheaply: a few spectra) for the path's
/// wavelengths.
///
/// A two-sided BSDF with different sides (Mitsuba's `twosided` with two
/// children) holds a `back` model: where `wo` is below the surface, the back
/// model scatters with both directions mirrored to its front (z negated), as
/// Mitsuba does; the side is decided by `wo` alone.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bsdf {
    model: BsdfModel,
    back: Option<BsdfModel>,
    transport_mode: TransportMode,
}

impl Bsdf {
    /// A BSDF for radiance transport.
    pub fn new(model: BsdfModel) -> Self {
        Self {
            model,
            back: None,
            transport_mode: TransportMode::Radiance,
        }
    }

    /// A BSDF scattering with `front` where `wo` is above the surface and
    /// with `back` (seen from its own front, directions mirrored) where it is
    /// below.
    pub fn two_sided(front: BsdfModel, back: BsdfModel) -> Self {
        Self {
            model: front,
            back: Some(back),
            transport_mode: TransportMode::Radiance,
        }
    }

    /// The same BSDF for the given transport mode.
    pub fn with_transport_mode(self, transport_mode: TransportMode) -> Self {
        Self {
            transport_mode,
            ..self
        }
    }

    /// The scattering model (of the front, for two different sides).
    pub fn model(&self) -> &BsdfModel {
        &self.model
    }

    /// The back's model, if the sides differ.
    pub fn back_model(&self) -> Option<&BsdfModel> {
        self.back.as_ref()
    }

    /// Radiance (camera paths) or importance (light paths).
    pub fn transport_mode(&self) -> TransportMode {
        self.transport_mode
    }

    /// The model that scatters light leaving towards `wo`, and whether the
    /// directions must be mirrored for it.
    #[inline]
    fn side(&self, wo: Vec3) -> (&BsdfModel, bool) {
        match &self.back {
            Some(back) if wo.z < 0.0 => (back, true),
            _ => (&self.model, false),
        }
    }

    /// f(wo, wi), without the cosine factor; 0 for delta lobes.
    ///
    /// `wavelengths` must be the set the BSDF was built for. The BSDFs here
    /// hold their spectra already sampled and do not read it; it is part of
    /// the signature so that models evaluating spectra per call can be added
    /// without changing callers.
    #[inline]
    pub fn evaluate(
        &self,
        wo: Vec3,
        wi: Vec3,
        _wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        match self.side(wo) {
            (model, false) => model.evaluate(wo, wi, self.transport_mode),
            (model, true) => model.evaluate(flip_z(wo), flip_z(wi), self.transport_mode),
        }
    }

    /// Importance-samples an incident direction for `wo`.
    ///
    /// `u_component` ∈ [0, 1) chooses between lobes (the vertex's
    /// [`crate::sampler::layout::SCATTER_COMPONENT`] dimension) and `u` ∈
    /// [0, 1)² places the direction within the lobe
    /// ([`crate::sampler::layout::SCATTER_DIRECTION`]). A dispersive dielectric
    /// terminates the secondary `wavelengths`. Returns `None` when no
    /// scattering is possible (grazing or back-facing `wo`, a black lobe, a
    /// zero density, or a `wi` in the tangent plane), as pbrt-v4 does.
    ///
    /// For non-delta lobes the returned value and pdf equal
    /// `evaluate(wo, wi)` and `pdf(wo, wi)`, except for stochastic models
    /// ([`CoatedDiffuseBsdf`], [`CoatedConductorBsdf`]), whose samples carry a path throughput and
    /// density with [`BsdfSample::pdf_is_proportional`] set: their ratio is
    /// the weight, and MIS must use [`Bsdf::pdf`].
    #[inline]
    pub fn sample(
        &self,
        wo: Vec3,
        u_component: f32,
        u: [f32; 2],
        wavelengths: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let sample = match self.side(wo) {
            (model, false) => model.sample(wo, u_component, u, wavelengths, self.transport_mode),
            (model, true) => model
                .sample(flip_z(wo), u_component, u, wavelengths, self.transport_mode)
                .map(|sample| BsdfSample {
                    wi: flip_z(sample.wi),
                    ..sample
                }),
        }?;
        sample.scatters().then_some(sample)
    }

    /// The density per unit solid angle with which [`Self::sample`] produces
    /// `wi` from `wo` (0 for delta lobes). `pdf(wi, wo)` is the reverse
    /// density (see the module docs).
    #[inline]
    pub fn pdf(&self, wo: Vec3, wi: Vec3) -> f32 {
        match self.side(wo) {
            (model, false) => model.pdf(wo, wi),
            (model, true) => model.pdf(flip_z(wo), flip_z(wi)),
        }
    }

    /// The kinds of scattering this BSDF can do (on either side).
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        match &self.back {
            Some(back) => self.model.flags() | back.flags(),
            None => self.model.flags(),
        }
    }

    /// The effective roughness in [0, 1] that LQMC's exploration uses to
    /// decide how far a path may be perturbed at this vertex: 0 for
    /// specular (delta) lobes (smooth conductors, dielectrics, thin
    /// dielectrics, smooth plastic's coating), the microfacet α (the larger
    /// of α_u and α_v, clamped to 1) for rough lobes (rough conductors,
    /// dielectrics and plastics), and 1 for diffuse reflection. A two-sided
    /// BSDF with different sides reports the smoother one.
    pub fn roughness(&self) -> f32 {
        match &self.back {
            Some(back) => self.model.roughness().min(back.roughness()),
            None => self.model.roughness(),
        }
    }
}

impl From<DiffuseBsdf> for Bsdf {
    fn from(diffuse: DiffuseBsdf) -> Self {
        Bsdf::new(BsdfModel::Diffuse(diffuse))
    }
}

impl From<ConductorBsdf> for Bsdf {
    fn from(conductor: ConductorBsdf) -> Self {
        Bsdf::new(BsdfModel::Conductor(conductor))
    }
}

impl From<DielectricBsdf> for Bsdf {
    fn from(dielectric: DielectricBsdf) -> Self {
        Bsdf::new(BsdfModel::Dielectric(dielectric))
    }
}

impl From<RoughConductorBsdf> for Bsdf {
    fn from(model: RoughConductorBsdf) -> Self {
        Bsdf::new(BsdfModel::RoughConductor(model))
    }
}

impl From<RoughDielectricBsdf> for Bsdf {
    fn from(model: RoughDielectricBsdf) -> Self {
        Bsdf::new(BsdfModel::RoughDielectric(model))
    }
}

impl From<ThinDielectricBsdf> for Bsdf {
    fn from(model: ThinDielectricBsdf) -> Self {
        Bsdf::new(BsdfModel::ThinDielectric(model))
    }
}

impl From<PlasticBsdf> for Bsdf {
    fn from(model: PlasticBsdf) -> Self {
        Bsdf::new(BsdfModel::Plastic(model))
    }
}

impl From<PrincipledBsdf> for Bsdf {
    fn from(model: PrincipledBsdf) -> Self {
        Bsdf::new(BsdfModel::Principled(model))
    }
}

impl From<PrincipledThinBsdf> for Bsdf {
    fn from(model: PrincipledThinBsdf) -> Self {
        Bsdf::new(BsdfModel::PrincipledThin(model))
    }
}

impl From<CoatedDiffuseBsdf> for Bsdf {
    fn from(model: CoatedDiffuseBsdf) -> Self {
        Bsdf::new(BsdfModel::CoatedDiffuse(model))
    }
}

impl From<CoatedConductorBsdf> for Bsdf {
    fn from(model: CoatedConductorBsdf) -> Self {
        Bsdf::new(BsdfModel::CoatedConductor(model))
    }
}

impl From<RoughPlasticBsdf> for Bsdf {
    fn from(model: RoughPlasticBsdf) -> Self {
        Bsdf::new(BsdfModel::RoughPlastic(model))
    }
}

/// A [`Bsdf`] placed on a surface: the same operations on world-space
/// directions, converted through the hit's [`ShadingFrame`], with a mask's
/// pass-through lobe and the side check of perturbed frames
/// ([`SurfaceAdapter`]). Integrators take cosines with `frame.normal()`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceBsdf {
    /// The hit's shading frame.
    pub frame: ShadingFrame,
    /// The local-frame BSDF.
    pub bsdf: Bsdf,
    /// Mask opacity and unperturbed normal ([`SurfaceAdapter::NONE`] for
    /// plain materials).
    pub adapter: SurfaceAdapter,
}

impl SurfaceBsdf {
    /// The Lambertian model when it is the whole BSDF (one side, opaque, the
    /// frame not perturbed): the common case, which the methods below serve
    /// without the generic dispatch. A Lambertian BSDF reads only the z
    /// components of its directions, so only those are converted, and the
    /// results equal the generic ones bit for bit.
    #[inline]
    fn plain_diffuse(&self) -> Option<&DiffuseBsdf> {
        match (&self.bsdf.model, &self.bsdf.back) {
            (BsdfModel::Diffuse(diffuse), None) if self.adapter == SurfaceAdapter::NONE => {
                Some(diffuse)
            }
            _ => None,
        }
    }

    /// Whether the BSDF is one plain Lambertian lobe (one side, opaque,
    /// the frame not perturbed): its value and density for a pair of
    /// directions then depend on `wo` only through the side of the shading
    /// normal it lies on (LQMC's members reuse a seed's step on that).
    pub fn is_plain_diffuse(&self) -> bool {
        self.plain_diffuse().is_some()
    }

    /// [`Bsdf::evaluate`] for world-space directions.
    pub fn evaluate(
        &self,
        wo_world: Vec3,
        wi_world: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        let wi = self.frame.to_local(wi_world);
        if self.adapter.opacity <= 0.0 || !self.adapter.sides_agree(wi_world, wi) {
            return SampledSpectrum::zero();
        }
        self.bsdf
            .evaluate(self.frame.to_local(wo_world), wi, wavelengths)
            * self.adapter.opacity
    }

    /// [`Self::evaluate`] and [`Self::pdf`] of the same pair of directions
    /// at once (next-event estimation needs both), converting each direction
    /// to the local frame once; equal to the two calls bit for bit.
    #[inline]
    pub fn evaluate_with_pdf(
        &self,
        wo_world: Vec3,
        wi_world: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        if let Some(diffuse) = self.plain_diffuse() {
            let normal = self.frame.normal();
            let wo = Vec3::new(0.0, 0.0, wo_world.dot(normal));
            let wi = Vec3::new(0.0, 0.0, wi_world.dot(normal));
            return (diffuse.evaluate(wo, wi), diffuse.pdf(wo, wi));
        }
        self.evaluate_with_pdf_general(wo_world, wi_world, wavelengths)
    }

    /// [`Self::evaluate_with_pdf`] for every BSDF but the plain Lambertian
    /// one: kept out of line so that the common case inlines small.
    #[inline(never)]
    fn evaluate_with_pdf_general(
        &self,
        wo_world: Vec3,
        wi_world: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> (SampledSpectrum, f32) {
        let wi = self.frame.to_local(wi_world);
        if self.adapter.opacity <= 0.0 || !self.adapter.sides_agree(wi_world, wi) {
            return (SampledSpectrum::zero(), 0.0);
        }
        let wo = self.frame.to_local(wo_world);
        (
            self.bsdf.evaluate(wo, wi, wavelengths) * self.adapter.opacity,
            self.bsdf.pdf(wo, wi) * self.adapter.opacity,
        )
    }

    /// [`Bsdf::sample`] for a world-space `wo`; the sample's `wi` is in world
    /// space.
    #[inline]
    pub fn sample(
        &self,
        wo_world: Vec3,
        u_component: f32,
        u: [f32; 2],
        wavelengths: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        if let Some(diffuse) = self.plain_diffuse() {
            let wo = Vec3::new(0.0, 0.0, wo_world.dot(self.frame.normal()));
            let mut sample = diffuse.sample(wo, u)?;
            // The check of `Bsdf::sample` (the value is black only for a
            // black reflectance).
            if !sample.scatters() {
                return None;
            }
            sample.wi = self.frame.to_world(sample.wi);
            return Some(sample);
        }
        self.sample_general(wo_world, u_component, u, wavelengths)
    }

    /// [`Self::sample`] for every BSDF but the plain Lambertian one: kept out
    /// of line so that the common case inlines small.
    #[inline(never)]
    fn sample_general(
        &self,
        wo_world: Vec3,
        u_component: f32,
        u: [f32; 2],
        wavelengths: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let wo = self.frame.to_local(wo_world);
        let Some(u_component) = self.adapter.nested_component_sample(u_component) else {
            let mut sample = self.adapter.pass_through_sample(wo)?;
            sample.wi = -wo_world;
            return Some(sample);
        };
        let mut sample = self.bsdf.sample(wo, u_component, u, wavelengths)?;
        let wi_world = self.frame.to_world(sample.wi);
        if !self.adapter.sides_agree(wi_world, sample.wi) {
            return None;
        }
        sample.wi = wi_world;
        if self.adapter.passes_through() {
            sample.value *= self.adapter.opacity;
            sample.pdf *= self.adapter.opacity;
        }
        Some(sample)
    }

    /// [`Bsdf::pdf`] for world-space directions.
    pub fn pdf(&self, wo_world: Vec3, wi_world: Vec3) -> f32 {
        let wi = self.frame.to_local(wi_world);
        if self.adapter.opacity <= 0.0 || !self.adapter.sides_agree(wi_world, wi) {
            return 0.0;
        }
        self.bsdf.pdf(self.frame.to_local(wo_world), wi) * self.adapter.opacity
    }

    /// [`Bsdf::flags`], with the pass-through lobe of a mask.
    #[inline]
    pub fn flags(&self) -> BsdfFlags {
        if let Some(diffuse) = self.plain_diffuse() {
            return diffuse.flags();
        }
        self.flags_general()
    }

    /// [`Self::flags`] for every BSDF but the plain Lambertian one (out of
    /// line, as [`Self::sample_general`]).
    #[inline(never)]
    fn flags_general(&self) -> BsdfFlags {
        self.adapter.flags(self.bsdf.flags())
    }

    /// [`Bsdf::roughness`]: the effective roughness in [0, 1] for LQMC (0 for
    /// specular lobes, the microfacet α for rough ones, 1 for diffuse). A
    /// mask's pass-through does not change it.
    pub fn roughness(&self) -> f32 {
        self.bsdf.roughness()
    }
}
