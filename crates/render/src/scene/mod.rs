//! Scenes: the renderer-independent [`description`] that built-in scenes and
//! loaders produce, the [`builtin`] scenes, and [`Scene`], what integrators
//! trace: geometry with its acceleration structure, a material and an
//! optional light per shape, the lights and the camera. [`Scene::build`]
//! makes a scene from a description with the builders of [`build`], the
//! only place where the description meets the lower layers.

pub mod build;
pub mod builtin;
pub mod description;
pub mod loader;
pub mod mesh_files;
pub mod mitsuba;
pub mod pbrt;
pub mod spectra;

use crate::camera::{CameraError, PerspectiveCamera};
use crate::film::{FilmFrame, Filter};
use crate::geometry::{Geometry, GeometryError};
use crate::light::{Light, LightError, LightSampler};
use crate::material::Material;
use crate::medium::{HomogeneousMedium, MediumInterface};
use crate::texture::TextureError;
use description::{MaterialDescription, SceneDescription};

/// Why a scene cannot be built from its description.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// A shape's geometry is invalid.
    #[error("shape {index}: {source}")]
    Geometry {
        index: usize,
        #[source]
        source: GeometryError,
    },
    /// The acceleration structure could not be built.
    #[error("{0}")]
    Accelerator(GeometryError),
    /// A colour or material parameter is invalid.
    #[error("{what}: {message}")]
    Parameter { what: String, message: String },
    /// The camera is invalid.
    #[error(transparent)]
    Camera(#[from] CameraError),
    /// The description uses a feature the renderer does not have (yet).
    #[error("not supported: {what}")]
    Unsupported { what: String },
    /// The scene emits no light.
    #[error("the scene has no light sources")]
    NoLights,
}

/// A texture's image that cannot be loaded is a parameter error (same text).
impl From<TextureError> for SceneError {
    fn from(TextureError { what, message }: TextureError) -> Self {
        SceneError::Parameter { what, message }
    }
}

/// A light's data that cannot be loaded is a parameter error (same text).
impl From<LightError> for SceneError {
    fn from(LightError { what, message }: LightError) -> Self {
        SceneError::Parameter { what, message }
    }
}

/// What a shape is made of.
#[derive(Debug, Clone)]
pub struct ShapeInfo {
    /// The material (`None` for a black surface that absorbs everything).
    pub material: Option<Material>,
    /// The index of the shape's area light in [`Scene::lights`].
    pub light: Option<u32>,
    /// The shape's front is the side opposite its stored normals.
    pub flip_normals: bool,
    /// The media on its two sides if the shape is a medium transition (see
    /// [`crate::medium`]); `None` keeps the ray's medium when crossing it.
    pub medium_interface: Option<MediumInterface>,
    /// An index-matched boundary (`MaterialDescription::Interface`): rays
    /// pass straight through; it only changes the medium.
    pub is_interface: bool,
}

/// A scene ready for rendering.
#[derive(Debug)]
pub struct Scene {
    /// The scene's name.
    pub name: String,
    /// Surfaces and their acceleration structure.
    pub geometry: Geometry,
    /// Per shape (same order as the geometry's shapes).
    pub shapes: Vec<ShapeInfo>,
    /// All lights: area lights first, in shape order, then the others.
    pub lights: Vec<Light>,
    /// Chooses lights for next-event estimation.
    pub light_sampler: LightSampler,
    /// Indices of the lights at infinity (seen by rays that escape).
    pub environment_lights: Vec<u32>,
    /// Participating media, referred to by [`ShapeInfo::medium_interface`]
    /// and [`Scene::camera_medium`].
    pub media: Vec<HomogeneousMedium>,
    /// The medium the camera sits in (`None`: vacuum).
    pub camera_medium: Option<u32>,
    /// The camera.
    pub camera: PerspectiveCamera,
    /// The pixel reconstruction filter.
    pub filter: Filter,
    /// The scene's suggested maximum depth (Mitsuba's convention).
    pub max_depth: Option<u32>,
    /// The scene's suggested samples per pixel.
    pub samples_per_pixel: Option<u64>,
    /// The scene's suggested Russian-roulette depth (Mitsuba's `rr_depth`).
    pub russian_roulette_depth: Option<u32>,
}

impl Scene {
    /// Whether the scene has participating media (the `path` integrator
    /// ignores them; `volpath` renders them).
    pub fn has_media(&self) -> bool {
        !self.media.is_empty()
    }

    /// Builds the scene: geometry and BVH, spectra from colours, lights.
    /// What each part is made of is built in [`build`]; errors come in the
    /// order of the description (shapes in order, then the other lights,
    /// the media, the camera's medium, a scene without lights, the filter
    /// and the camera).
    pub fn build(description: &SceneDescription) -> Result<Self, SceneError> {
        let media_count = description.media.len();
        let mut shapes = Vec::with_capacity(description.shapes.len());
        let mut infos = Vec::with_capacity(description.shapes.len());
        let mut lights = Vec::new();
        for (index, shape) in description.shapes.iter().enumerate() {
            shapes.push(build::shapes::shape(&shape.geometry, index)?);
            let light = build::lights::area_light(shape, index)?.map(|light| {
                lights.push(light);
                lights.len() as u32 - 1
            });
            let medium_interface = build::media::medium_interface(shape, index, media_count)?;
            let is_interface = matches!(shape.material, MaterialDescription::Interface);
            infos.push(ShapeInfo {
                material: if is_interface {
                    None
                } else {
                    build::materials::material(&shape.material)?
                },
                light,
                flip_normals: shape.flip_normals,
                medium_interface,
                is_interface,
            });
        }
        let geometry = Geometry::new(shapes).map_err(SceneError::Accelerator)?;
        let environment_lights =
            build::lights::push_listed_lights(&description.lights, &geometry, &mut lights)?;
        let media = build::media::media(&description.media)?;
        let camera_medium = build::media::camera_medium(description.camera_medium, media.len())?;
        if lights.is_empty() {
            return Err(SceneError::NoLights);
        }
        let light_sampler = build::lights::light_sampler(&lights, &geometry);
        let filter = build::film::filter(&description.filter)?;
        Ok(Self {
            name: description.name.clone(),
            geometry,
            shapes: infos,
            light_sampler,
            lights,
            environment_lights,
            media,
            camera_medium,
            camera: PerspectiveCamera::new(&description.camera)?,
            filter,
            max_depth: description.max_depth,
            samples_per_pixel: description.samples_per_pixel,
            russian_roulette_depth: description.russian_roulette_depth,
        })
    }
}

/// The splatting integrators' image plane spans the camera's image grown by
/// the filter's reach.
impl FilmFrame for Scene {
    fn resolution(&self) -> [u32; 2] {
        self.camera.resolution()
    }

    fn filter_radius(&self) -> [f32; 2] {
        self.filter.radius()
    }
}
