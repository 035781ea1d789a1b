//! A renderer-independent description of a scene: what the built-in scenes
//! and the scene-file loaders produce, and what [`super::Scene::build`] turns
//! into the structures the integrators trace. Colours are linear sRGB
//! triples; they become spectra when the scene is built.

use crate::camera::PerspectiveSettings;
use glam::{Affine3A, Vec3};

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
    /// The scene's suggested maximum path depth (Mitsuba's convention: the
    /// number of path segments; 1 shows emitters only), if it names one.
    pub max_depth: Option<u32>,
    /// The scene's suggested samples per pixel, if it names any.
    pub samples_per_pixel: Option<u64>,
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
    /// Emitted radiance (linear sRGB, multiplied by the D65 spectrum) if the
    /// surface is an area light; emission leaves the front side only.
    pub emission: Option<[f32; 3]>,
    /// Flip the normals (e.g. to see the inside of a sphere as its front).
    pub flip_normals: bool,
}

/// The geometry of a shape.
#[derive(Debug, Clone)]
pub enum ShapeGeometry {
    /// A triangle mesh in world space; counter-clockwise triangles (seen from
    /// the front) face their geometric normal.
    Mesh {
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
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

/// A surface material.
#[derive(Debug, Clone, PartialEq)]
pub enum MaterialDescription {
    /// Lambertian reflection (two-sided).
    Diffuse { reflectance: [f32; 3] },
    /// A perfect mirror.
    Mirror,
    /// A smooth conductor with a complex index of refraction per RGB channel
    /// (upsampled to spectra).
    Conductor { eta: [f32; 3], k: [f32; 3] },
    /// A smooth dielectric interface with interior index `eta` (outside 1).
    Dielectric { eta: f32 },
    /// Absorbs everything (e.g. the back of a light).
    Black,
}

/// A light that is not a shape.
#[derive(Debug, Clone, PartialEq)]
pub enum LightDescription {
    /// A point light with radiant intensity (linear sRGB × D65).
    Point { position: Vec3, intensity: [f32; 3] },
    /// Constant radiance from every direction at infinity.
    ConstantEnvironment { radiance: [f32; 3] },
}

impl ShapeDescription {
    /// A shape with a material and no emission.
    pub fn new(geometry: ShapeGeometry, material: MaterialDescription) -> Self {
        Self {
            geometry,
            material,
            emission: None,
            flip_normals: false,
        }
    }

    /// The same shape emitting `radiance`.
    pub fn emitting(mut self, radiance: [f32; 3]) -> Self {
        self.emission = Some(radiance);
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
        triangles,
    }
}
