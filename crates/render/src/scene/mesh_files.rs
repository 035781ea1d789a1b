//! Reading triangle meshes from files: Wavefront OBJ (tobj) and PLY
//! (ply-rs-bw; binary and ASCII, `.ply.gz` through flate2), as both scene
//! loaders need them.
//!
//! The readers return the file's data as it is (no flipping of texture
//! coordinates, no transform): what a format's renderer does with them is
//! the loader's business (Mitsuba flips OBJ texture coordinates, for one).

use super::loader::SceneFileError;
use glam::{Vec2, Vec3};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};
use std::io::{BufReader, Read};
use std::path::Path;

/// A triangle mesh as read from a file, in the file's coordinates.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct MeshData {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<Vec2>>,
    /// Triangles (polygons are split into fans).
    pub triangles: Vec<[u32; 3]>,
}

fn invalid(path: &Path, message: impl Into<String>) -> SceneFileError {
    SceneFileError::Syntax {
        file: path.to_path_buf(),
        line: 0,
        message: message.into(),
    }
}

impl MeshData {
    /// Checks that every index refers to a vertex and that the optional
    /// attributes have one entry per vertex.
    fn validated(self, path: &Path) -> Result<Self, SceneFileError> {
        let count = self.positions.len();
        if let Some(normals) = &self.normals
            && normals.len() != count
        {
            return Err(invalid(
                path,
                format!("{} normals for {count} vertices", normals.len()),
            ));
        }
        if let Some(uvs) = &self.uvs
            && uvs.len() != count
        {
            return Err(invalid(
                path,
                format!("{} texture coordinates for {count} vertices", uvs.len()),
            ));
        }
        if let Some(bad) = self
            .triangles
            .iter()
            .flatten()
            .find(|&&index| index as usize >= count)
        {
            return Err(invalid(
                path,
                format!("vertex index {bad} out of range ({count} vertices)"),
            ));
        }
        Ok(self)
    }
}

