//! Triangle meshes, stored in world space, and the Mitsuba-convention
//! rectangle and cube built from them.

use std::sync::OnceLock;

use glam::{Vec2, Vec3};

use super::sampling::{TriangleSampler, coordinate_frame};
use super::{AliasTable, Bounds3, GeometryError, ShapeSample, SurfaceHit, Transform};

/// An indexed triangle mesh in world space (transformed once at load, as pbrt).
///
/// Triangles wind counter-clockwise around their geometric normal. If the load
/// transform mirrors space (negative determinant) the vertex order of every
/// triangle is reversed at load so the winding normal keeps pointing to the same
/// side of the transformed surface (e.g. outward for a closed mesh).
#[derive(Clone, Debug)]
pub struct TriangleMesh {
    positions: Vec<Vec3>,
    normals: Option<Vec<Vec3>>,
    uvs: Option<Vec<Vec2>>,
    indices: Vec<[u32; 3]>,
    /// Per triangle, what [`TriangleMesh::surface_hit`] needs that does not
    /// depend on the hit point (same order as `indices`).
    frames: Vec<TriangleFrame>,
    /// Picks a triangle with probability proportional to its area; `None` if the
    /// mesh has zero total area (it can then not be sampled).
    area_distribution: Option<AliasTable>,
    surface_area: f32,
    /// `1 / surface_area`, or 0 for a mesh that cannot be sampled: the area
    /// density of [`TriangleMesh::sample_area`].
    inverse_surface_area: f32,
    /// Per-triangle records for [`TriangleMesh::sample_area`], built on the
    /// first sample (only emitters are sampled, and the records take more
    /// memory than the alias table).
    triangle_sampler: OnceLock<TriangleSampler>,
}

impl TriangleMesh {
    /// Builds a mesh from object-space data and the object-to-world transform.
    /// `normals` and `uvs`, when given, are per vertex (same length as
    /// `positions`). Fails on out-of-range indices, mismatched lengths or
    /// non-finite values.
    pub fn new(
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<Vec2>>,
        mut indices: Vec<[u32; 3]>,
        object_to_world: &Transform,
    ) -> Result<Self, GeometryError> {
        if indices.is_empty() {
            return Err(GeometryError::InvalidMesh("no triangles".into()));
        }
        if let Some(bad) = indices
            .iter()
            .flatten()
            .find(|&&i| i as usize >= positions.len())
        {
            return Err(GeometryError::InvalidMesh(format!(
                "index {bad} out of range for {} positions",
                positions.len()
            )));
        }
        if normals.as_ref().is_some_and(|n| n.len() != positions.len()) {
            return Err(GeometryError::InvalidMesh(
                "normals and positions differ in length".into(),
            ));
        }
        if uvs.as_ref().is_some_and(|uv| uv.len() != positions.len()) {
            return Err(GeometryError::InvalidMesh(
                "uvs and positions differ in length".into(),
            ));
        }
        if !positions.iter().all(|p| p.is_finite()) {
            return Err(GeometryError::NonFinite("mesh positions"));
        }
        if normals
            .as_ref()
            .is_some_and(|n| !n.iter().all(|v| v.is_finite()))
        {
            return Err(GeometryError::NonFinite("mesh normals"));
        }
        if uvs
            .as_ref()
            .is_some_and(|uv| !uv.iter().all(|v| v.is_finite()))
        {
            return Err(GeometryError::NonFinite("mesh uvs"));
        }
        let positions: Vec<Vec3> = positions
            .into_iter()
            .map(|p| object_to_world.point(p))
            .collect();
        let normals = normals.map(|n| {
            n.into_iter()
                .map(|v| object_to_world.normal(v).normalize_or_zero())
                .collect()
        });
        if object_to_world.swaps_handedness() {
            for triangle in &mut indices {
                triangle.swap(1, 2);
            }
        }
        let mut mesh = Self {
            positions,
            normals,
            uvs,
            indices,
            frames: Vec::new(),
            area_distribution: None,
            surface_area: 0.0,
            inverse_surface_area: 0.0,
            triangle_sampler: OnceLock::new(),
        };
        mesh.frames = (0..mesh.triangle_count())
            .map(|index| mesh.triangle_frame(index))
            .collect();
        let areas: Vec<f32> = (0..mesh.triangle_count())
            .map(|i| mesh.triangle_area(i))
            .collect();
        mesh.surface_area = areas.iter().map(|&a| a as f64).sum::<f64>() as f32;
        mesh.area_distribution = AliasTable::new(&areas).ok();
        if mesh.area_distribution.is_some() {
            mesh.inverse_surface_area = 1.0 / mesh.surface_area;
        }
        Ok(mesh)
    }

