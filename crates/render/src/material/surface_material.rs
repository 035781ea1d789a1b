//! [`Material`]: what a scene stores per shape, turned into a [`Bsdf`] at each
//! hit for the path's wavelengths.

use glam::Vec3;

use super::bsdf::{Bsdf, SurfaceBsdf};
use super::coated_conductor::CoatedConductorBsdf;
use super::conductor::{ConductorBsdf, ConductorReflectance};
use super::dielectric::DielectricBsdf;
use super::diffuse::DiffuseBsdf;
use super::error::MaterialError;
use super::layered::CoatedDiffuseBsdf;
use super::microfacet::{MicrofacetDistribution, MicrofacetKind};
use super::plastic::PlasticBsdf;
use super::principled_material::PrincipledMaterial;
use super::rough_conductor::RoughConductorBsdf;
use super::rough_dielectric::RoughDielectricBsdf;
use super::rough_plastic::{RoughPlasticBsdf, RoughPlasticTables};
use super::shading_frame::ShadingFrame;
use super::surface_adapter::{
    PerturbationOptions, SurfaceAdapter, bump_mapped_frame, normal_mapped_frame,
};
use super::thin_dielectric::ThinDielectricBsdf;
use crate::geometry::SurfaceHit;
use crate::spectrum::{
    SampledSpectrum, SampledWavelengths, Spectrum, VISIBLE_LAMBDA_MAX, VISIBLE_LAMBDA_MIN,
};
use crate::texture::{FloatTexture, RgbTexture, SpectrumTexture, TextureContext};

/// The roughness of a microfacet surface: the distribution and its α along
/// the shading frame's tangent (∂p/∂u) and bitangent, possibly textured.
#[derive(Debug, Clone, PartialEq)]
pub struct Roughness {
    /// GGX or Beckmann.
    pub kind: MicrofacetKind,
    /// α along the tangent.
    pub alpha_u: FloatTexture,
    /// α along the bitangent.
    pub alpha_v: FloatTexture,
    /// The textures hold pbrt-v4's perceptual roughness r; α = √r
    /// ([`MicrofacetDistribution::roughness_to_alpha`]).
    pub remap: bool,
}

impl Roughness {
    /// Isotropic roughness α, not remapped.
    pub fn isotropic(kind: MicrofacetKind, alpha: f32) -> Self {
        Self {
            kind,
            alpha_u: FloatTexture::Constant(alpha),
            alpha_v: FloatTexture::Constant(alpha),
            remap: false,
        }
    }

    /// The distribution at a hit.
    pub fn distribution(&self, context: &TextureContext) -> MicrofacetDistribution {
        let alpha = |texture: &FloatTexture| {
            let value = texture.evaluate(context);
            if self.remap {
                MicrofacetDistribution::roughness_to_alpha(value)
            } else {
                value
            }
        };
        MicrofacetDistribution::new(self.kind, alpha(&self.alpha_u), alpha(&self.alpha_v))
    }

    /// The distribution if α does not vary over the surface.
    pub fn constant_distribution(&self) -> Option<MicrofacetDistribution> {
        match (&self.alpha_u, &self.alpha_v) {
            (FloatTexture::Constant(_), FloatTexture::Constant(_)) => {
                let context = TextureContext {
                    uv: glam::Vec2::ZERO,
                    point: glam::Vec3::ZERO,
                };
                Some(self.distribution(&context))
            }
            _ => None,
        }
    }
}

