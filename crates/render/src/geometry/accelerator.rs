//! The scene's geometry: all shapes plus a 4-wide BVH over every primitive
//! ([`super::wide_bvh`]: built by obvhs' PLOC, traversed with SIMD slab tests
//! and packets of watertight triangle tests).

use glam::Vec3;

use super::wide_bvh::{ClosestPrimitive, WideBvh};
use super::{Bounds3, GeometryError, Ray, Shape, SurfaceHit};

/// Which shape, and which primitive within it, a BVH leaf entry stands for.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct PrimitiveReference {
    /// Index into the shape list given to [`Geometry::new`].
    pub shape_index: u32,
    /// Triangle index for meshes, 0 for analytic shapes.
    pub primitive_index: u32,
}

/// The closest primitive a ray hits, without the surface record of
/// [`Geometry::intersect`]: what Embree's `rtcIntersect1` reports (distance,
/// geometry and primitive id, barycentrics). Cheaper when only visibility or a
/// distance is needed, and the like-for-like query for throughput comparisons.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PrimitiveHit {
    /// Ray parameter of the hit.
    pub t: f32,
    /// Which shape and primitive was hit.
    pub reference: PrimitiveReference,
    /// Barycentric weights of the triangle's vertices 0, 1, 2 (zero for
    /// analytic shapes).
    pub barycentric: [f32; 3],
}

/// What the traversal needs to test an analytic primitive (triangles live in
/// the BVH's packets), stored in BVH slot order.
#[derive(Clone, Copy, Debug)]
enum PrimitiveData {
    Triangle,
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
    /// Primitives in BVH slot order.
    primitives: Vec<BvhPrimitive>,
    bvh: Option<WideBvh>,
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

impl Geometry {
    /// Builds the BVH over every primitive of `shapes` (obvhs' PLOC with its
    /// `medium_build` search distance and reinsertion, collapsed into a 4-wide
    /// tree with up to 4 primitives per leaf). An empty list is allowed
    /// (nothing is ever hit). Fails if more than `u32::MAX` primitives are given.
    pub fn new(shapes: Vec<Shape>) -> Result<Self, GeometryError> {
        let mut primitives = Vec::new();
        let mut aabbs = Vec::new();
        let mut bounds = Bounds3::EMPTY;
        for (shape_index, shape) in shapes.iter().enumerate() {
            let shape_index = u32::try_from(shape_index)
                .map_err(|_| GeometryError::InvalidMesh("too many shapes".into()))?;
            for primitive_index in 0..shape.primitive_count() {
                let data = match shape {
                    Shape::Mesh(_) => PrimitiveData::Triangle,
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
        if u32::try_from(primitives.len()).is_err() || primitives.len() >= 1 << 31 {
            return Err(GeometryError::InvalidMesh(
                "more than 2^31 primitives".into(),
            ));
        }
        let bvh = if primitives.is_empty() {
            None
        } else {
            let bvh = WideBvh::build(&aabbs, |i| {
                let reference = primitives[i].reference;
                match &shapes[reference.shape_index as usize] {
                    Shape::Mesh(mesh) => Some((
                        mesh.triangle_vertices(reference.primitive_index as usize),
                        reference,
                    )),
                    _ => None,
                }
            });
            // Reorder so slot i holds the primitive the BVH refers to.
            primitives = bvh
                .slot_primitives()
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

    /// Tests the analytic primitive in `slot` (a sphere or a disk).
    #[inline]
    fn test_analytic(&self, slot: u32, ray: &Ray, t_max: f32) -> Option<f32> {
        let primitive = &self.primitives[slot as usize];
        match primitive.data {
            PrimitiveData::Sphere(sphere) => sphere.intersect_t(ray.origin, ray.direction, t_max),
            PrimitiveData::Disk => match &self.shapes[primitive.reference.shape_index as usize] {
                Shape::Disk(disk) => disk.intersect_t(ray.origin, ray.direction, t_max),
                _ => None,
            },
            PrimitiveData::Triangle => None,
        }
    }

    /// The closest hit of `ray` with `0 < t < t_max`, or `None`. The direction
    /// should be unit length (see the module documentation).
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<SurfaceHit> {
        self.closest_primitive(ray, t_max)
            .map(|hit| self.surface_hit(ray, hit))
    }

    /// The closest primitive hit by `ray` with `0 < t < t_max` (the same hit
    /// as [`Geometry::intersect`]), its distance and barycentrics only.
    pub fn intersect_primitive(&self, ray: &Ray, t_max: f32) -> Option<PrimitiveHit> {
        self.closest_primitive(ray, t_max).map(|hit| PrimitiveHit {
            t: hit.t,
            reference: hit.reference,
            barycentric: hit.barycentric,
        })
    }

    #[inline(always)]
    fn closest_primitive(&self, ray: &Ray, t_max: f32) -> Option<ClosestPrimitive> {
        let bvh = self.bvh.as_ref()?;
        if !Self::traceable(ray, t_max) {
            return None;
        }
        bvh.closest_hit(ray, t_max, |slot, t_max| {
            self.test_analytic(slot, ray, t_max)
                .map(|t| (t, self.primitives[slot as usize].reference))
        })
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
        bvh.any_hit(ray, t_max, |slot, t_max| {
            self.test_analytic(slot, ray, t_max).is_some()
        })
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
        let reference = closest.reference;
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
