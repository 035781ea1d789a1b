//! `Shape`: `trianglemesh`, `plymesh` (`.ply` and `.ply.gz`), `bilinearmesh`
//! (planar patches, split into two triangles each), `sphere` and `disk`,
//! transformed to world space by the CTM, with the current material, area
//! light and media.
//!
//! Orientation (pbrt-v4): a surface's front is the side its normal points
//! to; area lights emit from the front only unless two-sided. For
//! triangles and bilinear patches without per-vertex normals the normal is
//! the winding normal, flipped when `ReverseOrientation` is active or the
//! transform mirrors (pbrt's `reverseOrientation ^ transformSwapsHandedness`);
//! with per-vertex normals `N` (flipped by `ReverseOrientation`) the face
//! normal is turned toward them. The renderer's meshes take the winding
//! normal as the front, so triangles are rewound accordingly. Spheres and
//! disks face outward (+z for the disk, through the normal transform), flipped
//! by `ReverseOrientation` only.

use super::graphics_state::ShapeTransform;
use super::parameters::{ParameterList, Position};
use super::parser::Loader;
use crate::scene::description::{
    MaterialDescription, ShapeDescription, ShapeGeometry, SpectrumDescription, TextureDescription,
};
use crate::scene::loader::SceneFileError;
use crate::scene::mesh_files::{MeshData, read_ply};
use glam::{Affine3A, DMat4, DVec3, Vec2, Vec3};
use std::f32::consts::PI;

/// A mesh in world space as pbrt orients it, before it becomes a shape.
struct WorldMesh {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    triangles: Vec<[u32; 3]>,
}

fn check_indices(
    indices: &[i64],
    vertex_count: usize,
    per_face: usize,
    what: &str,
    position: &Position,
) -> Result<(), SceneFileError> {
    if indices.is_empty() || !indices.len().is_multiple_of(per_face) {
        return Err(position.error(format!(
            "Shape \"{what}\": expected a multiple of {per_face} vertex indices, found {}",
            indices.len()
        )));
    }
    if let Some(bad) = indices
        .iter()
        .find(|&&i| i < 0 || i as usize >= vertex_count)
    {
        return Err(position.error(format!(
            "Shape \"{what}\": vertex index {bad} is outside the {vertex_count} vertices"
        )));
    }
    Ok(())
}

/// Checks a mesh read from a file: indices in range, one normal and uv per vertex.
fn check_mesh_data(mesh: &MeshData, what: &str, position: &Position) -> Result<(), SceneFileError> {
    let count = mesh.positions.len();
    if let Some(bad) = mesh
        .triangles
        .iter()
        .flatten()
        .find(|&&i| i as usize >= count)
    {
        return Err(position.error(format!(
            "{what}: vertex index {bad} is outside the {count} vertices"
        )));
    }
    if mesh.normals.as_ref().is_some_and(|n| n.len() != count)
        || mesh.uvs.as_ref().is_some_and(|uv| uv.len() != count)
    {
        return Err(position.error(format!(
            "{what}: the normals or texture coordinates do not match the {count} vertices"
        )));
    }
    Ok(())
}

/// Transforms a mesh given in object space and orients its triangles as pbrt
/// would (see the module documentation).
fn orient_mesh(mesh: MeshData, transform: &ShapeTransform, reverse_orientation: bool) -> WorldMesh {
    let positions: Vec<Vec3> = mesh
        .positions
        .iter()
        .map(|p| transform.point(p.to_array()))
        .collect();
    let normals: Option<Vec<Vec3>> = mesh.normals.map(|normals| {
        normals
            .iter()
            .map(|n| {
                let world = transform.normal(n.to_array()).normalize_or_zero();
                if reverse_orientation { -world } else { world }
            })
            .collect()
    });
    let flip_without_normals = reverse_orientation ^ transform.swaps_handedness();
    let triangles = mesh
        .triangles
        .into_iter()
        .map(|[a, b, c]| {
            let flip = match &normals {
                Some(normals) => {
                    let (pa, pb, pc) = (
                        positions[a as usize],
                        positions[b as usize],
                        positions[c as usize],
                    );
                    let winding = (pb - pa).cross(pc - pa);
                    let shading = normals[a as usize] + normals[b as usize] + normals[c as usize];
                    winding.dot(shading) < 0.0
                }
                None => flip_without_normals,
            };
            if flip { [a, c, b] } else { [a, b, c] }
        })
        .collect();
    WorldMesh {
        positions,
        normals,
        uvs: mesh.uvs,
        triangles,
    }
}