    /// Mitsuba's `rectangle`: the square `[-1, 1]²` in the plane `z = 0` of object
    /// space, normal `+z`, uv `(0,0)` at `(-1,-1)` to `(1,1)` at `(1,1)`, two triangles.
    pub fn rectangle(object_to_world: &Transform) -> Result<Self, GeometryError> {
        let positions = vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ];
        let uvs = vec![
            Vec2::new(0.0, 0.0),
            Vec2::new(1.0, 0.0),
            Vec2::new(1.0, 1.0),
            Vec2::new(0.0, 1.0),
        ];
        Self::new(
            positions,
            Some(vec![Vec3::Z; 4]),
            Some(uvs),
            vec![[0, 1, 2], [2, 3, 0]],
            object_to_world,
        )
    }

    /// Mitsuba's `cube`: `[-1, 1]³` in object space with outward normals, four
    /// vertices (own normals and uvs `[0,1]²`) and two triangles per face.
    pub fn cube(object_to_world: &Transform) -> Result<Self, GeometryError> {
        let mut positions = Vec::with_capacity(24);
        let mut normals = Vec::with_capacity(24);
        let mut uvs = Vec::with_capacity(24);
        let mut indices = Vec::with_capacity(12);
        for axis in 0..3 {
            for sign in [-1.0f32, 1.0] {
                let normal = sign * Vec3::AXES[axis];
                // (u, v, normal) is right-handed so the corners below wind
                // counter-clockwise seen from outside.
                let (u, v) = if sign > 0.0 {
                    (Vec3::AXES[(axis + 1) % 3], Vec3::AXES[(axis + 2) % 3])
                } else {
                    (Vec3::AXES[(axis + 2) % 3], Vec3::AXES[(axis + 1) % 3])
                };
                let base = positions.len() as u32;
                for (a, b) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
                    positions.push(normal + a * u + b * v);
                    normals.push(normal);
                    uvs.push(Vec2::new(0.5 * (a + 1.0), 0.5 * (b + 1.0)));
                }
                indices.push([base, base + 1, base + 2]);
                indices.push([base + 2, base + 3, base]);
            }
        }
        Self::new(
            positions,
            Some(normals),
            Some(uvs),
            indices,
            object_to_world,
        )
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// World-space vertex positions.
    pub fn positions(&self) -> &[Vec3] {
        &self.positions
    }

    /// Vertex indices of every triangle.
    pub fn indices(&self) -> &[[u32; 3]] {
        &self.indices
    }

    /// World-space per-vertex unit normals, if the mesh has them.
    pub fn normals(&self) -> Option<&[Vec3]> {
        self.normals.as_deref()
    }

    /// Per-vertex uvs, if the mesh has them.
    pub fn uvs(&self) -> Option<&[Vec2]> {
        self.uvs.as_deref()
    }

    /// The three world-space vertices of triangle `index`.
    #[inline]
    pub fn triangle_vertices(&self, index: usize) -> [Vec3; 3] {
        let [a, b, c] = self.indices[index];
        [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ]
    }

    /// Area of triangle `index`.
    pub fn triangle_area(&self, index: usize) -> f32 {
        let [p0, p1, p2] = self.triangle_vertices(index);
        0.5 * (p1 - p0).cross(p2 - p0).length()
    }

    /// Total surface area.
    pub fn surface_area(&self) -> f32 {
        self.surface_area
    }

    /// World bounds of triangle `index`.
    pub fn triangle_bounds(&self, index: usize) -> Bounds3 {
        Bounds3::from_points(self.triangle_vertices(index))
    }

    /// Unit geometric (winding) normal of triangle `index` (zero if degenerate).
    pub fn triangle_normal(&self, index: usize) -> Vec3 {
        self.frames[index].geometric_normal
    }

    fn vertex_uvs(&self, index: usize) -> [Vec2; 3] {
        match &self.uvs {
            Some(uvs) => self.indices[index].map(|i| uvs[i as usize]),
            // pbrt's default parameterisation.
            None => [
                Vec2::new(0.0, 0.0),
                Vec2::new(1.0, 0.0),
                Vec2::new(1.0, 1.0),
            ],
        }
    }

    /// The hit-independent part of triangle `index`'s hit record: its unit
    /// geometric normal and surface derivatives. Computed once per triangle at
    /// load so that [`TriangleMesh::surface_hit`] only interpolates (a cross
    /// product, a normalisation and the uv-derivative solve saved per hit).
    fn triangle_frame(&self, index: usize) -> TriangleFrame {
        let [p0, p1, p2] = self.triangle_vertices(index);
        let geometric_normal = (p1 - p0).cross(p2 - p0).normalize_or_zero();
        let (dpdu, dpdv) = if self.uvs.is_none() && geometric_normal != Vec3::ZERO {
            // pbrt's default uvs (0, 0), (1, 0), (1, 1), for which the general
            // formula reduces to ∂p/∂u = p1 − p0 and ∂p/∂v = p2 − p1. Both are
            // edges of the triangle, so they are usable tangents whenever its
            // normal is (a zero normal means a degenerate or overflowing one).
            let (dpdu, dpdv) = (p1 - p0, p2 - p1);
            debug_assert!(
                usable_tangent(dpdu, geometric_normal) && usable_tangent(dpdv, geometric_normal)
            );
            (dpdu, dpdv)
        } else {
            uv_derivatives(geometric_normal, [p0, p1, p2], self.vertex_uvs(index))
        };
        TriangleFrame {
            geometric_normal,
            dpdu,
            dpdv,
        }
    }

    /// The full hit record for triangle `index` hit at barycentrics `barycentric`
    /// and ray parameter `t` (shape index filled in as 0; the caller sets it).
    /// Always inlined: called out of line, its record was built on the stack
    /// and copied into the caller's (the path tracer's walk: 1 % of its
    /// instructions).
    #[inline(always)]
    pub fn surface_hit(
        &self,
        index: usize,
        barycentric: [f32; 3],
        t: f32,
        time: f32,
    ) -> SurfaceHit {
        let [a, b, c] = self.indices[index];
        let [p0, p1, p2] = [
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        ];
        let TriangleFrame {
            geometric_normal,
            dpdu,
            dpdv,
        } = self.frames[index];
        let [b0, b1, b2] = barycentric;
        let point = b0 * p0 + b1 * p1 + b2 * p2;
        let uv = match &self.uvs {
            Some(uvs) => b0 * uvs[a as usize] + b1 * uvs[b as usize] + b2 * uvs[c as usize],
            // pbrt's default uvs (0, 0), (1, 0), (1, 1).
            None => Vec2::new(b1 + b2, b2),
        };
        let shading_normal = match &self.normals {
            Some(normals) => {
                let n = (b0 * normals[a as usize]
                    + b1 * normals[b as usize]
                    + b2 * normals[c as usize])
                    .normalize_or_zero();
                if n == Vec3::ZERO {
                    geometric_normal
                } else if n.dot(geometric_normal) < 0.0 {
                    -n
                } else {
                    n
                }
            }
            None => geometric_normal,
        };
        SurfaceHit {
            t,
            point,
            geometric_normal,
            shading_normal,
            uv,
            dpdu,
            dpdv,
            shape_index: 0,
            primitive_index: index as u32,
            time,
        }
    }

    /// A point uniformly distributed over the whole mesh: `u_triangle` picks a
    /// triangle with probability proportional to its area (alias table), `u`
    /// places the point in it (Heitz's square-to-triangle map). Returns `None`
    /// for a mesh of zero area. Also returns the triangle index.
    #[inline]
    pub fn sample_area(&self, u_triangle: f32, u: Vec2) -> Option<(ShapeSample, usize)> {
        let distribution = self.area_distribution.as_ref()?;
        let sampler = self.triangle_sampler.get_or_init(|| {
            TriangleSampler::new(
                distribution,
                (0..self.triangle_count()).map(|index| self.triangle_vertices(index)),
            )
        });
        let (point, normal, index) = sampler.sample(u_triangle, u);
        Some((
            ShapeSample {
                point,
                normal,
                pdf_area: self.inverse_surface_area,
            },
            index,
        ))
    }

    /// The area density of [`TriangleMesh::sample_area`] at any point of the
    /// mesh: `1 / total area` (0 for a zero-area mesh).
    #[inline]
    pub fn pdf_area(&self) -> f32 {
        self.inverse_surface_area
    }
}