/// Reads an OBJ file (all its objects merged into one mesh).
pub fn read_obj(path: &Path) -> Result<MeshData, SceneFileError> {
    let file = std::fs::File::open(path).map_err(|source| SceneFileError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let options = tobj::LoadOptions {
        triangulate: true,
        single_index: true,
        ignore_points: true,
        ignore_lines: true,
    };
    // Materials are the scene file's business: an OBJ's `mtllib` is ignored.
    let (models, _) = tobj::load_obj_buf(&mut BufReader::new(file), &options, |_| {
        Ok(Default::default())
    })
    .map_err(|error| invalid(path, format!("invalid OBJ file: {error}")))?;
    let mut mesh = MeshData::default();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    let (mut all_normals, mut all_uvs) = (true, true);
    for model in &models {
        let data = &model.mesh;
        let first = mesh.positions.len() as u32;
        let count = data.positions.len() / 3;
        mesh.positions.extend(
            data.positions
                .chunks_exact(3)
                .map(|p| Vec3::new(p[0], p[1], p[2])),
        );
        if data.normals.len() == 3 * count {
            normals.extend(
                data.normals
                    .chunks_exact(3)
                    .map(|n| Vec3::new(n[0], n[1], n[2])),
            );
        } else {
            all_normals = false;
        }
        if data.texcoords.len() == 2 * count {
            uvs.extend(
                data.texcoords
                    .chunks_exact(2)
                    .map(|t| Vec2::new(t[0], t[1])),
            );
        } else {
            all_uvs = false;
        }
        mesh.triangles.extend(
            data.indices
                .chunks_exact(3)
                .map(|t| [first + t[0], first + t[1], first + t[2]]),
        );
    }
    if mesh.positions.is_empty() {
        return Err(invalid(path, "the OBJ file has no vertices"));
    }
    mesh.normals = all_normals.then_some(normals);
    mesh.uvs = all_uvs.then_some(uvs);
    mesh.validated(path)
}

fn scalar(property: &Property) -> Option<f64> {
    Some(match *property {
        Property::Char(v) => v as f64,
        Property::UChar(v) => v as f64,
        Property::Short(v) => v as f64,
        Property::UShort(v) => v as f64,
        Property::Int(v) => v as f64,
        Property::UInt(v) => v as f64,
        Property::Float(v) => v as f64,
        Property::Double(v) => v,
        _ => return None,
    })
}

fn index_list(property: &Property) -> Option<Vec<i64>> {
    Some(match property {
        Property::ListChar(v) => v.iter().map(|&i| i as i64).collect(),
        Property::ListUChar(v) => v.iter().map(|&i| i as i64).collect(),
        Property::ListShort(v) => v.iter().map(|&i| i as i64).collect(),
        Property::ListUShort(v) => v.iter().map(|&i| i as i64).collect(),
        Property::ListInt(v) => v.iter().map(|&i| i as i64).collect(),
        Property::ListUInt(v) => v.iter().map(|&i| i as i64).collect(),
        _ => return None,
    })
}

/// The first of `names` that `element` has, as a number.
fn field(element: &DefaultElement, names: &[&str]) -> Option<f32> {
    names
        .iter()
        .find_map(|name| element.get(*name))
        .and_then(scalar)
        .map(|v| v as f32)
}

/// Reads a PLY file (`.ply` or gzip-compressed `.ply.gz`).
pub fn read_ply(path: &Path) -> Result<MeshData, SceneFileError> {
    let file = std::fs::File::open(path).map_err(|source| SceneFileError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let gzipped = path
        .extension()
        .is_some_and(|extension| extension.eq_ignore_ascii_case("gz"));
    let mut reader: Box<dyn Read> = if gzipped {
        Box::new(BufReader::new(flate2::read::GzDecoder::new(file)))
    } else {
        Box::new(BufReader::new(file))
    };
    let parser = Parser::<DefaultElement>::new();
    let ply = parser
        .read_ply(&mut reader)
        .map_err(|error| invalid(path, format!("invalid PLY file: {error}")))?;
    let vertices = ply
        .payload
        .get("vertex")
        .ok_or_else(|| invalid(path, "the PLY file has no 'vertex' element"))?;
    let mut mesh = MeshData::default();
    let mut normals = Vec::with_capacity(vertices.len());
    let mut uvs = Vec::with_capacity(vertices.len());
    let (mut all_normals, mut all_uvs) = (true, true);
    for (index, vertex) in vertices.iter().enumerate() {
        match (
            field(vertex, &["x"]),
            field(vertex, &["y"]),
            field(vertex, &["z"]),
        ) {
            (Some(x), Some(y), Some(z)) => mesh.positions.push(Vec3::new(x, y, z)),
            _ => {
                return Err(invalid(
                    path,
                    format!("vertex {index} lacks an x, y or z property"),
                ));
            }
        }
        match (
            field(vertex, &["nx"]),
            field(vertex, &["ny"]),
            field(vertex, &["nz"]),
        ) {
            (Some(x), Some(y), Some(z)) => normals.push(Vec3::new(x, y, z)),
            _ => all_normals = false,
        }
        match (
            field(vertex, &["u", "s", "texture_u", "texture_s"]),
            field(vertex, &["v", "t", "texture_v", "texture_t"]),
        ) {
            (Some(u), Some(v)) => uvs.push(Vec2::new(u, v)),
            _ => all_uvs = false,
        }
    }
    if let Some(faces) = ply.payload.get("face") {
        for (index, face) in faces.iter().enumerate() {
            let indices = ["vertex_indices", "vertex_index"]
                .iter()
                .find_map(|name| face.get(*name))
                .and_then(index_list)
                .ok_or_else(|| {
                    invalid(
                        path,
                        format!("face {index} has no integer list 'vertex_indices'"),
                    )
                })?;
            let indices: Vec<u32> = indices
                .into_iter()
                .map(|i| u32::try_from(i).map_err(|_| ()))
                .collect::<Result<_, _>>()
                .map_err(|()| invalid(path, format!("face {index} has a negative index")))?;
            for corner in 1..indices.len().saturating_sub(1) {
                mesh.triangles
                    .push([indices[0], indices[corner], indices[corner + 1]]);
            }
        }
    }
    if mesh.positions.is_empty() {
        return Err(invalid(path, "the PLY file has no vertices"));
    }
    mesh.normals = all_normals.then_some(normals);
    mesh.uvs = all_uvs.then_some(uvs);
    mesh.validated(path)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A file `name` holding `contents` in a scratch directory, which is
    /// removed when the returned guard is dropped.
    fn temporary(name: &str, contents: &[u8]) -> TemporaryFile {
        let directory = crate::test_support::ScratchDirectory::new("mesh");
        let path = directory.join(name);
        std::fs::write(&path, contents).unwrap();
        TemporaryFile {
            path,
            _directory: directory,
        }
    }

    /// A file in a scratch directory; dereferences to its path.
    struct TemporaryFile {
        path: std::path::PathBuf,
        _directory: crate::test_support::ScratchDirectory,
    }

    impl std::ops::Deref for TemporaryFile {
        type Target = std::path::Path;

        fn deref(&self) -> &std::path::Path {
            &self.path
        }
    }

    #[test]
    fn obj_quad_becomes_two_triangles_with_attributes() {
        let path = temporary(
            "quad.obj",
            b"v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nf 1/1/1 2/2/1 3/3/1 4/4/1\n",
        );
        let mesh = read_obj(&path).unwrap();
        assert_eq!(mesh.triangles.len(), 2);
        assert_eq!(mesh.positions.len(), 4);
        assert_eq!(mesh.uvs.as_ref().unwrap().len(), 4);
        assert!(mesh.normals.unwrap().iter().all(|n| *n == Vec3::Z));
    }

    #[test]
    fn obj_without_normals_has_none() {
        let path = temporary("tri.obj", b"v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n");
        let mesh = read_obj(&path).unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
        assert!(mesh.normals.is_none() && mesh.uvs.is_none());
    }

    #[test]
    fn missing_mesh_names_the_path() {
        let error = read_obj(Path::new("/nonexistent/x.obj")).unwrap_err();
        assert!(error.to_string().contains("/nonexistent/x.obj"), "{error}");
        let error = read_ply(Path::new("/nonexistent/y.ply")).unwrap_err();
        assert!(error.to_string().contains("/nonexistent/y.ply"), "{error}");
    }

    const ASCII_PLY: &str = "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0\n1 0 0 1 0\n1 1 0 1 1\n0 1 0 0 1\n4 0 1 2 3\n";

    #[test]
    fn ascii_ply_quad() {
        let path = temporary("quad.ply", ASCII_PLY.as_bytes());
        let mesh = read_ply(&path).unwrap();
        assert_eq!(mesh.triangles, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(mesh.uvs.unwrap()[2], Vec2::new(1.0, 1.0));
        assert!(mesh.normals.is_none());
    }

    #[test]
    fn gzipped_binary_ply() {
        let mut bytes = b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n".to_vec();
        for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            for c in p {
                bytes.extend(c.to_le_bytes());
            }
        }
        bytes.push(3);
        for i in [0u32, 1, 2] {
            bytes.extend(i.to_le_bytes());
        }
        let mut encoder = flate2::write::GzEncoder::new(Vec::new(), flate2::Compression::fast());
        std::io::Write::write_all(&mut encoder, &bytes).unwrap();
        let path = temporary("tri.ply.gz", &encoder.finish().unwrap());
        let mesh = read_ply(&path).unwrap();
        assert_eq!(mesh.positions[1], Vec3::X);
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn out_of_range_index_is_an_error() {
        let path = temporary(
            "bad.ply",
            ASCII_PLY.replace("4 0 1 2 3", "3 0 1 9").as_bytes(),
        );
        let error = read_ply(&path).unwrap_err().to_string();
        assert!(error.contains("out of range"), "{error}");
    }
}