/// The surface area of a world-space mesh.
fn mesh_area(mesh: &WorldMesh) -> f32 {
    mesh.triangles
        .iter()
        .map(|&[a, b, c]| {
            let (pa, pb, pc) = (
                mesh.positions[a as usize],
                mesh.positions[b as usize],
                mesh.positions[c as usize],
            );
            0.5 * (pb - pa).cross(pc - pa).length()
        })
        .sum()
}

/// The uniform scale factor of a similarity transform's linear part, or
/// `None` if it scales directions differently.
fn uniform_scale(matrix: &DMat4) -> Option<f64> {
    let lengths = [
        matrix.transform_vector3(DVec3::X).length(),
        matrix.transform_vector3(DVec3::Y).length(),
        matrix.transform_vector3(DVec3::Z).length(),
    ];
    let mean = lengths.iter().sum::<f64>() / 3.0;
    let orthogonal = matrix
        .transform_vector3(DVec3::X)
        .dot(matrix.transform_vector3(DVec3::Y))
        .abs()
        + matrix
            .transform_vector3(DVec3::Y)
            .dot(matrix.transform_vector3(DVec3::Z))
            .abs()
        + matrix
            .transform_vector3(DVec3::X)
            .dot(matrix.transform_vector3(DVec3::Z))
            .abs();
    let similar =
        lengths.iter().all(|l| (l - mean).abs() <= 1e-5 * mean) && orthogonal <= 1e-5 * mean * mean;
    similar.then_some(mean)
}

/// A shape's world-space geometry moved by `transform` (object instancing).
pub fn transform_shape(
    mut shape: ShapeDescription,
    transform: DMat4,
) -> Result<ShapeDescription, String> {
    if transform == DMat4::IDENTITY {
        return Ok(shape);
    }
    let shape_transform = ShapeTransform { matrix: transform };
    let affine = shape_transform.affine();
    shape.geometry = match shape.geometry {
        ShapeGeometry::Mesh {
            positions,
            normals,
            uvs,
            triangles,
        } => {
            let swaps = shape_transform.swaps_handedness();
            ShapeGeometry::Mesh {
                positions: positions
                    .iter()
                    .map(|p| shape_transform.point(p.to_array()))
                    .collect(),
                normals: normals.map(|normals| {
                    normals
                        .iter()
                        .map(|n| shape_transform.normal(n.to_array()).normalize_or_zero())
                        .collect()
                }),
                uvs,
                // A mirror reverses the winding; keep the front where it was.
                triangles: triangles
                    .into_iter()
                    .map(|[a, b, c]| if swaps { [a, c, b] } else { [a, b, c] })
                    .collect(),
            }
        }
        ShapeGeometry::Sphere { center, radius } => {
            let scale = uniform_scale(&transform)
                .ok_or("a sphere instanced with a non-uniform scale (not supported)")?;
            ShapeGeometry::Sphere {
                center: shape_transform.point(center.to_array()),
                radius: radius * scale as f32,
            }
        }
        ShapeGeometry::Disk { to_world } => ShapeGeometry::Disk {
            to_world: affine * to_world,
        },
        ShapeGeometry::Rectangle { to_world } => ShapeGeometry::Rectangle {
            to_world: affine * to_world,
        },
        ShapeGeometry::Cube { to_world } => ShapeGeometry::Cube {
            to_world: affine * to_world,
        },
    };
    Ok(shape)
}

