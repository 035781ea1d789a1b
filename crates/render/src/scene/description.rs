//! A renderer-independent description of a scene: what the built-in scenes
//! and the scene-file loaders produce, and what [`super::Scene::build`] turns
//! into the structures the integrators trace. Colours are linear sRGB
//! triples; they become spectra when the scene is built.

use crate::camera::PerspectiveSettings;
/// The enums of the layers that use them, named here too so that loaders
/// describe scenes with one import.
pub use crate::light::{EnvironmentProjection, SpotFalloff};
pub use crate::texture::{ColourEncoding, TextureFilter, TextureWrap};
use glam::{Affine2, Affine3A, Vec2, Vec3};
use std::path::PathBuf;

/// A whole scene.
#[derive(Debug, Clone)]
pub struct SceneDescription {
    /// A short name for logs and metadata.
    pub name: String,
    /// The camera (its resolution is the image's).
    pub camera: PerspectiveSettings,
    /// The reconstruction filter.
    pub filter: FilterDescription,
    /// Surfaces, each with a material and optional emission.
    pub shapes: Vec<ShapeDescription>,
    /// Lights that are not shapes.
    pub lights: Vec<LightDescription>,
    /// Participating media, referred to by index from shapes and the camera.
    pub media: Vec<MediumDescription>,
    /// The medium the camera sits in (index into `media`), if any.
    pub camera_medium: Option<usize>,
    /// The scene's suggested maximum path depth (Mitsuba's convention: the
    /// number of path segments; 1 shows emitters only), if it names one.
    pub max_depth: Option<u32>,
    /// The scene's suggested samples per pixel, if it names any.
    pub samples_per_pixel: Option<u64>,
    /// The scene's suggested depth from which Russian roulette may end paths
    /// (Mitsuba's `rr_depth` convention), if it names one.
    pub russian_roulette_depth: Option<u32>,
    /// The integrator the scene file names (e.g. `path`, `volpath`,
    /// `direct`), as a hint; the command line decides.
    pub integrator: Option<String>,
}

/// The pixel reconstruction filter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum FilterDescription {
    /// Box of the given radius in pixels (0.5: one pixel).
    Box { radius: f32 },
    /// Tent (triangle) of the given radius.
    Tent { radius: f32 },
    /// Gaussian with radius and standard deviation.
    Gaussian { radius: f32, sigma: f32 },
}

/// One surface.
#[derive(Debug, Clone)]
pub struct ShapeDescription {
    /// Its geometry.
    pub geometry: ShapeGeometry,
    /// Its material.
    pub material: MaterialDescription,
    /// Emitted radiance if the surface is an area light; emission leaves the
    /// front side only (the side the normals point to, after `flip_normals`).
    pub emission: Option<SpectrumDescription>,
    /// Emitted radiance varying over the surface's uv (Mitsuba's `area`
    /// emitter with a texture); when set it replaces `emission`. Its RGB
    /// values are reflectance-like spectra, without D65, as Mitsuba 3
    /// evaluates them.
    pub emission_texture: Option<TextureDescription>,
    /// Flip the normals (e.g. to see the inside of a sphere as its front).
    pub flip_normals: bool,
    /// The medium inside the shape (the side opposite its normals), as an
    /// index into [`SceneDescription::media`]; `None` for vacuum.
    pub interior_medium: Option<usize>,
    /// The medium outside the shape (the side its normals point to).
    pub exterior_medium: Option<usize>,
}

/// The geometry of a shape.
#[derive(Debug, Clone)]
pub enum ShapeGeometry {
    /// A triangle mesh in world space; counter-clockwise triangles (seen from
    /// the front) face their geometric normal.
    Mesh {
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        /// Texture coordinates per vertex (pbrt's default per-triangle
        /// parameterisation when `None`).
        uvs: Option<Vec<Vec2>>,
        triangles: Vec<[u32; 3]>,
    },
    /// A sphere.
    Sphere { center: Vec3, radius: f32 },
    /// The square [−1, 1]² in z = 0 with normal +z, transformed.
    Rectangle { to_world: Affine3A },
    /// The cube [−1, 1]³ with outward normals, transformed.
    Cube { to_world: Affine3A },
    /// The unit disk in z = 0 with normal +z, transformed.
    Disk { to_world: Affine3A },
}