/// The surface description of a shape.
///
/// Spectra are validated by [`Material::validate`] (the checked constructors
/// call it), once per scene; [`Material::bsdf`] then never fails. Building a
/// variant directly skips validation: `bsdf` still returns something usable
/// (see each variant for how bad values are treated), but the scene loader
/// should call `validate`.
#[derive(Debug, Clone, PartialEq)]
pub enum Material {
    /// Two-sided Lambertian reflection. Reflectance values are clamped to
    /// [0, 1] at each hit (as pbrt-v4's diffuse material does), so a
    /// reflectance spectrum cannot create energy.
    Diffuse {
        /// The albedo.
        reflectance: SpectrumTexture,
        /// Both faces reflect (pbrt-v4, Mitsuba `twosided`); otherwise the
        /// back is black (Mitsuba's plain `diffuse`).
        two_sided: bool,
    },
    /// A smooth metal with complex index of refraction `eta` + i`k` relative
    /// to the surrounding medium (tabulated data such as pbrt-v4's
    /// `metal-Cu-eta` / `metal-Cu-k`). Negative or NaN values are clamped to
    /// 0 at each hit.
    Conductor {
        /// Real part η of the index of refraction.
        eta: Spectrum,
        /// Extinction coefficient κ.
        k: Spectrum,
    },
    /// An ideal mirror: reflectance 1 at every angle and wavelength.
    Mirror,
    /// A smooth dielectric (glass, water) with index `eta` inside relative to
    /// the outside (the side the normal points to). A [`Spectrum::Constant`]
    /// index means no dispersion; any other spectrum is treated as dispersive
    /// (the BSDF keeps only the hero wavelength when it refracts). A value of
    /// 0, NaN or below at the hero wavelength (e.g. outside a table's range)
    /// is treated as 1, an index-matched interface, as pbrt-v4 does.
    Dielectric {
        /// Relative index of refraction.
        eta: Spectrum,
    },
    /// A conductor in Mitsuba 3's general form (`conductor` /
    /// `roughconductor`): Fresnel reflectance of `eta` + i`k` (η = κ = 0: a
    /// perfect mirror) times `specular_reflectance` (clamped to [0, 1]),
    /// smooth when `roughness` is `None`, black from behind unless
    /// `two_sided`. A rough surface whose α is below
    /// [`super::SMOOTH_ALPHA_THRESHOLD`] is rendered smooth.
    RoughConductor {
        eta: Spectrum,
        k: Spectrum,
        specular_reflectance: Option<SpectrumTexture>,
        roughness: Option<Roughness>,
        two_sided: bool,
    },
    /// A rough dielectric interface (Walter et al. 2007) with relative index
    /// `eta` inside over outside (treated as [`Material::Dielectric`] where α
    /// is below [`super::SMOOTH_ALPHA_THRESHOLD`]).
    RoughDielectric { eta: Spectrum, roughness: Roughness },
    /// A thin dielectric sheet of relative index `eta`.
    ThinDielectric { eta: f32 },
    /// A diffuse base under a dielectric coating of relative index `eta`
    /// (Mitsuba 3's `plastic`, or `roughplastic` with a `coating`
    /// distribution, whose α must be constant).
    Plastic {
        diffuse_reflectance: SpectrumTexture,
        eta: f32,
        coating: Option<MicrofacetDistribution>,
        nonlinear: bool,
        two_sided: bool,
    },
    /// Mitsuba's `principled` or `principledthin` (Disney) BSDF.
    Principled(Box<PrincipledMaterial>),
    /// pbrt-v4's `coateddiffuse` ([`CoatedDiffuseBsdf`]): a diffuse base of
    /// albedo `reflectance` (clamped to [0, 1]) under a dielectric coating of
    /// relative index `eta`, smooth when `roughness` is `None`, over a layer
    /// of optical thickness `thickness` whose medium has albedo `albedo`
    /// (clamped to [0, 1]) and Henyey–Greenstein asymmetry `g`; walks of at
    /// most `max_depth` events, `samples` per evaluation. Two-sided.
    CoatedDiffuse {
        reflectance: SpectrumTexture,
        eta: f32,
        roughness: Option<Roughness>,
        thickness: f32,
        albedo: SpectrumTexture,
        g: f32,
        max_depth: u32,
        samples: u32,
    },
    /// pbrt-v4's `coatedconductor` ([`CoatedConductorBsdf`]): a conductor
    /// of index `conductor_eta` + i`conductor_k` (relative to the outside,
    /// as in the scene file; negative values are clamped to 0 at each hit,
    /// and both are divided by `interface_eta` for the conductor's
    /// interface with the coating, as pbrt-v4 does), smooth when
    /// `conductor_roughness` is `None`, under a dielectric coating of
    /// relative index `interface_eta`, smooth when `interface_roughness` is
    /// `None`, over a layer of optical thickness `thickness` whose medium
    /// has albedo `albedo` (clamped to [0, 1]) and Henyey–Greenstein
    /// asymmetry `g`; walks of at most `max_depth` events, `samples` per
    /// evaluation. Two-sided.
    CoatedConductor {
        interface_eta: f32,
        interface_roughness: Option<Roughness>,
        conductor_eta: Spectrum,
        conductor_k: Spectrum,
        conductor_roughness: Option<Roughness>,
        thickness: f32,
        albedo: SpectrumTexture,
        g: f32,
        max_depth: u32,
        samples: u32,
    },
    /// `front` where light arrives from the side the normal points to,
    /// `back` (seen as its own front) where it arrives from behind
    /// (Mitsuba's `twosided` with two children). Bump maps and masks inside
    /// `back` are ignored; those of `front` apply to both sides.
    TwoSided {
        front: Box<Material>,
        back: Box<Material>,
    },
    /// `nested` with the shading normal tilted by the height field `height`
    /// times `scale` (Mitsuba `bumpmap`; see [`bump_mapped_frame`]).
    BumpMap {
        height: FloatTexture,
        scale: f32,
        nested: Box<Material>,
        /// Mitsuba's flip and shadowing term.
        options: PerturbationOptions,
    },
    /// `nested` with the shading normal read from `normals`, a tangent-space
    /// normal encoded as RGB in [0, 1] (Mitsuba `normalmap`; see
    /// [`normal_mapped_frame`]).
    NormalMap {
        normals: RgbTexture,
        nested: Box<Material>,
        /// Mitsuba's flip and shadowing term.
        options: PerturbationOptions,
    },
    /// `nested` with probability `opacity` (clamped to [0, 1]), otherwise
    /// light passes straight through (Mitsuba `mask`; see [`SurfaceAdapter`]).
    Mask {
        opacity: FloatTexture,
        nested: Box<Material>,
    },
}