impl Loader {
    /// `Shape`.
    pub fn shape(
        &mut self,
        kind: &str,
        parameters: &ParameterList,
        position: &Position,
    ) -> Result<(), SceneFileError> {
        let transform = ShapeTransform {
            matrix: self.state.ctm,
        };
        let reverse = self.state.reverse_orientation;
        let (geometry, area, flip_normals) = match kind {
            "trianglemesh" => {
                let mesh = self.triangle_mesh(parameters, position)?;
                let world = orient_mesh(mesh, &transform, reverse);
                let area = mesh_area(&world);
                (mesh_geometry(world), area, false)
            }
            "plymesh" => {
                let filename = parameters.string("filename")?.ok_or_else(|| {
                    position.error("Shape \"plymesh\": expected a \"string filename\" parameter")
                })?;
                let path = self.resolve(&filename, position);
                if !path.is_file() {
                    return Err(position.error(format!(
                        "Shape \"plymesh\": cannot find the mesh \"{filename}\" (looked for {})",
                        path.display()
                    )));
                }
                if parameters.has("displacement") {
                    parameters.find("displacement");
                    parameters.float("edgelength", 1.0)?;
                    self.warn(
                        position,
                        "Shape \"plymesh\": displacement is not supported and is ignored",
                    );
                }
                let mesh = read_ply(&path)?;
                check_mesh_data(&mesh, &path.display().to_string(), position)?;
                let world = orient_mesh(mesh, &transform, reverse);
                let area = mesh_area(&world);
                (mesh_geometry(world), area, false)
            }
            "bilinearmesh" => {
                let mesh = self.bilinear_mesh(parameters, position)?;
                let world = orient_mesh(mesh, &transform, reverse);
                let area = mesh_area(&world);
                (mesh_geometry(world), area, false)
            }
            "sphere" => {
                let radius = parameters.float("radius", 1.0)?;
                let z_min = parameters.float("zmin", -radius)?;
                let z_max = parameters.float("zmax", radius)?;
                let phi_max = parameters.float("phimax", 360.0)?;
                if z_min > -radius || z_max < radius || phi_max < 360.0 {
                    self.warn(position, "Shape \"sphere\": partial spheres (zmin, zmax, phimax) are not supported; the whole sphere is used");
                }
                if radius.is_nan() || radius <= 0.0 {
                    return Err(position.error(format!(
                        "Shape \"sphere\": \"float radius\" must be positive, found {radius}"
                    )));
                }
                let scale = uniform_scale(&transform.matrix).ok_or_else(|| {
                    position.error("Shape \"sphere\": the transform scales non-uniformly (only rotations, translations, mirrors and uniform scales are supported for spheres)")
                })? as f32;
                let world_radius = radius * scale;
                (
                    ShapeGeometry::Sphere {
                        center: transform.point([0.0; 3]),
                        radius: world_radius,
                    },
                    4.0 * PI * world_radius * world_radius,
                    reverse,
                )
            }
            "disk" => {
                let radius = parameters.float("radius", 1.0)?;
                let height = parameters.float("height", 0.0)?;
                let inner_radius = parameters.float("innerradius", 0.0)?;
                let phi_max = parameters.float("phimax", 360.0)?;
                if inner_radius > 0.0 || phi_max < 360.0 {
                    self.warn(position, "Shape \"disk\": annuli and partial disks (innerradius, phimax) are not supported; the whole disk is used");
                }
                if radius.is_nan() || radius <= 0.0 {
                    return Err(position.error(format!(
                        "Shape \"disk\": \"float radius\" must be positive, found {radius}"
                    )));
                }
                let object = Affine3A::from_translation(Vec3::new(0.0, 0.0, height))
                    * Affine3A::from_scale(Vec3::new(radius, radius, 1.0));
                let to_world = transform.affine() * object;
                let area = PI
                    * to_world
                        .transform_vector3(Vec3::X)
                        .cross(to_world.transform_vector3(Vec3::Y))
                        .length();
                (ShapeGeometry::Disk { to_world }, area, reverse)
            }
            other => {
                self.warn(
                    position,
                    format!("Shape \"{other}\" is not supported and is skipped"),
                );
                for parameter in &parameters.parameters {
                    parameters.find(&parameter.name);
                }
                return Ok(());
            }
        };
        // Texture coordinates of pbrt meshes may be given as "uv" or "st";
        // normals and tangents read elsewhere.
        let mut material = self.current_material()?;
        match self.alpha(parameters)? {
            Alpha::Opaque => {}
            Alpha::Invisible => return Ok(()),
            Alpha::Partial(opacity) => {
                material = MaterialDescription::Mask {
                    opacity,
                    nested: Box::new(material),
                }
            }
        }
        let emission = match self.state.area_light.clone() {
            None => None,
            Some(light) => {
                if light.two_sided {
                    self.warn(position, "AreaLightSource \"diffuse\": \"twosided\" is not supported; the shape emits from its front only");
                }
                let mut scale = light.scale;
                if let Some(power) = light.power {
                    let sides = if light.two_sided { 2.0 } else { 1.0 };
                    let k_e = PI * sides * area;
                    if k_e > 0.0 {
                        scale *= power / k_e;
                    }
                }
                Some(super::spectrum_values::scaled(light.radiance, scale))
            }
        };
        let medium = |name: &Option<String>, loader: &mut Loader| -> Option<usize> {
            let name = name.as_ref()?;
            match loader.named_media.get(name) {
                Some(&index) => Some(index),
                None => {
                    loader.warn(
                        position,
                        format!("MediumInterface: no medium named \"{name}\"; vacuum is used"),
                    );
                    None
                }
            }
        };
        let (inside, outside) = (
            self.state.inside_medium.clone(),
            self.state.outside_medium.clone(),
        );
        let interior_medium = medium(&inside, self);
        let exterior_medium = medium(&outside, self);
        let shape = ShapeDescription {
            geometry,
            material,
            emission,
            emission_texture: None,
            flip_normals,
            interior_medium,
            exterior_medium,
        };
        match &mut self.current_object {
            Some((_, definition, _)) => {
                let mut shape = shape;
                if shape.emission.take().is_some() {
                    self.warnings.push(position.warning(
                        "area lights in object definitions are not supported (as in pbrt-v4); the shape does not emit",
                    ));
                }
                definition.shapes.push(shape);
            }
            None => self.shapes.push(shape),
        }
        Ok(())
    }

