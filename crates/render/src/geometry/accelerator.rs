//! The scene's geometry: all shapes plus an 8-wide compressed BVH (obvhs' CWBVH,
//! Ylitie et al. 2017, built with PLOC) over every primitive, traversed with
//! this module's own intersection routines.

use std::time::Duration;

// `UVec2` is used unqualified inside obvhs' `traverse!` macro.
use glam::{UVec2, Vec3, Vec3A};
use obvhs::BvhBuildParams;
use obvhs::cwbvh::CwBvh;
use obvhs::cwbvh::builder::build_cwbvh;

use super::triangle::WatertightRay;
use super::{Bounds3, GeometryError, Ray, Shape, SurfaceHit};

/// Which shape, and which primitive within it, a BVH leaf entry stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PrimitiveReference {
    /// Index into the shape list given to [`Geometry::new`].
    pub shape_index: u32,
    /// Triangle index for meshes, 0 for analytic shapes.
    pub primitive_index: u32,
}

/// What the traversal loop needs to test one primitive, stored in BVH leaf
/// order so leaves index it directly. Triangles are stored inline (no index
/// indirection), analytic shapes are looked up through their shape index.
#[derive(Clone, Copy, Debug)]
enum PrimitiveData {
    Triangle([Vec3; 3]),
    Sphere(super::Sphere),
    Disk,
}

#[derive(Clone, Copy, Debug)]
struct BvhPrimitive {
    data: PrimitiveData,
    reference: PrimitiveReference,
}

/// All shapes of a scene and the BVH over their primitives. Immutable after
/// construction and `Sync`, so any number of threads can trace rays at once.
pub struct Geometry {
    shapes: Vec<Shape>,
    primitives: Vec<BvhPrimitive>,
    bvh: Option<CwBvh>,
    bounds: Bounds3,
}

impl std::fmt::Debug for Geometry {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Geometry")
            .field("shapes", &self.shapes.len())
            .field("primitives", &self.primitives.len())
            .field("bounds", &self.bounds)
            .finish()
    }
}

/// The per-hit outcome of traversal before the full record is built.
#[derive(Clone, Copy)]
struct ClosestPrimitive {
    slot: usize,
    t: f32,
    barycentric: [f32; 3],
}

impl Geometry {
    /// Builds the BVH over every primitive of `shapes` (obvhs' `medium_build`
    /// preset: PLOC with medium search distance plus reinsertion, up to 3
    /// primitives per leaf). An empty list is allowed (nothing is ever hit).
    /// Fails if more than `u32::MAX` primitives are given.
    pub fn new(shapes: Vec<Shape>) -> Result<Self, GeometryError> {
        let mut primitives = Vec::new();
        let mut aabbs = Vec::new();
        let mut bounds = Bounds3::EMPTY;
        for (shape_index, shape) in shapes.iter().enumerate() {
            let shape_index = u32::try_from(shape_index)
                .map_err(|_| GeometryError::InvalidMesh("too many shapes".into()))?;
            for primitive_index in 0..shape.primitive_count() {
                let data = match shape {
                    Shape::Mesh(mesh) => {
                        PrimitiveData::Triangle(mesh.triangle_vertices(primitive_index))
                    }
                    Shape::Sphere(sphere) => PrimitiveData::Sphere(*sphere),
                    Shape::Disk(_) => PrimitiveData::Disk,
                };
                let primitive_bounds = shape.primitive_bounds(primitive_index);
                bounds = bounds.union(primitive_bounds);
                aabbs.push(primitive_bounds.to_aabb());
                primitives.push(BvhPrimitive {
                    data,
                    reference: PrimitiveReference {
                        shape_index,
                        primitive_index: primitive_index as u32,
                    },
                });
            }
        }
        if u32::try_from(primitives.len()).is_err() {
            return Err(GeometryError::InvalidMesh(
                "more than u32::MAX primitives".into(),
            ));
        }
        let bvh = if primitives.is_empty() {
            None
        } else {
            let bvh = build_cwbvh(
                &aabbs,
                BvhBuildParams::medium_build(),
                &mut Duration::default(),
            );
            // Reorder so leaf slot i holds the primitive the BVH refers to.
            primitives = bvh
                .primitive_indices
                .iter()
                .map(|&i| primitives[i as usize])
                .collect();
            Some(bvh)
        };
        Ok(Self {
            shapes,
            primitives,
            bvh,
            bounds,
        })
    }

    /// The shapes, in the order given.
    pub fn shapes(&self) -> &[Shape] {
        &self.shapes
    }

    /// Bounds of everything.
    pub fn bounds(&self) -> Bounds3 {
        self.bounds
    }

    /// Total number of primitives in the BVH.
    pub fn primitive_count(&self) -> usize {
        self.primitives.len()
    }