impl Material {
    /// A validated [`Material::Diffuse`].
    pub fn diffuse(reflectance: Spectrum) -> Result<Self, MaterialError> {
        let material = Material::Diffuse {
            reflectance: SpectrumTexture::Constant(reflectance),
            two_sided: true,
        };
        material.validate()?;
        Ok(material)
    }

    /// A validated [`Material::Conductor`].
    pub fn conductor(eta: Spectrum, k: Spectrum) -> Result<Self, MaterialError> {
        let material = Material::Conductor { eta, k };
        material.validate()?;
        Ok(material)
    }

    /// A validated [`Material::Dielectric`].
    pub fn dielectric(eta: Spectrum) -> Result<Self, MaterialError> {
        let material = Material::Dielectric { eta };
        material.validate()?;
        Ok(material)
    }

    /// Checks the spectra at every integer wavelength of the visible range
    /// ([`VISIBLE_LAMBDA_MIN`]–[`VISIBLE_LAMBDA_MAX`] nm, where paths sample
    /// wavelengths): reflectances, η and κ must be finite and non-negative; a
    /// dielectric's η must be positive somewhere (a zero is allowed, e.g.
    /// outside a table's range, but logged as a warning since it makes the
    /// interface invisible there).
    pub fn validate(&self) -> Result<(), MaterialError> {
        match self {
            Material::Diffuse { reflectance, .. } => match reflectance.as_constant() {
                Some(reflectance) => check_finite_non_negative("diffuse reflectance", reflectance),
                None => Ok(()),
            },
            Material::Conductor { eta, k } => {
                check_finite_non_negative("conductor eta", eta)?;
                check_finite_non_negative("conductor k", k)
            }
            Material::Mirror => Ok(()),
            Material::RoughConductor { eta, k, .. } => {
                check_finite_non_negative("conductor eta", eta)?;
                check_finite_non_negative("conductor k", k)
            }
            Material::RoughDielectric { eta, .. } => {
                Material::Dielectric { eta: eta.clone() }.validate()
            }
            Material::CoatedConductor {
                interface_eta,
                conductor_eta,
                conductor_k,
                thickness,
                g,
                ..
            } => {
                check_finite_non_negative("coated conductor eta", conductor_eta)?;
                check_finite_non_negative("coated conductor k", conductor_k)?;
                validate_layer(*interface_eta, *thickness, *g)
            }
            Material::CoatedDiffuse {
                eta, thickness, g, ..
            } => validate_layer(*eta, *thickness, *g),
            Material::ThinDielectric { eta } | Material::Plastic { eta, .. } => {
                if eta.is_finite() && *eta > 0.0 {
                    Ok(())
                } else {
                    Err(MaterialError::NonPositiveIndexOfRefraction { value: *eta })
                }
            }
            Material::Principled(_) => Ok(()),
            Material::TwoSided { front, back } => {
                front.validate()?;
                back.validate()
            }
            Material::BumpMap { nested, .. }
            | Material::NormalMap { nested, .. }
            | Material::Mask { nested, .. } => nested.validate(),
            Material::Dielectric { eta } => {
                check_finite_non_negative("dielectric eta", eta)?;
                let zeros = visible_wavelengths()
                    .filter(|&lambda| eta.evaluate(lambda) == 0.0)
                    .count();
                if zeros == visible_wavelengths().count() {
                    return Err(MaterialError::NonPositiveIndexOfRefraction { value: 0.0 });
                }
                if zeros > 0 {
                    log::warn!(
                        "dielectric index of refraction is 0 at {zeros} visible wavelengths; \
                         the interface is index-matched (invisible) there"
                    );
                }
                Ok(())
            }
        }
    }

