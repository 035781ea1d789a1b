//! The closed set of shapes the renderer supports, with a common interface for
//! bounds, brute-force intersection and sampling.

use glam::{Vec2, Vec3};

use super::triangle::WatertightRay;
use super::{
    Bounds3, Disk, Ray, ShapeSample, Sphere, SurfaceHit, TriangleMesh, area_pdf_to_solid_angle,
};

/// A shape: a triangle mesh (also rectangles and cubes), a sphere or a disk.
#[derive(Clone, Debug)]
pub enum Shape {
    /// An indexed triangle mesh in world space.
    Mesh(TriangleMesh),
    /// An analytic sphere.
    Sphere(Sphere),
    /// An analytic disk.
    Disk(Disk),
}

impl From<TriangleMesh> for Shape {
    fn from(mesh: TriangleMesh) -> Self {
        Shape::Mesh(mesh)
    }
}

impl From<Sphere> for Shape {
    fn from(sphere: Sphere) -> Self {
        Shape::Sphere(sphere)
    }
}

impl From<Disk> for Shape {
    fn from(disk: Disk) -> Self {
        Shape::Disk(disk)
    }
}

impl Shape {
    /// Number of BVH primitives (triangles of a mesh; 1 for analytic shapes).
    pub fn primitive_count(&self) -> usize {
        match self {
            Shape::Mesh(mesh) => mesh.triangle_count(),
            Shape::Sphere(_) | Shape::Disk(_) => 1,
        }
    }

    /// World bounds of primitive `primitive_index`.
    pub fn primitive_bounds(&self, primitive_index: usize) -> Bounds3 {
        match self {
            Shape::Mesh(mesh) => mesh.triangle_bounds(primitive_index),
            Shape::Sphere(sphere) => sphere.bounds(),
            Shape::Disk(disk) => disk.bounds(),
        }
    }

    /// Total surface area.
    pub fn surface_area(&self) -> f32 {
        match self {
            Shape::Mesh(mesh) => mesh.surface_area(),
            Shape::Sphere(sphere) => sphere.surface_area(),
            Shape::Disk(disk) => disk.surface_area(),
        }
    }

    /// Closest hit of `ray` with this shape alone in `(0, t_max)`, testing every
    /// primitive (a reference for the BVH; `shape_index` is left 0).
    pub fn intersect_brute_force(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        match self {
            Shape::Mesh(mesh) => {
                let watertight = WatertightRay::new(ray.origin, ray.direction);
                let mut best = None;
                let mut closest = t_max;
                for index in 0..mesh.triangle_count() {
                    let [p0, p1, p2] = mesh.triangle_vertices(index);
                    if let Some(hit) = watertight.intersect(p0, p1, p2, closest) {
                        closest = hit.t;
                        best = Some((index, hit));
                    }
                }
                best.map(|(index, hit)| mesh.surface_hit(index, hit.barycentric, hit.t, ray.time))
            }
            Shape::Sphere(sphere) => sphere
                .intersect_t(ray.origin, ray.direction, t_max)
                .map(|t| sphere.surface_hit(ray.origin, ray.direction, t, ray.time)),
            Shape::Disk(disk) => disk
                .intersect_t(ray.origin, ray.direction, t_max)
                .map(|t| disk.surface_hit(ray.origin, ray.direction, t, ray.time)),
        }
    }

    /// A point uniformly distributed over the surface (`u_primitive` picks the
    /// mesh triangle by area and is ignored by analytic shapes). `None` only for
    /// a zero-area mesh.
    #[inline]
    pub fn sample_area(&self, u_primitive: f32, u: Vec2) -> Option<ShapeSample> {
        match self {
            Shape::Mesh(mesh) => mesh.sample_area(u_primitive, u).map(|(sample, _)| sample),
            Shape::Sphere(sphere) => Some(sphere.sample_area(u)),
            Shape::Disk(disk) => Some(disk.sample_area(u)),
        }
    }

    /// A point sampled for lighting `reference`: spheres sample the subtended
    /// cone of directions (uniform area from inside), meshes and disks sample
    /// uniformly by area. The density is reported per unit area; convert with
    /// [`ShapeSample::solid_angle_pdf`].
    #[inline]
    pub fn sample_from(&self, reference: Vec3, u_primitive: f32, u: Vec2) -> Option<ShapeSample> {
        match self {
            Shape::Sphere(sphere) => Some(sphere.sample_from(reference, u)),
            _ => self.sample_area(u_primitive, u),
        }
    }

    /// The area density with which [`Shape::sample_from`] produces `point` (a point
    /// on the shape with unit geometric `normal`) for `reference`.
    #[inline]
    pub fn pdf_area_from(&self, reference: Vec3, point: Vec3, normal: Vec3) -> f32 {
        match self {
            Shape::Mesh(mesh) => mesh.pdf_area(),
            Shape::Sphere(sphere) => sphere.pdf_area_from(reference, point, normal),
            Shape::Disk(disk) => 1.0 / disk.surface_area(),
        }
    }

    /// The solid-angle density at `reference` with which [`Shape::sample_from`]
    /// produces the direction towards `point` (with unit geometric `normal`), as
    /// needed for multiple importance sampling of BSDF-sampled rays that hit the
    /// shape.
    #[inline]
    pub fn pdf_solid_angle_from(&self, reference: Vec3, point: Vec3, normal: Vec3) -> f32 {
        match self {
            Shape::Sphere(sphere) => sphere.pdf_solid_angle_from(reference, point, normal),
            _ => area_pdf_to_solid_angle(
                self.pdf_area_from(reference, point, normal),
                reference,
                point,
                normal,
            ),
        }
    }
}