    /// `trianglemesh` parameters: `P`, `indices` (optional for a single
    /// triangle), `N`, `uv`.
    fn triangle_mesh(
        &mut self,
        parameters: &ParameterList,
        position: &Position,
    ) -> Result<MeshData, SceneFileError> {
        let positions = parameters.tuples::<3>("P", &["point3"])?.ok_or_else(|| {
            position.error("Shape \"trianglemesh\": expected a \"point3 P\" parameter")
        })?;
        let indices = match parameters.integers("indices")? {
            Some(indices) => indices,
            None if positions.len() == 3 => vec![0, 1, 2],
            None => {
                return Err(position.error(
                    "Shape \"trianglemesh\": expected an \"integer indices\" parameter (only a single triangle may omit it)",
                ));
            }
        };
        check_indices(&indices, positions.len(), 3, "trianglemesh", position)?;
        let mesh = self.mesh_attributes(parameters, position, positions, "trianglemesh")?;
        Ok(MeshData {
            triangles: indices
                .chunks_exact(3)
                .map(|t| [t[0] as u32, t[1] as u32, t[2] as u32])
                .collect(),
            ..mesh
        })
    }

    /// `bilinearmesh`: patches of four vertices p00, p10, p01, p11, each split
    /// into the triangles (p00, p10, p11) and (p00, p11, p01). This is exact
    /// for planar patches (rectangles, as exporters write them) and an
    /// approximation otherwise.
    fn bilinear_mesh(
        &mut self,
        parameters: &ParameterList,
        position: &Position,
    ) -> Result<MeshData, SceneFileError> {
        let positions = parameters.tuples::<3>("P", &["point3"])?.ok_or_else(|| {
            position.error("Shape \"bilinearmesh\": expected a \"point3 P\" parameter")
        })?;
        let indices = match parameters.integers("indices")? {
            Some(indices) => indices,
            None if positions.len() == 4 => vec![0, 1, 2, 3],
            None => {
                return Err(position.error(
                    "Shape \"bilinearmesh\": expected an \"integer indices\" parameter (only a single patch may omit it)",
                ));
            }
        };
        check_indices(&indices, positions.len(), 4, "bilinearmesh", position)?;
        let mut non_planar = false;
        let mut triangles = Vec::with_capacity(indices.len() / 2);
        for patch in indices.chunks_exact(4) {
            let [p00, p10, p01, p11] = [patch[0], patch[1], patch[2], patch[3]].map(|i| i as u32);
            let corner = |i: u32| Vec3::from(positions[i as usize]);
            let normal = (corner(p10) - corner(p00)).cross(corner(p01) - corner(p00));
            let offset = (corner(p11) - corner(p00)).dot(normal.normalize_or_zero());
            let size = (corner(p11) - corner(p00)).length();
            non_planar |= offset.abs() > 1e-4 * size;
            triangles.push([p00, p10, p11]);
            triangles.push([p00, p11, p01]);
        }
        if non_planar {
            self.warn(
                position,
                "Shape \"bilinearmesh\": non-planar patches are approximated by two triangles each",
            );
        }
        let mesh = self.mesh_attributes(parameters, position, positions, "bilinearmesh")?;
        Ok(MeshData { triangles, ..mesh })
    }

