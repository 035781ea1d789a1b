//! Mitsuba's shapes: `obj`, `ply` (meshes from files), `rectangle`,
//! `cube`, `disk`, `sphere`, each with an optional BSDF (default: a
//! one-sided diffuse of reflectance 0.5), an `area` emitter, and interior
//! and exterior media.
//!
//! Meshes are transformed to world space here (positions by `to_world`,
//! normals by its inverse transpose). Mitsuba flips OBJ texture coordinates
//! (v → 1 − v, `flip_tex_coords`, default true) so that v = 0 is the top of
//! an image; PLY coordinates are used as they are.

use super::super::description::{
    MaterialDescription, ShapeDescription, ShapeGeometry, SpectrumDescription, TextureDescription,
};
use super::super::loader::SceneFileError;
use super::super::mesh_files::{read_obj, read_ply};
use super::values::Properties;
use super::xml::Element;
use super::{Loader, NamedObject};
use glam::{Affine3A, Vec2, Vec3};

/// Which side of a shape a medium is on.
#[derive(Clone, Copy)]
enum Side {
    Interior,
    Exterior,
}

impl Loader {
    /// The medium a shape names for `side` (a `<ref name>` or a nested
    /// `<medium name>`).
    fn shape_medium(
        &mut self,
        properties: &Properties,
        side: Side,
    ) -> Result<Option<usize>, SceneFileError> {
        let name = match side {
            Side::Interior => "interior",
            Side::Exterior => "exterior",
        };
        if let Some(element) = properties.get(name) {
            return match self.referenced(element)? {
                NamedObject::Medium(index) => Ok(Some(index)),
                other => Err(element.location.error(format!(
                    "'{name}' refers to a {}, expected a medium",
                    other.kind()
                ))),
            };
        }
        for object in &properties.objects {
            if object.tag == "medium" && object.attribute("name") == Some(name) {
                return self.medium(object);
            }
        }
        Ok(None)
    }

    /// Reads a mesh file named by the shape.
    fn mesh_file(
        &mut self,
        element: &Element,
        properties: &Properties,
        to_world: Affine3A,
        kind: &str,
    ) -> Result<ShapeGeometry, SceneFileError> {
        let name = properties.optional_string("filename")?.ok_or_else(|| {
            element
                .location
                .error(format!("shape '{kind}' needs a 'filename' string"))
        })?;
        let path = self.resolve(element, name, "mesh")?;
        let mesh = match self.meshes.get(&path) {
            Some(mesh) => mesh.clone(),
            None => {
                let read = if kind == "obj" { read_obj } else { read_ply };
                let mesh =
                    std::sync::Arc::new(read(&path).map_err(|error| {
                        element.location.error(format!("shape '{kind}': {error}"))
                    })?);
                self.meshes.insert(path.clone(), mesh.clone());
                mesh
            }
        };
        let face_normals = properties.boolean("face_normals", false)?;
        let flip_tex_coords = kind == "obj" && properties.boolean("flip_tex_coords", true)?;
        let normal_matrix = to_world.matrix3.inverse().transpose();
        let positions = mesh
            .positions
            .iter()
            .map(|&p| to_world.transform_point3(p))
            .collect();
        let normals = if face_normals {
            None
        } else {
            mesh.normals.as_ref().map(|normals| {
                normals
                    .iter()
                    .map(|&n| Vec3::from(normal_matrix * glam::Vec3A::from(n)).normalize_or_zero())
                    .collect()
            })
        };
        let uvs = mesh.uvs.as_ref().map(|uvs| {
            if flip_tex_coords {
                uvs.iter().map(|uv| Vec2::new(uv.x, 1.0 - uv.y)).collect()
            } else {
                uvs.clone()
            }
        });
        Ok(ShapeGeometry::Mesh {
            positions,
            normals,
            uvs,
            triangles: mesh.triangles.clone(),
        })
    }

    /// A sphere's geometry: `center` and `radius` moved by `to_world`.
    fn sphere(
        &mut self,
        element: &Element,
        properties: &Properties,
        to_world: Affine3A,
    ) -> Result<ShapeGeometry, SceneFileError> {
        let center = properties.optional_vector("center")?.unwrap_or(Vec3::ZERO);
        let radius = properties.float("radius", 1.0)?;
        let m = to_world.matrix3;
        let scales = [m.x_axis.length(), m.y_axis.length(), m.z_axis.length()];
        let mean = (scales[0] + scales[1] + scales[2]) / 3.0;
        if scales.iter().any(|s| (s - mean).abs() > 1e-4 * mean) {
            self.warn(
                element,
                format!(
                    "sphere: to_world scales unevenly ({scales:?}); using the mean scale {mean}"
                ),
            );
        }
        Ok(ShapeGeometry::Sphere {
            center: to_world.transform_point3(center),
            radius: radius * mean,
        })
    }

    /// Reads a `<shape>` and adds it to the description.
    pub(super) fn shape(&mut self, element: &Element) -> Result<(), SceneFileError> {
        let properties = Properties::new(element);
        let kind = properties.plugin_type();
        let to_world = properties
            .optional_transform("to_world")?
            .unwrap_or(Affine3A::IDENTITY);
        let geometry = match kind {
            "obj" | "ply" => self.mesh_file(element, &properties, to_world, kind)?,
            "rectangle" => ShapeGeometry::Rectangle { to_world },
            "cube" => ShapeGeometry::Cube { to_world },
            "disk" => ShapeGeometry::Disk { to_world },
            "sphere" => self.sphere(element, &properties, to_world)?,
            other => {
                self.warn(
                    element,
                    format!("shape type '{other}' is not supported: the shape is left out"),
                );
                return Ok(());
            }
        };
        let flip_normals = properties.boolean("flip_normals", false)?;
        let interior_medium = self.shape_medium(&properties, Side::Interior)?;
        let exterior_medium = self.shape_medium(&properties, Side::Exterior)?;
        let mut material = None;
        let mut emission = None;
        for object in &properties.objects {
            match object.tag.as_str() {
                "bsdf" => material = Some(self.bsdf(object)?),
                "ref" => match self.referenced(object)? {
                    NamedObject::Bsdf(referenced) => material = Some(referenced),
                    NamedObject::AreaEmitter(radiance) => emission = radiance,
                    other => {
                        return Err(object.location.error(format!(
                            "a shape's unnamed <ref> must name a bsdf or an area emitter, '{}' is a {}",
                            object.attribute("id").unwrap_or(""),
                            other.kind()
                        )));
                    }
                },
                "emitter" => emission = self.area_emitter(object)?,
                "medium" if object.attribute("name").is_some() => {}
                other => self.warn(
                    object,
                    format!("<{other}> inside shape '{kind}' is ignored"),
                ),
            }
        }
        self.finish(&properties);
        let material = material.unwrap_or(MaterialDescription::Diffuse {
            reflectance: TextureDescription::Constant(SpectrumDescription::Constant(0.5)),
            two_sided: false,
        });
        self.register(element, NamedObject::Other("shape".into()))?;
        // A constant radiance is a plain area light; a texture a textured one.
        let (emission, emission_texture) = match emission {
            Some(TextureDescription::Constant(spectrum)) => (Some(spectrum), None),
            Some(texture) => (None, Some(texture)),
            None => (None, None),
        };
        self.description.shapes.push(ShapeDescription {
            geometry,
            material,
            emission,
            emission_texture,
            flip_normals,
            interior_medium,
            exterior_medium,
        });
        Ok(())
    }
}