/// The part of a triangle's hit record that is the same at every point of
/// it, precomputed per triangle (36 bytes each; see
/// [`TriangleMesh::surface_hit`]).
#[derive(Clone, Copy, Debug)]
struct TriangleFrame {
    /// Unit geometric (winding) normal, zero if the triangle is degenerate.
    geometric_normal: Vec3,
    /// `∂p/∂u`, as [`SurfaceHit::dpdu`].
    dpdu: Vec3,
    /// `∂p/∂v`, as [`SurfaceHit::dpdv`].
    dpdv: Vec3,
}

/// Whether `tangent` can serve as a surface derivative: finite and not
/// parallel to `normal`.
#[inline]
fn usable_tangent(tangent: Vec3, normal: Vec3) -> bool {
    tangent.is_finite() && tangent.cross(normal) != Vec3::ZERO
}

/// `(∂p/∂u, ∂p/∂v)` of the triangle with vertices `positions`, uvs `uvs` and
/// unit normal `normal`, from the uv differentials (pbrt-v4, section 6.5.3),
/// with arbitrary tangents perpendicular to the normal where the uvs are
/// degenerate (see [`SurfaceHit::dpdu`]).
fn uv_derivatives(normal: Vec3, positions: [Vec3; 3], uvs: [Vec2; 3]) -> (Vec3, Vec3) {
    let [p0, p1, p2] = positions;
    let duv02 = uvs[0] - uvs[2];
    let duv12 = uvs[1] - uvs[2];
    let (dp02, dp12) = (p0 - p2, p1 - p2);
    let determinant = duv02.x * duv12.y - duv02.y * duv12.x;
    // One division for both derivatives.
    let inverse_determinant = 1.0 / determinant;
    let mut dpdu = if determinant.abs() > 1e-12 {
        (duv12.y * dp02 - duv02.y * dp12) * inverse_determinant
    } else {
        Vec3::ZERO
    };
    let usable = usable_tangent(dpdu, normal);
    if !usable {
        dpdu = coordinate_frame(normal).0;
    }
    let mut dpdv = if usable {
        (duv02.x * dp12 - duv12.x * dp02) * inverse_determinant
    } else {
        Vec3::ZERO
    };
    if !usable_tangent(dpdv, normal) {
        dpdv = normal.cross(dpdu);
    }
    (dpdu, dpdv)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_meshes() {
        let p = vec![Vec3::ZERO, Vec3::X, Vec3::Y];
        assert!(
            TriangleMesh::new(p.clone(), None, None, vec![[0, 1, 3]], &Transform::IDENTITY)
                .is_err()
        );
        assert!(
            TriangleMesh::new(
                p.clone(),
                Some(vec![Vec3::Z]),
                None,
                vec![[0, 1, 2]],
                &Transform::IDENTITY
            )
            .is_err()
        );
        assert!(TriangleMesh::new(p.clone(), None, None, vec![], &Transform::IDENTITY).is_err());
        assert!(TriangleMesh::new(p, None, None, vec![[0, 1, 2]], &Transform::IDENTITY).is_ok());
    }

    #[test]
    fn cube_normals_point_outward_even_when_mirrored() {
        for transform in [
            Transform::IDENTITY,
            Transform::scale(Vec3::new(-1.0, 2.0, 1.0)).unwrap(),
        ] {
            let cube = TriangleMesh::cube(&transform).unwrap();
            assert_eq!(cube.triangle_count(), 12);
            for i in 0..12 {
                let [p0, p1, p2] = cube.triangle_vertices(i);
                let centre = (p0 + p1 + p2) / 3.0;
                assert!(cube.triangle_normal(i).dot(centre) > 0.0);
            }
        }
        let rectangle = TriangleMesh::rectangle(&Transform::IDENTITY).unwrap();
        assert_eq!(rectangle.surface_area(), 4.0);
        assert!(rectangle.triangle_area(0) > 0.0);
        assert_eq!(rectangle.triangle_normal(0), Vec3::Z);
        assert_eq!(rectangle.triangle_normal(1), Vec3::Z);
    }

    #[test]
    fn surface_hit_uses_the_triangle_frame() {
        let positions = vec![
            Vec3::ZERO,
            Vec3::new(2.0, 0.0, 0.0),
            Vec3::new(0.0, 3.0, 0.0),
        ];
        let uvs = vec![Vec2::ZERO, Vec2::new(1.0, 0.0), Vec2::new(0.0, 1.0)];
        let with_uvs = TriangleMesh::new(
            positions.clone(),
            None,
            Some(uvs),
            vec![[0, 1, 2]],
            &Transform::IDENTITY,
        )
        .unwrap();
        let hit = with_uvs.surface_hit(0, [0.5, 0.25, 0.25], 1.0, 0.0);
        assert_eq!(hit.geometric_normal, Vec3::Z);
        assert_eq!(hit.shading_normal, Vec3::Z);
        assert_eq!(hit.dpdu, Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(hit.dpdv, Vec3::new(0.0, 3.0, 0.0));
        assert_eq!(hit.uv, Vec2::new(0.25, 0.25));
        assert_eq!(hit.point, Vec3::new(0.5, 0.75, 0.0));
        let default_uvs =
            TriangleMesh::new(positions, None, None, vec![[0, 1, 2]], &Transform::IDENTITY)
                .unwrap();
        let hit = default_uvs.surface_hit(0, [0.5, 0.25, 0.25], 1.0, 0.0);
        assert_eq!(hit.dpdu, Vec3::new(2.0, 0.0, 0.0));
        assert_eq!(hit.dpdv, Vec3::new(-2.0, 3.0, 0.0));
        assert_eq!(hit.uv, Vec2::new(0.5, 0.25));
        // A degenerate triangle still gets usable tangents.
        let degenerate = TriangleMesh::new(
            vec![Vec3::ZERO, Vec3::X, 2.0 * Vec3::X],
            None,
            None,
            vec![[0, 1, 2]],
            &Transform::IDENTITY,
        )
        .unwrap();
        let hit = degenerate.surface_hit(0, [0.5, 0.25, 0.25], 1.0, 0.0);
        assert_eq!(hit.geometric_normal, Vec3::ZERO);
        assert!(hit.dpdu.is_finite() && hit.dpdv.is_finite());
    }
}