/// A spectral quantity as scene files give it. What an RGB triple means
/// (a reflectance in [0, 1], an unbounded quantity such as an index of
/// refraction, or an illuminant relative to D65) depends on where it is
/// used; [`super::Scene::build`] decides.
#[derive(Debug, Clone, PartialEq)]
pub enum SpectrumDescription {
    /// Linear sRGB.
    Rgb([f32; 3]),
    /// The same value at every wavelength (Mitsuba's `<float>` where a
    /// spectrum is expected). Illuminants given this way are still
    /// multiplied by nothing: the value is radiance per nm as is.
    Constant(f32),
    /// Piecewise-linear samples: wavelengths (nm, increasing) and values.
    Sampled {
        wavelengths: Vec<f32>,
        values: Vec<f32>,
    },
    /// A spectrum named by the file: pbrt-v4's named spectra
    /// (`metal-Cu-eta`, `glass-BK7`, `stdillum-D65`, ...) or Mitsuba's
    /// conductor names resolved by the loader into these.
    Named(String),
    /// Planck's law at `temperature` kelvin, normalised to a maximum of 1.
    Blackbody { temperature: f32 },
    /// Another spectrum times a factor (light `scale`s, `power` parameters).
    Scaled {
        scale: f32,
        spectrum: Box<SpectrumDescription>,
    },
}

/// A value that may vary over a surface: a spectrum or a scalar (the same
/// description serves both; scalar uses read one channel or the average).
#[derive(Debug, Clone, PartialEq)]
pub enum TextureDescription {
    /// The same value everywhere.
    Constant(SpectrumDescription),
    /// An image file (PNG, JPEG, EXR, PFM, BMP) looked up by the surface's uv.
    Bitmap {
        /// The file, resolved against the scene file's search paths.
        filename: PathBuf,
        /// `None`: what the format implies (8-bit: sRGB; float formats: linear).
        encoding: Option<ColourEncoding>,
        filter: TextureFilter,
        wrap: TextureWrap,
        /// Maps the surface's uv to the texture's (Mitsuba's `to_uv`, pbrt's
        /// `uscale`/`vscale`/`udelta`/`vdelta`).
        to_uv: Affine2,
        /// Flip the image vertically (pbrt-v4 puts v = 0 at the bottom row;
        /// Mitsuba at the top). Loaders set what their renderer does.
        flip_vertically: bool,
        /// Multiply the looked-up value (pbrt's `scale`).
        scale: f32,
        /// Use 1 − value (pbrt's `invert`).
        invert: bool,
    },
    /// Alternating squares of two textures, one square per unit of the
    /// transformed uv (Mitsuba: 2×2 squares over [0, 1]² before `to_uv`).
    Checkerboard {
        even: Box<TextureDescription>,
        odd: Box<TextureDescription>,
        to_uv: Affine2,
    },
}

/// The microfacet normal distribution of a rough surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MicrofacetDistribution {
    /// Trowbridge–Reitz (GGX), the default.
    Ggx,
    /// Beckmann–Spizzichino.
    Beckmann,
}

/// The roughness of a microfacet surface.
#[derive(Debug, Clone, PartialEq)]
pub struct RoughnessDescription {
    pub distribution: MicrofacetDistribution,
    /// Roughness α along the shading frame's tangent (∂p/∂u).
    pub alpha_u: TextureDescription,
    /// Roughness α along the bitangent.
    pub alpha_v: TextureDescription,
    /// Convert the values with pbrt-v4's `RoughnessToAlpha` (α = √r) first.
    pub remap: bool,
}

