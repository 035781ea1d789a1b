//! The scene's geometry: all shapes plus an 8-wide BVH over every primitive
//! ([`super::wide_bvh`]: built by obvhs' PLOC, traversed with SIMD slab tests
//! and packets of watertight triangle tests).

use glam::Vec3;

use super::wide_bvh::{BuildOptions, BuildTriangle, ClosestPrimitive, WideBvh, WideBvhStatistics};
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

/// How the BVH's leaves store triangles. The hits are the same bit for bit;
/// only speed and memory differ.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TriangleLeafLayout {
    /// Packets of four triangles with their vertices and ids (192 bytes, 48
    /// a triangle): a leaf test reads nothing but its packet. The faster
    /// layout on both scenes of `examples/ray_throughput.rs`, the 1M-triangle
    /// one included (docs/performance.md, "BVH").
    #[default]
    Vertices,
    /// Packets of four triangles' vertex indices and slots (64 bytes) into a
    /// copy of all vertices (16 bytes each): about a third of the memory for
    /// closed meshes, but each packet test waits for a second, dependent
    /// memory access (the vertices) and gathers them (about 40 more
    /// instructions), which measured 25–40 % slower even on 1M triangles.
    /// For scenes whose vertex packets would not fit in memory.
    Indexed,
}

/// Choices for the acceleration structure of [`Geometry::with_options`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AcceleratorOptions {
    /// How leaves store triangles.
    pub leaf_layout: TriangleLeafLayout,
    /// Whether sibling leaves are merged into one packet where the surface
    /// area heuristic favours it (fewer, fuller packets).
    pub merge_leaves: bool,
}

impl Default for AcceleratorOptions {
    fn default() -> Self {
        Self {
            leaf_layout: TriangleLeafLayout::Vertices,
            merge_leaves: true,
        }
    }
}

/// Size and quality of a [`Geometry`]'s BVH (see [`Geometry::accelerator_statistics`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AcceleratorStatistics {
    /// 8-wide inner nodes (256 bytes each).
    pub nodes: usize,
    /// Bytes of all nodes.
    pub node_bytes: usize,
    /// Leaves.
    pub leaves: usize,
    /// Triangle packets.
    pub packets: usize,
    /// Bytes of all packets.
    pub packet_bytes: usize,
    /// Bytes of the shared vertex array of indexed leaves (0 otherwise).
    pub shared_vertex_bytes: usize,
    /// Triangles per packet lane (1 when every packet holds four triangles).
    pub packet_fill: f64,
    /// Surface area heuristic cost, one unit per node and per packet test.
    pub sah_cost: f64,
    /// Whether the leaves are indexed.
    pub indexed: bool,
}

impl From<WideBvhStatistics> for AcceleratorStatistics {
    fn from(s: WideBvhStatistics) -> Self {
        Self {
            nodes: s.nodes,
            node_bytes: s.node_bytes,
            leaves: s.leaves,
            packets: s.packets,
            packet_bytes: s.packet_bytes,
            shared_vertex_bytes: s.shared_vertex_bytes,
            packet_fill: s.packet_fill,
            sah_cost: s.sah_cost,
            indexed: s.indexed,
        }
    }
}