    /// The local-frame BSDF at a hit for the path's `wavelengths`, in
    /// [`crate::material::TransportMode::Radiance`] (use
    /// [`Bsdf::with_transport_mode`] for light paths).
    ///
    /// Textures are looked up at uv = (0, 0); integrators use
    /// [`Self::surface_bsdf_at`].
    pub fn bsdf(&self, wavelengths: &SampledWavelengths) -> Bsdf {
        let context = TextureContext {
            uv: glam::Vec2::ZERO,
            point: glam::Vec3::ZERO,
        };
        self.bsdf_with_context(&context, wavelengths)
    }

    /// The local-frame BSDF with textures evaluated at `context`.
    pub fn bsdf_with_context(
        &self,
        context: &TextureContext,
        wavelengths: &SampledWavelengths,
    ) -> Bsdf {
        match self {
            Material::Diffuse {
                reflectance,
                two_sided,
            } => diffuse_bsdf(reflectance, *two_sided, context, wavelengths),
            Material::Conductor { eta, k } => ConductorBsdf::new_unchecked(
                eta.sample(wavelengths).clamp_zero(),
                k.sample(wavelengths).clamp_zero(),
            )
            .into(),
            Material::Mirror => ConductorBsdf::perfect_mirror().into(),
            Material::Dielectric { eta } => {
                let (hero_eta, dispersive) = hero_index(eta, wavelengths);
                DielectricBsdf::new_unchecked(hero_eta, dispersive).into()
            }
            Material::RoughConductor {
                eta,
                k,
                specular_reflectance,
                roughness,
                two_sided,
            } => {
                let eta = eta.sample(wavelengths).clamp_zero();
                let k = k.sample(wavelengths).clamp_zero();
                let reflectance = if eta.is_black() && k.is_black() {
                    ConductorReflectance::Perfect
                } else {
                    ConductorReflectance::Fresnel { eta, k }
                };
                let factor = specular_reflectance
                    .as_ref()
                    .map(|texture| texture.evaluate(context, wavelengths).clamp(0.0, 1.0))
                    .unwrap_or(SampledSpectrum::splat(1.0));
                let distribution = roughness
                    .as_ref()
                    .map(|roughness| roughness.distribution(context))
                    .filter(|distribution| !distribution.is_effectively_smooth());
                match distribution {
                    Some(distribution) => {
                        RoughConductorBsdf::new(distribution, reflectance, factor, *two_sided)
                            .into()
                    }
                    None => {
                        let smooth = match reflectance {
                            ConductorReflectance::Perfect => ConductorBsdf::perfect_mirror(),
                            ConductorReflectance::Fresnel { eta, k } => {
                                ConductorBsdf::new_unchecked(eta, k)
                            }
                        };
                        smooth
                            .with_specular_factor(factor)
                            .with_two_sided(*two_sided)
                            .into()
                    }
                }
            }
            Material::RoughDielectric { eta, roughness } => {
                let (hero_eta, dispersive) = hero_index(eta, wavelengths);
                let distribution = roughness.distribution(context);
                if distribution.is_effectively_smooth() || hero_eta == 1.0 {
                    DielectricBsdf::new_unchecked(hero_eta, dispersive).into()
                } else {
                    RoughDielectricBsdf::new(distribution, hero_eta, dispersive).into()
                }
            }
            Material::ThinDielectric { eta } => ThinDielectricBsdf::new(*eta).into(),
            Material::Plastic {
                diffuse_reflectance,
                eta,
                coating,
                nonlinear,
                two_sided,
            } => {
                let diffuse = diffuse_reflectance
                    .evaluate(context, wavelengths)
                    .clamp(0.0, 1.0);
                match coating.filter(|coating| !coating.is_effectively_smooth()) {
                    Some(coating) => RoughPlasticBsdf::new(
                        coating,
                        RoughPlasticTables::shared(&coating, *eta),
                        diffuse,
                        *eta,
                        *nonlinear,
                        *two_sided,
                    )
                    .into(),
                    None => PlasticBsdf::new(diffuse, *eta, *nonlinear, *two_sided).into(),
                }
            }
            Material::Principled(principled) => principled.bsdf(context, wavelengths),
            Material::CoatedDiffuse {
                reflectance,
                eta,
                roughness,
                thickness,
                albedo,
                g,
                max_depth,
                samples,
            } => CoatedDiffuseBsdf::new(
                reflectance.evaluate(context, wavelengths).clamp(0.0, 1.0),
                *eta,
                roughness
                    .as_ref()
                    .map(|roughness| roughness.distribution(context)),
                *thickness,
                albedo.evaluate(context, wavelengths).clamp(0.0, 1.0),
                *g,
                *max_depth,
                *samples,
            )
            .into(),
            Material::CoatedConductor {
                interface_eta,
                interface_roughness,
                conductor_eta,
                conductor_k,
                conductor_roughness,
                thickness,
                albedo,
                g,
                max_depth,
                samples,
            } => {
                // The conductor's index relative to the coating (pbrt-v4).
                let relative = 1.0 / *interface_eta;
                let conductor = ConductorReflectance::Fresnel {
                    eta: conductor_eta.sample(wavelengths).clamp_zero() * relative,
                    k: conductor_k.sample(wavelengths).clamp_zero() * relative,
                };
                let distribution = |roughness: &Option<Roughness>| {
                    roughness
                        .as_ref()
                        .map(|roughness| roughness.distribution(context))
                };
                CoatedConductorBsdf::new(
                    *interface_eta,
                    distribution(interface_roughness),
                    conductor,
                    distribution(conductor_roughness),
                    *thickness,
                    albedo.evaluate(context, wavelengths).clamp(0.0, 1.0),
                    *g,
                    *max_depth,
                    *samples,
                )
                .into()
            }
            Material::TwoSided { front, back } => Bsdf::two_sided(
                *front.bsdf_with_context(context, wavelengths).model(),
                *back.bsdf_with_context(context, wavelengths).model(),
            ),
            Material::BumpMap { nested, .. }
            | Material::NormalMap { nested, .. }
            | Material::Mask { nested, .. } => nested.bsdf_with_context(context, wavelengths),
        }
    }