/// A surface material.
///
/// `two_sided`: pbrt-v4's materials scatter the same way from both sides;
/// Mitsuba 3's diffuse, conductor and plastic BSDFs are black from behind
/// unless wrapped in `twosided`. The built-in scenes use two-sided materials.
#[derive(Debug, Clone, PartialEq)]
pub enum MaterialDescription {
    /// Lambertian reflection.
    Diffuse {
        reflectance: TextureDescription,
        two_sided: bool,
    },
    /// A perfect mirror (two-sided).
    Mirror,
    /// A conductor with complex index of refraction `eta` + i`k` relative
    /// to the outside; smooth when `roughness` is `None`.
    Conductor {
        eta: SpectrumDescription,
        k: SpectrumDescription,
        /// A factor on the Fresnel reflectance (Mitsuba's
        /// `specular_reflectance`); `None` for 1.
        specular_reflectance: Option<TextureDescription>,
        roughness: Option<RoughnessDescription>,
        two_sided: bool,
    },
    /// A dielectric interface with index `interior_ior` inside (opposite the
    /// normals) and `exterior_ior` outside; smooth when `roughness` is `None`.
    Dielectric {
        interior_ior: SpectrumDescription,
        exterior_ior: f32,
        roughness: Option<RoughnessDescription>,
    },
    /// A thin dielectric sheet (Mitsuba `thindielectric`, pbrt
    /// `thindielectric`): reflection and straight-through transmission with
    /// the sheet's internal reflections summed.
    ThinDielectric {
        interior_ior: f32,
        exterior_ior: f32,
    },
    /// A diffuse base under a dielectric coating (Mitsuba `plastic` /
    /// `roughplastic`); smooth when `roughness` is `None`.
    Plastic {
        diffuse_reflectance: TextureDescription,
        interior_ior: f32,
        exterior_ior: f32,
        roughness: Option<RoughnessDescription>,
        /// Mitsuba's `nonlinear`: account for colour shifts of internal scattering.
        nonlinear: bool,
        two_sided: bool,
    },
    /// pbrt-v4's `coateddiffuse` (a stochastically evaluated layered BSDF):
    /// a diffuse base under a dielectric coating, with a medium of albedo
    /// `albedo` and Henyey–Greenstein asymmetry `g` in a layer of optical
    /// thickness `thickness`; random walks of at most `max_depth` events,
    /// `samples` per evaluation (pbrt-v4's defaults: reflectance 0.5, eta
    /// 1.5, roughness 0, thickness 0.01, albedo 0, g 0, maxdepth 10,
    /// nsamples 1).
    CoatedDiffuse {
        reflectance: TextureDescription,
        interior_ior: f32,
        roughness: Option<RoughnessDescription>,
        thickness: f32,
        albedo: TextureDescription,
        g: f32,
        max_depth: u32,
        samples: u32,
    },
    /// pbrt-v4's `coatedconductor` (a stochastically evaluated layered
    /// BSDF): a conductor of index `conductor_eta` + i`conductor_k` (relative
    /// to the outside; divided by `interface_ior` when built), smooth when
    /// `conductor_roughness` is `None`, under a dielectric coating of index
    /// `interface_ior`, smooth when `interface_roughness` is `None`, with a
    /// medium of albedo `albedo` and asymmetry `g` in a layer of optical
    /// thickness `thickness`; walks of at most `max_depth` events, `samples`
    /// per evaluation (pbrt-v4's defaults: interface roughness 0, eta 1.5,
    /// conductor `metal-Cu-eta` / `metal-Cu-k`, roughness 0, thickness 0.01,
    /// albedo 0, g 0, maxdepth 10, nsamples 1).
    CoatedConductor {
        interface_ior: f32,
        interface_roughness: Option<RoughnessDescription>,
        conductor_eta: SpectrumDescription,
        conductor_k: SpectrumDescription,
        conductor_roughness: Option<RoughnessDescription>,
        thickness: f32,
        albedo: TextureDescription,
        g: f32,
        max_depth: u32,
        samples: u32,
    },
    /// Different materials on the front and back (Mitsuba `twosided` with two
    /// children).
    TwoSided {
        front: Box<MaterialDescription>,
        back: Box<MaterialDescription>,
    },
    /// Bump mapping: the shading normal follows the gradient of a height field.
    BumpMap {
        height: TextureDescription,
        scale: f32,
        nested: Box<MaterialDescription>,
        /// Mitsuba 3.7.1's flip and shadowing term (on in Mitsuba files).
        options: crate::material::PerturbationOptions,
    },
    /// Normal mapping: the shading normal read from an RGB image (tangent space).
    NormalMap {
        normals: TextureDescription,
        nested: Box<MaterialDescription>,
        /// Mitsuba 3.7.1's flip and shadowing term (on in Mitsuba files).
        options: crate::material::PerturbationOptions,
    },
    /// Partly transparent: `opacity` of the time the nested material, else
    /// pass straight through (Mitsuba `mask`).
    Mask {
        opacity: TextureDescription,
        nested: Box<MaterialDescription>,
    },
    /// An index-matched boundary that only separates media (Mitsuba `null`,
    /// pbrt `interface`): rays pass straight through.
    Interface,
    /// Absorbs everything (e.g. the back of a light).
    Black,
    /// Mitsuba's `principled` / `principledthin` (Disney) BSDF.
    Principled(Box<PrincipledDescription>),
}

