//! Procedural meshes for benchmarks and tests: deterministic geometry of any
//! size without files.

use glam::Vec3;

/// A height field over `[-1, 1]²` (in x and z) of `quads` × `quads` quads,
/// two triangles each, with the height
/// `0.15 sin(7x) cos(5z) + 0.05 sin(31x + 17z)`: vertex positions and
/// triangle indices. `quads = 710` gives 1,008,200 triangles.
pub fn displaced_grid(quads: u32) -> (Vec<Vec3>, Vec<[u32; 3]>) {
    let vertices_per_side = quads + 1;
    let mut positions = Vec::with_capacity((vertices_per_side * vertices_per_side) as usize);
    for j in 0..vertices_per_side {
        for i in 0..vertices_per_side {
            let x = 2.0 * i as f32 / quads as f32 - 1.0;
            let z = 2.0 * j as f32 / quads as f32 - 1.0;
            let height =
                0.15 * (7.0 * x).sin() * (5.0 * z).cos() + 0.05 * (31.0 * x + 17.0 * z).sin();
            positions.push(Vec3::new(x, height, z));
        }
    }
    let mut indices = Vec::with_capacity(2 * (quads * quads) as usize);
    for j in 0..quads {
        for i in 0..quads {
            let a = j * vertices_per_side + i;
            let (b, c, d) = (a + 1, a + vertices_per_side, a + vertices_per_side + 1);
            indices.push([a, c, d]);
            indices.push([a, d, b]);
        }
    }
    (positions, indices)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_has_two_triangles_per_quad_and_valid_indices() {
        let (positions, indices) = displaced_grid(3);
        assert_eq!(positions.len(), 16);
        assert_eq!(indices.len(), 18);
        assert!(
            indices
                .iter()
                .flatten()
                .all(|&i| (i as usize) < positions.len())
        );
    }
}