    /// The BSDF at a surface hit, for world-space directions: textures are
    /// evaluated at the hit and the shading frame built from its shading
    /// normal and `∂p/∂u` (so anisotropic roughness follows the surface's
    /// parameterisation). This is what integrators call; `hit` must already
    /// be oriented (normals flipped for shapes with `flip_normals`).
    ///
    /// Lambertian reflection, the common case, is built here (inline in the
    /// integrator) without the generic dispatch; every other material goes
    /// through the out-of-line [`Self::surface_bsdf_at_general`].
    #[inline]
    pub fn surface_bsdf_at(
        &self,
        hit: &SurfaceHit,
        wavelengths: &SampledWavelengths,
    ) -> SurfaceBsdf {
        if let Material::Diffuse {
            reflectance,
            two_sided,
        } = self
        {
            let context = TextureContext::from_hit(hit);
            return SurfaceBsdf {
                frame: isotropic_frame(hit.shading_normal),
                bsdf: diffuse_bsdf(reflectance, *two_sided, &context, wavelengths),
                adapter: SurfaceAdapter::NONE,
            };
        }
        self.surface_bsdf_at_general(hit, wavelengths)
    }

    /// [`Self::surface_bsdf_at`] for every material but the plain diffuse
    /// one: kept out of line so that the common case inlines small.
    #[inline(never)]
    fn surface_bsdf_at_general(
        &self,
        hit: &SurfaceHit,
        wavelengths: &SampledWavelengths,
    ) -> SurfaceBsdf {
        let context = TextureContext::from_hit(hit);
        let frame = if self.is_tangent_independent() {
            isotropic_frame(hit.shading_normal)
        } else {
            ShadingFrame::from_normal_and_tangent(hit.shading_normal, hit.dpdu)
                .unwrap_or_else(|_| ShadingFrame::from_unit_normal(hit.shading_normal))
        };
        self.surface_bsdf_in_frame(hit, &context, frame, SurfaceAdapter::NONE, wavelengths)
    }