/// The parameters of Mitsuba's `principled` and `principledthin` BSDFs
/// (their defaults are Mitsuba's; see `material::PrincipledMaterial`).
#[derive(Debug, Clone, PartialEq)]
pub struct PrincipledDescription {
    /// `principledthin` rather than `principled`.
    pub thin: bool,
    pub base_color: TextureDescription,
    pub roughness: TextureDescription,
    pub anisotropic: TextureDescription,
    pub metallic: TextureDescription,
    pub spec_trans: TextureDescription,
    /// Relative index of refraction (for `principled` computed from `eta`
    /// or `specular`).
    pub eta: TextureDescription,
    pub spec_tint: TextureDescription,
    pub sheen: TextureDescription,
    pub sheen_tint: TextureDescription,
    pub clearcoat: TextureDescription,
    pub clearcoat_gloss: TextureDescription,
    pub flatness: TextureDescription,
    pub diff_trans: TextureDescription,
    pub sampling_rates: crate::material::PrincipledSamplingRates,
}

/// A light that is not a shape.
#[derive(Debug, Clone, PartialEq)]
pub enum LightDescription {
    /// A point light with radiant intensity (an RGB triple is relative to D65).
    Point {
        position: Vec3,
        intensity: SpectrumDescription,
    },
    /// A spot light at the origin of `to_world` shining along its +z, with
    /// full intensity `intensity` inside `falloff_start_degrees` of the axis,
    /// falling to 0 at `cutoff_degrees` with the profile `falloff` (Mitsuba:
    /// `beam_width` is the start, `cutoff_angle` the end, linear in the
    /// angle; pbrt-v4: `coneangle − conedeltaangle` and `coneangle`,
    /// smoothstep in the cosine).
    Spot {
        to_world: Affine3A,
        intensity: SpectrumDescription,
        cutoff_degrees: f32,
        falloff_start_degrees: f32,
        falloff: SpotFalloff,
        /// Mitsuba's projected texture (uv over the cone's image), if any.
        texture: Option<TextureDescription>,
    },
    /// Parallel light arriving from `direction` (the direction light
    /// travels), with irradiance on a surface facing it.
    Directional {
        direction: Vec3,
        irradiance: SpectrumDescription,
    },
    /// Constant radiance from every direction at infinity.
    ConstantEnvironment { radiance: SpectrumDescription },
    /// Radiance at infinity from an image.
    EnvironmentMap {
        filename: PathBuf,
        /// How directions map to the image.
        projection: EnvironmentProjection,
        /// From the light's frame to world (Mitsuba: +y up in the light frame;
        /// pbrt-v4: +z up).
        to_world: Affine3A,
        scale: f32,
    },
    /// Mitsuba 3's `projector`: a point at the origin of `to_world` projecting
    /// the image `irradiance` (times `scale`) along its +z through a
    /// perspective frustum of field of view `fov_degrees` along `fov_axis`
    /// of the image (see `light::ProjectorLight`).
    Projector {
        to_world: Affine3A,
        irradiance: TextureDescription,
        scale: f32,
        fov_degrees: f32,
        fov_axis: ProjectorFovAxis,
    },
}

/// Which extent of a projector's image its field of view spans
/// (Mitsuba's `fov_axis`).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProjectorFovAxis {
    /// The width.
    X,
    /// The height.
    Y,
    /// The diagonal.
    Diagonal,
    /// The smaller of width and height.
    Smaller,
    /// The larger of width and height.
    Larger,
}