impl std::fmt::Display for AcceleratorStatistics {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let mib = |bytes: usize| bytes as f64 / (1 << 20) as f64;
        write!(
            f,
            "{} nodes ({:.1} MiB), {} leaves, {} {} packets ({:.1} MiB{}), fill {:.1} %, SAH cost {:.2}",
            self.nodes,
            mib(self.node_bytes),
            self.leaves,
            self.packets,
            if self.indexed { "indexed" } else { "vertex" },
            mib(self.packet_bytes),
            if self.indexed {
                format!(
                    " + {:.1} MiB shared vertices",
                    mib(self.shared_vertex_bytes)
                )
            } else {
                String::new()
            },
            100.0 * self.packet_fill,
            self.sah_cost
        )
    }
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
    /// `medium_build` search distance and reinsertion, collapsed into an
    /// 8-wide tree with up to 4 primitives per leaf, vertex packets and
    /// merged leaves: [`AcceleratorOptions::default`]). An empty list is allowed
    /// (nothing is ever hit). Fails if more than `u32::MAX` primitives are given.
    pub fn new(shapes: Vec<Shape>) -> Result<Self, GeometryError> {
        Self::with_options(shapes, AcceleratorOptions::default())
    }

    /// [`Geometry::new`] with explicit acceleration structure choices (the
    /// hits are the same for every choice, bit for bit).
    pub fn with_options(
        shapes: Vec<Shape>,
        options: AcceleratorOptions,
    ) -> Result<Self, GeometryError> {
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
            // Every mesh's vertices, one after another, for indexed leaves.
            let mut vertex_offsets = vec![0u32; shapes.len()];
            let mut shared_vertices = Vec::new();
            let indexed = options.leaf_layout == TriangleLeafLayout::Indexed;
            if indexed {
                for (shape, offset) in shapes.iter().zip(&mut vertex_offsets) {
                    if let Shape::Mesh(mesh) = shape {
                        *offset = u32::try_from(shared_vertices.len()).map_err(|_| {
                            GeometryError::InvalidMesh("more than 2^32 vertices".into())
                        })?;
                        shared_vertices.extend_from_slice(mesh.positions());
                    }
                }
                if shared_vertices.len() >= u32::MAX as usize {
                    return Err(GeometryError::InvalidMesh("more than 2^32 vertices".into()));
                }
            }
            let bvh = WideBvh::build(
                &aabbs,
                |i| {
                    let reference = primitives[i].reference;
                    let shape = reference.shape_index as usize;
                    match &shapes[shape] {
                        Shape::Mesh(mesh) => {
                            let triangle = reference.primitive_index as usize;
                            Some(BuildTriangle {
                                vertices: mesh.triangle_vertices(triangle),
                                vertex_indices: mesh.indices()[triangle]
                                    .map(|index| index + vertex_offsets[shape]),
                                reference,
                            })
                        }
                        _ => None,
                    }
                },
                BuildOptions {
                    shared_vertices: indexed.then_some(shared_vertices.as_slice()),
                    merge_leaves: options.merge_leaves,
                },
            );
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

    /// Size and quality of the BVH (`None` for an empty scene).
    pub fn accelerator_statistics(&self) -> Option<AcceleratorStatistics> {
        self.bvh.as_ref().map(|bvh| bvh.statistics().into())
    }

    /// The BVH, for the tree dump of `wide_bvh`'s tests.
    #[cfg(test)]
    pub(crate) fn bvh_for_tests(&self) -> &WideBvh {
        self.bvh.as_ref().unwrap()
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
    ///
    /// Every ray pays for this check, so it is written without branches:
    /// `0 · x` is (signed) zero for a finite `x` and NaN for an infinite or
    /// NaN one, so the sum of the six products is zero exactly when all six
    /// coordinates are finite (`Vec3::is_finite` tests them one by one,
    /// about twice the instructions).
    #[inline(always)]
    fn traceable(ray: &Ray, t_max: f32) -> bool {
        let probe = ray.origin * 0.0 + ray.direction * 0.0;
        let finite = probe.x + probe.y + probe.z == 0.0;
        let non_zero = ray.direction.cmpne(Vec3::ZERO).any();
        finite & non_zero & (t_max > 0.0)
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
    #[inline]
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

    /// Two meshes and a sphere: every leaf layout, with and without leaf
    /// merging, finds the same closest hit (shape, primitive, distance and
    /// barycentrics, bit for bit) as testing every primitive, and the same
    /// any-hit answer; indexed leaves offset the second mesh's vertex indices.
    #[test]
    fn every_layout_matches_brute_force() {
        let grid = {
            let (positions, indices) = super::super::procedural::displaced_grid(12);
            super::super::TriangleMesh::new(
                positions,
                None,
                None,
                indices,
                &super::super::Transform::IDENTITY,
            )
            .unwrap()
        };
        let cube = super::super::TriangleMesh::cube(&super::super::Transform::translate(
            Vec3::new(0.3, 0.2, -0.1),
        ))
        .unwrap();
        let sphere = super::super::Sphere::new(Vec3::new(-0.4, 0.1, 0.3), 0.35).unwrap();
        let shapes: Vec<Shape> = vec![grid.into(), sphere.into(), cube.into()];
        let mut state = 3u64;
        let mut uniform = move || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
        };
        let rays: Vec<(Ray, f32)> = (0..3000)
            .map(|i| {
                let origin = Vec3::new(uniform(), uniform(), uniform()) * 3.0 - Vec3::splat(1.5);
                let direction = (Vec3::new(uniform(), uniform(), uniform()) - Vec3::splat(0.5))
                    .try_normalize()
                    .unwrap_or(Vec3::Z);
                (
                    Ray::new(origin, direction),
                    if i % 3 == 0 {
                        2.0 * uniform()
                    } else {
                        f32::INFINITY
                    },
                )
            })
            .collect();
        for leaf_layout in [TriangleLeafLayout::Vertices, TriangleLeafLayout::Indexed] {
            for merge_leaves in [false, true] {
                let options = AcceleratorOptions {
                    leaf_layout,
                    merge_leaves,
                };
                let geometry = Geometry::with_options(shapes.clone(), options).unwrap();
                let statistics = geometry.accelerator_statistics().unwrap();
                assert_eq!(
                    statistics.indexed,
                    leaf_layout == TriangleLeafLayout::Indexed
                );
                let mut hits = [0; 3];
                for (ray, t_max) in &rays {
                    let expected = geometry.intersect_brute_force(ray, *t_max);
                    let found = geometry.intersect_primitive(ray, *t_max);
                    assert_eq!(geometry.occluded(ray, *t_max), expected.is_some());
                    match (found, expected) {
                        (None, None) => {}
                        (Some(found), Some(expected)) => {
                            let reference = found.reference;
                            if (reference.shape_index, reference.primitive_index)
                                == (expected.shape_index, expected.primitive_index)
                            {
                                assert_eq!(found.t, expected.t, "{options:?} {ray:?}");
                                assert_eq!(geometry.intersect(ray, *t_max), Some(expected));
                            } else {
                                // Only a tie on a shared edge may pick another triangle.
                                assert!((found.t - expected.t).abs() <= 1e-5 * expected.t);
                            }
                            hits[expected.shape_index as usize] += 1;
                        }
                        (found, expected) => panic!("{options:?}: {found:?} vs {expected:?}"),
                    }
                }
                assert!(hits.iter().all(|&count| count > 20), "{hits:?}");
            }
        }
    }

    #[test]
    fn traceable_rejects_non_finite_zero_and_non_positive() {
        let ray = |origin: Vec3, direction: Vec3| Ray::new(origin, direction);
        let good = ray(Vec3::new(1.0, -2.0, 3.0), Vec3::new(0.0, -1e-30, 0.0));
        assert!(Geometry::traceable(&good, 1.0));
        assert!(Geometry::traceable(&good, f32::INFINITY));
        assert!(!Geometry::traceable(&good, 0.0));
        assert!(!Geometry::traceable(&good, -1.0));
        assert!(!Geometry::traceable(&good, f32::NAN));
        let bad = [f32::INFINITY, f32::NEG_INFINITY, f32::NAN];
        for value in bad {
            for axis in 0..3 {
                let mut coordinates = [1.0f32; 3];
                coordinates[axis] = value;
                let odd = Vec3::from_array(coordinates);
                assert!(!Geometry::traceable(&ray(odd, Vec3::Z), 1.0), "{odd}");
                assert!(!Geometry::traceable(&ray(Vec3::ZERO, odd), 1.0), "{odd}");
            }
        }
        assert!(!Geometry::traceable(&ray(Vec3::ZERO, Vec3::ZERO), 1.0));
        assert!(!Geometry::traceable(&ray(Vec3::ZERO, -Vec3::ZERO), 1.0));
        let huge = Vec3::splat(f32::MAX);
        assert!(Geometry::traceable(&ray(huge, huge), 1.0));
    }

    #[test]
    fn empty_scene_hits_nothing() {
        let geometry = Geometry::new(Vec::new()).unwrap();
        let ray = Ray::new(Vec3::ZERO, Vec3::Z);
        assert!(geometry.intersect(&ray, f32::INFINITY).is_none());
        assert!(!geometry.occluded(&ray, f32::INFINITY));
    }
}