    /// Per-vertex `N` and `uv` of a mesh given inline.
    fn mesh_attributes(
        &mut self,
        parameters: &ParameterList,
        position: &Position,
        positions: Vec<[f32; 3]>,
        what: &str,
    ) -> Result<MeshData, SceneFileError> {
        let count = positions.len();
        let normals = parameters.tuples::<3>("N", &["normal"])?;
        let uvs = match parameters.tuples::<2>("uv", &["point2"])? {
            Some(uvs) => Some(uvs),
            None => parameters.tuples::<2>("st", &["point2"])?,
        };
        if normals.as_ref().is_some_and(|n| n.len() != count) {
            return Err(position.error(format!(
                "Shape \"{what}\": \"normal N\" has {} normals for {count} vertices",
                normals.as_ref().map_or(0, Vec::len)
            )));
        }
        if uvs.as_ref().is_some_and(|uv| uv.len() != count) {
            return Err(position.error(format!(
                "Shape \"{what}\": \"point2 uv\" has {} coordinates for {count} vertices",
                uvs.as_ref().map_or(0, Vec::len)
            )));
        }
        // Tangents and per-face indices do not change the image here.
        parameters.tuples::<3>("S", &["vector3"])?;
        parameters.integers("faceIndices")?;
        Ok(MeshData {
            positions: positions.into_iter().map(Vec3::from).collect(),
            normals: normals.map(|n| n.into_iter().map(Vec3::from).collect()),
            uvs: uvs.map(|uv| uv.into_iter().map(Vec2::from).collect()),
            triangles: Vec::new(),
        })
    }

    /// The shape's `alpha` (a float or a float texture; default 1).
    fn alpha(&mut self, parameters: &ParameterList) -> Result<Alpha, SceneFileError> {
        if let Some(name) = parameters.texture_reference("alpha")? {
            let position = parameters.find("alpha").expect("present").position.clone();
            let texture = self.float_texture_named(&name, &position)?;
            return Ok(Alpha::Partial(texture));
        }
        let alpha = parameters.float("alpha", 1.0)?;
        Ok(if alpha >= 1.0 {
            Alpha::Opaque
        } else if alpha <= 0.0 {
            Alpha::Invisible
        } else {
            Alpha::Partial(TextureDescription::Constant(SpectrumDescription::Constant(
                alpha,
            )))
        })
    }
}

enum Alpha {
    Opaque,
    /// pbrt-v4 drops shapes with a constant alpha of 0.
    Invisible,
    Partial(TextureDescription),
}

fn mesh_geometry(mesh: WorldMesh) -> ShapeGeometry {
    ShapeGeometry::Mesh {
        positions: mesh.positions,
        normals: mesh.normals,
        uvs: mesh.uvs,
        triangles: mesh.triangles,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad() -> MeshData {
        MeshData {
            positions: vec![
                Vec3::new(0.0, 0.0, 0.0),
                Vec3::new(1.0, 0.0, 0.0),
                Vec3::new(0.0, 1.0, 0.0),
            ],
            normals: None,
            uvs: None,
            triangles: vec![[0, 1, 2]],
        }
    }

    fn winding(mesh: &WorldMesh) -> Vec3 {
        let [a, b, c] = mesh.triangles[0];
        (mesh.positions[b as usize] - mesh.positions[a as usize])
            .cross(mesh.positions[c as usize] - mesh.positions[a as usize])
    }

    #[test]
    fn mirrors_and_reverse_orientation_flip_unnormalled_triangles() {
        let identity = ShapeTransform {
            matrix: DMat4::IDENTITY,
        };
        let mirror = ShapeTransform {
            matrix: DMat4::from_scale(DVec3::new(1.0, 1.0, -1.0)),
        };
        assert!(winding(&orient_mesh(quad(), &identity, false)).z > 0.0);
        assert!(winding(&orient_mesh(quad(), &identity, true)).z < 0.0);
        // Mirrored in z, the object's +z normal becomes −z; pbrt keeps it.
        assert!(winding(&orient_mesh(quad(), &mirror, false)).z < 0.0);
        assert!(winding(&orient_mesh(quad(), &mirror, true)).z > 0.0);
    }

    #[test]
    fn vertex_normals_decide_the_front() {
        let identity = ShapeTransform {
            matrix: DMat4::IDENTITY,
        };
        let mut mesh = quad();
        mesh.normals = Some(vec![Vec3::new(0.0, 0.0, -1.0); 3]);
        assert!(winding(&orient_mesh(mesh.clone(), &identity, false)).z < 0.0);
        assert!(winding(&orient_mesh(mesh, &identity, true)).z > 0.0);
    }

    #[test]
    fn uniform_scales_are_recognised() {
        let rotation = DMat4::from_axis_angle(DVec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let similarity =
            DMat4::from_translation(DVec3::ONE) * rotation * DMat4::from_scale(DVec3::splat(2.0));
        assert!((uniform_scale(&similarity).unwrap() - 2.0).abs() < 1e-9);
        assert!(uniform_scale(&DMat4::from_scale(DVec3::new(1.0, 2.0, 1.0))).is_none());
    }
}