    /// Whether the BSDF is unchanged by rotating the shading frame about its
    /// normal (no anisotropic lobe, no bump or normal map reading ∂p/∂u), so
    /// that any tangent will do and [`ShadingFrame::from_unit_normal`]'s
    /// cheap one can replace ∂p/∂u made orthogonal to the normal. Only the
    /// frame's orientation about the normal changes, hence which random
    /// numbers pick which direction, never the distribution sampled.
    fn is_tangent_independent(&self) -> bool {
        match self {
            Material::Diffuse { .. }
            | Material::Conductor { .. }
            | Material::Mirror
            | Material::Dielectric { .. }
            | Material::ThinDielectric { .. } => true,
            Material::RoughConductor { roughness, .. } => roughness.is_none(),
            Material::Plastic { coating, .. } => coating.is_none(),
            Material::TwoSided { front, back } => {
                front.is_tangent_independent() && back.is_tangent_independent()
            }
            Material::Mask { nested, .. } => nested.is_tangent_independent(),
            _ => false,
        }
    }

    /// [`Self::surface_bsdf_at`] in `frame` (perturbed by enclosing bump or
    /// normal maps) with the `adapter` of enclosing masks.
    fn surface_bsdf_in_frame(
        &self,
        hit: &SurfaceHit,
        context: &TextureContext,
        frame: ShadingFrame,
        mut adapter: SurfaceAdapter,
        wavelengths: &SampledWavelengths,
    ) -> SurfaceBsdf {
        match self {
            Material::BumpMap {
                height,
                scale,
                nested,
                options,
            } => {
                let gradient = height.gradient(context) * *scale;
                let perturbed =
                    bump_mapped_frame(&frame, hit.geometric_normal, hit.dpdu, hit.dpdv, gradient);
                adapter.perturb(&frame, &perturbed, *options);
                nested.surface_bsdf_in_frame(hit, context, perturbed, adapter, wavelengths)
            }
            Material::NormalMap {
                normals,
                nested,
                options,
            } => {
                let perturbed = normal_mapped_frame(&frame, normals.evaluate(context));
                adapter.perturb(&frame, &perturbed, *options);
                nested.surface_bsdf_in_frame(hit, context, perturbed, adapter, wavelengths)
            }
            Material::TwoSided { front, back } => {
                let mut surface =
                    front.surface_bsdf_in_frame(hit, context, frame, adapter, wavelengths);
                let back = back.bsdf_with_context(context, wavelengths);
                surface.bsdf = Bsdf::two_sided(*surface.bsdf.model(), *back.model());
                surface
            }
            Material::Mask { opacity, nested } => {
                let opacity = opacity.evaluate(context);
                adapter.opacity *= if opacity.is_nan() {
                    1.0
                } else {
                    opacity.clamp(0.0, 1.0)
                };
                nested.surface_bsdf_in_frame(hit, context, frame, adapter, wavelengths)
            }
            _ => SurfaceBsdf {
                frame,
                bsdf: self.bsdf_with_context(context, wavelengths),
                adapter,
            },
        }
    }