impl ProjectorFovAxis {
    /// tan of half the horizontal field of view, for a field of view of
    /// `fov_degrees` along this axis of an image `width` × `height`.
    pub fn tan_half_horizontal(self, fov_degrees: f32, width: f32, height: f32) -> f32 {
        let tan_half = (0.5 * fov_degrees.to_radians()).tan();
        let axis = match self {
            ProjectorFovAxis::Smaller if width <= height => ProjectorFovAxis::X,
            ProjectorFovAxis::Smaller => ProjectorFovAxis::Y,
            ProjectorFovAxis::Larger if width >= height => ProjectorFovAxis::X,
            ProjectorFovAxis::Larger => ProjectorFovAxis::Y,
            other => other,
        };
        match axis {
            ProjectorFovAxis::Y => tan_half * width / height,
            ProjectorFovAxis::Diagonal => {
                tan_half * width / (width * width + height * height).sqrt()
            }
            _ => tan_half,
        }
    }
}

/// A homogeneous participating medium.
#[derive(Debug, Clone, PartialEq)]
pub struct MediumDescription {
    /// The extinction and scattering coefficients.
    pub coefficients: MediumCoefficients,
    /// A factor on the coefficients (units per scene length).
    pub scale: f32,
    /// The phase function.
    pub phase: PhaseDescription,
}

/// How a medium's coefficients are given.
#[derive(Debug, Clone, PartialEq)]
pub enum MediumCoefficients {
    /// Mitsuba's parameters: single-scattering albedo (a reflectance) and
    /// extinction σt (unbounded); σs = albedo·σt, σa = σt − σs.
    AlbedoExtinction {
        albedo: SpectrumDescription,
        sigma_t: SpectrumDescription,
    },
    /// pbrt's parameters: absorption σa and scattering σs (unbounded).
    AbsorptionScattering {
        sigma_a: SpectrumDescription,
        sigma_s: SpectrumDescription,
    },
}

/// A phase function.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PhaseDescription {
    /// Scattering in every direction alike.
    Isotropic,
    /// Henyey–Greenstein with asymmetry g ∈ (−1, 1).
    HenyeyGreenstein { g: f32 },
}

impl ShapeDescription {
    /// A shape with a material and no emission.
    pub fn new(geometry: ShapeGeometry, material: MaterialDescription) -> Self {
        Self {
            geometry,
            material,
            emission: None,
            emission_texture: None,
            flip_normals: false,
            interior_medium: None,
            exterior_medium: None,
        }
    }

    /// The same shape emitting `radiance`.
    pub fn emitting(mut self, radiance: [f32; 3]) -> Self {
        self.emission = Some(SpectrumDescription::Rgb(radiance));
        self
    }

    /// The same shape with flipped normals.
    pub fn flipped(mut self) -> Self {
        self.flip_normals = true;
        self
    }
}

/// A mesh of planar polygons, each given by its corners in order and split
/// into a triangle fan (as OBJ `f` lines with more than three vertices are).
pub fn polygon_mesh(polygons: &[&[[f32; 3]]]) -> ShapeGeometry {
    let mut positions = Vec::new();
    let mut triangles = Vec::new();
    for polygon in polygons {
        let first = positions.len() as u32;
        positions.extend(polygon.iter().map(|&p| Vec3::from(p)));
        for corner in 1..polygon.len() as u32 - 1 {
            triangles.push([first, first + corner, first + corner + 1]);
        }
    }
    ShapeGeometry::Mesh {
        positions,
        normals: None,
        uvs: None,
        triangles,
    }
}

impl MaterialDescription {
    /// A two-sided diffuse material with a constant RGB reflectance.
    pub fn diffuse_rgb(reflectance: [f32; 3]) -> Self {
        MaterialDescription::Diffuse {
            reflectance: TextureDescription::Constant(SpectrumDescription::Rgb(reflectance)),
            two_sided: true,
        }
    }

    /// A smooth dielectric with a constant interior index and air outside.
    pub fn smooth_dielectric(interior_ior: f32) -> Self {
        MaterialDescription::Dielectric {
            interior_ior: SpectrumDescription::Constant(interior_ior),
            exterior_ior: 1.0,
            roughness: None,
        }
    }
}
