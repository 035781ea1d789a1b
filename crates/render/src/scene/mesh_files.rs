//! Reading triangle meshes from files: Wavefront OBJ (tobj) and PLY
//! (ply-rs-bw; binary and ASCII, `.ply.gz` through flate2), as both scene
//! loaders need them. (To be written.)

use super::loader::SceneFileError;
use glam::{Vec2, Vec3};
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

/// Reads an OBJ file (all its objects merged into one mesh).
pub fn read_obj(path: &Path) -> Result<MeshData, SceneFileError> {
    Err(SceneFileError::Syntax {
        file: path.to_path_buf(),
        line: 1,
        message: "OBJ meshes are not supported yet".into(),
    })
}

/// Reads a PLY file (`.ply` or gzip-compressed `.ply.gz`).
pub fn read_ply(path: &Path) -> Result<MeshData, SceneFileError> {
    Err(SceneFileError::Syntax {
        file: path.to_path_buf(),
        line: 1,
        message: "PLY meshes are not supported yet".into(),
    })
}