    /// The BSDF at a hit placed in the hit's shading frame, for world-space
    /// directions.
    pub fn surface_bsdf(
        &self,
        frame: ShadingFrame,
        wavelengths: &SampledWavelengths,
    ) -> SurfaceBsdf {
        SurfaceBsdf {
            frame,
            bsdf: self.bsdf(wavelengths),
            adapter: SurfaceAdapter::NONE,
        }
    }
}

/// The Lambertian BSDF of [`Material::Diffuse`] with its reflectance
/// evaluated at `context` and clamped to [0, 1].
#[inline]
fn diffuse_bsdf(
    reflectance: &SpectrumTexture,
    two_sided: bool,
    context: &TextureContext,
    wavelengths: &SampledWavelengths,
) -> Bsdf {
    DiffuseBsdf::new_unchecked(
        reflectance.evaluate(context, wavelengths).clamp(0.0, 1.0),
        two_sided,
    )
    .into()
}

/// The shading frame of a BSDF that does not depend on the tangent: the
/// branchless basis of [`ShadingFrame::from_unit_normal`] around the shading
/// normal (normalised first only if it is not unit length already), a
/// deterministic function of the hit.
#[inline]
fn isotropic_frame(shading_normal: Vec3) -> ShadingFrame {
    if (shading_normal.length_squared() - 1.0).abs() < 1e-5 {
        ShadingFrame::from_unit_normal(shading_normal)
    } else {
        ShadingFrame::from_normal(shading_normal)
            .unwrap_or_else(|_| ShadingFrame::from_unit_normal(shading_normal))
    }
}

/// A dielectric's index at the hero wavelength (1, index-matched, where it
/// is 0, NaN or negative, as pbrt-v4 does) and whether it is dispersive
/// (any spectrum but a constant).
fn hero_index(eta: &Spectrum, wavelengths: &SampledWavelengths) -> (f32, bool) {
    let hero_eta = eta.evaluate(wavelengths.hero());
    let hero_eta = if hero_eta.is_finite() && hero_eta > 0.0 {
        hero_eta
    } else {
        1.0
    };
    (hero_eta, !matches!(eta, Spectrum::Constant(_)))
}

/// Every integer wavelength (nm) of the visible range.
fn visible_wavelengths() -> impl Iterator<Item = f32> {
    (VISIBLE_LAMBDA_MIN as i32..=VISIBLE_LAMBDA_MAX as i32).map(|lambda| lambda as f32)
}

/// [`MaterialError::InvalidSpectrumValue`] at the first visible wavelength
/// where `spectrum` is NaN, infinite or negative.
/// The checks shared by the layered materials: a positive finite coating
/// index, a finite non-negative thickness, a finite asymmetry g.
fn validate_layer(eta: f32, thickness: f32, g: f32) -> Result<(), MaterialError> {
    if !(eta.is_finite() && eta > 0.0) {
        return Err(MaterialError::NonPositiveIndexOfRefraction { value: eta });
    }
    if !(thickness.is_finite() && thickness >= 0.0) {
        return Err(MaterialError::InvalidValue {
            what: "layer thickness",
            requirement: "finite and non-negative",
            value: thickness,
        });
    }
    if !g.is_finite() {
        return Err(MaterialError::InvalidValue {
            what: "layer g",
            requirement: "finite",
            value: g,
        });
    }
    Ok(())
}

fn check_finite_non_negative(what: &'static str, spectrum: &Spectrum) -> Result<(), MaterialError> {
    for lambda in visible_wavelengths() {
        let value = spectrum.evaluate(lambda);
        if !(value.is_finite() && value >= 0.0) {
            return Err(MaterialError::InvalidSpectrumValue {
                what,
                requirement: "finite and non-negative",
                value,
                lambda,
            });
        }
    }
    Ok(())
}
