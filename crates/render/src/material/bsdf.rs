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
            (BsdfModel::Diffuse(diffuse), None) if self.adapter.is_none() => Some(diffuse),
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

    /// [`Bsdf::evaluate`] for world-space directions (with a perturbed
    /// frame's flip and shadowing term, [`SurfaceAdapter`]).
    pub fn evaluate(
        &self,
        wo_world: Vec3,
        wi_world: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        if self.adapter.has_mitsuba_options() {
            return self.evaluate_with_mitsuba_options(wo_world, wi_world, wavelengths);
        }
        match self.local_pair(&self.frame, wo_world, wi_world, self.bsdf.transport_mode()) {
            Some((wo, wi)) => self.bsdf.evaluate(wo, wi, wavelengths) * self.adapter.opacity,
            None => SampledSpectrum::zero(),
        }
    }

    /// The pair `wo`, `wi` in `frame`'s local coordinates, if the surface
    /// scatters between them in transport `mode`: it is not fully
    /// transparent and the pair passes the side check of a perturbed frame.
    #[inline]
    fn local_pair(
        &self,
        frame: &ShadingFrame,
        wo_world: Vec3,
        wi_world: Vec3,
        mode: TransportMode,
    ) -> Option<(Vec3, Vec3)> {
        let wo = frame.to_local(wo_world);
        let wi = frame.to_local(wi_world);
        (self.adapter.opacity > 0.0 && self.sides_agree(wo_world, wo, wi_world, wi, mode))
            .then_some((wo, wi))
    }

    /// [`Self::evaluate`] of a perturbed frame with Mitsuba 3.7.1's flip or
    /// shadowing term (out of line: the common case stays small).
    #[inline(never)]
    fn evaluate_with_mitsuba_options(
        &self,
        wo_world: Vec3,
        wi_world: Vec3,
        wavelengths: &SampledWavelengths,
    ) -> SampledSpectrum {
        let mode = self.bsdf.transport_mode();
        let frame = self.frame_for(wo_world, wi_world, mode);
        match self.local_pair(&frame, wo_world, wi_world, mode) {
            Some((wo, wi)) => {
                self.bsdf.evaluate(wo, wi, wavelengths)
                    * (self.adapter.opacity * self.shadowing(wo_world, wi_world, mode))
            }
            None => SampledSpectrum::zero(),
        }
    }

    /// The camera-side and the light-side direction of the pair `wo`, `wi`
    /// in transport `mode`.
    #[inline]
    fn camera_and_light_sides(wo: Vec3, wi: Vec3, mode: TransportMode) -> (Vec3, Vec3) {
        match mode {
            TransportMode::Radiance => (wo, wi),
            TransportMode::Importance => (wi, wo),
        }
    }

    /// The shading frame for the pair `wo`, `wi` in transport `mode`: the
    /// frame, or with Mitsuba's `flip_invalid_normals` the perturbed frame
    /// facing the camera-side direction.
    #[inline]
    fn frame_for(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> ShadingFrame {
        if !self.adapter.flips() {
            return self.frame;
        }
        let (to_camera, _) = Self::camera_and_light_sides(wo, wi, mode);
        self.adapter
            .perturbed_frame(self.adapter.flipped_for(to_camera), self.frame)
    }

    /// The shadowing term of a perturbed frame for the pair `wo`, `wi` in
    /// transport `mode` (1 for other BSDFs).
    #[inline]
    fn shadowing(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> f32 {
        if !self.adapter.shadowing_function {
            return 1.0;
        }
        let (_, to_light) = Self::camera_and_light_sides(wo, wi, mode);
        self.adapter.shadowing(to_light)
    }

    /// Sets the frame to the one Mitsuba's `flip_invalid_normals` picks for
    /// the camera-side direction `to_camera` (nothing for other BSDFs):
    /// camera paths, whose camera-side direction is known at the vertex,
    /// take cosines with this frame's normal. In place: a copy of the
    /// BSDF per vertex cost the path tracer 3 % of its instructions.
    #[inline]
    pub fn face_camera(&mut self, to_camera: Vec3) {
        if self.adapter.flips() {
            self.frame = self
                .adapter
                .perturbed_frame(self.adapter.flipped_for(to_camera), self.frame);
        }
    }

    /// The shading normal the value of the pair `wo`, `wi` in transport
    /// `mode` is taken with (the frame's, or the flipped one's).
    #[inline]
    pub fn shading_normal_for(&self, wo: Vec3, wi: Vec3, mode: TransportMode) -> Vec3 {
        if !self.adapter.flips() {
            return self.frame.normal();
        }
        self.frame_for(wo, wi, mode).normal()
    }

    /// The side check of a perturbed frame ([`SurfaceAdapter::sides_agree`])
    /// for the pair `wo`, `wi` (world and local) in transport `mode`: it
    /// applies to the direction light arrives from, `wi` in radiance
    /// transport and `wo` in importance transport. Mitsuba 3's `bumpmap` and
    /// `normalmap` check the sampled direction of camera paths, the light
    /// side; checking the sampled direction of light paths instead (the
    /// camera side) would give a path a different value on each subpath,
    /// and bidirectional weights that do not sum to one.
    #[inline]
    fn sides_agree(
        &self,
        wo_world: Vec3,
        wo: Vec3,
        wi_world: Vec3,
        wi: Vec3,
        mode: TransportMode,
    ) -> bool {
        match mode {
            TransportMode::Radiance => self.adapter.sides_agree(wi_world, wi),
            TransportMode::Importance => self.adapter.sides_agree(wo_world, wo),
        }
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
        let mode = self.bsdf.transport_mode();
        if self.adapter.flips() && mode == TransportMode::Importance {
            // Sampled from both frames: the density is their mixture's.
            return (
                self.evaluate(wo_world, wi_world, wavelengths),
                self.pdf_in_mode(wo_world, wi_world, mode),
            );
        }
        // The frame and shadowing term are the plain ones without Mitsuba's
        // options.
        let frame = self.frame_for(wo_world, wi_world, mode);
        match self.local_pair(&frame, wo_world, wi_world, mode) {
            Some((wo, wi)) => (
                self.bsdf.evaluate(wo, wi, wavelengths)
                    * (self.adapter.opacity * self.shadowing(wo_world, wi_world, mode)),
                self.bsdf.pdf(wo, wi) * self.adapter.opacity,
            ),
            None => (SampledSpectrum::zero(), 0.0),
        }
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
        let Some(u_component) = self.adapter.nested_component_sample(u_component) else {
            let wo = self.frame.to_local(wo_world);
            let mut sample = self.adapter.pass_through_sample(wo)?;
            sample.wi = -wo_world;
            return Some(sample);
        };
        let mode = self.bsdf.transport_mode();
        if self.adapter.flips() && mode == TransportMode::Importance {
            return self.sample_from_both_frames(wo_world, u_component, u, wavelengths);
        }
        // Radiance: the camera-side direction wo picks the frame.
        let frame = if self.adapter.flips() {
            self.frame_for(wo_world, wo_world, TransportMode::Radiance)
        } else {
            self.frame
        };
        let wo = frame.to_local(wo_world);
        if mode == TransportMode::Importance && !self.adapter.sides_agree(wo_world, wo) {
            return None;
        }
        let mut sample = self.bsdf.sample(wo, u_component, u, wavelengths)?;
        let wi_world = frame.to_world(sample.wi);
        if mode == TransportMode::Radiance && !self.adapter.sides_agree(wi_world, sample.wi) {
            return None;
        }
        sample.wi = wi_world;
        if self.adapter.passes_through() {
            sample.value *= self.adapter.opacity;
            sample.pdf *= self.adapter.opacity;
        }
        if self.adapter.shadowing_function {
            sample.value *= self.shadowing(wo_world, wi_world, mode);
        }
        Some(sample)
    }

    /// Importance transport through a frame that Mitsuba's flip makes
    /// depend on the sampled (camera-side) direction: the frame is chosen
    /// with probability ½ (by the component sample), the direction sampled
    /// from it, and the sample carries the value in the frame that
    /// direction picks and the density of the two frames' mixture
    /// ([`Self::pdf_in_mode`]). A delta lobe's direction counts only if it
    /// picks the frame it was sampled from.
    fn sample_from_both_frames(
        &self,
        wo_world: Vec3,
        u_component: f32,
        u: [f32; 2],
        wavelengths: &mut SampledWavelengths,
    ) -> Option<BsdfSample> {
        let flipped = u_component >= 0.5;
        let u_component = if flipped {
            2.0 * u_component - 1.0
        } else {
            2.0 * u_component
        }
        .min(1.0 - f32::EPSILON / 2.0);
        let frame = self.adapter.perturbed_frame(flipped, self.frame);
        let wo = frame.to_local(wo_world);
        if !self.adapter.sides_agree(wo_world, wo) {
            return None;
        }
        let mut sample = self.bsdf.sample(wo, u_component, u, wavelengths)?;
        let wi_world = frame.to_world(sample.wi);
        sample.wi = wi_world;
        if sample.is_specular() {
            if self.adapter.flipped_for(wi_world) != flipped {
                return None;
            }
            sample.value *= self.adapter.opacity * self.adapter.shadowing(wo_world);
            sample.pdf *= 0.5 * self.adapter.opacity;
            return Some(sample);
        }
        sample.value = self.evaluate(wo_world, wi_world, wavelengths);
        sample.pdf = self.pdf_in_mode(wo_world, wi_world, TransportMode::Importance);
        sample.pdf_is_proportional = false;
        (sample.pdf > 0.0 && !sample.value.is_black()).then_some(sample)
    }

    /// [`Bsdf::pdf`] for world-space directions.
    pub fn pdf(&self, wo_world: Vec3, wi_world: Vec3) -> f32 {
        self.pdf_in_mode(wo_world, wi_world, self.bsdf.transport_mode())
    }

    /// The density with which the BSDF in transport `mode` samples `wi`
    /// from `wo`: [`Self::pdf`] of the same surface on a subpath of the
    /// other kind. Bidirectional methods take reverse densities with the
    /// other mode (`pdf_in_mode(wi, wo, mode.other())`): the side check of
    /// perturbed frames applies to a different argument in each.
    ///
    /// With Mitsuba's flip, radiance transport samples in the frame the
    /// camera-side `wo` picks, importance transport from the two frames
    /// with probability ½ each (its density is their mixture's).
    pub fn pdf_in_mode(&self, wo_world: Vec3, wi_world: Vec3, mode: TransportMode) -> f32 {
        if self.adapter.has_mitsuba_options() {
            return self.pdf_with_mitsuba_options(wo_world, wi_world, mode);
        }
        self.local_pair(&self.frame, wo_world, wi_world, mode)
            .map_or(0.0, |(wo, wi)| self.bsdf.pdf(wo, wi) * self.adapter.opacity)
    }

    /// [`Self::pdf_in_mode`] of a perturbed frame with Mitsuba 3.7.1's flip
    /// or shadowing term (out of line).
    #[inline(never)]
    fn pdf_with_mitsuba_options(&self, wo_world: Vec3, wi_world: Vec3, mode: TransportMode) -> f32 {
        if self.adapter.opacity <= 0.0 {
            return 0.0;
        }
        if self.adapter.flips() && mode == TransportMode::Importance {
            let density = |flipped: bool| {
                let frame = self.adapter.perturbed_frame(flipped, self.frame);
                let wo = frame.to_local(wo_world);
                if !self.adapter.sides_agree(wo_world, wo) {
                    return 0.0;
                }
                self.bsdf.pdf(wo, frame.to_local(wi_world))
            };
            return 0.5 * (density(false) + density(true)) * self.adapter.opacity;
        }
        let frame = self.frame_for(wo_world, wi_world, mode);
        self.local_pair(&frame, wo_world, wi_world, mode)
            .map_or(0.0, |(wo, wi)| self.bsdf.pdf(wo, wi) * self.adapter.opacity)
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A one-sided Lambertian surface whose shading normal a normal map
    /// tilted by about 37° from the unperturbed one (the z axis).
    fn tilted(mode: TransportMode) -> SurfaceBsdf {
        tilted_with(mode, false)
    }

    /// [`tilted`], with Mitsuba 3.7.1's flip and shadowing term if
    /// `mitsuba`.
    fn tilted_with(mode: TransportMode, mitsuba: bool) -> SurfaceBsdf {
        let diffuse = DiffuseBsdf::one_sided(SampledSpectrum::splat(0.8)).unwrap();
        SurfaceBsdf {
            frame: ShadingFrame::from_normal(Vec3::new(0.6, 0.0, 0.8)).unwrap(),
            bsdf: Bsdf::new(BsdfModel::Diffuse(diffuse)).with_transport_mode(mode),
            adapter: SurfaceAdapter {
                opacity: 1.0,
                unperturbed_normal: Some(Vec3::Z),
                unperturbed_tangent: Vec3::X,
                perturbed_normal: Vec3::new(0.6, 0.0, 0.8),
                flip_invalid_normals: mitsuba,
                shadowing_function: mitsuba,
            },
        }
    }

    /// Directions on a grid over the sphere.
    fn directions() -> Vec<Vec3> {
        let mut directions = Vec::new();
        for i in 0..12 {
            for j in 0..24 {
                let theta = (i as f32 + 0.5) * std::f32::consts::PI / 12.0;
                let phi = j as f32 * std::f32::consts::TAU / 24.0;
                directions.push(Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ));
            }
        }
        directions
    }

    /// A path through a bump- or normal-mapped vertex has one value whichever
    /// subpath reaches it: the camera subpath's f(wo, wi) (wo towards the
    /// camera) equals the light subpath's adjoint f*(wi, wo), also where the
    /// side check of the perturbed frame passes for one direction and not
    /// for the other (it applies to the light's side in both modes); and the
    /// reverse density a camera vertex reports for the light subpath is the
    /// light subpath's own density. Before, each mode checked its second
    /// argument, so bidirectional strategies disagreed on such paths.
    /// The same with Mitsuba's flip and shadowing term, where the frame
    /// depends on the camera-side direction.
    #[test]
    fn perturbed_frames_give_both_transport_modes_one_path_value() {
        for mitsuba in [false, true] {
            both_transport_modes_give_one_path_value(mitsuba);
        }
    }

    fn both_transport_modes_give_one_path_value(mitsuba: bool) {
        let wavelengths = SampledWavelengths::sample_visible(0.5);
        let radiance = tilted_with(TransportMode::Radiance, mitsuba);
        let importance = tilted_with(TransportMode::Importance, mitsuba);
        let mut one_side_disagrees = 0;
        for &to_camera in &directions() {
            for &to_light in &directions() {
                let camera_value = radiance.evaluate(to_camera, to_light, &wavelengths);
                let light_value = importance.evaluate(to_light, to_camera, &wavelengths);
                assert_eq!(camera_value, light_value, "{to_camera} {to_light}");
                assert_eq!(
                    radiance.pdf_in_mode(to_light, to_camera, TransportMode::Importance),
                    importance.pdf(to_light, to_camera)
                );
                assert_eq!(
                    importance.pdf_in_mode(to_camera, to_light, TransportMode::Radiance),
                    radiance.pdf(to_camera, to_light)
                );
                assert_eq!(
                    radiance.shading_normal_for(to_camera, to_light, TransportMode::Radiance),
                    importance.shading_normal_for(to_light, to_camera, TransportMode::Importance)
                );
                let agrees = |w: Vec3| {
                    w.z * w.dot(radiance.shading_normal_for(
                        to_camera,
                        to_light,
                        TransportMode::Radiance,
                    )) > 0.0
                };
                if agrees(to_camera) != agrees(to_light) && !camera_value.is_black() {
                    one_side_disagrees += 1;
                }
            }
        }
        // The grid does reach the pairs where only one side agrees (with the
        // flip the camera side always agrees).
        assert!(mitsuba || one_side_disagrees > 0);
    }

    /// Sampling is unbiased in both transport modes with Mitsuba's flip
    /// (importance transport samples the camera-side direction from both
    /// frames, so the support of the value is covered): the mean of
    /// `value / pdf` over sampled directions equals the integral of the
    /// value over the sphere (midpoint rule, 400 × 800 cells), within four
    /// standard errors, for directions of arrival on both sides of the
    /// tilted normal; and every sample's value and density are what
    /// `evaluate` and `pdf` give.
    #[test]
    fn sampling_with_flipped_normals_is_unbiased_in_both_modes() {
        use crate::sampler::{PixelSampler, SampleSource};
        let wavelengths = SampledWavelengths::sample_visible(0.5);
        for mode in [TransportMode::Radiance, TransportMode::Importance] {
            let bsdf = tilted_with(mode, true);
            for given in [
                Vec3::new(-0.8, 0.0, 0.6),
                Vec3::new(0.3, 0.2, 0.93),
                Vec3::new(-0.95, 0.1, 0.2),
            ] {
                let given = given.normalize();
                let (rows, columns) = (400, 800);
                let mut integral = 0.0f64;
                for i in 0..rows {
                    let theta = (i as f64 + 0.5) * std::f64::consts::PI / rows as f64;
                    for j in 0..columns {
                        let phi = (j as f64 + 0.5) * std::f64::consts::TAU / columns as f64;
                        let w = Vec3::new(
                            (theta.sin() * phi.cos()) as f32,
                            (theta.sin() * phi.sin()) as f32,
                            theta.cos() as f32,
                        );
                        integral += bsdf.evaluate(given, w, &wavelengths)[0] as f64
                            * theta.sin()
                            * (std::f64::consts::PI / rows as f64)
                            * (std::f64::consts::TAU / columns as f64);
                    }
                }
                let mut random = crate::sampler::IndependentSampler::new(7);
                let count = 200_000;
                let (mut sum, mut sum_squares) = (0.0f64, 0.0f64);
                for index in 0..count {
                    random.start_pixel_sample((0, 0), index);
                    let mut lambdas = wavelengths;
                    let u_component = random.get(0);
                    let u = random.get_2d(1);
                    let Some(sample) = bsdf.sample(given, u_component, u, &mut lambdas) else {
                        continue;
                    };
                    let value = sample.value[0] as f64 / sample.pdf as f64;
                    assert!(
                        (sample.value[0] - bsdf.evaluate(given, sample.wi, &wavelengths)[0]).abs()
                            <= 1e-5 * sample.value[0].abs().max(1.0)
                    );
                    assert!(
                        (sample.pdf - bsdf.pdf(given, sample.wi)).abs()
                            <= 1e-5 * sample.pdf.max(1.0)
                    );
                    sum += value;
                    sum_squares += value * value;
                }
                let mean = sum / count as f64;
                let error = ((sum_squares / count as f64 - mean * mean) / count as f64).sqrt();
                assert!(
                    (mean - integral).abs() < 4.0 * error + 1e-4,
                    "{mode:?} {given}: sampled {mean} ± {error}, integral {integral}"
                );
            }
        }
    }

    /// Importance transport samples only from directions of arrival that
    /// pass the side check, and then never rejects the sampled direction.
    #[test]
    fn importance_sampling_checks_the_direction_of_arrival() {
        let mut wavelengths = SampledWavelengths::sample_visible(0.5);
        let importance = tilted(TransportMode::Importance);
        for &to_light in &directions() {
            let sample = importance.sample(to_light, 0.5, [0.3, 0.7], &mut wavelengths);
            let passes = to_light.z * to_light.dot(importance.frame.normal()) > 0.0;
            if !passes {
                assert!(sample.is_none(), "{to_light}");
            } else if let Some(sample) = sample {
                assert!(
                    (sample.pdf - importance.pdf(to_light, sample.wi)).abs() < 1e-5,
                    "{to_light}"
                );
            }
        }
    }
}