    /// Every primitive's shape and primitive index (in BVH leaf order).
    pub fn primitive_references(&self) -> impl Iterator<Item = PrimitiveReference> + '_ {
        self.primitives.iter().map(|p| p.reference)
    }

    /// Whether a ray can be traced: finite origin, finite non-zero direction,
    /// positive `t_max`.
    fn traceable(ray: &Ray, t_max: f32) -> bool {
        ray.origin.is_finite()
            && ray.direction.is_finite()
            && ray.direction != Vec3::ZERO
            && t_max > 0.0
    }

    #[inline(always)]
    fn test_primitive(
        &self,
        slot: usize,
        ray: &Ray,
        watertight: &WatertightRay,
        t_max: f32,
    ) -> Option<(f32, [f32; 3])> {
        let primitive = &self.primitives[slot];
        match primitive.data {
            PrimitiveData::Triangle([p0, p1, p2]) => watertight
                .intersect(p0, p1, p2, t_max)
                .map(|hit| (hit.t, hit.barycentric)),
            PrimitiveData::Sphere(sphere) => sphere
                .intersect_t(ray.origin, ray.direction, t_max)
                .map(|t| (t, [0.0; 3])),
            PrimitiveData::Disk => match &self.shapes[primitive.reference.shape_index as usize] {
                Shape::Disk(disk) => disk
                    .intersect_t(ray.origin, ray.direction, t_max)
                    .map(|t| (t, [0.0; 3])),
                _ => None,
            },
        }
    }

    /// The ray in obvhs' form for the node tests. Negative zeros in the
    /// direction are replaced by positive zeros (`-0 + 0 = +0`): obvhs picks the
    /// near slab plane from `direction < 0` but takes the reciprocal's sign from
    /// the zero's sign, so a `-0` component would swap near and far and make the
    /// ray miss every box (e.g. for `-Vec3::Y`, whose x and z are `-0`).
    fn obvhs_ray(ray: &Ray, t_max: f32) -> obvhs::ray::Ray {
        let direction = Vec3A::from(ray.direction) + Vec3A::ZERO;
        obvhs::ray::Ray::new(Vec3A::from(ray.origin), direction, 0.0, t_max)
    }

    /// The closest hit of `ray` with `0 < t < t_max`, or `None`. The direction
    /// should be unit length (see the module documentation).
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        let bvh = self.bvh.as_ref()?;
        if !Self::traceable(ray, t_max) {
            return None;
        }
        let watertight = WatertightRay::new(ray.origin, ray.direction);
        let mut traversal_ray = Self::obvhs_ray(ray, t_max);
        let mut closest: Option<ClosestPrimitive> = None;
        let mut state = bvh.new_traversal(traversal_ray.direction);
        let mut node;
        obvhs::traverse!(
            bvh,
            node,
            state,
            node.intersect_ray(&traversal_ray, state.oct_inv4),
            {
                let slot = state.primitive_id as usize;
                if let Some((t, barycentric)) =
                    self.test_primitive(slot, ray, &watertight, traversal_ray.tmax)
                {
                    traversal_ray.tmax = t;
                    closest = Some(ClosestPrimitive {
                        slot,
                        t,
                        barycentric,
                    });
                }
            }
        );
        closest.map(|hit| self.surface_hit(ray, hit))
    }

    /// Whether anything is hit with `0 < t < t_max` (any-hit query for shadow
    /// rays; stops at the first hit found).
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        let Some(bvh) = self.bvh.as_ref() else {
            return false;
        };
        if !Self::traceable(ray, t_max) {
            return false;
        }
        let watertight = WatertightRay::new(ray.origin, ray.direction);
        let traversal_ray = Self::obvhs_ray(ray, t_max);
        let mut state = bvh.new_traversal(traversal_ray.direction);
        let mut node;
        let mut hit = false;
        'traversal: {
            obvhs::traverse!(
                bvh,
                node,
                state,
                node.intersect_ray(&traversal_ray, state.oct_inv4),
                {
                    if self
                        .test_primitive(state.primitive_id as usize, ray, &watertight, t_max)
                        .is_some()
                    {
                        hit = true;
                        break 'traversal;
                    }
                }
            );
        }
        hit
    }

    /// The closest hit found by testing every primitive of every shape (slow;
    /// a reference for tests).
    pub fn intersect_brute_force(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        if !Self::traceable(ray, t_max) {
            return None;
        }
        let mut best: Option<SurfaceHit> = None;
        for (shape_index, shape) in self.shapes.iter().enumerate() {
            let limit = best.map_or(t_max, |b| b.t);
            if let Some(mut hit) = shape.intersect_brute_force(ray, limit) {
                hit.shape_index = shape_index as u32;
                best = Some(hit);
            }
        }
        best
    }

    fn surface_hit(&self, ray: &Ray, closest: ClosestPrimitive) -> SurfaceHit {
        let reference = self.primitives[closest.slot].reference;
        let mut hit = match &self.shapes[reference.shape_index as usize] {
            Shape::Mesh(mesh) => mesh.surface_hit(
                reference.primitive_index as usize,
                closest.barycentric,
                closest.t,
                ray.time,
            ),
            Shape::Sphere(sphere) => {
                sphere.surface_hit(ray.origin, ray.direction, closest.t, ray.time)
            }
            Shape::Disk(disk) => disk.surface_hit(ray.origin, ray.direction, closest.t, ray.time),
        };
        hit.shape_index = reference.shape_index;
        hit.primitive_index = reference.primitive_index;
        hit
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn geometry_is_send_and_sync() {
        fn assert_sync<T: Send + Sync>() {}
        assert_sync::<Geometry>();
    }

    #[test]
    fn empty_scene_hits_nothing() {
        let geometry = Geometry::new(Vec::new()).unwrap();
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert!(geometry.intersect(&ray, f32::INFINITY).is_none());
        assert!(!geometry.occluded(&ray, f32::INFINITY));
    }
}
